//! What a frame's GPU passes draw, as plain instance data: lit boxes and spheres, soft
//! sprites, screen-space rectangles, gathered in a [`Scene`]; and the colour and box
//! helpers the table, the men and the characters are built with.

use crate::camera::Camera;
use crate::view::Team;
use bytemuck::{Pod, Zeroable};
use glam::Quat;

/// Home team colour (linear RGB): electric blue.
pub const HOME_COLOR: [f32; 3] = [0.05, 0.42, 1.0];
/// Away team colour (linear RGB): crimson.
pub const AWAY_COLOR: [f32; 3] = [1.0, 0.10, 0.22];

/// A box or sphere instance: centre (`w` = emissive), half extents, orientation
/// quaternion `[x, y, z, w]`, colour (linear RGBA).
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Pod, Zeroable)]
pub struct MeshInstance {
    /// Centre xyz, m; `w`: emissive strength.
    pub center: [f32; 4],
    /// Half extents xyz, m (radius for the unit sphere).
    pub half: [f32; 4],
    /// Orientation quaternion.
    pub rotation: [f32; 4],
    /// Linear RGBA.
    pub color: [f32; 4],
}

/// A soft round sprite: a billboard (`center.w = 0`) or lying on the field
/// (`center.w = 1`). `size.x` radius (m), `size.y` edge hardness exponent.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Pod, Zeroable)]
pub struct Sprite {
    /// Centre xyz, m; `w` mode.
    pub center: [f32; 4],
    /// Radius, hardness.
    pub size: [f32; 4],
    /// Linear RGBA (alpha multiplies).
    pub color: [f32; 4],
}

/// A screen-space rectangle `[x0, y0, x1, y1]` in pixels (y down) with a colour.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Pod, Zeroable)]
pub struct UiRect {
    /// Pixels.
    pub rect: [f32; 4],
    /// Linear RGBA.
    pub color: [f32; 4],
}

/// Everything one frame draws.
#[derive(Debug, Clone)]
pub struct Scene {
    /// The camera.
    pub camera: Camera,
    /// Time for the animated background, s.
    pub time_s: f32,
    /// Lit boxes (table, rods, men).
    pub boxes: Vec<MeshInstance>,
    /// Lit spheres (the ball), drawn with a fine mesh.
    pub spheres: Vec<MeshInstance>,
    /// Lit spheres a few pixels across (the characters' helmets and pads), drawn with a
    /// coarse mesh: on a software rasteriser triangle setup, not pixels, is their cost.
    pub small_spheres: Vec<MeshInstance>,
    /// Darkening blobs on the field (alpha blended).
    pub shadows: Vec<Sprite>,
    /// Glowing particles (additive).
    pub particles: Vec<Sprite>,
    /// The 2-D overlay, drawn last in order.
    pub ui: Vec<UiRect>,
}

pub(crate) fn team_color(side: Team) -> [f32; 3] {
    match side {
        Team::Home => HOME_COLOR,
        Team::Away => AWAY_COLOR,
    }
}

pub(crate) fn rgba(c: [f32; 3], a: f32) -> [f32; 4] {
    [c[0], c[1], c[2], a]
}

pub(crate) fn scale3(c: [f32; 3], k: f32) -> [f32; 3] {
    [c[0] * k, c[1] * k, c[2] * k]
}

pub(crate) fn cuboid(
    center: [f32; 3],
    half: [f32; 3],
    rot: Quat,
    color: [f32; 3],
    emissive: f32,
) -> MeshInstance {
    MeshInstance {
        center: [center[0], center[1], center[2], emissive],
        half: [half[0], half[1], half[2], 0.0],
        rotation: rot.to_array(),
        color: rgba(color, 1.0),
    }
}

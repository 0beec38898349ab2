//! The fixed camera: above the `Home` players' side of the table (`−y`), looking down
//! at the table at an angle, the table's length (`x`) across the screen.

use crate::view::TableGeometry;
use glam::{Mat4, Vec3, Vec4};

/// Vertical field of view, radians.
pub const FOV_Y_RAD: f32 = 0.62;

/// How far past a side wall the camera keeps in view, m: the rod ends with their
/// handles, and a margin.
pub const HANDLE_REACH_M: f32 = 0.24;

/// A perspective camera (right-handed, depth 0…1 as wgpu expects).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Camera {
    /// Eye position, table frame, m.
    pub eye: Vec3,
    /// The point looked at, m.
    pub target: Vec3,
    /// World → clip.
    pub view_proj: Mat4,
    /// Unit vector to the right on screen, table frame.
    pub right: Vec3,
    /// Unit vector up on screen, table frame.
    pub up: Vec3,
}

impl Camera {
    /// The camera for a table on a screen of aspect `width / height`. The distance is
    /// chosen so the table with its goals fits the width (and the field the height).
    pub fn for_table(table: &TableGeometry, aspect: f32) -> Camera {
        let aspect = if aspect.is_finite() && aspect > 0.1 {
            aspect
        } else {
            16.0 / 9.0
        };
        // Half sizes to keep on screen, with some margin: across the table that
        // includes the handles (they stick out [`HANDLE_REACH_M`] past the walls).
        let half_x = 0.5 * (table.length_m + 2.0 * table.goal_depth_m) as f32 + 0.04;
        let half_y = 0.5 * table.width_m as f32 + HANDLE_REACH_M;
        let tan_y = (0.5 * FOV_Y_RAD).tan();
        let tan_x = tan_y * aspect;
        // Elevation of the view direction above the horizontal.
        let elevation = 0.8f32;
        // Distance so the table's length fits the width; the depth (y) shrinks by
        // sin(elevation) on screen.
        let dist_x = half_x / tan_x;
        let dist_y = half_y * elevation.sin() / tan_y + half_y * elevation.cos();
        let dist = dist_x.max(dist_y) * 1.1;
        let target = Vec3::new(0.0, 0.04, 0.0);
        let eye = target + dist * Vec3::new(0.0, -elevation.cos(), elevation.sin());
        let view = Mat4::look_at_rh(eye, target, Vec3::Z);
        let proj = Mat4::perspective_rh(FOV_Y_RAD, aspect, 0.05, 20.0);
        let forward = (target - eye).normalize();
        let right = forward.cross(Vec3::Z).normalize();
        let up = right.cross(forward).normalize();
        Camera {
            eye,
            target,
            view_proj: proj * view,
            right,
            up,
        }
    }

    /// Projects a table-frame point (m) to pixel coordinates `(x right, y down)` on an
    /// image `width × height`; `None` behind the camera.
    pub fn project(&self, p: [f64; 3], width: u32, height: u32) -> Option<(f32, f32)> {
        let clip = self.view_proj * Vec4::new(p[0] as f32, p[1] as f32, p[2] as f32, 1.0);
        if clip.w <= 1e-6 {
            return None;
        }
        let ndc = clip / clip.w;
        Some((
            (ndc.x * 0.5 + 0.5) * width as f32,
            (0.5 - ndc.y * 0.5) * height as f32,
        ))
    }

    /// On-screen radius (pixels) of a sphere of radius `r` (m) centred at `p`, on an
    /// image `height` pixels high (small-sphere approximation).
    pub fn projected_radius(&self, p: [f64; 3], r: f64, height: u32) -> f32 {
        let d = (Vec3::new(p[0] as f32, p[1] as f32, p[2] as f32) - self.eye).length();
        let tan_y = (0.5 * FOV_Y_RAD).tan();
        r as f32 / (d * tan_y) * 0.5 * height as f32
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fixture::reference_table;

    #[test]
    fn table_corners_are_on_screen_and_home_side_is_nearer() {
        let g = reference_table();
        let c = Camera::for_table(&g, 16.0 / 9.0);
        let (w, h) = (1280, 720);
        for sx in [-1.0, 1.0] {
            for sy in [-1.0, 1.0] {
                let p = [sx * 0.5 * g.length_m, sy * 0.5 * g.width_m, 0.0];
                let (x, y) = c.project(p, w, h).unwrap();
                assert!(x > 0.0 && x < w as f32 && y > 0.0 && y < h as f32, "{p:?}");
            }
        }
        // +x is to the right, −y (home handles) is lower on screen.
        let (xa, _) = c.project([0.5, 0.0, 0.0], w, h).unwrap();
        let (xb, _) = c.project([-0.5, 0.0, 0.0], w, h).unwrap();
        assert!(xa > xb);
        let (_, ya) = c.project([0.0, -0.3, 0.0], w, h).unwrap();
        let (_, yb) = c.project([0.0, 0.3, 0.0], w, h).unwrap();
        assert!(ya > yb);
    }
}

//! The characters, composed from lit primitives in the man frame (see [`crate::view`]):
//! a helmet with a glowing visor and an antenna, shoulder pads, a torso with a chest
//! light and a belt, two legs and two boots. Every part is sized from the kind's
//! [`CharacterLook`], so tall-and-thin (long legs, narrow torso, a tall helmet) and
//! short-and-wide (broad shoulders, big pads, a wide helmet) differ in silhouette, not
//! only in tint. Each man also casts a contact shadow on the cloth under his boots.

use crate::instances::{cuboid, rgba, scale3, team_color, MeshInstance, Scene, Sprite};
use crate::view::{CharacterKind, CharacterLook, FrameSnapshot, Team};
use glam::{Quat, Vec3};

/// Height of a boot, m (man frame, above the sole).
const BOOT_H: f32 = 0.014;

/// Where a character is drawn: `world = origin + scale · (rotation · local)`.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Placement {
    /// Origin of the man frame, table frame, m.
    pub origin: Vec3,
    /// Man frame → table frame.
    pub rotation: Quat,
    /// Drawing scale (1 on the table; larger for the selection previews).
    pub scale: f32,
    /// Brightness factor of the colours (1 normal; below 1 dims a preview).
    pub brightness: f32,
}

/// One part, man frame: centre, half extents, sphere (else box), colour, emissive.
struct Part {
    centre: [f32; 3],
    half: [f32; 3],
    sphere: bool,
    color: [f32; 3],
    emissive: f32,
}

/// The parts of `look` in `team`'s colours, facing `front` (`±1`, the man frame's `x`
/// the team attacks along).
fn parts(look: &CharacterLook, team: Team, front: f32) -> Vec<Part> {
    let r = look.foot_reach_m as f32;
    let head_top = look.head_height_m as f32;
    let shoulder = look.shoulder_height_m as f32;
    let w = look.body_width_m as f32;
    let d = look.body_depth_m as f32;
    let f = look.foot_width_m as f32;
    let hip = -0.4 * r;
    let base = team_color(team);
    let (base, pad_k) = match look.kind {
        CharacterKind::TallThin => (base, 0.16),
        CharacterKind::ShortWide => (
            [
                (base[0] * 0.8 + 0.2).min(1.0),
                base[1] * 0.9 + 0.05,
                base[2] * 0.8,
            ],
            0.4,
        ),
    };
    let dark = scale3(base, 0.5);
    let metal = [0.80, 0.83, 0.90];
    let glow = [0.35, 1.0, 0.95];
    let mut out = Vec::with_capacity(12);
    let mut part = |centre, half, sphere, color, emissive| {
        out.push(Part {
            centre,
            half,
            sphere,
            color,
            emissive,
        })
    };
    // Torso (hip to shoulder), belt, chest light.
    let tz = 0.5 * (shoulder + hip);
    let th = 0.5 * (shoulder - hip);
    part([0.0, 0.0, tz], [0.5 * d, 0.5 * w, th], false, base, 0.12);
    part(
        [0.0, 0.0, hip + 0.003],
        [0.5 * d + 0.001, 0.5 * w + 0.001, 0.003],
        false,
        metal,
        0.05,
    );
    part(
        [front * (0.5 * d + 0.0008), 0.0, tz + 0.3 * th],
        [0.0008, 0.22 * w, 0.18 * th],
        false,
        glow,
        0.9,
    );
    // Shoulder pads.
    let pad = pad_k * w;
    for s in [-1.0f32, 1.0] {
        part(
            [0.0, s * 0.5 * w, shoulder - 0.4 * pad],
            [0.6 * pad + 0.3 * d, pad, 0.7 * pad],
            true,
            metal,
            0.05,
        );
    }
    // Helmet: tall for tall-thin, wide for short-wide; a dark glowing visor in front.
    let rz = 0.5 * (head_top - shoulder) + 0.003;
    let ry = (0.42 * w).max(0.8 * rz);
    let rx = 0.5 * d + 0.003;
    let hz = head_top - rz;
    part([0.0, 0.0, hz], [rx, ry, rz], true, scale3(base, 1.25), 0.15);
    part(
        [front * 0.45 * rx, 0.0, hz + 0.1 * rz],
        [0.62 * rx, 0.8 * ry, 0.42 * rz],
        true,
        [0.02, 0.25, 0.35],
        0.7,
    );
    // Antenna with a glowing tip.
    let ant = 0.35 * rz + 0.002;
    part(
        [0.0, 0.0, head_top + ant],
        [0.0008, 0.0008, ant],
        false,
        metal,
        0.0,
    );
    part(
        [0.0, 0.0, head_top + 2.0 * ant],
        [0.0022, 0.0022, 0.0022],
        true,
        glow,
        1.0,
    );
    // Legs (hip to boot top) and boots (toes forward).
    let leg_top = hip;
    let leg_bottom = -r + BOOT_H;
    let leg_y = 0.26 * f;
    let leg_half_y = 0.2 * f.min(1.2 * w);
    for s in [-1.0f32, 1.0] {
        part(
            [0.0, s * leg_y, 0.5 * (leg_top + leg_bottom)],
            [0.38 * d, leg_half_y, 0.5 * (leg_top - leg_bottom)],
            false,
            dark,
            0.08,
        );
        part(
            [front * 0.004, s * leg_y, -r + 0.5 * BOOT_H],
            [0.5 * d + 0.005, 0.23 * f, 0.5 * BOOT_H],
            false,
            metal,
            0.08,
        );
    }
    out
}

/// Pushes the character `look` of `team` at `at` into the scene's meshes.
pub(crate) fn draw_character(scene: &mut Scene, look: &CharacterLook, team: Team, at: Placement) {
    let front = team.attack_dir() as f32;
    for p in parts(look, team, front) {
        let c = at.origin + at.scale * (at.rotation * Vec3::from(p.centre));
        let inst: MeshInstance = cuboid(
            c.to_array(),
            (Vec3::from(p.half) * at.scale).to_array(),
            at.rotation,
            scale3(p.color, at.brightness),
            p.emissive * at.brightness,
        );
        if p.sphere {
            scene.small_spheres.push(inst);
        } else {
            scene.boxes.push(inst);
        }
    }
}

/// The men of the snapshot on the table, each with a contact shadow on the cloth:
/// dark and tight when the boot is near the cloth, fading as it swings up.
pub(crate) fn draw_men(snap: &FrameSnapshot, scene: &mut Scene) {
    for man in &snap.men {
        let look = snap.table.look_of(man.team);
        let pivot = Vec3::from(man.pivot.map(|v| v as f32));
        if !pivot.is_finite() || !man.rotation.iter().all(|v| v.is_finite()) {
            continue;
        }
        let rotation = Quat::from_array(man.rotation.map(|v| v as f32)).normalize();
        draw_character(
            scene,
            look,
            man.team,
            Placement {
                origin: pivot,
                rotation,
                scale: 1.0,
                brightness: 1.0,
            },
        );
        let sole = pivot + rotation * Vec3::new(0.0, 0.0, -look.foot_reach_m as f32);
        let h = sole.z.max(0.0);
        let size = 0.5 * (look.foot_width_m as f32).max(look.body_depth_m as f32 + 0.01);
        scene.shadows.push(Sprite {
            center: [sole.x, sole.y, 0.0011, 1.0],
            size: [size * (1.3 + 12.0 * h), 1.2, 0.0, 0.0],
            color: [0.0, 0.0, 0.0, 0.75 / (1.0 + 40.0 * h)],
        });
        // A wider, fainter shadow of the whole figure under the rod.
        scene.shadows.push(Sprite {
            center: [pivot.x, pivot.y, 0.0010, 1.0],
            size: [1.1 * look.body_width_m as f32 + 0.01, 1.0, 0.0, 0.0],
            color: rgba([0.0; 3], 0.22),
        });
    }
}

/// Drawing scale of the chosen character in a selection preview.
pub(crate) const PREVIEW_SCALE: f32 = 3.0;

/// Where team `team`'s chosen character stands in the selection preview (the origin of
/// its man frame), table frame, m; its boots rest on the stage at `z =` [`STAGE_Z`].
pub(crate) fn preview_origin(look: &CharacterLook, team: Team) -> Vec3 {
    Vec3::new(
        -0.27 * team.attack_dir() as f32,
        -0.3,
        STAGE_Z + PREVIEW_SCALE * look.foot_reach_m as f32,
    )
}

/// Height of the selection screen's stage (a dark plate over the table), m.
pub(crate) const STAGE_Z: f32 = 0.135;

/// The selection screen's live previews: a dark stage over the table and, for each
/// team, its chosen kind large and turning, with the other kind smaller and dimmer
/// beside it, so both kinds are always on show.
pub(crate) fn draw_previews(snap: &FrameSnapshot, scene: &mut Scene) {
    let t = &snap.table;
    scene.boxes.push(cuboid(
        [0.0, 0.0, STAGE_Z - 0.002],
        [
            0.5 * t.length_m as f32 + 0.15,
            0.5 * t.width_m as f32 + 0.1,
            0.002,
        ],
        Quat::IDENTITY,
        [0.006, 0.006, 0.014],
        0.0,
    ));
    let time = snap.time_s as f32;
    for team in Team::BOTH {
        let chosen = t.characters[team.index()];
        let other = CharacterKind::BOTH[1 - chosen.index()];
        // Face the camera (man-frame x, the front, towards −y), swinging to show depth.
        let face = -std::f32::consts::FRAC_PI_2 * team.attack_dir() as f32;
        let swing = 0.55 * (0.9 * time + team.index() as f32 * 1.3).sin();
        let rotation = Quat::from_rotation_z(face + swing);
        let look = &t.looks[chosen.index()];
        draw_character(
            scene,
            look,
            team,
            Placement {
                origin: preview_origin(look, team),
                rotation,
                scale: PREVIEW_SCALE,
                brightness: 1.0,
            },
        );
        let small = 1.6;
        let look_o = &t.looks[other.index()];
        let base = preview_origin(look, team);
        draw_character(
            scene,
            look_o,
            team,
            Placement {
                origin: Vec3::new(
                    base.x - 0.25 * team.attack_dir() as f32,
                    base.y + 0.1,
                    STAGE_Z + small * look_o.foot_reach_m as f32,
                ),
                rotation: Quat::from_rotation_z(face),
                scale: small,
                brightness: 0.45,
            },
        );
    }
}

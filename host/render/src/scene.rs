//! The scene as GPU instance lists, built on the CPU from a snapshot and a screen: what
//! is drawn where. No GPU calls here, so it is testable anywhere.

use crate::camera::Camera;
use crate::characters;
use crate::instances::{cuboid, rgba, scale3, team_color};
pub use crate::instances::{MeshInstance, Scene, Sprite, UiRect, AWAY_COLOR, HOME_COLOR};
pub use crate::overlay::{hint_rect, score_rect, Hud, Screen, HINT_WIDTH_FRAC, SCORE_COLOR};
use crate::overlay::{hud_overlay, overlay};
use crate::view::{EventKind, FrameSnapshot, Team};
use glam::{Quat, Vec3};

/// Ball colour (linear RGB): gold, distinct from both teams and the stars.
pub const BALL_COLOR: [f32; 3] = [1.0, 0.72, 0.06];
/// Colour of a held rod's handle and markers (linear RGB): lime, unlike either
/// team, the ball or the markings.
pub const HELD_COLOR: [f32; 3] = [0.25, 1.0, 0.08];

/// Visual ball growth per metre of height (see [`ball_visual_scale`]).
pub const BALL_SCALE_PER_M: f64 = 6.0;
/// Largest visual ball scale.
pub const BALL_SCALE_MAX: f64 = 2.5;
/// Longest particle life, s: events older than this draw nothing.
pub const PARTICLE_LIFETIME_S: f64 = 1.6;
/// How long a bounce squashes the ball, s (exaggerated bounce, paper §5).
pub const SQUASH_S: f64 = 0.12;

/// The height cue of paper §5: the ball is drawn larger the higher it flies.
///
/// With `h = max(0, z − r)` the height of the ball's underside above the field (m),
/// the drawn radius is `r · s(h)` with `s(h) = min(1 + 6·h, 2.5)`: ×1 on the cloth,
/// ×1.6 at 10 cm (about the rod height), capped at ×2.5 from 25 cm. The growth is
/// on top of perspective (a higher ball is also nearer the camera). The drawn sphere
/// keeps its centre, so its underside never sinks into the cloth (`r·s − r = 6·r·h < h`
/// for any ball smaller than 16 cm).
pub fn ball_visual_scale(z_m: f64, radius_m: f64) -> f64 {
    let h = (z_m - radius_m).max(0.0);
    if !h.is_finite() {
        return 1.0;
    }
    (1.0 + BALL_SCALE_PER_M * h).min(BALL_SCALE_MAX)
}

/// Builds the scene of `snap` on `screen` for an image `width × height`.
pub fn build(snap: &FrameSnapshot, screen: Screen, width: u32, height: u32) -> Scene {
    build_with_hud(snap, screen, &Hud::default(), width, height)
}

/// Builds the scene of `snap` on `screen` with the live text `hud` on top.
pub fn build_with_hud(
    snap: &FrameSnapshot,
    screen: Screen,
    hud: &Hud,
    width: u32,
    height: u32,
) -> Scene {
    let camera = Camera::for_table(&snap.table, width as f32 / height.max(1) as f32);
    let mut scene = Scene {
        camera,
        time_s: snap.time_s as f32,
        boxes: Vec::new(),
        spheres: Vec::new(),
        small_spheres: Vec::new(),
        shadows: Vec::new(),
        particles: Vec::new(),
        ui: Vec::new(),
    };
    table_boxes(snap, &mut scene.boxes);
    if screen == Screen::CharacterSelect {
        characters::draw_previews(snap, &mut scene);
    } else {
        characters::draw_men(snap, &mut scene);
    }
    ball(snap, &mut scene);
    particles(snap, &mut scene.particles);
    overlay(
        snap,
        screen,
        hud,
        width as f32,
        height as f32,
        &mut scene.ui,
    );
    hud_overlay(hud, width as f32, height as f32, &mut scene.ui);
    scene
}

fn axis_box(center: [f32; 3], half: [f32; 3], color: [f32; 3], emissive: f32) -> MeshInstance {
    cuboid(center, half, Quat::IDENTITY, color, emissive)
}

/// Cloth, markings, walls with goal mouths, goal boxes, the hull under the table, rods
/// and handles.
/// The table's sizes the boxes are laid out with (m), and its colours.
struct TableLayout {
    hl: f32,
    hw: f32,
    wall_h: f32,
    gw: f32,
    gh: f32,
    gd: f32,
    /// Wall thickness.
    wt: f32,
    wall: [f32; 3],
    glow: [f32; 3],
}

fn table_boxes(snap: &FrameSnapshot, out: &mut Vec<MeshInstance>) {
    let t = &snap.table;
    let l = TableLayout {
        hl: 0.5 * t.length_m as f32,
        hw: 0.5 * t.width_m as f32,
        wall_h: t.wall_height_m as f32,
        gw: 0.5 * t.goal_width_m as f32,
        gh: t.goal_height_m as f32,
        gd: t.goal_depth_m as f32,
        wt: 0.025,
        wall: [0.09, 0.10, 0.16],
        glow: [0.1, 0.6, 0.8],
    };
    field_boxes(&l, out);
    wall_and_goal_boxes(&l, out);
    rod_boxes(snap, &l, out);
}

/// The hull under the table, the cloth and its glowing markings.
fn field_boxes(l: &TableLayout, out: &mut Vec<MeshInstance>) {
    let TableLayout { hl, hw, gw, gd, .. } = *l;
    let cloth = [0.02, 0.20, 0.09];
    let line = [0.55, 0.95, 0.85];
    // Hull under the table and the cloth.
    out.push(axis_box(
        [0.0, 0.0, -0.06],
        [hl + gd + 0.06, hw + 0.06, 0.05],
        [0.035, 0.035, 0.06],
        0.0,
    ));
    out.push(axis_box([0.0, 0.0, -0.005], [hl, hw, 0.005], cloth, 0.05));
    // Markings: centre line, centre circle, goal areas (thin glowing strips).
    let lw = 0.003f32;
    let lz = 0.0004f32;
    out.push(axis_box([0.0, 0.0, lz], [lw, hw, lz], line, 0.6));
    let rc = 0.09f32;
    for k in 0..28 {
        let a = k as f32 / 28.0 * std::f32::consts::TAU;
        let seg = Quat::from_rotation_z(a);
        out.push(cuboid(
            [rc * a.cos(), rc * a.sin(), lz],
            [lw, rc * 0.115, lz],
            seg,
            line,
            0.6,
        ));
    }
    for s in [-1.0f32, 1.0] {
        let depth = 0.08f32;
        let half_w = gw + 0.06;
        let x_in = s * (hl - depth);
        out.push(axis_box([x_in, 0.0, lz], [lw, half_w, lz], line, 0.6));
        for sy in [-1.0f32, 1.0] {
            out.push(axis_box(
                [s * (hl - 0.5 * depth), sy * half_w, lz],
                [0.5 * depth, lw, lz],
                line,
                0.6,
            ));
        }
    }
}

/// The side and end walls, the goal boxes in the defending team's colour.
fn wall_and_goal_boxes(l: &TableLayout, out: &mut Vec<MeshInstance>) {
    let TableLayout {
        hl,
        hw,
        wall_h,
        gw,
        gh,
        gd,
        wt,
        wall,
        glow,
    } = *l;
    // Side walls with a glowing top edge.
    for s in [-1.0f32, 1.0] {
        let y = s * (hw + 0.5 * wt);
        out.push(axis_box(
            [0.0, y, 0.5 * wall_h],
            [hl + wt, 0.5 * wt, 0.5 * wall_h],
            wall,
            0.0,
        ));
        out.push(axis_box(
            [0.0, y, wall_h + 0.002],
            [hl + wt, 0.004, 0.002],
            glow,
            0.8,
        ));
    }
    // End walls around the goal mouths, goal boxes glowing in the defending team's colour.
    for (side, s) in [(Team::Home, -1.0f32), (Team::Away, 1.0)] {
        let x = s * (hl + 0.5 * wt);
        let seg = 0.5 * (hw - gw);
        for sy in [-1.0f32, 1.0] {
            out.push(axis_box(
                [x, sy * (gw + seg), 0.5 * wall_h],
                [0.5 * wt, seg, 0.5 * wall_h],
                wall,
                0.0,
            ));
        }
        out.push(axis_box(
            [x, 0.0, 0.5 * (gh + wall_h)],
            [0.5 * wt, gw, 0.5 * (wall_h - gh)],
            wall,
            0.0,
        ));
        out.push(axis_box(
            [x, 0.0, wall_h + 0.002],
            [0.004, hw + wt, 0.002],
            glow,
            0.8,
        ));
        let c = team_color(side);
        // Goal box: floor, back and sides, lit from inside.
        let gx = s * (hl + 0.5 * gd);
        out.push(axis_box(
            [gx, 0.0, -0.002],
            [0.5 * gd, gw, 0.002],
            scale3(c, 0.25),
            0.8,
        ));
        out.push(axis_box(
            [s * (hl + gd), 0.0, 0.5 * gh],
            [0.004, gw + 0.004, 0.5 * gh],
            c,
            1.0,
        ));
        for sy in [-1.0f32, 1.0] {
            out.push(axis_box(
                [gx, sy * (gw + 0.004), 0.5 * gh],
                [0.5 * gd, 0.004, 0.5 * gh],
                scale3(c, 0.6),
                0.5,
            ));
        }
        out.push(axis_box(
            [gx, 0.0, gh + 0.004],
            [0.5 * gd, gw + 0.008, 0.004],
            scale3(c, 0.5),
            0.3,
        ));
    }
}

/// The rods outside the walls and their handles, a held rod glowing.
fn rod_boxes(snap: &FrameSnapshot, l: &TableLayout, out: &mut Vec<MeshInstance>) {
    let t = &snap.table;
    let TableLayout { hw, wt, .. } = *l;
    // Rods: hidden over the field (the players watch the ball and the men), drawn from
    // the walls out, with a handle on the owning team's side (Home at −y, Away at +y).
    // A held rod glows: a bright handle, a ring at the wall and a faint line over the
    // field.
    let rod_h = t.rod_height_m as f32;
    let rod_half_len = hw + 0.16;
    for (i, rod) in t.rods.iter().enumerate() {
        let pose = snap.rods.get(i).copied().unwrap_or_default();
        let slide = pose.slide_m as f32;
        let rot = Quat::from_rotation_y(pose.angle_rad as f32);
        let x = rod.x_m as f32;
        let held = snap.held_rods.contains(&i);
        let sign = rod.team.handle_sign() as f32;
        let steel = [0.55, 0.58, 0.66];
        // The two stubs outside the walls: [from the wall, to the rod end].
        for s in [sign, -sign] {
            let end = slide + s * rod_half_len;
            let (a, b) = (s * (hw + wt), end);
            if (b - a) * s <= 0.0 {
                continue;
            }
            out.push(cuboid(
                [x, 0.5 * (a + b), rod_h],
                [0.006, 0.5 * (b - a).abs(), 0.006],
                rot,
                steel,
                0.0,
            ));
        }
        let handle = [x, slide + sign * (rod_half_len + 0.045), rod_h];
        if held {
            out.push(cuboid(handle, [0.021, 0.05, 0.021], rot, HELD_COLOR, 0.45));
            out.push(axis_box(
                [x, sign * (hw + wt + 0.012), rod_h],
                [0.012, 0.006, 0.012],
                HELD_COLOR,
                0.45,
            ));
            out.push(axis_box(
                [x, 0.0, rod_h],
                [0.0018, hw, 0.0018],
                scale3(HELD_COLOR, 0.6),
                0.8,
            ));
        } else {
            out.push(cuboid(
                handle,
                [0.016, 0.045, 0.016],
                rot,
                scale3(team_color(rod.team), 0.7),
                0.2,
            ));
        }
    }
}

/// The ball (scaled by height, squashed by a fresh bounce, stretched by speed) and its
/// shadow blob.
fn ball(snap: &FrameSnapshot, scene: &mut Scene) {
    let r = snap.table.ball_radius_m;
    let p = snap.ball.position;
    if !p.iter().all(|v| v.is_finite()) {
        return;
    }
    let s = ball_visual_scale(p[2], r);
    let radius = (r * s) as f32;
    // Exaggerated bounce: a fresh bounce squashes the ball along the contact normal
    // (vertical for a floor bounce, along the velocity otherwise), relaxing linearly.
    let mut half = Vec3::splat(radius);
    let mut rot = Quat::IDENTITY;
    let latest_bounce = snap
        .events
        .iter()
        .filter(|e| matches!(e.kind, EventKind::Bounce | EventKind::Kick))
        .map(|e| (snap.time_s - e.time_s, e))
        .filter(|(age, _)| *age >= 0.0 && *age < SQUASH_S)
        .min_by(|a, b| a.0.total_cmp(&b.0));
    let v = Vec3::from(snap.ball.velocity.map(|x| x as f32));
    if let Some((age, e)) = latest_bounce {
        let k = (1.0 - age / SQUASH_S) as f32;
        let floor = e.position[2] <= 1.5 * r;
        let normal = if floor || v.length() < 1e-3 {
            Vec3::Z
        } else {
            v.normalize()
        };
        rot = Quat::from_rotation_arc(Vec3::Z, normal);
        half = Vec3::new(
            radius * (1.0 + 0.25 * k),
            radius * (1.0 + 0.25 * k),
            radius * (1.0 - 0.4 * k),
        );
    } else if v.length() > 0.5 {
        // Motion stretch along the velocity.
        let st = (1.0 + 0.05 * v.length()).min(1.35);
        rot = Quat::from_rotation_arc(Vec3::Z, v.normalize());
        half = Vec3::new(radius / st.sqrt(), radius / st.sqrt(), radius * st);
    }
    scene.spheres.push(MeshInstance {
        center: [p[0] as f32, p[1] as f32, p[2] as f32, 0.35],
        half: [half.x, half.y, half.z, 0.0],
        rotation: rot.to_array(),
        color: rgba(BALL_COLOR, 1.0),
    });
    // Shadow: wider and fainter the higher the ball.
    let h = (p[2] - r).max(0.0) as f32;
    scene.shadows.push(Sprite {
        center: [p[0] as f32, p[1] as f32, 0.0012, 1.0],
        size: [r as f32 * (1.15 + 3.0 * h / 0.1), 1.3, 0.0, 0.0],
        color: [0.0, 0.0, 0.0, 0.8 / (1.0 + 8.0 * h / 0.1)],
    });
}

/// Integer hash to `0…1`.
fn hash01(mut x: u32) -> f32 {
    x ^= x >> 16;
    x = x.wrapping_mul(0x7feb_352d);
    x ^= x >> 15;
    x = x.wrapping_mul(0x846c_a68b);
    x ^= x >> 16;
    (x >> 8) as f32 / (1u32 << 24) as f32
}

/// Particles are a pure function of the events and the time (no state): every event
/// younger than its life emits a deterministic burst.
fn particles(snap: &FrameSnapshot, out: &mut Vec<Sprite>) {
    for e in &snap.events {
        let age = snap.time_s - e.time_s;
        let (count, speed, life, size, colors): (u32, f32, f64, f32, [[f32; 3]; 3]) = match e.kind {
            EventKind::Kick => (
                28,
                0.55,
                0.6,
                0.010,
                [[1.0, 0.55, 0.1], [1.0, 0.85, 0.3], [1.0, 0.3, 0.05]],
            ),
            EventKind::Bounce => (
                16,
                0.3,
                0.45,
                0.008,
                [[0.3, 0.9, 1.0], [0.6, 0.5, 1.0], [0.9, 1.0, 1.0]],
            ),
            EventKind::Goal(side) => (
                140,
                1.1,
                PARTICLE_LIFETIME_S,
                0.016,
                [team_color(side), [1.0, 1.0, 1.0], BALL_COLOR],
            ),
        };
        if !(age >= 0.0 && age < life && e.position.iter().all(|v| v.is_finite())) {
            continue;
        }
        let a = age as f32;
        let fade = (1.0 - (age / life) as f32).powf(1.5);
        let boost = (1.0 + 0.15 * e.speed as f32).clamp(1.0, 2.0);
        let seed = (e.time_s * 1000.0) as u32 ^ (e.position[0] * 1.0e4) as i32 as u32;
        let p0 = Vec3::from(e.position.map(|v| v as f32));
        for j in 0..count {
            let h = |k: u32| {
                hash01(seed.wrapping_mul(747_796_405) ^ (j * 4 + k).wrapping_mul(2_891_336_453))
            };
            let phi = h(0) * std::f32::consts::TAU;
            let cos_t = h(1); // upper hemisphere
            let sin_t = (1.0 - cos_t * cos_t).sqrt();
            let dir = Vec3::new(sin_t * phi.cos(), sin_t * phi.sin(), cos_t);
            let v = dir * speed * boost * (0.4 + 0.8 * h(2));
            let mut p = p0 + v * a + Vec3::new(0.0, 0.0, -0.9) * (0.5 * a * a);
            p.z = p.z.max(0.002);
            let c = colors[(h(3) * 3.0) as usize % 3];
            out.push(Sprite {
                center: [p.x, p.y, p.z, 0.0],
                size: [
                    size * (0.6 + 0.6 * h(2)) * (0.5 + 0.5 * fade),
                    2.0,
                    0.0,
                    0.0,
                ],
                color: rgba(c, fade),
            });
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fixture::reference_table;
    use crate::view::RenderEvent;

    #[test]
    fn ball_scale_law() {
        let r = 0.0175;
        assert_eq!(ball_visual_scale(r, r), 1.0);
        assert_eq!(ball_visual_scale(0.0, r), 1.0);
        assert!((ball_visual_scale(r + 0.1, r) - 1.6).abs() < 1e-12);
        assert_eq!(ball_visual_scale(5.0, r), BALL_SCALE_MAX);
        assert_eq!(ball_visual_scale(f64::NAN, r), 1.0);
        // Monotonic.
        let mut last = 0.0;
        for i in 0..100 {
            let s = ball_visual_scale(r + i as f64 * 0.005, r);
            assert!(s >= last);
            last = s;
        }
    }

    #[test]
    fn screens_round_trip_names() {
        for s in Screen::ALL {
            assert_eq!(Screen::from_name(s.name()), Some(s));
        }
        assert_eq!(Screen::from_name("nope"), None);
    }

    #[test]
    fn events_spawn_particles_only_while_young() {
        let mut snap = FrameSnapshot::at_rest(&reference_table());
        snap.time_s = 10.0;
        let ev = |t: f64, kind| RenderEvent {
            time_s: t,
            kind,
            position: [0.1, 0.0, 0.02],
            speed: 2.0,
        };
        snap.events = vec![
            ev(9.9, EventKind::Kick),
            ev(9.95, EventKind::Bounce),
            ev(9.5, EventKind::Goal(Team::Away)),
            ev(5.0, EventKind::Kick),
            ev(11.0, EventKind::Kick),
        ];
        let s = build(&snap, Screen::Match, 640, 360);
        assert_eq!(s.particles.len(), 28 + 16 + 140);
        assert!(s.particles.iter().all(|p| p.center[2] > 0.0));
        // A fresh bounce squashes the ball.
        let b = s.spheres[0];
        assert!(b.half[2] < b.half[0]);
        // The same snapshot gives the same particles.
        assert_eq!(build(&snap, Screen::Match, 640, 360).particles, s.particles);
    }

    #[test]
    fn every_screen_has_an_overlay_and_score_text_depends_on_score() {
        let mut snap = FrameSnapshot::at_rest(&reference_table());
        for s in Screen::ALL {
            assert!(!build(&snap, s, 640, 360).ui.is_empty(), "{s:?}");
        }
        let a = build(&snap, Screen::Match, 640, 360).ui.len();
        snap.score = [1, 8];
        let b = build(&snap, Screen::Match, 640, 360).ui.len();
        assert_ne!(a, b);
    }

    #[test]
    fn hud_text_is_drawn_fits_the_width_and_replaces_calibration_instructions() {
        let snap = FrameSnapshot::at_rest(&reference_table());
        let (w, h) = (640, 360);
        let bare = build(&snap, Screen::Match, w, h).ui.len();
        let hud = Hud {
            heading: "A VERY LONG INSTRUCTION THAT WOULD NEVER FIT AT THE NORMAL SIZE\nLINE 2"
                .into(),
            lines: vec!["FIT: RMS 0.31 MM".into()],
            ..Hud::default()
        };
        let ui = build_with_hud(&snap, Screen::Match, &hud, w, h).ui;
        assert!(ui.len() > bare);
        for r in &ui[bare..] {
            assert!(
                r.rect[0] >= -1.0 && r.rect[2] <= w as f32 + 1.0,
                "{:?}",
                r.rect
            );
        }
        // Calibration: the live heading replaces the generic instructions.
        let generic = build(&snap, Screen::Calibration, w, h).ui.len();
        let title_only = build_with_hud(
            &snap,
            Screen::Calibration,
            &Hud {
                heading: "X".into(),
                ..Hud::default()
            },
            w,
            h,
        )
        .ui
        .len();
        assert!(title_only < generic);
        // Selection: a note per team.
        let plain = build(&snap, Screen::CharacterSelect, w, h).ui.len();
        let notes = Hud {
            team_notes: Some(["PLAYER".into(), "COMPUTER".into()]),
            ..Hud::default()
        };
        assert!(
            build_with_hud(&snap, Screen::CharacterSelect, &notes, w, h)
                .ui
                .len()
                > plain
        );
        assert!(Hud::default().is_empty() && !notes.is_empty());
    }
}

//! The scene as GPU instance lists, built on the CPU from a snapshot and a screen: what
//! is drawn where. No GPU calls here, so it is testable anywhere.

use crate::camera::Camera;
use crate::characters;
use crate::font;
use crate::view::{CharacterKind, EventKind, FrameSnapshot, Team};
use bytemuck::{Pod, Zeroable};
use glam::{Quat, Vec3};

/// Home team colour (linear RGB): electric blue.
pub const HOME_COLOR: [f32; 3] = [0.05, 0.42, 1.0];
/// Away team colour (linear RGB): crimson.
pub const AWAY_COLOR: [f32; 3] = [1.0, 0.10, 0.22];
/// Ball colour (linear RGB): gold, distinct from both teams and the stars.
pub const BALL_COLOR: [f32; 3] = [1.0, 0.72, 0.06];
/// Colour of a held rod's handle and markers (linear RGB): lime, unlike either
/// team, the ball or the markings.
pub const HELD_COLOR: [f32; 3] = [0.25, 1.0, 0.08];
/// Score digits colour (linear RGB): white.
pub const SCORE_COLOR: [f32; 3] = [1.0, 1.0, 1.0];

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

/// The screens of the cabinet.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Screen {
    /// Logo and the computer playing itself; "push a rod to start".
    Attract,
    /// Each team chooses its character type by spinning a rod.
    CharacterSelect,
    /// The match with the score.
    Match,
    /// The splash after a goal.
    GoalCeremony,
    /// The final score and the winner.
    FinalResult,
    /// The board was unplugged: play paused until it comes back.
    BoardLost,
    /// Calibration: the player is guided through the rod motions.
    Calibration,
}

impl Screen {
    /// Every screen.
    pub const ALL: [Screen; 7] = [
        Screen::Attract,
        Screen::CharacterSelect,
        Screen::Match,
        Screen::GoalCeremony,
        Screen::FinalResult,
        Screen::BoardLost,
        Screen::Calibration,
    ];

    /// Command-line name.
    pub fn name(self) -> &'static str {
        match self {
            Screen::Attract => "attract",
            Screen::CharacterSelect => "character-select",
            Screen::Match => "match",
            Screen::GoalCeremony => "goal-ceremony",
            Screen::FinalResult => "final-result",
            Screen::BoardLost => "board-lost",
            Screen::Calibration => "calibration",
        }
    }

    /// The screen of a command-line name.
    pub fn from_name(name: &str) -> Option<Screen> {
        Screen::ALL.into_iter().find(|s| s.name() == name)
    }
}

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

/// Live text a running game lays over any screen: a heading under the screen's own
/// title (the calibration step to do now, "PAUSED"), small lines at the bottom left
/// (fit quality, the keys) and, on the selection screen, who plays each team.
/// Upper-case letters, digits and `-!:./?%` are drawn; other characters are blank.
#[derive(Debug, Clone, PartialEq)]
pub struct Hud {
    /// Prominent lines (split at `\n`) centred from 36 % of the height, each shrunk to
    /// fit the width; empty for none. On the calibration screen it replaces the
    /// screen's generic instructions.
    pub heading: String,
    /// Small lines at the bottom left, top to bottom.
    pub lines: Vec<String>,
    /// On the selection screen: a note under each team's panel (`[home, away]`, e.g.
    /// "PLAYER", "COMPUTER").
    pub team_notes: Option<[String; 2]>,
    /// Opacity of the bottom lines, `0…1` (1 by default): the key hints fade out once
    /// play starts. Values outside `0…1` are clamped; NaN counts as 1.
    pub lines_opacity: f32,
}

impl Default for Hud {
    fn default() -> Self {
        Hud {
            heading: String::new(),
            lines: Vec::new(),
            team_notes: None,
            lines_opacity: 1.0,
        }
    }
}

impl Hud {
    /// Whether there is nothing to draw.
    pub fn is_empty(&self) -> bool {
        self.heading.is_empty() && self.lines.is_empty() && self.team_notes.is_none()
    }
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

fn hud_overlay(hud: &Hud, w: f32, h: f32, out: &mut Vec<UiRect>) {
    let mid = (h / 110.0).round().max(2.0);
    let mut y = 0.36 * h;
    for line in hud.heading.lines().filter(|l| !l.trim().is_empty()) {
        let s = line.to_ascii_uppercase();
        // Shrink to fit 94 % of the width.
        let fit = (0.94 * w / font::text_width(&s, 1.0).max(1.0)).floor();
        let cell = mid.min(fit).max(1.0);
        let tw = font::text_width(&s, cell);
        rect(
            out,
            [
                0.5 * (w - tw) - 2.0 * cell,
                y - 1.5 * cell,
                0.5 * (w + tw) + 2.0 * cell,
                y + (font::GLYPH_H as f32 + 1.5) * cell,
            ],
            [0.0, 0.0, 0.03, 0.7],
        );
        title(out, w, &s, 0.5 * w, y, cell, [1.0, 0.95, 0.4]);
        y += (font::GLYPH_H as f32 + 4.0) * cell;
    }
    let alpha = if hud.lines_opacity.is_nan() {
        1.0
    } else {
        hud.lines_opacity.clamp(0.0, 1.0)
    };
    if alpha <= 0.0 {
        return;
    }
    let Some(layout) = hint_layout(hud, w, h) else {
        return;
    };
    let small = layout.cell;
    rect(out, layout.rect, [0.0, 0.0, 0.03, 0.6 * alpha]);
    let mut y = layout.rect[1] + small;
    for line in &layout.lines {
        let x = layout.rect[2] - small - font::text_width(line, small);
        text(out, line, x, y, small, [0.85, 0.9, 1.0, alpha]);
        y += layout.line_h;
    }
}

/// Widest the bottom lines may be, as a fraction of the image width: the bottom-right
/// corner, right of Home's last handle (Home's handles are on the near rail, none at
/// the Away end).
pub const HINT_WIDTH_FRAC: f32 = 0.27;

/// The bottom lines laid out: wrapped to fit, with their panel.
struct HintLayout {
    lines: Vec<String>,
    cell: f32,
    line_h: f32,
    rect: [f32; 4],
}

fn hint_layout(hud: &Hud, w: f32, h: f32) -> Option<HintLayout> {
    let cell = (h / 330.0).round().max(1.0);
    let max_chars = ((HINT_WIDTH_FRAC * w - 2.0 * cell) / (font::ADVANCE as f32 * cell))
        .floor()
        .max(8.0) as usize;
    let lines: Vec<String> = hud
        .lines
        .iter()
        .flat_map(|l| wrap(&l.to_ascii_uppercase(), max_chars))
        .collect();
    if lines.is_empty() {
        return None;
    }
    let line_h = (font::GLYPH_H as f32 + 3.0) * cell;
    let widest = lines
        .iter()
        .map(|l| font::text_width(l, cell))
        .fold(0.0, f32::max);
    let x1 = w - cell;
    let y1 = h - cell;
    let rect = [
        x1 - widest - 2.0 * cell,
        y1 - lines.len() as f32 * line_h - cell,
        x1,
        y1,
    ];
    Some(HintLayout {
        lines,
        cell,
        line_h,
        rect,
    })
}

/// The panel of the bottom lines (`hud.lines`, key hints and notices) `[x0, y0, x1,
/// y1]` in pixels on a `width × height` image; `None` when there are none.
pub fn hint_rect(hud: &Hud, width: f32, height: f32) -> Option<[f32; 4]> {
    hint_layout(hud, width, height).map(|l| l.rect)
}

/// Splits `s` at spaces into lines of at most `max` characters (a longer word is cut).
fn wrap(s: &str, max: usize) -> Vec<String> {
    let mut out = Vec::new();
    let mut line = String::new();
    for word in s.split_whitespace() {
        let word: String = word.chars().take(max).collect();
        if !line.is_empty() && line.chars().count() + 1 + word.chars().count() > max {
            out.push(std::mem::take(&mut line));
        }
        if !line.is_empty() {
            line.push(' ');
        }
        line.push_str(&word);
    }
    if !line.is_empty() {
        out.push(line);
    }
    out
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

fn axis_box(center: [f32; 3], half: [f32; 3], color: [f32; 3], emissive: f32) -> MeshInstance {
    cuboid(center, half, Quat::IDENTITY, color, emissive)
}

/// Cloth, markings, walls with goal mouths, goal boxes, the hull under the table, rods
/// and handles.
fn table_boxes(snap: &FrameSnapshot, out: &mut Vec<MeshInstance>) {
    let t = &snap.table;
    let hl = 0.5 * t.length_m as f32;
    let hw = 0.5 * t.width_m as f32;
    let wall_h = t.wall_height_m as f32;
    let gw = 0.5 * t.goal_width_m as f32;
    let gh = t.goal_height_m as f32;
    let gd = t.goal_depth_m as f32;
    let wt = 0.025f32; // wall thickness
    let cloth = [0.02, 0.20, 0.09];
    let wall = [0.09, 0.10, 0.16];
    let glow = [0.1, 0.6, 0.8];
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

/// The rectangle of the score display `[x0, y0, x1, y1]` (pixels) on a
/// `width × height` image: the top-left corner, where the camera leaves no handle
/// (the far handles are Away's, on the right half of the far rail).
pub fn score_rect(width: f32, height: f32) -> [f32; 4] {
    let _ = width;
    let cell = score_cell(height);
    let small = (0.5 * cell).round().max(1.0);
    let w = font::text_width(&"W".repeat(NAME_CHARS), small)
        + font::text_width("99", cell)
        + 5.5 * cell;
    let row_h = (font::GLYPH_H as f32 + 2.0) * cell;
    let h = cell + 2.0 * row_h + (font::GLYPH_H as f32 + 1.5) * small;
    let x0 = (0.01 * height).round();
    let y0 = (0.01 * height).round();
    [x0, y0, x0 + w, y0 + h]
}

/// Longest team name shown in the score panel, characters.
const NAME_CHARS: usize = 8;

fn score_cell(height: f32) -> f32 {
    (height / 140.0).round().max(2.0)
}

fn text(out: &mut Vec<UiRect>, s: &str, x: f32, y: f32, cell: f32, color: [f32; 4]) {
    out.extend(
        font::layout(s, x, y, cell)
            .into_iter()
            .map(|rect| UiRect { rect, color }),
    );
}

/// Text centred on `cx` with a darker drop shadow, its cell shrunk (whole pixels, at
/// least 1) so it stays inside an image `w` pixels wide; returns its height.
fn title(
    out: &mut Vec<UiRect>,
    w: f32,
    s: &str,
    cx: f32,
    y: f32,
    cell: f32,
    color: [f32; 3],
) -> f32 {
    let room = 2.0 * cx.min(w - cx) * 0.97;
    let cell = cell
        .min((room / font::text_width(s, 1.0).max(1.0)).floor())
        .max(1.0);
    let x = (cx - 0.5 * font::text_width(s, cell)).round();
    let off = (0.35 * cell).max(1.0);
    text(out, s, x + off, y + off, cell, [0.0, 0.0, 0.0, 0.7]);
    text(out, s, x, y, cell, rgba(color, 1.0));
    font::GLYPH_H as f32 * cell
}

fn rect(out: &mut Vec<UiRect>, r: [f32; 4], color: [f32; 4]) {
    out.push(UiRect { rect: r, color });
}

fn score_display(snap: &FrameSnapshot, width: f32, height: f32, out: &mut Vec<UiRect>) {
    let r = score_rect(width, height);
    let cell = score_cell(height);
    let small = (0.5 * cell).round().max(1.0);
    // Opaque: nothing shows through, and the corner is clear of every handle.
    rect(out, r, [0.01, 0.01, 0.03, 1.0]);
    let row_h = (font::GLYPH_H as f32 + 2.0) * cell;
    let name_x = r[0] + 2.5 * cell;
    let digits_x = r[2] - cell - font::text_width("99", cell);
    for team in Team::BOTH {
        let y0 = r[1] + cell + team.index() as f32 * row_h;
        let c = team_color(team);
        rect(
            out,
            [r[0], y0 - 0.5 * cell, r[0] + cell, y0 + row_h - 1.5 * cell],
            rgba(c, 1.0),
        );
        let name: String = team_label(snap, team).chars().take(NAME_CHARS).collect();
        let ny = y0 + 0.5 * font::GLYPH_H as f32 * (cell - small);
        text(out, &name, name_x, ny, small, rgba(c, 1.0));
        let goals = format!("{:>2}", snap.score[team.index()].min(99));
        text(out, &goals, digits_x, y0, cell, rgba(SCORE_COLOR, 1.0));
    }
    // The match clock under the scores.
    let secs = if snap.time_s.is_finite() {
        snap.time_s.clamp(0.0, 5999.0) as u32
    } else {
        0
    };
    let clock = format!("{}:{:02}", secs / 60, secs % 60);
    text(
        out,
        &clock,
        name_x,
        r[1] + cell + 2.0 * row_h,
        small,
        [0.75, 0.8, 0.9, 1.0],
    );
}

fn character_name(c: CharacterKind) -> (&'static str, &'static str) {
    match c {
        CharacterKind::TallThin => ("TALL THIN", "STRONG ATTACK"),
        CharacterKind::ShortWide => ("SHORT WIDE", "STRONG DEFENCE"),
    }
}

/// A team's name as shown: its name from the table, or HOME / AWAY.
fn team_label(snap: &FrameSnapshot, team: Team) -> String {
    let name = snap.table.team_names[team.index()]
        .trim()
        .to_ascii_uppercase();
    if name.is_empty() {
        match team {
            Team::Home => "HOME".into(),
            Team::Away => "AWAY".into(),
        }
    } else {
        name
    }
}

fn last_scorer(snap: &FrameSnapshot) -> Team {
    snap.events
        .iter()
        .rev()
        .find_map(|e| match e.kind {
            EventKind::Goal(side) => Some(side),
            _ => None,
        })
        .unwrap_or(if snap.score[1] > snap.score[0] {
            Team::Away
        } else {
            Team::Home
        })
}

fn overlay(snap: &FrameSnapshot, screen: Screen, hud: &Hud, w: f32, h: f32, out: &mut Vec<UiRect>) {
    let cx = 0.5 * w;
    let big = (h / 40.0).round().max(3.0);
    let mid = (h / 110.0).round().max(2.0);
    let small = (h / 180.0).round().max(1.0);
    let dim = |out: &mut Vec<UiRect>, a: f32| rect(out, [0.0, 0.0, w, h], [0.0, 0.0, 0.02, a]);
    let pulse = 0.65 + 0.35 * (snap.time_s as f32 * 4.0).sin();
    let white = [1.0, 1.0, 1.0];
    match screen {
        Screen::Match => score_display(snap, w, h, out),
        Screen::Attract => {
            dim(out, 0.35);
            let y = 0.18 * h;
            // The logo: each letter in a colour from blue to crimson.
            for (line, word) in [(0.0, "SPACE"), (1.0, "FOOSBALL")] {
                let n = word.len() as f32;
                let x0 = (cx - 0.5 * font::text_width(word, big)).round();
                for (i, ch) in word.chars().enumerate() {
                    let k = i as f32 / (n - 1.0);
                    let c = [
                        HOME_COLOR[0] + (AWAY_COLOR[0] - HOME_COLOR[0]) * k,
                        HOME_COLOR[1] + (1.0 - HOME_COLOR[1]) * (1.0 - (2.0 * k - 1.0).abs()) * 0.6,
                        HOME_COLOR[2] + (AWAY_COLOR[2] - HOME_COLOR[2]) * k,
                    ];
                    let x = x0 + (i as u32 * font::ADVANCE) as f32 * big;
                    let yy = y + line * 9.0 * big;
                    let s = ch.to_string();
                    text(
                        out,
                        &s,
                        x + 0.4 * big,
                        yy + 0.4 * big,
                        big,
                        [0.0, 0.0, 0.0, 0.7],
                    );
                    text(out, &s, x, yy, big, rgba(c, 1.0));
                }
            }
            title(
                out,
                w,
                "PUSH A ROD TO START",
                cx,
                0.78 * h,
                mid,
                scale3(white, pulse),
            );
        }
        Screen::CharacterSelect => {
            // No dimming: the live previews stand on their stage in the 3-D scene; the
            // text sits above and below them.
            title(out, w, "CHOOSE YOUR TEAM", cx, 0.03 * h, mid * 1.2, white);
            for (i, side) in Team::BOTH.into_iter().enumerate() {
                let px = if i == 0 { 0.27 * w } else { 0.73 * w };
                let (name, note) = character_name(snap.table.characters[i]);
                let label = team_label(snap, side);
                let pw = font::text_width("STRONG DEFENCE", mid) + 4.0 * mid;
                rect(
                    out,
                    [px - 0.5 * pw, 0.12 * h, px + 0.5 * pw, 0.12 * h + small],
                    rgba(team_color(side), 1.0),
                );
                title(out, w, &label, px, 0.14 * h, mid, team_color(side));
                rect(
                    out,
                    [px - 0.5 * pw, 0.67 * h, px + 0.5 * pw, 0.83 * h],
                    [0.0, 0.0, 0.03, 0.75],
                );
                title(out, w, name, px, 0.685 * h, mid, white);
                title(out, w, note, px, 0.77 * h, small, [0.7, 0.8, 0.9]);
                if let Some(notes) = &hud.team_notes {
                    let s = notes[i].to_ascii_uppercase();
                    title(out, w, &s, px, 0.845 * h, mid, team_color(side));
                }
            }
            title(
                out,
                w,
                "SPIN A ROD TO CHOOSE - PUSH TO START",
                cx,
                0.93 * h,
                mid,
                scale3(white, pulse),
            );
        }
        Screen::GoalCeremony => {
            dim(out, 0.25);
            let side = last_scorer(snap);
            title(out, w, "GOAL!", cx, 0.25 * h, big * 1.6, team_color(side));
            let who = match side {
                Team::Home => "HOME SCORES",
                Team::Away => "AWAY SCORES",
            };
            title(out, w, who, cx, 0.56 * h, mid, white);
            score_display(snap, w, h, out);
        }
        Screen::FinalResult => {
            dim(out, 0.6);
            title(out, w, "FINAL SCORE", cx, 0.14 * h, mid * 1.5, white);
            let s = format!("{} - {}", snap.score[0], snap.score[1]);
            title(out, w, &s, cx, 0.33 * h, big * 1.3, white);
            let (msg, c) = match snap.score[0].cmp(&snap.score[1]) {
                std::cmp::Ordering::Greater => ("HOME WINS", HOME_COLOR),
                std::cmp::Ordering::Less => ("AWAY WINS", AWAY_COLOR),
                std::cmp::Ordering::Equal => ("DRAW", white),
            };
            title(out, w, msg, cx, 0.65 * h, big, c);
            title(
                out,
                w,
                "PUSH A ROD TO PLAY AGAIN",
                cx,
                0.86 * h,
                mid,
                scale3(white, pulse),
            );
        }
        Screen::BoardLost => {
            dim(out, 0.72);
            title(out, w, "BOARD LOST", cx, 0.3 * h, big, [1.0, 0.35, 0.05]);
            title(out, w, "PLAY IS PAUSED", cx, 0.55 * h, mid, white);
            title(
                out,
                w,
                "RECONNECT THE BOARD TO RESUME",
                cx,
                0.66 * h,
                mid,
                scale3(white, pulse),
            );
        }
        Screen::Calibration => {
            dim(out, 0.55);
            title(out, w, "CALIBRATION", cx, 0.12 * h, big, [0.3, 1.0, 0.6]);
            if !hud.heading.is_empty() {
                // The live guidance replaces the generic instructions.
                return;
            }
            title(
                out,
                w,
                "PUSH AND PULL EACH ROD ALL THE WAY",
                cx,
                0.45 * h,
                mid,
                white,
            );
            title(out, w, "THEN SPIN IT BOTH WAYS", cx, 0.55 * h, mid, white);
            title(
                out,
                w,
                "PUSH ROD 1 TO BEGIN",
                cx,
                0.8 * h,
                mid,
                scale3(white, pulse),
            );
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

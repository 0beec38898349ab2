//! The 2-D overlay of each screen: titles, the score display, the characters' names, the
//! running game's live text ([`Hud`]), as screen-space rectangles.

use crate::font;
use crate::instances::{rgba, scale3, team_color, UiRect, AWAY_COLOR, HOME_COLOR};
use crate::view::{CharacterKind, EventKind, FrameSnapshot, Team};

/// Score digits colour (linear RGB): white.
pub const SCORE_COLOR: [f32; 3] = [1.0, 1.0, 1.0];

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

pub(crate) fn hud_overlay(hud: &Hud, w: f32, h: f32, out: &mut Vec<UiRect>) {
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

/// The sizes an overlay is laid out with: the image (px), its centre line, the three
/// text sizes (px per font pixel) and the pulse of blinking prompts (0.3 … 1).
struct OverlaySizes {
    w: f32,
    h: f32,
    cx: f32,
    big: f32,
    mid: f32,
    small: f32,
    pulse: f32,
}

/// The attract screen: the logo, each letter in a colour from blue to crimson, and the
/// prompt.
fn attract_overlay(sz: &OverlaySizes, out: &mut Vec<UiRect>) {
    let OverlaySizes {
        w,
        h,
        cx,
        big,
        mid,
        pulse,
        ..
    } = *sz;
    let white = [1.0, 1.0, 1.0];

    rect(out, [0.0, 0.0, w, h], [0.0, 0.0, 0.02, 0.35]);
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

/// The selection screen: each team's label, character and note, and the prompt.
fn character_select_overlay(
    snap: &FrameSnapshot,
    hud: &Hud,
    sz: &OverlaySizes,
    out: &mut Vec<UiRect>,
) {
    let OverlaySizes {
        w,
        h,
        cx,
        mid,
        small,
        pulse,
        ..
    } = *sz;
    let white = [1.0, 1.0, 1.0];

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

pub(crate) fn overlay(
    snap: &FrameSnapshot,
    screen: Screen,
    hud: &Hud,
    w: f32,
    h: f32,
    out: &mut Vec<UiRect>,
) {
    let cx = 0.5 * w;
    let big = (h / 40.0).round().max(3.0);
    let mid = (h / 110.0).round().max(2.0);
    let small = (h / 180.0).round().max(1.0);
    let dim = |out: &mut Vec<UiRect>, a: f32| rect(out, [0.0, 0.0, w, h], [0.0, 0.0, 0.02, a]);
    let pulse = 0.65 + 0.35 * (snap.time_s as f32 * 4.0).sin();
    let white = [1.0, 1.0, 1.0];
    let sz = OverlaySizes {
        w,
        h,
        cx,
        big,
        mid,
        small,
        pulse,
    };
    match screen {
        Screen::Match => score_display(snap, w, h, out),
        Screen::Attract => attract_overlay(&sz, out),
        Screen::CharacterSelect => character_select_overlay(snap, hud, &sz, out),
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

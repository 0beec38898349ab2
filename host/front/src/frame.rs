//! What a frame shows besides the match itself, from the session's state: which screen,
//! the names and glows on the table, the live text ([`Hud`]), which sounds play.

use crate::calibrate::Calibrator;
use crate::flow::{Flow, Stage, PUSH_SPEED_M_S};
use crate::view;
use foosball_audio::Sound;
use foosball_render::{FrameSnapshot, Hud, Screen};
use space_foosball::input::paddles::{InputHealth, RodInputs};

/// How long the key hints stay fully shown once play starts, s.
pub const HINTS_SHOWN_S: f64 = 4.0;
/// How long they then take to fade out, s.
pub const HINTS_FADE_S: f64 = 2.0;

/// The screen of `stage`: the board-lost screen while the board is `lost`, the goal
/// ceremony while it shows.
pub fn screen(stage: Stage, lost: bool, goal_ceremony: bool) -> Screen {
    if lost {
        return Screen::BoardLost;
    }
    match stage {
        Stage::Attract => Screen::Attract,
        Stage::CharacterSelect => Screen::CharacterSelect,
        Stage::Playing if goal_ceremony => Screen::GoalCeremony,
        Stage::Playing => Screen::Match,
        Stage::FinalResult => Screen::FinalResult,
        Stage::Calibration => Screen::Calibration,
    }
}

/// Marks the table of `snapshot` for `stage`: the selection screen names the characters
/// chosen so far, calibration makes the rod being calibrated glow.
pub fn mark_table(
    snapshot: &mut FrameSnapshot,
    stage: Stage,
    flow: &Flow,
    calibration_rod: Option<usize>,
) {
    if stage == Stage::CharacterSelect {
        for (i, c) in flow.characters().into_iter().enumerate() {
            snapshot.table.characters[i] = view::kind(c);
        }
    }
    if stage == Stage::Calibration {
        snapshot.held_rods.extend(calibration_rod);
    }
}

/// Only a match someone plays makes match sounds: while neither `stage` nor
/// `stage_before` is play, only the menu's sounds stay in `sounds` (the attract match
/// behind the menus is silent; its particles still show).
pub fn keep_match_sounds_in_play(stage: Stage, stage_before: Stage, sounds: &mut Vec<Sound>) {
    if stage != Stage::Playing && stage_before != Stage::Playing {
        sounds.retain(|s| matches!(s, Sound::MenuTick | Sound::MenuConfirm));
    }
}

/// Whether any rod is being pushed (resumes a paused match).
pub fn rods_pushed(rods: &RodInputs) -> bool {
    rods.health == InputHealth::Live
        && rods
            .rods
            .iter()
            .any(|r| r.slide_velocity_m_per_s.abs() >= PUSH_SPEED_M_S)
}

/// The session's state the live text is made from.
#[derive(Debug, Clone)]
pub struct HudState<'a> {
    /// The screens' stage.
    pub stage: Stage,
    /// The board is lost (its name is shown).
    pub lost: bool,
    /// The board's name.
    pub board_name: &'a str,
    /// The screens' flow.
    pub flow: &'a Flow,
    /// Calibration mode, while it runs (its own text is shown on its screen).
    pub calibrator: Option<&'a Calibrator>,
    /// The player paused the match.
    pub user_paused: bool,
    /// The heading of a paused match (the keys that resume or quit).
    pub paused_heading: &'a str,
    /// The emulated board's key hints.
    pub key_hints: &'a [String],
    /// A notice showing now (a saved calibration, a board that came back).
    pub notice: Option<&'a str>,
    /// Lines the attract screen shows between games, above the key hints (the match
    /// history's best: top scorers, fastest shot); empty for none.
    pub attract_lines: &'a [String],
    /// The session's clock, s.
    pub now_s: f64,
}

/// The live text of a frame.
pub fn hud(state: &HudState) -> Hud {
    let mut hud = match (state.calibrator, state.stage) {
        (Some(c), Stage::Calibration) => c.hud(),
        _ => Hud::default(),
    };
    if state.lost {
        hud.lines.push(format!("BOARD: {}", state.board_name));
        return hud;
    }
    if state.stage == Stage::Playing && state.user_paused {
        hud.heading = state.paused_heading.into();
    }
    if state.stage == Stage::CharacterSelect {
        let who = state
            .flow
            .joined()
            .map(|j| if j { "PLAYER" } else { "COMPUTER" }.to_string());
        hud.team_notes = Some(who);
    }
    if state.stage == Stage::Attract {
        hud.lines.extend(state.attract_lines.iter().cloned());
    }
    if matches!(state.stage, Stage::Attract | Stage::Playing) {
        hud.lines.extend(state.key_hints.iter().cloned());
    }
    if state.stage == Stage::Playing && state.notice.is_none() {
        // The key hints fade once play starts: shown 4 s, gone after 6 s (a notice
        // keeps them all shown).
        let played = state.now_s - state.flow.since_s();
        hud.lines_opacity =
            (1.0 - ((played - HINTS_SHOWN_S) / HINTS_FADE_S)).clamp(0.0, 1.0) as f32;
    }
    hud.lines.extend(state.notice.map(str::to_string));
    hud
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_board_lost_screen_wins_and_the_goal_ceremony_shows_only_in_play() {
        assert_eq!(screen(Stage::Playing, true, true), Screen::BoardLost);
        assert_eq!(screen(Stage::Playing, false, true), Screen::GoalCeremony);
        assert_eq!(screen(Stage::Playing, false, false), Screen::Match);
        assert_eq!(screen(Stage::Attract, false, true), Screen::Attract);
        assert_eq!(
            screen(Stage::Calibration, false, false),
            Screen::Calibration
        );
    }

    #[test]
    fn menus_keep_only_their_own_sounds() {
        let all = || {
            vec![
                Sound::MenuTick,
                Sound::Kick { speed_m_s: 2.0 },
                Sound::GoalFanfare,
                Sound::MenuConfirm,
            ]
        };
        let mut sounds = all();
        keep_match_sounds_in_play(Stage::Attract, Stage::CharacterSelect, &mut sounds);
        assert_eq!(sounds, vec![Sound::MenuTick, Sound::MenuConfirm]);
        let mut sounds = all();
        keep_match_sounds_in_play(Stage::FinalResult, Stage::Playing, &mut sounds);
        assert_eq!(sounds, all(), "the match's last sounds, as it ends");
    }
}

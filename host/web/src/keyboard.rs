//! The page's emulated board: the desktop's controls ([`crate::controls`]: keyboard,
//! mouse and gamepad → rod targets) move emulated rods, which send IN reports as a real
//! board does (counts per millisecond at the default calibration), so the game reads them
//! through the same decoder and tracker as WebHID's.
//!
//! The keyboard and mouse drive one rod of one team at a time, a gamepad (the Gamepad
//! API, through gilrs) one rod of the other team, as on the desktop (the table of keys is
//! in [`crate::controls`]). The rods follow their targets at a hand's speed, at most
//! [`MAX_SLIDE_M_PER_S`] and [`MAX_SPIN_RAD_PER_S`]. Time here is the match's: one
//! [`KeyboardBoard::step_report`] is one emulated millisecond, so held keys and sticks
//! move the rods by match time however slowly the page draws.

use crate::controls::{Controls, Key, PadState};
use foosball_protocol::{InReport, PaddleStatus, PADDLES};
use space_foosball::input::calibration::{DEFAULT_COUNTS_PER_MM, DEFAULT_ROD_RADIUS_M};
use space_foosball::side::Side;
use space_foosball::table::Table;

/// Fastest slide of an emulated rod, m/s (a hand on a real rod).
pub const MAX_SLIDE_M_PER_S: f64 = 1.0;
/// Fastest turn of an emulated rod, rad/s.
pub const MAX_SPIN_RAD_PER_S: f64 = 60.0;

/// Counts per metre of slide at the default calibration.
const COUNTS_PER_M: f64 = DEFAULT_COUNTS_PER_MM * 1e3;
/// Counts per radian of turn at the default calibration (the rod surface's motion).
const COUNTS_PER_RAD: f64 = COUNTS_PER_M * DEFAULT_ROD_RADIUS_M;

/// The emulated rods and the controls that move them. See the [module](self).
#[derive(Debug, Clone)]
pub struct KeyboardBoard {
    controls: Controls,
    /// Handle sign per table rod (table frame = sign × paddle frame).
    signs: Vec<f64>,
    /// Paddle-frame pose `[axial_m, angle_rad]` the emulated rods are at, per table rod.
    poses: Vec<[f64; 2]>,
    /// Counts already sent, per port `[axial, rotation]`.
    sent: [[i64; 2]; PADDLES],
    /// The gamepad's state of this frame; its edges (kick, rod choice) not yet applied
    /// while `pad_edges` is set.
    pad: Option<PadState>,
    pad_edges: bool,
    sequence: u16,
}

impl KeyboardBoard {
    /// The emulated board of `table`'s rods, the keyboard on Home's goalkeeper, a
    /// gamepad on Away's.
    pub fn new(table: &Table) -> Self {
        Self {
            controls: Controls::new(table),
            signs: table.rods.iter().map(|r| r.handle_sign()).collect(),
            poses: vec![[0.0; 2]; table.rods.len()],
            sent: [[0; 2]; PADDLES],
            pad: None,
            pad_edges: false,
            sequence: 0,
        }
    }

    /// The table rod the keyboard drives.
    pub fn keyboard_rod(&self) -> Option<usize> {
        self.controls.keyboard_rod()
    }

    /// The table rod the gamepad drives, while one is connected.
    pub fn pad_rod(&self) -> Option<usize> {
        self.pad.and(self.controls.pad_rod())
    }

    /// The team the keyboard plays.
    pub fn keyboard_team(&self) -> Side {
        self.controls.keyboard_team()
    }

    /// The keyboard's rod as its key number (1 = the team's goalkeeper rod).
    pub fn keyboard_key_number(&self) -> usize {
        self.controls.keyboard_key_number()
    }

    /// The table-frame pose `[slide_m, angle_rad]` of emulated rod `rod`.
    pub fn pose(&self, rod: usize) -> Option<[f64; 2]> {
        let p = self.poses.get(rod)?;
        let sign = self.signs[rod];
        Some([sign * p[0], sign * p[1]])
    }

    /// A key went down (`pressed`) or up.
    pub fn key(&mut self, key: Key, pressed: bool) {
        self.controls.key(key, pressed);
    }

    /// Puts the keyboard on table rod `rod` (calibration mode's rod).
    pub fn select_rod(&mut self, rod: usize) {
        self.controls.select_rod(rod);
    }

    /// Turns table rod `rod`'s target by `turns` full turns (calibration's T and G).
    pub fn turn_paddle(&mut self, rod: usize, turns: f64) {
        self.controls.turn_paddle(rod, turns);
    }

    /// Lets go of every held key (the page lost focus).
    pub fn release_all(&mut self) {
        self.controls.release_all();
    }

    /// Relative mouse motion, CSS pixels (`dy` > 0 = down). Non-finite motion is ignored.
    pub fn mouse_motion(&mut self, dx: f64, dy: f64) {
        self.controls.mouse_motion(dx, dy);
    }

    /// Mouse wheel, lines (> 0 = away from the user: spin forward). Non-finite is ignored.
    pub fn wheel(&mut self, lines: f64) {
        self.controls.wheel(lines);
    }

    /// The gamepad's state this frame (`None`: no gamepad). Its sticks act on every
    /// following millisecond until the next call; its edges (a kick, a rod choice) once.
    pub fn gamepad(&mut self, state: Option<PadState>) {
        self.pad = state;
        self.pad_edges = true;
    }

    /// One emulated millisecond: held keys and sticks move the targets, the rods move
    /// towards them at a hand's speed, and the report of that millisecond's counts comes
    /// out.
    pub fn step_report(&mut self) -> InReport {
        let dt = 1e-3;
        let pad = self.pad.map(|mut p| {
            if !std::mem::take(&mut self.pad_edges) {
                p.kick = false;
                p.choose = 0;
            }
            p
        });
        self.controls.tick(dt, pad);
        let mut report = InReport::all_present(self.sequence);
        self.sequence = self.sequence.wrapping_add(1);
        let limits = [MAX_SLIDE_M_PER_S * dt, MAX_SPIN_RAD_PER_S * dt];
        for ((port, target), pose) in self.controls.paddle_targets().zip(&mut self.poses) {
            let port = port.min(PADDLES - 1);
            for axis in 0..2 {
                let d = (target[axis] - pose[axis]).clamp(-limits[axis], limits[axis]);
                pose[axis] += d;
            }
            // Paddle frame, in counts of the default calibration.
            let counts = [
                (pose[0] * COUNTS_PER_M).round() as i64,
                (pose[1] * COUNTS_PER_RAD).round() as i64,
            ];
            let sent = &mut self.sent[port];
            let axial = (counts[0] - sent[0]).clamp(i64::from(i16::MIN), i64::from(i16::MAX));
            let rotation = (counts[1] - sent[1]).clamp(i64::from(i16::MIN), i64::from(i16::MAX));
            sent[0] += axial;
            sent[1] += rotation;
            let motion = &mut report.paddles[port];
            motion.axial = axial as i16;
            motion.rotation = rotation as i16;
            motion.status = PaddleStatus::PRESENT;
        }
        report
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use space_foosball::input::calibration::Calibration;
    use space_foosball::input::paddles::PaddleTracker;
    use std::f64::consts::TAU;

    /// Runs `ms` emulated milliseconds into a tracker at the default calibration.
    fn run(kb: &mut KeyboardBoard, tracker: &mut PaddleTracker, ms: usize) {
        for _ in 0..ms {
            let r = kb.step_report();
            let decoded = InReport::decode(&r.to_bytes()).unwrap();
            tracker.apply_report(&decoded);
        }
    }

    #[test]
    fn keys_move_the_chosen_rod_and_the_tracker_reads_the_same_pose() {
        let table = Table::standard();
        let mut kb = KeyboardBoard::new(&table);
        let mut tracker = PaddleTracker::new(&table, Calibration::default());
        kb.key(Key::Rod(3), true);
        let rod = kb.keyboard_rod().unwrap();
        kb.key(Key::SlideAway, true);
        run(&mut kb, &mut tracker, 50);
        kb.key(Key::SlideAway, false);
        kb.key(Key::Kick, true);
        run(&mut kb, &mut tracker, 300);
        let pose = kb.pose(rod).unwrap();
        // 50 ms at the key's 0.8 m/s, away from Home's player = +y.
        assert!((pose[0] - 0.04).abs() < 1e-9, "{pose:?}");
        // A kick is one full turn towards Away's goal, reached within 300 ms at 60 rad/s.
        let forward = -Side::Home.attack_dir();
        assert!((pose[1] - forward * TAU).abs() < 1e-9, "{pose:?}");
        // The tracker reads the pose back within one count of each axis.
        let state = tracker.rod(rod).unwrap();
        assert!(
            (state.slide_m - pose[0]).abs() <= 1.0 / COUNTS_PER_M,
            "{state:?}"
        );
        assert!(
            (state.angle_rad - pose[1]).abs() <= 1.0 / COUNTS_PER_RAD,
            "{state:?}"
        );
        // Other rods stayed put.
        for r in (0..table.rods.len()).filter(|&r| r != rod) {
            assert_eq!(tracker.rod(r).unwrap().slide_m, 0.0);
        }
    }

    #[test]
    fn push_holds_the_far_stop_and_returns_and_tab_switches_team() {
        let table = Table::standard();
        let mut kb = KeyboardBoard::new(&table);
        let rod = kb.keyboard_rod().unwrap();
        let h = table.rods[rod].half_travel_m();
        kb.key(Key::Push, true);
        for _ in 0..500 {
            kb.step_report();
        }
        assert!((kb.pose(rod).unwrap()[0] - h).abs() < 1e-9);
        kb.key(Key::Push, false);
        for _ in 0..500 {
            kb.step_report();
        }
        assert!(kb.pose(rod).unwrap()[0].abs() < 1e-9);
        kb.key(Key::SwitchTeam, true);
        assert_eq!(kb.keyboard_team(), Side::Away);
        let away = kb.keyboard_rod().unwrap();
        assert_eq!(table.rods[away].team, Side::Away);
        kb.mouse_motion(f64::NAN, 1.0);
        kb.wheel(f64::INFINITY);
        for _ in 0..10 {
            kb.step_report();
        }
        assert_eq!(kb.pose(away).unwrap(), [0.0, 0.0]);
    }

    #[test]
    fn a_gamepad_drives_the_other_team_and_its_kick_turns_once() {
        let table = Table::standard();
        let mut kb = KeyboardBoard::new(&table);
        assert_eq!(kb.pad_rod(), None);
        kb.gamepad(Some(PadState {
            slide: 1.0,
            kick: true,
            ..PadState::default()
        }));
        let rod = kb.pad_rod().unwrap();
        assert_eq!(table.rods[rod].team, Side::Away);
        for _ in 0..100 {
            kb.step_report();
        }
        // 100 ms of full stick at 0.9 m/s (slower than the rod's 1 m/s, so the rod keeps
        // up), away from Away's player = −y; the kick is one turn, not one a millisecond.
        let h = table.rods[rod].half_travel_m();
        let pose = kb.pose(rod).unwrap();
        assert!((pose[0] + (0.09f64).min(h)).abs() < 1e-9, "{pose:?}");
        for _ in 0..200 {
            kb.step_report();
        }
        let forward = -Side::Away.attack_dir();
        assert!((kb.pose(rod).unwrap()[1] - forward * TAU).abs() < 1e-9);
        // The keyboard's rod stayed put.
        assert_eq!(kb.pose(kb.keyboard_rod().unwrap()), Some([0.0, 0.0]));
    }
}

//! The page's emulated board: keyboard and mouse move the rods, which send IN reports as
//! a real board does (counts per millisecond at the default calibration), so the game
//! reads them through the same decoder and tracker as WebHID's.
//!
//! The controls are the desktop's (`space-foosball play` on its emulated board): one
//! rod of one team at a time, targets in the **table frame** (slide m along `+y`, angle
//! rad about `+y`), written to the paddles in the paddle frame (`× Rod::handle_sign`).
//! The rods follow their targets at a hand's speed, at most [`MAX_SLIDE_M_PER_S`] and
//! [`MAX_SPIN_RAD_PER_S`].
//!
//! | input | effect |
//! |---|---|
//! | `1`–`4` | choose the rod of your team, from your goal forward |
//! | mouse up / down, `W` `S`, `↑` `↓` | slide the rod (up = away from you) |
//! | mouse left / right, wheel, `A` `D`, `←` `→` | spin the rod |
//! | `Space` | kick: one full turn towards the opponent's goal |
//! | `Enter` | push the rod to the far stop while held (start, confirm) |
//! | `Tab` | play the other team |

use foosball_protocol::{InReport, PaddleStatus, PADDLES};
use space_foosball::input::calibration::{DEFAULT_COUNTS_PER_MM, DEFAULT_ROD_RADIUS_M};
use space_foosball::side::Side;
use space_foosball::table::Table;
use std::f64::consts::TAU;

/// Slide per pixel of vertical mouse motion, m.
pub const MOUSE_SLIDE_M_PER_PX: f64 = 0.0012;
/// Turn per pixel of horizontal mouse motion, rad.
pub const MOUSE_SPIN_RAD_PER_PX: f64 = 0.02;
/// Turn per wheel line, rad.
pub const WHEEL_RAD_PER_LINE: f64 = 0.6;
/// Slide speed while a slide key is held, m/s.
pub const KEY_SLIDE_M_PER_S: f64 = 0.8;
/// Turn speed while a spin key is held, rad/s.
pub const KEY_SPIN_RAD_PER_S: f64 = 10.0;
/// Fastest slide of an emulated rod, m/s (a hand on a real rod).
pub const MAX_SLIDE_M_PER_S: f64 = 1.0;
/// Fastest turn of an emulated rod, rad/s.
pub const MAX_SPIN_RAD_PER_S: f64 = 60.0;

/// Counts per metre of slide at the default calibration.
const COUNTS_PER_M: f64 = DEFAULT_COUNTS_PER_MM * 1e3;
/// Counts per radian of turn at the default calibration (the rod surface's motion).
const COUNTS_PER_RAD: f64 = COUNTS_PER_M * DEFAULT_ROD_RADIUS_M;

/// A control a key stands for.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Key {
    /// Choose the team's rod `n` (0-based, from its own goal).
    Rod(usize),
    /// Slide away from the player.
    SlideAway,
    /// Slide towards the player.
    SlideNear,
    /// Spin forward (towards the opponent).
    SpinForward,
    /// Spin backward.
    SpinBack,
    /// One full turn forward.
    Kick,
    /// Hold the rod at the far stop.
    Push,
    /// Switch to the other team.
    SwitchTeam,
}

#[derive(Debug, Clone)]
struct RodInfo {
    port: usize,
    team: Side,
    sign: f64,
    half_travel_m: f64,
}

/// The emulated rods and the keys that move them. See the [module](self).
#[derive(Debug, Clone)]
pub struct KeyboardBoard {
    rods: Vec<RodInfo>,
    /// Table-frame `[slide_m, angle_rad]` the keys ask for, per rod.
    targets: Vec<[f64; 2]>,
    /// Table-frame pose the emulated rods are at, per rod.
    poses: Vec<[f64; 2]>,
    /// Counts already sent, per port `[axial, rotation]`.
    sent: [[i64; 2]; PADDLES],
    team: Side,
    rod: usize,
    held: [bool; 4],
    push_return: Option<f64>,
    sequence: u16,
}

impl KeyboardBoard {
    /// The emulated board of `table`'s rods, the keyboard on Home's goalkeeper.
    pub fn new(table: &Table) -> Self {
        let rods: Vec<RodInfo> = table
            .rods
            .iter()
            .map(|r| RodInfo {
                port: r.port.min(PADDLES - 1),
                team: r.team,
                sign: r.handle_sign(),
                half_travel_m: r.half_travel_m(),
            })
            .collect();
        Self {
            targets: vec![[0.0; 2]; rods.len()],
            poses: vec![[0.0; 2]; rods.len()],
            rods,
            sent: [[0; 2]; PADDLES],
            team: Side::Home,
            rod: 0,
            held: [false; 4],
            push_return: None,
            sequence: 0,
        }
    }

    fn team_rods(&self, team: Side) -> Vec<usize> {
        let mut rods: Vec<usize> = (0..self.rods.len())
            .filter(|&i| self.rods[i].team == team)
            .collect();
        if team == Side::Away {
            rods.reverse(); // rods are stored from the Home goal
        }
        rods
    }

    /// The table rod the keyboard drives.
    pub fn keyboard_rod(&self) -> Option<usize> {
        self.team_rods(self.team).get(self.rod).copied()
    }

    /// The team the keyboard plays.
    pub fn keyboard_team(&self) -> Side {
        self.team
    }

    /// The keyboard's rod as its key number (1 = the team's goalkeeper rod).
    pub fn keyboard_key_number(&self) -> usize {
        self.rod + 1
    }

    /// The table-frame pose `[slide_m, angle_rad]` of emulated rod `rod`.
    pub fn pose(&self, rod: usize) -> Option<[f64; 2]> {
        self.poses.get(rod).copied()
    }

    fn slide_by(&mut self, d_m: f64) {
        if let Some(r) = self.keyboard_rod() {
            let h = self.rods[r].half_travel_m;
            let t = &mut self.targets[r][0];
            *t = (*t + d_m).clamp(-h, h);
        }
    }

    fn spin_by(&mut self, d_rad: f64) {
        if let Some(r) = self.keyboard_rod() {
            // Forward = the feet swing towards the opponent's goal (−attack_dir about +y).
            let forward = -self.rods[r].team.attack_dir();
            self.targets[r][1] += forward * d_rad;
        }
    }

    fn end_push(&mut self) {
        if let (Some(r), Some(back)) = (self.keyboard_rod(), self.push_return.take()) {
            self.targets[r][0] = back;
        }
    }

    /// A key went down (`pressed`) or up.
    pub fn key(&mut self, key: Key, pressed: bool) {
        match key {
            Key::Rod(n) if pressed && n < self.team_rods(self.team).len() => {
                self.end_push();
                self.rod = n;
            }
            Key::SlideAway => self.held[0] = pressed,
            Key::SlideNear => self.held[1] = pressed,
            Key::SpinForward => self.held[2] = pressed,
            Key::SpinBack => self.held[3] = pressed,
            Key::Kick if pressed => self.spin_by(TAU),
            Key::Push if pressed => {
                if let (Some(r), None) = (self.keyboard_rod(), self.push_return) {
                    self.push_return = Some(self.targets[r][0]);
                    let info = &self.rods[r];
                    // The far stop, seen from the rod's own player.
                    self.targets[r][0] = info.sign * info.half_travel_m;
                }
            }
            Key::Push => self.end_push(),
            Key::SwitchTeam if pressed => {
                self.end_push();
                self.team = self.team.other();
                self.rod = 0;
            }
            _ => {}
        }
    }

    /// Relative mouse motion, CSS pixels (`dy` > 0 = down). Non-finite motion is ignored.
    pub fn mouse_motion(&mut self, dx: f64, dy: f64) {
        if !(dx.is_finite() && dy.is_finite()) {
            return;
        }
        if let Some(r) = self.keyboard_rod() {
            // Up on the screen is away from the player: +y for Home, −y for Away.
            let away = self.rods[r].sign;
            self.slide_by(-dy * MOUSE_SLIDE_M_PER_PX * away);
        }
        self.spin_by(dx * MOUSE_SPIN_RAD_PER_PX);
    }

    /// Mouse wheel, lines (> 0 = away from the user: spin forward). Non-finite is ignored.
    pub fn wheel(&mut self, lines: f64) {
        if lines.is_finite() {
            self.spin_by(lines * WHEEL_RAD_PER_LINE);
        }
    }

    /// One emulated millisecond: held keys move the targets, the rods move towards them
    /// at a hand's speed, and the report of that millisecond's counts comes out.
    pub fn step_report(&mut self) -> InReport {
        let dt = 1e-3;
        if let Some(r) = self.keyboard_rod() {
            let away = self.rods[r].sign;
            let slide = f64::from(u8::from(self.held[0])) - f64::from(u8::from(self.held[1]));
            self.slide_by(slide * away * KEY_SLIDE_M_PER_S * dt);
        }
        let spin = f64::from(u8::from(self.held[2])) - f64::from(u8::from(self.held[3]));
        self.spin_by(spin * KEY_SPIN_RAD_PER_S * dt);
        let mut report = InReport::all_present(self.sequence);
        self.sequence = self.sequence.wrapping_add(1);
        for ((info, target), pose) in self.rods.iter().zip(&self.targets).zip(&mut self.poses) {
            let limits = [MAX_SLIDE_M_PER_S * dt, MAX_SPIN_RAD_PER_S * dt];
            for axis in 0..2 {
                let d = (target[axis] - pose[axis]).clamp(-limits[axis], limits[axis]);
                pose[axis] += d;
            }
            // Paddle frame, in counts of the default calibration.
            let counts = [
                (info.sign * pose[0] * COUNTS_PER_M).round() as i64,
                (info.sign * pose[1] * COUNTS_PER_RAD).round() as i64,
            ];
            let sent = &mut self.sent[info.port];
            let axial = (counts[0] - sent[0]).clamp(i64::from(i16::MIN), i64::from(i16::MAX));
            let rotation = (counts[1] - sent[1]).clamp(i64::from(i16::MIN), i64::from(i16::MAX));
            sent[0] += axial;
            sent[1] += rotation;
            let motion = &mut report.paddles[info.port];
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
}

//! Keyboard, mouse and gamepad → targets for the emulated board's rods.
//!
//! With no board plugged in the game runs an emulated board whose rods follow targets at
//! a bounded hand speed: on the desktop the built-in emulated board's live targets, in
//! the browser the page's emulated board (which compiles this file). [`Controls`] keeps
//! one target per rod in the **table frame** (slide m along `+y`, angle rad about `+y`)
//! and hands them out in the paddle frame (`× Rod::handle_sign`, see
//! `space_foosball::input`) by [`Controls::paddle_targets`]. The keyboard and mouse
//! drive one rod of one team at a time; a gamepad drives a rod of the other team.
//!
//! | input | effect |
//! |---|---|
//! | `1`–`4` | choose the rod of your team, from your goal forward |
//! | mouse up / down, `W` `S`, `↑` `↓` | slide the rod (up = away from you) |
//! | mouse left / right, wheel, `A` `D`, `←` `→` | spin the rod |
//! | `Space` | kick: one full turn towards the opponent's goal |
//! | `Enter` | push the rod to the far stop while held (start, confirm) |
//! | `Tab` | play the other team |
//! | gamepad: left stick slide, right stick spin, `A` kick, `LB`/`RB` choose rod, `Start` push | the other team's rods |

use space_foosball::side::Side;
use space_foosball::table::Table;
use std::f64::consts::TAU;
use winit::keyboard::KeyCode;

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
/// Gamepad stick at full deflection: slide speed, m/s.
pub const PAD_SLIDE_M_PER_S: f64 = 0.9;
/// Gamepad stick at full deflection: turn speed, rad/s.
pub const PAD_SPIN_RAD_PER_S: f64 = 25.0;

/// A control a key stands for (the window maps physical keys to these).
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

/// The emulated board's control for a physical key (layout independent: `W` is the key
/// where US keyboards have W).
pub fn map_key(code: KeyCode) -> Option<Key> {
    Some(match code {
        KeyCode::Digit1 => Key::Rod(0),
        KeyCode::Digit2 => Key::Rod(1),
        KeyCode::Digit3 => Key::Rod(2),
        KeyCode::Digit4 => Key::Rod(3),
        KeyCode::KeyW | KeyCode::ArrowUp => Key::SlideAway,
        KeyCode::KeyS | KeyCode::ArrowDown => Key::SlideNear,
        KeyCode::KeyD | KeyCode::ArrowRight => Key::SpinForward,
        KeyCode::KeyA | KeyCode::ArrowLeft => Key::SpinBack,
        KeyCode::Space => Key::Kick,
        KeyCode::Enter | KeyCode::NumpadEnter => Key::Push,
        KeyCode::Tab => Key::SwitchTeam,
        _ => return None,
    })
}

/// A stick or mouse value, or nothing where it is not a number.
fn finite_or_zero(v: f64) -> f64 {
    if v.is_finite() {
        v
    } else {
        0.0
    }
}

/// The one rod a device drives at a time.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Cursor {
    team: Side,
    /// Index into the team's rods.
    rod: usize,
}

/// What a gamepad asks for this frame (sticks in −1…1).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct PadState {
    /// Slide stick (+1 = away from the player).
    pub slide: f64,
    /// Spin stick (+1 = forward).
    pub spin: f64,
    /// Kick pressed this frame.
    pub kick: bool,
    /// Push held.
    pub push: bool,
    /// Choose the next (+1) or previous (−1) rod this frame.
    pub choose: i32,
}

#[derive(Debug, Clone)]
struct RodInfo {
    port: usize,
    team: Side,
    sign: f64,
    half_travel_m: f64,
}

/// The targets of every rod and which rod each device drives. See the [module](self).
#[derive(Debug, Clone)]
pub struct Controls {
    rods: Vec<RodInfo>,
    /// Table-frame `[slide_m, angle_rad]` per rod of the table.
    targets: Vec<[f64; 2]>,
    keyboard: Cursor,
    pad: Cursor,
    held: [bool; 4],
    /// While pushing (Enter / Start): the slide to go back to, per device.
    push_return: [Option<f64>; 2],
}

impl Controls {
    /// Controls for `table`'s rods: the keyboard and mouse on Home's first rod, a
    /// gamepad on Away's.
    pub fn new(table: &Table) -> Self {
        let rods: Vec<RodInfo> = table
            .rods
            .iter()
            .map(|r| RodInfo {
                port: r.port,
                team: r.team,
                sign: r.handle_sign(),
                half_travel_m: r.half_travel_m(),
            })
            .collect();
        Self {
            targets: vec![[0.0; 2]; rods.len()],
            rods,
            keyboard: Cursor {
                team: Side::Home,
                rod: 0,
            },
            pad: Cursor {
                team: Side::Away,
                rod: 0,
            },
            held: [false; 4],
            push_return: [None; 2],
        }
    }

    /// Table rod indices of `team`, from its own goal forward.
    fn team_rods(&self, team: Side) -> Vec<usize> {
        let mut rods: Vec<usize> = (0..self.rods.len())
            .filter(|&i| self.rods[i].team == team)
            .collect();
        if team == Side::Away {
            rods.reverse(); // rods are stored from the Home goal
        }
        rods
    }

    fn rod_of(&self, cursor: Cursor) -> Option<usize> {
        self.team_rods(cursor.team).get(cursor.rod).copied()
    }

    /// The team the keyboard and mouse play.
    pub fn keyboard_team(&self) -> Side {
        self.keyboard.team
    }

    /// The keyboard's rod as its key number (1 = the team's goalkeeper rod).
    pub fn keyboard_key_number(&self) -> usize {
        self.keyboard.rod + 1
    }

    /// The table rod the keyboard and mouse drive.
    pub fn keyboard_rod(&self) -> Option<usize> {
        self.rod_of(self.keyboard)
    }

    /// The table rod a gamepad drives.
    pub fn pad_rod(&self) -> Option<usize> {
        self.rod_of(self.pad)
    }

    #[cfg(test)]
    /// The table-frame target `[slide_m, angle_rad]` of rod `rod`.
    pub fn target(&self, rod: usize) -> Option<[f64; 2]> {
        self.targets.get(rod).copied()
    }

    fn slide_by(&mut self, rod: Option<usize>, d_m: f64) {
        if let Some(r) = rod {
            let h = self.rods[r].half_travel_m;
            let t = &mut self.targets[r][0];
            *t = (*t + d_m).clamp(-h, h);
        }
    }

    fn spin_by(&mut self, rod: Option<usize>, d_rad: f64) {
        if let Some(r) = rod {
            // Forward = the feet swing towards the opponent's goal (−attack_dir about +y).
            let forward = -self.rods[r].team.attack_dir();
            self.targets[r][1] += forward * d_rad;
        }
    }

    /// A key went down (`pressed`) or up.
    pub fn key(&mut self, key: Key, pressed: bool) {
        let rod = self.keyboard_rod();
        let hold = |held: &mut [bool; 4], i: usize| held[i] = pressed;
        match key {
            Key::Rod(n) if pressed && n < self.team_rods(self.keyboard.team).len() => {
                self.end_push(0);
                self.keyboard.rod = n;
            }
            Key::SlideAway => hold(&mut self.held, 0),
            Key::SlideNear => hold(&mut self.held, 1),
            Key::SpinForward => hold(&mut self.held, 2),
            Key::SpinBack => hold(&mut self.held, 3),
            Key::Kick if pressed => self.spin_by(rod, TAU),
            Key::Push => {
                if pressed {
                    self.start_push(0, rod);
                } else {
                    self.end_push(0);
                }
            }
            Key::SwitchTeam if pressed => {
                self.end_push(0);
                let team = self.keyboard.team.other();
                self.keyboard = Cursor { team, rod: 0 };
                self.pad = Cursor {
                    team: team.other(),
                    rod: 0,
                };
            }
            _ => {}
        }
    }

    fn start_push(&mut self, device: usize, rod: Option<usize>) {
        if let (Some(r), None) = (rod, self.push_return[device]) {
            self.push_return[device] = Some(self.targets[r][0]);
            // The far stop, seen from the rod's own player.
            let info = &self.rods[r];
            self.targets[r][0] = info.sign * info.half_travel_m;
        }
    }

    fn end_push(&mut self, device: usize) {
        let rod = if device == 0 {
            self.keyboard_rod()
        } else {
            self.pad_rod()
        };
        if let (Some(r), Some(back)) = (rod, self.push_return[device].take()) {
            self.targets[r][0] = back;
        }
    }

    /// Makes the keyboard and mouse drive table rod `rod` (calibration mode asks for
    /// each rod in turn).
    pub fn select_rod(&mut self, rod: usize) {
        if self.keyboard_rod() == Some(rod) {
            return;
        }
        let Some(info) = self.rods.get(rod) else {
            return;
        };
        let team = info.team;
        if let Some(n) = self.team_rods(team).iter().position(|&r| r == rod) {
            self.end_push(0);
            self.keyboard = Cursor { team, rod: n };
            self.pad = Cursor {
                team: team.other(),
                rod: 0,
            };
        }
    }

    /// Turns table rod `rod` by `turns` full turns in its paddle frame (positive as the
    /// calibration motion's "forward").
    pub fn turn_paddle(&mut self, rod: usize, turns: f64) {
        if let Some(info) = self.rods.get(rod) {
            self.targets[rod][1] += info.sign * turns * TAU;
        }
    }

    /// Lets go of every held key (the window lost focus: their releases never arrive).
    pub fn release_all(&mut self) {
        self.held = [false; 4];
        self.end_push(0);
    }

    /// Relative mouse motion, pixels (`dy` > 0 = down). Non-finite motion is ignored.
    pub fn mouse_motion(&mut self, dx: f64, dy: f64) {
        if !(dx.is_finite() && dy.is_finite()) {
            return;
        }
        let rod = self.keyboard_rod();
        if let Some(r) = rod {
            // Up on the screen is away from the player: +y for Home, −y for Away.
            let away = self.rods[r].sign;
            self.slide_by(rod, -dy * MOUSE_SLIDE_M_PER_PX * away);
        }
        self.spin_by(rod, dx * MOUSE_SPIN_RAD_PER_PX);
    }

    /// Mouse wheel, lines (> 0 = away from the user: spin forward). Non-finite is ignored.
    pub fn wheel(&mut self, lines: f64) {
        let rod = self.keyboard_rod();
        self.spin_by(rod, finite_or_zero(lines) * WHEEL_RAD_PER_LINE);
    }

    /// Advances held keys and the gamepad by `dt_s` seconds (at most 0.1 s a call).
    pub fn tick(&mut self, dt_s: f64, pad: Option<PadState>) {
        let dt = finite_or_zero(dt_s).clamp(0.0, 0.1);
        let rod = self.keyboard_rod();
        if let Some(r) = rod {
            let away = self.rods[r].sign;
            let slide = f64::from(u8::from(self.held[0])) - f64::from(u8::from(self.held[1]));
            self.slide_by(rod, slide * away * KEY_SLIDE_M_PER_S * dt);
        }
        let spin = f64::from(u8::from(self.held[2])) - f64::from(u8::from(self.held[3]));
        self.spin_by(rod, spin * KEY_SPIN_RAD_PER_S * dt);
        if let Some(p) = pad {
            if p.choose != 0 {
                self.end_push(1);
                let n = self.team_rods(self.pad.team).len() as i32;
                if n > 0 {
                    self.pad.rod = (self.pad.rod as i32 + p.choose).rem_euclid(n) as usize;
                }
            }
            let rod = self.pad_rod();
            if let Some(r) = rod {
                let away = self.rods[r].sign;
                let slide = finite_or_zero(p.slide).clamp(-1.0, 1.0);
                self.slide_by(rod, slide * away * PAD_SLIDE_M_PER_S * dt);
            }
            let spin = finite_or_zero(p.spin).clamp(-1.0, 1.0);
            self.spin_by(rod, spin * PAD_SPIN_RAD_PER_S * dt);
            if p.kick {
                self.spin_by(rod, TAU);
            }
            if p.push {
                self.start_push(1, rod);
            } else {
                self.end_push(1);
            }
        }
    }

    /// Every rod's target for the emulated board, in table-rod order: its port and
    /// `[axial_m, angle_rad]` in the paddle frame.
    pub fn paddle_targets(&self) -> impl Iterator<Item = (usize, [f64; 2])> + '_ {
        self.rods
            .iter()
            .zip(&self.targets)
            .map(|(info, t)| (info.port, [info.sign * t[0], info.sign * t[1]]))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn keys_choose_rods_of_the_keyboard_team_and_move_only_that_rod() {
        let table = Table::standard();
        let mut c = Controls::new(&table);
        let home: Vec<usize> = table.rods_of(Side::Home).collect();
        assert_eq!(c.keyboard_rod(), Some(home[0]));
        c.key(Key::Rod(2), true);
        let r = c.keyboard_rod().unwrap();
        assert_eq!(r, home[2]);
        c.key(Key::SlideAway, true);
        c.tick(0.05, None);
        c.key(Key::SlideAway, false);
        c.tick(0.05, None);
        let t = c.target(r).unwrap();
        assert!((t[0] - 0.04).abs() < 1e-9, "{t:?}");
        // Every other rod stays put.
        for i in (0..table.rods.len()).filter(|&i| i != r) {
            assert_eq!(c.target(i), Some([0.0, 0.0]));
        }
        // Slides stop at the travel.
        c.mouse_motion(0.0, -1e6);
        assert_eq!(c.target(r).unwrap()[0], table.rods[r].half_travel_m());
    }

    #[test]
    fn kick_turns_the_feet_towards_the_opponent_goal() {
        let table = Table::standard();
        let mut c = Controls::new(&table);
        let r = c.keyboard_rod().unwrap();
        c.key(Key::Kick, true);
        // Home attacks +x: feet at −z swing to +x for a negative angle about +y.
        assert!((c.target(r).unwrap()[1] + TAU).abs() < 1e-12);
        c.key(Key::SwitchTeam, true);
        assert_eq!(c.keyboard_team(), Side::Away);
        let a = c.keyboard_rod().unwrap();
        assert_eq!(table.rods[a].team, Side::Away);
        c.key(Key::Kick, true);
        assert!((c.target(a).unwrap()[1] - TAU).abs() < 1e-12);
    }

    #[test]
    fn push_holds_the_far_stop_and_returns() {
        let table = Table::standard();
        let mut c = Controls::new(&table);
        c.key(Key::Rod(1), true);
        let r = c.keyboard_rod().unwrap();
        c.key(Key::Push, true);
        assert_eq!(c.target(r).unwrap()[0], table.rods[r].half_travel_m());
        c.key(Key::Push, false);
        assert_eq!(c.target(r).unwrap()[0], 0.0);
    }

    #[test]
    fn targets_reach_the_emulated_paddles_in_the_paddle_frame() {
        let table = Table::standard();
        let mut c = Controls::new(&table);
        c.key(Key::SwitchTeam, true);
        let a = c.keyboard_rod().unwrap();
        c.mouse_motion(0.0, -10.0); // up: away from the Away player = −y
        let t = c.target(a).unwrap();
        assert!(t[0] < 0.0);
        let (port, p) = c.paddle_targets().nth(a).unwrap();
        assert_eq!(port, table.rods[a].port);
        // Away's handles are on the other side: the paddle frame is the table's mirrored.
        assert!((p[0] - (-t[0])).abs() < 1e-12 && p[0] > 0.0);
    }

    #[test]
    fn the_desktop_keys_map_to_controls_and_nothing_else() {
        assert_eq!(map_key(KeyCode::Digit3), Some(Key::Rod(2)));
        assert_eq!(map_key(KeyCode::ArrowUp), Some(Key::SlideAway));
        assert_eq!(map_key(KeyCode::Space), Some(Key::Kick));
        assert_eq!(map_key(KeyCode::Enter), Some(Key::Push));
        assert_eq!(map_key(KeyCode::KeyQ), None);
    }

    #[test]
    fn non_finite_input_moves_nothing_and_release_all_lets_go() {
        let table = Table::standard();
        let mut c = Controls::new(&table);
        let r = c.keyboard_rod().unwrap();
        c.mouse_motion(f64::NAN, f64::INFINITY);
        c.wheel(f64::NEG_INFINITY);
        let pad = PadState {
            slide: f64::NAN,
            spin: f64::INFINITY,
            ..PadState::default()
        };
        c.tick(f64::NAN, Some(pad));
        c.tick(0.05, Some(pad));
        assert!(c.paddle_targets().all(|(_, t)| t == [0.0, 0.0]));
        c.key(Key::SlideAway, true);
        c.key(Key::Push, true);
        c.release_all();
        c.tick(0.05, None);
        assert_eq!(c.target(r), Some([0.0, 0.0]));
    }

    #[test]
    fn gamepad_drives_the_other_team() {
        let table = Table::standard();
        let mut c = Controls::new(&table);
        let pad = PadState {
            slide: 1.0,
            choose: 1,
            ..PadState::default()
        };
        c.tick(0.1, Some(pad));
        let r = c.pad_rod().unwrap();
        assert_eq!(table.rods[r].team, Side::Away);
        assert!(c.target(r).unwrap()[0] < 0.0);
    }
}

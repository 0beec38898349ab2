//! Keys → the rods of the emulated board, moved as a hand on the cabinet would.
//!
//! The keyboard plays one team's rods, one rod at a time, on the cabinet's wiring: rod
//! `i` of the table is on port `i`, from the Home goal — Home's goalkeeper, defence,
//! midfield and attack on ports 0, 1, 3, 5, Away's on 7, 6, 4, 2 (`1`–`4` count from
//! the team's own goal). Targets are in each rod's **paddle frame**, the player's own:
//! slide positive away from the player, and forward spin (the feet towards the
//! opponent's goal) negative, whichever team. The rods move towards their targets at a
//! hand's speed ([`crate::motion::live::LiveLimits`]); a terminal repeats a held key, so
//! holding `W` slides steadily and holding `Enter` keeps the rod pushed.

use crate::motion::live::LiveHandle;
use crate::motion::RodPose;
use foosball_protocol::PADDLES;
use std::f64::consts::TAU;
use std::time::{Duration, Instant};

use super::keys::Key;

/// Slide per key press, m (a terminal's key repeat, about 30 presses/s, makes about
/// the game window's 0.8 m/s).
pub const SLIDE_STEP_M: f64 = 0.025;
/// Turn per key press, rad (about the game window's 10 rad/s at key repeat).
pub const SPIN_STEP_RAD: f64 = 0.35;
/// How long a push holds the far stop after the last `Enter`, before the rod returns.
pub const PUSH_HOLD: Duration = Duration::from_millis(250);

/// A team of the table.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Team {
    /// The team whose goal is at the start of the table (ports 0, 1, 3, 5).
    Home,
    /// The other team (ports 7, 6, 4, 2).
    Away,
}

impl Team {
    /// The team's name as the game shows it.
    pub fn name(self) -> &'static str {
        match self {
            Team::Home => "Home",
            Team::Away => "Away",
        }
    }

    fn other(self) -> Self {
        match self {
            Team::Home => Team::Away,
            Team::Away => Team::Home,
        }
    }

    /// Ports of the team's rods, from its own goal forward.
    pub fn ports(self) -> [usize; 4] {
        match self {
            Team::Home => [0, 1, 3, 5],
            Team::Away => [7, 6, 4, 2],
        }
    }
}

/// Names of the rods from the team's own goal forward.
const ROD_NAMES: [&str; 4] = ["goalkeeper", "defence", "midfield", "attack"];
/// Half the axial travel of each rod, from the team's own goal forward, m (the
/// standard table: 190, 356, 116 and 180 mm of travel).
pub const HALF_TRAVEL_M: [f64; 4] = [0.095, 0.178, 0.058, 0.090];

/// A push under way: the rod at its far stop until `until`, then back to `back_m`.
#[derive(Debug, Clone, Copy)]
struct Push {
    port: usize,
    back_m: f64,
    until: Instant,
}

/// The rods' targets and which rod the keys drive. See the [module](self).
#[derive(Debug)]
pub struct HandControls {
    handle: LiveHandle,
    team: Team,
    /// Index into the team's rods.
    rod: usize,
    targets: [RodPose; PADDLES],
    push: Option<Push>,
}

impl HandControls {
    /// Controls writing to `handle`, on Home's goalkeeper rod, every rod at rest.
    pub fn new(handle: LiveHandle) -> Self {
        let controls = Self {
            handle,
            team: Team::Home,
            rod: 0,
            targets: [RodPose::default(); PADDLES],
            push: None,
        };
        controls.apply();
        controls
    }

    /// The team and the rod (0–3, from the team's goal) the keys drive, and its port.
    pub fn selected(&self) -> (Team, usize, usize) {
        (self.team, self.rod, self.team.ports()[self.rod])
    }

    /// One line saying which rod the keys drive.
    pub fn describe(&self) -> String {
        let (team, rod, port) = self.selected();
        format!(
            "{} rod {} ({}, port {port})",
            team.name(),
            rod + 1,
            ROD_NAMES[rod]
        )
    }

    /// The paddle-frame target of `port`.
    pub fn target(&self, port: usize) -> Option<RodPose> {
        self.targets.get(port).copied()
    }

    /// When a push under way ends, if one is.
    pub fn next_deadline(&self) -> Option<Instant> {
        self.push.map(|p| p.until)
    }

    /// A key pressed at `now`. Returns a line to show when the driven rod changed.
    /// [`Key::Quit`] is the caller's business and changes nothing here.
    pub fn key(&mut self, key: Key, now: Instant) -> Option<String> {
        if key != Key::Push {
            self.end_push();
        }
        let (_, rod, port) = self.selected();
        let mut changed = false;
        match key {
            Key::Rod(n) if n < 4 && n != self.rod => {
                self.rod = n;
                changed = true;
            }
            Key::SwitchTeam => {
                self.team = self.team.other();
                self.rod = 0;
                changed = true;
            }
            Key::SlideAway => self.slide(port, rod, SLIDE_STEP_M),
            Key::SlideNear => self.slide(port, rod, -SLIDE_STEP_M),
            Key::SpinForward => self.targets[port].angle_rad -= SPIN_STEP_RAD,
            Key::SpinBack => self.targets[port].angle_rad += SPIN_STEP_RAD,
            Key::Kick => self.targets[port].angle_rad -= TAU,
            Key::Push => {
                let back_m = match self.push {
                    Some(p) => p.back_m,
                    None => self.targets[port].axial_m,
                };
                self.targets[port].axial_m = HALF_TRAVEL_M[rod];
                self.push = Some(Push {
                    port,
                    back_m,
                    until: now + PUSH_HOLD,
                });
            }
            Key::Rod(_) | Key::Quit => {}
        }
        self.apply();
        changed.then(|| self.describe())
    }

    /// Ends a push whose hold is over at `now`.
    pub fn tick(&mut self, now: Instant) {
        if self.push.is_some_and(|p| now >= p.until) {
            self.end_push();
            self.apply();
        }
    }

    fn slide(&mut self, port: usize, rod: usize, by_m: f64) {
        let h = HALF_TRAVEL_M[rod];
        let t = &mut self.targets[port].axial_m;
        *t = (*t + by_m).clamp(-h, h);
    }

    fn end_push(&mut self) {
        if let Some(p) = self.push.take() {
            self.targets[p.port].axial_m = p.back_m;
        }
    }

    fn apply(&self) {
        for (port, pose) in self.targets.iter().enumerate() {
            self.handle.set_target(port, *pose);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn keys_move_only_the_selected_rod_in_its_paddle_frame() {
        let handle = LiveHandle::default();
        let mut c = HandControls::new(handle.clone());
        let t0 = Instant::now();
        assert_eq!(c.selected(), (Team::Home, 0, 0));
        assert_eq!(
            c.key(Key::Rod(1), t0).as_deref(),
            Some("Home rod 2 (defence, port 1)")
        );
        for _ in 0..3 {
            c.key(Key::SlideAway, t0);
        }
        c.key(Key::SlideNear, t0);
        c.key(Key::SpinForward, t0);
        let t = handle.targets()[1];
        assert!((t.axial_m - 2.0 * SLIDE_STEP_M).abs() < 1e-12, "{t:?}");
        assert!((t.angle_rad + SPIN_STEP_RAD).abs() < 1e-12, "{t:?}");
        for port in (0..PADDLES).filter(|&p| p != 1) {
            assert_eq!(handle.targets()[port], RodPose::default(), "port {port}");
        }
        // Slides stop at the rod's travel.
        for _ in 0..100 {
            c.key(Key::SlideNear, t0);
        }
        assert_eq!(c.target(1).unwrap().axial_m, -HALF_TRAVEL_M[1]);
    }

    #[test]
    fn a_kick_is_one_turn_forward_for_either_team() {
        let handle = LiveHandle::default();
        let mut c = HandControls::new(handle.clone());
        let t0 = Instant::now();
        c.key(Key::Kick, t0);
        assert!((handle.targets()[0].angle_rad + TAU).abs() < 1e-12);
        assert_eq!(
            c.key(Key::SwitchTeam, t0).as_deref(),
            Some("Away rod 1 (goalkeeper, port 7)")
        );
        c.key(Key::Kick, t0);
        c.key(Key::SpinBack, t0);
        let t = handle.targets()[7];
        assert!((t.angle_rad + TAU - SPIN_STEP_RAD).abs() < 1e-12, "{t:?}");
        c.key(Key::Rod(3), t0);
        assert_eq!(c.selected(), (Team::Away, 3, 2));
    }

    #[test]
    fn a_push_holds_the_far_stop_then_returns() {
        let handle = LiveHandle::default();
        let mut c = HandControls::new(handle.clone());
        let t0 = Instant::now();
        c.key(Key::Rod(2), t0);
        c.key(Key::SlideNear, t0);
        c.key(Key::Push, t0);
        assert_eq!(handle.targets()[3].axial_m, HALF_TRAVEL_M[2]);
        // A repeated Enter (a held key) keeps it there.
        c.key(Key::Push, t0 + PUSH_HOLD / 2);
        c.tick(t0 + PUSH_HOLD);
        assert_eq!(handle.targets()[3].axial_m, HALF_TRAVEL_M[2]);
        assert_eq!(c.next_deadline(), Some(t0 + PUSH_HOLD * 3 / 2));
        c.tick(t0 + PUSH_HOLD * 2);
        assert_eq!(handle.targets()[3].axial_m, -SLIDE_STEP_M);
        assert_eq!(c.next_deadline(), None);
        // Another key ends a push at once.
        c.key(Key::Push, t0);
        c.key(Key::SpinForward, t0);
        assert_eq!(handle.targets()[3].axial_m, -SLIDE_STEP_M);
    }
}

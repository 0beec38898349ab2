//! The view model: everything the renderer draws, as plain values that the game side
//! fills in. The renderer depends on nothing of the game or the physics.
//!
//! # Contract
//!
//! A [`FrameSnapshot`] is a plain value: the physics/match thread publishes one after a
//! step (or every few steps), the render thread keeps the two newest and draws
//! [`FrameSnapshot::interpolate`] between them at its own frame time, so a slow frame
//! never blocks physics.
//!
//! Units: metres, seconds, radians. **Table frame**: origin at the centre of the
//! playing surface, `x` along the table from the [`Team::Home`] goal (`−x`) to the
//! [`Team::Away`] goal (`+x`), `y` across (Home's handles at `−y`), `z` up.
//! Orientations are unit quaternions `[x, y, z, w]` rotating man-local vectors into the
//! table frame.
//!
//! The **man frame** of a character: origin on the rod axis at the man's centre, `y`
//! along the rod, `z` "up the man" (towards the head; the table's `+z` at rod angle 0,
//! feet down), `x` completing a right-handed frame.

use glam::{DQuat, DVec3};

/// A team.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Team {
    /// Defends the goal at `−x`; its handles are at `−y`.
    Home,
    /// Defends the goal at `+x`; its handles are at `+y`.
    Away,
}

impl Team {
    /// Both teams, Home first.
    pub const BOTH: [Team; 2] = [Team::Home, Team::Away];

    /// `0` for Home, `1` for Away (index into `[home, away]` arrays).
    pub fn index(self) -> usize {
        match self {
            Team::Home => 0,
            Team::Away => 1,
        }
    }

    /// The side of the table its handles are on: `−1` (Home, `−y`) or `+1` (Away).
    pub fn handle_sign(self) -> f64 {
        match self {
            Team::Home => -1.0,
            Team::Away => 1.0,
        }
    }

    /// The `x` direction it attacks in: `+1` for Home, `−1` for Away.
    pub fn attack_dir(self) -> f64 {
        -self.handle_sign()
    }

    /// The other team.
    pub fn other(self) -> Team {
        match self {
            Team::Home => Team::Away,
            Team::Away => Team::Home,
        }
    }
}

/// The kinds of character a team can be drawn as.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum CharacterKind {
    /// Long legs, narrow body, a tall helmet: the attacker.
    TallThin,
    /// Broad shoulders, short legs, a wide helmet: the defender.
    ShortWide,
}

impl CharacterKind {
    /// Both kinds, in the order of [`TableGeometry::looks`].
    pub const BOTH: [CharacterKind; 2] = [CharacterKind::TallThin, CharacterKind::ShortWide];

    /// Index into [`TableGeometry::looks`].
    pub fn index(self) -> usize {
        match self {
            CharacterKind::TallThin => 0,
            CharacterKind::ShortWide => 1,
        }
    }
}

/// How a character kind is shaped, man frame, metres: the renderer composes the head,
/// the body and the feet from these (the physical shape of a man is the game's).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CharacterLook {
    /// Which kind this is.
    pub kind: CharacterKind,
    /// Width of the body along the rod (`y`), m.
    pub body_width_m: f64,
    /// Thickness of the body across the rod (`x`), m.
    pub body_depth_m: f64,
    /// Top of the head above the rod axis (`+z`), m.
    pub head_height_m: f64,
    /// Shoulder (where the man hangs on the rod) above the rod axis, m.
    pub shoulder_height_m: f64,
    /// Rod axis to the sole of the foot (`−z`), m.
    pub foot_reach_m: f64,
    /// Width of the foot along the rod (`y`), m.
    pub foot_width_m: f64,
}

/// The fixed geometry of a table, as drawn.
#[derive(Debug, Clone, PartialEq)]
pub struct TableGeometry {
    /// Field length along `x`, m.
    pub length_m: f64,
    /// Field width along `y`, m.
    pub width_m: f64,
    /// Wall height above the field, m.
    pub wall_height_m: f64,
    /// Height of the rod axes above the field, m.
    pub rod_height_m: f64,
    /// Goal mouth width along `y` (centred on `y = 0`), m.
    pub goal_width_m: f64,
    /// Goal mouth height, m.
    pub goal_height_m: f64,
    /// Depth of the goal box behind the goal line, m.
    pub goal_depth_m: f64,
    /// Ball radius, m.
    pub ball_radius_m: f64,
    /// The rods, in order along `x`.
    pub rods: Vec<RodGeometry>,
    /// Character kind of each team, `[home, away]`.
    pub characters: [CharacterKind; 2],
    /// The shape of each kind, indexed by [`CharacterKind::index`] (both are needed:
    /// the selection screen previews both).
    pub looks: [CharacterLook; 2],
    /// Team names as shown, `[home, away]` (upper-case letters and digits draw best).
    pub team_names: [String; 2],
}

impl TableGeometry {
    /// The look of `team`'s characters.
    pub fn look_of(&self, team: Team) -> &CharacterLook {
        &self.looks[self.characters[team.index()].index()]
    }

    /// The `x` of `team`'s goal line (the end it defends), m.
    pub fn goal_line_x(&self, team: Team) -> f64 {
        -team.attack_dir() * 0.5 * self.length_m
    }
}

/// One rod's fixed geometry.
#[derive(Debug, Clone, PartialEq)]
pub struct RodGeometry {
    /// Axis position along the table, m.
    pub x_m: f64,
    /// The team playing it.
    pub team: Team,
    /// Axial travel, m (the slide ranges over `±travel/2`).
    pub travel_m: f64,
    /// Each man's centre along the rod at slide 0, m (`y`).
    pub man_offsets_m: Vec<f64>,
}

/// A rod's pose: slide along `+y` (m) and angle about `+y` (rad, 0 = feet down).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct RodPose {
    /// Slide, m.
    pub slide_m: f64,
    /// Angle, rad (unbounded).
    pub angle_rad: f64,
}

/// One man (character) on a rod: where his man frame is.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ManSnapshot {
    /// Index of its rod in [`TableGeometry::rods`].
    pub rod: usize,
    /// Its team (its look is [`TableGeometry::look_of`] the team).
    pub team: Team,
    /// Origin of the man frame (on the rod axis), table frame, m.
    pub pivot: [f64; 3],
    /// Orientation of the man frame, unit quaternion `[x, y, z, w]` (man → table).
    pub rotation: [f64; 4],
}

/// The ball.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BallSnapshot {
    /// Centre, m.
    pub position: [f64; 3],
    /// Velocity, m/s.
    pub velocity: [f64; 3],
}

/// What kind of event spawns particles.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum EventKind {
    /// A man hit the ball.
    Kick,
    /// The ball bounced off a wall or the field.
    Bounce,
    /// A goal, scored by the given team.
    Goal(Team),
}

/// A recent event, for particle effects.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RenderEvent {
    /// When it happened, s (same clock as [`FrameSnapshot::time_s`]).
    pub time_s: f64,
    /// What happened.
    pub kind: EventKind,
    /// Where, m (table frame).
    pub position: [f64; 3],
    /// Relative speed at the contact, m/s (scales the burst); 0 if unknown.
    pub speed: f64,
}

/// Everything the renderer draws for one instant.
#[derive(Debug, Clone, PartialEq)]
pub struct FrameSnapshot {
    /// Match time, s.
    pub time_s: f64,
    /// The table.
    pub table: TableGeometry,
    /// Per rod, in the order of [`TableGeometry::rods`].
    pub rods: Vec<RodPose>,
    /// The men.
    pub men: Vec<ManSnapshot>,
    /// The ball.
    pub ball: BallSnapshot,
    /// Goals, `[home, away]`.
    pub score: [u32; 2],
    /// Events of the last few seconds (older ones may be dropped by the producer; the
    /// renderer ignores those older than [`crate::scene::PARTICLE_LIFETIME_S`]).
    pub events: Vec<RenderEvent>,
    /// Rods drawn highlighted (indices into [`TableGeometry::rods`]): the rods the
    /// players hold, or the rod being calibrated. Out-of-range indices are ignored.
    pub held_rods: Vec<usize>,
}

impl FrameSnapshot {
    /// The table at rest: rods centred, men hanging, ball resting on the centre spot.
    pub fn at_rest(table: &TableGeometry) -> Self {
        let rods = vec![RodPose::default(); table.rods.len()];
        let ball = BallSnapshot {
            position: [0.0, 0.0, table.ball_radius_m],
            velocity: [0.0; 3],
        };
        Self::posed(table, 0.0, &rods, ball, [0, 0], Vec::new())
    }

    /// A snapshot with rigid men: every man placed from its rod's pose (a man at
    /// offset `o` along the rod hangs at `y = o + slide`, turned by the rod angle about
    /// the rod axis). Missing rod poses count as rest.
    pub fn posed(
        table: &TableGeometry,
        time_s: f64,
        rods: &[RodPose],
        ball: BallSnapshot,
        score: [u32; 2],
        events: Vec<RenderEvent>,
    ) -> Self {
        let poses: Vec<RodPose> = (0..table.rods.len())
            .map(|i| rods.get(i).copied().unwrap_or_default())
            .collect();
        let mut men = Vec::new();
        for (i, rod) in table.rods.iter().enumerate() {
            let pose = poses[i];
            let rotation = DQuat::from_rotation_y(pose.angle_rad).to_array();
            for &o in &rod.man_offsets_m {
                men.push(ManSnapshot {
                    rod: i,
                    team: rod.team,
                    pivot: [rod.x_m, o + pose.slide_m, table.rod_height_m],
                    rotation,
                });
            }
        }
        FrameSnapshot {
            time_s,
            table: table.clone(),
            rods: poses,
            men,
            ball,
            score,
            events,
            held_rods: Vec::new(),
        }
    }

    /// The snapshot between `a` (at `t = 0`) and `b` (at `t = 1`): times, slides,
    /// angles, man pivots and ball position/velocity interpolated linearly, man
    /// orientations by slerp. Discrete data (table, score, events, men's identities)
    /// come from the newer snapshot `b`; if the men of `a` and `b` do not correspond,
    /// the men of `b` are used as they are. `t` is clamped to `0…1`: the renderer never
    /// extrapolates.
    pub fn interpolate(a: &FrameSnapshot, b: &FrameSnapshot, t: f64) -> FrameSnapshot {
        let t = if t.is_finite() {
            t.clamp(0.0, 1.0)
        } else {
            1.0
        };
        let rods = b
            .rods
            .iter()
            .enumerate()
            .map(|(i, pb)| match a.rods.get(i) {
                Some(pa) => RodPose {
                    slide_m: lerp(pa.slide_m, pb.slide_m, t),
                    angle_rad: lerp(pa.angle_rad, pb.angle_rad, t),
                },
                None => *pb,
            })
            .collect();
        let same_men = a.men.len() == b.men.len()
            && a.men
                .iter()
                .zip(&b.men)
                .all(|(ma, mb)| ma.rod == mb.rod && ma.team == mb.team);
        let men = if same_men {
            a.men
                .iter()
                .zip(&b.men)
                .map(|(ma, mb)| {
                    let qa = DQuat::from_array(ma.rotation).normalize();
                    let qb = DQuat::from_array(mb.rotation).normalize();
                    ManSnapshot {
                        pivot: lerp3(ma.pivot, mb.pivot, t),
                        rotation: qa.slerp(qb, t).normalize().to_array(),
                        ..*mb
                    }
                })
                .collect()
        } else {
            b.men.clone()
        };
        FrameSnapshot {
            time_s: lerp(a.time_s, b.time_s, t),
            table: b.table.clone(),
            rods,
            men,
            ball: BallSnapshot {
                position: lerp3(a.ball.position, b.ball.position, t),
                velocity: lerp3(a.ball.velocity, b.ball.velocity, t),
            },
            score: b.score,
            events: b.events.clone(),
            held_rods: b.held_rods.clone(),
        }
    }

    /// The snapshot at render time `time_s` between `a` and `b` (by their
    /// [`time_s`](Self::time_s)); clamped to the newer one past it.
    pub fn at_time(a: &FrameSnapshot, b: &FrameSnapshot, time_s: f64) -> FrameSnapshot {
        let span = b.time_s - a.time_s;
        let t = if span > 0.0 {
            (time_s - a.time_s) / span
        } else {
            1.0
        };
        Self::interpolate(a, b, t)
    }
}

/// Where the sole of a man's foot is, table frame, m: `pivot + R · (0, 0, −reach)`.
pub fn foot_sole(man: &ManSnapshot, look: &CharacterLook) -> [f64; 3] {
    let q = DQuat::from_array(man.rotation).normalize();
    (DVec3::from(man.pivot) + q * DVec3::new(0.0, 0.0, -look.foot_reach_m)).to_array()
}

/// Exact at both ends: `lerp(a, b, 0) == a`, `lerp(a, b, 1) == b`.
fn lerp(a: f64, b: f64, t: f64) -> f64 {
    a * (1.0 - t) + b * t
}

fn lerp3(a: [f64; 3], b: [f64; 3], t: f64) -> [f64; 3] {
    [
        lerp(a[0], b[0], t),
        lerp(a[1], b[1], t),
        lerp(a[2], b[2], t),
    ]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fixture::reference_table;

    fn ball(p: [f64; 3]) -> BallSnapshot {
        BallSnapshot {
            position: p,
            velocity: [1.0, 0.0, 0.0],
        }
    }

    #[test]
    fn posed_men_follow_the_rods() {
        let t = reference_table();
        let mut rods = vec![RodPose::default(); t.rods.len()];
        rods[0] = RodPose {
            slide_m: 0.05,
            angle_rad: 0.3,
        };
        let s = FrameSnapshot::posed(&t, 0.0, &rods, ball([0.0, 0.0, 0.02]), [0, 0], vec![]);
        let men: usize = t.rods.iter().map(|r| r.man_offsets_m.len()).sum();
        assert_eq!(s.men.len(), men);
        // The keeper's sole swings forward with the angle: (x + reach·sin, z − reach·cos).
        let keeper = &s.men[0];
        let look = t.look_of(keeper.team);
        let sole = foot_sole(keeper, look);
        let r = look.foot_reach_m;
        assert!((sole[0] - (t.rods[0].x_m - r * 0.3f64.sin())).abs() < 1e-12);
        assert!((sole[2] - (t.rod_height_m - r * 0.3f64.cos())).abs() < 1e-12);
        assert!((sole[1] - 0.05).abs() < 1e-12);
    }

    #[test]
    fn interpolation_lerps_positions_and_slerps_orientations() {
        let t = reference_table();
        let n = t.rods.len();
        let a = FrameSnapshot::posed(
            &t,
            1.0,
            &vec![RodPose::default(); n],
            ball([0.0, 0.0, 0.02]),
            [0, 0],
            vec![],
        );
        let b = FrameSnapshot::posed(
            &t,
            1.01,
            &vec![
                RodPose {
                    slide_m: 0.04,
                    angle_rad: std::f64::consts::FRAC_PI_2,
                };
                n
            ],
            ball([0.1, -0.2, 0.06]),
            [1, 0],
            vec![],
        );
        let m = FrameSnapshot::interpolate(&a, &b, 0.5);
        assert!((m.time_s - 1.005).abs() < 1e-12);
        for (got, want) in m.ball.position.iter().zip([0.05, -0.1, 0.04]) {
            assert!((got - want).abs() < 1e-15, "{:?}", m.ball.position);
        }
        assert!((m.rods[3].slide_m - 0.02).abs() < 1e-12);
        assert_eq!(m.score, [1, 0]);
        // Orientation halfway: 45° about +y.
        let q = DQuat::from_array(m.men[0].rotation);
        let (axis, angle) = q.to_axis_angle();
        assert!((angle - std::f64::consts::FRAC_PI_4).abs() < 1e-9);
        assert!((axis - DVec3::Y).length() < 1e-9);
        // Endpoints are exact, and t is clamped.
        assert_eq!(FrameSnapshot::interpolate(&a, &b, 0.0).ball, a.ball);
        assert_eq!(FrameSnapshot::interpolate(&a, &b, 1.0).ball, b.ball);
        assert_eq!(FrameSnapshot::interpolate(&a, &b, 7.0).ball, b.ball);
        // By time.
        let q = FrameSnapshot::at_time(&a, &b, 1.0025);
        assert!((q.ball.position[0] - 0.025).abs() < 1e-12);
    }

    #[test]
    fn mismatched_men_take_the_newer_snapshot() {
        let a = FrameSnapshot::at_rest(&reference_table());
        let mut small = reference_table();
        small.rods.truncate(2);
        let b = FrameSnapshot::at_rest(&small);
        let m = FrameSnapshot::interpolate(&a, &b, 0.5);
        assert_eq!(m.men, b.men);
        assert_eq!(m.table, b.table);
    }

    #[test]
    fn teams_and_goal_lines() {
        let t = reference_table();
        assert_eq!(t.goal_line_x(Team::Home), -0.5 * t.length_m);
        assert_eq!(t.goal_line_x(Team::Away), 0.5 * t.length_m);
        assert_eq!(Team::Home.other(), Team::Away);
        assert_eq!(t.look_of(Team::Away).kind, t.characters[1]);
    }
}

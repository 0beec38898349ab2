//! What the renderer needs per frame, independent of the physics crate.
//!
//! # Contract
//!
//! A [`FrameSnapshot`] is a plain value: the physics/match thread publishes one after a
//! step (or every few steps), the render thread keeps the two newest and draws
//! [`FrameSnapshot::interpolate`] between them at its own frame time, so a slow frame
//! never blocks physics.
//!
//! Units and frame are those of [`space_foosball::table`]: metres, seconds, radians;
//! **table frame** with the origin at the centre of the playing surface, `x` along the
//! table from the `Home` goal (`−x`) to the `Away` goal (`+x`), `y` across, `z` up.
//! Orientations are unit quaternions `[x, y, z, w]` rotating box-local vectors into the
//! table frame.

use glam::{DQuat, DVec3};
use space_foosball::side::Side;
use space_foosball::table::{CharacterType, Table};

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
    /// Character type of each team, `[home, away]`.
    pub characters: [CharacterType; 2],
}

/// One rod's fixed geometry.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RodGeometry {
    /// Axis position along the table, m.
    pub x_m: f64,
    /// The team playing it.
    pub team: Side,
    /// Axial travel, m (the slide ranges over `±travel/2`).
    pub travel_m: f64,
}

impl From<&Table> for TableGeometry {
    fn from(t: &Table) -> Self {
        TableGeometry {
            length_m: t.field.length_m,
            width_m: t.field.width_m,
            wall_height_m: t.field.wall_height_m,
            rod_height_m: t.field.rod_height_m,
            goal_width_m: t.goal.width_m,
            goal_height_m: t.goal.height_m,
            goal_depth_m: t.goal.depth_m,
            ball_radius_m: t.ball.radius_m(),
            rods: t
                .rods
                .iter()
                .map(|r| RodGeometry {
                    x_m: r.x_m,
                    team: r.team,
                    travel_m: r.travel_m,
                })
                .collect(),
            characters: [t.teams[0].character, t.teams[1].character],
        }
    }
}

/// A rod's pose: slide along `+y` (m) and angle about `+y` (rad, 0 = feet down).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct RodPose {
    /// Slide, m.
    pub slide_m: f64,
    /// Angle, rad (unbounded).
    pub angle_rad: f64,
}

/// An oriented box in the table frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BoxPose {
    /// Centre, m.
    pub center: [f64; 3],
    /// Half extents along the box's own axes, m.
    pub half_extents: [f64; 3],
    /// Orientation, unit quaternion `[x, y, z, w]` (box frame → table frame).
    pub rotation: [f64; 4],
}

/// One man (character) on a rod.
#[derive(Debug, Clone, PartialEq)]
pub struct ManSnapshot {
    /// Index of its rod in [`TableGeometry::rods`].
    pub rod: usize,
    /// Its team.
    pub team: Side,
    /// Its character type (decides the shape; the boxes carry the actual sizes).
    pub character: CharacterType,
    /// The boxes making it up, table frame.
    pub boxes: Vec<BoxPose>,
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
    Goal(Side),
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
    /// The men, each with its boxes.
    pub men: Vec<ManSnapshot>,
    /// The ball.
    pub ball: BallSnapshot,
    /// Goals, `[home, away]`.
    pub score: [u32; 2],
    /// Events of the last few seconds (older ones may be dropped by the producer; the
    /// renderer ignores those older than [`crate::scene::PARTICLE_LIFETIME_S`]).
    pub events: Vec<RenderEvent>,
}

impl FrameSnapshot {
    /// The table at rest: rods centred, men hanging, ball resting on the centre spot.
    pub fn at_rest(table: &Table) -> Self {
        let r = table.ball.radius_m();
        let rods = vec![RodPose::default(); table.rods.len()];
        Self::posed(
            table,
            0.0,
            &rods,
            BallSnapshot {
                position: [0.0, 0.0, r],
                velocity: [0.0; 3],
            },
            [0, 0],
            Vec::new(),
        )
    }

    /// A snapshot with rigid men: every man's boxes placed from its rod's pose (a man at
    /// `offset` along the rod stands at `y = offset + slide`, turned by the rod angle
    /// about the rod axis). Missing rod poses count as rest.
    pub fn posed(
        table: &Table,
        time_s: f64,
        rods: &[RodPose],
        ball: BallSnapshot,
        score: [u32; 2],
        events: Vec<RenderEvent>,
    ) -> Self {
        let geometry = TableGeometry::from(table);
        let poses: Vec<RodPose> = (0..table.rods.len())
            .map(|i| rods.get(i).copied().unwrap_or_default())
            .collect();
        let mut men = Vec::new();
        for (i, rod) in table.rods.iter().enumerate() {
            let pose = poses[i];
            let team = table.team(rod.team);
            let params = table.character_of(i);
            let rot = DQuat::from_rotation_y(pose.angle_rad);
            for y in rod.man_positions(pose.slide_m) {
                let pivot = DVec3::new(rod.x_m, y, table.field.rod_height_m);
                let boxes = params
                    .boxes()
                    .iter()
                    .map(|b| BoxPose {
                        center: (pivot + rot * DVec3::from(b.centre)).to_array(),
                        half_extents: b.half_extents,
                        rotation: rot.to_array(),
                    })
                    .collect();
                men.push(ManSnapshot {
                    rod: i,
                    team: rod.team,
                    character: team.character,
                    boxes,
                });
            }
        }
        FrameSnapshot {
            time_s,
            table: geometry,
            rods: poses,
            men,
            ball,
            score,
            events,
        }
    }

    /// The snapshot between `a` (at `t = 0`) and `b` (at `t = 1`): times, slides,
    /// angles, box centres and ball position/velocity interpolated linearly, box
    /// orientations by slerp. Discrete data (table, score, events, men's identities)
    /// come from the newer snapshot `b`; if the men of `a` and `b` do not correspond
    /// (different counts), the men of `b` are used as they are. `t` is clamped to
    /// `0…1`: the renderer never extrapolates.
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
            && a.men.iter().zip(&b.men).all(|(ma, mb)| {
                ma.rod == mb.rod && ma.team == mb.team && ma.boxes.len() == mb.boxes.len()
            });
        let men = if same_men {
            a.men
                .iter()
                .zip(&b.men)
                .map(|(ma, mb)| ManSnapshot {
                    boxes: ma
                        .boxes
                        .iter()
                        .zip(&mb.boxes)
                        .map(|(ba, bb)| interpolate_box(ba, bb, t))
                        .collect(),
                    ..mb.clone()
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

fn interpolate_box(a: &BoxPose, b: &BoxPose, t: f64) -> BoxPose {
    let qa = DQuat::from_array(a.rotation).normalize();
    let qb = DQuat::from_array(b.rotation).normalize();
    BoxPose {
        center: lerp3(a.center, b.center, t),
        half_extents: lerp3(a.half_extents, b.half_extents, t),
        rotation: qa.slerp(qb, t).normalize().to_array(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ball(p: [f64; 3]) -> BallSnapshot {
        BallSnapshot {
            position: p,
            velocity: [1.0, 0.0, 0.0],
        }
    }

    #[test]
    fn posed_men_follow_the_table_kinematics() {
        let t = Table::standard();
        let mut rods = vec![RodPose::default(); t.rods.len()];
        rods[0] = RodPose {
            slide_m: 0.05,
            angle_rad: 0.3,
        };
        let s = FrameSnapshot::posed(&t, 0.0, &rods, ball([0.0, 0.0, 0.02]), [0, 0], vec![]);
        let men: usize = t.rods.iter().map(|r| r.men).sum();
        assert_eq!(s.men.len(), men);
        // Goalkeeper's leg box: its bottom face centre is the foot sole of the table.
        let keeper = &s.men[0];
        let leg = keeper.boxes[1];
        let q = DQuat::from_array(leg.rotation);
        let sole = DVec3::from(leg.center) + q * DVec3::new(0.0, 0.0, -leg.half_extents[2]);
        let (fx, fz) = t.foot_xz(0, 0.3);
        assert!((sole.x - fx).abs() < 1e-12 && (sole.z - fz).abs() < 1e-12);
        assert!((sole.y - 0.05).abs() < 1e-12);
        assert_eq!(s.table.rods.len(), t.rods.len());
        assert_eq!(s.table.characters, [CharacterType::TallThin; 2]);
    }

    #[test]
    fn interpolation_lerps_positions_and_slerps_orientations() {
        let t = Table::standard();
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
        let q = DQuat::from_array(m.men[0].boxes[0].rotation);
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
        let a = FrameSnapshot::at_rest(&Table::standard());
        let b = FrameSnapshot::at_rest(&Table::paper());
        let m = FrameSnapshot::interpolate(&a, &b, 0.5);
        assert_eq!(m.men, b.men);
        assert_eq!(m.table, b.table);
    }
}

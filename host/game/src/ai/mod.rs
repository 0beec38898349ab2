//! The computer opponent: ball state and rod geometry → target rod poses.
//!
//! Pure functions, deterministic (same inputs, same outputs, bit for bit), for any set
//! of rods of either team — one player against the machine, or the machine against
//! itself in attract mode. Table frame throughout (see [`crate::table`]).
//!
//! Per rod of team `S` (attacking along `d = S.attack_dir()`):
//! * **Lateral**: the man that can get closest ([`Rod::nearest_man`]) follows the ball's
//!   `y`. Goalkeeper and defence rods, when the ball comes towards their goal from in
//!   front of them, follow instead the `y` where the ball will cross the rod (its path
//!   reflected off the side walls): they **block the shot line**.
//! * **Angle**: if the ball is **in the strike zone of a man** (`(x_ball − x_rod)·d`
//!   within [`STRIKE_ZONE`] of the reach, laterally on his foot, and not coming at the
//!   rod faster than [`MAX_INCOMING_TO_SHOOT_M_PER_S`]), the rod **spins to shoot** — towards the
//!   opponent's goal at the bottom of the swing, i.e. angular velocity `−d` about `+y`.
//!   If the ball is behind the rod (between it and the own goal), the men are
//!   **lifted** (feet horizontal, forward) so the own rods behind can shoot through and
//!   no foot comes down on the ball. Otherwise they **rest** feet down (the nearest
//!   multiple of 2π, so turns are never unwound — or the next one forward when the feet
//!   are swung forward over a ball in reach, see [`REST_FORWARD_RAD`]).
//! * **Reaching** for a slow ball that would otherwise be left alone
//!   ([`REACH_SLOW_BALL_M_PER_S`], [`REACH_BEHIND_SLOW_BALL_M_PER_S`]): in front of the
//!   rod within its reach but beyond the strike zone, it shoots; behind the rod, where no
//!   own rod behind could shoot it, it spins forward when the ball is close behind the
//!   axis and kicks it backward when it is further (never the goalkeeper, who spins
//!   forward there too) — so a ball does not come to rest beside a man who ignores it.
//! * The targets move at most [`AiLimits`] per step: the rods are driven bodies, so a
//!   target reached within one step would mean an impossible velocity.
//!
//! [`Rod::nearest_man`]: crate::table::Rod::nearest_man

use crate::rules::BallState;
use crate::table::{Role, Table};
use serde::{Deserialize, Serialize};
use std::f64::consts::{FRAC_PI_2, TAU};

/// A rod pose, table frame.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct RodTarget {
    /// Slide along `+y`, m.
    pub slide_m: f64,
    /// Angle about `+y`, rad (unbounded).
    pub angle_rad: f64,
}

/// How fast the computer moves its rods.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct AiLimits {
    /// Slide speed, m/s.
    pub max_slide_speed_m_per_s: f64,
    /// Spin speed, rad/s.
    pub max_spin_rad_per_s: f64,
}

impl Default for AiLimits {
    /// About a good human player: 1.5 m/s sideways, 40 rad/s spin.
    fn default() -> Self {
        Self {
            max_slide_speed_m_per_s: 1.5,
            max_spin_rad_per_s: 40.0,
        }
    }
}

/// `y` (m) where a ball at `(x, y)` moving with `(vx, vy)` crosses `x = x_line`,
/// reflected off side walls at `±y_limit`. `None` if it does not move towards the line.
pub fn crossing_y(x: f64, y: f64, vx: f64, vy: f64, x_line: f64, y_limit: f64) -> Option<f64> {
    let t = (x_line - x) / vx;
    if !(t.is_finite() && t >= 0.0) || y_limit <= 0.0 {
        return None;
    }
    let free = y + vy * t;
    // Fold onto the interval [−L, L] by reflection (period 4L).
    let period = 4.0 * y_limit;
    let shifted = (free + y_limit).rem_euclid(period);
    Some(if shifted <= 2.0 * y_limit {
        shifted - y_limit
    } else {
        3.0 * y_limit - shifted
    })
}

/// Where along `x` a ball must be for a rod to shoot, as fractions of its reach
/// ([`Table::reach_x_m`]) ahead of the rod. Behind the rod axis the foot, swinging
/// forward, comes down on top of the ball and pins it against the cloth; beyond about
/// half the reach it meets the ball well past the bottom of its swing and lifts it (the
/// contact normal tilts up by `asin(ahead / reach)`). So the computer shoots only
/// between the two, and otherwise waits for the ball or leaves it to the next rod.
pub const STRIKE_ZONE: [f64; 2] = [0.05, 0.85];

/// A ball coming at the rod faster than this (m/s, towards the rod's own goal) is
/// blocked with the feet down, not shot: shooting into a fast ball only pumps energy
/// into it.
pub const MAX_INCOMING_TO_SHOOT_M_PER_S: f64 = 1.0;

/// Feet swung forward by more than this (rad) with the ball in front and in reach come
/// to rest by carrying on over the top, not by swinging back down onto the ball.
pub const REST_FORWARD_RAD: f64 = 0.2;

/// A ball slower than this (m/s, along the field) in front of a rod, within its reach
/// but beyond the strike zone, is **reached for**: the rod shoots it (it may lift a
/// little), so that a slow ball does not roll out of the rod's reach untouched, into a
/// corner where nobody reaches. Well above the rules' "slow" (0.05 m/s): the rod goes
/// for it before it stops.
pub const REACH_SLOW_BALL_M_PER_S: f64 = 0.6;

/// A ball slower than this (m/s) behind a rod, within its reach, where no own rod
/// behind could shoot it, is reached for as well ([`REACH_BACK_FORWARD_SHARE`]). Lower
/// than in front: spinning at a faster ball under or behind the rod tends to trap it
/// under the foot.
pub const REACH_BEHIND_SLOW_BALL_M_PER_S: f64 = 0.3;

/// A slow ball behind the rod axis by less than this share of the reach is reached for
/// by spinning **forward**: the foot comes round over the top and meets the ball from
/// behind low in its swing, sending it forward. Further behind, the foot would come
/// down on top of it, so the rod kicks it **backward** instead (towards its own rods),
/// except the goalkeeper, whose back kick would be an own goal.
pub const REACH_BACK_FORWARD_SHARE: f64 = 0.5;

/// How a rod plays a slow ball it reaches for.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Reach {
    /// Not reaching for the ball.
    No,
    /// Spin forward (towards the opponent at the bottom of the swing).
    Forward,
    /// Spin backward.
    Backward,
}

/// Whether a rod of `rod`'s team behind it (towards its own goal) has the ball at
/// `(bx, by)` in its strike zone and on a foot.
fn own_rod_behind_can_shoot(table: &Table, rod: usize, bx: f64, by: f64) -> bool {
    let r = &table.rods[rod];
    let dir = r.team.attack_dir();
    table.rods.iter().enumerate().any(|(i, other)| {
        if i == rod || other.team != r.team || (other.x_m - r.x_m) * dir >= 0.0 {
            return false;
        }
        let reach = table.reach_x_m(i);
        let ahead = (bx - other.x_m) * dir;
        (STRIKE_ZONE[0] * reach..=reach).contains(&ahead) && table.rod_covers_y(i, by)
    })
}

/// How rod `rod` reaches for a slow ball `ahead` (m, along its attack direction) of it,
/// at `(bx, by)`.
fn reach_for(table: &Table, rod: usize, ball: &BallState, ahead: f64) -> Reach {
    let [bx, by, _] = ball.position;
    let [vx, vy, _] = ball.velocity;
    let reach = table.reach_x_m(rod);
    let speed = virtual_physics::transcendental::hypot(vx, vy);
    if ahead.abs() > reach || !table.rod_covers_y(rod, by) {
        return Reach::No;
    }
    if ahead >= STRIKE_ZONE[0] * reach {
        // In front, in reach: shoot (beyond the strike zone the ball may lift a little).
        return if speed < REACH_SLOW_BALL_M_PER_S {
            Reach::Forward
        } else {
            Reach::No
        };
    }
    if speed >= REACH_BEHIND_SLOW_BALL_M_PER_S || own_rod_behind_can_shoot(table, rod, bx, by) {
        return Reach::No;
    }
    let keeper = table.rods[rod].role == Role::Goalkeeper;
    if keeper || ahead >= -REACH_BACK_FORWARD_SHARE * reach {
        Reach::Forward
    } else {
        Reach::Backward
    }
}

/// The pose a rod rests in: same slide, feet down at the nearest whole turn.
pub fn resting(current: RodTarget) -> RodTarget {
    RodTarget {
        slide_m: current.slide_m,
        angle_rad: nearest_angle(current.angle_rad, 0.0),
    }
}

/// The angle nearest `current` at which the rod's men point `phase` (rad, `0` = feet
/// down): `phase + 2πk`.
fn nearest_angle(current: f64, phase: f64) -> f64 {
    phase + ((current - phase) / TAU).round() * TAU
}

/// The pose rod `rod` wants, ignoring speed limits.
pub fn desired_pose(table: &Table, rod: usize, ball: &BallState, current: RodTarget) -> RodTarget {
    desired_pose_aimed(table, rod, ball, current, 0.0)
}

/// [`desired_pose`] with an aim: while shooting, the shooter stands `aim_m` (m, along
/// `+y`) beside the ball instead of square behind it, so the ball comes off the edge of
/// his foot at an angle (towards `−y` for a positive aim). A few centimetres at most:
/// beyond `foot half width + ball radius` the foot misses.
pub fn desired_pose_aimed(
    table: &Table,
    rod: usize,
    ball: &BallState,
    current: RodTarget,
    aim_m: f64,
) -> RodTarget {
    let r = &table.rods[rod];
    let dir = r.team.attack_dir();
    let [bx, by, _] = ball.position;
    let [vx, vy, _] = ball.velocity;
    let ahead = (bx - r.x_m) * dir;
    let reach = table.reach_x_m(rod);
    let character = table.character_of(rod);
    let ball_r = table.ball.radius_m();

    let coming_at_us = vx * dir < 0.0 && ahead > 0.0;
    let guards = matches!(r.role, Role::Goalkeeper | Role::Defence);
    let y_limit = 0.5 * table.field.width_m - ball_r;
    let y_target = if guards && coming_at_us {
        crossing_y(bx, by, vx, vy, r.x_m, y_limit).unwrap_or(by)
    } else {
        by
    };
    let choice = r.nearest_man(y_target, current.slide_m);

    // Shooting uses the man in front of the ball now (not the predicted crossing).
    let shooter = r.nearest_man(by, current.slide_m);
    let on_foot = shooter.miss_m <= 0.5 * character.foot_width_m + ball_r;
    let in_strike_zone = (STRIKE_ZONE[0] * reach..=STRIKE_ZONE[1] * reach).contains(&ahead)
        && -vx * dir < MAX_INCOMING_TO_SHOOT_M_PER_S;
    let reaching = if in_strike_zone {
        Reach::No
    } else {
        reach_for(table, rod, ball, ahead)
    };
    let in_reach = in_strike_zone || reaching != Reach::No;
    let rest = nearest_angle(current.angle_rad, 0.0);
    // How far the feet are swung forward (towards the opponent) from hanging down, rad.
    let forward = -dir * (current.angle_rad - rest);
    let angle_rad = if in_reach && on_foot && reaching == Reach::Backward {
        // Kick it back: a quarter turn behind where the rod is.
        current.angle_rad + dir * FRAC_PI_2
    } else if in_reach && on_foot {
        // Keep spinning forward: a quarter turn ahead of where the rod is.
        current.angle_rad - dir * FRAC_PI_2
    } else if ahead < 0.0 {
        // Behind the rod: feet up, out of the way of the own rods' shots (and never
        // brought down on top of the ball).
        nearest_angle(current.angle_rad, -dir * FRAC_PI_2)
    } else if ahead <= reach && forward > REST_FORWARD_RAD {
        // In front, in reach, feet swung forward: swinging back down would press the
        // ball into the cloth; carry on over the top to the next turn instead.
        rest - dir * TAU
    } else {
        rest
    };
    let slide_m = if reaching != Reach::No && !on_foot {
        // Reaching for a slow ball: the man nearest it goes to it.
        shooter.slide_m
    } else if in_reach && on_foot {
        // Keep the shooter lined up with the ball (and the aim) while kicking.
        let aim = if aim_m.is_finite() { aim_m } else { 0.0 };
        r.nearest_man(by + aim, current.slide_m).slide_m
    } else {
        choice.slide_m
    };
    RodTarget { slide_m, angle_rad }
}

/// `current` moved towards `desired` within `limits` over `dt_s` seconds, the slide
/// kept within the rod's travel.
pub fn step_towards(
    current: RodTarget,
    desired: RodTarget,
    limits: &AiLimits,
    half_travel_m: f64,
    dt_s: f64,
) -> RodTarget {
    let ds = limits.max_slide_speed_m_per_s * dt_s;
    let da = limits.max_spin_rad_per_s * dt_s;
    RodTarget {
        slide_m: (current.slide_m + (desired.slide_m - current.slide_m).clamp(-ds, ds))
            .clamp(-half_travel_m, half_travel_m),
        angle_rad: current.angle_rad + (desired.angle_rad - current.angle_rad).clamp(-da, da),
    }
}

/// [`targets`] with an aim per rod (see [`desired_pose_aimed`]; missing aims are 0).
pub fn targets_aimed(
    table: &Table,
    rods: &[usize],
    ball: &BallState,
    current: &[RodTarget],
    aims_m: &[f64],
    limits: &AiLimits,
    dt_s: f64,
) -> Vec<RodTarget> {
    rods.iter()
        .zip(current)
        .enumerate()
        .map(|(k, (&rod, &now))| {
            let aim = aims_m.get(k).copied().unwrap_or(0.0);
            let want = desired_pose_aimed(table, rod, ball, now, aim);
            step_towards(now, want, limits, table.rods[rod].half_travel_m(), dt_s)
        })
        .collect()
}

/// One step of the computer for `rods` (indices into the table), whose current poses
/// are `current` (same order): the next target of each, `dt_s` seconds later.
pub fn targets(
    table: &Table,
    rods: &[usize],
    ball: &BallState,
    current: &[RodTarget],
    limits: &AiLimits,
    dt_s: f64,
) -> Vec<RodTarget> {
    rods.iter()
        .zip(current)
        .map(|(&rod, &now)| {
            let want = desired_pose(table, rod, ball, now);
            step_towards(now, want, limits, table.rods[rod].half_travel_m(), dt_s)
        })
        .collect()
}

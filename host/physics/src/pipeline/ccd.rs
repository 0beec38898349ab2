//! Continuous collision for small fast spheres: the speculative contacts of a ball are
//! checked against its swept path over the step, so that only the contacts it really
//! makes reach the solver.
//!
//! With the continuous-collision effect every moving body's box and the narrow phase's
//! margin grow by the body's sweep, so a ball gets a speculative contact with every shape
//! it could reach within the step — including a post it passes 1 mm beside, whose nearest
//! point the solver would then treat as a wall across the ball's path. For each *fast*
//! sphere (a dynamic, awake sphere moving more than [`FAST_FRACTION`] of its radius per
//! step) this pass follows the ball's path over the step, impact by impact in the order
//! they happen:
//!
//! 1. from the ball's position and velocity at the start of the leg, the time of impact
//!    ([`crate::geometry::sphere_cast`]) against every shape (part) it has a manifold with,
//!    each moving with its own velocity (the velocity of the part's centre);
//! 2. at the earliest impact the ball's velocity relative to the target is reflected with
//!    the pair's restitution (above the restitution threshold; none below it, and no
//!    friction), and the next leg runs for the rest of the step, up to [`MAX_IMPACTS`]
//!    legs (past that every contact of the ball is kept).
//!
//! A ball whose path meets two or more shapes within the step, every one of them fixed,
//! ends the step where its path ends ([`BallPath`], applied after the solve): the solve
//! takes a ball to its first impact and bounces it there, and a ball that should bounce
//! again within the same step would lose the rest of the step at the wall. So does a ball
//! whose one impact is on a fixed shape without friction (the path is then exact); an
//! impact with friction is left to the solve, which spins the ball. Along the path
//! each impact reflects the normal velocity with the restitution (no friction) against a
//! fixed shape, so the path's speed never exceeds its start's: the ball cannot gain energy.
//!
//! A manifold that no leg touches is dropped (no false stop). Every target that the ball's
//! straight path over the step touches after the start (the first impact, and any other on
//! that line — two boxes sharing a post's edge are hit at once) gets its manifold rewritten
//! as the exact contact plane of that impact (normal and point at the time of impact, the
//! separation at the start of the step along that normal), so the solver lets the ball
//! close exactly the distance to it. Manifolds touched at the start, or only by a later
//! leg, stay as the narrow phase made them.
//!
//! The sweep is straight over each leg; what the step adds to it is bounded and taken as a
//! tolerance on the ball's radius: `|a| dt²` for the ball's acceleration `a` (gravity and the
//! applied force; the substepped integration moves the ball by at most `½ |a| dt² (1 + 1/n)`
//! off the line), `½ |v| |ω| h dt` for a spinning ball (each substep `h` moves its centre
//! along the screw of `T ← T·Exp(hV)`, off the chord by `½ |v| |ω| h²`), the turning of the target part (`|ω| ρ dt` for the part's reach `ρ`
//! about its centre, plus the centre's arc off its tangent, `|ω|² |o| dt²`), and
//! [`SWEEP_TOLERANCE_M`] for round-off.

use crate::dynamics::{BodyKind, BodySet};
use crate::geometry::{sphere_cast, Impact, Manifold, Material, Shape, M3, V3};

/// A sphere is fast when it moves more than this fraction of its radius per step (–): a
/// slower sphere's nearest-point contact stays within `δ²/2r` of the true contact over a
/// step of length `δ` (under 1 µm for a 35 mm ball at this fraction).
pub(crate) const FAST_FRACTION: f64 = 0.01;

/// Most impacts followed along one ball's path within a step.
pub(crate) const MAX_IMPACTS: usize = 32;

/// Round-off allowance on the swept radius (m).
pub(crate) const SWEEP_TOLERANCE_M: f64 = 1e-9;

/// What the pass reads of the step besides the bodies.
#[derive(Clone, Copy, Debug)]
pub(crate) struct SweepSettings {
    /// Step (s).
    pub(crate) dt: f64,
    /// Substep (s).
    pub(crate) substep: f64,
    /// Gravity (m/s², world), zero without the gravity effect.
    pub(crate) gravity: V3,
    /// Restitution threshold (m/s), or `None` without the restitution effect.
    pub(crate) restitution_threshold: Option<f64>,
}

/// Where a fast ball's path, followed through two or more impacts on fixed shapes, ends
/// the step.
#[derive(Clone, Copy, Debug)]
pub(crate) struct BallPath {
    /// The ball (body index).
    pub(crate) ball: usize,
    /// Centre at the end of the step (m, world).
    pub(crate) pos: V3,
    /// Velocity at the end of the step (m/s, world).
    pub(crate) vel: V3,
}

/// One shape (a part of a compound) a ball has a manifold with, posed at the start of the
/// step.
struct Target {
    manifold: usize,
    body: usize,
    shape: Shape,
    rot: M3,
    pos: V3,
    /// Velocity of the part's centre (m/s, world).
    vel: V3,
    /// Extra swept radius for the target's turning and the ball's acceleration (m).
    skin: f64,
    material: Material,
    touched: bool,
    /// Where the ball's straight path over the step first touches this target, when it
    /// does after the start (rewrites its manifold).
    straight: Option<Impact>,
}

/// Drops the manifolds of fast spheres that their swept path does not touch and rewrites
/// those their straight path touches as the contact planes of the impacts; writes to `paths`
/// the balls that end the step along their path. Returns the numbers of manifolds and
/// contact points dropped.
pub(crate) fn filter_manifolds(
    manifolds: &mut Vec<Manifold>,
    bodies: &BodySet,
    settings: &SweepSettings,
    paths: &mut Vec<BallPath>,
) -> (usize, usize) {
    paths.clear();
    let dt = settings.dt;
    let fast = |i: usize| {
        bodies.kind[i] == BodyKind::Dynamic
            && bodies.awake[i]
            && matches!(bodies.shape[i], Shape::Sphere { radius }
                if bodies.vel[i].norm() * dt > FAST_FRACTION * radius)
    };
    let mut balls: Vec<usize> = (0..bodies.len()).filter(|&i| fast(i)).collect();
    if balls.is_empty() {
        return (0, 0);
    }
    balls.sort_unstable();
    let is_ball = |i: usize| balls.binary_search(&i).is_ok();
    let mut keep = vec![true; manifolds.len()];
    let mut seen = vec![false; manifolds.len()];
    let mut targets = Vec::new();
    let mut impacts = Vec::new();
    for &ball in &balls {
        targets.clear();
        for (mi, m) in manifolds.iter().enumerate() {
            let (a, b) = (m.a as usize, m.b as usize);
            if a != ball && b != ball {
                continue;
            }
            let (other, part) = if a == ball {
                (b, m.part_b)
            } else {
                (a, m.part_a)
            };
            targets.push(target(bodies, mi, other, part as usize, ball, settings));
        }
        let end = follow(bodies, ball, &mut targets, settings, &mut impacts);
        let only_fixed = targets
            .iter()
            .all(|t| !t.touched || bodies.kind[t.body] == BodyKind::Fixed);
        let ball_material = bodies.material[ball];
        let frictionless = impacts
            .iter()
            .all(|&(k, _)| ball_material.pair_friction(&targets[k].material) == 0.0);
        let path_is_better = impacts.len() >= 2 || (impacts.len() == 1 && frictionless);
        if let (Some((pos, vel)), true, true) = (end, path_is_better, only_fixed) {
            paths.push(BallPath { ball, pos, vel });
        }
        for t in &targets {
            let other_fast = is_ball(t.body);
            if !seen[t.manifold] {
                seen[t.manifold] = true;
                keep[t.manifold] = t.touched;
            } else {
                keep[t.manifold] |= t.touched;
            }
            if let (Some(hit), false) = (t.straight, other_fast) {
                rewrite(&mut manifolds[t.manifold], bodies, ball, t, &hit, settings);
            }
        }
    }
    let (mut gone, mut points) = (0, 0);
    let mut k = 0;
    manifolds.retain(|m| {
        let kept = keep[k];
        k += 1;
        if !kept {
            gone += 1;
            points += m.len;
        }
        kept
    });
    (gone, points)
}

/// The part `part` of body `other` as a target of `ball`, posed at the start of the step.
fn target(
    bodies: &BodySet,
    manifold: usize,
    other: usize,
    part: usize,
    ball: usize,
    s: &SweepSettings,
) -> Target {
    let (r, p, w) = (&bodies.rot[other], &bodies.pos[other], &bodies.omega[other]);
    let (shape, rot, pos, material, offset) = match &bodies.shape[other] {
        Shape::Compound(c) => {
            let k = &c.parts()[part.min(c.parts().len() - 1)];
            let o = r * k.pos;
            (k.shape.clone(), r * k.rot, p + o, k.material, o)
        }
        s => (s.clone(), *r, *p, bodies.material[other], V3::zeros()),
    };
    let wn = w.norm();
    let dt = s.dt;
    let accel = s.gravity + bodies.force[ball] * bodies.inv_mass[ball];
    let screw = bodies.vel[ball].norm() * bodies.omega[ball].norm() * s.substep * dt * 0.5;
    let skin = SWEEP_TOLERANCE_M
        + screw
        + accel.norm() * dt * dt
        + wn * shape.bounding_radius() * dt
        + wn * wn * offset.norm() * dt * dt;
    Target {
        manifold,
        body: other,
        vel: bodies.vel[other] + w.cross(&offset),
        shape,
        rot,
        pos,
        skin,
        material,
        touched: false,
        straight: None,
    }
}

/// Follows `ball` over the step, impact by impact, marking the targets it touches; writes
/// the impacts in the order they happen to `impacts` (target index, time into the step in
/// s). Returns where the path ends the step, its centre and velocity (the step's
/// acceleration added as a straight leg would), or `None` past [`MAX_IMPACTS`].
fn follow(
    bodies: &BodySet,
    ball: usize,
    targets: &mut [Target],
    s: &SweepSettings,
    impacts: &mut Vec<(usize, f64)>,
) -> Option<(V3, V3)> {
    impacts.clear();
    let Shape::Sphere { radius } = bodies.shape[ball] else {
        return None;
    };
    let accel = s.gravity + bodies.force[ball] * bodies.inv_mass[ball];
    let end = |c: V3, v: V3, left: f64| {
        Some((c + v * left + accel * (0.5 * s.dt * s.dt), v + accel * s.dt))
    };
    let (mut c, mut v) = (bodies.pos[ball], bodies.vel[ball]);
    let (mut elapsed, mut left) = (0.0, s.dt);
    let mut last: Option<usize> = None;
    for leg in 0..=MAX_IMPACTS {
        if leg == MAX_IMPACTS {
            // Too many impacts to follow: keep every contact of the ball.
            targets.iter_mut().for_each(|t| t.touched = true);
            return None;
        }
        let mut best: Option<(usize, Impact)> = None;
        for (k, t) in targets.iter_mut().enumerate() {
            if last == Some(k) {
                // Leaving a convex part: the distance to it only grows along the leg.
                continue;
            }
            let pos = t.pos + t.vel * elapsed;
            let d = v * left;
            let Some(hit) = sphere_cast(
                &c,
                &d,
                radius + t.skin,
                &t.shape,
                &t.rot,
                &pos,
                &(t.vel * left),
            ) else {
                continue;
            };
            t.touched = true;
            if leg == 0 && hit.t > 0.0 {
                t.straight = Some(hit);
            }
            let approaching = (v - t.vel).dot(&hit.normal) < 0.0;
            if hit.t == 0.0 && !approaching {
                continue; // touching and not closing: a resting contact, no impact
            }
            if best.is_none_or(|(_, b)| hit.t < b.t) {
                best = Some((k, hit));
            }
        }
        let Some((k, hit)) = best else {
            return end(c, v, left);
        };
        let t = &targets[k];
        // Reflect the relative velocity at the impact.
        let rel = v - t.vel;
        let vn = rel.dot(&hit.normal);
        let e = match s.restitution_threshold {
            Some(th) if -vn > th => bodies.material[ball].pair_restitution(&t.material),
            _ => 0.0,
        };
        impacts.push((k, elapsed + left * hit.t));
        c += v * (left * hit.t);
        v -= hit.normal * ((1.0 + e) * vn);
        elapsed += left * hit.t;
        left -= left * hit.t;
        last = Some(k);
        if left <= 0.0 {
            return end(c, v, 0.0);
        }
    }
    None
}

/// Rewrites `m` as the contact plane of the impact `hit` of `ball`'s straight path on `t`:
/// the normal at the impact, the plane through the impact point moved back with the target
/// to the start of the step, and the ball's separation from that plane there.
fn rewrite(
    m: &mut Manifold,
    bodies: &BodySet,
    ball: usize,
    t: &Target,
    hit: &Impact,
    s: &SweepSettings,
) {
    let Shape::Sphere { radius } = bodies.shape[ball] else {
        return;
    };
    let n = hit.normal; // target → ball
    let q0 = hit.point - t.vel * (s.dt * hit.t);
    let sep = n.dot(&(bodies.pos[ball] - q0)) - radius;
    let normal = if m.b as usize == ball { n } else { -n };
    let same = m.normal.dot(&normal) > 0.95;
    let old = m.points[0];
    m.normal = normal;
    m.len = 0;
    // The point on the line through the ball's centre along the normal, midway across the
    // gap (as the narrow phase places a sphere's points): a normal impulse through the
    // centre does not spin the ball.
    m.push(bodies.pos[ball] - n * (radius + 0.5 * sep), sep);
    let (a, pa) = (m.a as usize, &mut m.points[0]);
    pa.local_a = bodies.rot[a].tr_mul(&(pa.point - bodies.pos[a]));
    if same {
        pa.normal_impulse = old.normal_impulse;
        pa.tangent_impulse = old.tangent_impulse;
    } else {
        m.friction_impulse = [0.0; 2];
        m.twist_impulse = 0.0;
        m.rolling_impulse = V3::zeros();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const R: f64 = 0.0175;

    /// A ball between two fixed walls `gap` (m) from each side, moving along x at `speed`.
    fn between_walls(gap: f64, speed: f64, restitution: f64) -> BodySet {
        let mut b = BodySet::default();
        let bouncy = Material {
            friction: 0.0,
            restitution,
            rolling_resistance: 0.0,
        };
        let wall = |b: &mut BodySet, x: f64| {
            b.push(
                "wall".into(),
                BodyKind::Fixed,
                Shape::Cuboid {
                    half: V3::new(0.01, 0.1, 0.1),
                },
                bouncy,
                0.0,
                V3::new(x, 0.0, 0.0),
                M3::identity(),
                V3::zeros(),
                V3::zeros(),
            );
        };
        wall(&mut b, -(R + gap + 0.01));
        wall(&mut b, R + gap + 0.01);
        b.push(
            "ball".into(),
            BodyKind::Dynamic,
            Shape::Sphere { radius: R },
            bouncy,
            0.027,
            V3::zeros(),
            M3::identity(),
            V3::new(speed, 0.0, 0.0),
            V3::zeros(),
        );
        b.awake[2] = true;
        b
    }

    #[test]
    fn several_impacts_within_one_step_come_in_order() {
        // 2 mm each side, 15 m/s, 1 ms: the right wall after 2 mm, the left after 4 mm more,
        // the right again after 4 mm more (elastic), all within the 15 mm of the step.
        let (gap, v, dt) = (0.002, 15.0, 1e-3);
        let bodies = between_walls(gap, v, 1.0);
        let s = SweepSettings {
            dt,
            substep: dt / 12.0,
            gravity: V3::zeros(),
            restitution_threshold: Some(0.5),
        };
        let mut targets: Vec<Target> = (0..2).map(|w| target(&bodies, w, w, 0, 2, &s)).collect();
        let mut impacts = Vec::new();
        follow(&bodies, 2, &mut targets, &s, &mut impacts);
        let expect = [
            (1, gap / v),
            (0, 3.0 * gap / v),
            (1, 5.0 * gap / v),
            (0, 7.0 * gap / v),
        ];
        assert!(impacts.len() >= expect.len(), "{impacts:?}");
        for (n, ((k, t), (ek, et))) in impacts.iter().zip(expect).enumerate() {
            assert_eq!(*k, ek, "{impacts:?}");
            // Each impact comes SWEEP_TOLERANCE_M early (the skin on the radius).
            let early = (n + 1) as f64 * 2.0 * SWEEP_TOLERANCE_M / v;
            assert!((t - et).abs() <= early + 1e-15, "{t} vs {et}");
        }
        assert!(targets.iter().all(|t| t.touched));
        // Only the wall ahead of the ball rewrites its manifold: the other one is behind the
        // straight path.
        assert!(targets[1].straight.is_some() && targets[0].straight.is_none());
    }

    #[test]
    fn a_dead_ball_slides_along_the_wall_it_hit() {
        // Restitution 0: after the first impact the ball stops against the right wall and
        // never reaches the left one.
        let bodies = between_walls(0.002, 15.0, 0.0);
        let s = SweepSettings {
            dt: 1e-3,
            substep: 1e-3 / 12.0,
            gravity: V3::zeros(),
            restitution_threshold: Some(0.5),
        };
        let mut targets: Vec<Target> = (0..2).map(|w| target(&bodies, w, w, 0, 2, &s)).collect();
        let mut impacts = Vec::new();
        follow(&bodies, 2, &mut targets, &s, &mut impacts);
        assert_eq!(impacts.len(), 1);
        assert!(targets[1].touched && !targets[0].touched);
    }
}

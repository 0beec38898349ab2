//! The sink a resting contact's load leaves, held back.
//!
//! A soft contact is a spring (`ContactStiffness`): under a steady load `F` it settles at the
//! overlap `F / (m ω²)`, and a stack sinks by the sum of its contacts' overlaps down to the
//! ground. A tower of 20 unit cubes sinks 5 mm at the default 12 substeps of 1/60 s and 29 mm
//! at 4, where the contacts are three times softer.
//!
//! Each step, each loaded contact between free bodies adds a share of its mean overlap beyond
//! the slop to the overlap it is solved as if it had beyond its own
//! ([`Manifold::held_overlap`]). That is an integral of the sink: a resting contact comes
//! to push as its load asks with its bodies at the slop, whatever its stiffness, and the
//! tower's sink falls to the slop of its 20 contacts (2 mm). The share is the step over
//! [`HOLD_TIME`], so the hold takes up a steady sink in about that time at any step.
//!
//! Only contacts that bear weight hold: a normal within 45° of gravity's vertical, as a body
//! stands on another. Between boxes pressed together from the sides the hold would only
//! move the pressed bodies (measured: a box wedged between two boxes pushed at it with
//! 1000 N each walked 4.4 cm in 20 s, against less than 2 cm without a hold).
//!
//! The hold is the same at each point of a manifold: it lifts a sunken contact without
//! tilting it. Held point by point, the integral also levelled a column's tilted contact,
//! but its lag let the columns of `towers-1120` rock until they fell (measured at 4
//! substeps: 0.09–0.7 m of drift in 200 steps at shares of 0.05–0.1 per step, against
//! 5 mm held per manifold). A contact that carried no load in the last step holds nothing:
//! a body lifted off, or only touching, is never pushed by a load it no longer has.

use crate::dynamics::solver::contact_constraint::LINEAR_SLOP;
use crate::dynamics::solver::{ContactConstraint, ContactStiffness};
use crate::geometry::{Manifold, V3};

/// A contact whose normal is within 45° of the vertical bears the weight of the body on top
/// (–).
const SUPPORT_COSINE: f64 = std::f64::consts::FRAC_1_SQRT_2;

/// Whether `m` bears weight under gravity along `-up` (`up` a unit vector): only those
/// contacts hold.
pub(crate) fn bears_weight(m: &Manifold, up: &V3) -> bool {
    m.normal.dot(up).abs() >= SUPPORT_COSINE
}

/// The time (s) over which the hold takes up a steady sink: a step of `dt` adds `dt /
/// HOLD_TIME` of the overlap beyond the slop (all of it where `dt ≥ HOLD_TIME`).
pub(crate) const HOLD_TIME: f64 = 0.25;

/// The hold's sums per body on top of weight-bearing contacts, kept between steps.
#[derive(Clone, Debug, Default)]
pub(crate) struct SinkHold {
    /// Per body: the sum over its loaded supports of their new holds (m), and how many.
    sums: Vec<(f64, u32)>,
    /// Per manifold, from the first pass: the body it holds up, [`UNTOUCHED`] or
    /// [`LET_GO`].
    picks: Vec<u32>,
}

/// A manifold the update leaves as it is.
const UNTOUCHED: u32 = u32::MAX;
/// A manifold that holds nothing.
const LET_GO: u32 = u32::MAX - 1;

/// The body a weight-bearing contact holds up: the one its normal points to along `up`.
fn upper(m: &Manifold, up: &V3) -> usize {
    if m.normal.dot(up) > 0.0 {
        m.b as usize
    } else {
        m.a as usize
    }
}

/// Whether `m` carried a load in the last step and bears weight under gravity along `-up`.
fn holds(m: &Manifold, up: &V3) -> bool {
    bears_weight(m, up) && m.points().iter().any(|p| p.normal_impulse > 0.0)
}

impl SinkHold {
    /// Updates the overlap each manifold of `manifolds` that `held` picks (those between free
    /// bodies the step solves) is held at, from its points' separations at the start of the
    /// step: the body on top takes, on the mean over its supports, the share `dt / HOLD_TIME`
    /// of their mean overlap beyond [`LINEAR_SLOP`] on top of their hold, within
    /// `[0, reach]` (`reach`: the speculative distance, the farthest a contact reaches), and
    /// each of its supports holds that. A contact that carried no load in the last step or
    /// bears no weight under gravity along `-up` ([`bears_weight`]) holds nothing. The same
    /// hold under every support of a body lifts it without tilting it.
    pub(crate) fn update(
        &mut self,
        manifolds: &mut [Manifold],
        held: impl Fn(&Manifold) -> bool,
        (bodies, dt, reach): (usize, f64, f64),
        up: &V3,
    ) {
        let share = (dt / HOLD_TIME).min(1.0);
        self.each_body(
            manifolds,
            |m| held(m).then(|| holds(m, up)),
            bodies,
            |m| {
                let held = m.held_overlap;
                held + share * (mean_overlap(m) - LINEAR_SLOP)
            },
            reach,
            up,
        );
    }

    /// When the contacts' stiffness changes (a world at rest taking fewer substeps, or its
    /// step's own again), each loaded contact that bears weight takes up at once the change
    /// of overlap its load asks, so that it stays at the slop: at rest its spring is
    /// compressed by `F / (m ω²)` on the mean over its points
    /// ([`ContactConstraint::mean_resting_overlap`]), so the change moves its mean overlap
    /// from `o` (now, [`mean_overlap`]) to `o + F / m (1 / ω_new² − 1 / ω_old²)`, and the hold
    /// grows by that less the slop; the body on top takes the mean over its supports, within
    /// `[0, reach]`. A resting stack stays where it stood instead of sinking into its softer
    /// contacts and climbing back over [`HOLD_TIME`]. `changes(ci, m)` gives the old and new
    /// stiffness of constraint `ci` (prepared from manifold `m`) where its substep changes
    /// (`None`: it does not); `up` is against gravity.
    pub(crate) fn restiffen(
        &mut self,
        constraints: &mut [ContactConstraint],
        manifolds: &mut [Manifold],
        changes: impl Fn(usize, &Manifold) -> Option<(ContactStiffness, ContactStiffness)>,
        (bodies, reach): (usize, f64),
        up: &V3,
    ) {
        let change = |ci: usize, c: &ContactConstraint, m: &Manifold| {
            let (old, new) = changes(ci, m)?;
            let omega = |k: &ContactStiffness| {
                2.0 * std::f64::consts::PI * k.hertz_for(c.against_static, c.mass_ratio())
            };
            Some(c.mean_resting_overlap(omega(&new)) - c.mean_resting_overlap(omega(&old)))
        };
        let (sums, mut seen) = (&mut self.sums, 0);
        sums.clear();
        sums.resize(bodies, (0.0, 0));
        for (ci, c) in constraints.iter().enumerate() {
            let m = &manifolds[c.manifold];
            if let (Some(d), true) = (change(ci, c, m), holds(m, up)) {
                let s = &mut sums[upper(m, up)];
                s.0 += m.held_overlap + mean_overlap(m) + d - LINEAR_SLOP;
                s.1 += 1;
                seen += 1;
            }
        }
        if seen == 0 {
            return;
        }
        for (ci, c) in constraints.iter_mut().enumerate() {
            let m = &mut manifolds[c.manifold];
            if change(ci, c, m).is_none() || !holds(m, up) {
                continue;
            }
            let (sum, count) = sums[upper(m, up)];
            let now = (sum / count as f64).clamp(0.0, reach.max(0.0));
            let held = m.held_overlap;
            if now.is_finite() && now != held {
                c.deepen(now - held);
                m.held_overlap = now;
            }
        }
    }

    /// Sets each manifold's hold to the mean over the supports of the body on top of
    /// `wanted(m)`, for the manifolds where `picked(m)` is `Some(true)`; nothing held where it
    /// is `Some(false)`; untouched where `None`.
    fn each_body(
        &mut self,
        manifolds: &mut [Manifold],
        picked: impl Fn(&Manifold) -> Option<bool>,
        bodies: usize,
        wanted: impl Fn(&Manifold) -> f64,
        reach: f64,
        up: &V3,
    ) {
        let sums = &mut self.sums;
        sums.clear();
        sums.resize(bodies, (0.0, 0));
        self.picks.clear();
        for m in manifolds.iter() {
            let pick = match (m.len > 0).then(|| picked(m)).flatten() {
                None => UNTOUCHED,
                Some(false) => LET_GO,
                Some(true) => {
                    let u = upper(m, up);
                    let s = &mut sums[u];
                    s.0 += wanted(m);
                    s.1 += 1;
                    u as u32
                }
            };
            self.picks.push(pick);
        }
        for (m, &pick) in manifolds.iter_mut().zip(&self.picks) {
            let now = match pick {
                UNTOUCHED => continue,
                LET_GO => 0.0,
                u => {
                    let (sum, count) = sums[u as usize];
                    (sum / count as f64).clamp(0.0, reach.max(0.0))
                }
            };
            m.held_overlap = now;
        }
    }
}

/// The mean overlap (m) of `m`'s points at the start of the step (negative: apart).
pub(crate) fn mean_overlap(m: &Manifold) -> f64 {
    let points = m.points();
    if points.is_empty() {
        return 0.0;
    }
    -points.iter().map(|p| p.separation).sum::<f64>() / points.len() as f64
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::ContactPoint;

    /// Against gravity along −z.
    const UP: V3 = V3::new(0.0, 0.0, 1.0);

    /// A manifold from body `a` up to body `b` (normal +z) with points at `separations`, each
    /// carrying `impulse` and held at `held`.
    fn manifold(a: u32, b: u32, separations: &[f64], impulse: f64, held: f64) -> Manifold {
        let mut m = Manifold::new(a, b);
        for (p, &s) in m.points.iter_mut().zip(separations) {
            *p = ContactPoint {
                separation: s,
                normal_impulse: impulse,
                ..ContactPoint::default()
            };
        }
        m.len = separations.len();
        m.held_overlap = held;
        m
    }

    fn update(ms: &mut [Manifold], dt: f64) {
        SinkHold::default().update(ms, |_| true, (4, dt, 0.02), &UP);
    }

    #[test]
    fn a_loaded_contact_takes_up_its_sink_over_the_hold_time() {
        // 1 mm beyond the slop at every point, a step of a tenth of the hold time.
        let s = -(1e-3 + LINEAR_SLOP);
        let mut ms = [manifold(0, 1, &[s; 4], 0.1, 0.0)];
        update(&mut ms, 0.1 * HOLD_TIME);
        assert!(
            (ms[0].held_overlap - 1e-4).abs() < 1e-15,
            "{}",
            ms[0].held_overlap
        );
        // A step as long as the hold time takes all of it, on top of what was held.
        update(&mut ms, HOLD_TIME);
        assert!((ms[0].held_overlap - 1.1e-3).abs() < 1e-15);
    }

    #[test]
    fn a_body_is_held_evenly_on_all_its_supports() {
        // Body 2 on bodies 0 and 1, tilted: 2 mm beyond the slop on one, at the slop on the
        // other. Both hold the mean, 1 mm; body 3 on body 2 is held on its own.
        let s = -LINEAR_SLOP;
        let mut ms = [
            manifold(0, 2, &[s - 2e-3; 4], 0.1, 0.0),
            manifold(1, 2, &[s; 2], 0.1, 0.0),
            manifold(2, 3, &[s - 4e-3; 4], 0.1, 0.0),
        ];
        update(&mut ms, HOLD_TIME);
        for m in &ms[..2] {
            assert!((m.held_overlap - 1e-3).abs() < 1e-15, "{}", m.held_overlap);
        }
        assert!((ms[2].held_overlap - 4e-3).abs() < 1e-15);
        // Lifted 0.5 mm above the slop: the hold gives back that much.
        let mut ms = [manifold(0, 1, &[s + 5e-4; 4], 0.1, 1e-3)];
        update(&mut ms, HOLD_TIME);
        assert!((ms[0].held_overlap - 5e-4).abs() < 1e-15);
    }

    #[test]
    fn an_unloaded_contact_holds_nothing_and_a_hold_stays_within_reach() {
        let mut ms = [manifold(0, 1, &[-5e-3; 2], 0.0, 3e-3)];
        update(&mut ms, 1.0 / 60.0);
        assert_eq!(ms[0].held_overlap, 0.0);
        let mut ms = [manifold(0, 1, &[-0.5; 2], 1.0, 0.0)];
        update(&mut ms, 1.0);
        assert_eq!(ms[0].held_overlap, 0.02);
        // Never below zero, far apart.
        let mut ms = [manifold(0, 1, &[0.5; 2], 1.0, 1e-3)];
        update(&mut ms, 1.0);
        assert_eq!(ms[0].held_overlap, 0.0);
    }

    #[test]
    fn a_contact_pressed_from_the_side_holds_nothing() {
        // A normal 50° from the vertical bears no weight; 40° from it, it does.
        for (degrees, holds) in [(50.0_f64, false), (40.0, true)] {
            let mut ms = [manifold(0, 1, &[-2e-3; 4], 0.1, 0.0)];
            let a = degrees.to_radians();
            ms[0].normal = V3::new(a.sin(), 0.0, a.cos());
            update(&mut ms, HOLD_TIME);
            assert_eq!(ms[0].held_overlap > 0.0, holds, "{degrees}°");
        }
    }

    #[test]
    fn a_manifold_the_step_does_not_solve_keeps_its_hold() {
        let mut ms = [manifold(0, 1, &[-2e-3; 4], 0.1, 7e-4)];
        SinkHold::default().update(&mut ms, |_| false, (2, HOLD_TIME, 0.02), &UP);
        assert_eq!(ms[0].held_overlap, 7e-4);
    }
}

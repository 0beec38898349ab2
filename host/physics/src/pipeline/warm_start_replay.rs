//! The contacts' warm start replayed per body.
//!
//! Each substep's warm start applies the impulse every contact accumulated over the substep
//! before (its warm start, biased solve and relax together), through the Jacobians and
//! inverse masses fixed for the step. That is exactly the change of each body's velocity the
//! contacts made in that substep. Where nothing else in the solve changes a free body's
//! velocity (no joints, no articulated trees) and the pose stage leaves the velocities alone
//! (the Lie-group Euler stage), that change is recorded per body over the substep and added
//! back at the next one: a pass over the bodies instead of a pass over every contact group,
//! with its gathers and scatters. The first substep of a step still warm starts from the
//! manifolds, because the constraints were prepared afresh.
//!
//! The velocities are the same as the contacts' warm start's up to rounding (one addition and
//! one subtraction per component), not bit for bit.

use crate::dynamics::BodySet;
use crate::geometry::V3;

/// Each body's velocity at a substep's start and the change the contacts made over it
/// (world frame; m/s and rad/s).
#[derive(Clone, Debug, Default)]
pub(crate) struct WarmStartReplay {
    start_vel: Vec<V3>,
    start_omega: Vec<V3>,
    dv: Vec<V3>,
    dw: Vec<V3>,
}

impl WarmStartReplay {
    /// At the start of a substep whose contacts warm start from the manifolds: remember the
    /// velocities before the warm start.
    pub(crate) fn mark(&mut self, bodies: &BodySet) {
        self.start_vel.clone_from(&bodies.vel);
        self.start_omega.clone_from(&bodies.omega);
    }

    /// In place of a later substep's warm start: remember the velocities, then add the
    /// change the contacts made over the substep before ([`Self::record`]).
    pub(crate) fn replay(&mut self, bodies: &mut BodySet) {
        self.mark(bodies);
        add(&mut bodies.vel, &self.dv);
        add(&mut bodies.omega, &self.dw);
    }

    /// At the end of a substep (after its last pass): the change the contacts made over it.
    pub(crate) fn record(&mut self, bodies: &BodySet) {
        difference(&mut self.dv, &bodies.vel, &self.start_vel);
        difference(&mut self.dw, &bodies.omega, &self.start_omega);
    }
}

fn add(v: &mut [V3], d: &[V3]) {
    for (v, d) in v.iter_mut().zip(d) {
        *v += d;
    }
}

fn difference(out: &mut Vec<V3>, end: &[V3], start: &[V3]) {
    out.resize(end.len(), V3::zeros());
    for ((d, e), s) in out.iter_mut().zip(end).zip(start) {
        *d = e - s;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_replay_adds_what_the_substep_changed() {
        let mut replay = WarmStartReplay::default();
        let mut bodies = BodySet {
            vel: vec![V3::new(1.0, 2.0, 3.0)],
            omega: vec![V3::new(0.0, -1.0, 0.5)],
            ..BodySet::default()
        };
        replay.mark(&bodies);
        bodies.vel[0] += V3::new(0.5, 0.0, -1.0);
        bodies.omega[0] += V3::new(0.0, 0.25, 0.0);
        replay.record(&bodies);
        bodies.vel[0] = V3::new(10.0, 0.0, 0.0);
        bodies.omega[0] = V3::zeros();
        replay.replay(&mut bodies);
        assert_eq!(bodies.vel[0], V3::new(10.5, 0.0, -1.0));
        assert_eq!(bodies.omega[0], V3::new(0.0, 0.25, 0.0));
    }
}

//! The step's guard as the world runs it: the checks before a step and the snapshot, the
//! check after it and the way back (what is checked: `pipeline/step_guard.rs`).

use super::step_guard::{
    at_most, finite3, max_abs, MAX_ANGULAR_SPEED_RAD_S, MAX_COORD_M, MAX_DT_S, MAX_GRAVITY_M_S2,
    MAX_SPEED_M_S, MAX_TREE_VALUE,
};
use super::world::World;
use crate::dynamics::{BodyKind, DynamicsError};
use crate::geometry::Shape;

impl World {
    /// The checks before a step, then the snapshot. Nothing is changed on an error.
    pub(super) fn guard_before_step(&mut self) -> Result<(), DynamicsError> {
        let param = |what: String, expected: &'static str, value: f64| {
            Err(DynamicsError::InvalidParameter {
                what,
                expected,
                value,
            })
        };
        if !(self.dt.is_finite() && self.dt > 0.0 && self.dt <= MAX_DT_S) {
            return param("dt".into(), "a finite step in (0, 1] s", self.dt);
        }
        for k in 0..3 {
            let g = self.gravity[k];
            if !(g.is_finite() && g.abs() <= MAX_GRAVITY_M_S2) {
                return param(format!("gravity[{k}]"), "finite, within ±1e6 m/s²", g);
            }
        }
        if self.settings.substeps == 0 {
            return param("settings.substeps".into(), "at least 1", 0.0);
        }
        let (s, v) = (&self.settings, &self.variants);
        for (what, value) in [
            ("settings.contact_hertz", s.contact_hertz),
            ("variants.contact_hertz_cap", v.contact_hertz_cap),
            ("settings.contact_damping_ratio", s.contact_damping_ratio),
            ("variants.contact_bias_rate", v.contact_bias_rate),
            ("settings.joint_hertz", s.joint_hertz),
            ("settings.joint_damping_ratio", s.joint_damping_ratio),
            ("settings.speculative_distance", s.speculative_distance),
            ("settings.max_push_velocity", s.max_push_velocity),
            ("settings.restitution_threshold", s.restitution_threshold),
            ("settings.linear_damping", s.linear_damping),
            ("settings.angular_damping", s.angular_damping),
        ] {
            if !(value.is_finite() && value >= 0.0) {
                return param(what.into(), "finite and ≥ 0", value);
            }
        }
        let n = self.bodies.len();
        let clock_only = self.guard.checked == n && self.only_the_clock_moves();
        let checked = self.guard.checked.min(n);
        for i in checked..n {
            self.check_new_body(i)?;
        }
        self.guard.checked = n;
        self.guard.clock_only = clock_only;
        self.guard.time = self.time;
        if clock_only {
            // A sleeping body's state changes only through the setters, which wake it: only
            // the kinematic and fixed bodies can have changed since the last full check.
            return (0..n)
                .filter(|&i| self.bodies.kind[i] != BodyKind::Dynamic)
                .try_for_each(|i| self.check_body_state(i));
        }
        self.check_state_and_snapshot()
    }

    /// Whether the step can only advance the clock: sleeping is on, no body is awake, no
    /// kinematic body moves and there is no articulated tree (the step's own test for an
    /// empty step, `World::step_unguarded`), and no body was added since the last step.
    fn only_the_clock_moves(&self) -> bool {
        self.islands.is_some()
            && self.articulated.is_empty()
            && self.bodies.awake.iter().all(|a| !a)
            && !self.kinematic_moving()
    }

    /// Body `i`'s pose and velocity finite and not huge.
    fn check_body_state(&self, i: usize) -> Result<(), DynamicsError> {
        let b = &self.bodies;
        let p = max_abs(&b.pos[i]);
        if !at_most(p, MAX_COORD_M) {
            return Err(self.body_error(i, "position", "finite, within ±1e9 m", p));
        }
        if !b.rot[i].iter().all(|x| x.is_finite()) {
            return Err(self.body_error(i, "rotation", "finite", f64::NAN));
        }
        let v = b.vel[i].norm();
        if !at_most(v, MAX_SPEED_M_S) {
            return Err(self.body_error(i, "velocity", "finite, at most 1e6 m/s", v));
        }
        let w = b.omega[i].norm();
        if !at_most(w, MAX_ANGULAR_SPEED_RAD_S) {
            return Err(self.body_error(i, "angular velocity", "finite, at most 1e6 rad/s", w));
        }
        Ok(())
    }

    fn body_error(
        &self,
        i: usize,
        what: &'static str,
        expected: &'static str,
        value: f64,
    ) -> DynamicsError {
        DynamicsError::InvalidBody {
            body: i,
            name: self.bodies.name[i].clone(),
            what,
            expected,
            value,
        }
    }

    /// The fixed properties of body `i`: mass, inertia, shape.
    fn check_new_body(&self, i: usize) -> Result<(), DynamicsError> {
        let b = &self.bodies;
        if b.kind[i] == BodyKind::Dynamic {
            let im = b.inv_mass[i];
            // The mass was given as its inverse: 1/m ≤ 0 means m ≤ 0 (or NaN), 1/m = ∞ a
            // subnormal mass.
            if !(im.is_finite() && im > 0.0 && (1.0 / im).is_finite()) {
                return Err(self.body_error(
                    i,
                    "inverse mass",
                    "finite and > 0 (a dynamic body needs a finite mass > 0)",
                    im,
                ));
            }
            for k in 0..3 {
                let (j, ij) = (b.inertia[i][k], b.inv_inertia[i][k]);
                if !(j.is_finite() && j > 0.0) {
                    return Err(self.body_error(i, "principal inertia", "finite and > 0", j));
                }
                if !(ij.is_finite() && ij > 0.0) {
                    return Err(self.body_error(
                        i,
                        "inverse principal inertia",
                        "finite and > 0",
                        ij,
                    ));
                }
            }
        }
        match &b.shape[i] {
            Shape::HalfSpace { normal } => {
                let n = normal.norm();
                if !(finite3(normal) && n.is_finite() && n > 0.0) {
                    return Err(self.body_error(
                        i,
                        "half-space normal length",
                        "finite and > 0",
                        n,
                    ));
                }
            }
            shape => {
                let r = shape.bounding_radius();
                if !(r.is_finite() && r > 0.0) {
                    return Err(self.body_error(
                        i,
                        "shape size (bounding radius)",
                        "finite and > 0",
                        r,
                    ));
                }
            }
        }
        Ok(())
    }

    /// Every body's and tree's state finite and not huge, copied into the snapshot.
    fn check_state_and_snapshot(&mut self) -> Result<(), DynamicsError> {
        for i in 0..self.bodies.len() {
            self.check_body_state(i)?;
        }
        let b = &self.bodies;
        for (t, a) in self.articulated.iter().enumerate() {
            for (what, values) in [("q", &a.q), ("qd", &a.qd), ("tau", &a.tau)] {
                if let Some((index, &value)) = values
                    .iter()
                    .enumerate()
                    .find(|(_, x)| !at_most(x.abs(), MAX_TREE_VALUE))
                {
                    return Err(DynamicsError::InvalidTree {
                        tree: t,
                        what,
                        index,
                        expected: "finite, within ±1e9",
                        value,
                    });
                }
            }
        }
        let g = &mut self.guard;
        g.pos.clone_from(&b.pos);
        g.rot.clone_from(&b.rot);
        g.vel.clone_from(&b.vel);
        g.omega.clone_from(&b.omega);
        g.awake.clone_from(&b.awake);
        g.sleep_time.clone_from(&b.sleep_time);
        g.aabb.clone_from(&b.aabb);
        g.trees.clear();
        for a in &self.articulated {
            g.trees.extend_from_slice(&a.q);
            g.trees.extend_from_slice(&a.qd);
        }
        g.joints.clone_from(&self.joints);
        Ok(())
    }

    /// The check after the step: `result` is the step's own; on it being an error or on a
    /// non-finite state, the world is put back and the error returned.
    pub(super) fn guard_after_step(
        &mut self,
        result: Result<(), DynamicsError>,
    ) -> Result<(), DynamicsError> {
        if self.guard.clock_only {
            // Nothing but the clock moved (nor was snapshotted): only it goes back.
            return result.inspect_err(|_| self.time = self.guard.time);
        }
        let error = match result {
            Err(e) => Some(e),
            Ok(()) => self.non_finite(),
        };
        match error {
            None => Ok(()),
            Some(e) => {
                self.roll_back();
                Err(e)
            }
        }
    }

    /// The first non-finite body or tree state; a dynamic body before a kinematic or fixed
    /// one (a NaN impulse also reaches the velocity of the ground it pushes against, whose
    /// inverse mass is 0).
    fn non_finite(&self) -> Option<DynamicsError> {
        let b = &self.bodies;
        let mut other = None;
        for i in 0..b.len() {
            let quantity = if !finite3(&b.pos[i]) {
                "position"
            } else if !b.rot[i].iter().all(|x| x.is_finite()) {
                "rotation"
            } else if !finite3(&b.vel[i]) {
                "velocity"
            } else if !finite3(&b.omega[i]) {
                "angular velocity"
            } else {
                continue;
            };
            if b.kind[i] != BodyKind::Dynamic {
                other = other.or(Some((i, quantity)));
                continue;
            }
            other = Some((i, quantity));
            break;
        }
        if let Some((i, quantity)) = other {
            return Some(DynamicsError::NonFinite {
                body: i,
                name: b.name[i].clone(),
                quantity,
            });
        }
        for (tree, a) in self.articulated.iter().enumerate() {
            let quantity = if !a.q.iter().all(|x| x.is_finite()) {
                "q"
            } else if !a.qd.iter().all(|x| x.is_finite()) {
                "qd"
            } else {
                continue;
            };
            return Some(DynamicsError::NonFiniteTree { tree, quantity });
        }
        None
    }

    /// Puts back the snapshot and clears the contact warm-start cache.
    fn roll_back(&mut self) {
        let g = &self.guard;
        let b = &mut self.bodies;
        b.pos.clone_from(&g.pos);
        b.rot.clone_from(&g.rot);
        b.vel.clone_from(&g.vel);
        b.omega.clone_from(&g.omega);
        b.awake.clone_from(&g.awake);
        b.sleep_time.clone_from(&g.sleep_time);
        b.aabb.clone_from(&g.aabb);
        let mut at = 0;
        for a in &mut self.articulated {
            let (nq, nv) = (a.q.len(), a.qd.len());
            a.q.copy_from_slice(&g.trees[at..at + nq]);
            a.qd.copy_from_slice(&g.trees[at + nq..at + nq + nv]);
            at += nq + nv;
        }
        self.joints.clone_from(&g.joints);
        self.time = g.time;
        // The failed step's rest does not count.
        self.resting_substeps.forget();
        if let Some(narrow) = self.narrow.as_mut() {
            narrow.clear();
        }
        // The world-axes inverse inertia follows the restored rotations.
        self.bodies.update_world_inertia();
    }
}

//! The decisions a step takes about its substeps once its contacts are known: the lean step
//! at rest, fewer substeps for a world at rest (`resting_substeps.rs`), extra substeps for the
//! islands whose columns would lean (`island_substeps.rs`) and the carried impulses rescaled
//! to the substep they are solved over.

use super::island_substeps::StepLoads;
use super::resting_substeps::RestingWorld;
use super::step::{manifolds, solved_between_free_bodies, ContactLeanStep};
use super::world::World;
use super::{Effect, FreeForces};
use crate::dynamics::solver::{
    ContactBatches, ContactConstraint, ContactSettings, ContactStiffness, SolvePass,
};
use crate::dynamics::BodySet;
use crate::geometry::Manifold;

impl World {
    /// The lean step this step may take, before its contacts are prepared: a world of free
    /// bodies in contact under gravity, soft contacts grouped four by four, no restitution,
    /// every body still, and a resting decision on fewer substeps that it keeps this step
    /// ([`RestingSubsteps::kept_for`]). Its grouped constraints are then read from their
    /// lanes alone (filled as each is prepared), never from `constraints`, so they are
    /// prepared in cache and not written there; the step checks once its substeps are known
    /// that it took them ([`Self::prepare_contacts_again`] otherwise).
    pub(super) fn lean_step(
        &self,
        n_sub: usize,
        dt: f64,
        predicted: Option<ContactStiffness>,
    ) -> Option<ContactLeanStep> {
        let eff = &self.effects;
        let plain = self.variants.lean_resting_contacts
            && self.variants.batch_contacts
            && self.variants.soft_contacts
            && self.variants.fewer_substeps_at_rest
            && eff.has(Effect::Gravity)
            && !eff.has(Effect::Restitution)
            && self.articulated.is_empty()
            && self.joints.is_empty()
            && !self.kinematic_moving()
            && !self.island_substeps.holding();
        if !plain {
            return None;
        }
        let substeps = self.resting_substeps.kept_for(&self.bodies, n_sub, dt)?;
        let substep = dt / substeps as f64;
        let stiffness = self.variants.stiffness_on(&self.settings, substep, dt);
        // The stiffness the constraints took last step (`predicted`, which each is stiffened
        // with as it is prepared), so that nothing is stiffened again.
        (predicted == Some(stiffness)).then_some(ContactLeanStep { substeps, substep })
    }

    /// Prepares every free bodies' contact constraint again, whole, in `constraints` (a lean
    /// step whose substeps came out otherwise; the bodies and manifolds are those the step
    /// prepared them from, so they come out as the full step would have prepared them).
    pub(super) fn prepare_contacts_again(&mut self, settings: &ContactSettings) {
        let Some(narrow) = self.narrow.as_ref() else {
            return;
        };
        let mut ci = 0;
        for (mi, m) in narrow.manifolds.iter().enumerate() {
            if solved_between_free_bodies(&self.bodies, &self.proxies, m) {
                self.constraints[ci].prepare_in(&self.bodies, m, mi, settings);
                ci += 1;
            }
        }
    }

    /// The substeps the step takes: fewer than `n_sub` where the world rests and its contacts
    /// hold it as well on fewer ([`RestingSubsteps::substeps`]); `coupled` says whether
    /// articulated trees are solved with the free bodies.
    pub(super) fn substeps_at_rest(&mut self, n_sub: usize, coupled: bool) -> usize {
        let g = self.gravity.norm();
        let allowed = self.variants.fewer_substeps_at_rest
            && self.variants.soft_contacts
            && self.effects.has(Effect::Gravity)
            && g > 0.0;
        if !allowed {
            self.resting_substeps.forget();
            return n_sub;
        }
        let joints_on = self.effects.has(Effect::Joints) && !self.joints.is_empty();
        let more_than_contacts = joints_on
            || coupled
            || !self.articulated.is_empty()
            || !self.tree_contacts.contacts.is_empty()
            || self.kinematic_moving();
        let stiffness = self
            .variants
            .contact_stiffness(&self.settings, self.dt / n_sub as f64);
        let world = RestingWorld {
            loads: StepLoads::new(
                &stiffness,
                &self.gravity,
                (manifolds(&self.narrow), &self.joint_pairs, &self.proxies),
                self.dt,
            ),
            more_than_contacts,
            hold_sink: self.variants.hold_sink,
            substeps: n_sub,
        };
        let (settings, variants) = (self.settings, self.variants);
        let dt = self.dt;
        self.resting_substeps.substeps(
            &self.bodies,
            &self.constraints,
            &mut self.island_substeps,
            &world,
            |n| variants.stiffness_on(&settings, dt / n as f64, dt),
        )
    }

    /// Decides which islands need stiffer contacts this step ([`IslandSubsteps::plan`]),
    /// stiffens them, and gives them the extra substeps that keep them within the stiffness
    /// cap; marks the constraints that take those substeps. `n_sub` is the step's substeps.
    pub(super) fn plan_island_substeps(&mut self, stiffness: &ContactStiffness, n_sub: usize) {
        let g = self.gravity.norm();
        let loaded = self.effects.has(Effect::Gravity) && !self.constraints.is_empty() && g > 0.0;
        if !loaded {
            return;
        }
        let sources = (
            manifolds(&self.narrow),
            &self.joint_pairs[..],
            &self.proxies[..],
        );
        let loads = StepLoads::new(stiffness, &self.gravity, sources, self.dt);
        let factor = self.island_substeps.plan(
            &self.bodies,
            &self.constraints,
            &loads,
            self.settings.speculative_distance,
        );
        if factor <= 1 {
            return;
        }
        // Each island's contacts its own factor times as stiff, on as many substeps as keep
        // the stiffest within the cap (none more where the step's contacts are far below it,
        // as at 1 ms).
        let cap = self.variants.contact_hertz_cap / stiffness.substep;
        let stiffest = stiffness.hertz.max(stiffness.even_hertz) * factor as f64;
        let substeps = ((stiffest / cap).ceil() as usize).clamp(1, factor);
        let stiffer = |k: usize| {
            let k = k as f64;
            ContactStiffness {
                hertz: stiffness.hertz * k,
                even_hertz: stiffness.even_hertz * k,
                static_hertz: stiffness.static_hertz * k,
                damping_ratio: stiffness.damping_ratio,
                substep: stiffness.substep / substeps as f64,
            }
        };
        self.fine_constraint.clear();
        for (ci, c) in self.constraints.iter_mut().enumerate() {
            let body = if c.ima > 0.0 { c.a } else { c.b };
            let k = self.island_substeps.fine[body];
            if k > 1 {
                c.stiffen(&stiffer(k));
                self.batches.set_softness(ci, c);
            }
            self.fine_constraint.push(k > 1 && substeps > 1);
        }
        self.fine_factor = substeps;
        if substeps > 1 {
            self.counters.fine_substeps = n_sub * substeps;
        }
        self.counters.fine_bodies = self.island_substeps.fine.iter().filter(|&&k| k > 1).count();
    }

    /// Scales each constraint's carried impulses from the substep they were accumulated over
    /// to the one it takes this step (`h`, or `h / fine_factor` in an island with extra
    /// substeps); whether any were rescaled. A lean step (`ContactLeanStep`) has checked
    /// that none is, as it prepared them, and its constraints are not read.
    pub(super) fn carry_impulses_to_substeps(&mut self, h: f64, lean: bool) -> bool {
        if self.fine_factor <= 1 {
            self.fine_constraint.clear();
            self.fine_constraint.resize(self.constraints.len(), false);
        }
        if lean {
            return false;
        }
        let Some(narrow) = self.narrow.as_mut() else {
            return false;
        };
        let fine_h = h / self.fine_factor as f64;
        let hold_up = self.variants.hold_up(&self.effects, &self.gravity);
        let reach = self.settings.speculative_distance;
        let fine = &self.fine_constraint;
        let substep = |ci: usize| if fine[ci] { fine_h } else { h };
        let mut changed = false;
        for (ci, c) in self.constraints.iter_mut().enumerate() {
            let carried = narrow.manifolds[c.manifold].impulse_substep;
            let now = substep(ci);
            if carried > 0.0 && carried != now {
                c.scale_impulses(now / carried);
                changed = true;
            }
        }
        // The holds follow the stiffness where the substep changed (the manifolds keep the
        // substep their impulses were carried over until the store).
        if let (Some(up), true) = (&hold_up, changed) {
            let (settings, variants, dt) = (&self.settings, &self.variants, self.dt);
            let changes = |ci: usize, m: &Manifold| {
                let (carried, now) = (m.impulse_substep, substep(ci));
                (carried > 0.0 && carried != now).then(|| {
                    (
                        variants.stiffness_on(settings, carried, dt),
                        variants.stiffness_on(settings, now, dt),
                    )
                })
            };
            self.sink_hold.restiffen(
                &mut self.constraints,
                &mut narrow.manifolds,
                changes,
                (self.bodies.len(), reach),
                up,
            );
        }
        changed
    }

    /// The extra substeps of the islands that take them: `substeps` of `h` (s) over their
    /// bodies and contacts alone (nothing else touches them: the plan keeps islands with
    /// joints, tree links or moving kinematic bodies out), then every body's `awake` flag
    /// back as it was.
    pub(super) fn fine_substeps(&mut self, substeps: usize, h: f64, forces: &FreeForces) {
        for (awake, &k) in self.bodies.awake.iter_mut().zip(&self.island_substeps.fine) {
            *awake = k > 1;
        }
        let inv_h = 1.0 / h;
        let max_push = self.settings.max_push_velocity;
        for sub in 0..substeps {
            self.integrator
                .integrate_velocities(&mut self.bodies, h, forces);
            self.fine_contacts(|c, b| c.warm_start(b), |g, b| g.warm_start(b));
            let rev = sub % 2 == 1;
            let relax = self.variants.relax_each_substep || sub + 1 == substeps;
            for (use_bias, reverse) in [(true, rev), (false, !rev)] {
                if !use_bias && !relax {
                    break;
                }
                let pass = SolvePass { use_bias, reverse };
                self.fine_contacts(
                    |c, b| c.solve(b, inv_h, max_push, pass),
                    |g, b| g.solve(b, inv_h, max_push, pass),
                );
                if use_bias {
                    self.integrator
                        .integrate_island_positions(&mut self.bodies, h);
                }
            }
        }
        self.bodies.awake.clone_from(&self.awake_saved);
    }

    /// Runs `one` on each contact constraint of the islands with extra substeps that is
    /// solved one by one, and `batched` on their coloured groups.
    pub(super) fn fine_contacts(
        &mut self,
        one: impl Fn(&mut ContactConstraint, &mut BodySet),
        batched: impl FnOnce(&mut ContactBatches, &mut BodySet),
    ) {
        if self.batched {
            batched(&mut self.fine_batches, &mut self.bodies);
            for &ci in &self.fine_batches.scalar {
                one(&mut self.constraints[ci], &mut self.bodies);
            }
        } else {
            for (c, &fine) in self.constraints.iter_mut().zip(&self.fine_constraint) {
                if fine {
                    one(c, &mut self.bodies);
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::builtin::pyramid;

    /// A lean step leaves its grouped constraints as last step's; where its substeps come out
    /// otherwise, `prepare_contacts_again` must give every constraint as the full step
    /// prepares it.
    #[test]
    fn constraints_prepared_again_are_the_full_steps() {
        let mut scene = pyramid(5);
        scene.effects.retain(|e| *e != Effect::Sleeping);
        let mut w = scene.build().unwrap();
        for _ in 0..60 {
            w.step().unwrap();
        }
        assert!(
            w.counters().lean_contacts > 0,
            "the pyramid took no lean step"
        );
        let settings = w.contact_settings();
        let narrow = w.narrow.as_ref().unwrap();
        let full: Vec<ContactConstraint> = narrow
            .manifolds
            .iter()
            .enumerate()
            .filter(|(_, m)| w.bodies.awake[m.a as usize] || w.bodies.awake[m.b as usize])
            .map(|(mi, m)| ContactConstraint::prepare(&w.bodies, m, mi, &settings))
            .collect();
        // What each constraint's warm start gives the bodies: the same for the same rows and
        // impulses.
        let kick = |w: &World, c: &ContactConstraint| {
            let mut b = w.bodies.clone();
            c.warm_start(&mut b);
            (b.vel, b.omega)
        };
        let differs = |w: &World| {
            full.iter()
                .zip(&w.constraints)
                .filter(|(f, c)| kick(w, f) != kick(w, c))
                .count()
        };
        assert_eq!(w.constraints.len(), full.len());
        assert!(
            differs(&w) > 0,
            "the lean steps kept their constraints whole"
        );
        w.prepare_contacts_again(&settings);
        assert_eq!(differs(&w), 0);
    }
}

//! The step of a world, stage by stage ([`World::step_unguarded`]): collision, the touching
//! contacts' impacts (`impacts.rs`), the contacts' preparation, the joints and trees, the plan of the substeps, the solve per substep (warm
//! start, solve, integrate, relax), the extra substeps of the islands that take them,
//! restitution and the impulses' store, the fast balls' paths (`ccd.rs`), the trees stepped on their own, and the islands.

use super::drives::DriveGroup;
use super::tree_contacts::Proxy;
use super::world::World;
use super::{ccd, link_proxies};
use super::{Effect, FreeForces, IntegratorKind, Stage};
use crate::dynamics::solver::{
    ContactConstraint, ContactSettings, ContactStiffness, FreeJoint, JointSoftness, Softness,
    SolvePass,
};
use crate::dynamics::{BodyKind, BodySet, DynamicsError};
use crate::geometry::{BodyMotion, BroadPhase, CollisionBodies, Manifold, NarrowPhase, V3};

/// The most pairs of overlapping bounding boxes a world may hold per body (–). Equal spheres
/// touch at most 12 others (the kissing number), and the boxes of a dense cubic pile of
/// boxes, grown by the contact margins, overlap their 26 neighbours': 13 pairs per body. A
/// large body among small ones touches many, but each of those few: a pile's pairs stay
/// near 13 per body. Far past that, bodies overlap en masse (many placed at one point), and
/// the step's contacts grow as the square of their number: the step refuses with
/// [`DynamicsError::TooManyContactPairs`], the scene with `SceneError::TooMany`, instead of
/// taking minutes and gigabytes.
pub const MAX_CONTACT_PAIRS_PER_BODY: usize = 64;

/// A step whose grouped contact constraints live in their lanes alone
/// (`World::lean_step`): what it was prepared for.
#[derive(Clone, Copy, Debug)]
pub(super) struct ContactLeanStep {
    /// The substeps the resting decision keeps.
    pub(super) substeps: usize,
    /// Their length (s).
    pub(super) substep: f64,
}

/// What the contacts' preparation leaves to the plan of the substeps.
struct PreparedContacts {
    /// The contact rows' settings.
    settings: ContactSettings,
    /// The stiffness each soft constraint took as it was prepared: last step's.
    predicted: Option<ContactStiffness>,
    /// The lean step the constraints were prepared for, if any.
    lean: Option<ContactLeanStep>,
    /// Whether a lean step's carried impulse must be rescaled to its substep.
    lean_rescales: bool,
    /// Whether a contact follows a round part's turn: its rows change within the step.
    follows: bool,
}

/// The substeps a step takes and what each solves with.
struct SubstepPlan {
    /// How many.
    substeps: usize,
    /// Their length (s).
    h: f64,
    /// Its inverse (1/s).
    inv_h: f64,
    /// The soft contacts' softness, against moving and against fixed bodies.
    soft: Softness,
    soft_static: Softness,
    /// The joints' softness.
    joint_soft: JointSoftness,
    /// Gravity, gyroscopic terms and damping over a substep.
    forces: FreeForces,
    /// Whether joints are solved.
    joints_on: bool,
    /// Whether articulated trees are solved with the free bodies.
    coupled: bool,
    /// Whether the contacts' warm start is replayed per body from the second substep on.
    replay: bool,
}

impl World {
    /// One step of `dt`, unchecked: its stages in order. A `whole` step (not a part of one)
    /// in which a free tree meets something it did not touch in the last step, farther than
    /// it can be followed on one set of contact rows (`parts_on_arrival`), stops after
    /// collision with nothing moved and returns `Some(parts)`: the caller takes the step in
    /// that many parts. Otherwise `None`.
    pub(super) fn step_unguarded(&mut self, whole: bool) -> Result<Option<usize>, DynamicsError> {
        self.counters.reset();
        self.counters.parts = 1;
        let h = self.dt / self.settings.substeps.max(1) as f64;
        self.counters.awake_bodies = self.bodies.awake.iter().filter(|a| **a).count();
        if self.islands.is_some() && self.counters.awake_bodies == 0 && !self.kinematic_moving() {
            // Everything sleeps and nothing can wake it: the free bodies' step is empty.
            self.step_articulated(h)?;
            self.time += self.dt;
            return Ok(None);
        }
        self.begin_step(h)?;
        self.collide(h)?;
        if whole {
            let parts = self.parts_on_arrival();
            if parts > 1 {
                // Nothing has moved yet: the parts collide again where the links are.
                self.ball_paths.clear();
                return Ok(Some(parts));
            }
        }
        self.touching_impacts();
        let prepared = self.prepare_contacts()?;
        let joints_on = self.prepare_joints(h);
        let coupled = self.begin_solve();
        let plan = self.plan_substeps(&prepared, joints_on, coupled);
        self.solve_substeps(&plan)?;
        self.fine_island_substeps(&plan);
        self.restitution_and_store(plan.h);
        self.end_ball_paths();
        self.step_articulated(plan.h)?;
        self.sync_link_proxies(false);
        self.update_islands();
        self.time += self.dt;
        Ok(None)
    }

    /// Before collision: the motors' velocities predicted for continuous collision, the tree
    /// links' proxies posed, the world inertias, and the broad phase rebuilt where bodies
    /// were inserted or removed.
    fn begin_step(&mut self, h: f64) -> Result<(), DynamicsError> {
        if self.effects.has(Effect::ContinuousCollision) {
            self.predict_motor_velocities(h)?;
        }
        self.sync_link_proxies(true);
        self.bodies.update_world_inertia();
        if self.broad_dirty {
            self.broad_dirty = false;
            if self.broad.is_some() {
                self.broad = Some(BroadPhase::new(&self.bodies.shape));
            }
        }
        Ok(())
    }

    /// Collision on substeps of `h` (s): each moving body's box (grown by the speculative
    /// distance, and by its sweep with continuous collision), the broad phase's pairs, the
    /// narrow phase's manifolds (fast balls keep only the contacts their swept path
    /// touches), and the resting contacts' held sink.
    fn collide(&mut self, h: f64) -> Result<(), DynamicsError> {
        let (Some(broad), Some(narrow)) = (self.broad.as_mut(), self.narrow.as_mut()) else {
            return Ok(());
        };
        let (eff, dt) = (self.effects, self.dt);
        let ccd = eff.has(Effect::ContinuousCollision);
        let spec = self.settings.speculative_distance;
        let b = &mut self.bodies;
        // Without continuous collision, a body whose centre travels more than half the
        // speculative distance in the step keeps its contacts as far as it travels: a heavy
        // body falling onto a pile meets it at the substep it arrives, not a step late.
        let travel = &mut self.travel;
        travel.clear();
        for i in 0..b.len() {
            let moving = b.awake[i] || b.kind[i] == BodyKind::Kinematic;
            if !moving && b.kind[i] == BodyKind::Dynamic {
                continue; // sleeping: box unchanged
            }
            let mut margin = spec;
            if ccd && moving {
                margin += dt * b.sweep_speed(i);
            }
            let mut aabb = b.shape[i].aabb(&b.rot[i], &b.pos[i]).loosened(margin);
            if !ccd && moving {
                // The centre's travel (a body spinning in place, a top, keeps its contacts);
                // the box swept along it, not grown all round.
                let d = b.vel[i] * dt;
                let far = d.norm();
                if far > 0.5 * spec {
                    travel.resize(b.len(), 0.0);
                    travel[i] = far;
                    aabb.min += d.inf(&V3::zeros());
                    aabb.max += d.sup(&V3::zeros());
                }
            }
            b.aabb[i] = aabb;
        }
        self.counters.mark(Stage::BroadPhase);
        if ccd {
            self.counters.mark(Stage::ContinuousCollision);
        }
        let limit = MAX_CONTACT_PAIRS_PER_BODY.saturating_mul(b.len());
        broad.max_pairs = limit;
        self.counters.broad_phase_tests = broad.update(
            &b.collision_view(),
            &self.excluded_pairs,
            self.variants.keep_broad_phase_pairs,
        );
        if broad.overflowed {
            return Err(DynamicsError::TooManyContactPairs {
                pairs: limit + 1,
                bodies: b.len(),
                limit,
                per_body: MAX_CONTACT_PAIRS_PER_BODY,
            });
        }
        self.counters.broad_phase_pairs = broad.pairs.len();
        let bodies = &*b;
        let motion = ccd.then_some(BodyMotion {
            dt,
            vel: &bodies.vel,
            omega: &bodies.omega,
        });
        let view = CollisionBodies {
            travel: &self.travel,
            ..bodies.collision_view()
        };
        let mut nc = narrow.update(&view, &broad.pairs, spec, motion);
        if ccd {
            // Fast balls keep only the contacts their swept path touches.
            let sweep = ccd::SweepSettings {
                dt,
                substep: h,
                gravity: if eff.has(Effect::Gravity) {
                    self.gravity
                } else {
                    V3::zeros()
                },
                restitution_threshold: eff
                    .has(Effect::Restitution)
                    .then_some(self.settings.restitution_threshold),
            };
            let paths = &mut self.ball_paths;
            let (m, p) = ccd::filter_manifolds(&mut narrow.manifolds, bodies, &sweep, paths);
            nc.manifolds -= m;
            nc.contacts -= p;
        }
        self.counters.mark(Stage::NarrowPhase);
        self.counters.pairs_tested = nc.pairs_tested;
        self.counters.manifolds_refreshed = nc.refreshed;
        self.counters.manifolds = nc.manifolds;
        self.counters.contacts = nc.contacts;
        self.counters.unsupported_pairs = nc.unsupported;
        if let Some(up) = &self.variants.hold_up(&self.effects, &self.gravity) {
            let (bodies, proxies) = (&self.bodies, &self.proxies);
            let solved = |m: &Manifold| solved_between_free_bodies(bodies, proxies, m);
            self.sink_hold
                .update(&mut narrow.manifolds, solved, (bodies.len(), dt, spec), up);
        }
        Ok(())
    }

    /// Pairs of bodies whose bounding boxes (grown by the speculative distance) overlap as
    /// the world stands, counted up to `limit` + 1 (the broad phase stops there); the world
    /// is left as it is.
    pub(crate) fn overlapping_pairs(&self, limit: usize) -> usize {
        let b = &self.bodies;
        let spec = self.settings.speculative_distance;
        let aabb: Vec<_> = (0..b.len())
            .map(|i| b.shape[i].aabb(&b.rot[i], &b.pos[i]).loosened(spec))
            .collect();
        let view = CollisionBodies {
            aabb: &aabb,
            ..b.collision_view()
        };
        let mut broad = BroadPhase::new(&b.shape);
        broad.max_pairs = limit;
        broad.update(&view, &self.excluded_pairs, false);
        if broad.overflowed {
            limit + 1
        } else {
            broad.pairs.len()
        }
    }

    /// The fast balls whose path meets several fixed shapes within the step end it where
    /// their path ends (`ccd.rs`).
    fn end_ball_paths(&mut self) {
        for p in self.ball_paths.drain(..) {
            self.bodies.pos[p.ball] = p.pos;
            self.bodies.vel[p.ball] = p.vel;
        }
    }

    /// With restitution, the touching contacts' impacts passed along pair by pair before the
    /// solve (`impacts.rs`).
    fn touching_impacts(&mut self) {
        if !self.effects.has(Effect::Restitution) {
            return;
        }
        let Some(narrow) = self.narrow.as_ref() else {
            return;
        };
        let proxies = &self.proxies;
        let free = |i: usize| proxies.get(i).is_none_or(Option::is_none);
        self.counters.touching_impacts = self.touching.propagate(
            &narrow.manifolds,
            &mut self.bodies,
            self.settings.restitution_threshold,
            free,
        );
    }

    /// The contacts' preparation: each manifold between free bodies, one of them awake,
    /// becomes a constraint, stiffened with last step's stiffness and put in its colour's
    /// group while it is in cache (a lean step prepares it in the scratch constraint and keeps
    /// whole only what is solved one by one); each manifold with a tree link on a side becomes
    /// a tree contact.
    fn prepare_contacts(&mut self) -> Result<PreparedContacts, DynamicsError> {
        let batch = self.variants.batch_contacts;
        if batch {
            self.batches.begin(self.bodies.len());
        }
        let predicted = self.last_stiffness.filter(|_| self.variants.soft_contacts);
        let settings = self.contact_settings();
        // A world at rest that keeps its decision on fewer substeps reads its grouped
        // constraints from their lanes alone: they are prepared in cache and not kept.
        let lean = self.lean_step(self.settings.substeps.max(1), self.dt, predicted);
        let mut out = PreparedContacts {
            settings,
            predicted,
            lean,
            lean_rescales: false,
            follows: false,
        };
        self.tree_contacts.clear();
        let mut prepared = 0;
        let articulated = self.effects.has(Effect::Articulated);
        for (mi, m) in manifolds(&self.narrow).iter().enumerate() {
            let (a, b) = (m.a as usize, m.b as usize);
            let proxy = |i: usize| self.proxies.get(i).is_some_and(Option::is_some);
            if proxy(a) || proxy(b) {
                if articulated {
                    self.tree_contacts.prepare(
                        &self.bodies,
                        &self.proxies,
                        &mut self.articulated,
                        &self.link_poses,
                        m,
                        mi,
                        &out.settings,
                    )?;
                }
                continue;
            }
            if !(self.bodies.awake[a] || self.bodies.awake[b]) {
                continue;
            }
            // The last step's constraints are rewritten in place; a lean step prepares each
            // in the scratch constraint, in cache, instead.
            if prepared == self.constraints.len() {
                self.constraints.push(ContactConstraint::blank());
            }
            let c = if out.lean.is_some() {
                &mut self.scratch_constraint
            } else {
                &mut self.constraints[prepared]
            };
            c.prepare_in(&self.bodies, m, mi, &out.settings);
            out.follows |= c.follows_turn();
            // A lean step's stiffness is the predicted one.
            if let Some(k) = &out.predicted {
                c.stiffen(k);
            }
            let grouped = batch && self.batches.add(prepared, c);
            if let Some(lean) = &out.lean {
                let carried = m.impulse_substep;
                out.lean_rescales |= carried > 0.0 && carried != lean.substep;
                self.counters.lean_contacts += usize::from(grouped);
                // Kept whole where it is solved one by one; a grouped one's slot keeps its
                // index, and last step's constraint.
                if !grouped {
                    self.constraints[prepared] = self.scratch_constraint;
                }
            }
            prepared += 1;
        }
        if prepared > 0 {
            self.counters.mark(Stage::ContactSolve);
            if out.settings.rolling {
                self.counters.mark(Stage::RollingResistance);
            }
        }
        // Last step's constraints beyond this step's (all of them without collision).
        self.constraints.truncate(prepared);
        if batch {
            self.batches.finish();
        }
        Ok(out)
    }

    /// The joints prepared for substeps of `h` (s) (motors and limits integrate over the
    /// substep in force), and their forest; whether joints are solved.
    fn prepare_joints(&mut self, h: f64) -> bool {
        let joints_on = self.effects.has(Effect::Joints) && !self.joints.is_empty();
        if joints_on {
            self.counters.mark(Stage::JointSolve);
            for j in &mut self.joints {
                j.set_substep(h);
                j.prepare(&self.bodies);
            }
            self.joint_graph.build(&self.joints, &self.bodies);
        }
        joints_on
    }

    /// The step's displacements cleared, and the drives of the trees solved with the free
    /// bodies prepared; whether any tree is.
    fn begin_solve(&mut self) -> bool {
        for i in 0..self.bodies.len() {
            self.bodies.dp[i] = V3::zeros();
            self.bodies.dtheta[i] = V3::zeros();
        }
        // The links' poses through the substeps are read only by tree contacts.
        if !self.tree_contacts.contacts.is_empty() {
            for (now, start) in self.tree_poses.iter_mut().zip(&self.link_poses) {
                now.clone_from(start);
            }
        }
        let coupled = self.coupled_trees();
        if !self.tree_contacts.contacts.is_empty() {
            self.counters.mark(Stage::ContactSolve);
        }
        if coupled {
            for a in self.articulated.iter_mut() {
                a.prepare_drives();
            }
        }
        coupled
    }

    /// The plan of the substeps, decided once the contacts are known: how many (fewer at
    /// rest), the contacts' softness and the islands' extra substeps, the carried impulses
    /// and the groups, the forces over a substep, and whether the warm start is replayed.
    fn plan_substeps(
        &mut self,
        prepared: &PreparedContacts,
        joints_on: bool,
        coupled: bool,
    ) -> SubstepPlan {
        let (n_sub, lean_holds, prepared_again) = self.choose_substeps(prepared, coupled);
        let h = self.dt / n_sub as f64;
        let (soft, soft_static) =
            self.soften_contacts(prepared, (n_sub, h), lean_holds, prepared_again);
        let rescaled = self.carry_impulses_to_substeps(h, lean_holds);
        self.regroup_contacts(rescaled || prepared_again);
        let inv_h = 1.0 / h;
        let joint_soft = JointSoftness {
            each: Softness::new(
                self.settings.joint_hertz.min(0.25 * inv_h),
                self.settings.joint_damping_ratio,
                h,
            ),
            forest: JointSoftness::forest(h),
        };
        let forces = self.substep_forces(h);
        if self.fine_factor > 1 {
            // The coarse substeps move the other bodies only.
            self.awake_saved.clone_from(&self.bodies.awake);
            for (awake, &k) in self.bodies.awake.iter_mut().zip(&self.island_substeps.fine) {
                *awake &= k == 1;
            }
        }
        // Only the contacts change the free bodies' velocities in the solve, through rows
        // fixed for the step, and the pose stage leaves the velocities alone: the contacts'
        // warm start can be replayed per body.
        let replay = self.variants.replay_warm_start
            && n_sub > 1
            && !self.constraints.is_empty()
            && !prepared.follows
            && !joints_on
            && !coupled
            && self.tree_contacts.contacts.is_empty()
            && matches!(
                self.integrator(),
                IntegratorKind::SymplecticEuler | IntegratorKind::ImplicitGyroscopic
            );
        SubstepPlan {
            substeps: n_sub,
            h,
            inv_h,
            soft,
            soft_static,
            joint_soft,
            forces,
            joints_on,
            coupled,
            replay,
        }
    }

    /// The step's substeps (fewer where the world rests, [`Self::substeps_at_rest`]), whether
    /// a lean step holds (the world took the substeps it was prepared for and no carried
    /// impulse is rescaled), and whether its constraints were prepared again, whole, because
    /// it does not.
    fn choose_substeps(
        &mut self,
        prepared: &PreparedContacts,
        coupled: bool,
    ) -> (usize, bool, bool) {
        // What ran before with the step's own substep does not run at rest: joints and trees
        // keep the step's substeps, and continuous collision's sweep margin
        // (`½ |v| |ω| h dt`) is nil for bodies at rest.
        let n_sub = self.settings.substeps.max(1);
        let fewer = self.substeps_at_rest(n_sub, coupled);
        let lean_holds = prepared
            .lean
            .as_ref()
            .is_some_and(|l| fewer == l.substeps && !prepared.lean_rescales);
        let prepared_again = prepared.lean.is_some() && !lean_holds;
        if prepared_again {
            self.prepare_contacts_again(&prepared.settings);
        }
        (fewer.min(n_sub), lean_holds, prepared_again)
    }

    /// The contacts' softness on `substeps` of `h` (s): the soft step's stiffness by mass
    /// ratio (the constraints stiffened again only where it changed; islands that would lean
    /// take extra substeps, [`Self::plan_island_substeps`]), or rigid rows with a position
    /// bias. Returns the softness against moving and against fixed bodies.
    fn soften_contacts(
        &mut self,
        prepared: &PreparedContacts,
        (n_sub, h): (usize, f64),
        lean_holds: bool,
        prepared_again: bool,
    ) -> (Softness, Softness) {
        let inv_h = 1.0 / h;
        let at_rest = n_sub < self.settings.substeps.max(1);
        let (s, v) = (self.settings, self.variants);
        let hz = s.contact_hertz.min(v.contact_hertz_cap * inv_h);
        self.fine_factor = 1;
        if !v.soft_contacts {
            let rigid = Softness::rigid(v.contact_bias_rate.min(0.5 * inv_h));
            for (ci, c) in self.constraints.iter_mut().enumerate() {
                c.set_softness(rigid);
                self.batches.set_softness(ci, c);
            }
            return (rigid, rigid);
        }
        let stiffness = v.stiffness_on(&s, h, self.dt);
        // A lean step's lanes hold this stiffness already, and its constraints are not read.
        if prepared_again || (!lean_holds && prepared.predicted != Some(stiffness)) {
            for (ci, c) in self.constraints.iter_mut().enumerate() {
                c.stiffen(&stiffness);
                self.batches.set_softness(ci, c);
            }
        }
        self.last_stiffness = Some(stiffness);
        // A world that takes fewer substeps at rest leans within the tolerance at their
        // stiffness, and holds no island's factor: no island needs more.
        if !at_rest {
            self.plan_island_substeps(&stiffness, n_sub);
        }
        (
            Softness::new(hz, s.contact_damping_ratio, h),
            Softness::new(2.0 * hz, s.contact_damping_ratio, h),
        )
    }

    /// The groups filled as the constraints were prepared hold them as they are now, unless
    /// an island took extra substeps (its constraints go to their own groups, stiffer) or the
    /// constraints changed since (`changed`: carried impulses rescaled to a changed substep,
    /// or prepared again): then they are grouped again from the constraints.
    fn regroup_contacts(&mut self, changed: bool) {
        self.batched = self.variants.batch_contacts && !self.constraints.is_empty();
        if !self.batched {
            return;
        }
        if changed || self.fine_factor > 1 {
            let fine = &self.fine_constraint;
            self.batches
                .build_of(&self.constraints, self.bodies.len(), |ci| !fine[ci]);
            if self.fine_factor > 1 {
                self.fine_batches
                    .build_of(&self.constraints, self.bodies.len(), |ci| fine[ci]);
            }
        }
        self.counters.contact_colours = self.batches.colours;
        self.counters.contact_groups = self.batches.groups();
    }

    /// Gravity, gyroscopic terms and damping over a substep of `h` (s), as declared.
    fn substep_forces(&mut self, h: f64) -> FreeForces {
        let eff = self.effects;
        let gravity = if eff.has(Effect::Gravity) {
            self.counters.mark(Stage::Gravity);
            self.gravity
        } else {
            V3::zeros()
        };
        let gyro = eff.has(Effect::Gyroscopic);
        let damping = eff.has(Effect::Damping);
        if gyro {
            self.counters.mark(Stage::Gyroscopic);
        }
        if damping {
            self.counters.mark(Stage::Damping);
        }
        self.counters.mark(Stage::Integrate);
        FreeForces {
            gravity,
            gyroscopic: gyro,
            damping: damping.then(|| self.settings.damping_factors(h)),
        }
    }

    /// The substeps: velocities, the trees' velocity stage, the warm start, a solve with the
    /// position bias, positions, then a relax without it (Box2D v3's soft step).
    fn solve_substeps(&mut self, plan: &SubstepPlan) -> Result<(), DynamicsError> {
        let (n_sub, h) = (plan.substeps, plan.h);
        let eff = self.effects;
        for sub in 0..n_sub {
            self.integrator
                .integrate_velocities(&mut self.bodies, h, &plan.forces);
            self.substep_clock = (h, self.time + (sub + 1) as f64 * h);
            if plan.coupled {
                for a in self.articulated.iter_mut() {
                    if link_proxies::in_solve(eff, a) {
                        a.velocity_stage(h)?;
                        a.refresh_drive_responses()?;
                        self.counters.articulated_solves += 1;
                    }
                }
            }
            if plan.replay && sub > 0 {
                self.warm_start_replay.replay(&mut self.bodies);
            } else {
                if plan.replay {
                    self.warm_start_replay.mark(&self.bodies);
                }
                self.warm_start_contacts();
            }
            self.tree_contacts
                .warm_start(&mut self.bodies, &mut self.articulated);
            if plan.joints_on {
                for j in &self.joints {
                    j.warm_start(&mut self.bodies);
                }
            }
            let rev = sub % 2 == 1;
            self.solve_pass(
                plan,
                SolvePass {
                    use_bias: true,
                    reverse: rev,
                },
            );
            self.integrator.integrate_positions(&mut self.bodies, h);
            if plan.joints_on && self.joint_graph.usable() {
                self.joint_graph
                    .project_positions(&self.joints, &mut self.bodies);
            }
            if plan.coupled {
                let in_contact = !self.tree_contacts.contacts.is_empty();
                for (a, poses) in self.articulated.iter_mut().zip(&mut self.tree_poses) {
                    if link_proxies::in_solve(eff, a) {
                        a.position_stage(h);
                        if in_contact && a.has_shapes() {
                            a.model().body_poses_into(a.q(), poses);
                        }
                    }
                }
            }
            self.counters.solver_iterations += 1;
            if self.variants.relax_each_substep || sub + 1 == n_sub {
                self.solve_pass(
                    plan,
                    SolvePass {
                        use_bias: false,
                        reverse: !rev,
                    },
                );
                self.counters.solver_iterations += 1;
            }
            if plan.replay && sub + 1 < n_sub {
                self.warm_start_replay.record(&self.bodies);
            }
            if plan.coupled {
                for a in self.articulated.iter_mut() {
                    a.end_substep_drives();
                }
            }
            self.counters.substeps += 1;
        }
        Ok(())
    }

    /// The extra substeps of the islands that take them (`fine_factor` for each of the
    /// plan's), after the step's own.
    fn fine_island_substeps(&mut self, plan: &SubstepPlan) {
        if self.fine_factor <= 1 {
            return;
        }
        let h = plan.h / self.fine_factor as f64;
        let forces = FreeForces {
            damping: plan
                .forces
                .damping
                .map(|_| self.settings.damping_factors(h)),
            ..plan.forces
        };
        self.fine_substeps(plan.substeps * self.fine_factor, h, &forces);
    }

    /// After the solve: the groups' impulses back into the constraints where something reads
    /// them, restitution, and every contact's impulses stored into its manifold for the next
    /// step's warm start, accumulated over substeps of `h` (s).
    fn restitution_and_store(&mut self, h: f64) {
        let eff = self.effects;
        let restitution = eff.has(Effect::Restitution) && !self.constraints.is_empty();
        // Without restitution nothing reads the constraints' impulses after the solve: the
        // groups store theirs straight into the manifolds (below).
        let grouped_store = self.batched && !restitution && self.narrow.is_some();
        if self.batched && !grouped_store {
            self.batches.write_back(&mut self.constraints);
            if self.fine_factor > 1 {
                self.fine_batches.write_back(&mut self.constraints);
            }
        }
        if restitution {
            self.counters.mark(Stage::Restitution);
            let th = self.settings.restitution_threshold;
            for c in &mut self.constraints {
                if c.bounces() {
                    self.counters.restitution_constraints += 1;
                    c.restitution(&mut self.bodies, th);
                }
            }
        }
        if let Some(narrow) = self.narrow.as_mut() {
            let fine_h = h / self.fine_factor as f64;
            let store = |c: &ContactConstraint, fine: bool, manifolds: &mut [Manifold]| {
                let m = &mut manifolds[c.manifold];
                c.store(m);
                m.impulse_substep = if fine { fine_h } else { h };
            };
            if grouped_store {
                self.batches.store_impulses(&mut narrow.manifolds, h);
                for &ci in &self.batches.scalar {
                    store(&self.constraints[ci], false, &mut narrow.manifolds);
                }
                if self.fine_factor > 1 {
                    self.fine_batches
                        .store_impulses(&mut narrow.manifolds, fine_h);
                    for &ci in &self.fine_batches.scalar {
                        store(&self.constraints[ci], true, &mut narrow.manifolds);
                    }
                }
            } else {
                for (c, &fine) in self.constraints.iter().zip(&self.fine_constraint) {
                    store(c, fine, &mut narrow.manifolds);
                }
            }
        }
        if !self.tree_contacts.contacts.is_empty() {
            if eff.has(Effect::Restitution) {
                let th = self.settings.restitution_threshold;
                self.tree_contacts
                    .restitution(&mut self.bodies, &mut self.articulated, th);
            }
            if let Some(narrow) = self.narrow.as_mut() {
                self.tree_contacts.store(&mut narrow.manifolds, h);
            }
        }
    }

    /// The islands and sleeping, with the `sleeping` effect.
    fn update_islands(&mut self) {
        if let Some(islands) = self.islands.as_mut() {
            self.counters.mark(Stage::Islands);
            self.counters.islands = islands.update(
                &mut self.bodies,
                manifolds(&self.narrow),
                &self.joint_pairs,
                self.dt,
            );
        }
    }

    /// The articulated trees that do not touch the world (no shapes, or no `contacts`) and
    /// have no motors or limits: one step per tree per substep of `h` with the selected
    /// integrator (with `articulated`), prescribed coordinates landing on their trajectories
    /// at the substep's end.
    fn step_articulated(&mut self, h: f64) -> Result<(), DynamicsError> {
        if self.effects.has(Effect::Articulated) && !self.articulated.is_empty() {
            self.counters.mark(Stage::Articulated);
            let coupled = self.coupled_trees();
            let n_sub = self.settings.substeps.max(1);
            for a in &mut self.articulated {
                if coupled && link_proxies::in_solve(self.effects, a) {
                    continue; // stepped inside the constraint solve
                }
                a.prepare_drives();
                for sub in 0..n_sub {
                    a.step_until(h, self.time + (sub + 1) as f64 * h)?;
                    self.counters.articulated_solves += 1;
                }
                a.end_substep_drives();
            }
        }
        Ok(())
    }

    /// Whether a kinematic body has a non-zero velocity (it may wake sleeping bodies).
    pub(crate) fn kinematic_moving(&self) -> bool {
        (0..self.bodies.len()).any(|i| {
            self.bodies.kind[i] == BodyKind::Kinematic
                && (self.bodies.vel[i] != V3::zeros() || self.bodies.omega[i] != V3::zeros())
        })
    }

    /// Warm start of the contacts: the batches, then the constraints solved one by one.
    fn warm_start_contacts(&mut self) {
        if self.batched {
            self.batches.warm_start(&mut self.bodies);
            for &ci in &self.batches.scalar {
                self.constraints[ci].warm_start(&mut self.bodies);
            }
        } else {
            for (c, &fine) in self.constraints.iter().zip(&self.fine_constraint) {
                if !fine {
                    c.warm_start(&mut self.bodies);
                }
            }
        }
    }

    /// One pass over the joints, the contacts, the trees' drives and their contacts.
    fn solve_pass(&mut self, plan: &SubstepPlan, pass: SolvePass) {
        let (inv_h, max_push) = (plan.inv_h, self.settings.max_push_velocity);
        if plan.joints_on {
            self.solve_joints(&plan.joint_soft, pass.use_bias);
        }
        if self.batched {
            self.batches.solve(&mut self.bodies, inv_h, max_push, pass);
            for &ci in &self.batches.scalar {
                self.constraints[ci].solve(&mut self.bodies, inv_h, max_push, pass);
            }
        } else {
            for (c, &fine) in self.constraints.iter_mut().zip(&self.fine_constraint) {
                if !fine {
                    c.solve(&mut self.bodies, inv_h, max_push, pass);
                }
            }
        }
        // The force-limited motors before the tree contacts, so that a servo pressing a
        // link onto a body ends the pass with the contact's answer (`DriveGroup`).
        self.solve_tree_drives(&plan.soft_static, pass, DriveGroup::Motors);
        if !self.tree_contacts.contacts.is_empty() {
            self.tree_contacts.solve(
                &mut self.bodies,
                &mut self.articulated,
                &self.tree_poses,
                &plan.soft,
                &plan.soft_static,
                inv_h,
                max_push,
                pass,
            );
        }
        // Limits and prescribed motion last: each pass ends on their bounds and trajectories.
        self.solve_tree_drives(&plan.soft_static, pass, DriveGroup::Hard);
    }

    /// The contact rows' settings from the scene's effects and the solver settings.
    pub(super) fn contact_settings(&self) -> ContactSettings {
        let eff = &self.effects;
        ContactSettings {
            friction: eff.has(Effect::Friction),
            restitution: eff.has(Effect::Restitution),
            rolling: eff.has(Effect::RollingResistance),
            restitution_threshold: self.settings.restitution_threshold,
            max_push_velocity: self.settings.max_push_velocity,
            up: if eff.has(Effect::Gravity) {
                -self.gravity.try_normalize(0.0).unwrap_or_else(V3::zeros)
            } else {
                V3::zeros()
            },
        }
    }

    /// One pass over the joints: every constraint block at once when they form a forest,
    /// one joint after another otherwise; then the driven coordinates.
    fn solve_joints(&mut self, soft: &JointSoftness, use_bias: bool) {
        for j in &mut self.joints {
            j.begin_pass(&self.bodies, use_bias);
        }
        if use_bias {
            self.joint_graph.factor(&self.joints, &self.bodies);
        }
        if self.joint_graph.usable() {
            let block = FreeJoint::block_softness(&soft.forest, use_bias);
            self.joint_graph
                .solve_blocks(&mut self.joints, &mut self.bodies, block, use_bias);
            for j in &mut self.joints {
                j.solve_driven(&mut self.bodies, &soft.each, use_bias);
            }
        } else {
            for j in &mut self.joints {
                j.solve_block(&mut self.bodies, &soft.each, use_bias);
                j.solve_driven(&mut self.bodies, &soft.each, use_bias);
            }
        }
    }

    /// One pass over the drives of `group` of the trees stepped inside the solve.
    fn solve_tree_drives(&mut self, soft: &Softness, pass: SolvePass, group: DriveGroup) {
        if self.coupled_trees() {
            let (h, t_end) = self.substep_clock;
            let effects = self.effects;
            for a in self.articulated.iter_mut() {
                // Trees that step on their own (prescribed motion only) are not in the solve.
                if a.has_drives() && link_proxies::in_solve(effects, a) {
                    a.solve_drives(h, t_end, soft, pass, group);
                }
            }
        }
    }
}

/// Whether manifold `m` is solved as a contact constraint between free bodies: neither body
/// is a tree link's proxy (those contacts act on the tree), and one of them is awake.
pub(super) fn solved_between_free_bodies(
    bodies: &BodySet,
    proxies: &[Option<Proxy>],
    m: &Manifold,
) -> bool {
    let (a, b) = (m.a as usize, m.b as usize);
    let proxy = |i: usize| proxies.get(i).is_some_and(Option::is_some);
    !(proxy(a) || proxy(b)) && (bodies.awake[a] || bodies.awake[b])
}

/// The narrow phase's manifolds (none without collision).
pub(super) fn manifolds(narrow: &Option<NarrowPhase>) -> &[Manifold] {
    narrow.as_ref().map_or(&[][..], |n| &n.manifolds[..])
}

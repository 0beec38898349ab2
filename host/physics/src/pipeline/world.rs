//! The world: bodies, joints, articulated trees and the step pipeline built from the declared
//! effects. A stage whose effect is not declared has no state (`None`) and is never entered.

use super::articulated::ArticulatedSystem;
use super::handles::{BodyHandle, JointHandle, Slots};
use super::islands::Islands;
use super::{Effect, Effects, FreeForces, FreeIntegrator, IntegratorKind, Stage, StepCounters};
use crate::dynamics::solver::{
    ContactBatches, ContactConstraint, ContactSettings, ContactStiffness, FreeJoint, JointGraph,
    JointSoftness, Softness, SolvePass,
};
use crate::dynamics::{BodyKind, BodySet, DynamicsError};
use crate::geometry::{BodyMotion, BroadPhase, Manifold, NarrowPhase, V3};

#[path = "ccd.rs"]
mod ccd;

#[path = "step_guard.rs"]
mod step_guard;

#[path = "island_substeps.rs"]
pub(crate) mod island_substeps;
use island_substeps::{IslandSubsteps, StepLoads};

#[path = "resting_substeps.rs"]
mod resting_substeps;
use resting_substeps::{RestingSubsteps, RestingWorld};

#[path = "sink_hold.rs"]
pub(crate) mod sink_hold;
use sink_hold::SinkHold;

#[path = "warm_start_replay.rs"]
mod warm_start_replay;
use warm_start_replay::WarmStartReplay;

#[path = "link_proxies.rs"]
mod link_proxies;

#[path = "world_bodies.rs"]
mod world_bodies;

#[path = "world_joints.rs"]
pub(crate) mod world_joints;
pub use world_bodies::{BodyMut, BodyRef};

#[path = "world_trees.rs"]
mod world_trees;

#[path = "world_state.rs"]
mod world_state;

#[path = "world_contacts.rs"]
mod world_contacts;
pub use world_contacts::Contact;

use super::drives::DriveGroup;
use super::tree_contacts::{Proxy, TreeContacts, TreeDisplacements};

/// Solver and collision settings (SI units).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SolverSettings {
    /// Substeps per step.
    pub substeps: usize,
    /// Relax (solve without position bias) after every substep, as Box2D v3 does (default).
    /// When false, only after the last substep: `substeps + 1` passes instead of
    /// `2 × substeps` (measured: towers-1120 5.6 → 3.7 ms/step, same sink, lateral drift
    /// 2.6 → 1.1 mm), but the push-out velocity of the intermediate substeps stays in the
    /// bodies: a box dropped 8.5 m onto a tower bounces off it by more than a metre
    /// (`tests/gating.rs::a_falling_box_wakes_a_sleeping_tower` fails), so it is off.
    pub relax_each_substep: bool,
    /// Contact stiffness (Hz); capped at `contact_hertz_cap` × the substep rate.
    pub contact_hertz: f64,
    /// Largest contact stiffness as a fraction of the substep rate (–); Box2D v3's quarter.
    /// Stiffer contacts sink less but make stacks lean (README, settings sweep).
    pub contact_hertz_cap: f64,
    /// Contact damping ratio (–).
    pub contact_damping_ratio: f64,
    /// Stiffness of a contact between two moving bodies of equal mass, as a multiple of
    /// `contact_hertz` (–), within the same cap; it falls to `contact_hertz` at a mass ratio of
    /// 10 (`ContactStiffness`). 1.5 holds a tower of 40 equal boxes within 1 mm for 20 s at
    /// the default step (120 Hz lets it lean 12 cm), while a 1 g box under 1 kg keeps the
    /// 120 Hz it needs.
    pub even_mass_stiffening: f64,
    /// Soft contacts (Box2D soft step: springs of `contact_hertz`) when true; rigid contacts
    /// with a position bias of `contact_bias_rate` when false (soft is the default).
    pub soft_contacts: bool,
    /// Position error to push-out speed (1/s) of rigid contacts.
    pub contact_bias_rate: f64,
    /// Stiffness (Hz) of the position correction of joints solved one after another: those
    /// that close a loop among moving bodies. A forest of joints is solved exactly, as one
    /// system, and corrects as stiffly as the substep allows (a quarter of its rate).
    pub joint_hertz: f64,
    /// Damping ratio (–) of the joints solved one after another.
    pub joint_damping_ratio: f64,
    /// Contacts are kept up to this separation (m) — speculative distance.
    pub speculative_distance: f64,
    /// Largest push-out speed (m/s).
    pub max_push_velocity: f64,
    /// Approach speed below which restitution is not applied (m/s).
    pub restitution_threshold: f64,
    /// Linear damping rate (1/s), with the `damping` effect.
    pub linear_damping: f64,
    /// Angular damping rate (1/s), with the `damping` effect.
    pub angular_damping: f64,
    /// Let a world whose free bodies all rest take a half, a third, a quarter or a sixth of
    /// `substeps` (the fewest that hold) when its contacts, at the stiffness of those fewer
    /// substeps, hold it within 5 mm of sink and 1 mm of lean, and no body stands alone on
    /// another (a column keeps `substeps`: it would rock on its single contact)
    /// (`pipeline/resting_substeps.rs`; default). Off, every step takes `substeps`, as a sweep
    /// over them needs.
    pub fewer_substeps_at_rest: bool,
    /// Solve the contacts four at a time (`ContactBatches`: graph colouring, one constraint
    /// per lane); false solves them one by one in manifold order (the same rows, another
    /// Gauss–Seidel order).
    pub batch_contacts: bool,
    /// From a step's second substep on, warm start the contacts by adding back each body's
    /// change of velocity from the contacts over the substep before, where only contacts
    /// change the free bodies' velocities in the solve (no joints or articulated trees; the
    /// semi-implicit Euler integrators): the same impulses up to rounding, for a pass over
    /// the bodies instead of one over the contacts (`pipeline/warm_start_replay.rs`; default).
    pub replay_warm_start: bool,
    /// Hold back the sink of loaded contacts between free bodies: each step, a share of a
    /// contact's overlap beyond the slop (the step over a quarter second) is added to the
    /// overlap it is solved as if it had, so a resting stack stands at its slop whatever the
    /// contacts' stiffness (`pipeline/sink_hold.rs`; default). Off, a soft contact settles at
    /// the overlap its load asks, `F / (m ω²)`.
    pub hold_sink: bool,
    /// Keep the broad phase's pairs while every body's box stays within 5 cm of where the
    /// grid was built, taking from them the pairs whose boxes overlap now
    /// (`geometry/broad_phase.rs`; default). Off, the grid is built every step: the same
    /// pairs.
    pub keep_broad_phase_pairs: bool,
    /// A world at rest that keeps its decision on fewer substeps prepares the contact
    /// constraints it solves four at a time straight into their lanes, without keeping each
    /// whole (default): the same bits, without writing some 1.6 kB per contact. Off, every
    /// constraint is kept.
    pub lean_resting_contacts: bool,
}

impl SolverSettings {
    /// The contacts' stiffness on substeps of `h` (s): `contact_hertz` within the cap,
    /// `even_mass_stiffening` times that between equal masses, twice it against a body that
    /// does not move.
    fn contact_stiffness(&self, h: f64) -> ContactStiffness {
        let cap = self.contact_hertz_cap * (1.0 / h);
        let hz = self.contact_hertz.min(cap);
        ContactStiffness {
            hertz: hz,
            even_hertz: (self.even_mass_stiffening * hz).min(cap).max(hz),
            static_hertz: 2.0 * hz,
            damping_ratio: self.contact_damping_ratio,
            substep: h,
        }
    }

    /// The contacts' stiffness on substeps of `h` (s) in a step of `dt` (s):
    /// [`Self::contact_stiffness`], except that substeps longer than the step's own (a world
    /// at rest on fewer, `pipeline/resting_substeps.rs`) keep a contact against a body that
    /// does not move within [`resting_substeps::RESTING_STATIC_CAP`] of their rate.
    fn stiffness_on(&self, h: f64, dt: f64) -> ContactStiffness {
        let mut k = self.contact_stiffness(h);
        if h > 1.5 * dt / self.substeps as f64 {
            k.static_hertz = k.static_hertz.min(resting_substeps::RESTING_STATIC_CAP / h);
        }
        k
    }

    /// The unit vector against `gravity` (m/s², world) where the contacts hold their sink
    /// (soft contacts under declared gravity, [`Self::hold_sink`]; `pipeline/sink_hold.rs`),
    /// `None` where they do not.
    fn hold_up(&self, effects: &Effects, gravity: &V3) -> Option<V3> {
        let g = gravity.norm();
        (self.hold_sink && self.soft_contacts && effects.has(Effect::Gravity) && g > 0.0)
            .then(|| -gravity / g)
    }

    /// The factors `(linear, angular)` (–) the `damping` effect scales the velocities by over
    /// a substep of `h` (s): `1 / (1 + h c)` for each damping rate `c`.
    fn damping_factors(&self, h: f64) -> (f64, f64) {
        (
            1.0 / (1.0 + h * self.linear_damping),
            1.0 / (1.0 + h * self.angular_damping),
        )
    }
}

impl Default for SolverSettings {
    fn default() -> Self {
        Self {
            substeps: 12,
            relax_each_substep: true,
            contact_hertz: 120.0,
            contact_hertz_cap: 0.25,
            contact_damping_ratio: 10.0,
            even_mass_stiffening: 1.5,
            soft_contacts: true,
            contact_bias_rate: 20.0,
            joint_hertz: 60.0,
            joint_damping_ratio: 5.0,
            speculative_distance: 0.02,
            max_push_velocity: 3.0,
            restitution_threshold: 0.5,
            linear_damping: 0.0,
            angular_damping: 0.0,
            batch_contacts: true,
            fewer_substeps_at_rest: true,
            replay_warm_start: true,
            hold_sink: true,
            keep_broad_phase_pairs: true,
            lean_resting_contacts: true,
        }
    }
}

/// A step whose grouped contact constraints live in their lanes alone
/// (`World::lean_step`): what it was prepared for.
#[derive(Clone, Copy, Debug)]
struct ContactLeanStep {
    /// The substeps the resting decision keeps.
    substeps: usize,
    /// Their length (s).
    substep: f64,
}

/// A simulated world.
pub struct World {
    /// The rigid bodies.
    pub(crate) bodies: BodySet,
    /// Declared effects.
    pub(crate) effects: Effects,
    /// Step (s).
    pub(crate) dt: f64,
    /// Gravity (m/s², world); applied only with the `gravity` effect.
    pub(crate) gravity: V3,
    /// Solver settings.
    pub(crate) settings: SolverSettings,
    /// Joints between free bodies.
    pub(crate) joints: Vec<FreeJoint>,
    /// The joints' forest, solved as one system when the joints close no loop.
    pub(crate) joint_graph: JointGraph,
    /// Articulated trees.
    pub(crate) articulated: Vec<ArticulatedSystem>,
    /// Counters of the last step.
    pub(crate) counters: StepCounters,
    /// Simulated time (s).
    pub(crate) time: f64,
    /// The integrator of the free bodies (and, through [`World::set_integrator`], of the
    /// articulated trees).
    integrator: FreeIntegrator,
    broad: Option<BroadPhase>,
    narrow: Option<NarrowPhase>,
    islands: Option<Islands>,
    constraints: Vec<ContactConstraint>,
    joint_pairs: Vec<(usize, usize)>,
    excluded_pairs: Vec<u64>,
    batches: ContactBatches,
    batched: bool,
    /// Islands whose contacts would lean take extra substeps (`island_substeps.rs`).
    island_substeps: IslandSubsteps,
    /// A world at rest takes fewer substeps (`resting_substeps.rs`).
    resting_substeps: RestingSubsteps,
    /// The resting contacts' sink held back (`sink_hold.rs`).
    sink_hold: SinkHold,
    /// Substeps of those islands per substep of the step (1: none this step).
    fine_factor: usize,
    /// The soft contacts' stiffness of the last step, which each constraint takes as it is
    /// prepared: a world that keeps its substeps keeps it, and its constraints are not
    /// visited again to be stiffened.
    last_stiffness: Option<ContactStiffness>,
    /// The constraint prepared last where the step's constraints are not kept
    /// (`ContactLeanStep`): its lane is filled from here, in cache.
    scratch_constraint: ContactConstraint,
    /// Per constraint: whether it belongs to such an island.
    fine_constraint: Vec<bool>,
    /// The contacts of those islands, coloured and grouped.
    fine_batches: ContactBatches,
    /// The contacts' change of each body's velocity over the last substep.
    warm_start_replay: WarmStartReplay,
    /// The bodies' `awake` flags, kept while the extra substeps move only their islands.
    awake_saved: Vec<bool>,
    /// Checks before and after each step, and the snapshot a failed step is rolled back to.
    guard: step_guard::StepGuard,
    /// For each body, the tree link it stands for (a proxy), if any.
    proxies: Vec<Option<Proxy>>,
    /// Contacts with a tree link on a side, this step.
    tree_contacts: TreeContacts,
    /// Per tree, `Σ h q̇` over the step's substeps so far.
    tree_dq: TreeDisplacements,
    /// Per tree, the link poses at the start of the step.
    link_poses: Vec<Vec<crate::algebra::SE3<f64>>>,
    /// Per tree, the velocity its motors reach in the step's first substep (empty: none).
    predicted_qd: Vec<Vec<f64>>,
    /// The substep (s) and the time at its end (s), for the drives' rows.
    substep_clock: (f64, f64),
    /// Body handles ↔ storage indices.
    body_slots: Slots,
    /// Joint handles ↔ indices into `joints`.
    joint_slots: Slots,
    /// Bodies were inserted or removed since the broad phase sized its grid.
    broad_dirty: bool,
}

impl World {
    /// A world for `bodies` with the declared `effects`; the stages are built here.
    pub(crate) fn new(
        bodies: BodySet,
        effects: Effects,
        dt: f64,
        gravity: V3,
        settings: SolverSettings,
    ) -> Self {
        let contacts = effects.has(Effect::Contacts);
        let broad = contacts.then(|| BroadPhase::new(&bodies.shape));
        let mut body_slots = Slots::default();
        for _ in 0..bodies.len() {
            body_slots.insert::<BodyHandle>();
        }
        Self {
            broad,
            narrow: contacts.then(NarrowPhase::default),
            islands: effects.has(Effect::Sleeping).then(Islands::default),
            bodies,
            effects,
            dt,
            gravity,
            settings,
            joints: Vec::new(),
            joint_graph: JointGraph::default(),
            articulated: Vec::new(),
            counters: StepCounters::default(),
            time: 0.0,
            integrator: FreeIntegrator::default(),
            constraints: Vec::new(),
            joint_pairs: Vec::new(),
            excluded_pairs: Vec::new(),
            batches: ContactBatches::default(),
            batched: false,
            island_substeps: IslandSubsteps::default(),
            resting_substeps: RestingSubsteps::default(),
            sink_hold: SinkHold::default(),
            fine_factor: 1,
            last_stiffness: None,
            scratch_constraint: ContactConstraint::blank(),
            fine_constraint: Vec::new(),
            fine_batches: ContactBatches::default(),
            awake_saved: Vec::new(),
            warm_start_replay: WarmStartReplay::default(),
            guard: step_guard::StepGuard::default(),
            proxies: Vec::new(),
            tree_contacts: TreeContacts::default(),
            tree_dq: Vec::new(),
            link_poses: Vec::new(),
            predicted_qd: Vec::new(),
            substep_clock: (0.0, 0.0),
            body_slots,
            joint_slots: Slots::default(),
            broad_dirty: false,
        }
    }

    /// The selected integrator.
    pub fn integrator(&self) -> IntegratorKind {
        self.integrator.kind
    }

    /// Selects the integrator of the free bodies and of every articulated tree (trees added
    /// later take it too). See [`IntegratorKind`] for which kinds apply to trees.
    pub fn set_integrator(&mut self, kind: IntegratorKind) {
        self.integrator = FreeIntegrator::new(kind);
        for a in &mut self.articulated {
            a.integrator = kind;
        }
    }

    /// Adds an articulated tree; it takes the world's integrator. Links with shapes
    /// ([`ArticulatedSystem::with_link_shape`]) get a proxy body each (a kinematic body named
    /// after the link, posed from the tree), through which they touch the other bodies.
    pub(crate) fn add_articulated(&mut self, mut system: ArticulatedSystem) {
        system.integrator = self.integrator.kind;
        self.tree_dq.push(vec![0.0; system.qd.len()]);
        self.link_poses.push(system.link_poses());
        self.articulated.push(system);
        self.add_link_proxies(self.articulated.len() - 1);
    }

    /// Adds a joint (contacts between its two bodies are disabled).
    pub(crate) fn add_joint(&mut self, j: FreeJoint) -> JointHandle {
        let (a, b) = (j.a.min(j.b), j.a.max(j.b));
        self.joint_pairs.push((j.a, j.b));
        self.excluded_pairs.push(((a as u64) << 32) | b as u64);
        self.excluded_pairs.sort_unstable();
        self.joints.push(j);
        self.joint_slots.insert()
    }

    /// Whether the world has a broad phase (the `contacts` effect).
    pub fn has_broad_phase(&self) -> bool {
        self.broad.is_some()
    }

    /// The current contact manifolds (empty without contacts).
    pub(crate) fn manifolds(&self) -> &[crate::geometry::Manifold] {
        self.narrow.as_ref().map_or(&[], |n| &n.manifolds)
    }

    /// Deepest overlap among the manifolds (m), 0 when none.
    pub fn max_penetration(&self) -> f64 {
        self.manifolds()
            .iter()
            .map(|m| -m.min_separation())
            .fold(0.0, f64::max)
    }

    /// Kinetic energy plus gravitational potential (J) of the free bodies and the trees.
    pub fn energy(&self) -> f64 {
        let mut e = self.bodies.kinetic_energy();
        if self.effects.has(Effect::Gravity) {
            for i in 0..self.bodies.len() {
                if self.bodies.kind[i] == BodyKind::Dynamic {
                    e -= self.bodies.mass(i) * self.gravity.dot(&self.bodies.pos[i]);
                }
            }
        }
        e + self.articulated.iter().map(|a| a.energy()).sum::<f64>()
    }

    /// One step of `dt`, guarded (`pipeline/step_guard.rs`): state the step cannot use
    /// (`dt` ≤ 0 or not finite, non-finite gravity, a dynamic body of mass ≤ 0, NaN or ∞, a
    /// non-finite size, a huge or non-finite pose or velocity) is an error before anything
    /// moves; a step that makes a body's or a tree's state non-finite returns
    /// [`DynamicsError::NonFinite`] (or `NonFiniteTree`) naming it, and the world is put
    /// back as it was before the step (the contact warm-start cache is cleared).
    pub fn step(&mut self) -> Result<(), DynamicsError> {
        self.guard_before_step()?;
        let result = self.step_unguarded();
        self.guard_after_step(result)
    }

    /// One step of `dt`, unchecked.
    fn step_unguarded(&mut self) -> Result<(), DynamicsError> {
        self.counters.reset();
        let eff = self.effects;
        let dt = self.dt;
        let mut n_sub = self.settings.substeps.max(1);
        let mut h = dt / n_sub as f64;
        let mut inv_h = 1.0 / h;
        self.counters.awake_bodies = self.bodies.awake.iter().filter(|a| **a).count();
        if self.islands.is_some() && self.counters.awake_bodies == 0 && !self.kinematic_moving() {
            // Everything sleeps and nothing can wake it: the free bodies' step is empty.
            self.step_articulated(h)?;
            self.time += dt;
            return Ok(());
        }
        if eff.has(Effect::ContinuousCollision) {
            self.predict_motor_velocities(h)?;
        }
        self.sync_link_proxies(true);
        self.bodies.update_world_inertia();

        // Collision.
        if self.broad_dirty {
            self.broad_dirty = false;
            if self.broad.is_some() {
                self.broad = Some(BroadPhase::new(&self.bodies.shape));
            }
        }
        let mut prepared = 0;
        // Each constraint is coloured and its lane filled as soon as it is prepared, while it
        // is in cache (`ContactBatches::add`).
        let batch = self.settings.batch_contacts;
        if batch {
            self.batches.begin(self.bodies.len());
        }
        let predicted = self.last_stiffness.filter(|_| self.settings.soft_contacts);
        let settings = self.contact_settings();
        // A world at rest that keeps its decision on fewer substeps reads its grouped
        // constraints from their lanes alone: they are prepared in cache and not kept.
        let lean = self.lean_step(n_sub, dt, predicted);
        // Whether a carried impulse must be rescaled to this step's substep.
        let mut lean_rescales = false;
        // Whether a contact follows a round part's turn: its rows change within the step.
        let mut follows = false;
        self.tree_contacts.clear();
        if let (Some(broad), Some(narrow)) = (self.broad.as_mut(), self.narrow.as_mut()) {
            let ccd = eff.has(Effect::ContinuousCollision);
            let spec = self.settings.speculative_distance;
            let b = &mut self.bodies;
            for i in 0..b.len() {
                let moving = b.awake[i] || b.kind[i] == BodyKind::Kinematic;
                if !moving && b.kind[i] == BodyKind::Dynamic {
                    continue; // sleeping: box unchanged
                }
                let mut margin = spec;
                if ccd && moving {
                    margin += dt * b.sweep_speed(i);
                }
                b.aabb[i] = b.shape[i].aabb(&b.rot[i], &b.pos[i]).loosened(margin);
            }
            self.counters.mark(Stage::BroadPhase);
            if ccd {
                self.counters.mark(Stage::ContinuousCollision);
            }
            self.counters.broad_phase_tests = broad.update(
                &b.collision_view(),
                &self.excluded_pairs,
                self.settings.keep_broad_phase_pairs,
            );
            self.counters.broad_phase_pairs = broad.pairs.len();
            let bodies = &*b;
            let motion = ccd.then_some(BodyMotion {
                dt,
                vel: &bodies.vel,
                omega: &bodies.omega,
            });
            let mut nc = narrow.update(&bodies.collision_view(), &broad.pairs, spec, motion);
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
                let (m, p) = ccd::filter_manifolds(&mut narrow.manifolds, bodies, &sweep);
                nc.manifolds -= m;
                nc.contacts -= p;
            }
            self.counters.mark(Stage::NarrowPhase);
            self.counters.pairs_tested = nc.pairs_tested;
            self.counters.manifolds_refreshed = nc.refreshed;
            self.counters.manifolds = nc.manifolds;
            self.counters.contacts = nc.contacts;
            self.counters.unsupported_pairs = nc.unsupported;
            let hold_up = self.settings.hold_up(&self.effects, &self.gravity);
            if let Some(up) = &hold_up {
                let (bodies, proxies) = (&self.bodies, &self.proxies);
                let solved = |m: &Manifold| solved_between_free_bodies(bodies, proxies, m);
                self.sink_hold
                    .update(&mut narrow.manifolds, solved, (bodies.len(), dt, spec), up);
            }
            for (mi, m) in narrow.manifolds.iter().enumerate() {
                let (a, b) = (m.a as usize, m.b as usize);
                let proxy = |i: usize| self.proxies.get(i).is_some_and(Option::is_some);
                if proxy(a) || proxy(b) {
                    if eff.has(Effect::Articulated) {
                        self.tree_contacts.prepare(
                            &self.bodies,
                            &self.proxies,
                            &mut self.articulated,
                            &self.link_poses,
                            m,
                            mi,
                            &settings,
                        )?;
                    }
                } else if self.bodies.awake[a] || self.bodies.awake[b] {
                    // The last step's constraints are rewritten in place; a lean step
                    // prepares each in the scratch constraint, in cache, instead.
                    if prepared == self.constraints.len() {
                        self.constraints.push(ContactConstraint::blank());
                    }
                    let c = if lean.is_some() {
                        &mut self.scratch_constraint
                    } else {
                        &mut self.constraints[prepared]
                    };
                    c.prepare_in(&self.bodies, m, mi, &settings);
                    follows |= c.follows_turn();
                    // A lean step's stiffness is the predicted one.
                    if let Some(k) = &predicted {
                        c.stiffen(k);
                    }
                    let grouped = batch && self.batches.add(prepared, c);
                    if let Some(lean) = &lean {
                        let carried = m.impulse_substep;
                        lean_rescales |= carried > 0.0 && carried != lean.substep;
                        self.counters.lean_contacts += usize::from(grouped);
                        // Kept whole where it is solved one by one; a grouped one's slot
                        // keeps its index, and last step's constraint.
                        if !grouped {
                            self.constraints[prepared] = self.scratch_constraint;
                        }
                    }
                    prepared += 1;
                }
            }
            if prepared > 0 {
                self.counters.mark(Stage::ContactSolve);
                if settings.rolling {
                    self.counters.mark(Stage::RollingResistance);
                }
            }
        }
        // Last step's constraints beyond this step's (all of them without collision).
        self.constraints.truncate(prepared);
        if batch {
            self.batches.finish();
        }
        let joints_on = eff.has(Effect::Joints) && !self.joints.is_empty();
        if joints_on {
            self.counters.mark(Stage::JointSolve);
            for j in &mut self.joints {
                // Motors and limits integrate over the substep in force now.
                j.set_substep(h);
                j.prepare(&self.bodies);
            }
            self.joint_graph.build(&self.joints, &self.bodies);
        }
        for i in 0..self.bodies.len() {
            self.bodies.dp[i] = V3::zeros();
            self.bodies.dtheta[i] = V3::zeros();
        }
        for dq in &mut self.tree_dq {
            dq.iter_mut().for_each(|x| *x = 0.0);
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

        // Decided once the contacts are known. What ran before with the step's own substep
        // does not run at rest: joints and trees keep the step's substeps, and continuous
        // collision's sweep margin (`½ |v| |ω| h dt`) is nil for bodies at rest.
        let fewer = self.substeps_at_rest(n_sub, coupled);
        let at_rest = fewer < n_sub;
        // The lean step holds only where the world took the substeps it was prepared for and
        // nothing rescales a carried impulse; otherwise the constraints are prepared again,
        // whole, from the same bodies and manifolds, and grouped and stiffened from them.
        let lean_holds = lean
            .as_ref()
            .is_some_and(|l| fewer == l.substeps && !lean_rescales);
        let prepared_again = lean.is_some() && !lean_holds;
        if prepared_again {
            self.prepare_contacts_again(&settings);
        }
        if at_rest {
            n_sub = fewer;
            h = dt / n_sub as f64;
            inv_h = 1.0 / h;
        }
        let hz = self
            .settings
            .contact_hertz
            .min(self.settings.contact_hertz_cap * inv_h);
        let (soft, soft_static) = if self.settings.soft_contacts {
            (
                Softness::new(hz, self.settings.contact_damping_ratio, h),
                Softness::new(2.0 * hz, self.settings.contact_damping_ratio, h),
            )
        } else {
            let rigid = Softness::rigid(self.settings.contact_bias_rate.min(0.5 * inv_h));
            (rigid, rigid)
        };
        self.fine_factor = 1;
        if self.settings.soft_contacts {
            let stiffness = self.settings.stiffness_on(h, dt);
            // A lean step's lanes hold this stiffness already, and its constraints are not read.
            if prepared_again || (!lean_holds && predicted != Some(stiffness)) {
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
        } else {
            for (ci, c) in self.constraints.iter_mut().enumerate() {
                c.set_softness(soft);
                self.batches.set_softness(ci, c);
            }
        }
        let rescaled = self.carry_impulses_to_substeps(h, lean_holds);
        self.batched = batch && !self.constraints.is_empty();
        // The groups filled as the constraints were prepared hold them as they are now,
        // unless an island took extra substeps (its constraints go to their own groups,
        // stiffer) or carried impulses were rescaled to a changed substep: then they are
        // grouped again from the constraints.
        if self.batched && (rescaled || self.fine_factor > 1 || prepared_again) {
            let fine = &self.fine_constraint;
            self.batches
                .build_of(&self.constraints, self.bodies.len(), |ci| !fine[ci]);
            if self.fine_factor > 1 {
                self.fine_batches
                    .build_of(&self.constraints, self.bodies.len(), |ci| fine[ci]);
            }
        }
        if self.batched {
            self.counters.contact_colours = self.batches.colours;
            self.counters.contact_groups = self.batches.groups();
        }
        let joint_soft = JointSoftness {
            each: Softness::new(
                self.settings.joint_hertz.min(0.25 * inv_h),
                self.settings.joint_damping_ratio,
                h,
            ),
            forest: JointSoftness::forest(h),
        };
        let gravity = if eff.has(Effect::Gravity) {
            self.counters.mark(Stage::Gravity);
            self.gravity
        } else {
            V3::zeros()
        };
        let gyro = eff.has(Effect::Gyroscopic);
        let damping = eff.has(Effect::Damping);
        let forces = FreeForces {
            gravity,
            gyroscopic: gyro,
            damping: damping.then(|| self.settings.damping_factors(h)),
        };
        if gyro {
            self.counters.mark(Stage::Gyroscopic);
        }
        if damping {
            self.counters.mark(Stage::Damping);
        }
        self.counters.mark(Stage::Integrate);
        let max_push = self.settings.max_push_velocity;
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
        let replay = self.settings.replay_warm_start
            && n_sub > 1
            && !self.constraints.is_empty()
            && !follows
            && !joints_on
            && !coupled
            && self.tree_contacts.contacts.is_empty()
            && matches!(
                self.integrator(),
                IntegratorKind::SymplecticEuler | IntegratorKind::ImplicitGyroscopic
            );
        for sub in 0..n_sub {
            self.integrator
                .integrate_velocities(&mut self.bodies, h, &forces);
            self.substep_clock = (h, self.time + (sub + 1) as f64 * h);
            if coupled {
                for a in self.articulated.iter_mut() {
                    if link_proxies::in_solve(eff, a) {
                        a.velocity_stage(h)?;
                        a.refresh_drive_responses()?;
                        self.counters.articulated_solves += 1;
                    }
                }
            }
            if replay && sub > 0 {
                self.warm_start_replay.replay(&mut self.bodies);
            } else {
                if replay {
                    self.warm_start_replay.mark(&self.bodies);
                }
                self.warm_start_contacts();
            }
            self.tree_contacts
                .warm_start(&mut self.bodies, &mut self.articulated);
            if joints_on {
                for j in &self.joints {
                    j.warm_start(&mut self.bodies);
                }
            }
            let rev = sub % 2 == 1;
            let solve = SolvePass {
                use_bias: true,
                reverse: rev,
            };
            self.solve_pass(
                &soft,
                &soft_static,
                &joint_soft,
                inv_h,
                max_push,
                joints_on,
                solve,
            );
            self.integrator.integrate_positions(&mut self.bodies, h);
            if joints_on && self.joint_graph.usable() {
                self.joint_graph
                    .project_positions(&self.joints, &mut self.bodies);
            }
            if coupled {
                for (a, dq) in self.articulated.iter_mut().zip(&mut self.tree_dq) {
                    if link_proxies::in_solve(eff, a) {
                        a.position_stage(h);
                        for (x, v) in dq.iter_mut().zip(&a.qd) {
                            *x += h * v;
                        }
                    }
                }
            }
            self.counters.solver_iterations += 1;
            if self.settings.relax_each_substep || sub + 1 == n_sub {
                let relax = SolvePass {
                    use_bias: false,
                    reverse: !rev,
                };
                self.solve_pass(
                    &soft,
                    &soft_static,
                    &joint_soft,
                    inv_h,
                    max_push,
                    joints_on,
                    relax,
                );
                self.counters.solver_iterations += 1;
            }
            if replay && sub + 1 < n_sub {
                self.warm_start_replay.record(&self.bodies);
            }
            if coupled {
                for a in self.articulated.iter_mut() {
                    a.end_substep_drives();
                }
            }
            self.counters.substeps += 1;
        }
        if self.fine_factor > 1 {
            let h = h / self.fine_factor as f64;
            let forces = FreeForces {
                damping: forces.damping.map(|_| self.settings.damping_factors(h)),
                ..forces
            };
            self.fine_substeps(n_sub * self.fine_factor, h, &forces);
        }
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
        self.step_articulated(h)?;
        self.sync_link_proxies(false);
        if let Some(islands) = self.islands.as_mut() {
            self.counters.mark(Stage::Islands);
            self.counters.islands = islands.update(
                &mut self.bodies,
                manifolds(&self.narrow),
                &self.joint_pairs,
                dt,
            );
        }
        self.time += dt;
        Ok(())
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
    fn kinematic_moving(&self) -> bool {
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

    #[allow(clippy::too_many_arguments)]
    fn solve_pass(
        &mut self,
        soft: &Softness,
        soft_static: &Softness,
        joint_soft: &JointSoftness,
        inv_h: f64,
        max_push: f64,
        joints_on: bool,
        pass: SolvePass,
    ) {
        if joints_on {
            self.solve_joints(joint_soft, pass.use_bias);
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
        self.solve_tree_drives(soft_static, pass, DriveGroup::Motors);
        if !self.tree_contacts.contacts.is_empty() {
            self.tree_contacts.solve(
                &mut self.bodies,
                &mut self.articulated,
                &self.tree_dq,
                soft,
                soft_static,
                inv_h,
                max_push,
                pass,
            );
        }
        // Limits and prescribed motion last: each pass ends on their bounds and trajectories.
        self.solve_tree_drives(soft_static, pass, DriveGroup::Hard);
    }

    /// The contact rows' settings from the scene's effects and the solver settings.
    fn contact_settings(&self) -> ContactSettings {
        let eff = &self.effects;
        ContactSettings {
            friction: eff.has(Effect::Friction),
            restitution: eff.has(Effect::Restitution),
            rolling: eff.has(Effect::RollingResistance),
            restitution_threshold: self.settings.restitution_threshold,
            max_push_velocity: self.settings.max_push_velocity,
        }
    }

    /// The lean step this step may take, before its contacts are prepared: a world of free
    /// bodies in contact under gravity, soft contacts grouped four by four, no restitution,
    /// every body still, and a resting decision on fewer substeps that it keeps this step
    /// ([`RestingSubsteps::kept_for`]). Its grouped constraints are then read from their
    /// lanes alone (filled as each is prepared), never from `constraints`, so they are
    /// prepared in cache and not written there; the step checks once its substeps are known
    /// that it took them ([`Self::prepare_contacts_again`] otherwise).
    fn lean_step(
        &self,
        n_sub: usize,
        dt: f64,
        predicted: Option<ContactStiffness>,
    ) -> Option<ContactLeanStep> {
        let eff = &self.effects;
        let plain = self.settings.lean_resting_contacts
            && self.settings.batch_contacts
            && self.settings.soft_contacts
            && self.settings.fewer_substeps_at_rest
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
        let stiffness = self.settings.stiffness_on(substep, dt);
        // The stiffness the constraints took last step (`predicted`, which each is stiffened
        // with as it is prepared), so that nothing is stiffened again.
        (predicted == Some(stiffness)).then_some(ContactLeanStep { substeps, substep })
    }

    /// Prepares every free bodies' contact constraint again, whole, in `constraints` (a lean
    /// step whose substeps came out otherwise; the bodies and manifolds are those the step
    /// prepared them from, so they come out as the full step would have prepared them).
    fn prepare_contacts_again(&mut self, settings: &ContactSettings) {
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
    fn substeps_at_rest(&mut self, n_sub: usize, coupled: bool) -> usize {
        let g = self.gravity.norm();
        let allowed = self.settings.fewer_substeps_at_rest
            && self.settings.soft_contacts
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
        let stiffness = self.settings.contact_stiffness(self.dt / n_sub as f64);
        let world = RestingWorld {
            loads: StepLoads::new(
                &stiffness,
                &self.gravity,
                (manifolds(&self.narrow), &self.joint_pairs, &self.proxies),
                self.dt,
            ),
            more_than_contacts,
            hold_sink: self.settings.hold_sink,
            substeps: n_sub,
        };
        let settings = self.settings;
        let dt = self.dt;
        self.resting_substeps.substeps(
            &self.bodies,
            &self.constraints,
            &mut self.island_substeps,
            &world,
            |n| settings.stiffness_on(dt / n as f64, dt),
        )
    }

    /// Decides which islands need stiffer contacts this step ([`IslandSubsteps::plan`]),
    /// stiffens them, and gives them the extra substeps that keep them within the stiffness
    /// cap; marks the constraints that take those substeps. `n_sub` is the step's substeps.
    fn plan_island_substeps(&mut self, stiffness: &ContactStiffness, n_sub: usize) {
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
        let cap = self.settings.contact_hertz_cap / stiffness.substep;
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
    fn carry_impulses_to_substeps(&mut self, h: f64, lean: bool) -> bool {
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
        let hold_up = self.settings.hold_up(&self.effects, &self.gravity);
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
            let (settings, dt) = (&self.settings, self.dt);
            let changes = |ci: usize, m: &Manifold| {
                let (carried, now) = (m.impulse_substep, substep(ci));
                (carried > 0.0 && carried != now).then(|| {
                    (
                        settings.stiffness_on(carried, dt),
                        settings.stiffness_on(now, dt),
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
    fn fine_substeps(&mut self, substeps: usize, h: f64, forces: &FreeForces) {
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
            let relax = self.settings.relax_each_substep || sub + 1 == substeps;
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
    fn fine_contacts(
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

    /// Storage index of the first body named `name`.
    pub(crate) fn body_index(&self, name: &str) -> Option<usize> {
        self.bodies.name.iter().position(|n| n == name)
    }
}

/// Whether manifold `m` is solved as a contact constraint between free bodies: neither body
/// is a tree link's proxy (those contacts act on the tree), and one of them is awake.
fn solved_between_free_bodies(bodies: &BodySet, proxies: &[Option<Proxy>], m: &Manifold) -> bool {
    let (a, b) = (m.a as usize, m.b as usize);
    let proxy = |i: usize| proxies.get(i).is_some_and(Option::is_some);
    !(proxy(a) || proxy(b)) && (bodies.awake[a] || bodies.awake[b])
}

/// The narrow phase's manifolds (none without collision).
fn manifolds(narrow: &Option<NarrowPhase>) -> &[Manifold] {
    narrow.as_ref().map_or(&[][..], |n| &n.manifolds[..])
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

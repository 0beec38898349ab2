//! The world: bodies, joints, articulated trees and the step pipeline built from the declared
//! effects. A stage whose effect is not declared has no state (`None`) and is never entered.

use super::articulated::ArticulatedSystem;
use super::handles::{BodyHandle, JointHandle, Slots};
use super::island_substeps::IslandSubsteps;
use super::islands::Islands;
use super::resting_substeps::RestingSubsteps;
use super::settings::SolverVariants;
use super::sink_hold::SinkHold;
use super::step_guard;
use super::tree_contacts::{Proxy, TreeContacts, TreePoses};
use super::warm_start_replay::WarmStartReplay;
use super::{Effect, Effects, FreeIntegrator, IntegratorKind, SolverSettings, StepCounters};
use crate::dynamics::solver::{
    ContactBatches, ContactConstraint, ContactStiffness, FreeJoint, JointGraph,
};
use crate::dynamics::{BodyKind, BodySet, DynamicsError};
use crate::geometry::{BroadPhase, NarrowPhase, V3};

/// A simulated world. A clone is a snapshot: stepping it gives what stepping this world
/// would, bit for bit (rollback netcode restores one and steps again).
#[derive(Clone)]
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
    /// The solver's internal optimizations and alternative forms.
    pub(crate) variants: SolverVariants,
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
    pub(crate) integrator: FreeIntegrator,
    pub(crate) broad: Option<BroadPhase>,
    pub(crate) narrow: Option<NarrowPhase>,
    pub(crate) islands: Option<Islands>,
    pub(crate) constraints: Vec<ContactConstraint>,
    pub(crate) joint_pairs: Vec<(usize, usize)>,
    pub(crate) excluded_pairs: Vec<u64>,
    pub(crate) batches: ContactBatches,
    pub(crate) batched: bool,
    /// Islands whose contacts would lean take extra substeps (`island_substeps.rs`).
    pub(crate) island_substeps: IslandSubsteps,
    /// A world at rest takes fewer substeps (`resting_substeps.rs`).
    pub(crate) resting_substeps: RestingSubsteps,
    /// The resting contacts' sink held back (`sink_hold.rs`).
    pub(crate) sink_hold: SinkHold,
    /// Fast balls that end this step along their followed path (continuous collision).
    pub(crate) ball_paths: Vec<super::ccd::BallPath>,
    /// Each fast body's travel over this step beyond which its contacts are not kept (m;
    /// `CollisionBodies::travel`), empty when no body is fast or with continuous collision.
    pub(crate) travel: Vec<f64>,
    /// The touching contacts that bounce, kept between steps (`impacts.rs`).
    pub(crate) touching: super::impacts::TouchingImpacts,
    /// Substeps of those islands per substep of the step (1: none this step).
    pub(crate) fine_factor: usize,
    /// The soft contacts' stiffness of the last step, which each constraint takes as it is
    /// prepared: a world that keeps its substeps keeps it, and its constraints are not
    /// visited again to be stiffened.
    pub(crate) last_stiffness: Option<ContactStiffness>,
    /// The constraint prepared last where the step's constraints are not kept
    /// (`ContactLeanStep`): its lane is filled from here, in cache.
    pub(crate) scratch_constraint: ContactConstraint,
    /// Per constraint: whether it belongs to such an island.
    pub(crate) fine_constraint: Vec<bool>,
    /// The contacts of those islands, coloured and grouped.
    pub(crate) fine_batches: ContactBatches,
    /// The contacts' change of each body's velocity over the last substep.
    pub(crate) warm_start_replay: WarmStartReplay,
    /// The bodies' `awake` flags, kept while the extra substeps move only their islands.
    pub(crate) awake_saved: Vec<bool>,
    /// Checks before and after each step, and the snapshot a failed step is rolled back to.
    pub(crate) guard: step_guard::StepGuard,
    /// For each body, the tree link it stands for (a proxy), if any.
    pub(crate) proxies: Vec<Option<Proxy>>,
    /// Contacts with a tree link on a side, this step.
    pub(crate) tree_contacts: TreeContacts,
    /// Per tree, its links' poses at the current substep (the start of the step's, then
    /// each substep's): where the tree contacts' anchors are now.
    pub(crate) tree_poses: TreePoses,
    /// Per tree, the link poses at the start of the step.
    pub(crate) link_poses: Vec<Vec<crate::algebra::SE3<f64>>>,
    /// Per tree, the velocity its motors reach in the step's first substep (empty: none).
    pub(crate) predicted_qd: Vec<Vec<f64>>,
    /// The substep (s) and the time at its end (s), for the drives' rows.
    pub(crate) substep_clock: (f64, f64),
    /// Body handles ↔ storage indices.
    pub(crate) body_slots: Slots,
    /// Joint handles ↔ indices into `joints`.
    pub(crate) joint_slots: Slots,
    /// Bodies were inserted or removed since the broad phase sized its grid.
    pub(crate) broad_dirty: bool,
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
            variants: SolverVariants::default(),
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
            ball_paths: Vec::new(),
            travel: Vec::new(),
            touching: Default::default(),
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
            tree_poses: Vec::new(),
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
        self.tree_poses.push(system.link_poses());
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

    measure_pub_fn! {
        /// Whether the world has a broad phase (the `contacts` effect).
        fn has_broad_phase(&self) -> bool {
            self.broad.is_some()
        }
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
        let result = match self.step_parts() {
            1 => match self.step_unguarded(true) {
                Ok(Some(parts)) => self.step_in_parts(parts),
                other => other.map(|_| ()),
            },
            parts => self.step_in_parts(parts),
        };
        self.guard_after_step(result)
    }

    /// Storage index of the first body named `name`.
    pub(crate) fn body_index(&self, name: &str) -> Option<usize> {
        self.bodies.name.iter().position(|n| n == name)
    }
}

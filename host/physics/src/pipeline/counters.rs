//! Step counters: what the last step actually did, so tests can prove effect gating.

/// A stage of the step.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Stage {
    /// Gravity added to velocities.
    Gravity,
    /// Bounding boxes and the grid broad phase.
    BroadPhase,
    /// Contact manifolds.
    NarrowPhase,
    /// Contact constraint preparation and solve.
    ContactSolve,
    /// Joint constraint solve.
    JointSolve,
    /// The restitution pass.
    Restitution,
    /// Rolling resistance rows inside the contact solve.
    RollingResistance,
    /// Continuous collision (velocity-swept margins).
    ContinuousCollision,
    /// Gyroscopic term.
    Gyroscopic,
    /// Velocity damping.
    Damping,
    /// Free-body position integration.
    Integrate,
    /// Articulated trees (ABA).
    Articulated,
    /// Islands and sleeping.
    Islands,
}

#[cfg_attr(not(feature = "measure"), allow(dead_code))]
impl Stage {
    /// All stages.
    pub(crate) const ALL: [Stage; 13] = [
        Stage::Gravity,
        Stage::BroadPhase,
        Stage::NarrowPhase,
        Stage::ContactSolve,
        Stage::JointSolve,
        Stage::Restitution,
        Stage::RollingResistance,
        Stage::ContinuousCollision,
        Stage::Gyroscopic,
        Stage::Damping,
        Stage::Integrate,
        Stage::Articulated,
        Stage::Islands,
    ];

    /// Short name (for JSON output).
    pub fn name(self) -> &'static str {
        match self {
            Stage::Gravity => "gravity",
            Stage::BroadPhase => "broad_phase",
            Stage::NarrowPhase => "narrow_phase",
            Stage::ContactSolve => "contact_solve",
            Stage::JointSolve => "joint_solve",
            Stage::Restitution => "restitution",
            Stage::RollingResistance => "rolling_resistance",
            Stage::ContinuousCollision => "continuous_collision",
            Stage::Gyroscopic => "gyroscopic",
            Stage::Damping => "damping",
            Stage::Integrate => "integrate",
            Stage::Articulated => "articulated",
            Stage::Islands => "islands",
        }
    }
}

/// Counters of the last step (reset at the start of each step).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct StepCounters {
    stages: u32,
    /// Box overlap tests in the broad phase.
    pub broad_phase_tests: usize,
    /// Candidate pairs from the broad phase.
    pub(crate) broad_phase_pairs: usize,
    /// Pairs given to a narrow-phase routine.
    pub pairs_tested: usize,
    /// Pairs of resting boxes whose manifold was moved with the bodies instead of collided
    /// again.
    pub manifolds_refreshed: usize,
    /// Contact constraints prepared straight into their lanes, not kept whole (a world at
    /// rest, `SolverVariants::lean_resting_contacts`).
    pub lean_contacts: usize,
    /// Manifolds with points.
    pub manifolds: usize,
    /// Contact points.
    pub contacts: usize,
    /// Pairs of shapes without a contact routine.
    pub unsupported_pairs: usize,
    /// Solver passes over the constraints (solve + relax, per substep).
    pub solver_iterations: usize,
    /// Substeps.
    pub substeps: usize,
    /// Colours of the contact graph (constraints of one colour share no moving body).
    pub contact_colours: usize,
    /// Groups of four contact constraints solved side by side.
    pub contact_groups: usize,
    /// Contact points that received a restitution impulse check.
    pub restitution_constraints: usize,
    /// Two-body impacts passed along touching contacts before the solve.
    pub(crate) touching_impacts: usize,
    /// ABA calls.
    pub articulated_solves: usize,
    /// Bodies simulated (awake dynamic).
    pub awake_bodies: usize,
    /// Islands found (with sleeping on).
    pub(crate) islands: usize,
    /// Substeps taken by the islands whose contacts would lean, where they take more than the
    /// step's (0: none this step).
    pub fine_substeps: usize,
    /// Bodies in the islands whose contacts would lean (stiffened, on extra substeps where
    /// the stiffness cap asks for them).
    pub fine_bodies: usize,
    /// Parts the step was taken in: 1, or more where a tree touching static geometry (and
    /// not driven in every coordinate) moved farther in the step than its contacts see
    /// (`pipeline/step_parts.rs`).
    pub parts: usize,
}

impl StepCounters {
    /// Marks a stage as run.
    #[inline]
    pub(crate) fn mark(&mut self, s: Stage) {
        self.stages |= 1 << s as u32;
    }

    /// Whether stage `s` ran.
    #[cfg_attr(not(feature = "measure"), allow(dead_code))]
    pub fn ran(&self, s: Stage) -> bool {
        self.stages & (1 << s as u32) != 0
    }

    /// The stages that ran.
    #[cfg_attr(not(feature = "measure"), allow(dead_code))]
    pub fn stages(&self) -> impl Iterator<Item = Stage> + '_ {
        Stage::ALL.into_iter().filter(|s| self.ran(*s))
    }

    /// Adds the work of `part`, a later part of the same step, to these counters: the
    /// stages run, the tests, passes, substeps and solves add up; the step's state (its
    /// manifolds, contacts, colours, groups, awake bodies, islands) is the last part's.
    pub(crate) fn add_part(&mut self, part: &StepCounters) {
        let work = StepCounters {
            stages: self.stages | part.stages,
            broad_phase_tests: self.broad_phase_tests + part.broad_phase_tests,
            broad_phase_pairs: self.broad_phase_pairs + part.broad_phase_pairs,
            pairs_tested: self.pairs_tested + part.pairs_tested,
            manifolds_refreshed: self.manifolds_refreshed + part.manifolds_refreshed,
            solver_iterations: self.solver_iterations + part.solver_iterations,
            substeps: self.substeps + part.substeps,
            restitution_constraints: self.restitution_constraints + part.restitution_constraints,
            touching_impacts: self.touching_impacts + part.touching_impacts,
            articulated_solves: self.articulated_solves + part.articulated_solves,
            fine_substeps: self.fine_substeps + part.fine_substeps,
            parts: self.parts + part.parts,
            ..*part
        };
        *self = work;
    }

    /// Clears everything.
    pub(crate) fn reset(&mut self) {
        *self = Self::default();
    }
}

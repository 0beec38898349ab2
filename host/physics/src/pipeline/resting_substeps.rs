//! Fewer substeps for a world at rest whose contacts hold it as well on fewer.
//!
//! The step's substeps are there for what moves: an impact, a fast spin, a light body under a
//! heavy one, a joint or a tree. A world whose free bodies all rest needs them only for its
//! contacts' stiffness, which the substep caps (a quarter of its rate): a soft contact at rest
//! is a spring of its normal rows' effective mass, and under its load `F` it overlaps by
//! `F / (m ω²)`. A body's sink is the overlap of the contact it stands on plus the sink of the
//! body below it (the largest over its supports), each contact also keeping its slop; a resting
//! stack sinks by the sum down to the ground, and a column leans by its contacts' tilt
//! ([`IslandSubsteps::leans`]).
//!
//! [`RestingSubsteps::substeps`] predicts both from the loads the contacts carried in the last
//! step, at the stiffness of half and of a third of the step's substeps, and gives the world
//! the fewer substeps where the sink stays within [`SINK_TOLERANCE`] and no column leans
//! beyond [`LEAN_TOLERANCE`]. Only a world that has rested for [`RESTING_TIME`] takes them:
//! every awake dynamic body below the sleep speeds, no joint, no articulated tree, no moving
//! kinematic body, no contact between moving bodies [`UNEVEN_MASS_RATIO`] times apart and
//! none that follows a round part's turn. The first step in which any of that changes takes
//! the step's substeps again.

use super::island_substeps::{IslandSubsteps, StepLoads, LEAN_TOLERANCE};
use crate::dynamics::solver::contact_constraint::LINEAR_SLOP;
use crate::dynamics::solver::softness::UNEVEN_MASS_RATIO;
use crate::dynamics::solver::{ContactConstraint, ContactStiffness};
use crate::dynamics::{BodyKind, BodySet};
use crate::pipeline::islands::{ANGULAR_SLEEP_SPEED, LINEAR_SLEEP_SPEED, TIME_TO_SLEEP};

/// The sink (m) a resting world may take on fewer substeps: half the centimetre a resting
/// stack is allowed to move (`tests/stacking.rs`), the other half left to its sideways move
/// and to the settling of its first steps.
pub const SINK_TOLERANCE: f64 = 5e-3;

/// How long (s) every body must have rested before the world takes fewer substeps: the time
/// a body takes to fall asleep.
pub const RESTING_TIME: f64 = TIME_TO_SLEEP;

/// A contact whose normal is within 45° of the vertical supports the body on top (–).
const SUPPORT_COSINE: f64 = std::f64::consts::FRAC_1_SQRT_2;

/// The divisors of the step's substeps tried, the least demanding first.
const DIVISORS: [usize; 2] = [2, 3];

/// The decision's state, kept between steps.
#[derive(Clone, Debug, Default)]
pub(crate) struct RestingSubsteps {
    /// How long (s) the world has rested.
    rested: f64,
    /// Per body: its predicted sink (m).
    sink: Vec<f64>,
    /// Supporting contacts: the height (m) of the body on top, the body on top, the body
    /// below, the constraint.
    supports: Vec<(f64, u32, u32, u32)>,
}

/// What the world tells the decision about itself.
pub(crate) struct RestingWorld<'a> {
    /// The loads of the step at its own substeps.
    pub loads: StepLoads<'a>,
    /// Whether anything but free bodies in contact is stepped: joints, articulated trees,
    /// a moving kinematic body.
    pub more_than_contacts: bool,
    /// The step's substeps.
    pub substeps: usize,
}

impl RestingSubsteps {
    /// Forgets how long the world has rested (its bodies changed).
    pub(crate) fn forget(&mut self) {
        self.rested = 0.0;
    }

    /// The substeps the world takes this step: fewer than `world.substeps` where it has
    /// rested long enough and its contacts hold it as well on fewer; `stiffness(n)` is the
    /// contacts' stiffness on `n` substeps.
    pub(crate) fn substeps(
        &mut self,
        bodies: &BodySet,
        constraints: &[ContactConstraint],
        islands: &mut IslandSubsteps,
        world: &RestingWorld<'_>,
        stiffness: impl Fn(usize) -> ContactStiffness,
    ) -> usize {
        let n = world.substeps;
        if !self.rests(bodies, constraints, world) || islands.holding() {
            self.rested = 0.0;
            return n;
        }
        self.rested += world.loads.dt;
        if self.rested < RESTING_TIME {
            return n;
        }
        let mut chosen = n;
        for d in DIVISORS {
            let fewer = n / d;
            if fewer == 0 || fewer >= chosen {
                break;
            }
            let k = stiffness(fewer);
            let loads = StepLoads {
                stiffness: &k,
                ..world.loads
            };
            let holds = islands.leans(bodies, constraints, &loads) <= LEAN_TOLERANCE
                && !islands.stacked()
                && self.sink(bodies, constraints, &loads) <= SINK_TOLERANCE;
            if !holds {
                break;
            }
            chosen = fewer;
        }
        chosen
    }

    /// Whether the world rests this step: see the module's documentation.
    fn rests(
        &self,
        bodies: &BodySet,
        constraints: &[ContactConstraint],
        world: &RestingWorld<'_>,
    ) -> bool {
        if world.more_than_contacts || constraints.is_empty() || world.loads.gravity <= 0.0 {
            return false;
        }
        let still = (0..bodies.len()).all(|i| {
            bodies.kind[i] != BodyKind::Dynamic
                || !bodies.awake[i]
                || (bodies.vel[i].norm() <= LINEAR_SLEEP_SPEED
                    && bodies.omega[i].norm() <= ANGULAR_SLEEP_SPEED)
        });
        still
            && constraints
                .iter()
                .all(|c| c.mass_ratio() < UNEVEN_MASS_RATIO && !c.follows_turn())
    }

    /// The largest sink (m) of a body at the contacts' stiffness `loads.stiffness`, under the
    /// loads they carried: each body the overlap and slop of a contact it stands on plus the
    /// sink of the body below, the largest over its supports, taken from the lowest body up.
    fn sink(
        &mut self,
        bodies: &BodySet,
        constraints: &[ContactConstraint],
        loads: &StepLoads<'_>,
    ) -> f64 {
        let up = loads.up;
        let moving = |i: usize| bodies.kind[i] == BodyKind::Dynamic && bodies.awake[i];
        // A contact's overlap under its load, and its slop.
        let overlap = |c: &ContactConstraint| {
            let hz = loads.stiffness.hertz_for(c.against_static, c.mass_ratio());
            let substep = loads
                .manifolds
                .get(c.manifold)
                .map_or(0.0, |m| m.impulse_substep);
            c.resting_overlap(2.0 * std::f64::consts::PI * hz, substep) + LINEAR_SLOP
        };
        let mut most: f64 = 0.0;
        self.supports.clear();
        for (ci, c) in constraints.iter().enumerate() {
            if c.normal_impulse() <= 0.0 {
                continue;
            }
            let along = c.normal().dot(&up);
            if along.abs() < SUPPORT_COSINE {
                // A contact pressed from the side moves its bodies by its own overlap.
                most = most.max(overlap(c));
                continue;
            }
            let (upper, lower) = if along > 0.0 { (c.b, c.a) } else { (c.a, c.b) };
            if moving(upper) {
                let height = up.dot(&bodies.pos[upper]);
                self.supports
                    .push((height, upper as u32, lower as u32, ci as u32));
            }
        }
        // A body's supports lie below it, so theirs come first.
        self.supports.sort_unstable_by(|x, y| x.0.total_cmp(&y.0));
        self.sink.clear();
        self.sink.resize(bodies.len(), 0.0);
        for &(_, upper, lower, ci) in &self.supports {
            let overlap = overlap(&constraints[ci as usize]);
            let below = if moving(lower as usize) {
                self.sink[lower as usize]
            } else {
                0.0
            };
            let s = &mut self.sink[upper as usize];
            *s = s.max(below + overlap);
            most = most.max(*s);
        }
        most
    }
}

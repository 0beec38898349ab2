//! Fewer substeps for a world at rest whose contacts hold it as well on fewer.
//!
//! The step's substeps are there for what moves: an impact, a fast spin, a light body under a
//! heavy one, a joint or a tree. A world whose free bodies all rest needs them only for its
//! contacts' stiffness, which the substep caps (a quarter of its rate): a soft contact at rest
//! is a spring of its normal rows' effective mass, and under its load `F` it overlaps by
//! `F / (m ω²)`. A body's sink is the overlap of the contact it stands on plus the sink of the
//! body below it (the largest over its supports), each contact also keeping its slop; a resting
//! stack sinks by the sum down to the ground, and a column leans by its contacts' tilt
//! ([`IslandSubsteps::leans`]). Where the world holds its contacts' sink
//! (`pipeline/sink_hold.rs`), a contact that bears weight keeps its mean overlap at the slop
//! on any stiffness, taking up the softer contacts' overlap as the substeps change: only its
//! most loaded point's excess over the mean sinks further.
//!
//! [`RestingSubsteps::substeps`] predicts both from the loads the contacts carried in the last
//! step, at the stiffness of a half, a third, a quarter and a sixth of the step's substeps, and
//! gives the world the fewest substeps where the sink stays within [`SINK_TOLERANCE`], no column leans beyond
//! [`LEAN_TOLERANCE`] and no column of bodies standing alone on one another rocks too freely on
//! its softer contacts: its rocking ratio ([`IslandSubsteps::rocking`], Dunkerley's sum of its
//! weight against its contacts' stiffness against tilting) stays within [`ROCKING_MARGIN`].
//! On those fewer substeps a contact against a body that does not move keeps within
//! [`RESTING_STATIC_CAP`] of their rate. So a tower of 5 unit cubes takes a sixth of the
//! step's substeps, one of 20 a half and one of 40 none fewer. Only a world that
//! has rested for [`RESTING_TIME`] takes them: every awake dynamic body below the sleep
//! speeds, no joint, no articulated tree, no moving kinematic body, no contact between moving
//! bodies [`UNEVEN_MASS_RATIO`] times apart and none that follows a round part's turn. The
//! first step in which any of that changes, and the step after a body is added, removed or
//! set through the world's API (whose new contacts carry no load yet), counts the rest afresh
//! and takes the step's substeps. (A contact that appears in a pile at rest, as a side face
//! comes within the speculative distance, carries no load either, and needs none.) While the
//! world stays at rest its loads stay as they were, so a decision is kept for
//! [`RESTING_TIME`] before it is taken again (taken each step, the decision and the lean plan
//! were 5 % of the resting pyramid's step, `perf record`); the world's own plan of extra
//! substeps is not made while it rests on fewer (their stiffness was checked here).

use super::island_substeps::{IslandSubsteps, StepLoads, LEAN_TOLERANCE};
use crate::dynamics::solver::contact_constraint::LINEAR_SLOP;
use crate::dynamics::solver::softness::UNEVEN_MASS_RATIO;
use crate::dynamics::solver::{ContactConstraint, ContactStiffness};
use crate::dynamics::{BodyKind, BodySet};
use crate::pipeline::islands::{ANGULAR_SLEEP_SPEED, LINEAR_SLEEP_SPEED, TIME_TO_SLEEP};

/// The sink (m) a resting world may take on fewer substeps: half the centimetre a resting
/// stack is allowed to move (`tests/stacking.rs`), the other half left to its sideways move
/// and to the settling of its first steps.
pub(crate) const SINK_TOLERANCE: f64 = 5e-3;

/// How long (s) every body must have rested before the world takes fewer substeps: the time
/// a body takes to fall asleep.
pub(crate) const RESTING_TIME: f64 = TIME_TO_SLEEP;

/// The largest stiffness of a contact against a body that does not move on a resting
/// world's fewer substeps, as a fraction of their rate (–). Elsewhere such a contact takes
/// twice the stiffness of one between moving bodies, up to half the substep rate where those
/// are at their cap of a quarter (Box2D v3's rule); at half the rate a column's ground contact
/// keeps it wobbling: a 5-box tower on 6 substeps, its top box turning at 0.02–0.03 rad/s,
/// moved 2.7 mm sideways in 20 s, 1.3 mm with the cap at a third of the rate, and 0.02 mm at
/// 0.3 (0.04–0.05 mm on 2 and 4 substeps; measured with a build switch not kept, see
/// `docs/physics/integrators-accuracy-hard-cases.md`; hard case 12 checks the 5-box tower at rest). The step's own 12 substeps at
/// 1/60 s keep their 240 Hz, a third of their rate.
pub(crate) const RESTING_STATIC_CAP: f64 = 0.3;

/// The largest rocking ratio ([`IslandSubsteps::rocking`]) of a column on fewer substeps
/// (–): its weight at most half the load its contacts hold upright by Dunkerley's sum, the
/// usual safety factor of two of a column against buckling; a tilt grows at most twice under
/// it. (Measured on towers-1120, 20 unit cubes, with the sink held: the ratio is 0.69 on 4
/// substeps, where the towers sway 1.1–1.2 cm with a period of 7–8 s, and 0.31 on 6, where
/// they stay within 3 mm.)
pub(crate) const ROCKING_MARGIN: f64 = 0.5;

/// A contact whose normal is within 45° of the vertical supports the body on top (–).
const SUPPORT_COSINE: f64 = std::f64::consts::FRAC_1_SQRT_2;

/// The divisors of the step's substeps tried, the least demanding first.
const DIVISORS: [usize; 4] = [2, 3, 4, 6];

/// The decision's state, kept between steps.
#[derive(Clone, Debug, Default)]
pub(crate) struct RestingSubsteps {
    /// How long (s) every body has rested.
    rested: f64,
    /// The last decision: the step's substeps it was taken for, the substeps chosen, and how
    /// long (s) it has been kept.
    kept: Option<(usize, usize, f64)>,
    /// Per body: its predicted sink (m).
    sink: Vec<f64>,
    /// The loaded contacts that support a body, lowest body on top first.
    supports: Vec<Load>,
    /// The loaded contacts pressed from the side.
    sides: Vec<Load>,
}

/// A loaded contact, as the sink prediction reads it.
#[derive(Clone, Copy, Debug)]
struct Load {
    /// Height (m) of the body on top along `up` (supports only).
    height: f64,
    /// The body on top and the body below (supports only).
    upper: u32,
    lower: u32,
    /// Whether one body cannot move.
    against_static: bool,
    /// Heavier over lighter moving mass (–).
    mass_ratio: f64,
    /// `max λ / (h m)` over its points (m/s²): its overlap at stiffness `ω` is this over `ω²`
    /// ([`ContactConstraint::resting_overlap`] at `ω = 1`).
    load: f64,
    /// Where the contact holds its sink (`pipeline/sink_hold.rs`: it bears weight and the
    /// world holds sinks): the mean over its points of `λ / (h m)` (m/s²), the share of
    /// `load` its hold takes up; 0 where it does not.
    held_load: f64,
}

/// What the world tells the decision about itself.
pub(crate) struct RestingWorld<'a> {
    /// The step's loads (at its own substeps' stiffness; each candidate replaces it with its
    /// own).
    pub(crate) loads: StepLoads<'a>,
    /// Whether anything but free bodies in contact is stepped: joints, articulated trees,
    /// a moving kinematic body.
    pub(crate) more_than_contacts: bool,
    /// Whether the contacts hold back their sink (`SolverVariants::hold_sink`).
    pub(crate) hold_sink: bool,
    /// The step's substeps.
    pub(crate) substeps: usize,
}

impl RestingSubsteps {
    /// Forgets how long the world has rested (while it may not take fewer substeps).
    pub(crate) fn forget(&mut self) {
        self.rested = 0.0;
        self.kept = None;
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
        if !still(bodies, constraints, world) || islands.holding() {
            self.forget();
            return n;
        }
        let dt = world.loads.dt;
        self.rested += dt;
        if self.rested < RESTING_TIME {
            return n;
        }
        // While the world stays at rest its loads stay as they were: a decision holds for
        // [`RESTING_TIME`] before it is taken again.
        if let Some((of, chosen, age)) = &mut self.kept {
            if *of == n && *age + dt < RESTING_TIME {
                *age += dt;
                return *chosen;
            }
        }
        let chosen = self.decide(bodies, constraints, islands, world, stiffness);
        self.kept = Some((n, chosen, 0.0));
        chosen
    }

    /// The fewer substeps [`Self::substeps`] will return this step without taking its
    /// decision again, where it will: every body still (as [`still`] asks of them), rested
    /// long enough, and a decision on fewer than `n` kept. The caller checks the rest (a world
    /// of free bodies in contact under gravity) by the substeps `substeps` returns.
    pub(crate) fn kept_for(&self, bodies: &BodySet, n: usize, dt: f64) -> Option<usize> {
        let (of, chosen, age) = self.kept?;
        let keeps = of == n && chosen < n && age + dt < RESTING_TIME;
        let rested = self.rested + dt >= RESTING_TIME;
        (keeps && rested && bodies_still(bodies)).then_some(chosen)
    }

    /// [`RestingSubsteps::substeps`] for a world that has rested long enough: the fewest
    /// substeps that hold it.
    fn decide(
        &mut self,
        bodies: &BodySet,
        constraints: &[ContactConstraint],
        islands: &mut IslandSubsteps,
        world: &RestingWorld<'_>,
        stiffness: impl Fn(usize) -> ContactStiffness,
    ) -> usize {
        let n = world.substeps;
        if !self.gather(bodies, constraints, &world.loads, world.hold_sink) {
            return n;
        }
        let mut chosen = n;
        let mut lean = None;
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
            // A lean grows as the contacts soften: none at stiffer contacts, none at these. (A
            // column's rocking ratio grows too, and is summed again at each stiffness.)
            if lean != Some(0.0) || islands.stacked() {
                lean = Some(islands.leans(bodies, constraints, &loads, true));
            }
            let holds = lean.is_some_and(|l| l <= LEAN_TOLERANCE)
                && islands.rocking() <= ROCKING_MARGIN
                && self.sink(bodies, &k) <= SINK_TOLERANCE;
            if !holds {
                break;
            }
            chosen = fewer;
        }
        chosen
    }

    /// Gathers the loaded contacts, the supports sorted from the lowest body on top up;
    /// false where a contact joins moving bodies [`UNEVEN_MASS_RATIO`] times apart or follows
    /// a round part's turn.
    fn gather(
        &mut self,
        bodies: &BodySet,
        constraints: &[ContactConstraint],
        loads: &StepLoads<'_>,
        hold: bool,
    ) -> bool {
        let up = loads.up;
        let moving = |i: usize| bodies.kind[i] == BodyKind::Dynamic && bodies.awake[i];
        self.supports.clear();
        self.sides.clear();
        for c in constraints {
            let mass_ratio = c.mass_ratio();
            if mass_ratio >= UNEVEN_MASS_RATIO || c.follows_turn() {
                return false;
            }
            let load = c.resting_overlap(1.0);
            if load <= 0.0 {
                continue;
            }
            let along = c.normal().dot(&up);
            let (upper, lower) = if along > 0.0 { (c.b, c.a) } else { (c.a, c.b) };
            let l = Load {
                height: up.dot(&bodies.pos[upper]),
                upper: upper as u32,
                lower: lower as u32,
                against_static: c.against_static,
                mass_ratio,
                load,
                held_load: if hold && along.abs() >= SUPPORT_COSINE {
                    c.mean_resting_overlap(1.0)
                } else {
                    0.0
                },
            };
            if along.abs() < SUPPORT_COSINE {
                self.sides.push(l);
            } else if moving(upper) {
                self.supports.push(l);
            }
        }
        // A body's supports lie below it, so theirs come first. (Sorted by the centres of the
        // bodies on top: a wide body tilted near 45° may have its centre above that of a body
        // resting on it, whose sink then misses that body's share, an underestimate no resting
        // pile of boxes makes.)
        self.supports
            .sort_unstable_by(|x, y| x.height.total_cmp(&y.height));
        true
    }

    /// The largest sink (m) of a body at the contacts' stiffness `k`, under the gathered
    /// loads: each body the overlap and slop of a contact it stands on plus the sink of the
    /// body below, the largest over its supports, taken from the lowest body up; a contact
    /// pressed from the side (as between pushed boxes) moves its bodies by its own overlap.
    /// A contact that holds its sink keeps its mean overlap at the slop as the stiffness
    /// changes (`sink_hold::restiffen`): only its most loaded point's excess over the mean
    /// overlaps beyond it.
    fn sink(&mut self, bodies: &BodySet, k: &ContactStiffness) -> f64 {
        let moving = |i: usize| bodies.kind[i] == BodyKind::Dynamic && bodies.awake[i];
        let overlap = |l: &Load| {
            let omega = 2.0 * std::f64::consts::PI * k.hertz_for(l.against_static, l.mass_ratio);
            (l.load - l.held_load).max(0.0) / (omega * omega) + LINEAR_SLOP
        };
        let mut most = self.sides.iter().map(overlap).fold(0.0, f64::max);
        self.sink.clear();
        self.sink.resize(bodies.len(), 0.0);
        for l in &self.supports {
            let below = if moving(l.lower as usize) {
                self.sink[l.lower as usize]
            } else {
                0.0
            };
            let s = &mut self.sink[l.upper as usize];
            *s = s.max(below + overlap(l));
            most = most.max(*s);
        }
        most
    }
}

/// Whether every awake dynamic body rests, below the sleep speeds, in a world of free bodies
/// in contact under gravity.
fn still(bodies: &BodySet, constraints: &[ContactConstraint], world: &RestingWorld<'_>) -> bool {
    if world.more_than_contacts || constraints.is_empty() || world.loads.gravity <= 0.0 {
        return false;
    }
    bodies_still(bodies)
}

/// Whether every awake dynamic body is below the sleep speeds.
fn bodies_still(bodies: &BodySet) -> bool {
    (0..bodies.len()).all(|i| {
        bodies.kind[i] != BodyKind::Dynamic
            || !bodies.awake[i]
            || (bodies.vel[i].norm() <= LINEAR_SLEEP_SPEED
                && bodies.omega[i].norm() <= ANGULAR_SLEEP_SPEED)
    })
}

//! Stiffer contacts, and the extra substeps they need, for the islands whose resting stacks
//! would lean.
//!
//! A soft contact is a spring of its normal rows' effective mass at the step's contact
//! stiffness, so under a steady load it sinks `F / (m ω²)`. Evenly loaded, every point of a
//! contact sinks alike and the bodies only settle. Loaded on one edge, as under a column whose
//! centre of mass lies outside the middle third of the contact, one edge sinks and the other
//! lifts: the column tilts by that sink over the contact's width, and its top leans by the
//! tilt times its height, which moves its load further out (the lean feeds on itself).
//!
//! Each step, before the solve, [`IslandSubsteps::plan`] finds the columns: each moving body
//! that stands on exactly one supporting contact (loaded in the last step, its normal within
//! 45° of the vertical) and the bodies that stand on it alone, their weight, centre of mass and
//! top gathered from the tops down. It predicts, at the step's contact stiffness, the tilt the
//! column's static load gives its contact ([`ContactConstraint::column_tilt`]) times the
//! column's height above it: the lean of the column's top. An island whose largest lean
//! exceeds [`LEAN_TOLERANCE`] takes contacts `k` times as stiff, `k` the least factor that
//! brings the lean within the tolerance (the sink falls as `1 / k²`), at most
//! [`MAX_SUBSTEP_FACTOR`]; the world gives the islands that stiffen as many substeps for each
//! of its own as keep the stiffest of them within the stiffness cap (a quarter of the substep
//! rate): the largest `k` at 1/60 s, where the step's contacts are at the cap already, none
//! extra at 1 ms. Islands with joints,
//! tree links or moving kinematic bodies keep the step's contacts and substeps (their other
//! constraints are solved at that rate), and so do islands with a contact between moving
//! bodies whose masses differ [`UNEVEN_MASS_RATIO`] times or more: there the extra passes do
//! harm (measured: a 500 kg box dropped 0.5 m onto a 10-layer pyramid of 1 kg boxes, which the
//! step's 12 substeps carry, sank through it within 3 s in four of six runs at 96 substeps,
//! contacts at 950–970 Hz).

use super::tree_contacts::Proxy;
use super::union_find::UnionFind;
use crate::dynamics::solver::softness::UNEVEN_MASS_RATIO;
use crate::dynamics::solver::{ContactConstraint, ContactStiffness};
use crate::dynamics::{BodyKind, BodySet};
use crate::geometry::{Manifold, V3};

/// The elastic lean (m) that an island's contacts may give its top at the step's substep:
/// a tenth of the centimetre a resting stack is allowed to move (`tests/stacking.rs`).
pub(crate) const LEAN_TOLERANCE: f64 = 1e-3;

/// A contact whose normal is within 45° of the vertical supports the body on top (–).
const SUPPORT_COSINE: f64 = std::f64::consts::FRAC_1_SQRT_2;

/// Largest stiffness factor of an island's contacts, and so of its substeps for each of the
/// step's (–).
pub(crate) const MAX_SUBSTEP_FACTOR: usize = 8;

/// How long (s) an island keeps a factor after its loads last asked for it. The loads answer
/// the stiffness (stiffer contacts carry a stack's load more evenly), so a factor taken on the
/// loads of one step alone would alternate between two values step after step, and each
/// change of stiffness shakes the stack.
pub(crate) const FACTOR_HOLD_TIME: f64 = 0.5;

/// The plan's buffers, kept between steps.
#[derive(Clone, Debug, Default)]
pub(crate) struct IslandSubsteps {
    sets: UnionFind,
    /// Per body: its island cannot take extra substeps.
    blocked: Vec<bool>,
    /// Per body: its column.
    column: Vec<Column>,
    /// Per body (island root): the island's stiffness factor.
    factor: Vec<usize>,
    /// Per body (island root): the largest lean of the island's contacts (m).
    lean: Vec<f64>,
    /// Per body: how many contacts support it, and the last of them.
    supports: Vec<(u8, u32)>,
    /// Per body: the body it stands on alone ([`NONE`]: none).
    below: Vec<u32>,
    /// Whether a moving body stands alone on another ([`IslandSubsteps::stacked`]).
    stacked: bool,
    /// Per body that stands alone on a loaded contact: its column's weight times the height
    /// of the column's centre of mass above the contact, over the contact's stiffness
    /// against tilting (–).
    rocking_ratio: Vec<f64>,
    /// Per body: the sum of the rocking ratios from it down to the body its column stands on
    /// (NaN: not summed yet).
    rocking_sum: Vec<f64>,
    /// The largest rocking ratio of a column ([`IslandSubsteps::rocking`]).
    rocking: f64,
    /// Per body: how many bodies stand on it alone whose columns it has not gathered yet.
    standing: Vec<u32>,
    /// Bodies whose columns are complete, to be added to the bodies below them.
    order: Vec<u32>,
    /// Per body: the stiffness factor its island takes this step (1: the step's own).
    pub(crate) fine: Vec<usize>,
    /// Per body: the factor its island holds, and for how long (s) its loads have asked for
    /// less.
    held: Vec<(usize, f64)>,
}

/// No body.
const NONE: u32 = u32::MAX;

/// A body and the bodies that stand on it alone, through bodies that stand alone on one
/// another.
#[derive(Clone, Copy, Debug)]
struct Column {
    /// Mass (kg).
    mass: f64,
    /// First moment of mass, `Σ m p` (kg·m, world).
    moment: V3,
    /// Highest point along `up` (m).
    top: f64,
}

impl Default for Column {
    fn default() -> Self {
        Self {
            mass: 0.0,
            moment: V3::zeros(),
            top: f64::NEG_INFINITY,
        }
    }
}

/// What the world tells the plan about the step.
pub(crate) struct StepLoads<'a> {
    /// The contacts' stiffness at the step's substep.
    pub(crate) stiffness: &'a ContactStiffness,
    /// Unit vector against gravity.
    pub(crate) up: V3,
    /// Gravity's magnitude (m/s²).
    pub(crate) gravity: f64,
    /// The step's manifolds (for the bodies that touch tree links).
    pub(crate) manifolds: &'a [Manifold],
    /// Body pairs joined by a joint.
    pub(crate) joint_pairs: &'a [(usize, usize)],
    /// Per body, whether it stands for a tree link.
    pub(crate) proxies: &'a [Option<Proxy>],
    /// The step (s).
    pub(crate) dt: f64,
}

/// What a step's loads are read from: the world's manifolds, its joints' body pairs and its
/// tree-link proxies.
pub(crate) type LoadSources<'a> = (&'a [Manifold], &'a [(usize, usize)], &'a [Option<Proxy>]);

impl<'a> StepLoads<'a> {
    /// The loads of a step under `gravity` (m/s², world, not zero) at the contacts' stiffness
    /// `stiffness`: the world's manifolds, its joints' body pairs and its tree-link proxies.
    pub(crate) fn new(
        stiffness: &'a ContactStiffness,
        gravity: &V3,
        world: LoadSources<'a>,
        dt: f64,
    ) -> Self {
        let g = gravity.norm();
        let (manifolds, joint_pairs, proxies) = world;
        Self {
            stiffness,
            up: -gravity / g,
            gravity: g,
            manifolds,
            joint_pairs,
            proxies,
            dt,
        }
    }
}

impl IslandSubsteps {
    /// Whether, at the last [`IslandSubsteps::leans`], a moving body stood alone on another
    /// (a column of two or more bodies).
    pub(crate) fn stacked(&self) -> bool {
        self.stacked
    }

    /// The largest rocking ratio of a column at the last [`IslandSubsteps::leans`] (–; 0:
    /// no column). A column of bodies standing alone on one another stays upright while its
    /// contacts' stiffness against tilting (`ContactConstraint::rocking_stiffness`) outweighs
    /// the turn its weight gives a tilt: each contact alone holds up to the weight `k / d`
    /// above it, `k` its stiffness against tilting and `d` the height of the column's centre
    /// of mass above it, and by Dunkerley's sum, a lower bound on a column's buckling load,
    /// the column holds while the sum of `W d / k` over its contacts down to its base stays
    /// below 1. This is that sum, the largest over the columns; at a ratio `r` a tilt grows
    /// `1 / (1 − r)` times under the column's own weight.
    pub(crate) fn rocking(&self) -> f64 {
        self.rocking
    }

    /// Whether an island holds a stiffness factor above 1 from its last steps.
    pub(crate) fn holding(&self) -> bool {
        self.held.iter().any(|&(k, _)| k > 1)
    }

    /// Lets go of the factors the islands hold (their bodies' indices changed).
    pub(crate) fn forget_held(&mut self) {
        self.held.clear();
    }

    /// Decides each body's stiffness factor ([`IslandSubsteps::fine`]) and returns the largest
    /// (1: none this step). Only islands at rest take one: an island with a point faster than
    /// a fall through `speculative_distance` (m) under the step's gravity, `√(2 g d)`, is in
    /// an impact or in flight, where no column stands under a static load.
    pub(crate) fn plan(
        &mut self,
        bodies: &BodySet,
        constraints: &[ContactConstraint],
        loads: &StepLoads<'_>,
        speculative_distance: f64,
    ) -> usize {
        let n = bodies.len();
        self.fine.clear();
        self.fine.resize(n, 1);
        self.held.resize(n, (1, 0.0));
        let holding = self.holding();
        let most = self.leans(bodies, constraints, loads, false);
        if most <= LEAN_TOLERANCE && !holding {
            return 1;
        }
        let moving = |i: usize| bodies.kind[i] == BodyKind::Dynamic && bodies.awake[i];
        // Islands of moving bodies joined by contacts; those with joints, tree links or moving
        // kinematic bodies are blocked.
        self.sets.reset(n);
        self.blocked.clear();
        self.blocked.resize(n, false);
        let kinematic_moving = |i: usize| {
            bodies.kind[i] == BodyKind::Kinematic
                && (bodies.vel[i] != V3::zeros() || bodies.omega[i] != V3::zeros())
        };
        for c in constraints {
            if c.ima > 0.0 && c.imb > 0.0 {
                self.sets.union(c.a, c.b);
                if c.mass_ratio() >= UNEVEN_MASS_RATIO {
                    self.blocked[c.a] = true;
                }
            }
            if kinematic_moving(c.a) {
                self.blocked[c.b] = true;
            }
            if kinematic_moving(c.b) {
                self.blocked[c.a] = true;
            }
        }
        // The leans are those of columns at rest: an island with a body in an impact or in
        // flight is in motion, and keeps the step's substeps.
        let settling = (2.0 * loads.gravity * speculative_distance).sqrt();
        for i in (0..n).filter(|&i| moving(i) && !settles(bodies, i, settling)) {
            self.blocked[i] = true;
        }
        for &(a, b) in loads.joint_pairs {
            self.blocked[a] = true;
            self.blocked[b] = true;
        }
        for m in loads.manifolds {
            let (a, b) = (m.a as usize, m.b as usize);
            if loads.proxies.get(a).is_some_and(Option::is_some) {
                self.blocked[b] = true;
            }
            if loads.proxies.get(b).is_some_and(Option::is_some) {
                self.blocked[a] = true;
            }
        }
        for i in 0..n {
            let r = self.sets.find(i);
            if self.blocked[i] {
                self.blocked[r] = true;
            }
            if r != i {
                self.lean[r] = self.lean[r].max(self.lean[i]);
            }
        }
        // Each body holds its island's factor a while; the island takes the largest its
        // bodies hold.
        let mut island_factor = std::mem::take(&mut self.factor);
        island_factor.clear();
        island_factor.resize(n, 1);
        for i in 0..n {
            if !moving(i) {
                self.held[i] = (1, 0.0);
                continue;
            }
            let r = self.sets.find(i);
            let (k, t) = &mut self.held[i];
            if self.blocked[r] {
                (*k, *t) = (1, 0.0);
                continue;
            }
            let need = substep_factor(self.lean[r]);
            if need >= *k {
                (*k, *t) = (need, 0.0);
            } else {
                *t += loads.dt;
                if *t > FACTOR_HOLD_TIME {
                    (*k, *t) = (need, 0.0);
                }
            }
            island_factor[r] = island_factor[r].max(*k);
        }
        let mut factor = 1;
        for i in 0..n {
            if moving(i) {
                let k = island_factor[self.sets.find(i)];
                self.fine[i] = k;
                factor = factor.max(k);
            }
        }
        self.factor = island_factor;
        factor
    }

    /// The elastic lean (m) that each column contact gives the top of its column at the
    /// contacts' stiffness `loads.stiffness` ([`IslandSubsteps::lean`], by the body it
    /// supports), and the largest of them (0: no body stands on a loaded contact); with
    /// `rocking`, the columns' rocking ratio too ([`IslandSubsteps::rocking`], NaN without:
    /// the plan of each step does not read it).
    pub(crate) fn leans(
        &mut self,
        bodies: &BodySet,
        constraints: &[ContactConstraint],
        loads: &StepLoads<'_>,
        rocking: bool,
    ) -> f64 {
        let n = bodies.len();
        let moving = |i: usize| bodies.kind[i] == BodyKind::Dynamic && bodies.awake[i];
        let up = loads.up;
        // Each moving body's supporting contacts (loaded, the normal within 45° of up, the
        // body on top); a body on exactly one stands in a column on the body below it.
        self.supports.clear();
        self.supports.resize(n, (0, 0));
        let mut columns = false;
        for (ci, c) in constraints.iter().enumerate() {
            let along = c.normal().dot(&up);
            let supports = along.abs() >= SUPPORT_COSINE && c.normal_impulse() > 0.0;
            if !supports {
                continue;
            }
            let upper = if along > 0.0 { c.b } else { c.a };
            if moving(upper) {
                let (count, _) = self.supports[upper];
                self.supports[upper] = (count.saturating_add(1), ci as u32);
                columns |= count == 0;
            }
        }
        if !columns {
            self.lean.clear();
            self.lean.resize(n, 0.0);
            self.stacked = false;
            self.rocking = 0.0;
            return 0.0;
        }
        self.gather_columns(bodies, constraints, &up);
        // The lean each column contact gives the top of its column, kept by the body it
        // supports.
        self.lean.clear();
        self.lean.resize(n, 0.0);
        self.rocking_ratio.clear();
        self.rocking_ratio.resize(n, 0.0);
        let mut most: f64 = 0.0;
        for i in 0..n {
            let (count, ci) = self.supports[i];
            if count != 1 || !moving(i) {
                continue;
            }
            let c = &constraints[ci as usize];
            let col = self.column[i];
            let hz = loads.stiffness.hertz_for(c.against_static, c.mass_ratio());
            let omega = 2.0 * std::f64::consts::PI * hz;
            let origin = bodies.pos[c.a];
            let com = col.moment / col.mass;
            let weight = col.mass * loads.gravity;
            let at = up.dot(&(origin + c.anchor_a()));
            let tilt = c.column_tilt(&origin, &com, weight, &up, omega);
            if tilt > 0.0 {
                self.lean[i] = tilt * (col.top - at).max(0.0);
                most = most.max(self.lean[i]);
            }
            if !rocking {
                continue;
            }
            let k = c.rocking_stiffness(&up, omega);
            let arm = (up.dot(&com) - at).max(0.0);
            self.rocking_ratio[i] = if k > 0.0 {
                weight * arm / k
            } else {
                f64::INFINITY
            };
        }
        self.rocking = if rocking {
            self.rocking_sums()
        } else {
            f64::NAN
        };
        most
    }

    /// Each moving body's column, gathered from the tops down through the bodies that stand
    /// alone on one another ([`Self::supports`] known), and the body each stands on alone.
    fn gather_columns(&mut self, bodies: &BodySet, constraints: &[ContactConstraint], up: &V3) {
        let n = bodies.len();
        let moving = |i: usize| bodies.kind[i] == BodyKind::Dynamic && bodies.awake[i];
        // Each body's own column, and the body it stands on alone (`NONE`: none).
        self.column.clear();
        self.column.resize(n, Column::default());
        self.below.clear();
        self.below.resize(n, NONE);
        self.standing.clear();
        self.standing.resize(n, 0);
        for i in (0..n).filter(|&i| moving(i)) {
            let m = bodies.mass(i);
            let b = &bodies.aabb[i];
            let (c, half) = ((b.min + b.max) * 0.5, (b.max - b.min) * 0.5);
            self.column[i] = Column {
                mass: m,
                moment: bodies.pos[i] * m,
                top: up.dot(&c) + half.x * up.x.abs() + half.y * up.y.abs() + half.z * up.z.abs(),
            };
            let (count, ci) = self.supports[i];
            if count == 1 {
                let c = &constraints[ci as usize];
                let below = if c.a == i { c.b } else { c.a };
                if moving(below) {
                    self.below[i] = below as u32;
                    self.standing[below] += 1;
                }
            }
        }
        self.stacked = self.below.iter().any(|&b| b != NONE);
        // From the tops down: a body's column is complete once every body standing on it
        // alone has added its own (each body once; a loop, which no resting stack makes, is
        // left out).
        self.order.clear();
        self.order.extend(
            (0..n as u32).filter(|&i| moving(i as usize) && self.standing[i as usize] == 0),
        );
        while let Some(i) = self.order.pop() {
            let below = self.below[i as usize];
            if below == NONE {
                continue;
            }
            let (above, below) = (self.column[i as usize], below as usize);
            let col = &mut self.column[below];
            col.mass += above.mass;
            col.moment += above.moment;
            col.top = col.top.max(above.top);
            self.standing[below] -= 1;
            if self.standing[below] == 0 {
                self.order.push(below as u32);
            }
        }
    }

    /// Sums each column's rocking ratios from each body down to the body the column stands
    /// on (each body once), and returns the largest sum.
    fn rocking_sums(&mut self) -> f64 {
        let n = self.below.len();
        self.rocking_sum.clear();
        self.rocking_sum.resize(n, f64::NAN);
        let mut most: f64 = 0.0;
        for top in 0..n {
            // Down to the first body already summed, or the column's base; the bodies on the
            // way are marked (−∞) so that a loop, which no resting stack makes, ends.
            self.order.clear();
            let mut i = top;
            let mut sum = 0.0;
            loop {
                let s = self.rocking_sum[i];
                if s == f64::NEG_INFINITY {
                    break;
                }
                if !s.is_nan() {
                    sum = s;
                    break;
                }
                self.rocking_sum[i] = f64::NEG_INFINITY;
                self.order.push(i as u32);
                match self.below[i] {
                    NONE => break,
                    below => i = below as usize,
                }
            }
            // Back up: each body its own ratio on the sum below it.
            while let Some(k) = self.order.pop() {
                sum += self.rocking_ratio[k as usize];
                self.rocking_sum[k as usize] = sum;
            }
            most = most.max(sum);
        }
        most
    }
}

/// Whether no point of body `i` moves faster than `speed` (m/s): `|v| + |ω| ρ`, `ρ` its
/// bounding radius.
fn settles(bodies: &BodySet, i: usize, speed: f64) -> bool {
    let radius = bodies.shape[i].bounding_radius();
    bodies.vel[i].norm() + bodies.omega[i].norm() * radius <= speed
}

/// The least stiffness factor (–) that brings an elastic lean of `lean` (m) at the step's
/// contacts within [`LEAN_TOLERANCE`]: the sink of a soft contact falls as the square of its
/// frequency.
pub(crate) fn substep_factor(lean: f64) -> usize {
    let k = (lean / LEAN_TOLERANCE).sqrt().ceil();
    if k.is_nan() {
        return 1;
    }
    (k as usize).clamp(1, MAX_SUBSTEP_FACTOR)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_factor_is_the_least_that_brings_the_lean_within_the_tolerance() {
        assert_eq!(substep_factor(0.0), 1);
        assert_eq!(substep_factor(LEAN_TOLERANCE), 1);
        assert_eq!(substep_factor(1.01 * LEAN_TOLERANCE), 2);
        assert_eq!(substep_factor(4.0 * LEAN_TOLERANCE), 2);
        assert_eq!(substep_factor(17.0 * LEAN_TOLERANCE), 5);
        assert_eq!(substep_factor(1e9), MAX_SUBSTEP_FACTOR);
        assert_eq!(substep_factor(f64::NAN), 1);
        for k in 1..=MAX_SUBSTEP_FACTOR {
            let lean = (k * k) as f64 * LEAN_TOLERANCE;
            // At k substeps per step the lean is k² times smaller: within the tolerance.
            assert!(lean / (substep_factor(lean).pow(2) as f64) <= LEAN_TOLERANCE * (1.0 + 1e-12));
        }
    }
}

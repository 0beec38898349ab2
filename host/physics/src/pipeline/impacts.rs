//! Simultaneous impacts as a sequence of pairwise impacts, before the solve.
//!
//! A contact solve treats every contact of a step at once: a row of touching spheres struck
//! at one end (a Newton's cradle) comes out as the least-squares answer, the struck sphere
//! bouncing back and the other four sharing the speed. Real balls of hard steel pass the
//! impulse along as a train of two-body impacts, the wave running through the row faster
//! than the balls move. This pass follows that law, the sequential collision processing of
//! Guendelman, Bridson and Fedkiw ("Nonconvex rigid bodies with stacking", SIGGRAPH 2003,
//! §5): before the solve, each contact point that **touches** at the start of the step (no
//! gap beyond [`LINEAR_SLOP`]), between bodies that bounce (a pair restitution `e > 0`), and
//! closes faster than the restitution threshold, takes the two-body impact along its normal,
//!
//! `j = −(1 + e) v_n / k`, `k = 1/m_a + 1/m_b + (r_a × n)·I_a⁻¹(r_a × n) + (r_b × n)·I_b⁻¹(r_b × n)`,
//!
//! so the point separates at `−e v_n`; a manifold takes one impact, at the centroid of its touching
//! points. The points are swept in order until a sweep finds
//! none closing, at most [`MAX_SWEEPS`] sweeps; what is left closing then goes to the solve
//! and its restitution as before. Each impact takes `½ j v_n (1 − e) ≥ 0` of kinetic energy
//! and adds none, whatever the order. Friction is left to the solve.
//!
//! Contacts with a gap at the start are not touched: the solve's speculative contact lets the
//! bodies close it, and its restitution bounces them in the step they meet. Sleeping bodies
//! and the links of articulated trees are left to the solve.

use crate::dynamics::solver::LINEAR_SLOP;
use crate::dynamics::{BodyKind, BodySet};
use crate::geometry::{Manifold, V3};

/// Most sweeps over the touching points within one step (–): a row of this many bodies
/// passes an impact from either end within one step.
pub(crate) const MAX_SWEEPS: usize = 64;

/// One touching manifold that bounces, at the centroid of its touching points.
#[derive(Clone, Copy, Debug)]
struct Point {
    a: usize,
    b: usize,
    /// Normal, A to B (world).
    n: V3,
    /// Arms from the centres of mass to the point (world, m).
    ra: V3,
    rb: V3,
    /// Inverse effective mass along the normal (1/kg).
    k: f64,
    /// Pair restitution (–).
    e: f64,
}

/// The touching manifolds that bounce, gathered each step into storage kept between steps.
#[derive(Clone, Debug, Default)]
pub(crate) struct TouchingImpacts {
    points: Vec<Point>,
}

impl TouchingImpacts {
    /// Applies the pairwise impacts of the touching points of `manifolds` to the velocities
    /// of `bodies`; returns how many impacts it applied. `threshold` is the restitution
    /// threshold (m/s); `free` says whether a body is a free body (not an articulated tree's
    /// link).
    pub(crate) fn propagate(
        &mut self,
        manifolds: &[Manifold],
        bodies: &mut BodySet,
        threshold: f64,
        free: impl Fn(usize) -> bool,
    ) -> usize {
        touching_points(manifolds, bodies, free, &mut self.points);
        let mut impacts = 0;
        for _ in 0..MAX_SWEEPS {
            let mut any = false;
            for p in &self.points {
                let dv = bodies.vel[p.b] + bodies.omega[p.b].cross(&p.rb)
                    - bodies.vel[p.a]
                    - bodies.omega[p.a].cross(&p.ra);
                let vn = p.n.dot(&dv);
                if vn >= -threshold {
                    continue;
                }
                let j = -(1.0 + p.e) * vn / p.k;
                let imp = p.n * j;
                let (a, b) = (p.a, p.b);
                bodies.vel[a] -= imp * bodies.inv_mass[a];
                bodies.omega[a] -= bodies.inv_inertia_world[a] * p.ra.cross(&imp);
                bodies.vel[b] += imp * bodies.inv_mass[b];
                bodies.omega[b] += bodies.inv_inertia_world[b] * p.rb.cross(&imp);
                impacts += 1;
                any = true;
            }
            if !any {
                break;
            }
        }
        impacts
    }
}

/// The points of `manifolds` that touch, bounce and join two awake-or-unmoving free bodies,
/// at least one of them dynamic.
fn touching_points(
    manifolds: &[Manifold],
    bodies: &BodySet,
    free: impl Fn(usize) -> bool,
    out: &mut Vec<Point>,
) {
    out.clear();
    let takes_part = |i: usize| match bodies.kind[i] {
        BodyKind::Dynamic => bodies.awake[i],
        BodyKind::Kinematic | BodyKind::Fixed => true,
    };
    for m in manifolds {
        let (a, b) = (m.a as usize, m.b as usize);
        if !free(a) || !free(b) || !takes_part(a) || !takes_part(b) {
            continue;
        }
        if bodies.inv_mass[a] == 0.0 && bodies.inv_mass[b] == 0.0 {
            continue;
        }
        let e = bodies
            .part_material(a, m.part_a)
            .pair_restitution(&bodies.part_material(b, m.part_b));
        if e <= 0.0 {
            continue;
        }
        // One impact per manifold, at the centroid of its touching points: a face resting
        // flat takes its impact without the spin one corner's would give it.
        let touching = m.points[..m.len]
            .iter()
            .filter(|cp| cp.separation <= LINEAR_SLOP);
        let (sum, count) = touching.fold((V3::zeros(), 0usize), |(s, c), cp| (s + cp.point, c + 1));
        if count == 0 {
            continue;
        }
        let point = sum / count as f64;
        let ra = point - bodies.pos[a];
        let rb = point - bodies.pos[b];
        let (ca, cb) = (ra.cross(&m.normal), rb.cross(&m.normal));
        let k = bodies.inv_mass[a]
            + bodies.inv_mass[b]
            + ca.dot(&(bodies.inv_inertia_world[a] * ca))
            + cb.dot(&(bodies.inv_inertia_world[b] * cb));
        if k > 0.0 && k.is_finite() {
            out.push(Point {
                a,
                b,
                n: m.normal,
                ra,
                rb,
                k,
                e: e.min(1.0),
            });
        }
    }
}

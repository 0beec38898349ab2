//! Narrow phase: contact manifolds for the broad phase's pairs, persistent across steps.
//!
//! Manifolds are kept sorted by pair key, so last step's manifold of a pair is found by a
//! merge walk (no hashing, no allocation: two buffers swap). A new point inherits the
//! accumulated impulses of the old point whose anchor (in body A's frame) is within
//! [`MATCH_DISTANCE`], which warm-starts the solver. Pairs of two bodies that are both asleep
//! keep their manifold unchanged.

use super::box_box::{box_box, BoxPose};
use super::primitives as p;
use super::{Manifold, Shape, M3, V3};
use crate::dynamics::BodySet;

/// Anchors closer than this (m, body A frame) are the same contact point across steps.
pub const MATCH_DISTANCE: f64 = 0.05;

/// Counts of one narrow-phase update.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct NarrowCounts {
    /// Pairs given to a contact routine.
    pub pairs_tested: usize,
    /// Manifolds with at least one point.
    pub manifolds: usize,
    /// Contact points in all manifolds.
    pub contacts: usize,
    /// Pairs of shapes with no contact routine (cylinder against box, capsule or cylinder).
    pub unsupported: usize,
}

/// The narrow phase and its persistent manifolds.
#[derive(Clone, Debug, Default)]
pub struct NarrowPhase {
    /// Manifolds of the last update, sorted by pair key.
    pub manifolds: Vec<Manifold>,
    old: Vec<Manifold>,
}

fn rank(s: &Shape) -> u8 {
    match s {
        Shape::HalfSpace { .. } => 0,
        Shape::Cuboid { .. } => 1,
        Shape::Capsule { .. } => 2,
        Shape::Cylinder { .. } => 3,
        Shape::Sphere { .. } => 4,
    }
}

/// Contact between two posed shapes with `rank(sa) ≤ rank(sb)`; the normal from a to b.
/// `None` when the pair has no routine.
#[allow(clippy::too_many_arguments)]
pub fn collide(
    sa: &Shape,
    ra: &M3,
    pa: &V3,
    sb: &Shape,
    rb: &M3,
    pb: &V3,
    margin: f64,
    out: &mut Manifold,
) -> Option<bool> {
    use Shape::*;
    out.len = 0;
    let hit = match (*sa, *sb) {
        (HalfSpace { normal }, b) => {
            let n = ra * normal;
            let o = n.dot(pa);
            match b {
                HalfSpace { .. } => false,
                Cuboid { half } => p::plane_box(&n, o, rb, pb, &half, margin, out),
                Sphere { radius } => p::plane_sphere(&n, o, pb, radius, margin, out),
                Capsule {
                    radius,
                    half_height,
                } => p::plane_capsule(&n, o, rb, pb, radius, half_height, margin, out),
                Cylinder {
                    radius,
                    half_height,
                } => p::plane_cylinder(&n, o, rb, pb, radius, half_height, margin, out),
            }
        }
        (Cuboid { half: ha }, Cuboid { half: hb }) => box_box(
            BoxPose {
                r: ra,
                p: pa,
                half: &ha,
            },
            BoxPose {
                r: rb,
                p: pb,
                half: &hb,
            },
            margin,
            out,
        ),
        (Cuboid { half }, Sphere { radius }) => {
            p::box_sphere(ra, pa, &half, pb, radius, margin, out)
        }
        (
            Cuboid { half },
            Capsule {
                radius,
                half_height,
            },
        ) => p::box_capsule(ra, pa, &half, rb, pb, radius, half_height, margin, out),
        (
            Capsule {
                radius: r1,
                half_height: h1,
            },
            Capsule {
                radius: r2,
                half_height: h2,
            },
        ) => p::capsule_capsule(ra, pa, r1, h1, rb, pb, r2, h2, margin, out),
        (
            Capsule {
                radius,
                half_height,
            },
            Sphere { radius: rs },
        ) => p::capsule_sphere(ra, pa, radius, half_height, pb, rs, margin, out),
        (
            Cylinder {
                radius,
                half_height,
            },
            Sphere { radius: rs },
        ) => p::cylinder_sphere(ra, pa, radius, half_height, pb, rs, margin, out),
        (Sphere { radius: r1 }, Sphere { radius: r2 }) => {
            p::sphere_sphere(pa, r1, pb, r2, margin, out)
        }
        (
            Cuboid { half },
            Cylinder {
                radius,
                half_height,
            },
        ) => p::probe_pair(
            &p::Probe::Cuboid(ra, pa, &half),
            &p::Probe::Cylinder(rb, pb, radius, half_height),
            margin,
            out,
        ),
        (
            Capsule {
                radius: r1,
                half_height: h1,
            },
            Cylinder {
                radius: r2,
                half_height: h2,
            },
        ) => p::probe_pair(
            &p::Probe::Capsule(ra, pa, r1, h1),
            &p::Probe::Cylinder(rb, pb, r2, h2),
            margin,
            out,
        ),
        (
            Cylinder {
                radius: r1,
                half_height: h1,
            },
            Cylinder {
                radius: r2,
                half_height: h2,
            },
        ) => p::probe_pair(
            &p::Probe::Cylinder(ra, pa, r1, h1),
            &p::Probe::Cylinder(rb, pb, r2, h2),
            margin,
            out,
        ),
        _ => return None,
    };
    Some(hit)
}

impl NarrowPhase {
    /// Recomputes the manifolds of `pairs` (sorted keys). `margin(a, b)` is the speculative
    /// distance (m) of a pair: contacts up to that separation are kept.
    pub fn update(
        &mut self,
        bodies: &BodySet,
        pairs: &[u64],
        margin: impl Fn(usize, usize) -> f64,
    ) -> NarrowCounts {
        std::mem::swap(&mut self.manifolds, &mut self.old);
        self.manifolds.clear();
        let mut counts = NarrowCounts::default();
        let mut oi = 0;
        for &k in pairs {
            while oi < self.old.len() && self.old[oi].key() < k {
                oi += 1;
            }
            let old = (oi < self.old.len() && self.old[oi].key() == k).then(|| &self.old[oi]);
            let (a, b) = ((k >> 32) as usize, (k & 0xffff_ffff) as usize);
            if !bodies.awake[a] && !bodies.awake[b] {
                if let Some(o) = old {
                    self.manifolds.push(*o);
                    counts.manifolds += 1;
                    counts.contacts += o.len;
                }
                continue;
            }
            counts.pairs_tested += 1;
            let mut m = Manifold::new(a as u32, b as u32);
            let (sa, sb) = (&bodies.shape[a], &bodies.shape[b]);
            let swap = rank(sa) > rank(sb);
            let (i, j) = if swap { (b, a) } else { (a, b) };
            let hit = collide(
                &bodies.shape[i],
                &bodies.rot[i],
                &bodies.pos[i],
                &bodies.shape[j],
                &bodies.rot[j],
                &bodies.pos[j],
                margin(a, b),
                &mut m,
            );
            let Some(hit) = hit else {
                counts.unsupported += 1;
                continue;
            };
            if !hit || m.len == 0 {
                continue;
            }
            if swap {
                m.normal = -m.normal;
            }
            let (ra, pa) = (&bodies.rot[a], &bodies.pos[a]);
            let normal_kept = old.is_some_and(|o| o.normal.dot(&m.normal) > 0.95);
            for c in m.points[..m.len].iter_mut() {
                c.local_a = ra.tr_mul(&(c.point - pa));
                if let (Some(o), true) = (old, normal_kept) {
                    let mut best = MATCH_DISTANCE * MATCH_DISTANCE;
                    for q in o.points() {
                        let d2 = (q.local_a - c.local_a).norm_squared();
                        if d2 < best {
                            best = d2;
                            c.normal_impulse = q.normal_impulse;
                            c.tangent_impulse = q.tangent_impulse;
                        }
                    }
                }
            }
            if normal_kept {
                m.rolling_impulse = old.map_or(V3::zeros(), |o| o.rolling_impulse);
            }
            counts.manifolds += 1;
            counts.contacts += m.len;
            self.manifolds.push(m);
        }
        counts
    }

    /// Forgets every manifold.
    pub fn clear(&mut self) {
        self.manifolds.clear();
        self.old.clear();
    }
}

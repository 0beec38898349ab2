//! Narrow phase: contact manifolds for the broad phase's pairs, persistent across steps.
//!
//! Manifolds are kept sorted by pair key, so last step's manifold of a pair is found by a
//! merge walk (no hashing, no allocation: two buffers swap). A new point inherits the
//! accumulated impulses of the old point whose anchor (in body A's frame) is within
//! [`MATCH_DISTANCE`], which warm-starts the solver. Pairs of two bodies that are both asleep
//! keep their manifold unchanged.
//!
//! A compound body is tested part by part: each part of one body against each part of the
//! other whose boxes overlap, one manifold per touching pair of parts, ordered by
//! [`Manifold::part_key`] within the body pair.

use super::box_box::{box_box, BoxPose};
use super::manifold_refresh;
use super::posed_part::PosedPart;
use super::primitives as p;
use super::{Aabb, CollisionBodies, Manifold, Shape, M3, V3};

/// Anchors closer than this (m, body A frame) are the same contact point across steps.
pub(crate) const MATCH_DISTANCE: f64 = 0.05;

/// Counts of one narrow-phase update.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(crate) struct NarrowCounts {
    /// Pairs given to a contact routine.
    pub(crate) pairs_tested: usize,
    /// Pairs whose last manifold was moved with the bodies instead (`manifold_refresh`).
    pub(crate) refreshed: usize,
    /// Manifolds with at least one point.
    pub(crate) manifolds: usize,
    /// Contact points in all manifolds.
    pub(crate) contacts: usize,
    /// Pairs of shapes with no contact routine (two half-spaces).
    pub(crate) unsupported: usize,
}

/// The narrow phase and its persistent manifolds.
#[derive(Clone, Debug, Default)]
pub struct NarrowPhase {
    /// Manifolds of the last update, sorted by pair key.
    pub(crate) manifolds: Vec<Manifold>,
    old: Vec<Manifold>,
    /// The compounds' parts posed in the world for the current update.
    posed: PosedParts,
}

/// A compound's part posed in the world, with its box.
#[derive(Clone, Copy, Debug)]
struct PosedBox {
    index: u16,
    rot: M3,
    pos: V3,
    aabb: Aabb,
    /// How far the part can move over the step (m).
    sweep: f64,
    /// A half-space's world normal and offset `n · x ≤ offset` (its box is all of space).
    plane: Option<(V3, f64)>,
    /// A box's half extents (m, along `rot`'s columns).
    half: Option<V3>,
}

/// Slots the in-place update makes when a new contact finds none free
/// (`NarrowPhase::update_in_place`): this many, or one per this many pairs where that is more.
/// A resting pyramid of 8 555 pairs gains some 30–60 contacts a step as it loses as many.
const ROOM: usize = 64;

/// The bodies' velocities over the step, for the margins of continuous collision.
#[derive(Clone, Copy, Debug)]
pub struct BodyMotion<'a> {
    /// The step (s).
    pub(crate) dt: f64,
    /// Velocity of each body's origin, world (m/s).
    pub(crate) vel: &'a [V3],
    /// Angular velocity of each body, world (rad/s).
    pub(crate) omega: &'a [V3],
}

impl BodyMotion<'_> {
    /// How far any point within `radius` of world point `centre` on body `i` moves over the
    /// step (m): `dt (|v + ω × (centre − origin)| + |ω| radius)`.
    pub(crate) fn sweep(
        &self,
        bodies: &CollisionBodies<'_>,
        i: usize,
        centre: &V3,
        radius: f64,
    ) -> f64 {
        let (v, w) = (self.vel[i], self.omega[i]);
        self.dt * ((v + w.cross(&(centre - bodies.pos[i]))).norm() + w.norm() * radius)
    }
}

impl PosedBox {
    /// Whether the two parts' boxes come within `margin` (m) of each other; against a
    /// half-space, whether the other box comes within `margin` of its plane.
    fn meets(&self, other: &PosedBox, margin: f64) -> bool {
        let below = |(n, offset): (V3, f64), b: &Aabb| {
            let c = (b.min + b.max) * 0.5;
            let e = (b.max - b.min) * 0.5;
            n.dot(&c) - n.abs().dot(&e) <= offset + margin
        };
        match (self.plane, other.plane) {
            (Some(p), _) => below(p, &other.aabb),
            (None, Some(p)) => below(p, &self.aabb),
            (None, None) => {
                self.aabb.loosened(margin).overlaps(&other.aabb)
                    && !self.box_clears(&other.aabb, margin)
                    && !other.box_clears(&self.aabb, margin)
            }
        }
    }

    /// Whether this part is a box that stays farther than `margin` (m) from all of
    /// `aabb` along one of its own axes: a turned box (a corner ramp) whose axis-aligned
    /// box covers parts its faces are far from.
    fn box_clears(&self, aabb: &Aabb, margin: f64) -> bool {
        let Some(half) = self.half else {
            return false;
        };
        let d = (aabb.min + aabb.max) * 0.5 - self.pos;
        let e = (aabb.max - aabb.min) * 0.5;
        (0..3).any(|i| {
            let u = self.rot.column(i);
            u.dot(&d).abs() > half[i] + u.abs().dot(&e) + margin
        })
    }

    fn posed<'a>(&self, shape: &'a Shape) -> PosedPart<'a> {
        PosedPart {
            index: self.index,
            shape: part_shape(shape, self.index),
            rot: self.rot,
            pos: self.pos,
        }
    }
}

/// Posed parts of the bodies met so far in one update: body `i`'s are
/// `parts[range[i].0..range[i].1]`, posed on first use.
#[derive(Clone, Debug, Default)]
struct PosedParts {
    range: Vec<(u32, u32)>,
    parts: Vec<PosedBox>,
}

/// A body whose parts are not posed yet in this update.
const NOT_POSED: (u32, u32) = (u32::MAX, u32::MAX);

impl PosedParts {
    fn reset(&mut self, bodies: usize) {
        self.range.clear();
        self.range.resize(bodies, NOT_POSED);
        self.parts.clear();
    }

    /// The index range of body `i`'s posed parts, posing them first if needed;
    /// `sweep(i, centre, radius)` is how far a part of body `i` moves over the step (m).
    fn parts_of(
        &mut self,
        bodies: &CollisionBodies<'_>,
        i: usize,
        sweep: &impl Fn(usize, &V3, f64) -> f64,
    ) -> std::ops::Range<usize> {
        if self.range[i] == NOT_POSED {
            let start = self.parts.len() as u32;
            let parts = &mut self.parts;
            for_each_part(bodies, i, |p| {
                parts.push(PosedBox {
                    index: p.index,
                    rot: p.rot,
                    pos: p.pos,
                    aabb: p.shape.aabb(&p.rot, &p.pos),
                    sweep: sweep(i, &p.pos, p.shape.bounding_radius()),
                    plane: match *p.shape {
                        Shape::HalfSpace { normal } => {
                            let n = p.rot * normal;
                            Some((n, n.dot(&p.pos)))
                        }
                        _ => None,
                    },
                    half: match *p.shape {
                        Shape::Cuboid { half } => Some(half),
                        _ => None,
                    },
                });
            });
            self.range[i] = (start, self.parts.len() as u32);
        }
        let (s, e) = self.range[i];
        s as usize..e as usize
    }
}

fn rank(s: &Shape) -> u8 {
    match s {
        Shape::HalfSpace { .. } => 0,
        Shape::Cuboid { .. } => 1,
        Shape::Capsule { .. } => 2,
        Shape::Cylinder { .. } => 3,
        Shape::Sphere { .. } => 4,
        Shape::Compound(_) => 5,
    }
}

/// Contact between two posed primitive shapes with `rank(sa) ≤ rank(sb)` (half-space, box,
/// capsule, cylinder, sphere); the normal from a to b. `None` when the pair has no routine
/// (two half-spaces, or a compound: the narrow phase splits those into their parts).
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
    let hit = match (sa, sb) {
        (&HalfSpace { normal }, b) => {
            let n = ra * normal;
            let o = n.dot(pa);
            match *b {
                HalfSpace { .. } => false,
                Compound(_) => return None,
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
        (&Cuboid { half: ha }, &Cuboid { half: hb }) => box_box(
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
        (&Cuboid { half }, &Sphere { radius }) => {
            p::box_sphere(ra, pa, &half, pb, radius, margin, out)
        }
        (
            &Cuboid { half },
            &Capsule {
                radius,
                half_height,
            },
        ) => p::box_capsule(ra, pa, &half, rb, pb, radius, half_height, margin, out),
        (
            &Capsule {
                radius: r1,
                half_height: h1,
            },
            &Capsule {
                radius: r2,
                half_height: h2,
            },
        ) => p::capsule_capsule(ra, pa, r1, h1, rb, pb, r2, h2, margin, out),
        (
            &Capsule {
                radius,
                half_height,
            },
            &Sphere { radius: rs },
        ) => p::capsule_sphere(ra, pa, radius, half_height, pb, rs, margin, out),
        (
            &Cylinder {
                radius,
                half_height,
            },
            &Sphere { radius: rs },
        ) => p::cylinder_sphere(ra, pa, radius, half_height, pb, rs, margin, out),
        (&Sphere { radius: r1 }, &Sphere { radius: r2 }) => {
            p::sphere_sphere(pa, r1, pb, r2, margin, out)
        }
        (
            &Cuboid { half },
            &Cylinder {
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
            &Capsule {
                radius: r1,
                half_height: h1,
            },
            &Cylinder {
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
            &Cylinder {
                radius: r1,
                half_height: h1,
            },
            &Cylinder {
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

/// Part `index` of a shape: a compound's part, or the shape itself.
fn part_shape(shape: &Shape, index: u16) -> &Shape {
    match shape {
        Shape::Compound(c) => &c.parts()[index as usize].shape,
        s => s,
    }
}

/// Calls `f` with each primitive of body `i`: the shape itself, or each part of a compound.
#[inline]
fn for_each_part(bodies: &CollisionBodies<'_>, i: usize, mut f: impl FnMut(PosedPart<'_>)) {
    let (r, p) = (&bodies.rot[i], &bodies.pos[i]);
    match &bodies.shape[i] {
        Shape::Compound(c) => {
            for (k, part) in c.parts().iter().enumerate() {
                f(PosedPart {
                    index: k as u16,
                    shape: &part.shape,
                    rot: r * part.rot,
                    pos: p + r * part.pos,
                });
            }
        }
        s => f(PosedPart {
            index: 0,
            shape: s,
            rot: *r,
            pos: *p,
        }),
    }
}

impl NarrowPhase {
    /// Recomputes the manifolds of `pairs` (sorted keys). Contacts up to the speculative
    /// distance `speculative` (m), grown by each side's [`CollisionBodies::travel`], are kept; with `motion` (continuous collision) a pair's
    /// distance grows by how far each side can move over the step: for each part of a
    /// compound, by its own motion (a rod's bar spinning in its wall slot moves by the bar's
    /// radius times the turn, not by its men's reach).
    pub(crate) fn update(
        &mut self,
        bodies: &CollisionBodies<'_>,
        pairs: &[u64],
        speculative: f64,
        motion: Option<BodyMotion<'_>>,
    ) -> NarrowCounts {
        self.posed.reset(bodies.len());
        let mut counts = NarrowCounts::default();
        let done = if motion.is_none() {
            self.update_in_place(bodies, pairs, speculative, &mut counts)
        } else {
            std::mem::swap(&mut self.manifolds, &mut self.old);
            self.manifolds.clear();
            0
        };
        self.update_from_old(bodies, &pairs[done..], speculative, motion, &mut counts);
        counts
    }

    /// The first pairs of `pairs` updated in place, without continuous collision, while
    /// each holds one manifold at most and no compound: each of last step's manifolds is
    /// recomputed, or its points moved, where it lies, moved down over those of pairs that
    /// parted; a new contact ahead of every parted one makes room by moving the manifolds
    /// not read yet up ([`ROOM`]). At a compound, or a pair of several manifolds, the
    /// manifolds not read yet go to `old` and the number of pairs done is returned, for
    /// [`Self::update_from_old`] to go on. The same manifolds as that general update alone,
    /// without its copy of every manifold from last step's array into this step's.
    fn update_in_place(
        &mut self,
        bodies: &CollisionBodies<'_>,
        pairs: &[u64],
        speculative: f64,
        counts: &mut NarrowCounts,
    ) -> usize {
        let mut n_old = self.manifolds.len();
        // `oi`: last step's first manifold not read yet; `kept`: this step's so far
        // (`kept` ≤ `oi`, so no manifold not read yet is written over).
        let (mut oi, mut kept) = (0, 0);
        for (p, &k) in pairs.iter().enumerate() {
            while oi < n_old && self.manifolds[oi].key() < k {
                oi += 1;
            }
            let has_old = oi < n_old && self.manifolds[oi].key() == k;
            let (a, b) = ((k >> 32) as usize, (k & 0xffff_ffff) as usize);
            let compound = matches!(bodies.shape[a], Shape::Compound(_))
                || matches!(bodies.shape[b], Shape::Compound(_));
            let more_old = has_old && oi + 1 < n_old && self.manifolds[oi + 1].key() == k;
            if compound || more_old {
                self.old.clear();
                self.old.extend_from_slice(&self.manifolds[oi..n_old]);
                self.manifolds.truncate(kept);
                return p;
            }
            if !has_old && kept == oi && oi < n_old {
                // A new contact ahead of every parted one: the manifolds not read yet move up
                // by `room` slots (one move of the rest, not a copy of each).
                let room = ROOM.max(pairs.len() / ROOM);
                self.manifolds.resize(n_old + room, Manifold::new(0, 0));
                self.manifolds.copy_within(oi..n_old, oi + room);
                oi += room;
                n_old += room;
            }
            let asleep = !bodies.awake[a] && !bodies.awake[b];
            let posed = |i: usize| PosedPart {
                index: 0,
                shape: &bodies.shape[i],
                rot: bodies.rot[i],
                pos: bodies.pos[i],
            };
            let (pa, pb) = (posed(a), posed(b));
            // A fast body's contacts reach as far as it travels in the step, and are collided
            // afresh every step (never refreshed from last step's points).
            let travel = bodies.travel(a) + bodies.travel(b);
            let margin = speculative + travel;
            let reach = (travel == 0.0)
                .then(|| manifold_refresh::reach(&bodies.shape[a], &bodies.shape[b], speculative))
                .flatten();
            let origin = match reach {
                Some(reach) if has_old && !asleep => {
                    manifold_refresh::within_reach(&self.manifolds[oi], &pa, &pb, reach)
                }
                _ => None,
            };
            if has_old && (asleep || origin.is_some()) {
                if kept != oi {
                    self.manifolds[kept] = self.manifolds[oi];
                }
                let m = &mut self.manifolds[kept];
                if let Some(origin) = origin {
                    manifold_refresh::move_points(m, &origin, &pa, &pb);
                    counts.refreshed += 1;
                }
                counts.manifolds += 1;
                counts.contacts += m.len;
                kept += 1;
                oi += 1;
                continue;
            }
            let old = if has_old {
                std::slice::from_ref(&self.manifolds[oi])
            } else {
                &[]
            };
            let contact = if asleep {
                None
            } else {
                Self::contact(bodies, a, &pa, b, &pb, margin, old, counts)
            };
            if let Some(mut m) = contact {
                if reach.is_some() {
                    manifold_refresh::record(&mut m, &pa, &pb);
                }
                if kept < self.manifolds.len() {
                    self.manifolds[kept] = m;
                } else {
                    self.manifolds.push(m);
                }
                kept += 1;
            }
            if has_old {
                oi += 1;
            }
        }
        self.manifolds.truncate(kept);
        self.old.clear();
        pairs.len()
    }

    /// Updates `pairs` (the rest of [`Self::update`]'s) from last step's manifolds in `old`,
    /// appending this step's to `manifolds`.
    fn update_from_old(
        &mut self,
        bodies: &CollisionBodies<'_>,
        pairs: &[u64],
        speculative: f64,
        motion: Option<BodyMotion<'_>>,
        counts: &mut NarrowCounts,
    ) {
        let sweep = |i: usize, centre: &V3, radius: f64| {
            motion
                .as_ref()
                .map_or(0.0, |m| m.sweep(bodies, i, centre, radius))
        };
        let mut oi = 0;
        for &k in pairs {
            while oi < self.old.len() && self.old[oi].key() < k {
                oi += 1;
            }
            let first_old = oi;
            while oi < self.old.len() && self.old[oi].key() == k {
                oi += 1;
            }
            let old = &self.old[first_old..oi];
            let (a, b) = ((k >> 32) as usize, (k & 0xffff_ffff) as usize);
            if !bodies.awake[a] && !bodies.awake[b] {
                for o in old {
                    self.manifolds.push(*o);
                    counts.manifolds += 1;
                    counts.contacts += o.len;
                }
                continue;
            }
            let compound = matches!(bodies.shape[a], Shape::Compound(_))
                || matches!(bodies.shape[b], Shape::Compound(_));
            if !compound {
                let pa = PosedPart {
                    index: 0,
                    shape: &bodies.shape[a],
                    rot: bodies.rot[a],
                    pos: bodies.pos[a],
                };
                let pb = PosedPart {
                    index: 0,
                    shape: &bodies.shape[b],
                    rot: bodies.rot[b],
                    pos: bodies.pos[b],
                };
                let travel = bodies.travel(a) + bodies.travel(b);
                let reach = (motion.is_none() && travel == 0.0)
                    .then(|| {
                        manifold_refresh::reach(&bodies.shape[a], &bodies.shape[b], speculative)
                    })
                    .flatten();
                if let (Some(reach), [o]) = (reach, old) {
                    if let Some(origin) = manifold_refresh::within_reach(o, &pa, &pb, reach) {
                        // Moved in place once copied (one copy of the manifold, not two).
                        self.manifolds.push(*o);
                        let m = self.manifolds.last_mut().expect("pushed above");
                        manifold_refresh::move_points(m, &origin, &pa, &pb);
                        counts.refreshed += 1;
                        counts.manifolds += 1;
                        counts.contacts += m.len;
                        continue;
                    }
                }
                let margin = speculative
                    + travel
                    + sweep(a, &bodies.pos[a], bodies.shape[a].bounding_radius())
                    + sweep(b, &bodies.pos[b], bodies.shape[b].bounding_radius());
                if let Some(mut m) = Self::contact(bodies, a, &pa, b, &pb, margin, old, counts) {
                    if reach.is_some() {
                        manifold_refresh::record(&mut m, &pa, &pb);
                    }
                    self.manifolds.push(m);
                }
                continue;
            }
            // Compound pair: every part of A against every part of B whose boxes overlap,
            // in part-key order (A's part, then B's). Each compound's parts are posed and
            // boxed once per update, whatever number of pairs it is in, and a part of A that
            // misses B's box is skipped (a rod's sixteen parts against the field meet only
            // at the men's feet).
            // B's box holds each of its parts grown by the speculative distance and the
            // part's motion, so a part of A grown by its own motion that misses it is out
            // of reach of every part of B.
            let body_b = bodies.aabb[b];
            let (ra, rb) = (
                self.posed.parts_of(bodies, a, &sweep),
                self.posed.parts_of(bodies, b, &sweep),
            );
            let parts = &self.posed.parts;
            let (travel_a, travel_b) = (bodies.travel(a), bodies.travel(b));
            for posed_a in &parts[ra] {
                let grown = posed_a.sweep + travel_a;
                if !posed_a.aabb.loosened(grown).overlaps(&body_b) {
                    continue;
                }
                let pa = posed_a.posed(&bodies.shape[a]);
                for posed_b in &parts[rb.clone()] {
                    let margin = speculative + grown + posed_b.sweep + travel_b;
                    if !posed_a.meets(posed_b, margin) {
                        continue;
                    }
                    let pb = posed_b.posed(&bodies.shape[b]);
                    if let Some(m) = Self::contact(bodies, a, &pa, b, &pb, margin, old, counts) {
                        self.manifolds.push(m);
                    }
                }
            }
        }
    }

    /// The manifold of part `pa` of body `a` against part `pb` of body `b`, with the warm-start
    /// impulses of the matching points of last step's manifold of the same parts.
    #[allow(clippy::too_many_arguments)]
    fn contact(
        bodies: &CollisionBodies<'_>,
        a: usize,
        pa: &PosedPart<'_>,
        b: usize,
        pb: &PosedPart<'_>,
        margin: f64,
        old_of_pair: &[Manifold],
        counts: &mut NarrowCounts,
    ) -> Option<Manifold> {
        counts.pairs_tested += 1;
        let mut m = Manifold::between_parts(a as u32, pa.index, b as u32, pb.index);
        let swap = rank(pa.shape) > rank(pb.shape);
        let (i, j) = if swap { (pb, pa) } else { (pa, pb) };
        let hit = collide(
            i.shape, &i.rot, &i.pos, j.shape, &j.rot, &j.pos, margin, &mut m,
        );
        let Some(hit) = hit else {
            counts.unsupported += 1;
            return None;
        };
        if !hit || m.len == 0 {
            return None;
        }
        if swap {
            m.normal = -m.normal;
        }
        let old = old_of_pair.iter().find(|o| o.part_key() == m.part_key());
        let (ra, pos_a) = (&bodies.rot[a], &bodies.pos[a]);
        let normal_kept = old.is_some_and(|o| o.normal.dot(&m.normal) > 0.95);
        for c in m.points[..m.len].iter_mut() {
            c.local_a = ra.tr_mul(&(c.point - pos_a));
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
        if let (Some(o), true) = (old, normal_kept) {
            m.friction_impulse = o.friction_impulse;
            m.twist_impulse = o.twist_impulse;
            m.held_overlap = o.held_overlap;
        }
        if normal_kept {
            m.rolling_impulse = old.map_or(V3::zeros(), |o| o.rolling_impulse);
            m.impulse_substep = old.map_or(0.0, |o| o.impulse_substep);
        }
        counts.manifolds += 1;
        counts.contacts += m.len;
        Some(m)
    }

    /// Forgets the manifolds (and warm starts) that involve body `a` or body `b`: used when a
    /// body is removed and another moves into its index.
    pub(crate) fn forget_bodies(&mut self, a: usize, b: usize) {
        let (a, b) = (a as u32, b as u32);
        let keep = |m: &Manifold| m.a != a && m.b != a && m.a != b && m.b != b;
        self.manifolds.retain(keep);
        self.old.retain(keep);
    }

    /// Forgets every manifold.
    pub(crate) fn clear(&mut self) {
        self.manifolds.clear();
        self.old.clear();
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::compound::{Compound, Part};
    use std::sync::Arc;

    /// A part as the compound pass poses it, for `meets`.
    fn posed_box(shape: &Shape, rot: M3, pos: V3) -> PosedBox {
        PosedBox {
            index: 0,
            rot,
            pos,
            aabb: shape.aabb(&rot, &pos),
            sweep: 0.0,
            plane: None,
            half: match *shape {
                Shape::Cuboid { half } => Some(half),
                _ => None,
            },
        }
    }

    #[test]
    fn a_turned_box_meets_only_the_parts_near_its_faces() {
        // A long ramp turned 45° about y: its axis-aligned box covers a cube above its top
        // face's middle, which is 0.3 m from the face.
        let ramp = Shape::Cuboid {
            half: V3::new(1.0, 1.0, 0.05),
        };
        let (s, c) = std::f64::consts::FRAC_PI_4.sin_cos();
        let turned = M3::new(c, 0.0, s, 0.0, 1.0, 0.0, -s, 0.0, c);
        let a = posed_box(&ramp, turned, V3::zeros());
        let cube = Shape::Cuboid {
            half: V3::repeat(0.05),
        };
        let normal = turned.column(2).into_owned();
        let far = posed_box(&cube, M3::identity(), normal * 0.4);
        assert!(a.aabb.overlaps(&far.aabb), "the boxes' bounds overlap");
        assert!(!a.meets(&far, 0.01) && !far.meets(&a, 0.01));
        // Within the margin of the face, and touching it: they meet.
        let near = posed_box(&cube, M3::identity(), normal * 0.16);
        assert!(a.meets(&near, 0.05) && near.meets(&a, 0.05));
        assert!(!a.meets(&near, 0.01));
        let touching = posed_box(&cube, M3::identity(), normal * 0.1);
        assert!(a.meets(&touching, 0.0));
        // A sphere's part is no box: only its bound is used.
        let ball = Shape::Sphere { radius: 0.05 };
        assert!(!a.meets(&posed_box(&ball, M3::identity(), normal * 0.4), 0.01));
    }

    /// Unit boxes along x about 1 m apart, jittered step by step so that neighbours touch,
    /// part and touch again; one body in four asleep on some steps, and a compound last.
    struct Row {
        shape: Vec<Shape>,
        rot: Vec<M3>,
        pos: Vec<V3>,
        aabb: Vec<Aabb>,
        awake: Vec<bool>,
        responds: Vec<bool>,
    }

    impl Row {
        fn new(n: usize) -> Self {
            let unit = Shape::Cuboid {
                half: V3::new(0.5, 0.5, 0.5),
            };
            let mut shape = vec![unit.clone(); n];
            let part = |x: f64| Part {
                shape: unit.clone(),
                rot: M3::identity(),
                pos: V3::new(x, 0.0, 0.0),
                material: Default::default(),
            };
            let compound = Compound::from_parts(vec![part(-0.25), part(0.25)]).unwrap();
            shape[n - 1] = Shape::Compound(Arc::new(compound));
            Self {
                shape,
                rot: vec![M3::identity(); n],
                pos: vec![V3::zeros(); n],
                aabb: vec![
                    Aabb {
                        min: V3::zeros(),
                        max: V3::zeros()
                    };
                    n
                ],
                awake: vec![true; n],
                responds: vec![true; n],
            }
        }

        fn pose(&mut self, step: u64) {
            let mut seed = 0x9e37_79b9_7f4a_7c15_u64 ^ step;
            for i in 0..self.pos.len() {
                seed ^= seed << 13;
                seed ^= seed >> 7;
                seed ^= seed << 17;
                let jitter = (seed >> 11) as f64 / (1u64 << 53) as f64 - 0.5;
                // Gaps of −1 cm to +1 cm: within and beyond the speculative distance.
                self.pos[i] = V3::new(
                    i as f64 * (1.0 + 0.02 * jitter) + 0.001 * step as f64,
                    0.0,
                    0.0,
                );
                self.awake[i] = !(step % 3 == 1 && i % 4 == 2);
                self.aabb[i] = self.shape[i]
                    .aabb(&self.rot[i], &self.pos[i])
                    .loosened(0.02);
            }
        }

        fn view(&self) -> CollisionBodies<'_> {
            CollisionBodies {
                shape: &self.shape,
                rot: &self.rot,
                pos: &self.pos,
                aabb: &self.aabb,
                awake: &self.awake,
                responds: &self.responds,
                travel: &[],
            }
        }
    }

    #[test]
    fn the_in_place_update_gives_the_manifolds_of_the_general_one() {
        let n = 40;
        let mut row = Row::new(n);
        // Every pair of neighbours and next neighbours: a broad phase's superset.
        let pairs: Vec<u64> = (0..n as u64)
            .flat_map(|i| (i + 1..(i + 3).min(n as u64)).map(move |j| i << 32 | j))
            .collect();
        let (mut in_place, mut general) = (NarrowPhase::default(), NarrowPhase::default());
        let (mut made_room, mut parted) = (false, false);
        for step in 0..60 {
            row.pose(step);
            let before = in_place.manifolds.len();
            let a = in_place.update(&row.view(), &pairs, 0.005, None);
            std::mem::swap(&mut general.manifolds, &mut general.old);
            general.manifolds.clear();
            general.posed.reset(n);
            let mut b = NarrowCounts::default();
            general.update_from_old(&row.view(), &pairs, 0.005, None, &mut b);
            assert_eq!(a, b, "step {step}");
            assert_eq!(in_place.manifolds, general.manifolds, "step {step}");
            made_room |= in_place.manifolds.len() > before;
            parted |= in_place.manifolds.len() < before;
        }
        // The steps made contacts and parted them.
        assert!(made_room && parted);
    }
}

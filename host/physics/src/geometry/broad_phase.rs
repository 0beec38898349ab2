//! Broad phase: a uniform grid hashed by cell, rebuilt each step without allocating (the
//! buffers keep their capacity). Half-spaces and bodies whose box covers too many cells are
//! tested against every other body instead.
//!
//! Each candidate pair is reported once: only in the cell holding the lower corner of the two
//! boxes' intersection. Output: sorted pair keys `a << 32 | b`, `a < b`.

use super::{Aabb, Shape};
use crate::dynamics::{BodyKind, BodySet};

/// Most cells one body may cover before it is treated as oversized.
const MAX_CELLS_PER_BODY: i64 = 64;

/// The grid broad phase.
#[derive(Clone, Debug)]
pub struct BroadPhase {
    /// Cell edge (m).
    pub cell: f64,
    entries: Vec<(u64, u32)>,
    oversized: Vec<u32>,
    /// Candidate pairs of the last update, sorted keys `a << 32 | b`.
    pub pairs: Vec<u64>,
}

#[inline]
fn cell_of(x: f64, inv: f64) -> i64 {
    (x * inv).floor() as i64
}

#[inline]
fn key(ix: i64, iy: i64, iz: i64) -> u64 {
    let m = (1u64 << 21) - 1;
    ((ix as u64) & m) | (((iy as u64) & m) << 21) | (((iz as u64) & m) << 42)
}

impl BroadPhase {
    /// A grid sized for the bodies: cells twice the median body diameter.
    pub fn new(bodies: &BodySet) -> Self {
        let mut d: Vec<f64> = bodies
            .shape
            .iter()
            .filter(|s| !s.is_half_space())
            .map(|s| 2.0 * s.bounding_radius())
            .collect();
        d.sort_by(f64::total_cmp);
        let median = d.get(d.len() / 2).copied().unwrap_or(1.0);
        Self {
            cell: (2.0 * median).max(0.05),
            entries: Vec::new(),
            oversized: Vec::new(),
            pairs: Vec::new(),
        }
    }

    /// Recomputes `pairs` from the bodies' `aabb`. Pairs of two non-dynamic bodies, of two
    /// bodies that are both not awake, and pairs in `excluded` (sorted keys) are skipped.
    /// Returns the number of box–box overlap tests made.
    pub fn update(&mut self, bodies: &BodySet, excluded: &[u64]) -> usize {
        self.entries.clear();
        self.oversized.clear();
        self.pairs.clear();
        let inv = 1.0 / self.cell;
        for i in 0..bodies.len() {
            if matches!(bodies.shape[i], Shape::HalfSpace { .. }) {
                self.oversized.push(i as u32);
                continue;
            }
            let b = &bodies.aabb[i];
            let (x0, y0, z0) = (
                cell_of(b.min.x, inv),
                cell_of(b.min.y, inv),
                cell_of(b.min.z, inv),
            );
            let (x1, y1, z1) = (
                cell_of(b.max.x, inv),
                cell_of(b.max.y, inv),
                cell_of(b.max.z, inv),
            );
            let n = (x1 - x0 + 1) * (y1 - y0 + 1) * (z1 - z0 + 1);
            if !(1..=MAX_CELLS_PER_BODY).contains(&n) {
                self.oversized.push(i as u32);
                continue;
            }
            for x in x0..=x1 {
                for y in y0..=y1 {
                    for z in z0..=z1 {
                        self.entries.push((key(x, y, z), i as u32));
                    }
                }
            }
        }
        self.entries.sort_unstable();
        let mut tests = 0;
        let mut s = 0;
        while s < self.entries.len() {
            let k = self.entries[s].0;
            let mut e = s + 1;
            while e < self.entries.len() && self.entries[e].0 == k {
                e += 1;
            }
            for u in s..e {
                let a = self.entries[u].1 as usize;
                for v in u + 1..e {
                    let b = self.entries[v].1 as usize;
                    if !Self::wanted(bodies, a, b) {
                        continue;
                    }
                    tests += 1;
                    let (ba, bb) = (&bodies.aabb[a], &bodies.aabb[b]);
                    if !ba.overlaps(bb) {
                        continue;
                    }
                    // Report in the cell of the intersection's lower corner only.
                    let lo = ba.min.sup(&bb.min);
                    if key(cell_of(lo.x, inv), cell_of(lo.y, inv), cell_of(lo.z, inv)) != k {
                        continue;
                    }
                    self.push_pair(a, b, excluded);
                }
            }
            s = e;
        }
        // Oversized bodies and half-spaces against everything.
        for oi in 0..self.oversized.len() {
            let o = self.oversized[oi] as usize;
            let half_space = bodies.shape[o].is_half_space();
            for b in 0..bodies.len() {
                if b == o || !Self::wanted(bodies, o, b) {
                    continue;
                }
                // Two oversized bodies: only once.
                if self.oversized.contains(&(b as u32)) && b < o {
                    continue;
                }
                tests += 1;
                let hit = if half_space {
                    half_space_overlaps(bodies, o, &bodies.aabb[b])
                } else if bodies.shape[b].is_half_space() {
                    half_space_overlaps(bodies, b, &bodies.aabb[o])
                } else {
                    bodies.aabb[o].overlaps(&bodies.aabb[b])
                };
                if hit {
                    self.push_pair(o, b, excluded);
                }
            }
        }
        self.pairs.sort_unstable();
        tests
    }

    #[inline]
    fn wanted(bodies: &BodySet, a: usize, b: usize) -> bool {
        (bodies.kind[a] == BodyKind::Dynamic || bodies.kind[b] == BodyKind::Dynamic)
            && (bodies.awake[a] || bodies.awake[b])
    }

    #[inline]
    fn push_pair(&mut self, a: usize, b: usize, excluded: &[u64]) {
        let (a, b) = if a < b { (a, b) } else { (b, a) };
        let k = ((a as u64) << 32) | b as u64;
        if excluded.binary_search(&k).is_err() {
            self.pairs.push(k);
        }
    }
}

/// Whether the box reaches into the half-space of body `h`.
fn half_space_overlaps(bodies: &BodySet, h: usize, b: &Aabb) -> bool {
    let Shape::HalfSpace { normal } = bodies.shape[h] else {
        return false;
    };
    let n = bodies.rot[h] * normal;
    let o = n.dot(&bodies.pos[h]);
    let c = (b.min + b.max) * 0.5;
    let e = (b.max - b.min) * 0.5;
    n.dot(&c) - n.abs().dot(&e) <= o
}

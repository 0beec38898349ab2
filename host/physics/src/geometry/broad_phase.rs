//! Broad phase: a uniform grid hashed by cell, rebuilt each step without allocating (the
//! buffers keep their capacity). Half-spaces and bodies whose box covers too many cells are
//! tested against every other body instead. A world of at most [`ALL_PAIRS_BODIES`] bodies
//! (a foosball table: 36) sweeps its boxes along x instead and tests the pairs that overlap
//! along x, which costs less than hashing and sorting the grid's cells.
//!
//! Each candidate pair is reported once: only in the cell holding the lower corner of the two
//! boxes' intersection. Output: sorted pair keys `a << 32 | b`, `a < b`.
//!
//! The grid runs on the bodies' boxes grown by [`REUSE_MARGIN`], and its pairs are kept: while
//! every body's box stays within its grown box (a world at rest, or slow), the pairs whose
//! boxes overlap now are among the kept ones, and the step takes them from those instead of
//! hashing and sorting the grid again (Box2D's fattened boxes, for a grid). The pairs are the
//! same either way.

use super::{Aabb, CollisionBodies, Shape};

/// Worlds of at most this many bodies sweep along x: at most 2 016 box tests of a few ns
/// each, against the grid's hashing and sorting of every cell a body covers (a foosball table's
/// rods span the field and cover some 40 cells each).
pub(crate) const ALL_PAIRS_BODIES: usize = 64;

/// How far (m) a body's box may move out of place before the grid is built again: each
/// body's box is grown by this much for the grid, and while every body's box stays within its
/// grown box the kept pairs are reused. Half Box2D v3's `B2_AABB_MARGIN` (0.1 m).
pub(crate) const REUSE_MARGIN: f64 = 0.05;

/// Most cells one body may cover before it is treated as oversized.
const MAX_CELLS_PER_BODY: i64 = 64;

/// The grid broad phase.
#[derive(Clone, Debug)]
pub struct BroadPhase {
    /// Cell edge (m).
    pub(crate) cell: f64,
    entries: Vec<(u64, u32)>,
    oversized: Vec<u32>,
    /// Candidate pairs of the last update, sorted keys `a << 32 | b`.
    pub pairs: Vec<u64>,
    /// The grid's last build: each body's box grown by [`REUSE_MARGIN`], which bodies
    /// respond to contacts, the excluded pairs, and the pairs of the grown boxes (awake or
    /// not); empty until built.
    grown: Vec<Aabb>,
    grown_responds: Vec<bool>,
    grown_excluded: Vec<u64>,
    grown_pairs: Vec<u64>,
    /// The bodies in order of their boxes' lower x at the last update of a small world.
    sweep_order: Vec<u32>,
    /// The most pairs of grown boxes a grid build gathers before it stops ([`Self::overflowed`]);
    /// the world sets it from its bodies (`MAX_CONTACT_PAIRS_PER_BODY`).
    pub(crate) max_pairs: usize,
    /// Whether the last grid build stopped at [`Self::max_pairs`]: `pairs` is then empty.
    pub(crate) overflowed: bool,
}

/// The cell of coordinate `x`; saturating (`as` clamps to the `i64` range, NaN gives 0), so
/// a distant box never overflows. Cells beyond the key's 21 bits alias nearer ones: that
/// only adds candidates, which the box test then rejects.
#[inline]
fn cell_of(x: f64, inv: f64) -> i64 {
    floor(x * inv) as i64
}

/// `x.floor()` without the library call that baseline x86-64 makes of it (no SSE4.1
/// rounding instruction): through an integer below 2⁵³, the library's own beyond that and
/// for NaN, so a NaN box still fails the cell count.
#[inline]
fn floor(x: f64) -> f64 {
    if x.abs() < 9.0e15 {
        let t = x as i64 as f64;
        if t > x {
            t - 1.0
        } else {
            t
        }
    } else {
        x.floor()
    }
}

/// The lowest and highest cells a box covers, or `None` when it covers more than
/// [`MAX_CELLS_PER_BODY`] cells or is not finite: then it goes on the oversized list. The
/// count is taken in floating point, where it cannot wrap (in integers a 1.6e19 m box wraps
/// it into `1..=64` and the loop over its cells never ends).
#[inline]
fn cell_range(b: &Aabb, inv: f64) -> Option<([i64; 3], [i64; 3])> {
    let mut cells = 1.0;
    for k in 0..3 {
        cells *= floor(b.max[k] * inv) - floor(b.min[k] * inv) + 1.0;
    }
    // NaN fails both comparisons.
    if !(cells >= 1.0 && cells <= MAX_CELLS_PER_BODY as f64) {
        return None;
    }
    let lo = [0, 1, 2].map(|k| cell_of(b.min[k], inv));
    let hi = [0, 1, 2].map(|k| cell_of(b.max[k], inv));
    Some((lo, hi))
}

/// The grid's cell edge (m) for boxes of median diameter `median` (m): twice that, at least
/// 5 cm, at most 1 km (larger boxes are oversized anyway), 1 m when it is not finite.
fn cell_edge(median: f64) -> f64 {
    let cell = 2.0 * median;
    if cell.is_finite() {
        cell.clamp(0.05, 1e3)
    } else {
        1.0
    }
}

#[inline]
fn key(ix: i64, iy: i64, iz: i64) -> u64 {
    let m = (1u64 << 21) - 1;
    ((ix as u64) & m) | (((iy as u64) & m) << 21) | (((iz as u64) & m) << 42)
}

impl BroadPhase {
    /// A grid sized for the shapes: cells twice the median body diameter.
    pub fn new(shapes: &[Shape]) -> Self {
        let mut d: Vec<f64> = shapes
            .iter()
            .filter(|s| !s.is_half_space())
            .map(|s| 2.0 * s.bounding_radius())
            .collect();
        d.sort_by(f64::total_cmp);
        let median = d.get(d.len() / 2).copied().unwrap_or(1.0);
        Self {
            cell: cell_edge(median),
            entries: Vec::new(),
            oversized: Vec::new(),
            pairs: Vec::new(),
            grown: Vec::new(),
            grown_responds: Vec::new(),
            grown_excluded: Vec::new(),
            grown_pairs: Vec::new(),
            sweep_order: Vec::new(),
            max_pairs: usize::MAX,
            overflowed: false,
        }
    }

    /// Recomputes `pairs` from the bodies' `aabb`. Pairs of two bodies that do not respond to
    /// contacts (`responds`), of two bodies that are both not awake, and pairs in `excluded`
    /// (sorted keys) are skipped. With `keep`, the grid's last pairs are reused while every
    /// box stays within its grown box; without, the grid is built every time (the same
    /// pairs). Returns the number of box–box overlap tests made.
    pub fn update(&mut self, bodies: &CollisionBodies<'_>, excluded: &[u64], keep: bool) -> usize {
        self.pairs.clear();
        if bodies.len() <= ALL_PAIRS_BODIES {
            return self.all_pairs(bodies, excluded);
        }
        let mut tests = 0;
        if !keep || !self.still_within(bodies, excluded) {
            self.grown.clear();
            self.grown
                .extend(bodies.aabb.iter().map(|b| b.loosened(REUSE_MARGIN)));
            self.grown_responds.clear();
            self.grown_responds.extend_from_slice(bodies.responds);
            self.grown_excluded.clear();
            self.grown_excluded.extend_from_slice(excluded);
            tests += self.build_grid(bodies);
            if self.overflowed {
                // Nothing kept: the next update builds the grid again.
                self.grown.clear();
                return tests;
            }
        }
        // The pairs whose boxes overlap now, of those of the grown boxes.
        for &k in &self.grown_pairs {
            let (a, b) = ((k >> 32) as usize, (k & 0xffff_ffff) as usize);
            if !Self::wanted(bodies, a, b) {
                continue;
            }
            tests += 1;
            if boxes_meet(bodies, bodies.aabb, a, b) {
                self.pairs.push(k);
            }
        }
        tests
    }

    /// Whether the grid's last build still holds every candidate: the same bodies respond
    /// to contacts, the same pairs are excluded, and every body's box lies within its grown
    /// box.
    fn still_within(&self, bodies: &CollisionBodies<'_>, excluded: &[u64]) -> bool {
        self.grown.len() == bodies.len()
            && self.grown_responds == bodies.responds
            && self.grown_excluded == excluded
            && self
                .grown
                .iter()
                .zip(bodies.aabb)
                .all(|(g, b)| g.contains(b))
    }

    /// Builds the grid on the grown boxes: `grown_pairs`, every pair of them that overlaps,
    /// of bodies one of which responds to contacts, not excluded. Returns the number of box
    /// tests made.
    fn build_grid(&mut self, bodies: &CollisionBodies<'_>) -> usize {
        self.overflowed = false;
        self.entries.clear();
        self.oversized.clear();
        self.grown_pairs.clear();
        let boxes = &self.grown;
        let inv = 1.0 / self.cell;
        for (i, b) in boxes.iter().enumerate() {
            if bodies.shape[i].is_half_space() {
                self.oversized.push(i as u32);
                continue;
            }
            let Some(([x0, y0, z0], [x1, y1, z1])) = cell_range(b, inv) else {
                self.oversized.push(i as u32);
                continue;
            };
            for x in x0..=x1 {
                for y in y0..=y1 {
                    for z in z0..=z1 {
                        self.entries.push((key(x, y, z), i as u32));
                    }
                }
            }
        }
        self.entries.sort_unstable();
        let responds = |a: usize, b: usize| bodies.responds[a] || bodies.responds[b];
        let mut tests = 0;
        let mut s = 0;
        'cells: while s < self.entries.len() {
            let k = self.entries[s].0;
            let mut e = s + 1;
            while e < self.entries.len() && self.entries[e].0 == k {
                e += 1;
            }
            for u in s..e {
                let a = self.entries[u].1 as usize;
                for v in u + 1..e {
                    let b = self.entries[v].1 as usize;
                    if !responds(a, b) {
                        continue;
                    }
                    tests += 1;
                    let (ba, bb) = (&boxes[a], &boxes[b]);
                    if !ba.overlaps(bb) {
                        continue;
                    }
                    // Report in the cell of the intersection's lower corner only.
                    let lo = ba.min.sup(&bb.min);
                    if key(cell_of(lo.x, inv), cell_of(lo.y, inv), cell_of(lo.z, inv)) != k {
                        continue;
                    }
                    push_pair(&mut self.grown_pairs, a, b, &self.grown_excluded);
                    if self.grown_pairs.len() > self.max_pairs {
                        self.overflowed = true;
                        break 'cells;
                    }
                }
            }
            s = e;
        }
        if self.overflowed {
            return tests;
        }
        // Oversized bodies and half-spaces against everything.
        for oi in 0..self.oversized.len() {
            let o = self.oversized[oi] as usize;
            for b in 0..boxes.len() {
                if b == o || !responds(o, b) {
                    continue;
                }
                // Two oversized bodies: only once.
                if self.oversized.contains(&(b as u32)) && b < o {
                    continue;
                }
                tests += 1;
                if boxes_meet(bodies, boxes, o, b) {
                    push_pair(&mut self.grown_pairs, o, b, &self.grown_excluded);
                    if self.grown_pairs.len() > self.max_pairs {
                        self.overflowed = true;
                        return tests;
                    }
                }
            }
        }
        self.grown_pairs.sort_unstable();
        tests
    }

    /// Every pair whose boxes overlap along x, found by sweeping the boxes in order of
    /// their lower x (the order of the last update, re-sorted: nearly sorted already, so the
    /// insertion sort is linear); keys come out in order. The pairs are those of testing
    /// every pair: a pair apart along x cannot overlap, and a half-space's box spans x.
    fn all_pairs(&mut self, bodies: &CollisionBodies<'_>, excluded: &[u64]) -> usize {
        let boxes = bodies.aabb;
        let n = bodies.len();
        if self.sweep_order.len() != n {
            self.sweep_order.clear();
            self.sweep_order.extend(0..n as u32);
        }
        let order = &mut self.sweep_order;
        let lower_x = |i: u32| boxes[i as usize].min.x;
        for k in 1..n {
            let mut j = k;
            while j > 0 && lower_x(order[j - 1]).total_cmp(&lower_x(order[j])).is_gt() {
                order.swap(j - 1, j);
                j -= 1;
            }
        }
        let mut tests = 0;
        for (k, &a) in order.iter().enumerate() {
            let a = a as usize;
            let upper_x = boxes[a].max.x;
            for &b in &order[k + 1..] {
                let b = b as usize;
                // NaN compares false: a box that is not finite is swept past, never met.
                if boxes[b].min.x > upper_x {
                    break;
                }
                if !Self::wanted(bodies, a, b) {
                    continue;
                }
                tests += 1;
                if boxes_meet(bodies, boxes, a, b) {
                    push_pair(&mut self.pairs, a, b, excluded);
                }
            }
        }
        self.pairs.sort_unstable();
        tests
    }

    #[inline]
    fn wanted(bodies: &CollisionBodies<'_>, a: usize, b: usize) -> bool {
        (bodies.responds[a] || bodies.responds[b]) && (bodies.awake[a] || bodies.awake[b])
    }
}

/// Adds the pair of `a` and `b` to `pairs` as the key `a << 32 | b` (`a < b`) unless it is in
/// `excluded` (sorted keys).
#[inline]
fn push_pair(pairs: &mut Vec<u64>, a: usize, b: usize, excluded: &[u64]) {
    let (a, b) = if a < b { (a, b) } else { (b, a) };
    let k = ((a as u64) << 32) | b as u64;
    if excluded.binary_search(&k).is_err() {
        pairs.push(k);
    }
}

/// Whether the boxes `boxes` of bodies `a` and `b` overlap; against a half-space, whether the
/// other box reaches into it.
#[inline]
fn boxes_meet(bodies: &CollisionBodies<'_>, boxes: &[Aabb], a: usize, b: usize) -> bool {
    if bodies.shape[a].is_half_space() {
        half_space_overlaps(bodies, a, &boxes[b])
    } else if bodies.shape[b].is_half_space() {
        half_space_overlaps(bodies, b, &boxes[a])
    } else {
        boxes[a].overlaps(&boxes[b])
    }
}

/// Whether the box reaches into the half-space of body `h`.
fn half_space_overlaps(bodies: &CollisionBodies<'_>, h: usize, b: &Aabb) -> bool {
    let Shape::HalfSpace { normal } = bodies.shape[h] else {
        return false;
    };
    let n = bodies.rot[h] * normal;
    let o = n.dot(&bodies.pos[h]);
    let c = (b.min + b.max) * 0.5;
    let e = (b.max - b.min) * 0.5;
    n.dot(&c) - n.abs().dot(&e) <= o
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A test world's bodies, all but their boxes: unturned, at the origin unless placed.
    struct TestBodies {
        shape: Vec<Shape>,
        rot: Vec<crate::geometry::M3>,
        pos: Vec<V3>,
        awake: Vec<bool>,
        responds: Vec<bool>,
    }

    impl TestBodies {
        fn new(shape: Vec<Shape>, awake: Vec<bool>, responds: Vec<bool>) -> Self {
            let n = shape.len();
            Self {
                shape,
                rot: vec![crate::geometry::M3::identity(); n],
                pos: vec![V3::zeros(); n],
                awake,
                responds,
            }
        }

        fn view<'a>(&'a self, aabb: &'a [Aabb]) -> CollisionBodies<'a> {
            CollisionBodies {
                shape: &self.shape,
                rot: &self.rot,
                pos: &self.pos,
                aabb,
                awake: &self.awake,
                responds: &self.responds,
                travel: &[],
            }
        }
    }

    /// Uniform numbers in [0, 1) from a xorshift generator.
    fn uniform(mut seed: u64) -> impl FnMut() -> f64 {
        move || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            (seed >> 11) as f64 / (1u64 << 53) as f64
        }
    }

    /// The pairs that testing every pair finds, sorted.
    fn every_pair(bodies: &CollisionBodies<'_>, excluded: &[u64]) -> Vec<u64> {
        let mut pairs = Vec::new();
        for a in 0..bodies.len() {
            for b in a + 1..bodies.len() {
                if BroadPhase::wanted(bodies, a, b) && boxes_meet(bodies, bodies.aabb, a, b) {
                    push_pair(&mut pairs, a, b, excluded);
                }
            }
        }
        pairs
    }

    /// A small world's sweep along x finds exactly the pairs that testing every pair finds,
    /// step after step with every box placed anew (the order kept from the last step is out
    /// of date), with half-spaces along and across x, fixed and sleeping bodies, an
    /// excluded pair and a box that is not finite.
    #[test]
    fn the_sweep_finds_the_pairs_that_testing_every_pair_finds() {
        let n = ALL_PAIRS_BODIES;
        let mut next = uniform(0x2545_f491_4f6c_dd1d);
        let mut shape = vec![
            Shape::HalfSpace { normal: V3::z() },
            Shape::HalfSpace { normal: V3::x() },
        ];
        shape.extend((2..n).map(|_| Shape::Cuboid {
            half: V3::repeat(0.05),
        }));
        let mut world = TestBodies::new(
            shape,
            (0..n).map(|i| i > 1 && i % 5 != 0).collect(),
            (0..n).map(|i| i % 7 != 3).collect(),
        );
        world.pos[1] = V3::new(0.6, 0.0, 0.0);
        let excluded = [(5u64 << 32) | 9];
        let mut sweep = BroadPhase::new(&world.shape);
        let mut found = 0;
        for step in 0..40 {
            let mut aabbs: Vec<Aabb> = (0..n)
                .map(|i| match world.shape[i] {
                    Shape::HalfSpace { .. } => world.shape[i].aabb(&world.rot[i], &world.pos[i]),
                    _ => {
                        let c = V3::new(next(), next() * 0.3, next() * 0.3 - 0.1);
                        let half = V3::repeat(0.01 + 0.1 * next());
                        Aabb {
                            min: c - half,
                            max: c + half,
                        }
                    }
                })
                .collect();
            if step % 4 == 3 {
                aabbs[n - 1] = Aabb {
                    min: V3::repeat(f64::NAN),
                    max: V3::repeat(f64::NAN),
                };
            }
            let bodies = world.view(&aabbs);
            sweep.update(&bodies, &excluded, true);
            let every = every_pair(&bodies, &excluded);
            assert_eq!(sweep.pairs, every, "step {step}");
            found += every.len();
        }
        assert!(
            found > 40 * n,
            "the world is crowded enough to test: {found} pairs"
        );
    }

    /// The grid finds exactly the overlapping pairs that testing every pair finds, on a
    /// scattered world too large for the all-pairs path (boxes of mixed sizes, a ground
    /// half-space, some bodies static or asleep).
    #[test]
    fn the_grid_finds_the_pairs_that_testing_every_pair_finds() {
        let n = 3 * ALL_PAIRS_BODIES;
        let mut next = uniform(0x9e37_79b9_7f4a_7c15);
        let mut shape = vec![Shape::HalfSpace { normal: V3::z() }];
        let mut aabbs = vec![Aabb {
            min: V3::repeat(f64::NEG_INFINITY),
            max: V3::repeat(f64::INFINITY),
        }];
        for _ in 1..n {
            let c = V3::new(next() * 2.0, next() * 2.0, next() * 0.5 - 0.1);
            let half = V3::repeat(0.02 + 0.2 * next() * next());
            shape.push(Shape::Cuboid { half });
            aabbs.push(Aabb {
                min: c - half,
                max: c + half,
            });
        }
        let world = TestBodies::new(
            shape,
            (0..n).map(|i| i > 0 && i % 5 != 0).collect(),
            (0..n).map(|i| i > 0 && i % 7 != 0).collect(),
        );
        let bodies = world.view(&aabbs);
        let excluded = [(3u64 << 32) | 4];
        let mut grid = BroadPhase::new(&world.shape);
        grid.update(&bodies, &excluded, true);
        let every = every_pair(&bodies, &excluded);
        assert!(every.len() > n, "the world is crowded enough to test");
        assert_eq!(grid.pairs, every);
    }

    /// Bodies that move within their grown boxes reuse the grid's pairs, which are then
    /// exactly those that testing every pair finds; a body that moves out of its grown box
    /// builds the grid again.
    #[test]
    fn kept_pairs_are_the_pairs_of_the_boxes_now() {
        let n = 2 * ALL_PAIRS_BODIES;
        let world = TestBodies::new(
            vec![
                Shape::Cuboid {
                    half: V3::repeat(0.5)
                };
                n
            ],
            vec![true; n],
            vec![true; n],
        );
        // A row of unit boxes 1.01 m apart, each box grown by 5 mm: neighbours' boxes touch.
        let place = |shift: &dyn Fn(usize) -> f64| -> Vec<Aabb> {
            (0..n)
                .map(|i| {
                    let c = V3::new(1.01 * i as f64 + shift(i), 0.0, 0.0);
                    Aabb {
                        min: c - V3::repeat(0.505),
                        max: c + V3::repeat(0.505),
                    }
                })
                .collect()
        };
        let mut grid = BroadPhase::new(&world.shape);
        let mut check = |aabbs: &[Aabb], built: bool| {
            let bodies = world.view(aabbs);
            let before = grid.grown.clone();
            grid.update(&bodies, &[], true);
            assert_eq!(grid.grown != before, built, "built the grid again");
            assert_eq!(grid.pairs, every_pair(&bodies, &[]));
        };
        check(&place(&|_| 0.0), true);
        // Every odd box 2 cm to the right: within the grown boxes; boxes 2 and 3 and the like
        // part (2 cm apart), and the grid is not built again.
        check(&place(&|i| if i % 2 == 1 { 0.02 } else { 0.0 }), false);
        // One box 6 cm away from its place: built again.
        check(&place(&|i| if i == 7 { 0.06 } else { 0.0 }), true);
    }

    #[test]
    fn the_fast_floor_is_the_library_floor() {
        let mut xs = vec![
            0.0,
            -0.0,
            1.0,
            -1.0,
            0.5,
            -0.5,
            2.0 - 1e-15,
            -2.0 + 1e-15,
            1e15,
            -1e15,
        ];
        xs.extend([
            9.5e15,
            -9.5e15,
            1e300,
            -1e300,
            f64::INFINITY,
            f64::NEG_INFINITY,
        ]);
        for k in 0..2000 {
            xs.push((k as f64 - 1000.0) * 0.37);
        }
        for x in xs {
            assert_eq!(floor(x), x.floor(), "floor({x})");
        }
        assert!(floor(f64::NAN).is_nan());
    }
    use crate::geometry::V3;

    fn aabb(min: [f64; 3], max: [f64; 3]) -> Aabb {
        Aabb {
            min: V3::from(min),
            max: V3::from(max),
        }
    }

    #[test]
    fn a_small_box_covers_its_cells() {
        // Cells of 1 m: [-0.5, 0.5] covers cells -1 and 0 on each axis.
        let r = cell_range(&aabb([-0.5; 3], [0.5; 3]), 1.0);
        assert_eq!(r, Some(([-1; 3], [0; 3])));
        let r = cell_range(&aabb([0.1, 0.1, 0.1], [0.2, 0.2, 0.2]), 1.0);
        assert_eq!(r, Some(([0; 3], [0; 3])));
    }

    #[test]
    fn more_than_the_cell_limit_is_oversized() {
        // 4 × 4 × 4 = 64 cells is the limit; 5 × 4 × 4 is over it.
        assert!(cell_range(&aabb([0.0; 3], [3.5; 3]), 1.0).is_some());
        assert!(cell_range(&aabb([0.0; 3], [4.5, 3.5, 3.5]), 1.0).is_none());
    }

    #[test]
    fn huge_boxes_are_oversized_without_overflow() {
        // The half extent that once wrapped the integer count into 1..=64 (with y and z
        // spans of 2 cells, 2 × 8e18 overflows i64).
        let h = 1.6e19;
        assert!(cell_range(&aabb([-h, -0.5, -0.5], [h, 0.5, 0.5]), 0.25).is_none());
        for h in [1e30, 1e300, f64::MAX] {
            assert!(cell_range(&aabb([-h; 3], [h; 3]), 0.25).is_none(), "{h}");
        }
        assert!(cell_range(&aabb([f64::NEG_INFINITY; 3], [f64::INFINITY; 3]), 1.0).is_none());
        assert!(cell_range(&aabb([f64::NAN; 3], [f64::NAN; 3]), 1.0).is_none());
    }

    #[test]
    fn a_small_box_far_away_covers_one_saturated_cell() {
        // Beyond i64 cells the index saturates: one cell, no overflow, no endless loop.
        let x = 1e25;
        let r = cell_range(&aabb([x, 0.0, 0.0], [x * (1.0 + 1e-16), 0.1, 0.1]), 1.0);
        assert_eq!(r, Some(([i64::MAX, 0, 0], [i64::MAX, 0, 0])));
    }

    #[test]
    fn the_cell_edge_is_finite_and_bounded() {
        assert_eq!(cell_edge(0.5), 1.0);
        assert_eq!(cell_edge(1e-9), 0.05);
        assert_eq!(cell_edge(1.6e19), 1e3);
        assert_eq!(cell_edge(f64::NAN), 1.0);
        assert_eq!(cell_edge(f64::INFINITY), 1.0);
    }
}

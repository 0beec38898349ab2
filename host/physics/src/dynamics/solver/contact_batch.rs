//! Contact constraints solved four at a time.
//!
//! Graph colouring (as Box2D v3's solver sets): each constraint takes the first colour in which
//! neither of its moving bodies is used yet, so the constraints of one colour share no moving
//! body and can be solved side by side — four per [`ContactGroup`], one per [`Lanes`] lane —
//! without changing what Gauss–Seidel computes: the colours run one after the other, and within
//! a colour the order does not matter. The rows, the soft step and the friction patch are
//! those of [`ContactConstraint::solve`], lane by lane.
//!
//! Constraints with rolling resistance or anchors that follow a round part's turn
//! (`ContactConstraint::follows`), and those no colour can take, stay scalar: the caller
//! solves [`ContactBatches::scalar`] with [`ContactConstraint::solve`] in the same pass.
//!
//! On x86-64 the same code also runs compiled for AVX2, or for AVX-512 (its 32 registers for
//! the same four lanes), when the processor has it ([`KernelIsa`], detected once); every copy
//! computes the same bits (no fused multiply–add is ever formed).

use super::contact_constraint::{PatchFriction, PointConstraint, Row, LINEAR_SLOP};
use super::lanes::{compiled_for, KernelIsa, LaneV3, Lanes, WIDTH};
use super::{ContactConstraint, Softness, SolvePass};
use crate::dynamics::BodySet;
use crate::geometry::{Manifold, MAX_MANIFOLD_POINTS, V3};

/// Colours tried before a constraint is left to the scalar solve.
const MAX_COLOURS: usize = 24;

/// One row of four constraints' points.
#[derive(Clone, Copy, Debug, Default)]
struct RowLanes {
    ia: LaneV3,
    ib: LaneV3,
    mass: Lanes,
}

/// The `k`-th point of four constraints.
#[derive(Clone, Copy, Debug, Default)]
struct PointLanes {
    /// The normal row's angular Jacobians `ra × n`, `rb × n` (m).
    ja: LaneV3,
    jb: LaneV3,
    n: RowLanes,
    separation: Lanes,
    normal_impulse: Lanes,
    max_normal_impulse: Lanes,
}

/// The friction patches of four constraints.
#[derive(Clone, Copy, Debug, Default)]
struct PatchLanes {
    ra: LaneV3,
    rb: LaneV3,
    t: [RowLanes; 2],
    twist: RowLanes,
    arm: Lanes,
    tangent_impulse: [Lanes; 2],
    twist_impulse: Lanes,
}

/// Four constraints of one colour with the same number of points (fewer in the last group
/// of a colour and point count: `lanes`).
#[derive(Clone, Debug, Default)]
struct ContactGroup {
    /// Constraint index of each lane.
    constraint: [usize; WIDTH],
    /// Manifold index of each lane.
    manifold: [usize; WIDTH],
    a: [usize; WIDTH],
    b: [usize; WIDTH],
    lanes: usize,
    /// Points of each lane's constraint: the solve and the warm start visit these alone.
    point_count: usize,
    normal: LaneV3,
    tangents: [LaneV3; 2],
    ima: Lanes,
    imb: Lanes,
    friction: Lanes,
    bias_rate: Lanes,
    mass_scale: Lanes,
    impulse_scale: Lanes,
    points: [PointLanes; MAX_MANIFOLD_POINTS],
    patch: PatchLanes,
}

/// What a solve pass's normal rows read beside each point: the bodies' displacement along
/// the normal and turns over the step so far, the substep rate and the pass.
#[derive(Clone, Copy)]
struct PointPass {
    nd: Lanes,
    dta: LaneV3,
    dtb: LaneV3,
    inv_h: Lanes,
    max_push: f64,
    pass: SolvePass,
}

/// The velocity state of the two bodies of every lane.
struct BodyLanes {
    va: LaneV3,
    wa: LaneV3,
    vb: LaneV3,
    wb: LaneV3,
}

impl BodyLanes {
    /// Applies the impulse `p` (N·s, world) with the angular responses `ia`, `ib` already
    /// through each body's inverse inertia: −`p` to A, +`p` to B.
    #[inline(always)]
    fn apply(&mut self, ima: Lanes, imb: Lanes, p: &LaneV3, ia: &LaneV3, ib: &LaneV3) {
        self.va -= p.scale(ima);
        self.wa -= *ia;
        self.vb += p.scale(imb);
        self.wb += *ib;
    }
}

#[inline(always)]
fn gather(v: &[V3], idx: &[usize; WIDTH], lanes: usize) -> LaneV3 {
    let mut r = LaneV3::default();
    // A full group, as most are, takes a loop of constant length, which compiles to
    // straight-line loads (measured: towers-1120 2 % and pyramid-1240 5 % faster, the same
    // bits); only the last group of a colour takes the loop over its lanes.
    if lanes == WIDTH {
        for (l, &i) in idx.iter().enumerate() {
            r.set(l, v[i].into());
        }
    } else {
        for (l, &i) in idx.iter().enumerate().take(lanes) {
            r.set(l, v[i].into());
        }
    }
    r
}

#[inline(always)]
fn scatter(v: &mut [V3], idx: &[usize; WIDTH], lanes: usize, x: &LaneV3) {
    // As in `gather`.
    if lanes == WIDTH {
        for (l, &i) in idx.iter().enumerate() {
            v[i] = x.get(l).into();
        }
    } else {
        for (l, &i) in idx.iter().enumerate().take(lanes) {
            v[i] = x.get(l).into();
        }
    }
}

impl PointLanes {
    /// Lane `l` from a point, or zeros (a row that changes nothing) for `None`.
    fn set_lane(&mut self, l: usize, pc: Option<&PointConstraint>) {
        let zero = PointConstraint::default();
        let pc = pc.unwrap_or(&zero);
        self.ja.set(l, pc.ja.into());
        self.jb.set(l, pc.jb.into());
        self.n.set_lane(l, &pc.n);
        self.separation.0[l] = pc.separation;
        self.normal_impulse.0[l] = pc.normal_impulse;
        self.max_normal_impulse.0[l] = pc.max_normal_impulse;
    }
}

impl RowLanes {
    /// Lane `l` from a row.
    fn set_lane(&mut self, l: usize, r: &Row) {
        self.ia.set(l, r.ia.into());
        self.ib.set(l, r.ib.into());
        self.mass.0[l] = r.mass;
    }
}

impl PatchLanes {
    /// Lane `l` from a patch, or zeros (rows that change nothing) for `None`.
    fn set_lane(&mut self, l: usize, f: Option<&PatchFriction>) {
        let zero = PatchFriction::default();
        let f = f.unwrap_or(&zero);
        self.ra.set(l, f.ra.into());
        self.rb.set(l, f.rb.into());
        for k in 0..2 {
            self.t[k].set_lane(l, &f.t[k]);
            self.tangent_impulse[k].0[l] = f.tangent_impulse[k];
        }
        self.twist.set_lane(l, &f.twist);
        self.arm.0[l] = f.arm;
        self.twist_impulse.0[l] = f.twist_impulse;
    }
}

impl ContactGroup {
    /// Fills lane `l` in place (the group's buffers are reused step after step) with
    /// constraint `ci` of `c`, or with zeros (rows that change nothing) for `None`; unused
    /// points become zeros too.
    fn set_lane(&mut self, l: usize, c: Option<(usize, &ContactConstraint)>) {
        let (ci, mi, a, b) = c.map_or((0, 0, 0, 0), |(ci, c)| (ci, c.manifold, c.a, c.b));
        self.constraint[l] = ci;
        self.manifold[l] = mi;
        self.a[l] = a;
        self.b[l] = b;
        let c = c.map(|(_, c)| c);
        let v = |f: fn(&ContactConstraint) -> V3| c.map_or([0.0; 3], |c| f(c).into());
        self.normal.set(l, v(|c| c.normal));
        self.tangents[0].set(l, v(|c| c.tangents[0]));
        self.tangents[1].set(l, v(|c| c.tangents[1]));
        let x = |f: fn(&ContactConstraint) -> f64| c.map_or(0.0, f);
        self.ima.0[l] = x(|c| c.ima);
        self.imb.0[l] = x(|c| c.imb);
        self.friction.0[l] = x(|c| c.friction);
        let s = c.map_or(Softness::rigid(0.0), |c| c.softness);
        self.bias_rate.0[l] = s.bias_rate;
        self.mass_scale.0[l] = s.mass_scale;
        self.impulse_scale.0[l] = s.impulse_scale;
        let points = c.map_or(&[][..], |c| &c.points[..c.len]);
        for (k, pl) in self.points.iter_mut().enumerate() {
            pl.set_lane(l, points.get(k));
        }
        self.patch.set_lane(l, c.map(|c| &c.patch));
    }

    #[inline(always)]
    fn load(&self, b: &BodySet) -> BodyLanes {
        BodyLanes {
            va: gather(&b.vel, &self.a, self.lanes),
            wa: gather(&b.omega, &self.a, self.lanes),
            vb: gather(&b.vel, &self.b, self.lanes),
            wb: gather(&b.omega, &self.b, self.lanes),
        }
    }

    /// Writes the lanes' velocities back. A fixed or sleeping body shared by several lanes
    /// gets its unchanged velocity back from each (its inverse mass is zero here).
    #[inline(always)]
    fn store(&self, b: &mut BodySet, s: &BodyLanes) {
        scatter(&mut b.vel, &self.a, self.lanes, &s.va);
        scatter(&mut b.omega, &self.a, self.lanes, &s.wa);
        scatter(&mut b.vel, &self.b, self.lanes, &s.vb);
        scatter(&mut b.omega, &self.b, self.lanes, &s.wb);
    }

    #[inline(always)]
    fn warm_start(&self, bodies: &mut BodySet) {
        // The impulses summed first (as `ContactConstraint::warm_start` sums them), then
        // applied once: the bodies' velocities wait on one chain of additions, not five.
        let f = &self.patch;
        let [l0, l1] = f.tangent_impulse;
        let tw = f.twist_impulse;
        let mut ia = f.t[0].ia.scale(l0) + f.t[1].ia.scale(l1) + f.twist.ia.scale(tw);
        let mut ib = f.t[0].ib.scale(l0) + f.t[1].ib.scale(l1) + f.twist.ib.scale(tw);
        let mut total = Lanes::splat(0.0);
        for pl in &self.points[..self.point_count] {
            total = total + pl.normal_impulse;
            ia += pl.n.ia.scale(pl.normal_impulse);
            ib += pl.n.ib.scale(pl.normal_impulse);
        }
        let p = self.normal.scale(total) + self.tangents[0].scale(l0) + self.tangents[1].scale(l1);
        let mut s = self.load(bodies);
        s.apply(self.ima, self.imb, &p, &ia, &ib);
        self.store(bodies, &s);
    }

    #[inline(always)]
    fn solve(&mut self, bodies: &mut BodySet, inv_h: f64, max_push: f64, pass: SolvePass) {
        let mut s = self.load(bodies);
        let n = self.normal;
        let nd = n.dot(
            &(gather(&bodies.dp, &self.b, self.lanes) - gather(&bodies.dp, &self.a, self.lanes)),
        );
        let dta = gather(&bodies.dtheta, &self.a, self.lanes);
        let dtb = gather(&bodies.dtheta, &self.b, self.lanes);
        let one = Lanes::splat(1.0);
        let pp = PointPass {
            nd,
            dta,
            dtb,
            inv_h: Lanes::splat(inv_h),
            max_push,
            pass,
        };
        // A group of full manifolds, as most are, takes a loop of constant length, which
        // compiles to straight-line code, as `gather` does for a full group.
        let total = if self.point_count == MAX_MANIFOLD_POINTS {
            self.solve_points::<MAX_MANIFOLD_POINTS>(&mut s, &pp)
        } else {
            self.solve_points_of(self.point_count, &mut s, &pp)
        };
        let [t0, t1] = self.tangents;
        {
            let f = &mut self.patch;
            let l0 = f.tangent_impulse;
            let dv = s.vb + s.wb.cross(&f.rb) - s.va - s.wa.cross(&f.ra);
            let l = [
                l0[0] - f.t[0].mass * t0.dot(&dv),
                l0[1] - f.t[1].mass * t1.dot(&dv),
            ];
            // Coulomb cone: |λt| ≤ μ Σ λn (a patch with no normal impulse gets none).
            let max = self.friction * total;
            let len2 = l[0] * l[0] + l[1] * l[1];
            // Where the cone clips, len2 > max² ≥ 0, and only there is the quotient used:
            // resting contacts rarely clip, so the square root and division run only when a
            // lane does.
            let clips = len2.gt(max * max);
            let l = if clips.any() {
                let scale = clips.select(max / len2.sqrt(), one);
                [l[0] * scale, l[1] * scale]
            } else {
                l
            };
            let d = [l[0] - l0[0], l[1] - l0[1]];
            f.tangent_impulse = l;
            let p = t0.scale(d[0]) + t1.scale(d[1]);
            let ia = f.t[0].ia.scale(d[0]) + f.t[1].ia.scale(d[1]);
            let ib = f.t[0].ib.scale(d[0]) + f.t[1].ib.scale(d[1]);
            s.apply(self.ima, self.imb, &p, &ia, &ib);
            // Torsion about the normal: |λ| ≤ μ ρ Σ λn.
            let tw0 = f.twist_impulse;
            let max = self.friction * f.arm * total;
            let tw = (tw0 - f.twist.mass * n.dot(&(s.wb - s.wa)))
                .max(-max)
                .min(max);
            let d = tw - tw0;
            f.twist_impulse = tw;
            s.wa -= f.twist.ia.scale(d);
            s.wb += f.twist.ib.scale(d);
        }
        self.store(bodies, &s);
    }

    /// The normal rows of the group's first `N` points, in the pass's order, applied to `s`;
    /// the sum of their accumulated impulses.
    #[inline(always)]
    fn solve_points<const N: usize>(&mut self, s: &mut BodyLanes, pp: &PointPass) -> Lanes {
        // The points' order, taken once per pass rather than per point (measured: towers-1120
        // 3–4 % and pyramid-1240 2 % faster, the same bits).
        let mut order: [usize; N] = std::array::from_fn(|i| i);
        if pp.pass.reverse {
            order.reverse();
        }
        self.solve_rows(&order, s, pp)
    }

    /// [`Self::solve_points`] for the first `count` points, `count` known at run time.
    #[inline(always)]
    fn solve_points_of(&mut self, count: usize, s: &mut BodyLanes, pp: &PointPass) -> Lanes {
        let mut order: [usize; MAX_MANIFOLD_POINTS] = std::array::from_fn(|i| i);
        let order = &mut order[..count];
        if pp.pass.reverse {
            order.reverse();
        }
        self.solve_rows(order, s, pp)
    }

    /// The normal rows of the points `order` names, in that order, applied to `s`; the sum
    /// of their accumulated impulses.
    #[inline(always)]
    fn solve_rows(&mut self, order: &[usize], s: &mut BodyLanes, pp: &PointPass) -> Lanes {
        let PointPass {
            nd,
            dta,
            dtb,
            inv_h,
            max_push,
            pass,
        } = *pp;
        let n = self.normal;
        let (zero, one) = (Lanes::splat(0.0), Lanes::splat(1.0));
        let mut total = zero;
        for &k in order {
            let pl = &mut self.points[k];
            let sep = nd + (dtb.dot(&pl.jb) - dta.dot(&pl.ja)) + pl.separation;
            let ahead = sep.gt(zero);
            let (bias, ms, is) = if pass.use_bias {
                let pushed = (self.bias_rate * (sep + Lanes::splat(LINEAR_SLOP)).min(zero))
                    .max(Lanes::splat(-max_push));
                (
                    ahead.select(sep * inv_h, pushed),
                    ahead.select(one, self.mass_scale),
                    ahead.select(zero, self.impulse_scale),
                )
            } else {
                (ahead.select(sep * inv_h, zero), one, zero)
            };
            let vn = n.dot(&(s.vb - s.va)) + (s.wb.dot(&pl.jb) - s.wa.dot(&pl.ja));
            let imp = -(pl.n.mass * ms * (vn + bias)) - is * pl.normal_impulse;
            let new = (pl.normal_impulse + imp).max(zero);
            let delta = new - pl.normal_impulse;
            pl.normal_impulse = new;
            pl.max_normal_impulse = pl.max_normal_impulse.max_num(delta);
            total = total + new;
            let p = n.scale(delta);
            let (ia, ib) = (pl.n.ia.scale(delta), pl.n.ib.scale(delta));
            s.apply(self.ima, self.imb, &p, &ia, &ib);
        }
        total
    }

    /// Lane `l`'s accumulated impulses.
    fn impulses(&self, l: usize) -> LaneImpulses {
        let f = &self.patch;
        LaneImpulses {
            normal: std::array::from_fn(|k| self.points[k].normal_impulse.0[l]),
            max_normal: std::array::from_fn(|k| self.points[k].max_normal_impulse.0[l]),
            tangent: [f.tangent_impulse[0].0[l], f.tangent_impulse[1].0[l]],
            twist: f.twist_impulse.0[l],
        }
    }

    /// Copies the accumulated impulses back into the constraints.
    fn write_back(&self, constraints: &mut [ContactConstraint]) {
        for l in 0..self.lanes {
            let c = &mut constraints[self.constraint[l]];
            let i = self.impulses(l);
            for (k, pc) in c.points[..c.len].iter_mut().enumerate() {
                pc.normal_impulse = i.normal[k];
                pc.max_normal_impulse = i.max_normal[k];
            }
            c.patch.tangent_impulse = i.tangent;
            c.patch.twist_impulse = i.twist;
        }
    }

    /// Stores lane `l`'s accumulated impulses straight into its manifold, as
    /// [`ContactConstraint::store`] would after [`Self::write_back`] (a grouped constraint
    /// has no rolling resistance), accumulated over substeps of `impulse_substep` seconds.
    fn store_lane(&self, manifolds: &mut [Manifold], l: usize, impulse_substep: f64) {
        let m = &mut manifolds[self.manifold[l]];
        let i = self.impulses(l);
        for (k, cp) in m.points[..m.len].iter_mut().enumerate() {
            cp.normal_impulse = i.normal[k];
            cp.max_normal_impulse = i.max_normal[k];
        }
        m.friction_impulse = i.tangent;
        m.twist_impulse = i.twist;
        m.rolling_impulse = V3::zeros();
        m.impulse_substep = impulse_substep;
    }
}

/// One lane's accumulated impulses (N·s; the twist in N·m·s).
struct LaneImpulses {
    normal: [f64; MAX_MANIFOLD_POINTS],
    max_normal: [f64; MAX_MANIFOLD_POINTS],
    tangent: [f64; 2],
    twist: f64,
}

/// Where a grouped constraint sits: its colour, its group within the colour and its lane.
#[derive(Clone, Copy, Debug)]
struct Slot {
    colour: u16,
    lane: u16,
    group: u32,
}

/// The step's contact constraints, coloured and grouped four by four.
///
/// Built one constraint at a time ([`ContactBatches::begin`], [`ContactBatches::add`],
/// [`ContactBatches::finish`]) so that the world fills each constraint's lane right after
/// preparing it, while the constraint is still in cache: filled from the whole prepared
/// array afterwards, the fill read every constraint back from memory.
#[derive(Clone, Debug, Default)]
pub(crate) struct ContactBatches {
    /// Per colour, its group buffers, kept across steps; the first `live_groups[k]` are this
    /// step's. Each colour's groups lie side by side in the order they are solved.
    colour_groups: Vec<Vec<ContactGroup>>,
    /// Per colour, its groups in use this step.
    live_groups: Vec<usize>,
    /// Per colour and point count, the group being filled (`None`: none yet, or full). A
    /// group holds constraints of one point count, so that its solve visits no empty point
    /// (a sphere's single point is not solved as four).
    open: Vec<[Option<u32>; MAX_MANIFOLD_POINTS + 1]>,
    /// Constraints solved one at a time (rolling resistance, or no colour free).
    pub(crate) scalar: Vec<usize>,
    /// Colours used in the last build.
    pub(crate) colours: usize,
    /// Per colour, a bit per body: the moving bodies it holds.
    used: Vec<Vec<u64>>,
    /// Per constraint added, where it sits (`None`: in no group).
    slot: Vec<Option<Slot>>,
}

impl ContactBatches {
    /// Colours and groups `constraints` (each with its own softness).
    #[cfg(test)]
    pub(crate) fn build(&mut self, constraints: &[ContactConstraint], n_bodies: usize) {
        self.build_of(constraints, n_bodies, |_| true);
    }

    /// Colours and groups the constraints of `constraints` whose index `include` accepts.
    pub(crate) fn build_of(
        &mut self,
        constraints: &[ContactConstraint],
        n_bodies: usize,
        include: impl Fn(usize) -> bool,
    ) {
        self.begin(n_bodies);
        for (ci, c) in constraints.iter().enumerate() {
            if include(ci) {
                self.add(ci, c);
            } else {
                self.skip(ci);
            }
        }
        self.finish();
    }

    /// Starts a build over `n_bodies` bodies; the constraints follow in their index order
    /// through [`Self::add`] or [`Self::skip`].
    pub(crate) fn begin(&mut self, n_bodies: usize) {
        self.scalar.clear();
        self.colours = 0;
        self.slot.clear();
        let words = n_bodies.div_ceil(64);
        if self.used.len() < MAX_COLOURS {
            self.used.resize(MAX_COLOURS, Vec::new());
            self.live_groups.resize(MAX_COLOURS, 0);
            self.open
                .resize(MAX_COLOURS, [None; MAX_MANIFOLD_POINTS + 1]);
            self.colour_groups.resize_with(MAX_COLOURS, Vec::new);
        }
        for ((u, live), open) in self
            .used
            .iter_mut()
            .zip(&mut self.live_groups)
            .zip(&mut self.open)
        {
            u.clear();
            u.resize(words, 0);
            *live = 0;
            *open = [None; MAX_MANIFOLD_POINTS + 1];
        }
    }

    /// Constraint `ci` (the next index) is not in this build.
    pub(crate) fn skip(&mut self, ci: usize) {
        debug_assert_eq!(ci, self.slot.len());
        self.slot.push(None);
    }

    /// Adds constraint `ci` (the next index): the first colour in which neither of its
    /// moving bodies is used yet takes it, in the next lane of that colour's last group,
    /// filled now; constraints no colour can take, or with rolling resistance or rows that
    /// follow a turn, go to [`Self::scalar`]. Its softness may still change
    /// ([`Self::set_softness`]). Whether it went to a group.
    pub(crate) fn add(&mut self, ci: usize, c: &ContactConstraint) -> bool {
        debug_assert_eq!(ci, self.slot.len());
        if c.rolling_arm > 0.0 || c.follows {
            self.scalar.push(ci);
            self.slot.push(None);
            return false;
        }
        let bit = |i: usize| (i / 64, 1u64 << (i % 64));
        let moving_a = (c.ima > 0.0).then(|| bit(c.a));
        let moving_b = (c.imb > 0.0).then(|| bit(c.b));
        let free = |u: &Vec<u64>| {
            moving_a.is_none_or(|(w, m)| u[w] & m == 0)
                && moving_b.is_none_or(|(w, m)| u[w] & m == 0)
        };
        let Some(k) = self.used.iter().position(free) else {
            self.scalar.push(ci);
            self.slot.push(None);
            return false;
        };
        let u = &mut self.used[k];
        for (w, m) in [moving_a, moving_b].into_iter().flatten() {
            u[w] |= m;
        }
        self.colours = self.colours.max(k + 1);
        let points = c.len.min(MAX_MANIFOLD_POINTS);
        let groups = &mut self.colour_groups[k];
        let group = match self.open[k][points] {
            Some(g) => g as usize,
            None => {
                let g = self.live_groups[k];
                self.live_groups[k] += 1;
                if groups.len() == g {
                    groups.push(ContactGroup::default());
                }
                groups[g].lanes = 0;
                groups[g].point_count = points;
                self.open[k][points] = Some(g as u32);
                g
            }
        };
        let g = &mut groups[group];
        let lane = g.lanes;
        g.set_lane(lane, Some((ci, c)));
        g.lanes = lane + 1;
        if g.lanes == WIDTH {
            self.open[k][points] = None;
        }
        self.slot.push(Some(Slot {
            colour: k as u16,
            lane: lane as u16,
            group: group as u32,
        }));
        true
    }

    /// Ends a build: the unused lanes of each colour's last group become rows that change
    /// nothing.
    pub(crate) fn finish(&mut self) {
        for k in 0..self.colours {
            for g in self.open[k].iter().flatten() {
                let g = &mut self.colour_groups[k][*g as usize];
                for l in g.lanes..WIDTH {
                    g.set_lane(l, None);
                }
            }
        }
    }

    /// Sets the softness of constraint `ci`'s lane to `c`'s, where `ci` is grouped.
    pub(crate) fn set_softness(&mut self, ci: usize, c: &ContactConstraint) {
        let Some(&Some(slot)) = self.slot.get(ci) else {
            return;
        };
        let g = &mut self.colour_groups[slot.colour as usize][slot.group as usize];
        let l = slot.lane as usize;
        g.bias_rate.0[l] = c.softness.bias_rate;
        g.mass_scale.0[l] = c.softness.mass_scale;
        g.impulse_scale.0[l] = c.softness.impulse_scale;
    }

    /// Each colour's groups of this step, in the order they are solved.
    fn live(&self) -> impl Iterator<Item = &[ContactGroup]> {
        self.colour_groups
            .iter()
            .zip(&self.live_groups)
            .take(self.colours)
            .map(|(g, &live)| &g[..live])
    }

    /// Number of four-lane groups.
    pub(crate) fn groups(&self) -> usize {
        self.live().map(<[ContactGroup]>::len).sum()
    }

    /// Applies every group's accumulated impulses (warm start).
    pub(crate) fn warm_start(&self, bodies: &mut BodySet) {
        let isa = KernelIsa::detect();
        for groups in self.live() {
            warm_start_on(isa, groups, bodies);
        }
    }

    /// One pass over the groups (see [`ContactConstraint::solve`]).
    pub(crate) fn solve(
        &mut self,
        bodies: &mut BodySet,
        inv_h: f64,
        max_push: f64,
        pass: SolvePass,
    ) {
        let isa = KernelIsa::detect();
        for (g, &m) in self
            .colour_groups
            .iter_mut()
            .zip(&self.live_groups)
            .take(self.colours)
        {
            solve_on(isa, &mut g[..m], bodies, inv_h, max_push, pass);
        }
    }

    /// Copies the accumulated impulses back into `constraints` (before restitution and the
    /// manifolds' warm-start store).
    pub(crate) fn write_back(&self, constraints: &mut [ContactConstraint]) {
        for g in self.live().flatten() {
            g.write_back(constraints);
        }
    }

    /// Stores every group's accumulated impulses straight into `manifolds` (the manifold
    /// warm-start store without the constraints in between, where nothing reads their
    /// impulses after the solve: no restitution), with the substep (s) they were
    /// accumulated over.
    pub(crate) fn store_impulses(&self, manifolds: &mut [Manifold], impulse_substep: f64) {
        // In the constraints' order, which is the manifolds': the manifolds are written
        // front to back (the colours interleave them).
        for slot in self.slot.iter().flatten() {
            let g = &self.colour_groups[slot.colour as usize][slot.group as usize];
            g.store_lane(manifolds, slot.lane as usize, impulse_substep);
        }
    }
}

/// The warm start compiled for `isa`, which the processor must run.
fn warm_start_on(isa: KernelIsa, groups: &[ContactGroup], bodies: &mut BodySet) {
    match isa {
        // SAFETY: the processor has the instructions (`KernelIsa::detect`).
        #[cfg(target_arch = "x86_64")]
        KernelIsa::Avx512 => unsafe { warm_start_avx512(groups, bodies) },
        // SAFETY: as above.
        #[cfg(target_arch = "x86_64")]
        KernelIsa::Avx2 => unsafe { warm_start_avx2(groups, bodies) },
        KernelIsa::Baseline => warm_start_all(groups, bodies),
    }
}

/// The solve pass compiled for `isa`, which the processor must run.
fn solve_on(
    isa: KernelIsa,
    groups: &mut [ContactGroup],
    bodies: &mut BodySet,
    inv_h: f64,
    max_push: f64,
    pass: SolvePass,
) {
    match isa {
        // SAFETY: the processor has the instructions (`KernelIsa::detect`).
        #[cfg(target_arch = "x86_64")]
        KernelIsa::Avx512 => unsafe { solve_avx512(groups, bodies, inv_h, max_push, pass) },
        // SAFETY: as above.
        #[cfg(target_arch = "x86_64")]
        KernelIsa::Avx2 => unsafe { solve_avx2(groups, bodies, inv_h, max_push, pass) },
        KernelIsa::Baseline => solve_all(groups, bodies, inv_h, max_push, pass),
    }
}

#[inline(always)]
fn warm_start_all(groups: &[ContactGroup], bodies: &mut BodySet) {
    for g in groups {
        g.warm_start(bodies);
    }
}

#[inline(always)]
fn solve_all(
    groups: &mut [ContactGroup],
    bodies: &mut BodySet,
    inv_h: f64,
    max_push: f64,
    pass: SolvePass,
) {
    for g in groups {
        g.solve(bodies, inv_h, max_push, pass);
    }
}

compiled_for!(fn(groups: &[ContactGroup], bodies: &mut BodySet) => warm_start_all:
    warm_start_avx2 = "avx2",
    warm_start_avx512 = "avx2,avx512f,avx512vl",
);
compiled_for!(fn(
    groups: &mut [ContactGroup],
    bodies: &mut BodySet,
    inv_h: f64,
    max_push: f64,
    pass: SolvePass,
) => solve_all:
    solve_avx2 = "avx2",
    solve_avx512 = "avx2,avx512f,avx512vl",
);

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dynamics::solver::ContactSettings;
    use crate::dynamics::{BodyKind, Material};
    use crate::geometry::{Manifold, Shape, M3};

    /// `n` unit boxes in a row along x, 1.0 m apart (touching), the first one fixed, with
    /// some velocity so that every row of the solve does something.
    fn bodies(n: usize) -> BodySet {
        let mut b = BodySet::default();
        for i in 0..n {
            let kind = if i == 0 {
                BodyKind::Fixed
            } else {
                BodyKind::Dynamic
            };
            let k = i as f64;
            b.push(
                String::new(),
                kind,
                Shape::Cuboid {
                    half: V3::new(0.5, 0.5, 0.5),
                },
                Material::default(),
                1.0 + 0.3 * k,
                V3::new(k, 0.0, 0.0),
                M3::identity(),
                V3::new(-0.4 * k, 0.2, 0.1 * k),
                V3::new(0.3, -0.2 * k, 0.5),
            );
            b.dp[i] = V3::new(0.001 * k, 0.0, -0.0005);
        }
        b.update_world_inertia();
        b
    }

    /// The face contact between boxes `i` and `i + 1`: four corners, slightly overlapping,
    /// with impulses carried from a previous step.
    fn manifold(i: usize) -> Manifold {
        let mut m = Manifold::new(i as u32, i as u32 + 1);
        m.normal = V3::x();
        for (k, (y, z)) in [(-0.5, -0.5), (0.5, -0.5), (0.5, 0.5), (-0.5, 0.5)]
            .into_iter()
            .enumerate()
        {
            m.push(V3::new(i as f64 + 0.5, y, z), -0.001 * k as f64);
            m.points[k].normal_impulse = 0.01 * k as f64;
        }
        m.friction_impulse = [0.002, -0.001 * i as f64];
        m.twist_impulse = 0.0004 * i as f64;
        m
    }

    fn constraints(b: &BodySet, n: usize) -> Vec<ContactConstraint> {
        (0..n - 1)
            .map(|i| ContactConstraint::prepare(b, &manifold(i), i, &ContactSettings::default()))
            .collect()
    }

    #[test]
    fn a_colour_never_holds_two_constraints_of_one_moving_body() {
        let n = 40;
        let b = bodies(n);
        let c = constraints(&b, n);
        let mut batches = ContactBatches::default();
        batches.build(&c, n);
        // A chain needs two colours; every constraint is in exactly one group.
        assert_eq!(batches.colours, 2);
        assert!(batches.scalar.is_empty());
        let mut seen = vec![0; c.len()];
        for g in batches.live().flatten() {
            let mut moving: Vec<usize> = Vec::new();
            for l in 0..g.lanes {
                seen[g.constraint[l]] += 1;
                for (body, im) in [(g.a[l], g.ima.0[l]), (g.b[l], g.imb.0[l])] {
                    if im > 0.0 {
                        moving.push(body);
                    }
                }
            }
            let before = moving.len();
            moving.sort_unstable();
            moving.dedup();
            assert_eq!(moving.len(), before, "a body twice in one group");
        }
        assert!(seen.iter().all(|&k| k == 1));
    }

    #[test]
    fn a_softness_set_after_the_lane_is_filled_is_the_one_solved() {
        // The world fills each lane as its constraint is prepared and stiffens it afterwards:
        // the group must solve with the later softness, as the scalar solve does.
        let n = 8;
        let base = bodies(n);
        let mut pick: Vec<ContactConstraint> =
            constraints(&base, n).into_iter().step_by(2).collect();
        let mut batches = ContactBatches::default();
        batches.build(&pick, n);
        for (ci, c) in pick.iter_mut().enumerate() {
            c.set_softness(Softness::new(60.0 + 30.0 * ci as f64, 10.0, 1.0 / 720.0));
            batches.set_softness(ci, c);
        }
        let pass = SolvePass {
            use_bias: true,
            reverse: false,
        };
        let mut scalar_bodies = base.clone();
        for c in &mut pick.clone() {
            c.solve(&mut scalar_bodies, 720.0, 3.0, pass);
        }
        let mut batch_bodies = base.clone();
        batches.solve(&mut batch_bodies, 720.0, 3.0, pass);
        assert_eq!(scalar_bodies.vel, batch_bodies.vel);
        assert_eq!(scalar_bodies.omega, batch_bodies.omega);
    }

    #[test]
    fn a_group_computes_what_the_scalar_solve_computes() {
        // Independent constraints (one per pair of bodies): one group of four solves exactly
        // what four scalar solves do, bit for bit, in both kinds of pass.
        let n = 8;
        let base = bodies(n);
        let all = constraints(&base, n);
        let mut pick: Vec<ContactConstraint> = [0, 2, 4, 6].iter().map(|&i| all[i]).collect();
        // Each constraint with its own softness, as loads make them.
        for (k, c) in pick.iter_mut().enumerate() {
            let hz = if c.against_static {
                240.0
            } else {
                120.0 + 40.0 * k as f64
            };
            c.set_softness(Softness::new(hz, 10.0, 1.0 / 720.0));
        }
        // The warm start, in every copy of the lane code this processor runs.
        let mut scalar_bodies = base.clone();
        for c in &pick {
            c.warm_start(&mut scalar_bodies);
        }
        assert_ne!(scalar_bodies.vel, base.vel);
        for isa in KernelIsa::available() {
            let mut batch_bodies = base.clone();
            let mut batches = ContactBatches::default();
            batches.build(&pick, n);
            warm_start_on(isa, &batches.colour_groups[0][..1], &mut batch_bodies);
            assert_eq!(scalar_bodies.vel, batch_bodies.vel, "{isa:?}");
            assert_eq!(scalar_bodies.omega, batch_bodies.omega, "{isa:?}");
        }
        for pass in [
            SolvePass {
                use_bias: true,
                reverse: false,
            },
            SolvePass {
                use_bias: false,
                reverse: true,
            },
        ] {
            let (mut scalar_bodies, mut scalar) = (base.clone(), pick.clone());
            for c in &mut scalar {
                c.solve(&mut scalar_bodies, 720.0, 3.0, pass);
            }
            // Every copy of the lane code this processor runs (`KernelIsa::available`).
            for isa in KernelIsa::available() {
                let (mut batch_bodies, mut batched) = (base.clone(), pick.clone());
                let mut batches = ContactBatches::default();
                batches.build(&batched, n);
                assert_eq!((batches.colours, batches.groups()), (1, 1));
                solve_on(
                    isa,
                    &mut batches.colour_groups[0][..1],
                    &mut batch_bodies,
                    720.0,
                    3.0,
                    pass,
                );
                batches.write_back(&mut batched);
                assert_eq!(scalar_bodies.vel, batch_bodies.vel);
                assert_eq!(scalar_bodies.omega, batch_bodies.omega);
                for (s, b) in scalar.iter().zip(&batched) {
                    for (ps, pb) in s.points.iter().zip(&b.points) {
                        assert_eq!(ps.normal_impulse, pb.normal_impulse);
                        assert_eq!(ps.max_normal_impulse, pb.max_normal_impulse);
                    }
                    assert_eq!(s.patch.tangent_impulse, b.patch.tangent_impulse);
                    assert_eq!(s.patch.twist_impulse, b.patch.twist_impulse);
                }
                // The pass did something.
                assert_ne!(batch_bodies.vel, base.vel);
            }
        }
    }

    #[test]
    fn constraints_of_different_point_counts_are_grouped_apart_and_solved_alike() {
        // Independent constraints of 1, 2, 3 and 4 points, twice each: one colour, a group per
        // point count that visits that many points, and the scalar solve's bits.
        let n = 17;
        let base = bodies(n);
        let pick: Vec<ContactConstraint> = (0..8)
            .map(|j| {
                let i = 2 * j;
                let mut m = manifold(i);
                m.len = 1 + j % 4;
                ContactConstraint::prepare(&base, &m, i, &ContactSettings::default())
            })
            .collect();
        let mut batches = ContactBatches::default();
        batches.build(&pick, n);
        assert_eq!((batches.colours, batches.groups()), (1, 4));
        for g in batches.live().flatten() {
            assert_eq!(g.lanes, 2);
            for l in 0..g.lanes {
                assert_eq!(pick[g.constraint[l]].len, g.point_count);
            }
        }
        let pass = SolvePass {
            use_bias: true,
            reverse: true,
        };
        let (mut scalar_bodies, mut scalar) = (base.clone(), pick.clone());
        for c in &mut scalar {
            c.warm_start(&mut scalar_bodies);
            c.solve(&mut scalar_bodies, 720.0, 3.0, pass);
        }
        let mut batch_bodies = base.clone();
        batches.warm_start(&mut batch_bodies);
        batches.solve(&mut batch_bodies, 720.0, 3.0, pass);
        assert_eq!(scalar_bodies.vel, batch_bodies.vel);
        assert_eq!(scalar_bodies.omega, batch_bodies.omega);
    }
}

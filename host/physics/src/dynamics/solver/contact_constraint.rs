//! Contact constraints: non-penetration (soft, speculative), Coulomb friction on the cone,
//! restitution above a velocity threshold, and rolling resistance.
//!
//! One constraint per manifold, up to 4 points. Everything in world coordinates: anchors
//! `ra`, `rb` from each centre of mass to the contact (m), normal from A to B. Effective masses
//! (kg) and the angular responses `I⁻¹ (r × n)` are precomputed in [`ContactConstraint::prepare`].
//!
//! Friction is the manifold's, not each point's (patch friction, as PhysX solves it): two
//! tangent rows at the points' centroid bounded together by `μ Σ λn`, and a torsional row about
//! the normal bounded by `μ ρ Σ λn`, `ρ` the points' mean distance from the centroid. A face
//! contact takes three friction rows instead of eight; a one-point contact takes the point's
//! two rows (its torsional bound is zero).

use super::{ContactStiffness, Softness};
use crate::dynamics::BodySet;
use crate::geometry::{Manifold, Shape, M3, MAX_MANIFOLD_POINTS, V3};

mod resting;

/// Overlap allowed without position correction (m): keeps resting contacts from jittering.
pub(crate) const LINEAR_SLOP: f64 = 1e-4;

/// A contact narrower than this (m) along its load's offset gives no tilt in
/// [`ContactConstraint::column_tilt`].
const TILT_MIN_SPAN: f64 = 1e-3;

/// A round part whose centre of curvature lies farther than this (m) from its body's centre
/// of mass moves its contact point with the body's turn during the step
/// ([`ContactConstraint::follows`]); closer, the lever arm it would correct is below this
/// times the turn (a sphere at its centre of mass: zero to rounding).
const FOLLOW_MIN_OFFSET: f64 = 1e-6;

/// Solver settings for contacts (from the scene's effects).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct ContactSettings {
    /// Friction on.
    pub(crate) friction: bool,
    /// Restitution on.
    pub(crate) restitution: bool,
    /// Rolling resistance on.
    pub(crate) rolling: bool,
    /// Approach speed below which no bounce is applied (m/s).
    pub(crate) restitution_threshold: f64,
    /// Largest push-out speed of the position bias (m/s).
    pub(crate) max_push_velocity: f64,
    /// Unit vector against gravity (world), zero without gravity: which body of a contact
    /// carries the other ([`carried_scale`]).
    pub(crate) up: V3,
}

impl Default for ContactSettings {
    fn default() -> Self {
        Self {
            friction: true,
            restitution: false,
            rolling: false,
            restitution_threshold: 0.5,
            max_push_velocity: 3.0,
            up: V3::zeros(),
        }
    }
}

/// The largest ratio of a carried body's mass to the mass its carrier takes in their contact
/// (–); see [`carried_scale`].
pub(crate) const MAX_CARRIED_RATIO: f64 = 2.0;

/// A contact normal within this angle's cosine of the vertical carries weight (–): 45°.
const CARRYING_COS: f64 = std::f64::consts::FRAC_1_SQRT_2;

/// Heavy on light: the scale (A's, B's) of the inverse mass and inertia each body takes in
/// their contact. Where a body lies beneath one more than [`MAX_CARRIED_RATIO`] times
/// heavier (the normal within 45° of `up`), it takes that much of the heavier body's mass in
/// this contact alone, so the contact stops the heavy body within the substep's pass instead
/// of over a number of passes that grows with the mass ratio. This is shock propagation
/// (Guendelman, Bridson and Fedkiw, "Nonconvex rigid bodies with stacking", SIGGRAPH 2003,
/// §7; Erleben, "Stable, robust, and versatile multibody dynamics animation", 2004, ch. 8)
/// softened to a bounded mass ratio per contact instead of an infinite mass per level: the
/// carrier still feels the load, scaled by the ratio it takes, and momentum is kept between
/// bodies of like masses. What it gives up: a light body under a heavy one passes on less
/// than the heavy body's weight to what lies beneath it.
pub(crate) fn carried_scale(n: &V3, up: &V3, ima: f64, imb: f64) -> (f64, f64) {
    let vertical = n.dot(up);
    if ima == 0.0 || imb == 0.0 {
        return (1.0, 1.0);
    }
    if vertical > CARRYING_COS && ima > MAX_CARRIED_RATIO * imb {
        // B on A, A the lighter.
        (MAX_CARRIED_RATIO * imb / ima, 1.0)
    } else if vertical < -CARRYING_COS && imb > MAX_CARRIED_RATIO * ima {
        // A on B, B the lighter.
        (1.0, MAX_CARRIED_RATIO * ima / imb)
    } else {
        (1.0, 1.0)
    }
}

/// What one Gauss–Seidel pass over the contacts does.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct SolvePass {
    /// Push overlapping points out with the soft position bias (the substep's solve pass);
    /// false in the relax pass, which removes the push-out velocity again.
    pub(crate) use_bias: bool,
    /// Walk the points backwards: alternating the direction between passes keeps the
    /// Gauss–Seidel order from tilting a resting box one way step after step.
    pub(crate) reverse: bool,
}

/// One row along a direction `d` at a point: each body's `I⁻¹ (r × d)` and the effective mass.
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct Row {
    pub(super) ia: V3,
    pub(super) ib: V3,
    pub(super) mass: f64,
}

impl Row {
    #[inline]
    fn new(ra: &V3, rb: &V3, d: &V3, ima: f64, imb: f64, ia: &M3, ib: &M3) -> Self {
        let ra_x = ra.cross(d);
        let rb_x = rb.cross(d);
        let iax = ia * ra_x;
        let ibx = ib * rb_x;
        let k = ima + imb + ra_x.dot(&iax) + rb_x.dot(&ibx);
        Self {
            ia: iax,
            ib: ibx,
            mass: if k > 0.0 { 1.0 / k } else { 0.0 },
        }
    }
}

#[derive(Clone, Copy, Debug, Default)]
pub(super) struct PointConstraint {
    pub(super) ra: V3,
    pub(super) rb: V3,
    /// The normal row's angular Jacobians `ra × n` and `rb × n` (m): the normal relative
    /// velocity is `n·(vb − va) + ωb·(rb × n) − ωa·(ra × n)`.
    pub(super) ja: V3,
    pub(super) jb: V3,
    pub(super) n: Row,
    /// Separation at the start of the step (m).
    pub(super) separation: f64,
    /// Normal relative velocity at the start of the step (m/s), for restitution.
    pub(super) relative_velocity: f64,
    pub(super) normal_impulse: f64,
    pub(super) max_normal_impulse: f64,
}

/// The manifold's friction: two tangent rows at the points' centroid and a torsional row.
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct PatchFriction {
    /// The centroid's anchors (m, world, from each centre of mass).
    pub(super) ra: V3,
    pub(super) rb: V3,
    /// Rows along the two tangents at the centroid.
    pub(super) t: [Row; 2],
    /// The torsional row: each body's `I⁻¹ n` and the effective mass `1 / nᵀ(I⁻¹a + I⁻¹b)n`
    /// (kg·m²).
    pub(super) twist: Row,
    /// Mean distance of the points from the centroid (m): the torsional bound is
    /// `μ × arm × Σ λn`.
    pub(super) arm: f64,
    /// Accumulated impulses along the tangents (N·s).
    pub(super) tangent_impulse: [f64; 2],
    /// Accumulated torsional impulse about the normal (N·m·s).
    pub(super) twist_impulse: f64,
}

impl PatchFriction {
    /// The patch of the points' anchors `ra`, `rb` (the first `len` of `points`).
    fn new(
        points: &[PointConstraint],
        n: &V3,
        tangents: &[V3; 2],
        inv: (f64, f64, &M3, &M3),
        impulses: ([f64; 2], f64),
    ) -> Self {
        let (ima, imb, ia, ib) = inv;
        let k = points.len() as f64;
        let ra = points.iter().map(|p| p.ra).sum::<V3>() / k;
        let rb = points.iter().map(|p| p.rb).sum::<V3>() / k;
        let arm = if points.len() > 1 {
            points.iter().map(|p| (p.ra - ra).norm()).sum::<f64>() / k
        } else {
            0.0
        };
        let (ian, ibn) = (ia * n, ib * n);
        let kt = n.dot(&ian) + n.dot(&ibn);
        Self {
            ra,
            rb,
            t: [
                Row::new(&ra, &rb, &tangents[0], ima, imb, ia, ib),
                Row::new(&ra, &rb, &tangents[1], ima, imb, ia, ib),
            ],
            twist: Row {
                ia: ian,
                ib: ibn,
                mass: if kt > 0.0 && arm > 0.0 { 1.0 / kt } else { 0.0 },
            },
            arm,
            tangent_impulse: impulses.0,
            twist_impulse: impulses.1,
        }
    }
}

/// The constraint of one manifold.
#[derive(Clone, Copy, Debug)]
pub(crate) struct ContactConstraint {
    /// Body A.
    pub(crate) a: usize,
    /// Body B.
    pub(crate) b: usize,
    /// Index of the manifold it came from.
    pub(crate) manifold: usize,
    pub(super) normal: V3,
    pub(super) tangents: [V3; 2],
    pub(crate) ima: f64,
    pub(crate) imb: f64,
    /// World inverse inertias (1/(kg·m²)) of A and B: set only with rolling resistance.
    ia: M3,
    ib: M3,
    pub(super) friction: f64,
    restitution: f64,
    /// Largest rolling-resistance torque per unit normal impulse (m): coefficient × radius.
    pub(super) rolling_arm: f64,
    /// The rolling rows' effective mass `(I⁻¹a + I⁻¹b)⁻¹` (kg·m²): set only with rolling
    /// resistance.
    rolling_mass: M3,
    rolling_impulse: V3,
    /// Whether one body cannot move (stiffer softness).
    pub(crate) against_static: bool,
    /// The soft coefficients of the normal rows ([`ContactConstraint::stiffen`]); until set,
    /// rigid without position bias.
    pub(super) softness: Softness,
    pub(super) len: usize,
    pub(super) points: [PointConstraint; MAX_MANIFOLD_POINTS],
    /// The manifold's friction rows and impulses.
    pub(super) patch: PatchFriction,
    /// The substep (s) the carried impulses were accumulated over (0: none carried).
    impulse_substep: f64,
    /// Radius (m) of A's and B's part where it is round (sphere, capsule) and its centre of
    /// curvature is off the body's centre of mass; 0 otherwise.
    round_radius: [f64; 2],
    /// Each point's centres of curvature on A and B (m, body frames, from the centres of
    /// mass), where that side is round; zero otherwise, and left as they were where neither
    /// side is round.
    centre: [[V3; 2]; MAX_MANIFOLD_POINTS],
    /// Whether a round part's contact follows its body's turn within the step: the point
    /// where a round part touches stays one radius from its centre of curvature, which turns
    /// with the body, and a body's world inertia turns with it. Anchors, rows and inverse
    /// inertias fixed at the step's start misplace the point and mis-weigh the impulses on a
    /// body that turns far within a step: a top spinning at 100 rad/s turns 1.7 rad per
    /// 1/60 s step and nutates at about 30 Hz, and the stale inverse inertia raised its
    /// energy 1.2 % in 0.8 s (with fresh anchors but the stale inertia: 0.9 % in 1 s; with
    /// both fresh it never rises above the start). Such constraints take their anchors and
    /// rows at each pass from the bodies' rotations and inverse inertias now
    /// ([`ContactConstraint::rows_now`]) and are solved one by one.
    pub(super) follows: bool,
}

/// A point's angular Jacobians (m) and normal row at the current substep.
#[derive(Clone, Copy, Debug, Default)]
struct PointRows {
    ja: V3,
    jb: V3,
    n: Row,
}

/// A unit vector orthogonal to `n` and a second completing the right-handed basis.
#[inline]
pub(crate) fn tangent_basis(n: &V3) -> [V3; 2] {
    let t1 = if n.x.abs() < 0.57 {
        V3::new(0.0, n.z, -n.y)
    } else {
        V3::new(n.y, -n.x, 0.0)
    }
    .normalize();
    [t1, n.cross(&t1)]
}

/// The radius (m) and centre of curvature (m, body frame) of body `i`'s part `part` nearest
/// to `point` (m, body frame), where the part is round: a sphere's centre; the point of a
/// capsule's segment nearest to `point` (it moves little along the segment over one step).
fn round_centre(bodies: &BodySet, i: usize, part: u16, point: &V3) -> Option<(f64, V3)> {
    let (shape, rot, pos) = match &bodies.shape[i] {
        Shape::Compound(c) => {
            let p = c.parts().get(part as usize)?;
            (&p.shape, p.rot, p.pos)
        }
        s => (s, M3::identity(), V3::zeros()),
    };
    match *shape {
        Shape::Sphere { radius } => Some((radius, pos)),
        Shape::Capsule {
            radius,
            half_height,
        } => {
            let z = rot
                .tr_mul(&(point - pos))
                .z
                .clamp(-half_height, half_height);
            Some((radius, pos + rot.column(2) * z))
        }
        _ => None,
    }
}

fn rolling_radius(s: &Shape) -> f64 {
    match *s {
        Shape::Sphere { radius }
        | Shape::Capsule { radius, .. }
        | Shape::Cylinder { radius, .. } => radius,
        _ => 0.0,
    }
}

impl ContactConstraint {
    /// Builds the constraint of manifold `mi` from the bodies' current state (the world
    /// prepares its constraints in place, [`ContactConstraint::prepare_in`]).
    #[cfg(test)]
    pub(crate) fn prepare(
        bodies: &BodySet,
        m: &Manifold,
        mi: usize,
        settings: &ContactSettings,
    ) -> Self {
        let mut c = Self::blank();
        c.prepare_in(bodies, m, mi, settings);
        c
    }

    /// A constraint that changes nothing, to be prepared in place.
    pub(crate) fn blank() -> Self {
        Self {
            a: 0,
            b: 0,
            manifold: 0,
            normal: V3::zeros(),
            tangents: [V3::zeros(); 2],
            ima: 0.0,
            imb: 0.0,
            ia: M3::zeros(),
            ib: M3::zeros(),
            friction: 0.0,
            restitution: 0.0,
            rolling_arm: 0.0,
            rolling_mass: M3::zeros(),
            rolling_impulse: V3::zeros(),
            against_static: false,
            softness: Softness::rigid(0.0),
            len: 0,
            points: [PointConstraint::default(); MAX_MANIFOLD_POINTS],
            patch: PatchFriction::default(),
            impulse_substep: 0.0,
            round_radius: [0.0; 2],
            centre: [[V3::zeros(); 2]; MAX_MANIFOLD_POINTS],
            follows: false,
        }
    }

    /// [`ContactConstraint::prepare`] in place: the world's constraints are kept step after
    /// step and rewritten, which spares the copy of a new one into its place.
    pub(crate) fn prepare_in(
        &mut self,
        bodies: &BodySet,
        m: &Manifold,
        mi: usize,
        settings: &ContactSettings,
    ) {
        let (a, b) = (m.a as usize, m.b as usize);
        let ima = if bodies.awake[a] {
            bodies.inv_mass[a]
        } else {
            0.0
        };
        let imb = if bodies.awake[b] {
            bodies.inv_mass[b]
        } else {
            0.0
        };
        let (sa, sb) = carried_scale(&m.normal, &settings.up, ima, imb);
        let (ima, imb) = (ima * sa, imb * sb);
        let ia = if ima > 0.0 {
            bodies.inv_inertia_world[a] * sa
        } else {
            M3::zeros()
        };
        let ib = if imb > 0.0 {
            bodies.inv_inertia_world[b] * sb
        } else {
            M3::zeros()
        };
        let (ma, mb) = (
            &bodies.part_material(a, m.part_a),
            &bodies.part_material(b, m.part_b),
        );
        let n = m.normal;
        let tangents = tangent_basis(&n);
        let (va, wa, vb, wb) = (
            bodies.vel[a],
            bodies.omega[a],
            bodies.vel[b],
            bodies.omega[b],
        );
        for (pc, cp) in self.points.iter_mut().zip(m.points()) {
            let ra = cp.point - bodies.pos[a];
            let rb = cp.point - bodies.pos[b];
            let dv = vb + wb.cross(&rb) - va - wa.cross(&ra);
            *pc = PointConstraint {
                ra,
                rb,
                ja: ra.cross(&n),
                jb: rb.cross(&n),
                n: Row::new(&ra, &rb, &n, ima, imb, &ia, &ib),
                separation: cp.separation - m.held_overlap,
                relative_velocity: n.dot(&dv),
                normal_impulse: cp.normal_impulse,
                max_normal_impulse: 0.0,
            };
        }
        for pc in &mut self.points[m.len..] {
            *pc = PointConstraint::default();
        }
        self.patch = PatchFriction::new(
            &self.points[..m.len.max(1)],
            &n,
            &tangents,
            (ima, imb, &ia, &ib),
            if settings.friction {
                (m.friction_impulse, m.twist_impulse)
            } else {
                ([0.0; 2], 0.0)
            },
        );
        let rr = if settings.rolling {
            ma.rolling_resistance.max(mb.rolling_resistance)
                * rolling_radius(bodies.part_shape(a, m.part_a))
                    .max(rolling_radius(bodies.part_shape(b, m.part_b)))
        } else {
            0.0
        };
        let radius = self.prepare_round_centres(bodies, m, (ima > 0.0, imb > 0.0));
        self.a = a;
        self.b = b;
        self.manifold = mi;
        self.normal = n;
        self.tangents = tangents;
        self.ima = ima;
        self.imb = imb;
        // The inverse inertias and the rolling rows are read only with rolling resistance
        // (`rolling_arm` > 0), and left as they are otherwise, as the centres above.
        if rr > 0.0 {
            self.ia = ia;
            self.ib = ib;
            self.rolling_mass = (ia + ib).try_inverse().unwrap_or(M3::zeros());
        }
        self.friction = if settings.friction {
            ma.pair_friction(mb)
        } else {
            0.0
        };
        self.restitution = if settings.restitution {
            ma.pair_restitution(mb)
        } else {
            0.0
        };
        self.rolling_arm = rr;
        self.rolling_impulse = if rr > 0.0 {
            m.rolling_impulse
        } else {
            V3::zeros()
        };
        self.against_static = ima == 0.0 || imb == 0.0;
        self.softness = Softness::rigid(0.0);
        self.len = m.len;
        self.impulse_substep = m.impulse_substep;
        self.round_radius = radius;
        self.follows = radius[0] > 0.0 || radius[1] > 0.0;
    }

    /// The centres of curvature of the manifold's round parts (a sphere's or a capsule's)
    /// off their moving body's centre of mass, per point and side, and each side's radius
    /// (0 where the side is not round, or its centre lies on the body's centre of mass);
    /// `moving` says whether A and B move.
    #[inline]
    fn prepare_round_centres(
        &mut self,
        bodies: &BodySet,
        m: &Manifold,
        moving: (bool, bool),
    ) -> [f64; 2] {
        // Centres of curvature of round parts off their body's centre of mass: A's contact
        // point lies one radius along +n from its centre, B's along −n.
        // Written in place: a local array copied in at the end stalled on its own stores
        // (`perf annotate`: 13 % of this function on pyramid-1240).
        // Only read where a side is round (`round_radius`), so left as they are otherwise:
        // most contacts are between boxes, and the lines not written are not fetched.
        let mut radius = [0.0; 2];
        let round = |i: usize, part: u16, moving: bool| {
            moving
                && matches!(
                    bodies.part_shape(i, part),
                    Shape::Sphere { .. } | Shape::Capsule { .. }
                )
        };
        let (a, b) = (m.a as usize, m.b as usize);
        let sides = [
            (a, m.part_a, round(a, m.part_a, moving.0)),
            (b, m.part_b, round(b, m.part_b, moving.1)),
        ];
        let centre = &mut self.centre;
        if sides.iter().any(|s| s.2) {
            for c in centre.iter_mut() {
                *c = [V3::new(0.0, 0.0, 0.0); 2];
            }
        }
        for (side, (i, part, round)) in sides.into_iter().enumerate() {
            if !round {
                continue;
            }
            let mut off = false;
            for (c, cp) in centre.iter_mut().zip(m.points()) {
                let point = bodies.rot[i].tr_mul(&(cp.point - bodies.pos[i]));
                if let Some((r, x)) = round_centre(bodies, i, part, &point) {
                    radius[side] = r;
                    c[side] = x;
                    off |= x.norm() > FOLLOW_MIN_OFFSET;
                }
            }
            if !off {
                radius[side] = 0.0;
            }
        }
        radius
    }

    /// Point `k`'s angular Jacobians and normal row now. Unless the constraint
    /// [`follows`](ContactConstraint::follows) its round parts (`now` is `None`), those of the
    /// step's start; otherwise from its anchors now ([`ContactConstraint::anchors_now`]) and
    /// each body's inverse inertia at its rotation now, `R I⁻¹_body Rᵀ`
    /// ([`ContactConstraint::inertias_now`], taken once per pass). (The separation keeps its
    /// first-order update from the step's anchors, `n·(Δp + dθ × r)`, which is the same for a
    /// round side's contact point and its centre.)
    #[inline]
    fn rows_now(&self, k: usize, bodies: &BodySet, now: Option<&(M3, M3)>) -> PointRows {
        let pc = &self.points[k];
        let Some((ia, ib)) = now else {
            return PointRows {
                ja: pc.ja,
                jb: pc.jb,
                n: pc.n,
            };
        };
        let n = self.normal;
        let (ra, rb) = self.anchors_now(k, bodies);
        PointRows {
            ja: ra.cross(&n),
            jb: rb.cross(&n),
            n: Row::new(&ra, &rb, &n, self.ima, self.imb, ia, ib),
        }
    }

    /// For a constraint that [`follows`](ContactConstraint::follows) its round parts, each
    /// moving body's inverse inertia at its rotation now, `R I⁻¹_body Rᵀ` scaled as the
    /// contact's inverse mass (zero for a body that
    /// does not move here); `None` for one that keeps the step's rows.
    fn inertias_now(&self, bodies: &BodySet) -> Option<(M3, M3)> {
        if !self.follows {
            return None;
        }
        // Scaled as the inverse mass this contact takes (`carried_scale`).
        let world_inv = |i: usize, im: f64| {
            if im > 0.0 {
                let r = bodies.rot[i];
                r * M3::from_diagonal(&bodies.inv_inertia[i])
                    * r.transpose()
                    * (im / bodies.inv_mass[i])
            } else {
                M3::zeros()
            }
        };
        Some((world_inv(self.a, self.ima), world_inv(self.b, self.imb)))
    }

    /// Point `k`'s anchors now (m, world, from each centre of mass): a round side's centre of
    /// curvature turned with its body plus its radius along the normal; a side that is not
    /// round keeps the step's anchor.
    fn anchors_now(&self, k: usize, bodies: &BodySet) -> (V3, V3) {
        let pc = &self.points[k];
        let n = self.normal;
        let [rad_a, rad_b] = self.round_radius;
        let ra = if rad_a > 0.0 {
            bodies.rot[self.a] * self.centre[k][0] + n * rad_a
        } else {
            pc.ra
        };
        let rb = if rad_b > 0.0 {
            bodies.rot[self.b] * self.centre[k][1] - n * rad_b
        } else {
            pc.rb
        };
        (ra, rb)
    }

    /// The friction patch's anchors and rows now (see [`ContactConstraint::rows_now`]), with
    /// its accumulated impulses.
    fn patch_now(&self, bodies: &BodySet, now: Option<&(M3, M3)>) -> PatchFriction {
        let Some((ia, ib)) = now else {
            return self.patch;
        };
        let mut points = [PointConstraint::default(); MAX_MANIFOLD_POINTS];
        for (k, p) in points[..self.len].iter_mut().enumerate() {
            (p.ra, p.rb) = self.anchors_now(k, bodies);
        }
        PatchFriction::new(
            &points[..self.len.max(1)],
            &self.normal,
            &self.tangents,
            (self.ima, self.imb, ia, ib),
            (self.patch.tangent_impulse, self.patch.twist_impulse),
        )
    }

    /// Takes its stiffness from the bodies' mass ratio ([`ContactStiffness`]).
    pub(crate) fn stiffen(&mut self, k: &ContactStiffness) {
        self.softness = k.softness(self.against_static, self.mass_ratio());
    }

    /// Solves the contact as if it were `extra` (m) deeper than prepared (negative: less
    /// deep), as its hold changes (`pipeline/sink_hold.rs`).
    pub(crate) fn deepen(&mut self, extra: f64) {
        for pc in &mut self.points[..self.len] {
            pc.separation -= extra;
        }
    }

    /// Whether the contact follows a round part's turn within the step
    /// ([`ContactConstraint::follows`]).
    pub(crate) fn follows_turn(&self) -> bool {
        self.follows
    }

    /// The normal (world, from A to B).
    pub(crate) fn normal(&self) -> V3 {
        self.normal
    }

    /// The sum of the carried normal impulses (N·s).
    pub(crate) fn normal_impulse(&self) -> f64 {
        self.points[..self.len]
            .iter()
            .map(|p| p.normal_impulse)
            .sum()
    }

    /// The first point's anchor on body A (m, world, from A's centre of mass).
    pub(crate) fn anchor_a(&self) -> V3 {
        self.points[0].ra
    }

    /// Scales the carried impulses by `f` (–): impulses are accumulated per substep, so a
    /// contact whose substep changes from `h₀` to `h` carries `h / h₀` of them.
    pub(crate) fn scale_impulses(&mut self, f: f64) {
        for pc in &mut self.points[..self.len] {
            pc.normal_impulse *= f;
        }
        let p = &mut self.patch;
        p.tangent_impulse = [p.tangent_impulse[0] * f, p.tangent_impulse[1] * f];
        p.twist_impulse *= f;
        self.rolling_impulse *= f;
        self.impulse_substep *= f;
    }

    /// Ratio of the heavier to the lighter moving body (1 against a body that does not move).
    pub(crate) fn mass_ratio(&self) -> f64 {
        if self.against_static {
            1.0
        } else {
            self.ima.max(self.imb) / self.ima.min(self.imb)
        }
    }

    /// Sets the soft coefficients of the normal rows.
    pub(crate) fn set_softness(&mut self, s: Softness) {
        self.softness = s;
    }

    #[inline]
    fn apply(&self, bodies: &mut BodySet, p: &V3, ia_ang: &V3, ib_ang: &V3, s: f64) {
        let (a, b) = (self.a, self.b);
        bodies.vel[a] -= p * (self.ima * s);
        bodies.omega[a] -= ia_ang * s;
        bodies.vel[b] += p * (self.imb * s);
        bodies.omega[b] += ib_ang * s;
    }

    /// Applies the accumulated impulses (warm start).
    pub(crate) fn warm_start(&self, bodies: &mut BodySet) {
        // The friction patch's impulses, then each point's normal impulse, summed before
        // they are applied once (the four-lane warm start sums in the same order).
        let now = self.inertias_now(bodies);
        let f = self.patch_now(bodies, now.as_ref());
        let [l0, l1] = f.tangent_impulse;
        let tw = f.twist_impulse;
        let mut total = 0.0;
        let mut ia = f.t[0].ia * l0 + f.t[1].ia * l1 + f.twist.ia * tw;
        let mut ib = f.t[0].ib * l0 + f.t[1].ib * l1 + f.twist.ib * tw;
        for (k, pc) in self.points[..self.len].iter().enumerate() {
            let r = self.rows_now(k, bodies, now.as_ref());
            total += pc.normal_impulse;
            ia += r.n.ia * pc.normal_impulse;
            ib += r.n.ib * pc.normal_impulse;
        }
        let p = self.normal * total + self.tangents[0] * l0 + self.tangents[1] * l1;
        if p != V3::zeros() || ia != V3::zeros() || ib != V3::zeros() {
            self.apply(bodies, &p, &ia, &ib, 1.0);
        }
        if self.rolling_arm > 0.0 {
            let r = self.rolling_impulse;
            bodies.omega[self.a] -= self.ia * r;
            bodies.omega[self.b] += self.ib * r;
        }
    }

    /// One pass over the points: normal (with the position bias of its
    /// [`ContactConstraint::softness`] in the substep's solve pass), friction, rolling
    /// resistance. `inv_h` = 1 / substep (1/s).
    pub(crate) fn solve(
        &mut self,
        bodies: &mut BodySet,
        inv_h: f64,
        max_push: f64,
        pass: SolvePass,
    ) {
        let SolvePass { use_bias, reverse } = pass;
        let soft = self.softness;
        let (a, b) = (self.a, self.b);
        let n = self.normal;
        let (ima, imb) = (self.ima, self.imb);
        // Work on local copies of the two bodies' velocities; write back once.
        let (mut va, mut wa, mut vb, mut wb) = (
            bodies.vel[a],
            bodies.omega[a],
            bodies.vel[b],
            bodies.omega[b],
        );
        // The separation now: `n·Δp` once, then each point's `dθb·(rb × n) − dθa·(ra × n)`.
        let nd = n.dot(&(bodies.dp[b] - bodies.dp[a]));
        let (dta, dtb) = (bodies.dtheta[a], bodies.dtheta[b]);
        let now = self.inertias_now(bodies);
        let mut total = 0.0;
        let len = self.len;
        let idx = |i: usize| if reverse { len - 1 - i } else { i };
        for i in 0..len {
            let r = self.rows_now(idx(i), bodies, now.as_ref());
            let pc = &mut self.points[idx(i)];
            let s = nd + (dtb.dot(&pc.jb) - dta.dot(&pc.ja)) + pc.separation;
            let (bias, ms, is) = if s > 0.0 {
                (s * inv_h, 1.0, 0.0)
            } else if use_bias {
                let s = (s + LINEAR_SLOP).min(0.0);
                (
                    (soft.bias_rate * s).max(-max_push),
                    soft.mass_scale,
                    soft.impulse_scale,
                )
            } else {
                (0.0, 1.0, 0.0)
            };
            let vn = n.dot(&(vb - va)) + (wb.dot(&r.jb) - wa.dot(&r.ja));
            let imp = -r.n.mass * ms * (vn + bias) - is * pc.normal_impulse;
            let new = (pc.normal_impulse + imp).max(0.0);
            let delta = new - pc.normal_impulse;
            pc.normal_impulse = new;
            pc.max_normal_impulse = pc.max_normal_impulse.max(delta);
            total += new;
            let p = n * delta;
            va -= p * ima;
            wa -= r.n.ia * delta;
            vb += p * imb;
            wb += r.n.ib * delta;
        }
        let f = &self.patch;
        let carried = f.tangent_impulse != [0.0; 2] || f.twist_impulse != 0.0;
        if self.friction > 0.0 && (total > 0.0 || carried) {
            let (t0, t1) = (self.tangents[0], self.tangents[1]);
            let r = self.patch_now(bodies, now.as_ref());
            let l0 = self.patch.tangent_impulse;
            let dv = vb + wb.cross(&r.rb) - va - wa.cross(&r.ra);
            let mut l = [
                l0[0] - r.t[0].mass * t0.dot(&dv),
                l0[1] - r.t[1].mass * t1.dot(&dv),
            ];
            // Coulomb cone: |λt| ≤ μ Σ λn.
            let max = self.friction * total;
            let len2 = l[0] * l[0] + l[1] * l[1];
            if len2 > max * max {
                let sc = if len2 > 0.0 { max / len2.sqrt() } else { 0.0 };
                l = [l[0] * sc, l[1] * sc];
            }
            let d = [l[0] - l0[0], l[1] - l0[1]];
            self.patch.tangent_impulse = l;
            let p = t0 * d[0] + t1 * d[1];
            va -= p * ima;
            wa -= r.t[0].ia * d[0] + r.t[1].ia * d[1];
            vb += p * imb;
            wb += r.t[0].ib * d[0] + r.t[1].ib * d[1];
            // Torsion about the normal: |λ| ≤ μ ρ Σ λn.
            let tw0 = self.patch.twist_impulse;
            let max = self.friction * r.arm * total;
            // Clamped as the four-lane solve clamps (a NaN bound gives the bound).
            let tw = tw0 - r.twist.mass * n.dot(&(wb - wa));
            let tw = if tw > -max { tw } else { -max };
            let tw = if tw < max { tw } else { max };
            let d = tw - tw0;
            self.patch.twist_impulse = tw;
            wa -= r.twist.ia * d;
            wb += r.twist.ib * d;
        }
        if self.rolling_arm > 0.0 {
            let dw = wb - wa;
            let old = self.rolling_impulse;
            let mut l = old - self.rolling_mass * dw;
            let max = self.rolling_arm * total;
            let n2 = l.norm_squared();
            if n2 > max * max {
                l *= max / n2.sqrt();
            }
            let d = l - old;
            self.rolling_impulse = l;
            wa -= self.ia * d;
            wb += self.ib * d;
        }
        bodies.vel[a] = va;
        bodies.omega[a] = wa;
        bodies.vel[b] = vb;
        bodies.omega[b] = wb;
    }

    /// Restitution: points that approached faster than `threshold` (m/s) and carried load
    /// bounce with the material's coefficient.
    pub(crate) fn restitution(&mut self, bodies: &mut BodySet, threshold: f64) {
        if self.restitution == 0.0 {
            return;
        }
        let (a, b) = (self.a, self.b);
        let n = self.normal;
        for k in 0..self.len {
            let pc = self.points[k];
            if pc.relative_velocity > -threshold || pc.max_normal_impulse == 0.0 {
                continue;
            }
            let dv = bodies.vel[b] + bodies.omega[b].cross(&pc.rb)
                - bodies.vel[a]
                - bodies.omega[a].cross(&pc.ra);
            let vn = n.dot(&dv);
            let imp = -pc.n.mass * (vn + self.restitution * pc.relative_velocity);
            let new = (pc.normal_impulse + imp).max(0.0);
            let delta = new - pc.normal_impulse;
            self.points[k].normal_impulse = new;
            self.points[k].max_normal_impulse = pc.max_normal_impulse.max(delta);
            self.apply(
                bodies,
                &(n * delta),
                &(pc.n.ia * delta),
                &(pc.n.ib * delta),
                1.0,
            );
        }
    }

    /// Whether this constraint has a restitution coefficient.
    pub(crate) fn bounces(&self) -> bool {
        self.restitution > 0.0
    }

    /// Writes the accumulated impulses back into the manifold (warm start of the next step).
    pub(crate) fn store(&self, m: &mut Manifold) {
        for (cp, pc) in m.points[..m.len].iter_mut().zip(&self.points) {
            cp.normal_impulse = pc.normal_impulse;
            cp.max_normal_impulse = pc.max_normal_impulse;
        }
        m.friction_impulse = self.patch.tangent_impulse;
        m.twist_impulse = self.patch.twist_impulse;
        m.rolling_impulse = self.rolling_impulse;
    }
}

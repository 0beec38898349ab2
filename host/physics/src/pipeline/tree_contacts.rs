//! Contacts that touch a link of an articulated tree, solved in the same passes as the
//! free-body contacts.
//!
//! A link takes part in collision detection through a *proxy*: a kinematic body of the body
//! set that carries the link's shapes and is posed from the tree's forward kinematics at the
//! start and end of every step. A manifold with a proxy on either side becomes a
//! [`TreeContact`] instead of a free-body contact constraint. Each of its rows (normal and two
//! tangents per point) acts on the tree's generalised velocities: the row's Jacobian `J`
//! (`J q̇` = the link point's velocity along the row) runs through the tree from the link to
//! the root, and the tree's response to an impulse `λ` is `q̇ += M(q)⁻¹ Jᵀ λ`, with `M⁻¹ Jᵀ`
//! from one articulated-body pass at zero velocity and gravity (O(n) per row, Mirtich's
//! impulse propagation through the articulated inertias). The effective mass of a row is
//! `1 / (Σ_free (m⁻¹ + (r×d)·I⁻¹(r×d)) + Σ_link J M⁻¹ Jᵀ)`.
//!
//! Rows are prepared once per step at the start-of-step configuration, as the free-body rows
//! are; the separation is updated through the substeps from each side's displacement (for a
//! link, where the link's pose at the current substep carries the contact point, held in the
//! link's frame). Friction (Coulomb cone),
//! restitution above the threshold, soft position bias and warm starting follow the free-body
//! contacts exactly.

use super::articulated::ArticulatedSystem;
use crate::algebra::SE3;
use crate::dynamics::solver::contact_constraint::{tangent_basis, LINEAR_SLOP};
use crate::dynamics::solver::{ContactSettings, Softness, SolvePass};
use crate::dynamics::{BodySet, DynamicsError};
use crate::geometry::{Manifold, M3, MAX_MANIFOLD_POINTS, V3};

/// A link coordinate moves a contact point "only tangentially" when the point's velocity
/// along the normal is at most this fraction of its speed. A point that moves exactly
/// tangentially by the joint's geometry (a bar turning in its bearing) comes out at rounding
/// level, some 1e-16 of its speed; solved, its normal row's effective mass would be some
/// 1e30 kg and its impulse unbounded.
pub(crate) const INERT_NORMAL_RATIO: f64 = 1e-9;

/// What a side of a contact is.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Side {
    /// A body contacts cannot move (fixed, kinematic or sleeping).
    Still,
    /// A free dynamic body: inverse mass and world inverse inertia.
    Free { body: usize, im: f64, ii: M3 },
    /// Link `link` of tree `tree`.
    Link { tree: usize, link: usize },
}

/// The link behind a proxy body.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Proxy {
    /// The tree.
    pub(crate) tree: usize,
    /// The link (body index in the tree).
    pub(crate) link: usize,
}

#[derive(Clone, Copy, Debug, Default)]
struct Point {
    ra: V3,
    rb: V3,
    /// The contact point at the start of the step (m, world).
    point: V3,
    /// Per side (A, B), the contact point in its link's frame, where the side is a link (m).
    anchor: [V3; 2],
    /// Effective masses of the normal and the two tangent rows (kg).
    mass: [f64; 3],
    /// Start of this point's rows in the row buffer: per direction (n, t0, t1) and side
    /// (A, B), `J` then `M⁻¹Jᵀ`, each `nv` of that side's tree (unused for other sides).
    rows: [[usize; 2]; 3],
    separation: f64,
    relative_velocity: f64,
    normal_impulse: f64,
    tangent_impulse: [f64; 2],
    /// The largest normal impulse of one pass of the step (N·s).
    max_normal_impulse: f64,
    /// Normal impulse of the step's finished substeps (N·s).
    step_impulse: f64,
}

/// A contact with a tree link on at least one side.
#[derive(Clone, Debug)]
pub(crate) struct TreeContact {
    a: Side,
    b: Side,
    /// Index of the manifold it came from.
    pub(crate) manifold: usize,
    normal: V3,
    tangents: [V3; 2],
    friction: f64,
    restitution: f64,
    len: usize,
    points: [Point; MAX_MANIFOLD_POINTS],
}

/// The tree contacts of a step and their row buffer (reused: no allocation once warm).
#[derive(Clone, Debug, Default)]
pub(crate) struct TreeContacts {
    pub(crate) contacts: Vec<TreeContact>,
    rows: Vec<f64>,
    /// Manifolds whose contacts no impulse can act on (`inert_contact`).
    pub(crate) inert: Vec<usize>,
    /// Scratch: a contact point's velocity Jacobian on side A's and side B's link.
    point_jacobians: [Vec<V3>; 2],
    /// Substeps warm-started so far in this step.
    substeps: usize,
}

/// Per tree, the world pose of each link at the current substep's configuration.
pub(crate) type TreePoses = Vec<Vec<SE3<f64>>>;

fn side_of(bodies: &BodySet, proxies: &[Option<Proxy>], i: usize) -> Side {
    if let Some(p) = proxies.get(i).copied().flatten() {
        return Side::Link {
            tree: p.tree,
            link: p.link,
        };
    }
    if bodies.awake[i] && bodies.inv_mass[i] > 0.0 {
        Side::Free {
            body: i,
            im: bodies.inv_mass[i],
            ii: bodies.inv_inertia_world[i],
        }
    } else {
        Side::Still
    }
}

impl TreeContacts {
    /// The trees whose links had a contact that impulses act on in the last step, once per
    /// link side of each contact (a contact between two links names both trees).
    pub(crate) fn trees_touching(&self) -> impl Iterator<Item = usize> + '_ {
        self.contacts.iter().flat_map(|c| {
            [c.a, c.b].into_iter().filter_map(|side| match side {
                Side::Link { tree, .. } => Some(tree),
                _ => None,
            })
        })
    }

    /// Forgets last step's contacts.
    pub(crate) fn clear(&mut self) {
        self.contacts.clear();
        self.inert.clear();
        self.rows.clear();
        self.substeps = 0;
    }

    /// Builds the contact of manifold `mi`, whose bodies include a proxy.
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn prepare(
        &mut self,
        bodies: &BodySet,
        proxies: &[Option<Proxy>],
        trees: &mut [ArticulatedSystem],
        poses: &[Vec<crate::algebra::SE3<f64>>],
        m: &Manifold,
        mi: usize,
        settings: &ContactSettings,
    ) -> Result<(), DynamicsError> {
        let (ia, ib) = (m.a as usize, m.b as usize);
        let (a, b) = (side_of(bodies, proxies, ia), side_of(bodies, proxies, ib));
        let (ma, mb) = (
            bodies.part_material(ia, m.part_a),
            bodies.part_material(ib, m.part_b),
        );
        let n = m.normal;
        let tangents = tangent_basis(&n);
        let dirs = [n, tangents[0], tangents[1]];
        if self.inert_contact(proxies, trees, poses, m, &a, &b) {
            self.inert.push(mi);
            return Ok(());
        }
        let mut points = [Point::default(); MAX_MANIFOLD_POINTS];
        for (pc, cp) in points.iter_mut().zip(m.points()) {
            let ra = cp.point - bodies.pos[ia];
            let rb = cp.point - bodies.pos[ib];
            // The contact point's velocity Jacobian on each link side, shared by its rows.
            let mut anchor = [V3::zeros(); 2];
            for (s, side) in [a, b].into_iter().enumerate() {
                if let Side::Link { tree, link } = side {
                    anchor[s] = poses[tree][link]
                        .r
                        .tr_mul(&(cp.point - poses[tree][link].p));
                    trees[tree].point_velocity_jacobian(
                        &poses[tree],
                        link,
                        &cp.point,
                        &mut self.point_jacobians[s],
                    );
                }
            }
            let mut vel = [0.0; 2];
            for (k, d) in dirs.iter().enumerate() {
                let mut k_sum = 0.0;
                for (s, (side, body, r)) in [(a, ia, ra), (b, ib, rb)].into_iter().enumerate() {
                    match side {
                        Side::Still => {}
                        Side::Free { im, ii, .. } => {
                            let rd = r.cross(d);
                            k_sum += im + rd.dot(&(ii * rd));
                            if k == 0 {
                                vel[s] = d.dot(&(bodies.vel[body] + bodies.omega[body].cross(&r)));
                            }
                        }
                        Side::Link { tree, .. } => {
                            let t = &mut trees[tree];
                            let nv = t.qd.len();
                            let start = self.rows.len();
                            self.rows.resize(start + 2 * nv, 0.0);
                            let (j, w) = self.rows[start..].split_at_mut(nv);
                            for (x, u) in j.iter_mut().zip(&self.point_jacobians[s]) {
                                *x = d.dot(u);
                            }
                            t.apply_inverse_mass(j, w)?;
                            k_sum += j.iter().zip(w.iter()).map(|(x, y)| x * y).sum::<f64>();
                            if k == 0 {
                                vel[s] = j.iter().zip(&t.qd).map(|(x, y)| x * y).sum();
                            }
                            pc.rows[k][s] = start;
                        }
                    }
                }
                pc.mass[k] = if k_sum > 0.0 { 1.0 / k_sum } else { 0.0 };
            }
            *pc = Point {
                ra,
                rb,
                point: cp.point,
                anchor,
                separation: cp.separation,
                relative_velocity: vel[1] - vel[0],
                normal_impulse: cp.normal_impulse,
                tangent_impulse: if settings.friction {
                    cp.tangent_impulse
                } else {
                    [0.0; 2]
                },
                max_normal_impulse: 0.0,
                step_impulse: 0.0,
                ..*pc
            };
        }
        self.contacts.push(TreeContact {
            a,
            b,
            manifold: mi,
            normal: n,
            tangents,
            friction: if settings.friction {
                ma.pair_friction(&mb)
            } else {
                0.0
            },
            restitution: if settings.restitution {
                ma.pair_restitution(&mb)
            } else {
                0.0
            },
            len: m.len,
            points,
        });
        Ok(())
    }

    /// Whether neither side of manifold `m` can move along its normal at any of its points
    /// (a rod's bar in its wall slot, a sole turning over the cloth): no side is a free body,
    /// and at every point each coordinate of each link side moves the point along the normal
    /// by at most [`INERT_NORMAL_RATIO`] of its speed. No impulse changes such a contact's
    /// gap, so it has no rows to solve.
    fn inert_contact(
        &mut self,
        proxies: &[Option<Proxy>],
        trees: &[ArticulatedSystem],
        poses: &[Vec<crate::algebra::SE3<f64>>],
        m: &Manifold,
        a: &Side,
        b: &Side,
    ) -> bool {
        if matches!(a, Side::Free { .. }) || matches!(b, Side::Free { .. }) {
            return false;
        }
        let n = m.normal;
        for cp in m.points() {
            for (side, body) in [(a, m.a as usize), (b, m.b as usize)] {
                let Side::Link { tree, .. } = *side else {
                    continue;
                };
                let link = proxies[body].map_or(0, |p| p.link);
                let u = &mut self.point_jacobians[0];
                trees[tree].point_velocity_jacobian(&poses[tree], link, &cp.point, u);
                if u.iter()
                    .any(|u| n.dot(u).abs() > INERT_NORMAL_RATIO * u.norm())
                {
                    return false;
                }
            }
        }
        true
    }

    /// Velocity of a side at a point along row `k` (m/s).
    #[inline]
    fn side_velocity(
        &self,
        side: Side,
        r: &V3,
        d: &V3,
        row: usize,
        bodies: &BodySet,
        trees: &[ArticulatedSystem],
    ) -> f64 {
        match side {
            Side::Still => 0.0,
            Side::Free { body, .. } => d.dot(&(bodies.vel[body] + bodies.omega[body].cross(r))),
            Side::Link { tree, .. } => {
                let qd = &trees[tree].qd;
                self.rows[row..row + qd.len()]
                    .iter()
                    .zip(qd)
                    .map(|(j, v)| j * v)
                    .sum()
            }
        }
    }

    /// Applies impulse `lambda` (N·s) along `d` to a side.
    #[inline]
    #[allow(clippy::too_many_arguments)]
    fn apply(
        &self,
        side: Side,
        r: &V3,
        d: &V3,
        row: usize,
        lambda: f64,
        bodies: &mut BodySet,
        trees: &mut [ArticulatedSystem],
    ) {
        match side {
            Side::Still => {}
            Side::Free { body, im, ii } => {
                bodies.vel[body] += d * (im * lambda);
                bodies.omega[body] += ii * r.cross(d) * lambda;
            }
            Side::Link { tree, .. } => {
                let qd = &mut trees[tree].qd;
                let nv = qd.len();
                for (v, w) in qd.iter_mut().zip(&self.rows[row + nv..row + 2 * nv]) {
                    *v += w * lambda;
                }
            }
        }
    }

    /// Displacement of a side's point along the normal over the step so far (m): a free
    /// body's from its displacement and turn; a link's from where its pose now carries the
    /// point (not `J Δq`, which misses the point's swing when a link turns about a joint far
    /// from it: a falling arm's links dipped millimetres past a step's edge in one step).
    #[inline]
    fn side_displacement(
        side: Side,
        r: &V3,
        anchor: &V3,
        point: &V3,
        n: &V3,
        bodies: &BodySet,
        poses: &TreePoses,
    ) -> f64 {
        match side {
            Side::Still => 0.0,
            Side::Free { body, .. } => n.dot(&(bodies.dp[body] + bodies.dtheta[body].cross(r))),
            Side::Link { tree, link } => {
                let pose = &poses[tree][link];
                n.dot(&(pose.r * anchor + pose.p - point))
            }
        }
    }

    /// Applies the accumulated impulses (warm start). From the second substep of a step on,
    /// the accumulated normal impulse is what the previous substep gave, and joins the
    /// step's total.
    pub(crate) fn warm_start(&mut self, bodies: &mut BodySet, trees: &mut [ArticulatedSystem]) {
        if self.substeps > 0 {
            for c in &mut self.contacts {
                for pc in &mut c.points[..c.len] {
                    pc.step_impulse += pc.normal_impulse;
                }
            }
        }
        self.substeps += 1;
        for c in &self.contacts {
            let dirs = [c.normal, c.tangents[0], c.tangents[1]];
            for pc in &c.points[..c.len] {
                let l = [
                    pc.normal_impulse,
                    pc.tangent_impulse[0],
                    pc.tangent_impulse[1],
                ];
                for k in 0..3 {
                    if l[k] != 0.0 {
                        self.apply(c.a, &pc.ra, &dirs[k], pc.rows[k][0], -l[k], bodies, trees);
                        self.apply(c.b, &pc.rb, &dirs[k], pc.rows[k][1], l[k], bodies, trees);
                    }
                }
            }
        }
    }

    /// One Gauss–Seidel pass over every tree contact (normal with the soft position bias in
    /// the solve pass, then friction), as the free-body contacts do.
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn solve(
        &mut self,
        bodies: &mut BodySet,
        trees: &mut [ArticulatedSystem],
        poses: &TreePoses,
        soft: &Softness,
        soft_static: &Softness,
        inv_h: f64,
        max_push: f64,
        pass: SolvePass,
    ) {
        let mut contacts = std::mem::take(&mut self.contacts);
        for c in &mut contacts {
            let still = matches!(c.a, Side::Still) || matches!(c.b, Side::Still);
            let soft = if still { soft_static } else { soft };
            let n = c.normal;
            for i in 0..c.len {
                let i = if pass.reverse { c.len - 1 - i } else { i };
                let pc = c.points[i];
                let s = pc.separation
                    + Self::side_displacement(
                        c.b,
                        &pc.rb,
                        &pc.anchor[1],
                        &pc.point,
                        &n,
                        bodies,
                        poses,
                    )
                    - Self::side_displacement(
                        c.a,
                        &pc.ra,
                        &pc.anchor[0],
                        &pc.point,
                        &n,
                        bodies,
                        poses,
                    );
                let (bias, ms, is) = if s > 0.0 {
                    (s * inv_h, 1.0, 0.0)
                } else if pass.use_bias {
                    let s = (s + LINEAR_SLOP).min(0.0);
                    (
                        (soft.bias_rate * s).max(-max_push),
                        soft.mass_scale,
                        soft.impulse_scale,
                    )
                } else {
                    (0.0, 1.0, 0.0)
                };
                let vn = self.side_velocity(c.b, &pc.rb, &n, pc.rows[0][1], bodies, trees)
                    - self.side_velocity(c.a, &pc.ra, &n, pc.rows[0][0], bodies, trees);
                let imp = -pc.mass[0] * ms * (vn + bias) - is * pc.normal_impulse;
                let new = (pc.normal_impulse + imp).max(0.0);
                let delta = new - pc.normal_impulse;
                c.points[i].normal_impulse = new;
                c.points[i].max_normal_impulse = pc.max_normal_impulse.max(delta);
                self.apply(c.a, &pc.ra, &n, pc.rows[0][0], -delta, bodies, trees);
                self.apply(c.b, &pc.rb, &n, pc.rows[0][1], delta, bodies, trees);
            }
            if c.friction > 0.0 {
                for i in 0..c.len {
                    let pc = c.points[i];
                    if pc.normal_impulse == 0.0 && pc.tangent_impulse == [0.0; 2] {
                        continue;
                    }
                    let mut l = [0.0; 2];
                    for (k, lk) in l.iter_mut().enumerate() {
                        let t = c.tangents[k];
                        let v =
                            self.side_velocity(c.b, &pc.rb, &t, pc.rows[k + 1][1], bodies, trees)
                                - self.side_velocity(
                                    c.a,
                                    &pc.ra,
                                    &t,
                                    pc.rows[k + 1][0],
                                    bodies,
                                    trees,
                                );
                        *lk = pc.tangent_impulse[k] - pc.mass[k + 1] * v;
                    }
                    let max = c.friction * pc.normal_impulse;
                    let len2 = l[0] * l[0] + l[1] * l[1];
                    if len2 > max * max {
                        let sc = if len2 > 0.0 { max / len2.sqrt() } else { 0.0 };
                        l = [l[0] * sc, l[1] * sc];
                    }
                    for (k, lk) in l.iter().enumerate() {
                        let d = lk - pc.tangent_impulse[k];
                        let t = c.tangents[k];
                        self.apply(c.a, &pc.ra, &t, pc.rows[k + 1][0], -d, bodies, trees);
                        self.apply(c.b, &pc.rb, &t, pc.rows[k + 1][1], d, bodies, trees);
                    }
                    c.points[i].tangent_impulse = l;
                }
            }
        }
        self.contacts = contacts;
    }

    /// Restitution: points that approached faster than `threshold` (m/s) and carried load
    /// bounce with the material's coefficient.
    pub(crate) fn restitution(
        &mut self,
        bodies: &mut BodySet,
        trees: &mut [ArticulatedSystem],
        threshold: f64,
    ) {
        let mut contacts = std::mem::take(&mut self.contacts);
        for c in &mut contacts {
            if c.restitution == 0.0 {
                continue;
            }
            let n = c.normal;
            for i in 0..c.len {
                let pc = c.points[i];
                if pc.relative_velocity > -threshold || pc.max_normal_impulse == 0.0 {
                    continue;
                }
                let vn = self.side_velocity(c.b, &pc.rb, &n, pc.rows[0][1], bodies, trees)
                    - self.side_velocity(c.a, &pc.ra, &n, pc.rows[0][0], bodies, trees);
                let imp = -pc.mass[0] * (vn + c.restitution * pc.relative_velocity);
                let new = (pc.normal_impulse + imp).max(0.0);
                let delta = new - pc.normal_impulse;
                c.points[i].normal_impulse = new;
                c.points[i].max_normal_impulse = pc.max_normal_impulse.max(delta);
                self.apply(c.a, &pc.ra, &n, pc.rows[0][0], -delta, bodies, trees);
                self.apply(c.b, &pc.rb, &n, pc.rows[0][1], delta, bodies, trees);
            }
        }
        self.contacts = contacts;
    }

    /// Writes the accumulated impulses back into the manifolds (warm start of the next
    /// step). A point's `max_normal_impulse` is the normal impulse it gave over the whole
    /// step (every substep's, N·s): a link that keeps pushing through the substeps (a
    /// driven rod kicking the ball) gives its impact in parts, and the step's sum is the
    /// impact's strength.
    pub(crate) fn store(&self, manifolds: &mut [Manifold], substep: f64) {
        for &mi in &self.inert {
            let m = &mut manifolds[mi];
            for cp in m.points[..m.len].iter_mut() {
                cp.normal_impulse = 0.0;
                cp.tangent_impulse = [0.0; 2];
                cp.max_normal_impulse = 0.0;
            }
            m.impulse_substep = 0.0;
        }
        for c in &self.contacts {
            let m = &mut manifolds[c.manifold];
            m.impulse_substep = substep;
            for (cp, pc) in m.points[..m.len].iter_mut().zip(&c.points) {
                cp.normal_impulse = pc.normal_impulse;
                cp.tangent_impulse = pc.tangent_impulse;
                cp.max_normal_impulse = pc
                    .max_normal_impulse
                    .max(pc.step_impulse + pc.normal_impulse);
            }
        }
    }
}

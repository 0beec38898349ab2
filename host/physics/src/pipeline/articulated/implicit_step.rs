//! Linearly implicit velocity update of an articulated tree, O(n) by an articulated-body
//! recursion.
//!
//! Semi-implicit Euler takes `q̇₁ = q̇₀ + h M⁻¹ (τ − C(q, q̇₀) q̇₀ − g(q))`: the velocity
//! products (Coriolis, centrifugal and gyroscopic terms, the `ad` and `ad*` terms of ABA) are
//! explicit. Their Jacobian `D = ∂(C q̇)/∂q̇` has eigenvalues of the order of the joint rates
//! divided by the links' own share of the inertia — for a whipping chain of thin rods tens of
//! thousands per second — and explicit treatment multiplies such a mode by `|1 + i h λ| > 1`
//! each step. This update takes them implicitly, linearised at `q̇₀` (one Newton step of
//! backward Euler in the velocity, at fixed `q`):
//!
//! `(M + h D) Δq̇ = h (τ − C(q, q̇₀) q̇₀ − g(q))`, `q̇₁ = q̇₀ + Δq̇`.
//!
//! `M + h D` is the joint-space operator of a tree whose links carry, besides their inertia,
//! the linearised velocity products. In body frames (as [`aba`](crate::dynamics::aba)), with
//! `A_i = Ad_{f_i⁻¹}`, `v_i = S_i q̇_i` and `V_i` the link twist, the directional derivative of
//! the recursive Newton–Euler equations along `x = Δq̇` gives per link the pair
//! `z_i = (w_i, ã_i)` (the twist change and the "acceleration" `w_i + h δa_i`):
//!
//! * `w_i = A_i w_λ + S_i x_i`,
//! * `ã_i = A_i ã_λ − h ad_{v_i} A_i w_λ + (S_i + h (ad_{V_i} − ad_{v_i}) S_i) x_i`,
//! * link wrench `F_i = I_i ã_i + h G_i w_i + Σ_children Ad*_{f_c⁻¹} F_c`, with
//!   `G_i w = −ad*_w (I_i V_i) − ad*_{V_i} (I_i w)`,
//! * joint equation `S_iᵀ F_i = h (τ_i − S_iᵀ F⁰_i)` (`F⁰` the Newton–Euler wrenches at
//!   `q̈ = 0`, gravity included).
//!
//! That is a chain of linear maps `z_i = X_i z_λ + Ŝ_i x_i` (12×12 and 12×d) and wrenches
//! linear in `z_i` (6×12), solved by the articulated-body elimination: backward, children
//! first, `P_i` (6×12) and `p_i` collect `F_i = P_i z_i + p_i`; `D_i = S_iᵀ P_i Ŝ_i` (d×d, not
//! symmetric), `K_i = D_i⁻¹ S_iᵀ P_i X_i`, `κ_i = D_i⁻¹ (r_i − S_iᵀ p_i)`, and into the
//! parent `P_λ += Ad*_{f_i⁻¹} (P_i X_i − P_i Ŝ_i K_i)`, `p_λ += Ad*_{f_i⁻¹} (p_i + P_i Ŝ_i κ_i)`;
//! forward, `x_i = κ_i − K_i z_λ`. As `h → 0` the operator is `M` and the update is
//! `h q̈` of ABA. The joint's own bias `Ṡ q̇` (universal joints) stays explicit.
//!
//! Cost: a fixed number of 6×12 and 12×12 products per link — O(n), several times one ABA
//! (the `tree_step` group of `benches/tree_response.rs`).

use nalgebra::{Matrix6, SMatrix, SVector, Vector6};

use crate::algebra::{dse3, se3, Vec3, SE3};
use crate::dynamics::DynamicsError;
use crate::model::ArticulatedTree;

type M6 = Matrix6<f64>;
type M6x12 = SMatrix<f64, 6, 12>;
type M12 = SMatrix<f64, 12, 12>;
type M12x6 = SMatrix<f64, 12, 6>;
type V6 = Vector6<f64>;
type V12 = SVector<f64, 12>;

/// Preallocated storage of [`implicit_velocity_update`] for one model.
#[derive(Clone, Debug)]
pub(crate) struct ImplicitWorkspace {
    nbodies: usize,
    ndofs: usize,
    s_cols: Vec<se3<f64>>,
    v: Vec<se3<f64>>,
    a0: Vec<se3<f64>>,
    f: Vec<SE3<f64>>,
    f0: Vec<V6>,
    x: Vec<M12>,
    shat: Vec<M12x6>,
    s: Vec<M6>,
    p: Vec<M6x12>,
    pb: Vec<V6>,
    k: Vec<M6x12>,
    kappa: Vec<V6>,
    z: Vec<V12>,
    /// `S_kᵀ I_i S_k`, the joint's own rigid inertia per coordinate.
    rigid: Vec<V6>,
}

impl ImplicitWorkspace {
    /// Storage for `model`.
    pub(crate) fn new(model: &ArticulatedTree<f64>) -> Self {
        let n = model.len();
        Self {
            nbodies: n,
            ndofs: model.nv(),
            s_cols: vec![se3::zeros(); model.nv()],
            v: vec![se3::zeros(); n],
            a0: vec![se3::zeros(); n],
            f: vec![SE3::identity(); n],
            f0: vec![V6::zeros(); n],
            x: vec![M12::zeros(); n],
            shat: vec![M12x6::zeros(); n],
            s: vec![M6::zeros(); n],
            p: vec![M6x12::zeros(); n],
            pb: vec![V6::zeros(); n],
            k: vec![M6x12::zeros(); n],
            kappa: vec![V6::zeros(); n],
            z: vec![V12::zeros(); n],
            rigid: vec![V6::zeros(); n],
        }
    }
}

fn tw(v: &se3<f64>) -> V6 {
    V6::new(v.w.x, v.w.y, v.w.z, v.v.x, v.v.y, v.v.z)
}

fn wr(f: &dse3<f64>) -> V6 {
    V6::new(f.m.x, f.m.y, f.m.z, f.f.x, f.f.y, f.f.z)
}

fn unit_twist(k: usize) -> se3<f64> {
    let mut a = [0.0; 6];
    a[k] = 1.0;
    se3::new(Vec3::new(a[0], a[1], a[2]), Vec3::new(a[3], a[4], a[5]))
}

fn unit_wrench(k: usize) -> dse3<f64> {
    let mut a = [0.0; 6];
    a[k] = 1.0;
    dse3::new(Vec3::new(a[0], a[1], a[2]), Vec3::new(a[3], a[4], a[5]))
}

/// The 6×6 matrix of a linear map of twists to twists.
fn twist_map(f: impl Fn(&se3<f64>) -> se3<f64>) -> M6 {
    M6::from_fn(|r, c| tw(&f(&unit_twist(c)))[r])
}

/// The 6×6 matrix of a linear map of twists to wrenches.
fn twist_to_wrench_map(f: impl Fn(&se3<f64>) -> dse3<f64>) -> M6 {
    M6::from_fn(|r, c| wr(&f(&unit_twist(c)))[r])
}

/// The 6×6 matrix of a linear map of wrenches to wrenches.
fn wrench_map(f: impl Fn(&dse3<f64>) -> dse3<f64>) -> M6 {
    M6::from_fn(|r, c| wr(&f(&unit_wrench(c)))[r])
}

/// Writes `Δq̇` of the linearly implicit velocity update (module docs) over `h` seconds for
/// configuration `q`, velocity `qd` and joint forces `tau` (gravity from the model). O(n), no
/// allocation. Errors on wrong lengths and on a singular joint block `D_i`.
///
/// `prescribed` holds coordinates whose change is given (hybrid dynamics: a kinematic root,
/// a driven wheel), as `(velocity coordinate, Δq̇_k)`; their joint equations are replaced by
/// `x_k = Δq̇_k` and the rest of the tree answers through the same operator. The impulse
/// (N·s or N·m·s) each prescribed coordinate takes to move so is written to `impulses`, in
/// the same order.
#[allow(clippy::too_many_arguments)]
pub(crate) fn implicit_velocity_update(
    model: &ArticulatedTree<f64>,
    ws: &mut ImplicitWorkspace,
    q: &[f64],
    qd: &[f64],
    tau: &[f64],
    h: f64,
    prescribed: &[(usize, f64)],
    impulses: &mut [f64],
    dqd: &mut [f64],
) -> Result<Implicitness, DynamicsError> {
    for level in [
        Implicitness::Full,
        Implicitness::Velocity,
        Implicitness::Explicit,
    ] {
        if level == Implicitness::Full && !prescribed.is_empty() {
            // Under prescribed motion the position Jacobian fails without a pivot falling
            // below the floor (a 100-link chain under a shaken root: a singular operator at
            // 1.7 s; `M + h D` holds it for 10 s — `docs/physics/compounds-trees-drives.md`, "Long chains").
            continue;
        }
        let (hv, hq) = match level {
            Implicitness::Full => (h, h),
            Implicitness::Velocity => (h, 0.0),
            Implicitness::Explicit => (0.0, 0.0),
        };
        let system = LinearSystem {
            h,
            hv,
            hq,
            prescribed,
        };
        if factor_and_solve(model, ws, q, qd, tau, &system, impulses, dqd)? {
            return Ok(level);
        }
    }
    // The explicit operator is M, whose pivots are at least the rigid ones: unreachable
    // unless the inertias are not positive.
    Err(DynamicsError::Singular { body: 0 })
}

/// Which Jacobians an update took implicitly.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Implicitness {
    /// `M + h D + h² K`.
    Full,
    /// `M + h D`: the position Jacobian would have brought a joint pivot below
    /// [`PIVOT_FLOOR`] of its rigid inertia (a mode unstable faster than `1/h`, such as links
    /// in compression).
    Velocity,
    /// `M` (semi-implicit Euler at the predicted configuration).
    Explicit,
}

/// A joint pivot `D_kk` of the implicit operator must keep at least this fraction of the
/// joint's own rigid inertia `S_kᵀ I S_k` (the articulated one is never below it); below,
/// the linearised step would amplify a physically unstable mode by `1/(1 − h²λ²)` instead
/// of following it, and the update drops the offending Jacobian.
pub(crate) const PIVOT_FLOOR: f64 = 0.5;

/// One level of the update: the operator `M + hv (D + hq K)` over a step of `h` seconds, with
/// the prescribed coordinates' changes.
struct LinearSystem<'a> {
    h: f64,
    hv: f64,
    hq: f64,
    prescribed: &'a [(usize, f64)],
}

impl LinearSystem<'_> {
    /// The given `Δq̇` of velocity coordinate `k`, if it is prescribed.
    fn prescribed(&self, k: usize) -> Option<f64> {
        self.prescribed
            .iter()
            .find_map(|&(c, x)| (c == k).then_some(x))
    }
}

/// One factorisation of `system`'s operator and the solve for the right-hand side
/// `h (τ − bias)`. `Ok(false)` when a free joint pivot falls below [`PIVOT_FLOOR`].
#[allow(clippy::too_many_arguments)]
fn factor_and_solve(
    model: &ArticulatedTree<f64>,
    ws: &mut ImplicitWorkspace,
    q: &[f64],
    qd: &[f64],
    tau: &[f64],
    system: &LinearSystem,
    impulses: &mut [f64],
    dqd: &mut [f64],
) -> Result<bool, DynamicsError> {
    let nv = model.nv();
    if ws.nbodies != model.len() || ws.ndofs != nv {
        return Err(DynamicsError::Workspace {
            expected: ws.nbodies,
            dofs: ws.ndofs,
        });
    }
    for (what, expected, got) in [
        ("q", model.nq(), q.len()),
        ("qd", nv, qd.len()),
        ("tau", nv, tau.len()),
        ("dqd", nv, dqd.len()),
        ("impulses", system.prescribed.len(), impulses.len()),
    ] {
        if expected != got {
            return Err(DynamicsError::Dimension {
                what,
                expected,
                got,
            });
        }
    }
    link_maps(model, ws, q, qd, system);
    if !eliminate_joints(model, ws, tau, system)? {
        return Ok(false);
    }
    back_substitute(model, ws, tau, system, impulses, dqd);
    Ok(true)
}

/// The forward pass: each link's kinematics, its Newton–Euler wrench at `q̈ = 0`, and the
/// linear maps of its motion change (`x`, `ŝ`, `P`) over the step of `system`.
fn link_maps(
    model: &ArticulatedTree<f64>,
    ws: &mut ImplicitWorkspace,
    q: &[f64],
    qd: &[f64],
    system: &LinearSystem,
) {
    let LinearSystem { hv, hq, .. } = *system;
    let bodies = model.bodies();
    let base_acc = se3::new(Vec3::zeros(), -model.gravity());
    for (i, body) in bodies.iter().enumerate() {
        let (qo, vo, d) = (body.q_offset, body.v_offset, body.nv());
        let qdi = &qd[vo..vo + d];
        let s = &mut ws.s_cols[vo..vo + d];
        let (xj, jbias) = body.joint.kinematics(&q[qo..qo + body.nq()], qdi, s);
        let f = body.placement * xj;
        let mut vj = se3::zeros();
        for k in 0..d {
            vj += s[k] * qdi[k];
        }
        // The parent's twist and acceleration seen in this frame.
        let (avp, aap) = match body.parent {
            Some(p) => (f.ad_inv(&ws.v[p]), f.ad_inv(&ws.a0[p])),
            None => (se3::zeros(), f.ad_inv(&base_acc)),
        };
        let v = avp + vj;
        let a0 = aap + v.ad(&vj) + jbias;
        let inertia = &body.inertia;
        let iv = inertia.mul_twist(&v);
        ws.f0[i] = wr(&(inertia.mul_twist(&a0) - v.dad(&iv)));
        let a = twist_map(|e| f.ad_inv(e));
        let ad_vj = twist_map(|e| vj.ad(e));
        let ad_v = twist_map(|e| v.ad(e));
        let mut x = M12::zeros();
        x.fixed_view_mut::<6, 6>(0, 0).copy_from(&a);
        x.fixed_view_mut::<6, 6>(6, 6).copy_from(&a);
        x.fixed_view_mut::<6, 6>(6, 0)
            .copy_from(&(-hv * (ad_vj * a)));
        let mut s6 = M6::zeros();
        for (k, col) in s.iter().enumerate() {
            s6.set_column(k, &tw(col));
        }
        // δq_i = h x_i turns the frame: Ad_{f⁻¹} picks up ad_{Ad V_λ} S and ad_{Ad a_λ} S.
        let sw = s6 + hq * (twist_map(|e| avp.ad(e)) * s6);
        let sa =
            s6 + hv * (ad_v * s6) - hv * (ad_vj * sw) + (hv * hq) * (twist_map(|e| aap.ad(e)) * s6);
        let mut shat = M12x6::zeros();
        shat.fixed_view_mut::<6, 6>(0, 0).copy_from(&sw);
        shat.fixed_view_mut::<6, 6>(6, 0).copy_from(&sa);
        let i6 = twist_to_wrench_map(|e| inertia.mul_twist(e));
        let g = twist_to_wrench_map(|e| -e.dad(&iv) - v.dad(&inertia.mul_twist(e)));
        let mut p = M6x12::zeros();
        p.fixed_view_mut::<6, 6>(0, 0).copy_from(&(hv * g));
        for k in 0..d {
            ws.rigid[i][k] = s6.column(k).dot(&(i6 * s6.column(k)));
        }
        p.fixed_view_mut::<6, 6>(0, 6).copy_from(&i6);
        ws.f[i] = f;
        ws.v[i] = v;
        ws.a0[i] = a0;
        ws.x[i] = x;
        ws.shat[i] = shat;
        ws.s[i] = s6;
        ws.p[i] = p;
        ws.pb[i] = V6::zeros();
    }
}

/// The backward pass: each joint eliminated, children first, its wrenches handed to its
/// parent. `Ok(false)` when a free joint pivot falls below [`PIVOT_FLOOR`].
fn eliminate_joints(
    model: &ArticulatedTree<f64>,
    ws: &mut ImplicitWorkspace,
    tau: &[f64],
    system: &LinearSystem,
) -> Result<bool, DynamicsError> {
    let LinearSystem { h, hv, hq, .. } = *system;
    let bodies = model.bodies();
    for i in (0..bodies.len()).rev() {
        let body = &bodies[i];
        let (vo, d) = (body.v_offset, body.nv());
        let (p, s6, x) = (ws.p[i], ws.s[i], ws.x[i]);
        let u = p * ws.shat[i];
        let mut dm = s6.transpose() * u;
        let mut coupling = s6.transpose() * p * x;
        let mut r = V6::zeros();
        let st_f0 = s6.transpose() * ws.f0[i];
        let st_pb = s6.transpose() * ws.pb[i];
        for k in 0..6 {
            if k >= d {
                dm[(k, k)] = 1.0;
            } else if let Some(given) = system.prescribed(vo + k) {
                // The joint equation gives way to `x_k = Δq̇_k`.
                dm.set_row(k, &nalgebra::RowVector6::zeros());
                dm[(k, k)] = 1.0;
                coupling.set_row(k, &nalgebra::RowSVector::<f64, 12>::zeros());
                r[k] = given;
            } else {
                r[k] = h * (tau[vo + k] - st_f0[k]) - st_pb[k];
                if dm[(k, k)].is_nan() || dm[(k, k)] < PIVOT_FLOOR * ws.rigid[i][k] {
                    return Ok(false);
                }
            }
        }
        let dinv = dm
            .try_inverse()
            .filter(|m| m.iter().all(|x| x.is_finite()))
            .ok_or(DynamicsError::Singular { body: i })?;
        let k = dinv * coupling;
        let kappa = dinv * r;
        ws.k[i] = k;
        ws.kappa[i] = kappa;
        if let Some(parent) = body.parent {
            let f = ws.f[i];
            let t = wrench_map(|e| f.dad_inv(e));
            // The transmitted wrench turns with the joint: −h² Ad*(ad*_{S x_i} F⁰_i).
            let f0 = dse3::new(
                Vec3::new(ws.f0[i][0], ws.f0[i][1], ws.f0[i][2]),
                Vec3::new(ws.f0[i][3], ws.f0[i][4], ws.f0[i][5]),
            );
            let mut l = M6::zeros();
            for c in 0..d {
                l.set_column(c, &wr(&ws.s_cols[vo + c].dad(&f0)));
            }
            let l = (hv * hq) * l;
            let pc = p * x - u * k + l * k;
            let pbc = ws.pb[i] + u * kappa - l * kappa;
            ws.p[parent] += t * pc;
            ws.pb[parent] += t * pbc;
            let f0c = t * ws.f0[i];
            ws.f0[parent] += f0c;
        }
    }
    Ok(true)
}

/// The forward substitution: each joint's velocity change into `dqd` and each link's motion
/// change, then what the prescribed coordinates took into `impulses`.
fn back_substitute(
    model: &ArticulatedTree<f64>,
    ws: &mut ImplicitWorkspace,
    tau: &[f64],
    system: &LinearSystem,
    impulses: &mut [f64],
    dqd: &mut [f64],
) {
    let h = system.h;
    let bodies = model.bodies();
    // Forward: joint velocity changes and link motion changes.
    for (i, body) in bodies.iter().enumerate() {
        let (vo, d) = (body.v_offset, body.nv());
        let zp = body.parent.map_or(V12::zeros(), |p| ws.z[p]);
        let xi = ws.kappa[i] - ws.k[i] * zp;
        dqd[vo..vo + d].copy_from_slice(&xi.as_slice()[..d]);
        ws.z[i] = ws.x[i] * zp + ws.shat[i] * xi;
    }
    // What the prescribed coordinates took: the joint equation's residual,
    // `S_kᵀ (P z + p) + h S_kᵀ F⁰ − h τ_k`, with the children's wrenches gathered above.
    for (slot, &(c, _)) in impulses.iter_mut().zip(system.prescribed) {
        *slot = 0.0;
        if let Some((i, body)) = bodies
            .iter()
            .enumerate()
            .find(|(_, b)| (b.v_offset..b.v_offset + b.nv()).contains(&c))
        {
            let col = ws.s[i].column(c - body.v_offset);
            let wrench = ws.p[i] * ws.z[i] + ws.pb[i] + h * ws.f0[i];
            *slot = col.dot(&wrench) - h * tau[c];
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dynamics::{aba, mass_matrix, rnea, Workspace};

    /// The mass-ratio tree of revolute, prismatic and ball joints at a generic state: the
    /// model, `q`, `q̇` and `τ`.
    #[allow(clippy::type_complexity)]
    fn fixture() -> (ArticulatedTree<f64>, Vec<f64>, Vec<f64>, Vec<f64>) {
        let model = crate::model::builders::mass_ratio().build::<f64>().unwrap();
        let (nq, nv) = (model.nq(), model.nv());
        let q = (0..nq).map(|k| 0.3 * ((k as f64) * 1.7).sin()).collect();
        let qd = (0..nv).map(|k| 2.0 * ((k as f64) * 0.9).cos()).collect();
        let tau = (0..nv).map(|k| 0.1 * k as f64).collect();
        (model, q, qd, tau)
    }

    /// `q ⊞ ε e_c`: additive coordinates, or `R exp(ε e)` for a ball joint.
    fn perturb(model: &ArticulatedTree<f64>, q: &[f64], c: usize, eps: f64) -> Vec<f64> {
        use crate::algebra::{exp_so3, log_so3};
        let mut out = q.to_vec();
        for b in model.bodies() {
            let (qo, vo, d) = (b.q_offset, b.v_offset, b.nv());
            if !(vo..vo + d).contains(&c) {
                continue;
            }
            if b.joint.describe().kind == "ball" {
                let mut e = Vec3::zeros();
                e[c - vo] = eps;
                let r = exp_so3(&Vec3::new(q[qo], q[qo + 1], q[qo + 2])) * exp_so3(&e);
                out[qo..qo + 3].copy_from_slice(log_so3(&r).as_slice());
            } else {
                out[qo + c - vo] += eps;
            }
        }
        out
    }

    /// `Δq̇` solves `(M + h ∂RNEA/∂q̇ + h² ∂RNEA/∂q) Δq̇ = h (τ − RNEA(q, q̇, 0))`, with `M` from
    /// CRBA and both Jacobians by central differences (the position one in the joints'
    /// charts), on a tree of revolute, prismatic and ball joints; and `Δq̇ / h → q̈` of ABA as
    /// `h → 0`.
    #[test]
    fn the_update_solves_the_linearised_backward_euler_system() {
        let (model, q, qd, tau) = fixture();
        let nv = model.nv();
        let mut ws = Workspace::new(&model);
        let mut iws = ImplicitWorkspace::new(&model);
        let h = 0.03;
        let mut dqd = vec![0.0; nv];
        let level =
            implicit_velocity_update(&model, &mut iws, &q, &qd, &tau, h, &[], &mut [], &mut dqd)
                .unwrap();
        assert_eq!(level, Implicitness::Full);
        let mut m = vec![0.0; nv * nv];
        mass_matrix(&model, &mut ws, &q, &mut m).unwrap();
        let zero = vec![0.0; nv];
        let mut bias = vec![0.0; nv];
        rnea(&model, &mut ws, &q, &qd, &zero, None, &mut bias).unwrap();
        let eps = 1e-6;
        let (mut plus, mut minus) = (vec![0.0; nv], vec![0.0; nv]);
        let mut lhs = vec![0.0; nv];
        for (r, l) in lhs.iter_mut().enumerate() {
            *l = (0..nv).map(|c| m[r * nv + c] * dqd[c]).sum();
        }
        for c in 0..nv {
            let mut qp = qd.clone();
            qp[c] += eps;
            rnea(&model, &mut ws, &q, &qp, &zero, None, &mut plus).unwrap();
            qp[c] -= 2.0 * eps;
            rnea(&model, &mut ws, &q, &qp, &zero, None, &mut minus).unwrap();
            for r in 0..nv {
                lhs[r] += h * (plus[r] - minus[r]) / (2.0 * eps) * dqd[c];
            }
            rnea(
                &model,
                &mut ws,
                &perturb(&model, &q, c, eps),
                &qd,
                &zero,
                None,
                &mut plus,
            )
            .unwrap();
            rnea(
                &model,
                &mut ws,
                &perturb(&model, &q, c, -eps),
                &qd,
                &zero,
                None,
                &mut minus,
            )
            .unwrap();
            for r in 0..nv {
                lhs[r] += h * h * (plus[r] - minus[r]) / (2.0 * eps) * dqd[c];
            }
        }
        let scale = bias.iter().chain(&tau).fold(1.0f64, |a, x| a.max(x.abs()));
        for r in 0..nv {
            let rhs = h * (tau[r] - bias[r]);
            assert!(
                (lhs[r] - rhs).abs() < 1e-7 * h * scale,
                "row {r}: {} vs {rhs}",
                lhs[r]
            );
        }
        // Small h: the explicit acceleration.
        let mut qdd = vec![0.0; nv];
        aba(&model, &mut ws, &q, &qd, &tau, None, &mut qdd).unwrap();
        let h = 1e-9;
        implicit_velocity_update(&model, &mut iws, &q, &qd, &tau, h, &[], &mut [], &mut dqd)
            .unwrap();
        let norm = qdd.iter().fold(1.0f64, |a, x| a.max(x.abs()));
        for (d, a) in dqd.iter().zip(&qdd) {
            assert!((d / h - a).abs() < 1e-6 * norm, "{} vs {a}", d / h);
        }
    }

    /// With coordinate `c` prescribed, the update moves it by exactly the given amount, every
    /// other row solves `(M + h ∂RNEA/∂q̇) Δq̇ = h (τ − RNEA(q, q̇, 0))` (the velocity level:
    /// prescribed motion leaves the position Jacobian out), and the impulse reported for `c`
    /// is what its own row lacks: `((M + h D) Δq̇)_c − h (τ_c − bias_c)`.
    #[test]
    fn a_prescribed_coordinate_moves_by_the_given_change_and_reports_its_impulse() {
        let (model, q, qd, tau) = fixture();
        let nv = model.nv();
        let mut ws = Workspace::new(&model);
        let mut iws = ImplicitWorkspace::new(&model);
        let h = 0.03;
        let c = 0;
        let given = 0.7;
        let mut dqd = vec![0.0; nv];
        let mut impulse = [0.0];
        let level = implicit_velocity_update(
            &model,
            &mut iws,
            &q,
            &qd,
            &tau,
            h,
            &[(c, given)],
            &mut impulse,
            &mut dqd,
        )
        .unwrap();
        assert_eq!(level, Implicitness::Velocity);
        assert!((dqd[c] - given).abs() < 1e-12, "{} vs {given}", dqd[c]);
        let mut m = vec![0.0; nv * nv];
        mass_matrix(&model, &mut ws, &q, &mut m).unwrap();
        let zero = vec![0.0; nv];
        let mut bias = vec![0.0; nv];
        rnea(&model, &mut ws, &q, &qd, &zero, None, &mut bias).unwrap();
        let mut lhs: Vec<f64> = (0..nv)
            .map(|r| (0..nv).map(|k| m[r * nv + k] * dqd[k]).sum())
            .collect();
        let eps = 1e-6;
        let (mut plus, mut minus) = (vec![0.0; nv], vec![0.0; nv]);
        for k in 0..nv {
            let mut qp = qd.clone();
            qp[k] += eps;
            rnea(&model, &mut ws, &q, &qp, &zero, None, &mut plus).unwrap();
            qp[k] -= 2.0 * eps;
            rnea(&model, &mut ws, &q, &qp, &zero, None, &mut minus).unwrap();
            for r in 0..nv {
                lhs[r] += h * (plus[r] - minus[r]) / (2.0 * eps) * dqd[k];
            }
        }
        let scale = bias.iter().chain(&tau).fold(1.0f64, |a, x| a.max(x.abs()));
        for r in 0..nv {
            let residual = lhs[r] - h * (tau[r] - bias[r]);
            if r == c {
                assert!(
                    (residual - impulse[0]).abs() < 1e-7 * h * scale,
                    "impulse {} vs residual {residual}",
                    impulse[0]
                );
            } else {
                assert!(
                    residual.abs() < 1e-7 * h * scale,
                    "row {r}: residual {residual}"
                );
            }
        }
    }
}

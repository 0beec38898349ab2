//! Forward dynamics: the recursive articulated-body algorithm of Appendix A.
//!
//! Appendix A for a chain with 1-DOF joints, generalised here to trees (a body's articulated
//! inertia and bias collect from all its children) and to `d`-DOF joints (the scalar
//! `Ω = ⟨S, Ĵ S⟩` becomes the `d×d` matrix `D = Sᵀ Ĵ S`):
//!
//! 1. forward, parents first: `f_i = M_i e^{S_i q_i}`, `V_i = Ad_{f_i⁻¹} V_{λ(i)} + S_i q̇_i`,
//!    `c_i = ad_{V_i} S_i q̇_i (+ Ṡ_i q̇_i)`, `Ĵ_i = J_i`, `b_i = −ad*_{V_i} J_i V_i − F^ext_i`;
//! 2. backward, children first: `U_i = Ĵ_i S_i`, `D_i = S_iᵀ U_i`,
//!    `u_i = τ_i − S_iᵀ(Ĵ_i c_i + b_i)`, and into the parent
//!    `Ĵ_λ += Ad*_{f_i⁻¹} (Ĵ_i − U_i D_i⁻¹ U_iᵀ) Ad_{f_i⁻¹}` (Eq. 6, `.xform_inv`),
//!    `b_λ += Ad*_{f_i⁻¹} (Ĵ_i c_i + b_i + U_i D_i⁻¹ u_i)`;
//! 3. forward: `q̈_i = D_i⁻¹ (u_i − U_iᵀ Ad_{f_i⁻¹} V̇_λ)` (Appendix A's
//!    `(τ_i − ⟨S_i, Ĵ_i (Ad V̇ + c_i) + b_i⟩)/Ω_i`, with `Ĵ_i c_i` already in `u_i`),
//!    `V̇_i = Ad_{f_i⁻¹} V̇_λ + c_i + S_i q̈_i`, with `V̇_0 = (0, −g)`.
//!
//! For `d = 1` these are literally the scalar formulas of Appendix A
//! (`U = Ĵ S`, `Ω = ⟨S, U⟩`, `Ψ = (Ĵ − U ⊗ U / Ω).Xform(f⁻¹)`).

use super::linalg::spd_inverse;
use super::{DynamicsError, Workspace};
use crate::algebra::{dse3, se3, AInertia, Vec3};
use crate::model::ArticulatedTree;
use crate::Real;

/// Forward dynamics: writes `q̈` for configuration `q`, velocity `q̇` and joint forces `τ`,
/// with optional external wrenches `fext[i]` on each body (body frame, `(N·m, N)`).
/// No allocation.
pub fn aba<T: Real>(
    model: &ArticulatedTree<T>,
    ws: &mut Workspace<T>,
    q: &[T],
    qd: &[T],
    tau: &[T],
    fext: Option<&[dse3<T>]>,
    qdd: &mut [T],
) -> Result<(), DynamicsError> {
    let nv = model.nv();
    ws.check(
        model,
        &[
            ("q", model.nq(), q.len()),
            ("qd", nv, qd.len()),
            ("tau", nv, tau.len()),
            ("qdd", nv, qdd.len()),
            ("fext", model.len(), fext.map_or(model.len(), |f| f.len())),
        ],
    )?;
    let bodies = model.bodies();
    let n = bodies.len();

    // 1. Forward recursion: kinematics, velocity products, initial Ĵ and b.
    for (i, body) in bodies.iter().enumerate() {
        let (qo, vo, d) = (body.q_offset, body.v_offset, body.nv());
        let qdi = &qd[vo..vo + d];
        let s = &mut ws.s[vo..vo + d];
        let (xj, bias) = body.joint.kinematics(&q[qo..qo + body.nq()], qdi, s);
        let f = body.placement * xj;
        let vj = match d {
            0 => se3::zeros(),
            1 => s[0] * qdi[0],
            _ => {
                let mut vj = s[0] * qdi[0];
                for k in 1..d {
                    vj += s[k] * qdi[k];
                }
                vj
            }
        };
        let v = match body.parent {
            Some(p) => f.ad_inv(&ws.v[p]) + vj,
            None => vj,
        };
        ws.c[i] = v.ad(&vj) + bias;
        let jv = body.inertia.mul_twist(&v);
        let mut b = -v.dad(&jv);
        if let Some(fe) = fext {
            b -= fe[i];
        }
        ws.f[i] = f;
        ws.v[i] = v;
        ws.b[i] = b;
        ws.jhat[i] = AInertia::from(body.inertia);
    }

    // 2. Backward recursion: articulated inertias and bias forces.
    for i in (0..n).rev() {
        let body = &bodies[i];
        let (vo, d) = (body.v_offset, body.nv());
        let jh = ws.jhat[i];
        let f = ws.f[i];
        let pa = jh.mul_twist(&ws.c[i]) + ws.b[i];
        let (ja, pa) = match d {
            0 => (jh, pa),
            1 => {
                let s = ws.s[vo];
                let u = jh.mul_twist(&s);
                let omega = s.dot(&u);
                if !positive(omega) {
                    return Err(DynamicsError::Singular { body: i });
                }
                let dinv = T::one() / omega;
                let uu = tau[vo] - s.dot(&pa);
                ws.u[vo] = u;
                ws.uu[vo] = uu;
                ws.dinv[ws.dinv_offset[i]] = dinv;
                if body.parent.is_none() {
                    continue;
                }
                (jh - u.kron_self(dinv), pa + u * (dinv * uu))
            }
            _ => {
                let mut dm = [T::zero(); 36];
                for k in 0..d {
                    let u = jh.mul_twist(&ws.s[vo + k]);
                    ws.u[vo + k] = u;
                    ws.uu[vo + k] = tau[vo + k] - ws.s[vo + k].dot(&pa);
                    for l in 0..=k {
                        let x = ws.s[vo + l].dot(&u);
                        dm[k * d + l] = x;
                        dm[l * d + k] = x;
                    }
                }
                let off = ws.dinv_offset[i];
                spd_inverse(&mut dm[..d * d], d, &mut ws.dinv[off..off + d * d])
                    .map_err(|_| DynamicsError::Singular { body: i })?;
                if body.parent.is_none() {
                    continue;
                }
                // W = D⁻¹ U; U D⁻¹ Uᵀ = Σ_k U_k W_kᵀ; U D⁻¹ u = Σ_k W_k u_k.
                let u = &ws.u[vo..vo + d];
                let dinv = &ws.dinv[off..off + d * d];
                let mut w = [dse3::zeros(); 6];
                let mut pa = pa;
                for k in 0..d {
                    let mut wk = u[0] * dinv[k * d];
                    for l in 1..d {
                        wk += u[l] * dinv[k * d + l];
                    }
                    w[k] = wk;
                    pa += wk * ws.uu[vo + k];
                }
                (jh.sub_products(u, &w[..d]), pa)
            }
        };
        if let Some(p) = body.parent {
            ws.jhat[p] += ja.xform_inv(&f);
            ws.b[p] += f.dad_inv(&pa);
        }
    }

    accelerations(model, ws, qdd);
    Ok(())
}

/// Pass 3 of [`aba`], forward: each joint's `q̈` into `qdd` and each body's `V̇` into the
/// workspace, from the articulated inertias and bias forces of pass 2.
fn accelerations<T: Real>(model: &ArticulatedTree<T>, ws: &mut Workspace<T>, qdd: &mut [T]) {
    let bodies = model.bodies();
    let g = model.gravity();
    let a0 = se3::new(Vec3::zeros(), -g);
    for (i, body) in bodies.iter().enumerate() {
        let (vo, d) = (body.v_offset, body.nv());
        let f = ws.f[i];
        // u_i already holds −⟨S_i, Ĵ_i c_i⟩, so c_i enters q̈ only through u_i.
        let ap = match body.parent {
            Some(p) => f.ad_inv(&ws.a[p]),
            None => f.ad_inv(&a0),
        };
        let apc = ap + ws.c[i];
        ws.a[i] = match d {
            0 => apc,
            1 => {
                let x = ws.dinv[ws.dinv_offset[i]] * (ws.uu[vo] - ws.u[vo].dot(&ap));
                qdd[vo] = x;
                apc + ws.s[vo] * x
            }
            _ => {
                let off = ws.dinv_offset[i];
                let mut r = [T::zero(); 6];
                for (k, rk) in r.iter_mut().enumerate().take(d) {
                    *rk = ws.uu[vo + k] - ws.u[vo + k].dot(&ap);
                }
                let mut a = apc;
                for k in 0..d {
                    let mut x = T::zero();
                    for (l, rl) in r.iter().enumerate().take(d) {
                        x += ws.dinv[off + k * d + l] * *rl;
                    }
                    qdd[vo + k] = x;
                    a += ws.s[vo + k] * x;
                }
                a
            }
        };
    }
}

/// `x > 0` (false for NaN).
#[inline(always)]
fn positive<T: Real>(x: T) -> bool {
    x > T::zero()
}

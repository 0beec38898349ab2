//! Inverse dynamics: recursive Newton–Euler with the body equation Eq. (3).

use super::{DynamicsError, Workspace};
use crate::algebra::{dse3, se3, Vec3};
use crate::model::ArticulatedTree;
use crate::Real;

/// Inverse dynamics: writes the joint forces `τ` that produce `q̈` at `(q, q̇)`, with optional
/// external wrenches `fext[i]` on each body (body frame). No allocation.
///
/// Forward: `V_i = Ad_{f_i⁻¹} V_λ + S_i q̇_i`,
/// `V̇_i = Ad_{f_i⁻¹} V̇_λ + S_i q̈_i + ad_{V_i} S_i q̇_i (+ Ṡ_i q̇_i)`,
/// `F_i = J_i V̇_i − ad*_{V_i} J_i V_i − F^ext_i` (Eq. 3); backward: `τ_i = S_iᵀ F_i`,
/// `F_λ += Ad*_{f_i⁻¹} F_i`.
#[cfg_attr(not(feature = "measure"), allow(dead_code))]
pub fn rnea<T: Real>(
    model: &ArticulatedTree<T>,
    ws: &mut Workspace<T>,
    q: &[T],
    qd: &[T],
    qdd: &[T],
    fext: Option<&[dse3<T>]>,
    tau: &mut [T],
) -> Result<(), DynamicsError> {
    let nv = model.nv();
    ws.check(
        model,
        &[
            ("q", model.nq(), q.len()),
            ("qd", nv, qd.len()),
            ("qdd", nv, qdd.len()),
            ("tau", nv, tau.len()),
            ("fext", model.len(), fext.map_or(model.len(), |f| f.len())),
        ],
    )?;
    let bodies = model.bodies();
    let a0 = se3::new(Vec3::zeros(), -model.gravity());
    for (i, body) in bodies.iter().enumerate() {
        let (qo, vo, d) = (body.q_offset, body.v_offset, body.nv());
        let qdi = &qd[vo..vo + d];
        let s = &mut ws.s[vo..vo + d];
        let (xj, bias) = body.joint.kinematics(&q[qo..qo + body.nq()], qdi, s);
        let f = body.placement * xj;
        let mut vj = se3::zeros();
        let mut aj = se3::zeros();
        for k in 0..d {
            vj += s[k] * qdi[k];
            aj += s[k] * qdd[vo + k];
        }
        let (vp, ap) = match body.parent {
            Some(p) => (f.ad_inv(&ws.v[p]), f.ad_inv(&ws.a[p])),
            None => (se3::zeros(), f.ad_inv(&a0)),
        };
        let v = vp + vj;
        let c = v.ad(&vj) + bias;
        let a = ap + aj + c;
        let mut force = body.inertia.mul_twist(&a) - v.dad(&body.inertia.mul_twist(&v));
        if let Some(fe) = fext {
            force -= fe[i];
        }
        ws.f[i] = f;
        ws.v[i] = v;
        ws.c[i] = c;
        ws.a[i] = a;
        ws.b[i] = force;
    }
    for i in (0..bodies.len()).rev() {
        let body = &bodies[i];
        let (vo, d) = (body.v_offset, body.nv());
        let force = ws.b[i];
        for k in 0..d {
            tau[vo + k] = ws.s[vo + k].dot(&force);
        }
        if let Some(p) = body.parent {
            ws.b[p] += ws.f[i].dad_inv(&force);
        }
    }
    Ok(())
}

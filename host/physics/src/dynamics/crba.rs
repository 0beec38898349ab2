//! The joint-space mass matrix by composite rigid bodies.

use super::{DynamicsError, Workspace};
use crate::algebra::SE3;
use crate::model::ArticulatedTree;
use crate::Real;

/// Writes the joint-space mass matrix `M(q)` (row-major `nv × nv`, symmetric) such that
/// `τ = M(q) q̈ + h(q, q̇)`. Uses the composite inertia `Jc_i = J_i + Σ_children Jc.Xform(f⁻¹)`
/// and `M_kl = ⟨S_k, Ad*… Jc S_l⟩` along the path to the root. No allocation.
pub fn mass_matrix<T: Real>(
    model: &ArticulatedTree<T>,
    ws: &mut Workspace<T>,
    q: &[T],
    m: &mut [T],
) -> Result<(), DynamicsError> {
    let nv = model.nv();
    ws.check(
        model,
        &[("q", model.nq(), q.len()), ("m", nv * nv, m.len())],
    )?;
    let bodies = model.bodies();
    let n = bodies.len();
    for (i, body) in bodies.iter().enumerate() {
        let (qo, vo, d) = (body.q_offset, body.v_offset, body.nv());
        let qi = &q[qo..qo + body.nq()];
        body.joint.motion_subspace(qi, &mut ws.s[vo..vo + d]);
        ws.f[i] = body.placement * body.joint.transform(qi);
        ws.ic[i] = body.inertia;
    }
    // Composite inertias, children first.
    for i in (0..n).rev() {
        if let Some(p) = bodies[i].parent {
            let child = ws.ic[i].xform_inv(&ws.f[i]);
            ws.ic[p] = ws.ic[p] + child;
        }
    }
    m.iter_mut().for_each(|x| *x = T::zero());
    for (i, body) in bodies.iter().enumerate() {
        let jc = ws.ic[i];
        for k in 0..body.nv() {
            let col = body.v_offset + k;
            let mut force = jc.mul_twist(&ws.s[col]);
            for l in 0..body.nv() {
                let row = body.v_offset + l;
                m[row * nv + col] = ws.s[row].dot(&force);
            }
            let mut j = i;
            while let Some(p) = bodies[j].parent {
                let fj: SE3<T> = ws.f[j];
                force = fj.dad_inv(&force);
                let bp = &bodies[p];
                for l in 0..bp.nv() {
                    let row = bp.v_offset + l;
                    let x = ws.s[row].dot(&force);
                    m[row * nv + col] = x;
                    m[col * nv + row] = x;
                }
                j = p;
            }
        }
    }
    Ok(())
}

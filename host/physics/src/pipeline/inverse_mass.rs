//! The joint-space inverse mass matrix `M(q)⁻¹` of a small tree, kept for the configuration
//! it was computed at.
//!
//! Every row that acts on a tree's generalised velocities (a contact row, a motor, a travel
//! limit) needs the tree's response `M⁻¹ Jᵀ` to an impulse. For a long chain that is one
//! articulated-body pass per row, O(n). For a tree of a few coordinates (a foosball rod: one
//! cylindrical joint, two coordinates; a ten-link chain, fifteen) the dense `nv × nv`
//! inverse costs less than one pass once it is known, so it is formed once per configuration (composite rigid bodies, then a
//! Cholesky inverse) and every response is a matrix–vector product. A match holds some 40
//! contact rows and 16 drive rows on its eight rods in every step; they shared 270
//! articulated-body passes per step before this and share 32 factorisations now.

use crate::dynamics::{mass_matrix, spd_inverse, DynamicsError, Workspace};
use crate::model::ArticulatedTree;

/// Trees with at most this many velocity coordinates keep a dense inverse: up to a ten-link
/// chain on a floating base (15), whose product of 225 multiply–adds costs less than one
/// articulated-body pass over its ten bodies, and whose inverse (`O(nv³)`, once per
/// configuration) its contact rows share. Longer chains keep the pass per row.
pub(crate) const DENSE_INVERSE_MASS_DOFS: usize = 16;

/// `M(q)⁻¹` (row-major `nv × nv`) and the `q` it belongs to.
#[derive(Clone, Debug, Default)]
pub(crate) struct InverseMassCache {
    q: Vec<f64>,
    minv: Vec<f64>,
    scratch: Vec<f64>,
    valid: bool,
}

impl InverseMassCache {
    /// Whether a tree of `nv` velocity coordinates uses the dense inverse.
    pub(crate) fn applies(nv: usize) -> bool {
        nv <= DENSE_INVERSE_MASS_DOFS
    }

    /// `out = M(q)⁻¹ tau`, forming the inverse first if `q` is not the configuration it was
    /// formed at.
    pub(crate) fn apply(
        &mut self,
        tree: &ArticulatedTree<f64>,
        ws: &mut Workspace<f64>,
        q: &[f64],
        tau: &[f64],
        out: &mut [f64],
    ) -> Result<(), DynamicsError> {
        let nv = tau.len();
        if !(self.valid && self.q == q) {
            self.form(tree, ws, q)?;
        }
        for (i, o) in out.iter_mut().enumerate().take(nv) {
            let row = &self.minv[i * nv..(i + 1) * nv];
            *o = row.iter().zip(tau).map(|(m, t)| m * t).sum();
        }
        Ok(())
    }

    fn form(
        &mut self,
        tree: &ArticulatedTree<f64>,
        ws: &mut Workspace<f64>,
        q: &[f64],
    ) -> Result<(), DynamicsError> {
        let nv = tree.nv();
        self.valid = false;
        self.scratch.resize(nv * nv, 0.0);
        self.minv.resize(nv * nv, 0.0);
        mass_matrix(tree, ws, q, &mut self.scratch)?;
        spd_inverse(&mut self.scratch, nv, &mut self.minv)
            .map_err(|e| DynamicsError::Singular { body: e.0 })?;
        self.q.clear();
        self.q.extend_from_slice(q);
        self.valid = true;
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::algebra::{Inertia, Sym3, Vec3, SE3};
    use crate::dynamics::aba;
    use crate::model::joints::{Cylindrical, Free, Revolute};

    /// `M⁻¹ τ` by ABA at zero velocity and zero gravity: the reference.
    fn by_aba(tree: &mut ArticulatedTree<f64>, q: &[f64], tau: &[f64]) -> Vec<f64> {
        let g = tree.gravity();
        tree.set_gravity(Vec3::zeros());
        let mut ws = Workspace::new(tree);
        let mut out = vec![0.0; tau.len()];
        aba(tree, &mut ws, q, &vec![0.0; tau.len()], tau, None, &mut out).unwrap();
        tree.set_gravity(g);
        out
    }

    /// A body whose centre of mass is off the joint axis, with a full inertia tensor.
    fn off_axis_body() -> Inertia<f64> {
        Inertia::from_com(
            0.6,
            Vec3::new(0.01, -0.03, 0.07),
            Sym3::new(2e-3, 3e-3, 1e-3, 1e-4, -2e-4, 3e-4),
        )
    }

    /// Two links hinged about `z`, the elbow 0.3 m out along the upper arm.
    fn two_link_arm() -> ArticulatedTree<f64> {
        let mut arm = ArticulatedTree::new(Vec3::zeros());
        let z = Vec3::new(0.0, 0.0, 1.0);
        let upper = arm
            .add_body(
                "upper",
                None,
                SE3::identity(),
                Revolute::new(z),
                off_axis_body(),
            )
            .unwrap();
        let elbow = SE3::from_translation(Vec3::new(0.3, 0.0, 0.0));
        arm.add_body(
            "fore",
            Some(upper),
            elbow,
            Revolute::new(z),
            off_axis_body(),
        )
        .unwrap();
        arm
    }

    fn assert_same(tree: &mut ArticulatedTree<f64>, q: &[f64], cache: &mut InverseMassCache) {
        let nv = tree.nv();
        let mut ws = Workspace::new(tree);
        for k in 0..nv {
            let tau: Vec<f64> = (0..nv).map(|i| ((i + 2 * k) as f64 * 0.7).sin()).collect();
            let mut dense = vec![0.0; nv];
            cache.apply(tree, &mut ws, q, &tau, &mut dense).unwrap();
            let reference = by_aba(tree, q, &tau);
            let scale = reference.iter().fold(0.0f64, |m, x| m.max(x.abs()));
            for (d, r) in dense.iter().zip(&reference) {
                // Two exact factorisations of one matrix: they agree to rounding.
                assert!(
                    (d - r).abs() <= 1e-12 * scale,
                    "{dense:?} against {reference:?}"
                );
            }
        }
    }

    #[test]
    fn a_rod_on_a_cylindrical_joint_answers_as_the_articulated_body_pass() {
        let mut tree = ArticulatedTree::new(Vec3::new(0.0, 0.0, -9.81));
        tree.add_body(
            "rod",
            None,
            SE3::identity(),
            Cylindrical::new(Vec3::new(0.0, 1.0, 0.0)),
            off_axis_body(),
        )
        .unwrap();
        let mut cache = InverseMassCache::default();
        assert!(InverseMassCache::applies(tree.nv()));
        assert_same(&mut tree, &[0.02, 0.4], &mut cache);
    }

    #[test]
    fn a_free_body_and_a_two_link_arm_answer_as_the_articulated_body_pass() {
        let mut free = ArticulatedTree::new(Vec3::zeros());
        free.add_body("box", None, SE3::identity(), Free, off_axis_body())
            .unwrap();
        let q_free = [0.1, -0.2, 0.3, 0.5, 0.0, -0.4, 0.2];
        let nq = free.nq();
        assert_same(&mut free, &q_free[..nq], &mut InverseMassCache::default());

        let mut arm = two_link_arm();
        assert_same(&mut arm, &[0.3, -1.1], &mut InverseMassCache::default());
    }

    /// A ten-link chain on a floating base, hinged about alternating axes: fifteen
    /// coordinates, the largest kind of tree that keeps a dense inverse.
    #[test]
    fn a_ten_link_chain_on_a_floating_base_answers_as_the_articulated_body_pass() {
        let mut chain = ArticulatedTree::new(Vec3::zeros());
        let mut parent = chain
            .add_body("link0", None, SE3::identity(), Free, off_axis_body())
            .unwrap();
        let step = SE3::from_translation(Vec3::new(0.1, 0.0, 0.0));
        for k in 1..10 {
            let axis = if k % 2 == 1 {
                Vec3::new(0.0, 1.0, 0.0)
            } else {
                Vec3::new(0.0, 0.0, 1.0)
            };
            parent = chain
                .add_body(
                    format!("link{k}"),
                    Some(parent),
                    step,
                    Revolute::new(axis),
                    off_axis_body(),
                )
                .unwrap();
        }
        assert_eq!(chain.nv(), 15);
        assert!(InverseMassCache::applies(chain.nv()));
        let q: Vec<f64> = (0..chain.nq()).map(|i| (i as f64 * 0.37).sin()).collect();
        assert_same(&mut chain, &q, &mut InverseMassCache::default());
    }

    #[test]
    fn a_new_configuration_forms_the_inverse_again() {
        let mut arm = two_link_arm();
        let mut cache = InverseMassCache::default();
        // The arm's mass matrix depends on the elbow angle: a stale inverse would differ.
        assert_same(&mut arm, &[0.0, 0.0], &mut cache);
        assert_same(&mut arm, &[0.0, 1.5], &mut cache);
    }
}

//! Articulated trees stepped with part 1's ABA: `q̈ = FD(q, q̇, τ)`, then semi-implicit Euler
//! (`q̇ += h q̈`, then `q` from `q̇` on each joint's configuration space: additive for
//! revolute, prismatic, cylindrical and universal joints; `R ← R·exp(h ω)` for ball joints;
//! `T ← T·Exp(h V)` for free joints).

use crate::algebra::{exp_so3, log_so3, se3, Vec3, SE3};
use crate::dynamics::{aba, DynamicsError, Workspace};
use crate::model::ArticulatedTree;

/// One articulated tree with its state.
pub struct ArticulatedSystem {
    /// The model.
    pub tree: ArticulatedTree<f64>,
    ws: Workspace<f64>,
    /// Configuration.
    pub q: Vec<f64>,
    /// Velocity.
    pub qd: Vec<f64>,
    /// Joint forces (held constant).
    pub tau: Vec<f64>,
    qdd: Vec<f64>,
    joints: Vec<(String, usize, usize)>,
}

impl ArticulatedSystem {
    /// A system at `q`, `qd` (lengths checked by the scene loader).
    pub fn new(tree: ArticulatedTree<f64>, q: Vec<f64>, qd: Vec<f64>) -> Self {
        let ws = Workspace::new(&tree);
        let nv = tree.nv();
        let joints = tree
            .bodies()
            .iter()
            .map(|b| (b.joint.describe().kind, b.q_offset, b.v_offset))
            .collect();
        Self {
            tree,
            ws,
            q,
            qd,
            tau: vec![0.0; nv],
            qdd: vec![0.0; nv],
            joints,
        }
    }

    /// One step of `h` seconds.
    pub fn step(&mut self, h: f64) -> Result<(), DynamicsError> {
        aba(
            &self.tree,
            &mut self.ws,
            &self.q,
            &self.qd,
            &self.tau,
            None,
            &mut self.qdd,
        )?;
        for (v, a) in self.qd.iter_mut().zip(&self.qdd) {
            *v += h * a;
        }
        for (kind, qo, vo) in &self.joints {
            let (qo, vo) = (*qo, *vo);
            let v3 = |s: &[f64], o: usize| Vec3::new(s[o], s[o + 1], s[o + 2]);
            match kind.as_str() {
                "ball" => {
                    let r = exp_so3(&v3(&self.q, qo)) * exp_so3(&(v3(&self.qd, vo) * h));
                    self.q[qo..qo + 3].copy_from_slice(log_so3(&r).as_slice());
                }
                "free" => {
                    let t = SE3::new(exp_so3(&v3(&self.q, qo)), v3(&self.q, qo + 3))
                        * SE3::exp(&se3::new(v3(&self.qd, vo) * h, v3(&self.qd, vo + 3) * h));
                    self.q[qo..qo + 3].copy_from_slice(log_so3(&t.r).as_slice());
                    self.q[qo + 3..qo + 6].copy_from_slice(t.p.as_slice());
                }
                "fixed" => {}
                _ => {
                    let n = self
                        .tree
                        .bodies()
                        .iter()
                        .find(|b| b.q_offset == qo)
                        .map_or(0, |b| b.nq());
                    for k in 0..n {
                        self.q[qo + k] += h * self.qd[vo + k];
                    }
                }
            }
        }
        Ok(())
    }

    /// Kinetic plus potential energy (J), gravity from the model.
    pub fn energy(&self) -> f64 {
        let poses = self.tree.body_poses(&self.q);
        let mut e = 0.0;
        let g = self.tree.gravity();
        // Potential: −m g·c for each body's centre of mass.
        for (b, t) in self.tree.bodies().iter().zip(&poses) {
            let c = t.transform_point(&b.inertia.com());
            e -= b.inertia.m * g.dot(&c);
        }
        // Kinetic: ½ q̇ᵀ M q̇ via body twists is not exposed; use the mass matrix.
        let nv = self.tree.nv();
        let mut m = vec![0.0; nv * nv];
        let mut ws = Workspace::new(&self.tree);
        if crate::dynamics::mass_matrix(&self.tree, &mut ws, &self.q, &mut m).is_ok() {
            for i in 0..nv {
                for j in 0..nv {
                    e += 0.5 * self.qd[i] * m[i * nv + j] * self.qd[j];
                }
            }
        }
        e
    }
}

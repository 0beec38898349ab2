//! Proxies of tree links in the body set: how links with shapes take part in collision
//! detection (see `tree_contacts`).

use super::{Proxy, World};
use crate::algebra::SE3;
use crate::dynamics::BodyKind;
use crate::geometry::{Compound, Part, V3};
use crate::pipeline::articulated::ArticulatedSystem;
use crate::pipeline::{Effect, Effects};

/// Whether tree `a` steps inside the constraint solve (semi-implicit Euler, substep by
/// substep): it has shapes and the `contacts` effect, or motors or limits (or prescribed
/// motion that its integrator cannot take as given). Other trees step on their own with the
/// selected integrator, prescribed coordinates included.
pub(super) fn in_solve(effects: Effects, a: &ArticulatedSystem) -> bool {
    (a.has_drives() && !a.steps_prescribed_alone())
        || (a.has_shapes() && effects.has(Effect::Contacts))
}

impl World {
    /// Whether any tree is stepped inside the constraint solve this step.
    pub(super) fn coupled_trees(&self) -> bool {
        self.effects.has(Effect::Articulated)
            && self.articulated.iter().any(|a| in_solve(self.effects, a))
    }

    /// Adds a kinematic proxy body for every link of tree `t` that carries shapes, named
    /// after the link; links of one tree do not collide with each other. Shapes on a link
    /// index the tree does not have are ignored.
    pub(super) fn add_link_proxies(&mut self, t: usize) {
        let sys = &self.articulated[t];
        if !sys.has_shapes() {
            return;
        }
        let poses = sys.link_poses();
        let mut links: Vec<usize> = sys
            .link_shapes
            .iter()
            .map(|s| s.link)
            .filter(|&l| l < poses.len())
            .collect();
        links.sort_unstable();
        links.dedup();
        let first = self.bodies.len();
        for link in links {
            let shapes: Vec<_> = sys.link_shapes.iter().filter(|s| s.link == link).collect();
            let material = shapes[0].material;
            let shape = if shapes.len() == 1 && shapes[0].pose == SE3::identity() {
                shapes[0].shape.clone()
            } else {
                let parts = shapes
                    .iter()
                    .map(|s| Part {
                        shape: s.shape.clone(),
                        rot: s.pose.r,
                        pos: s.pose.p,
                        material: s.material,
                    })
                    .collect();
                match Compound::from_parts(parts) {
                    Ok(c) => c.into_shape(),
                    Err(_) => continue,
                }
            };
            let name = sys.tree.bodies()[link].name.clone();
            let i = self.bodies.push(
                name,
                BodyKind::Kinematic,
                shape,
                material,
                0.0,
                poses[link].p,
                poses[link].r,
                V3::zeros(),
                V3::zeros(),
            );
            self.body_slots.insert::<crate::pipeline::BodyHandle>();
            self.bodies.awake[i] = true;
            self.bodies.responds[i] = true;
            self.proxies.resize(i + 1, None);
            self.proxies[i] = Some(Proxy { tree: t, link });
        }
        let last = self.bodies.len();
        for a in first..last {
            for b in a + 1..last {
                self.excluded_pairs.push(((a as u64) << 32) | b as u64);
            }
        }
        self.excluded_pairs.sort_unstable();
        self.sync_link_proxies();
    }

    /// Poses every proxy from its tree's forward kinematics and gives it the link's velocity
    /// (world angular velocity, world velocity of the link frame's origin); keeps the link
    /// poses for the contact rows of the step.
    pub(super) fn sync_link_proxies(&mut self) {
        if self.proxies.is_empty() {
            return;
        }
        for (t, sys) in self.articulated.iter().enumerate() {
            if sys.has_shapes() {
                let poses = sys.link_poses();
                let vel = sys.link_velocities(&poses);
                for (i, p) in self.proxies.iter().enumerate() {
                    if let Some(p) = p.filter(|p| p.tree == t) {
                        self.bodies.pos[i] = poses[p.link].p;
                        self.bodies.rot[i] = poses[p.link].r;
                        self.bodies.omega[i] = vel[p.link].0;
                        self.bodies.vel[i] = vel[p.link].1;
                    }
                }
                self.link_poses[t] = poses;
            }
        }
    }
}

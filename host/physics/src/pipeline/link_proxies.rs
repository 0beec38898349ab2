//! Proxies of tree links in the body set: how links with shapes take part in collision
//! detection (see `tree_contacts`).

use super::tree_contacts::Proxy;
use super::world::World;
use crate::algebra::SE3;
use crate::dynamics::{BodyKind, DynamicsError};
use crate::geometry::{Compound, Part, V3};
use crate::pipeline::ArticulatedSystem;
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
        self.sync_link_proxies(false);
    }

    /// Each shaped tree's velocity after its motors' first substep of `h`, for the proxies of
    /// the step ([`ArticulatedSystem::motor_predicted_velocity`]); empty for trees without
    /// motors.
    pub(super) fn predict_motor_velocities(&mut self, h: f64) -> Result<(), DynamicsError> {
        self.predicted_qd
            .resize_with(self.articulated.len(), Vec::new);
        for (sys, out) in self.articulated.iter_mut().zip(&mut self.predicted_qd) {
            out.clear();
            let motors = sys
                .drives
                .iter()
                .any(|d| matches!(d.kind, crate::pipeline::DriveKind::Motor(_)));
            if sys.has_shapes() && motors {
                sys.motor_predicted_velocity(h, out)?;
            }
        }
        Ok(())
    }

    /// Poses every proxy from its tree's forward kinematics and gives it the link's velocity
    /// (world angular velocity, world velocity of the link frame's origin); keeps the link
    /// poses for the contact rows of the step.
    ///
    /// At the start of a step (`predicted`) a tree with motors gives its proxies the velocity
    /// its motors reach within the first substep: a servo gets to its target speed within a
    /// substep or two, so that velocity, not the one the step starts with, is how far the link
    /// moves over the step, and what the step's boxes, contact margins and continuous
    /// collision sweep it with (a rod that kicks from rest turns 0.03 rad in its first
    /// millisecond). Otherwise the proxies take the tree's velocity.
    pub(super) fn sync_link_proxies(&mut self, predicted: bool) {
        if self.proxies.is_empty() {
            return;
        }
        // The link poses go straight into the step's kept ones; one velocity buffer serves
        // every tree.
        let mut vel = Vec::new();
        for (t, sys) in self.articulated.iter().enumerate() {
            if sys.has_shapes() {
                let poses = &mut self.link_poses[t];
                sys.model().body_poses_into(sys.q(), poses);
                let qd = match self.predicted_qd.get(t) {
                    Some(qd) if predicted && !qd.is_empty() => qd,
                    _ => sys.qd(),
                };
                sys.link_velocities_into(poses, qd, &mut vel);
                for (i, p) in self.proxies.iter().enumerate() {
                    if let Some(p) = p.filter(|p| p.tree == t) {
                        self.bodies.pos[i] = poses[p.link].p;
                        self.bodies.rot[i] = poses[p.link].r;
                        self.bodies.omega[i] = vel[p.link].0;
                        self.bodies.vel[i] = vel[p.link].1;
                    }
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use crate::algebra::{Inertia, Sym3, Vec3, SE3};
    use crate::geometry::{Material, Shape, V3};
    use crate::model::{ArticulatedTree, Revolute};
    use crate::pipeline::ArticulatedSystem;
    use crate::pipeline::{BodyBuilder, Effect, Effects, World};

    /// A one-link tree hinged about the horizontal `axis` at `pivot`, carrying `shape` at
    /// `offset` from the hinge (link frame), turned `q` rad.
    fn hinged(
        pivot: Vec3<f64>,
        axis: Vec3<f64>,
        shape: Shape,
        offset: Vec3<f64>,
        q: f64,
    ) -> ArticulatedSystem {
        let mut tree = ArticulatedTree::new(Vec3::new(0.0, 0.0, -9.81));
        tree.add_body(
            "link",
            None,
            SE3::from_translation(pivot),
            Revolute::new(axis),
            Inertia::from_com(1.0, offset, Sym3::diagonal(&Vec3::repeat(1e-3))),
        )
        .unwrap();
        ArticulatedSystem::new(tree, vec![q], vec![0.0]).with_link_shape(
            0,
            shape,
            SE3::from_translation(offset),
            Material::default(),
        )
    }

    /// A bar turning about its own axis 1 mm over the ground moves only along the ground where
    /// it is nearest: its contact has no rows. A pendulum's ball swung 0.3 rad out over the
    /// ground moves partly along the normal there: its contact is solved.
    #[test]
    fn a_contact_that_its_links_can_move_only_along_is_not_solved() {
        let effects = Effects::of(&[Effect::Gravity, Effect::Contacts, Effect::Articulated]);
        let mut w = World::builder(effects)
            .dt(1e-3)
            .gravity(V3::new(0.0, 0.0, -9.81))
            .build();
        w.insert_body(BodyBuilder::fixed(Shape::HalfSpace { normal: V3::z() }));
        let (r, skew) = (0.01_f64, 0.3_f64);
        let axis = Vec3::new(skew.cos(), skew.sin(), 0.0);
        // The capsule's own axis is z: turned onto the hinge axis.
        let bar = Shape::Capsule {
            radius: r,
            half_height: 0.2,
        };
        let mut sys = hinged(Vec3::new(0.0, 0.0, r + 1e-3), axis, bar, Vec3::zeros(), 0.0);
        sys.link_shapes[0].pose = SE3::from_rotation(crate::algebra::exp_so3(
            &(Vec3::new(-skew.sin(), skew.cos(), 0.0) * std::f64::consts::FRAC_PI_2),
        ));
        w.insert_tree(sys);
        let (arm, ball) = (0.3, 0.02);
        let swung = 0.3_f64;
        let pivot_height = arm * swung.cos() + ball + 1e-3;
        let pendulum = hinged(
            Vec3::new(2.0, 0.0, pivot_height),
            Vec3::new(0.0, 1.0, 0.0),
            Shape::Sphere { radius: ball },
            Vec3::new(0.0, 0.0, -arm),
            swung,
        );
        w.insert_tree(pendulum);
        w.step().unwrap();
        assert_eq!(
            w.manifolds().len(),
            2,
            "both links are within the contact margin"
        );
        assert_eq!(
            w.tree_contacts.inert.len(),
            1,
            "the bar's contact has no rows"
        );
        assert_eq!(
            w.tree_contacts.contacts.len(),
            1,
            "the pendulum's contact is solved"
        );
    }
}

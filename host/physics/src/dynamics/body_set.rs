//! The rigid bodies of a world, stored as parallel arrays (structure of arrays) so that each
//! stage streams only the fields it needs.
//!
//! Frames and units: `pos` is the centre of mass in world coordinates (m) and `rot` the world
//! from body rotation (columns are the body axes): together the pose `T = (rot, pos)` of the
//! body frame, whose origin is the centre of mass and whose axes are the principal axes.
//! `vel` (m/s) and `omega` (rad/s) are the linear velocity of the centre of mass and the
//! angular velocity, both in world coordinates; the body twist of part 1 is
//! `V = (rotᵀ omega, rotᵀ vel)`.

use crate::geometry::{Aabb, CollisionBodies, Material, Shape, M3, V3};

/// How a body moves.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BodyKind {
    /// Moved by forces and contacts.
    Dynamic,
    /// Moved by its prescribed velocity only (infinite mass); pushes dynamic bodies.
    Kinematic,
    /// Never moves.
    Fixed,
}

/// Every body of a world, structure of arrays (index = body id).
#[derive(Clone, Debug, Default)]
pub struct BodySet {
    /// Names (may be empty).
    pub(crate) name: Vec<String>,
    /// Kind.
    pub(crate) kind: Vec<BodyKind>,
    /// Shape, body frame (a compound carries its parts' poses and materials).
    pub(crate) shape: Vec<Shape>,
    /// Material of a body with a primitive shape (a compound's parts have their own).
    pub(crate) material: Vec<Material>,
    /// Centre of mass, world (m).
    pub(crate) pos: Vec<V3>,
    /// World from body rotation.
    pub(crate) rot: Vec<M3>,
    /// Linear velocity of the centre of mass, world (m/s).
    pub(crate) vel: Vec<V3>,
    /// Angular velocity, world (rad/s).
    pub(crate) omega: Vec<V3>,
    /// Inverse mass (1/kg), 0 for kinematic and fixed bodies.
    pub(crate) inv_mass: Vec<f64>,
    /// Principal inertia, body axes (kg·m²).
    pub(crate) inertia: Vec<V3>,
    /// Inverse principal inertia (0 for kinematic and fixed bodies).
    pub(crate) inv_inertia: Vec<V3>,
    /// Inverse inertia in world axes, `R diag(inv_inertia) Rᵀ`, refreshed each step.
    pub(crate) inv_inertia_world: Vec<M3>,
    /// Whether the body is simulated this step (dynamic and not sleeping).
    pub(crate) awake: Vec<bool>,
    /// Whether contacts move the body: dynamic bodies, and the proxies of tree links (whose
    /// contacts act on their tree).
    pub(crate) responds: Vec<bool>,
    /// Time the body has been slow enough to sleep (s).
    pub(crate) sleep_time: Vec<f64>,
    /// World bounding box, grown by the contact margin (m).
    pub(crate) aabb: Vec<Aabb>,
    /// Position change during the current step (m, world), for the solver's separation update.
    pub(crate) dp: Vec<V3>,
    /// Rotation change during the current step, linearised (rad, world).
    pub(crate) dtheta: Vec<V3>,
    /// Applied external force (N, world), kept until changed.
    pub(crate) force: Vec<V3>,
    /// Applied external torque (N·m, world), kept until changed.
    pub(crate) torque: Vec<V3>,
}

impl BodySet {
    /// Number of bodies.
    pub(crate) fn len(&self) -> usize {
        self.pos.len()
    }

    /// Adds a body with mass `mass` (ignored unless dynamic); returns its index.
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn push(
        &mut self,
        name: String,
        kind: BodyKind,
        shape: Shape,
        material: Material,
        mass: f64,
        pos: V3,
        rot: M3,
        vel: V3,
        omega: V3,
    ) -> usize {
        let dynamic = kind == BodyKind::Dynamic;
        let inertia = if dynamic {
            shape.principal_inertia(mass)
        } else {
            V3::zeros()
        };
        let inv = |x: f64| if x > 0.0 { 1.0 / x } else { 0.0 };
        self.aabb.push(shape.aabb(&rot, &pos));
        self.name.push(name);
        self.kind.push(kind);
        self.shape.push(shape);
        self.material.push(material);
        self.pos.push(pos);
        self.rot.push(rot);
        self.vel.push(vel);
        self.omega.push(omega);
        self.inv_mass.push(if dynamic { inv(mass) } else { 0.0 });
        self.inertia.push(inertia);
        self.inv_inertia
            .push(V3::new(inv(inertia.x), inv(inertia.y), inv(inertia.z)));
        self.inv_inertia_world.push(M3::zeros());
        self.awake.push(dynamic);
        self.responds.push(dynamic);
        self.sleep_time.push(0.0);
        self.dp.push(V3::zeros());
        self.dtheta.push(V3::zeros());
        self.force.push(V3::zeros());
        self.torque.push(V3::zeros());
        self.len() - 1
    }

    /// Removes body `i` the way `Vec::swap_remove` does: the last body moves into `i`.
    pub(crate) fn swap_remove(&mut self, i: usize) {
        self.name.swap_remove(i);
        self.kind.swap_remove(i);
        self.shape.swap_remove(i);
        self.material.swap_remove(i);
        self.pos.swap_remove(i);
        self.rot.swap_remove(i);
        self.vel.swap_remove(i);
        self.omega.swap_remove(i);
        self.inv_mass.swap_remove(i);
        self.inertia.swap_remove(i);
        self.inv_inertia.swap_remove(i);
        self.inv_inertia_world.swap_remove(i);
        self.awake.swap_remove(i);
        self.responds.swap_remove(i);
        self.sleep_time.swap_remove(i);
        self.aabb.swap_remove(i);
        self.dp.swap_remove(i);
        self.dtheta.swap_remove(i);
        self.force.swap_remove(i);
        self.torque.swap_remove(i);
    }

    /// What collision detection reads of the bodies.
    pub(crate) fn collision_view(&self) -> CollisionBodies<'_> {
        CollisionBodies {
            shape: &self.shape,
            rot: &self.rot,
            pos: &self.pos,
            aabb: &self.aabb,
            awake: &self.awake,
            responds: &self.responds,
            travel: &[],
        }
    }

    /// The primitive shape of part `part` of body `i` (the body's shape unless a compound).
    pub(crate) fn part_shape(&self, i: usize, part: u16) -> &Shape {
        match &self.shape[i] {
            Shape::Compound(c) => c
                .parts()
                .get(part as usize)
                .map_or(&self.shape[i], |p| &p.shape),
            s => s,
        }
    }

    /// The material of part `part` of body `i` (the body's material unless a compound).
    pub(crate) fn part_material(&self, i: usize, part: u16) -> Material {
        match &self.shape[i] {
            Shape::Compound(c) => c
                .parts()
                .get(part as usize)
                .map_or(self.material[i], |p| p.material),
            _ => self.material[i],
        }
    }

    /// Mass (kg), `∞` for kinematic and fixed bodies.
    pub(crate) fn mass(&self, i: usize) -> f64 {
        if self.inv_mass[i] > 0.0 {
            1.0 / self.inv_mass[i]
        } else {
            f64::INFINITY
        }
    }

    /// Refreshes `inv_inertia_world` of the awake bodies.
    pub(crate) fn update_world_inertia(&mut self) {
        for i in 0..self.len() {
            if self.awake[i] {
                let r = &self.rot[i];
                let d = self.inv_inertia[i];
                let rd =
                    M3::from_columns(&[r.column(0) * d.x, r.column(1) * d.y, r.column(2) * d.z]);
                self.inv_inertia_world[i] = rd * r.transpose();
            }
        }
    }

    /// Whether body `i` stands for a link of an articulated tree: posed by the tree's
    /// kinematics at the start and end of each step, never integrated on its own.
    pub(crate) fn is_link_proxy(&self, i: usize) -> bool {
        self.kind[i] == BodyKind::Kinematic && self.responds[i]
    }

    /// How fast any point of body `i` moves (m/s): its velocity plus its angular velocity
    /// times its shape's reach from the spin axis through its centre.
    pub(crate) fn sweep_speed(&self, i: usize) -> f64 {
        let w = self.omega[i];
        let wn = w.norm();
        let turn = if wn > 0.0 {
            wn * self.shape[i].reach_about(&(self.rot[i].tr_mul(&w) / wn))
        } else {
            0.0
        };
        self.vel[i].norm() + turn
    }

    /// Kinetic energy `½ m v² + ½ ωᵀ I ω` of the dynamic bodies (J).
    pub(crate) fn kinetic_energy(&self) -> f64 {
        let mut e = 0.0;
        for i in 0..self.len() {
            if self.kind[i] == BodyKind::Dynamic {
                let wl = self.rot[i].tr_mul(&self.omega[i]);
                e += 0.5 * self.mass(i) * self.vel[i].norm_squared()
                    + 0.5 * wl.dot(&self.inertia[i].component_mul(&wl));
            }
        }
        e
    }

    /// Linear momentum of the dynamic bodies (kg·m/s, world).
    pub(crate) fn linear_momentum(&self) -> V3 {
        let mut p = V3::zeros();
        for i in 0..self.len() {
            if self.kind[i] == BodyKind::Dynamic {
                p += self.vel[i] * self.mass(i);
            }
        }
        p
    }

    /// Angular momentum of the dynamic bodies about the world origin (kg·m²/s, world).
    pub(crate) fn angular_momentum(&self) -> V3 {
        let mut l = V3::zeros();
        for i in 0..self.len() {
            if self.kind[i] == BodyKind::Dynamic {
                let r = &self.rot[i];
                let wl = r.tr_mul(&self.omega[i]);
                l += r * self.inertia[i].component_mul(&wl)
                    + self.pos[i].cross(&(self.vel[i] * self.mass(i)));
            }
        }
        l
    }
}

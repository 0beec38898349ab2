//! The world's bodies through handles: inserting, removing, reading and setting them.
//!
//! Frames and units (as everywhere in the world): a body's position is its centre of mass
//! (m, world) and its rotation is world from body (the body axes are its principal axes);
//! velocities are world-frame, linear of the centre of mass (m/s) and angular (rad/s).

use super::world::World;
use crate::algebra::SE3;
use crate::dynamics::{BodyKind, BodySet};
use crate::geometry::{Material, Shape, M3, V3};
use crate::pipeline::{BodyBuilder, BodyHandle};

/// A body of a world, read-only. Get one with [`World::body`].
#[derive(Clone, Copy)]
pub struct BodyRef<'w> {
    set: &'w BodySet,
    i: usize,
    handle: BodyHandle,
}

/// A body of a world, to set its state. Get one with [`World::body_mut`].
pub struct BodyMut<'w> {
    set: &'w mut BodySet,
    i: usize,
    handle: BodyHandle,
}

impl<'w> BodyRef<'w> {
    /// Its handle.
    pub fn handle(&self) -> BodyHandle {
        self.handle
    }

    /// How it moves.
    pub fn kind(&self) -> BodyKind {
        self.set.kind[self.i]
    }

    /// Its surface properties (a compound's parts have their own).
    pub fn material(&self) -> Material {
        self.set.material[self.i]
    }

    /// Centre of mass (m, world).
    pub fn position(&self) -> V3 {
        self.set.pos[self.i]
    }

    /// Rotation world from body.
    pub fn rotation(&self) -> M3 {
        self.set.rot[self.i]
    }

    /// Pose of the body frame in the world, `T_wb`.
    pub fn pose(&self) -> SE3<f64> {
        SE3::new(self.set.rot[self.i], self.set.pos[self.i])
    }

    /// Linear velocity of the centre of mass (m/s, world).
    pub fn linear_velocity(&self) -> V3 {
        self.set.vel[self.i]
    }

    /// Angular velocity (rad/s, world).
    pub fn angular_velocity(&self) -> V3 {
        self.set.omega[self.i]
    }

    /// Velocity of the world point `p` moving with the body (m/s, world).
    pub fn point_velocity(&self, p: &V3) -> V3 {
        self.set.vel[self.i] + self.set.omega[self.i].cross(&(p - self.set.pos[self.i]))
    }

    /// Mass (kg); infinite for kinematic and fixed bodies.
    pub fn mass(&self) -> f64 {
        self.set.mass(self.i)
    }

    /// Principal moments of inertia about the centre of mass (kg·m², body axes); zero for
    /// kinematic and fixed bodies.
    pub fn principal_inertia(&self) -> V3 {
        self.set.inertia[self.i]
    }

    /// Whether it is simulated this step (dynamic and not asleep).
    pub fn is_awake(&self) -> bool {
        self.set.awake[self.i]
    }

    /// The applied external force (N, world) and torque (N·m, world).
    pub fn applied(&self) -> (V3, V3) {
        (self.set.force[self.i], self.set.torque[self.i])
    }

    /// Its name (empty when none was given).
    pub fn name(&self) -> &'w str {
        &self.set.name[self.i]
    }

    /// Its shape, in the body frame.
    pub fn shape(&self) -> &'w Shape {
        &self.set.shape[self.i]
    }
}

impl BodyMut<'_> {
    /// The body read-only: its pose, velocities, mass and the rest of [`BodyRef`]'s reads.
    pub fn read(&self) -> BodyRef<'_> {
        BodyRef {
            set: self.set,
            i: self.i,
            handle: self.handle,
        }
    }

    /// Places the centre of mass (m, world); wakes the body.
    pub fn set_position(&mut self, p: V3) -> &mut Self {
        self.set.pos[self.i] = p;
        self.wake_up()
    }

    /// Sets the rotation world from body (re-orthonormalised); wakes the body.
    pub fn set_rotation(&mut self, r: M3) -> &mut Self {
        self.set.rot[self.i] = crate::algebra::exp_so3(&crate::algebra::log_so3(&r));
        self.wake_up()
    }

    /// Sets the linear velocity of the centre of mass (m/s, world); wakes the body.
    pub fn set_linear_velocity(&mut self, v: V3) -> &mut Self {
        self.set.vel[self.i] = v;
        self.wake_up()
    }

    /// Sets the angular velocity (rad/s, world); wakes the body.
    pub fn set_angular_velocity(&mut self, w: V3) -> &mut Self {
        self.set.omega[self.i] = w;
        self.wake_up()
    }

    /// Sets the applied external force (N, world, through the centre of mass), kept until
    /// changed; wakes the body.
    pub fn set_force(&mut self, f: V3) -> &mut Self {
        self.set.force[self.i] = f;
        self.wake_up()
    }

    /// Sets the applied external torque (N·m, world), kept until changed; wakes the body.
    pub fn set_torque(&mut self, t: V3) -> &mut Self {
        self.set.torque[self.i] = t;
        self.wake_up()
    }

    /// Wakes a sleeping dynamic body (kinematic and fixed bodies never sleep or wake).
    pub(crate) fn wake_up(&mut self) -> &mut Self {
        if self.set.kind[self.i] == BodyKind::Dynamic {
            self.set.awake[self.i] = true;
            self.set.sleep_time[self.i] = 0.0;
        }
        self
    }
}

impl World {
    /// Number of bodies (free, kinematic, fixed, and the proxies of tree links).
    pub fn body_count(&self) -> usize {
        self.bodies.len()
    }

    /// Every body's handle, in storage order (insertion order until a body is removed).
    pub fn body_handles(&self) -> impl ExactSizeIterator<Item = BodyHandle> + '_ {
        (0..self.bodies.len()).map(|i| self.body_slots.handle(i))
    }

    /// Every body, in storage order.
    pub fn bodies(&self) -> impl ExactSizeIterator<Item = BodyRef<'_>> + '_ {
        (0..self.bodies.len()).map(|i| BodyRef {
            set: &self.bodies,
            i,
            handle: self.body_slots.handle(i),
        })
    }

    /// The body `h`, or `None` when it was removed.
    pub fn body(&self, h: BodyHandle) -> Option<BodyRef<'_>> {
        let i = self.body_slots.index(h)?;
        Some(BodyRef {
            set: &self.bodies,
            i,
            handle: h,
        })
    }

    /// The body `h` to set its state, or `None` when it was removed. A tree link's proxy
    /// body is posed by its tree: what is set on it is overwritten at the next step. The
    /// world counts its rest afresh (a body set in motion, pushed or moved takes the step's
    /// substeps until everything has rested again).
    pub fn body_mut(&mut self, h: BodyHandle) -> Option<BodyMut<'_>> {
        let i = self.body_slots.index(h)?;
        self.resting_substeps.forget();
        Some(BodyMut {
            set: &mut self.bodies,
            i,
            handle: h,
        })
    }

    /// The first body named `name`.
    pub fn body_named(&self, name: &str) -> Option<BodyHandle> {
        let i = self.bodies.name.iter().position(|n| n == name)?;
        Some(self.body_slots.handle(i))
    }

    /// Inserts a body; its handle stays valid until it is removed, whatever else is
    /// inserted or removed. The body's state is checked by the next step (a dynamic body
    /// needs a positive finite mass).
    pub fn insert_body(&mut self, b: BodyBuilder) -> BodyHandle {
        let (mass, pos, rot) = b.mass_and_pose();
        self.bodies.push(
            b.name,
            b.kind,
            b.shape,
            b.material,
            mass,
            pos,
            rot,
            b.velocity,
            b.angular_velocity,
        );
        self.broad_dirty = true;
        self.resting_substeps.forget();
        self.body_slots.insert()
    }

    /// Removes body `h` and the joints attached to it. Returns `false` (and changes nothing)
    /// when `h` is stale or names a tree link's proxy (links leave with their tree). The
    /// contacts of the body that moves into the freed storage index lose their warm start
    /// for one step.
    pub fn remove_body(&mut self, h: BodyHandle) -> bool {
        let Some(i) = self.body_slots.index(h) else {
            return false;
        };
        if self.proxies.get(i).is_some_and(Option::is_some) {
            return false;
        }
        let mut k = self.joints.len();
        while k > 0 {
            k -= 1;
            if self.joints[k].a == i || self.joints[k].b == i {
                self.remove_joint_at(k);
            }
        }
        let last = self.bodies.len() - 1;
        if let Some(narrow) = self.narrow.as_mut() {
            narrow.forget_bodies(i, last);
        }
        self.bodies.swap_remove(i);
        self.body_slots.swap_remove(i);
        if self.proxies.len() > last {
            self.proxies.swap_remove(i);
        } else if i < self.proxies.len() {
            self.proxies[i] = None;
        }
        let moved = |x: &mut usize| {
            if *x == last {
                *x = i;
            }
        };
        for j in &mut self.joints {
            moved(&mut j.a);
            moved(&mut j.b);
        }
        for (a, b) in &mut self.joint_pairs {
            moved(a);
            moved(b);
        }
        self.rebuild_excluded_pairs();
        // The factors islands hold belong to bodies by index: start them afresh.
        self.island_substeps.forget_held();
        self.resting_substeps.forget();
        self.guard.recheck_all();
        self.broad_dirty = true;
        true
    }

    /// Removes joint `k` (storage index) with its handle and pair.
    pub(super) fn remove_joint_at(&mut self, k: usize) {
        self.joints.swap_remove(k);
        self.joint_pairs.swap_remove(k);
        self.joint_slots.swap_remove(k);
        self.rebuild_excluded_pairs();
    }

    /// The pairs that never collide: the two bodies of each joint, and the links of one
    /// tree with each other.
    pub(super) fn rebuild_excluded_pairs(&mut self) {
        let key = |a: usize, b: usize| ((a.min(b) as u64) << 32) | a.max(b) as u64;
        self.excluded_pairs.clear();
        for &(a, b) in &self.joint_pairs {
            self.excluded_pairs.push(key(a, b));
        }
        let links: Vec<(usize, usize)> = self
            .proxies
            .iter()
            .enumerate()
            .filter_map(|(i, p)| p.map(|p| (p.tree, i)))
            .collect();
        for (x, &(ta, a)) in links.iter().enumerate() {
            for &(tb, b) in &links[x + 1..] {
                if ta == tb {
                    self.excluded_pairs.push(key(a, b));
                }
            }
        }
        self.excluded_pairs.sort_unstable();
        self.excluded_pairs.dedup();
    }

    /// Kinetic energy of the free dynamic bodies (J).
    pub fn kinetic_energy(&self) -> f64 {
        self.bodies.kinetic_energy()
    }

    /// Linear momentum of the free dynamic bodies (kg·m/s, world).
    pub fn linear_momentum(&self) -> V3 {
        self.bodies.linear_momentum()
    }

    /// Angular momentum of the free dynamic bodies about the world origin (kg·m²/s, world).
    pub fn angular_momentum(&self) -> V3 {
        self.bodies.angular_momentum()
    }
}

//! Articulated trees: bodies in topological order (every parent before its children).

use super::{Body, Joint, ModelError};
use crate::algebra::{Inertia, Vec3, SE3};
use crate::Real;

/// A tree of rigid bodies connected by joints, rooted at the fixed world frame.
///
/// Bodies are stored in topological order: a body's parent always has a smaller index, so a
/// forward loop visits parents first and a backward loop children first. Several bodies may
/// have no parent (a forest rooted at the world) and any body may have several children.
#[derive(Clone, Debug)]
pub struct ArticulatedTree<T: Real> {
    bodies: Vec<Body<T>>,
    gravity: Vec3<T>,
    nq: usize,
    nv: usize,
}

impl<T: Real> ArticulatedTree<T> {
    /// An empty tree with the given gravity (m/s², world frame), e.g. `(0, 0, −9.81)`.
    pub fn new(gravity: Vec3<T>) -> Self {
        Self {
            bodies: Vec::new(),
            gravity,
            nq: 0,
            nv: 0,
        }
    }

    /// Adds a body attached to `parent` (an earlier body, or `None` for the world) by `joint`
    /// whose frame sits at `placement` in the parent frame; `inertia` in the new body's frame.
    /// Returns the new body's index.
    pub fn add_body(
        &mut self,
        name: impl Into<String>,
        parent: Option<usize>,
        placement: SE3<T>,
        joint: impl Joint<T> + 'static,
        inertia: Inertia<T>,
    ) -> Result<usize, ModelError> {
        self.add_boxed(name, parent, placement, Box::new(joint), inertia)
    }

    /// As [`ArticulatedTree::add_body`] with an already boxed joint.
    pub(crate) fn add_boxed(
        &mut self,
        name: impl Into<String>,
        parent: Option<usize>,
        placement: SE3<T>,
        joint: Box<dyn Joint<T>>,
        inertia: Inertia<T>,
    ) -> Result<usize, ModelError> {
        let name = name.into();
        let index = self.bodies.len();
        if let Some(p) = parent {
            if p >= index {
                return Err(ModelError::InvalidParent {
                    body: index,
                    name,
                    parent: p,
                });
            }
        }
        let m = inertia.m.to_f64();
        if m.is_nan() || m < 0.0 {
            return Err(ModelError::InvalidInertia {
                name,
                why: format!("mass must be non-negative, got {}", inertia.m),
            });
        }
        let (nq, nv) = (joint.nq(), joint.nv());
        self.bodies.push(Body {
            name,
            parent,
            placement,
            joint,
            inertia,
            q_offset: self.nq,
            v_offset: self.nv,
            nq,
            nv,
        });
        self.nq += nq;
        self.nv += nv;
        Ok(index)
    }

    /// The bodies, parents first.
    #[inline]
    pub fn bodies(&self) -> &[Body<T>] {
        &self.bodies
    }

    /// Number of bodies.
    #[inline]
    pub fn len(&self) -> usize {
        self.bodies.len()
    }

    /// True if the tree has no body.
    #[inline]
    pub fn is_empty(&self) -> bool {
        self.bodies.is_empty()
    }

    /// Size of the configuration vector `q`.
    #[inline]
    pub fn nq(&self) -> usize {
        self.nq
    }

    /// Degrees of freedom: size of `q̇`, `q̈`, `τ`.
    #[inline]
    pub fn nv(&self) -> usize {
        self.nv
    }

    /// Gravity (m/s², world frame).
    #[inline]
    pub(crate) fn gravity(&self) -> Vec3<T> {
        self.gravity
    }

    /// Sets the gravity (m/s², world frame).
    pub(crate) fn set_gravity(&mut self, g: Vec3<T>) {
        self.gravity = g;
    }

    /// The neutral configuration (every joint at its zero).
    pub fn neutral_configuration(&self) -> Vec<T> {
        let mut q = vec![T::zero(); self.nq];
        for b in &self.bodies {
            b.joint.neutral(&mut q[b.q_offset..b.q_offset + b.nq()]);
        }
        q
    }

    /// Pose of every body frame in the world frame at configuration `q`.
    pub fn body_poses(&self, q: &[T]) -> Vec<SE3<T>> {
        let mut out: Vec<SE3<T>> = Vec::with_capacity(self.bodies.len());
        self.body_poses_into(q, &mut out);
        out
    }

    /// [`Self::body_poses`] written into `out` (cleared first; no allocation once it holds
    /// a pose per body).
    pub(crate) fn body_poses_into(&self, q: &[T], out: &mut Vec<SE3<T>>) {
        out.clear();
        for b in &self.bodies {
            let f = b.placement * b.joint.transform(&q[b.q_offset..b.q_offset + b.nq()]);
            let pose = match b.parent {
                Some(p) => out[p] * f,
                None => f,
            };
            out.push(pose);
        }
    }
}

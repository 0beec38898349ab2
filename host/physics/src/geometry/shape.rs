//! The collision shapes, their axis-aligned bounding boxes and mass properties.
//!
//! Shapes are described in their body frame, centred on the body origin (which is also the
//! centre of mass): a box by half extents, a sphere by radius, a capsule and a cylinder by
//! radius and half height along the body `z` axis, a half-space by its outward normal (body
//! frame) through the body origin — the solid is `{x : n·x ≤ 0}`; a compound by its parts,
//! each posed in the body frame ([`Compound`]).

use super::{Compound, M3, V3};
use std::sync::Arc;

/// A collision shape in its body frame (m).
#[derive(Clone, Debug, PartialEq)]
pub enum Shape {
    /// Box with half extents along the body axes.
    Cuboid {
        /// Half extents (m).
        half: V3,
    },
    /// Sphere.
    Sphere {
        /// Radius (m).
        radius: f64,
    },
    /// Capsule: segment `[-h, h]` on `z`, swept by `radius`.
    Capsule {
        /// Radius (m).
        radius: f64,
        /// Half length of the core segment (m).
        half_height: f64,
    },
    /// Cylinder along `z`.
    Cylinder {
        /// Radius (m).
        radius: f64,
        /// Half height (m).
        half_height: f64,
    },
    /// Half-space `{x : n·x ≤ 0}` (body frame). Only on fixed or kinematic bodies.
    HalfSpace {
        /// Unit outward normal, body frame.
        normal: V3,
    },
    /// Several primitives rigidly joined, each with its pose and material (shared, so that
    /// cloning a shape stays cheap).
    Compound(Arc<Compound>),
}

/// An axis-aligned box in world coordinates (m).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Aabb {
    /// Lower corner.
    pub(crate) min: V3,
    /// Upper corner.
    pub(crate) max: V3,
}

impl Aabb {
    /// Whether two boxes overlap (closed).
    #[inline]
    pub(crate) fn overlaps(&self, o: &Aabb) -> bool {
        self.min.x <= o.max.x
            && o.min.x <= self.max.x
            && self.min.y <= o.max.y
            && o.min.y <= self.max.y
            && self.min.z <= o.max.z
            && o.min.z <= self.max.z
    }

    /// Whether `o` lies within this box (closed).
    #[inline]
    pub(crate) fn contains(&self, o: &Aabb) -> bool {
        self.min.x <= o.min.x
            && self.min.y <= o.min.y
            && self.min.z <= o.min.z
            && o.max.x <= self.max.x
            && o.max.y <= self.max.y
            && o.max.z <= self.max.z
    }

    /// Grown by `m` on every side.
    #[inline]
    pub(crate) fn loosened(&self, m: f64) -> Aabb {
        let d = V3::new(m, m, m);
        Aabb {
            min: self.min - d,
            max: self.max + d,
        }
    }
}

impl Shape {
    /// Whether this is a half-space (infinite; kept out of the grid).
    pub fn is_half_space(&self) -> bool {
        matches!(self, Shape::HalfSpace { .. })
    }

    /// Volume (m³); `∞` for a half-space.
    pub fn volume(&self) -> f64 {
        use std::f64::consts::PI;
        match *self {
            Shape::Cuboid { half } => 8.0 * half.x * half.y * half.z,
            Shape::Sphere { radius } => 4.0 / 3.0 * PI * radius.powi(3),
            Shape::Capsule {
                radius,
                half_height,
            } => PI * radius * radius * (2.0 * half_height + 4.0 / 3.0 * radius),
            Shape::Cylinder {
                radius,
                half_height,
            } => PI * radius * radius * 2.0 * half_height,
            Shape::HalfSpace { .. } => f64::INFINITY,
            Shape::Compound(ref c) => c.volume(),
        }
    }

    /// Principal moments of inertia about the centre, body axes, for mass `m` (kg·m²).
    pub(crate) fn principal_inertia(&self, m: f64) -> V3 {
        match *self {
            Shape::Cuboid { half } => {
                let (x2, y2, z2) = (
                    4.0 * half.x * half.x,
                    4.0 * half.y * half.y,
                    4.0 * half.z * half.z,
                );
                V3::new(
                    m * (y2 + z2) / 12.0,
                    m * (x2 + z2) / 12.0,
                    m * (x2 + y2) / 12.0,
                )
            }
            Shape::Sphere { radius } => V3::repeat(0.4 * m * radius * radius),
            Shape::Cylinder {
                radius,
                half_height,
            } => {
                let h = 2.0 * half_height;
                let ixx = m * (3.0 * radius * radius + h * h) / 12.0;
                V3::new(ixx, ixx, 0.5 * m * radius * radius)
            }
            Shape::Capsule {
                radius,
                half_height,
            } => {
                // Cylinder + two hemispheres, masses split by volume.
                use std::f64::consts::PI;
                let r2 = radius * radius;
                let h = 2.0 * half_height;
                let vc = PI * r2 * h;
                let vs = 4.0 / 3.0 * PI * r2 * radius;
                let (mc, ms) = (m * vc / (vc + vs), m * vs / (vc + vs));
                let izz = 0.5 * mc * r2 + 0.4 * ms * r2;
                let ixx = mc * (3.0 * r2 + h * h) / 12.0
                    + ms * (0.4 * r2 + 0.25 * h * h + 0.375 * radius * h);
                V3::new(ixx, ixx, izz)
            }
            Shape::HalfSpace { .. } => V3::zeros(),
            Shape::Compound(ref c) => c.principal_inertia(m),
        }
    }

    /// Bounding box for pose `(r, p)` (world from body). A half-space gets an infinite box.
    pub(crate) fn aabb(&self, r: &M3, p: &V3) -> Aabb {
        let ext = match *self {
            Shape::Cuboid { half } => r.abs() * half,
            Shape::Sphere { radius } => V3::repeat(radius),
            Shape::Capsule {
                radius,
                half_height,
            } => r.column(2).abs() * half_height + V3::repeat(radius),
            Shape::Cylinder {
                radius,
                half_height,
            } => {
                let a = r.column(2);
                // Disc extent along each world axis: radius·sqrt(1 − a_i²).
                let disc = V3::new(
                    (1.0 - a.x * a.x).max(0.0).sqrt(),
                    (1.0 - a.y * a.y).max(0.0).sqrt(),
                    (1.0 - a.z * a.z).max(0.0).sqrt(),
                );
                a.abs() * half_height + disc * radius
            }
            Shape::HalfSpace { .. } => V3::repeat(f64::INFINITY),
            Shape::Compound(ref c) => return c.aabb(r, p),
        };
        Aabb {
            min: p - ext,
            max: p + ext,
        }
    }

    /// A length that bounds how far the shape reaches from its centre (m); 0 for a half-space.
    pub fn bounding_radius(&self) -> f64 {
        match *self {
            Shape::Cuboid { half } => half.norm(),
            Shape::Sphere { radius } => radius,
            Shape::Capsule {
                radius,
                half_height,
            } => radius + half_height,
            Shape::Cylinder {
                radius,
                half_height,
            } => (radius * radius + half_height * half_height).sqrt(),
            Shape::HalfSpace { .. } => 0.0,
            Shape::Compound(ref c) => c.bounding_radius(),
        }
    }

    /// How far the shape reaches from the line through its centre along the unit `axis`
    /// (body frame, m): a point of the shape moves by at most this times the turn when the
    /// body turns about that line. A compound's parts count by their distance from the line
    /// (a foosball rod spinning about its bar sweeps its men's reach, not its length); other
    /// shapes give their bounding radius.
    pub(crate) fn reach_about(&self, axis: &V3) -> f64 {
        match self {
            Shape::Compound(c) => c
                .parts()
                .iter()
                .map(|p| (p.pos - axis * axis.dot(&p.pos)).norm() + p.shape.bounding_radius())
                .fold(0.0, f64::max),
            s => s.bounding_radius(),
        }
    }

    /// The smallest half-dimension (m): how thin the shape is (for continuous collision).
    pub(crate) fn thinness(&self) -> f64 {
        match *self {
            Shape::Cuboid { half } => half.min(),
            Shape::Sphere { radius } | Shape::Capsule { radius, .. } => radius,
            Shape::Cylinder {
                radius,
                half_height,
            } => radius.min(half_height),
            Shape::HalfSpace { .. } => f64::INFINITY,
            Shape::Compound(ref c) => c.thinness(),
        }
    }

    /// Signed distance (m) from a point in the body frame to the surface, negative inside.
    /// A compound takes the nearest part.
    pub fn signed_distance(&self, local: &V3) -> f64 {
        match *self {
            Shape::HalfSpace { normal } => normal.dot(local),
            Shape::Cuboid { half } => {
                let q = local.abs() - half;
                let outside = q.sup(&V3::zeros()).norm();
                let inside = q.max().min(0.0);
                outside + inside
            }
            Shape::Cylinder {
                radius,
                half_height,
            } => {
                let radial = (local.x * local.x + local.y * local.y).sqrt() - radius;
                let axial = local.z.abs() - half_height;
                let outside = (radial.max(0.0).powi(2) + axial.max(0.0).powi(2)).sqrt();
                outside + radial.max(axial).min(0.0)
            }
            Shape::Capsule {
                radius,
                half_height,
            } => {
                let z = local.z.clamp(-half_height, half_height);
                (local - V3::new(0.0, 0.0, z)).norm() - radius
            }
            Shape::Sphere { radius } => local.norm() - radius,
            Shape::Compound(ref c) => c
                .parts()
                .iter()
                .map(|p| p.shape.signed_distance(&p.rot.tr_mul(&(local - p.pos))))
                .fold(f64::INFINITY, f64::min),
        }
    }
}

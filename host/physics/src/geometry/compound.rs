//! Compound shapes: several primitive shapes fixed in one body frame, each with its own pose
//! and material, and the mass properties of the whole.
//!
//! A compound is described in a *reference frame* `r` chosen by the user (where the parts'
//! poses are stated). [`Compound::new`] sums the parts' inertias in that frame (each part's
//! inertia moved there by [`Inertia::xform_inv`](crate::algebra::Inertia::xform_inv)), finds
//! the centre of mass and the principal axes, and re-expresses every part in the *body frame*
//! `b`: origin at the centre of mass, axes the principal axes — the frame every body of the
//! engine moves in. [`CompoundMass::body_in_reference`] is the pose `T_rb` of that frame in the
//! reference frame.

use super::{Aabb, Material, Shape, M3, V3};
use crate::algebra::{Inertia, Sym3, SE3};
use std::sync::Arc;

/// One part of a compound: a primitive shape at a pose in the body frame.
#[derive(Clone, Debug, PartialEq)]
pub struct Part {
    /// The shape (never a half-space or another compound), centred on its own frame.
    pub(crate) shape: Shape,
    /// Rotation body from part (columns: the part's axes in the body frame).
    pub(crate) rot: M3,
    /// Centre of the part in the body frame (m).
    pub(crate) pos: V3,
    /// Surface properties of this part.
    pub(crate) material: Material,
}

/// A part as the user states it: in the compound's reference frame, with its mass.
#[derive(Clone, Debug, PartialEq)]
pub struct PartDesc {
    /// The shape (a primitive: box, sphere, capsule or cylinder).
    pub shape: Shape,
    /// Pose of the part in the reference frame, `T_rp`.
    pub pose: SE3<f64>,
    /// Mass of the part (kg, > 0).
    pub mass: f64,
    /// Surface properties.
    pub material: Material,
}

/// Why a compound cannot be built.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum CompoundError {
    /// No parts.
    #[error("a compound needs at least one part")]
    Empty,
    /// A part is a half-space or a compound.
    #[error("part {0}: a compound's parts are boxes, spheres, capsules or cylinders")]
    UnsupportedPart(usize),
    /// A part's mass is not a positive finite number.
    #[error("part {part}: mass {mass} kg is not a positive finite number")]
    BadMass {
        /// Index of the part.
        part: usize,
        /// The mass given (kg).
        mass: f64,
    },
}

/// The mass properties of a compound.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CompoundMass {
    /// Total mass (kg).
    pub mass: f64,
    /// Principal moments of inertia about the centre of mass (kg·m²), body axes.
    pub principal_inertia: V3,
    /// Pose of the body frame (centre of mass, principal axes) in the reference frame.
    pub body_in_reference: SE3<f64>,
}

/// Several primitive shapes rigidly joined; shared by reference ([`Shape::Compound`]).
#[derive(Clone, Debug, PartialEq)]
pub struct Compound {
    parts: Vec<Part>,
    /// Principal inertia per kilogram of total mass (m²), body axes.
    unit_inertia: V3,
    volume: f64,
    bounding_radius: f64,
    thinness: f64,
}

impl Compound {
    /// Builds a compound from parts stated in a reference frame; returns it (parts in the
    /// body frame) and its mass properties.
    pub fn new(parts: &[PartDesc]) -> Result<(Compound, CompoundMass), CompoundError> {
        if parts.is_empty() {
            return Err(CompoundError::Empty);
        }
        let mut total = Inertia::<f64>::zeros();
        for (k, p) in parts.iter().enumerate() {
            if matches!(p.shape, Shape::HalfSpace { .. } | Shape::Compound(_)) {
                return Err(CompoundError::UnsupportedPart(k));
            }
            if !(p.mass.is_finite() && p.mass > 0.0) {
                return Err(CompoundError::BadMass {
                    part: k,
                    mass: p.mass,
                });
            }
            let own = Inertia::diagonal(p.mass, p.shape.principal_inertia(p.mass));
            total = total + own.xform_inv(&p.pose);
        }
        let mass = total.m;
        let com = total.com();
        let (rot, moments) = principal_axes(&total.i_com());
        let body_in_reference = SE3::new(rot, com);
        let reference_in_body = body_in_reference.inverse();
        let parts: Vec<Part> = parts
            .iter()
            .map(|p| {
                let t = reference_in_body * p.pose;
                Part {
                    shape: p.shape.clone(),
                    rot: t.r,
                    pos: t.p,
                    material: p.material,
                }
            })
            .collect();
        let bounding_radius = parts
            .iter()
            .map(|p| p.pos.norm() + p.shape.bounding_radius())
            .fold(0.0, f64::max);
        let thinness = parts
            .iter()
            .map(|p| p.shape.thinness())
            .fold(f64::INFINITY, f64::min);
        let volume = parts.iter().map(|p| p.shape.volume()).sum();
        let compound = Compound {
            parts,
            unit_inertia: moments / mass,
            volume,
            bounding_radius,
            thinness,
        };
        Ok((
            compound,
            CompoundMass {
                mass,
                principal_inertia: moments,
                body_in_reference,
            },
        ))
    }

    /// A compound of parts already posed in the body frame, for collision only: it has no
    /// mass properties of its own (the shapes on a tree link, whose mass is the model's).
    pub(crate) fn from_parts(parts: Vec<Part>) -> Result<Compound, CompoundError> {
        if parts.is_empty() {
            return Err(CompoundError::Empty);
        }
        if let Some(k) = parts
            .iter()
            .position(|p| matches!(p.shape, Shape::HalfSpace { .. } | Shape::Compound(_)))
        {
            return Err(CompoundError::UnsupportedPart(k));
        }
        Ok(Compound {
            unit_inertia: V3::zeros(),
            volume: parts.iter().map(|p| p.shape.volume()).sum(),
            bounding_radius: parts
                .iter()
                .map(|p| p.pos.norm() + p.shape.bounding_radius())
                .fold(0.0, f64::max),
            thinness: parts
                .iter()
                .map(|p| p.shape.thinness())
                .fold(f64::INFINITY, f64::min),
            parts,
        })
    }

    /// The parts, posed in the body frame.
    pub(crate) fn parts(&self) -> &[Part] {
        &self.parts
    }

    /// Wraps it as a shape.
    pub(crate) fn into_shape(self) -> Shape {
        Shape::Compound(Arc::new(self))
    }

    /// Principal inertia for total mass `m` (kg·m²): the parts keep their mass ratios.
    pub(crate) fn principal_inertia(&self, m: f64) -> V3 {
        self.unit_inertia * m
    }

    /// Sum of the parts' volumes (m³; overlaps counted twice).
    pub(crate) fn volume(&self) -> f64 {
        self.volume
    }

    /// Largest distance from the body origin reached by a part (m).
    pub(crate) fn bounding_radius(&self) -> f64 {
        self.bounding_radius
    }

    /// Thinnest part's smallest half-dimension (m).
    pub(crate) fn thinness(&self) -> f64 {
        self.thinness
    }

    /// Union of the parts' boxes for body pose `(r, p)`.
    pub(crate) fn aabb(&self, r: &M3, p: &V3) -> Aabb {
        let mut out = Aabb {
            min: V3::repeat(f64::INFINITY),
            max: V3::repeat(f64::NEG_INFINITY),
        };
        for part in &self.parts {
            let b = part.shape.aabb(&(r * part.rot), &(p + r * part.pos));
            out.min = out.min.inf(&b.min);
            out.max = out.max.sup(&b.max);
        }
        out
    }
}

/// Principal axes of a symmetric inertia: a proper rotation `R` (columns: the axes) and the
/// moments, with `I = R diag(moments) Rᵀ`.
fn principal_axes(i: &Sym3<f64>) -> (M3, V3) {
    let m = i.to_matrix();
    // Already diagonal (every part on the axes): keep the reference axes exactly.
    let off = m[(0, 1)].abs() + m[(0, 2)].abs() + m[(1, 2)].abs();
    if off <= 1e-15 * m.diagonal().abs().max() {
        return (M3::identity(), m.diagonal());
    }
    let eig = nalgebra::SymmetricEigen::new(m);
    let mut r = eig.eigenvectors;
    if r.determinant() < 0.0 {
        r.column_mut(2).neg_mut();
    }
    (r, eig.eigenvalues)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn part(shape: Shape, pose: SE3<f64>, mass: f64) -> PartDesc {
        PartDesc {
            shape,
            pose,
            mass,
            material: Material::default(),
        }
    }

    #[test]
    fn an_off_axis_compound_gets_a_proper_rotation_that_diagonalises_it() {
        let bar = Shape::Cuboid {
            half: V3::new(0.5, 0.05, 0.05),
        };
        let tilt = SE3::from_axis_angle(&V3::new(0.3, 0.2, 1.0).normalize(), 0.7);
        let (c, mp) = Compound::new(&[
            part(bar.clone(), tilt, 2.0),
            part(
                Shape::Sphere { radius: 0.1 },
                SE3::from_translation(V3::x()),
                1.0,
            ),
        ])
        .expect("valid");
        let r = mp.body_in_reference.r;
        assert!((r.determinant() - 1.0).abs() < 1e-12);
        assert!((r.transpose() * r - M3::identity()).norm() < 1e-12);
        assert_eq!(c.parts().len(), 2);
        assert!((mp.mass - 3.0).abs() < 1e-15);
    }

    #[test]
    fn half_spaces_and_bad_masses_are_refused() {
        let hs = Shape::HalfSpace { normal: V3::z() };
        assert_eq!(
            Compound::new(&[part(hs, SE3::identity(), 1.0)]).unwrap_err(),
            CompoundError::UnsupportedPart(0)
        );
        let s = Shape::Sphere { radius: 0.1 };
        assert!(matches!(
            Compound::new(&[part(s, SE3::identity(), f64::NAN)]),
            Err(CompoundError::BadMass { part: 0, .. })
        ));
        assert_eq!(Compound::new(&[]).unwrap_err(), CompoundError::Empty);
    }
}

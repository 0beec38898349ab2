//! Describing a body before it enters a world: [`BodyBuilder`].

use crate::algebra::SE3;
use crate::dynamics::BodyKind;
use crate::geometry::{Compound, CompoundError, Material, PartDesc, Shape, M3, V3};

/// Density (kg/m³) of a dynamic body that states neither a mass nor a density: water.
pub const DEFAULT_DENSITY: f64 = 1000.0;

/// A body to insert into a [`World`](super::World) with
/// [`World::insert_body`](super::World::insert_body).
///
/// Frames: the position and rotation place the body's frame in the world (m; world from
/// body rotation). For a primitive shape the body frame is the shape's own frame (centre of
/// mass, principal axes). For a compound built with [`BodyBuilder::compound`] they place the
/// frame its parts were stated in; the engine then moves the body in its centre-of-mass
/// principal frame, and [`BodyRef::position`](super::BodyRef::position) reads that frame.
/// Velocities are world-frame: linear of the centre of mass (m/s), angular (rad/s).
#[derive(Clone, Debug)]
pub struct BodyBuilder {
    pub(crate) name: String,
    pub(crate) kind: BodyKind,
    pub(crate) shape: Shape,
    pub(crate) material: Material,
    pub(crate) mass: Option<f64>,
    pub(crate) density: Option<f64>,
    /// Compound only: its mass and the pose of its principal frame in the parts' frame.
    pub(crate) compound: Option<(f64, SE3<f64>)>,
    pub(crate) position: V3,
    pub(crate) rotation: M3,
    pub(crate) velocity: V3,
    pub(crate) angular_velocity: V3,
}

impl BodyBuilder {
    /// A body of `kind` with a primitive `shape` (a compound shape is allowed too, taken as
    /// already in its principal frame), at the origin, at rest.
    pub(crate) fn new(kind: BodyKind, shape: Shape) -> Self {
        Self {
            name: String::new(),
            kind,
            shape,
            material: Material::default(),
            mass: None,
            density: None,
            compound: None,
            position: V3::zeros(),
            rotation: M3::identity(),
            velocity: V3::zeros(),
            angular_velocity: V3::zeros(),
        }
    }

    /// A dynamic body (moved by forces and contacts).
    pub fn dynamic(shape: Shape) -> Self {
        Self::new(BodyKind::Dynamic, shape)
    }

    /// A kinematic body (moved only by the velocity and pose set on it; pushes dynamic ones).
    pub fn kinematic(shape: Shape) -> Self {
        Self::new(BodyKind::Kinematic, shape)
    }

    /// A fixed body (never moves).
    pub fn fixed(shape: Shape) -> Self {
        Self::new(BodyKind::Fixed, shape)
    }

    /// A body of `kind` made of `parts` stated in one reference frame, each with its mass and
    /// material; its mass, centre of mass and inertia come from the parts.
    pub fn compound(kind: BodyKind, parts: &[PartDesc]) -> Result<Self, CompoundError> {
        let (compound, mass) = Compound::new(parts)?;
        let mut b = Self::new(kind, compound.into_shape());
        b.compound = Some((mass.mass, mass.body_in_reference));
        Ok(b)
    }

    /// Its name (for lookups with [`World::body_named`](super::World::body_named) and output).
    pub fn name(mut self, name: impl Into<String>) -> Self {
        self.name = name.into();
        self
    }

    /// Surface properties (of a primitive shape; a compound's parts carry their own).
    pub fn material(mut self, material: Material) -> Self {
        self.material = material;
        self
    }

    /// Mass (kg); overrides the density and a compound's parts' total.
    pub fn mass(mut self, kg: f64) -> Self {
        self.mass = Some(kg);
        self
    }

    /// Density (kg/m³); the mass is density × the shape's volume.
    pub fn density(mut self, kg_per_m3: f64) -> Self {
        self.density = Some(kg_per_m3);
        self
    }

    /// Position of the body frame (m, world).
    pub fn position(mut self, p: V3) -> Self {
        self.position = p;
        self
    }

    /// Rotation world from body frame.
    pub fn rotation(mut self, r: M3) -> Self {
        self.rotation = r;
        self
    }

    /// Linear velocity of the centre of mass (m/s, world).
    pub fn velocity(mut self, v: V3) -> Self {
        self.velocity = v;
        self
    }

    /// Angular velocity (rad/s, world).
    pub fn angular_velocity(mut self, w: V3) -> Self {
        self.angular_velocity = w;
        self
    }

    /// The mass (kg) and the pose of the centre-of-mass frame in the world.
    pub(crate) fn mass_and_pose(&self) -> (f64, V3, M3) {
        let (mut pos, mut rot) = (self.position, self.rotation);
        let mut mass = None;
        if let Some((m, t)) = self.compound {
            pos += rot * t.p;
            rot *= t.r;
            mass = Some(m);
        }
        let from_density = |d: f64| d * self.shape.volume();
        let mass = self
            .mass
            .or(self.density.map(from_density))
            .or(mass)
            .unwrap_or_else(|| from_density(DEFAULT_DENSITY));
        (mass, pos, rot)
    }
}

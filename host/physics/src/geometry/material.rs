//! Surface properties of a shape.

/// Surface properties of a shape (or of every shape of a body that has one).
///
/// Pairs mix as: friction `sqrt(μa μb)`, restitution and rolling resistance the larger.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Material {
    /// Coulomb friction coefficient (–).
    pub friction: f64,
    /// Restitution coefficient, 0 … 1 (–).
    pub restitution: f64,
    /// Rolling resistance coefficient: resisting torque = coefficient · radius · normal force (–).
    pub rolling_resistance: f64,
}

impl Default for Material {
    fn default() -> Self {
        Self {
            friction: 0.5,
            restitution: 0.0,
            rolling_resistance: 0.0,
        }
    }
}

impl Material {
    /// The friction coefficient of a pair of surfaces: `sqrt(μa μb)` (–).
    #[inline]
    pub(crate) fn pair_friction(&self, other: &Material) -> f64 {
        (self.friction * other.friction).sqrt()
    }

    /// The restitution coefficient of a pair of surfaces: the larger (–).
    #[inline]
    pub(crate) fn pair_restitution(&self, other: &Material) -> f64 {
        self.restitution.max(other.restitution)
    }
}

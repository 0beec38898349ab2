//! The effects a scene declares; the pipeline builds and runs only these.

use serde::{Deserialize, Serialize};

/// One simulation effect.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Effect {
    /// Uniform gravity.
    Gravity,
    /// Collision detection and non-penetration.
    Contacts,
    /// Coulomb friction at contacts.
    Friction,
    /// Bounce above a velocity threshold.
    Restitution,
    /// Rolling resistance torque at contacts of round bodies.
    RollingResistance,
    /// Joints between free bodies.
    Joints,
    /// Articulated trees (part 1's ABA).
    Articulated,
    /// Continuous collision (speculative contacts swept by velocity).
    ContinuousCollision,
    /// The gyroscopic term `−ω × Iω` of free bodies.
    Gyroscopic,
    /// Linear and angular velocity damping.
    Damping,
    /// Islands and sleeping.
    Sleeping,
}

impl Effect {
    /// Every effect, in declaration order.
    pub const ALL: [Effect; 11] = [
        Effect::Gravity,
        Effect::Contacts,
        Effect::Friction,
        Effect::Restitution,
        Effect::RollingResistance,
        Effect::Joints,
        Effect::Articulated,
        Effect::ContinuousCollision,
        Effect::Gyroscopic,
        Effect::Damping,
        Effect::Sleeping,
    ];

    /// The scene-file name (`rolling_resistance`, …).
    pub fn name(self) -> &'static str {
        match self {
            Effect::Gravity => "gravity",
            Effect::Contacts => "contacts",
            Effect::Friction => "friction",
            Effect::Restitution => "restitution",
            Effect::RollingResistance => "rolling_resistance",
            Effect::Joints => "joints",
            Effect::Articulated => "articulated",
            Effect::ContinuousCollision => "continuous_collision",
            Effect::Gyroscopic => "gyroscopic",
            Effect::Damping => "damping",
            Effect::Sleeping => "sleeping",
        }
    }

    /// Effects this one needs declared too.
    pub(crate) fn requires(self) -> &'static [Effect] {
        match self {
            Effect::Friction
            | Effect::Restitution
            | Effect::RollingResistance
            | Effect::ContinuousCollision => &[Effect::Contacts],
            _ => &[],
        }
    }
}

/// A set of effects (bit set).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Effects(u32);

impl Effects {
    /// No effect.
    pub(crate) fn none() -> Self {
        Self(0)
    }

    /// From a list.
    pub fn of(list: &[Effect]) -> Self {
        let mut s = Self::none();
        for &e in list {
            s.insert(e);
        }
        s
    }

    /// Adds an effect.
    pub fn insert(&mut self, e: Effect) {
        self.0 |= 1 << e as u32;
    }

    /// Removes an effect.
    pub fn remove(&mut self, e: Effect) {
        self.0 &= !(1 << e as u32);
    }

    /// Whether `e` is declared.
    #[inline]
    pub(crate) fn has(&self, e: Effect) -> bool {
        self.0 & (1 << e as u32) != 0
    }

    /// The declared effects.
    pub fn iter(&self) -> impl Iterator<Item = Effect> + '_ {
        Effect::ALL.into_iter().filter(|e| self.has(*e))
    }
}

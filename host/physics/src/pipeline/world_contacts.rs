//! The world's contacts through handles: what touches what after a step.

use super::world::World;
use crate::geometry::{Manifold, V3};
use crate::pipeline::BodyHandle;

/// One touching pair of shapes (a part of each body, for compounds) after the last step.
#[derive(Clone, Copy, Debug)]
pub struct Contact<'w> {
    /// Body A.
    pub a: BodyHandle,
    /// Body B.
    pub b: BodyHandle,
    manifold: &'w Manifold,
}

impl Contact<'_> {
    /// Unit normal from A to B (world).
    pub fn normal(&self) -> V3 {
        self.manifold.normal
    }

    /// The touching parts of A and B (0 unless the body is a compound).
    pub fn parts(&self) -> (u16, u16) {
        (self.manifold.part_a, self.manifold.part_b)
    }

    /// Deepest separation of the contact points (m; negative when overlapping). Points up
    /// to the speculative margin apart count as contacts.
    pub fn min_separation(&self) -> f64 {
        self.manifold.min_separation()
    }

    /// Contact points: world position (m) and separation (m).
    pub fn points(&self) -> impl Iterator<Item = (V3, f64)> + '_ {
        self.manifold
            .points()
            .iter()
            .map(|p| (p.point, p.separation))
    }

    /// The largest normal impulse (N·s) any point took in the last step (its strongest
    /// moment, not the end-of-step warm start).
    pub fn max_normal_impulse(&self) -> f64 {
        self.manifold
            .points()
            .iter()
            .map(|p| p.max_normal_impulse)
            .fold(0.0, f64::max)
    }

    /// The total normal impulse (N·s) of the last substep (impulses are accumulated per
    /// substep); divided by that substep, the contact force ([`Contact::force`]).
    pub fn normal_impulse(&self) -> f64 {
        self.manifold
            .points()
            .iter()
            .map(|p| p.normal_impulse)
            .sum()
    }

    /// The total normal force (N) the contact carried at the end of the last step: its normal
    /// impulse over the substep it was accumulated in (the step's substep, or an island's
    /// shorter one); 0 for a contact that has carried none.
    pub fn force(&self) -> f64 {
        let h = self.manifold.impulse_substep;
        if h > 0.0 {
            self.normal_impulse() / h
        } else {
            0.0
        }
    }
}

impl World {
    /// Every touching pair after the last step (empty without the `contacts` effect).
    pub fn contacts(&self) -> impl Iterator<Item = Contact<'_>> + '_ {
        self.manifolds().iter().map(move |m| Contact {
            a: self.body_slots.handle(m.a as usize),
            b: self.body_slots.handle(m.b as usize),
            manifold: m,
        })
    }

    /// The contacts of the last step whose strongest point impulse reached `min_impulse`
    /// (N·s). The match derives its "Kick" and "Bounce" events from these.
    pub fn impacts(&self, min_impulse: f64) -> impl Iterator<Item = Contact<'_>> + '_ {
        self.contacts().filter(move |c| {
            let j = c.max_normal_impulse();
            j >= min_impulse && j > 0.0
        })
    }
}

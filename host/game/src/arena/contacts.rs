//! The ball's contacts, as the rules want them, and its clearance to every solid.
//!
//! **Contacts.** After a step, every manifold between the ball and another body that
//! carried an impulse during the step (its strongest point's `max_normal_impulse > 0`, as
//! [`World::impacts`] counts them) is a contact. One [`Contact`] per thing touched: the
//! field, the walls (all walls, ramps, goal boxes and the cover together), and each rod (its
//! link: the bar and all its men, one body; the arena names it through
//! [`World::link_of`]), with the strongest of its manifolds — so a man's body and leg
//! touching at once is one kick.
//!
//! * A **man's** contact speed comes from the impulse his link gave the ball: the
//!   impulse (N·s) over the ball's mass, the speed the kick gave the ball along the contact
//!   normal (m/s). A rod that swings past the ball without touching it, or rests on it,
//!   kicks nothing however fast it turns.
//! * A **wall's** or the **field's** is the ball's approach speed along the contact normal
//!   before the step (ball velocity and spin from before the step; they stand still),
//!   clamped at 0.
//!
//! **Clearance.** The signed distance from a ball centre to the nearest solid minus the
//! ball's radius, from the shapes' exact geometry (box, cylinder, capsule, half-space,
//! compound): negative means overlap. It does not use the engine's contacts, so it checks
//! them.

use super::build::BodyRole;
use crate::rules::{Contact, ContactWith};
use virtual_physics::algebra::Vec3;
use virtual_physics::pipeline::{BodyHandle, World};

/// The ball's state at the start of a step (body frame origin = centre), table frame.
#[derive(Debug, Clone, Copy)]
pub struct BallBefore {
    /// Centre, m.
    pub position: Vec3,
    /// Velocity, m/s.
    pub velocity: Vec3,
    /// Angular velocity, rad/s.
    pub spin: Vec3,
}

fn contact_with(role: BodyRole) -> Option<ContactWith> {
    match role {
        BodyRole::Field => Some(ContactWith::Field),
        BodyRole::Wall => Some(ContactWith::Wall),
        BodyRole::Man(rod) => Some(ContactWith::Man { rod }),
        BodyRole::Ball => None,
    }
}

/// The ball's contacts of the last step of `world`, for the ball `ball` of mass
/// `ball_mass_kg`; `roles` by body storage index, `handles` the bodies in that order. Order:
/// field, wall, rods by index.
pub fn ball_contacts(
    world: &World,
    roles: &[BodyRole],
    handles: &[BodyHandle],
    ball: BodyHandle,
    before: &BallBefore,
    ball_mass_kg: f64,
) -> Vec<Contact> {
    let mut out: Vec<Contact> = Vec::with_capacity(4);
    for m in world.contacts() {
        let (other, ball_is_b) = if m.b == ball {
            (m.a, true)
        } else if m.a == ball {
            (m.b, false)
        } else {
            continue;
        };
        let Some(other) = handles.iter().position(|&h| h == other) else {
            continue;
        };
        let impulse = m.max_normal_impulse();
        if impulse <= 0.0 {
            continue;
        }
        let Some(with) = roles.get(other).copied().and_then(contact_with) else {
            continue;
        };
        let speed = match with {
            ContactWith::Man { .. } => impulse / ball_mass_kg,
            ContactWith::Field | ContactWith::Wall => {
                let mut speed: f64 = 0.0;
                for (point, _) in m.points() {
                    let v = before.velocity + before.spin.cross(&(point - before.position));
                    // Normal from A to B; the ball approaches when it moves against it.
                    let along = if ball_is_b { v } else { -v };
                    speed = speed.max(-m.normal().dot(&along));
                }
                speed
            }
        };
        merge(
            &mut out,
            Contact {
                with,
                normal_speed_m_per_s: speed,
            },
        );
    }
    out
}

/// Adds contact `c` to `into`, one per thing touched (the faster speed wins); keeps the
/// order field, wall, rods by index.
fn merge(into: &mut Vec<Contact>, c: Contact) {
    match into.iter_mut().find(|x| x.with == c.with) {
        Some(x) => x.normal_speed_m_per_s = x.normal_speed_m_per_s.max(c.normal_speed_m_per_s),
        None => into.push(c),
    }
    let rank = |w: &ContactWith| match *w {
        ContactWith::Field => 0,
        ContactWith::Wall => 1,
        ContactWith::Man { rod } => 2 + rod,
    };
    into.sort_by_key(|c| rank(&c.with));
}

/// The smallest gap (m) between a ball of radius `radius_m` centred at `centre` and any
/// body but the one of index `ball`, and that body's role; `(+∞, Field)` for a world with
/// nothing else.
pub fn clearance(
    world: &World,
    roles: &[BodyRole],
    ball: usize,
    radius_m: f64,
    centre: &Vec3,
) -> (f64, BodyRole) {
    let mut best = (f64::INFINITY, BodyRole::Field);
    for (i, body) in world.bodies().enumerate() {
        if i == ball {
            continue;
        }
        let local = body.rotation().tr_mul(&(centre - body.position()));
        let gap = body.shape().signed_distance(&local) - radius_m;
        if gap < best.0 {
            best = (gap, roles.get(i).copied().unwrap_or(BodyRole::Wall));
        }
    }
    best
}

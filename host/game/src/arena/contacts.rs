//! The ball's contacts, as the rules want them, and its clearance to every solid.
//!
//! **Contacts.** After a step, every manifold between the ball and another body that
//! carried an impulse during the step (`max_normal_impulse > 0`, as
//! `World::impacts` counts them) is a contact; its speed is the relative velocity along
//! the contact normal *before* the step (ball velocity and spin from before the step, the
//! other body's velocity at the contact point: kinematic men move with the rod's slide
//! and spin, walls stand still), clamped at 0. One [`Contact`] per thing touched: the
//! field, the walls (all walls, ramps, goal boxes and the cover together), and each rod
//! (its bar and all its men), with the fastest of its points — so a man's body and leg
//! touching at once is one kick.
//!
//! **Clearance.** The signed distance from a ball centre to the nearest solid minus the
//! ball's radius, from the shapes' exact geometry (box, cylinder, half-space): negative
//! means overlap. It does not use the engine's contacts, so it checks them.

use super::build::BodyRole;
use crate::rules::{Contact, ContactWith};
use virtual_physics::geometry::V3;
use virtual_physics::pipeline::World;

/// The ball's state at the start of a step (body frame origin = centre), table frame.
#[derive(Debug, Clone, Copy)]
pub struct BallBefore {
    /// Centre, m.
    pub position: V3,
    /// Velocity, m/s.
    pub velocity: V3,
    /// Angular velocity, rad/s.
    pub spin: V3,
}

fn contact_with(role: BodyRole) -> Option<ContactWith> {
    match role {
        BodyRole::Field => Some(ContactWith::Field),
        BodyRole::Wall => Some(ContactWith::Wall),
        BodyRole::Rod(rod) | BodyRole::Man(rod) => Some(ContactWith::Man { rod }),
        BodyRole::Ball => None,
    }
}

/// The ball's contacts of the last step of `world`. Order: field, wall, rods by index.
pub fn ball_contacts(
    world: &World,
    roles: &[BodyRole],
    ball: usize,
    before: &BallBefore,
) -> Vec<Contact> {
    let b = &world.bodies;
    let mut field: Option<f64> = None;
    let mut wall: Option<f64> = None;
    let mut rods: Vec<(usize, f64)> = Vec::new();
    for m in world.manifolds() {
        let (a, bb) = (m.a as usize, m.b as usize);
        let (other, ball_is_b) = if bb == ball {
            (a, true)
        } else if a == ball {
            (bb, false)
        } else {
            continue;
        };
        if !m.points().iter().any(|p| p.max_normal_impulse > 0.0) {
            continue;
        }
        let Some(with) = roles.get(other).copied().and_then(contact_with) else {
            continue;
        };
        let mut speed: f64 = 0.0;
        for p in m.points() {
            let v_ball = before.velocity + before.spin.cross(&(p.point - before.position));
            let v_other = b.vel[other] + b.omega[other].cross(&(p.point - b.pos[other]));
            // Normal from A to B; approach = −n · (v_B − v_A).
            let rel = if ball_is_b {
                v_ball - v_other
            } else {
                v_other - v_ball
            };
            speed = speed.max(-m.normal.dot(&rel));
        }
        match with {
            ContactWith::Field => field = Some(field.map_or(speed, |s| s.max(speed))),
            ContactWith::Wall => wall = Some(wall.map_or(speed, |s| s.max(speed))),
            ContactWith::Man { rod } => match rods.iter_mut().find(|(r, _)| *r == rod) {
                Some((_, s)) => *s = s.max(speed),
                None => rods.push((rod, speed)),
            },
        }
    }
    rods.sort_by_key(|(r, _)| *r);
    let mut out = Vec::with_capacity(2 + rods.len());
    if let Some(s) = field {
        out.push(Contact {
            with: ContactWith::Field,
            normal_speed_m_per_s: s,
        });
    }
    if let Some(s) = wall {
        out.push(Contact {
            with: ContactWith::Wall,
            normal_speed_m_per_s: s,
        });
    }
    out.extend(rods.into_iter().map(|(rod, s)| Contact {
        with: ContactWith::Man { rod },
        normal_speed_m_per_s: s,
    }));
    out
}

/// Adds `new` contacts to `into`, one per thing touched (the faster speed wins); keeps
/// the order field, wall, rods by index.
pub fn merge(into: &mut Vec<Contact>, new: Vec<Contact>) {
    for c in new {
        match into.iter_mut().find(|x| x.with == c.with) {
            Some(x) => x.normal_speed_m_per_s = x.normal_speed_m_per_s.max(c.normal_speed_m_per_s),
            None => into.push(c),
        }
    }
    let rank = |w: &ContactWith| match *w {
        ContactWith::Field => 0,
        ContactWith::Wall => 1,
        ContactWith::Man { rod } => 2 + rod,
    };
    into.sort_by_key(|c| rank(&c.with));
}

/// Signed distance (m) from `point` (world) to the shape of body `i` (negative inside).
pub fn signed_distance(world: &World, i: usize, point: &V3) -> Option<f64> {
    let b = &world.bodies;
    let local = b.rot[i].tr_mul(&(point - b.pos[i]));
    Some(b.shape[i].signed_distance(&local))
}

/// The smallest gap (m) between a ball of body `ball` centred at `centre` and any other
/// body, and that body's role; `(+∞, Field)` for a world with nothing else.
pub fn clearance(world: &World, roles: &[BodyRole], ball: usize, centre: &V3) -> (f64, BodyRole) {
    let r = world.sphere_radius(ball).unwrap_or(0.0);
    let mut best = (f64::INFINITY, BodyRole::Field);
    for (i, role) in roles.iter().enumerate() {
        if i == ball {
            continue;
        }
        if let Some(d) = signed_distance(world, i, centre) {
            let gap = d - r;
            if gap < best.0 {
                best = (gap, *role);
            }
        }
    }
    best
}

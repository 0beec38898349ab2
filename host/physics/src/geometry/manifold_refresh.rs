//! Manifolds refreshed from the bodies' poses instead of collided again, while a pair of
//! boxes (or a box on a half-space) barely moves relative to each other, as in a resting
//! stack: the persistent-manifold shortcut of Bullet and Jolt.
//!
//! When a pair is collided, the manifold records where B lay in A's frame ([`PairPose`]) and
//! each point's anchors on both bodies and separation then. A later step whose relative pose
//! is still within [`MAX_RELATIVE_MOTION`] of the recorded one moves the anchors with their
//! bodies instead: each point is the midpoint of its two anchors and its separation changes by
//! their offset along the normal (which turns with A). The recorded pose, anchors and
//! separations stay those of the collision, so the error never accumulates past the bound, and
//! the pair is collided again as soon as it moves further.
//!
//! The bound: no point of B moves in A's frame by more than `‖R − R₀‖_F r_B + |p − p₀|`,
//! `r_B` B's bounding radius. While that is below a quarter of the speculative distance, a
//! feature that the collision left out (farther apart than that distance) cannot have come
//! into contact, so the refreshed manifold misses no point the collision would find, and the
//! points it keeps are off by at most the bound. The bound is a tenth of a millimetre (a
//! tenth of what the 40-box tower may move in 20 s), and a twentieth of the smaller box's
//! size for small boxes. Jolt's own tolerance, 1 mm, was measured too: the pyramid-1240's
//! boxes then creep 2.3 mm sideways in 5 s, against 0.5 mm when every pair is collided and
//! 0.7 mm at a tenth of a millimetre (`vphys bench pyramid-1240 --steps 300 --sleeping
//! false`).

use super::posed_part::PosedPart;
use super::{Manifold, Shape, M3, V3};

/// Largest motion (m) of any point of B relative to A for which a manifold is refreshed.
pub(crate) const MAX_RELATIVE_MOTION: f64 = 1e-4;

/// Where body B lay in body A's frame when a manifold's points were computed.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PairPose {
    /// B's rotation in A's frame, `R_Aᵀ R_B`.
    pub(crate) rot: M3,
    /// B's centre in A's frame (m), `R_Aᵀ (p_B − p_A)`.
    pub(crate) pos: V3,
    /// The normal in A's frame (unit).
    pub(crate) normal: V3,
}

/// The largest motion (m) a refresh may cover for the pair of shapes `a`, `b` and
/// speculative distance `speculative` (m); `None` for pairs that are always collided (only
/// boxes, and a box whose A is a half-space, are refreshed: a half-space as B would turn
/// its unbounded surface with it).
pub(crate) fn reach(a: &Shape, b: &Shape, speculative: f64) -> Option<f64> {
    let size = |s: &Shape| match *s {
        Shape::Cuboid { half } => Some(half.min()),
        _ => None,
    };
    let smallest = match a {
        Shape::HalfSpace { .. } => size(b)?,
        _ => size(a)?.min(size(b)?),
    };
    Some(
        MAX_RELATIVE_MOTION
            .min(0.25 * speculative)
            .min(0.05 * 2.0 * smallest),
    )
}

/// Records on a freshly collided manifold the pair's pose and each point's anchors.
pub(crate) fn record(m: &mut Manifold, a: &PosedPart<'_>, b: &PosedPart<'_>) {
    m.origin = Some(PairPose {
        rot: a.rot.tr_mul(&b.rot),
        pos: a.rot.tr_mul(&(b.pos - a.pos)),
        normal: a.rot.tr_mul(&m.normal),
    });
    for c in m.points[..m.len].iter_mut() {
        c.local_b = b.rot.tr_mul(&(c.point - b.pos));
        c.origin_separation = c.separation;
    }
}

/// `old` moved with its bodies, when the pair of poses lies within `reach` (m) of the pose
/// `old` was collided at; `None` when it must be collided again.
#[cfg(test)]
pub(crate) fn refresh(
    old: &Manifold,
    a: &PosedPart<'_>,
    b: &PosedPart<'_>,
    reach: f64,
) -> Option<Manifold> {
    let origin = within_reach(old, a, b, reach)?;
    let mut m = *old;
    move_points(&mut m, &origin, a, b);
    Some(m)
}

/// The pose `m` was collided at, when the pair of poses lies within `reach` (m) of it; `None`
/// when it must be collided again (or was never recorded).
pub(crate) fn within_reach(
    m: &Manifold,
    a: &PosedPart<'_>,
    b: &PosedPart<'_>,
    reach: f64,
) -> Option<PairPose> {
    let origin = m.origin?;
    let radius_b = b.shape.bounding_radius();
    let rot = a.rot.tr_mul(&b.rot);
    let pos = a.rot.tr_mul(&(b.pos - a.pos));
    let motion = (rot - origin.rot).norm() * radius_b + (pos - origin.pos).norm();
    if motion.is_nan() || motion > reach {
        return None;
    }
    Some(origin)
}

/// Moves `m`'s normal and points with the bodies from the pose `origin` it was collided at
/// ([`within_reach`]), in place.
pub(crate) fn move_points(
    m: &mut Manifold,
    origin: &PairPose,
    a: &PosedPart<'_>,
    b: &PosedPart<'_>,
) {
    m.normal = a.rot * origin.normal;
    for c in m.points[..m.len].iter_mut() {
        let on_a = a.rot * c.local_a + a.pos;
        let on_b = b.rot * c.local_b + b.pos;
        c.point = (on_a + on_b) * 0.5;
        c.separation = c.origin_separation + m.normal.dot(&(on_b - on_a));
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::box_box::{box_box, BoxPose};
    use nalgebra::{Rotation3, Vector3};

    fn cube() -> Shape {
        Shape::Cuboid {
            half: V3::new(0.5, 0.5, 0.5),
        }
    }

    /// Two unit cubes within 2 cm of each other.
    fn collide(ra: &M3, pa: &V3, rb: &M3, pb: &V3, m: &mut Manifold) -> bool {
        let half = V3::repeat(0.5);
        let a = BoxPose {
            r: ra,
            p: pa,
            half: &half,
        };
        let b = BoxPose {
            r: rb,
            p: pb,
            half: &half,
        };
        box_box(a, b, 0.02, m)
    }

    /// A unit cube resting on another, B moved by `shift` and turned by `turn` (rad) about
    /// the vertical after the manifold was recorded: the refreshed points and separations
    /// agree with a new collision to within the motion, and a larger motion is refused.
    #[test]
    fn a_refreshed_manifold_agrees_with_a_new_collision_within_the_motion() {
        let (ra, pa) = (M3::identity(), V3::zeros());
        let rb0 = M3::identity();
        let pb0 = V3::new(0.1, -0.05, 0.999);
        let mut m = Manifold::new(0, 1);
        assert!(collide(&ra, &pa, &rb0, &pb0, &mut m));
        assert_eq!(m.len, 4);
        for c in m.points[..m.len].iter_mut() {
            c.local_a = ra.tr_mul(&(c.point - pa));
        }
        let shape = cube();
        let posed = |rot: M3, pos: V3| PosedPart {
            index: 0,
            shape: &shape,
            rot,
            pos,
        };
        let (a, b0) = (posed(ra, pa), posed(rb0, pb0));
        record(&mut m, &a, &b0);
        let reach = reach(&cube(), &cube(), 0.02).unwrap();
        assert_eq!(reach, MAX_RELATIVE_MOTION);
        let radius = cube().bounding_radius();
        let turn = 2e-5;
        let rb: M3 = Rotation3::from_axis_angle(&Vector3::z_axis(), turn).into_inner();
        let pb = pb0 + V3::new(2e-5, 1e-5, -3e-5);
        let b = posed(rb, pb);
        let refreshed = refresh(&m, &a, &b, reach).expect("within reach");
        let mut fresh = Manifold::new(0, 1);
        assert!(collide(&ra, &pa, &rb, &pb, &mut fresh));
        let bound = (rb - rb0).norm() * radius + (pb - pb0).norm();
        for c in refreshed.points() {
            let nearest = fresh
                .points()
                .iter()
                .min_by(|p, q| {
                    (p.point - c.point)
                        .norm()
                        .total_cmp(&(q.point - c.point).norm())
                })
                .unwrap();
            assert!((nearest.point - c.point).norm() <= bound);
            assert!((nearest.separation - c.separation).abs() <= bound);
        }
        assert!((refreshed.normal - fresh.normal).norm() <= bound);
        let far = pb0 + V3::new(2.0 * MAX_RELATIVE_MOTION, 0.0, 0.0);
        assert!(refresh(&m, &a, &posed(rb0, far), reach).is_none());
        // A manifold that was never recorded is always collided again.
        let mut unrecorded = m;
        unrecorded.origin = None;
        assert!(refresh(&unrecorded, &a, &b, reach).is_none());
    }

    #[test]
    fn only_boxes_and_boxes_on_half_spaces_are_refreshed() {
        let plane = Shape::HalfSpace { normal: V3::z() };
        let ball = Shape::Sphere { radius: 0.1 };
        assert!(reach(&plane, &cube(), 0.02).is_some());
        assert!(reach(&cube(), &plane, 0.02).is_none());
        assert!(reach(&ball, &cube(), 0.02).is_none());
        // A small box takes a twentieth of its size; a small speculative distance a quarter.
        let small = Shape::Cuboid {
            half: V3::new(0.0005, 0.01, 0.01),
        };
        assert_eq!(reach(&small, &cube(), 0.02), Some(5e-5));
        assert_eq!(reach(&cube(), &cube(), 2e-4), Some(5e-5));
    }
}

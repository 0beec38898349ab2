//! The shapes and sizes the arena's parts share: the walls' thickness, the rods' radius,
//! the rotations a rod's turn and a lying cylinder take, a man's shapes. The world's
//! bodies (`build.rs`) and the rods' trees (`rods.rs`) are built from them.

use virtual_physics::algebra::{Mat3, Vec3};
use virtual_physics::geometry::Shape;

/// Wall thickness, m: thick against tunnelling (the ball moves at most ~2 cm per step).
pub const WALL_THICKNESS_M: f64 = 0.05;
/// Radius of the steel rods, m (16 mm rods).
pub const ROD_RADIUS_M: f64 = 0.008;

/// Rotation about `+y` by `angle` (rad): the rod's turn (0 = feet down).
pub fn rot_y(angle: f64) -> Mat3 {
    let (s, c) = virtual_physics::transcendental::sin_cos(angle);
    Mat3::new(c, 0.0, s, 0.0, 1.0, 0.0, -s, 0.0, c)
}

/// Rotation taking the body `z` axis to the table's `+y` (cylinders lie along body `z`).
pub fn z_to_y_rotation() -> Mat3 {
    Mat3::new(1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, -1.0, 0.0)
}

/// The character's two boxes ([`crate::table::CharacterParams::boxes`]: body, leg),
/// except that the leg's sole is rounded: the leg box stops `r` above the sole and a
/// capsule of radius `r = body_depth / 2` lying along the rod (`y`, as wide as the
/// foot) makes the sole, its bottom exactly at the foot reach. A foot that comes down
/// on the ball then squeezes it out sideways (the contact normal points from the
/// rounded sole to the ball's centre) instead of pressing it flat into the cloth, which
/// a flat kinematic sole does. The drawn men (square soles) differ only in the two
/// sole edges, by at most `r (1 − 1/√2)` ≈ 2 mm.
pub fn man_shapes(character: &crate::table::CharacterParams) -> Vec<(Shape, Vec3, Mat3)> {
    let [body, leg] = character.boxes();
    let r = 0.5 * character.body_depth_m;
    let sole_centre_z = -character.foot_reach_m + r;
    let leg_top = leg.centre[2] + leg.half_extents[2];
    let leg_half_z = 0.5 * (leg_top - sole_centre_z);
    vec![
        (
            Shape::Cuboid {
                half: Vec3::from(body.half_extents),
            },
            Vec3::from(body.centre),
            Mat3::identity(),
        ),
        (
            Shape::Cuboid {
                half: Vec3::new(leg.half_extents[0], leg.half_extents[1], leg_half_z),
            },
            Vec3::new(leg.centre[0], leg.centre[1], sole_centre_z + leg_half_z),
            Mat3::identity(),
        ),
        (
            Shape::Capsule {
                radius: r,
                half_height: (leg.half_extents[1] - r).max(0.0),
            },
            Vec3::new(leg.centre[0], leg.centre[1], sole_centre_z),
            z_to_y_rotation(),
        ),
    ]
}

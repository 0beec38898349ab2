//! A world at rest that keeps its decision on fewer substeps prepares the contacts it solves
//! four at a time straight into their lanes (`SolverVariants::lean_resting_contacts`): it
//! steps to the same bits as with every constraint kept whole.

use virtual_physics::algebra::Vec3;
use virtual_physics::dynamics::Material;
use virtual_physics::geometry::Shape;
use virtual_physics::pipeline::{BodyBuilder, Effect, World};
use virtual_physics::scene::builtin::pyramid;

/// The 5-layer pyramid, sleeping off, with rolling resistance declared and a cylinder standing
/// on the ground beside it (its contact, with rolling resistance, is solved one by one, and
/// kept whole).
fn pyramid_and_ball(lean: bool) -> World {
    let mut s = pyramid(5);
    s.effects.retain(|e| *e != Effect::Sleeping);
    s.effects.push(Effect::RollingResistance);
    let mut w = s.build().unwrap();
    w.variants_mut().lean_resting_contacts = lean;
    w.insert_body(
        BodyBuilder::dynamic(Shape::Cylinder {
            radius: 0.3,
            half_height: 0.3,
        })
        .mass(2.0)
        .material(Material {
            rolling_resistance: 0.05,
            ..Material::default()
        })
        .position(Vec3::new(8.0, 0.0, 0.3)),
    );
    w
}

/// Positions, rotations and velocities of every body, bit for bit.
fn state(w: &World) -> Vec<[f64; 18]> {
    w.bodies()
        .map(|b| {
            let mut x = [0.0; 18];
            let (p, r) = (b.position(), b.rotation());
            let (v, o) = (b.linear_velocity(), b.angular_velocity());
            x[..3].copy_from_slice(p.as_slice());
            x[3..12].copy_from_slice(r.as_slice());
            x[12..15].copy_from_slice(v.as_slice());
            x[15..18].copy_from_slice(o.as_slice());
            x
        })
        .collect()
}

#[test]
fn a_lean_step_gives_the_bits_of_a_full_one() {
    let (mut lean, mut full) = (pyramid_and_ball(true), pyramid_and_ball(false));
    let mut lean_steps = 0;
    for _ in 0..150 {
        lean.step().unwrap();
        full.step().unwrap();
        assert_eq!(full.counters().lean_contacts, 0);
        lean_steps += usize::from(lean.counters().lean_contacts > 0);
    }
    // The pyramid rests from its 31st step; the decision is taken again every 30 steps.
    assert!(lean_steps > 60, "{lean_steps} lean steps");
    assert_eq!(lean.counters().substeps, 2);
    assert_eq!(state(&lean), state(&full));
}

//! Narrow and broad phase: manifolds of the shape pairs, and the grid broad phase against a
//! brute-force pair search.

use nalgebra::Matrix3;
use std::borrow::Borrow;
use virtual_physics::algebra::exp_so3;
use virtual_physics::algebra::Vec3;

use virtual_physics::geometry::{collide, Manifold, Shape};

mod scene_order;
use scene_order::*;

fn cube(h: f64) -> Shape {
    Shape::Cuboid {
        half: Vec3::repeat(h),
    }
}

fn contact(
    sa: impl Borrow<Shape>,
    ra: Matrix3<f64>,
    pa: Vec3,
    sb: impl Borrow<Shape>,
    rb: Matrix3<f64>,
    pb: Vec3,
) -> Manifold {
    let mut m = Manifold::new(0, 1);
    let (sa, sb) = (sa.borrow(), sb.borrow());
    let hit = collide(sa, &ra, &pa, sb, &rb, &pb, 0.0, &mut m).expect("supported pair");
    assert_eq!(hit, !m.points().is_empty());
    m
}

#[test]
fn aligned_boxes_give_four_corner_points() {
    let i = Matrix3::identity();
    let m = contact(
        cube(0.5),
        i,
        Vec3::zeros(),
        cube(0.5),
        i,
        Vec3::new(0.1, 0.0, 0.99),
    );
    assert_eq!(m.points().len(), 4);
    assert!((m.normal - Vec3::z()).norm() < 1e-12);
    for p in m.points() {
        assert!((p.separation + 0.01).abs() < 1e-12);
        assert!((p.point.z - 0.495).abs() < 1e-12);
        assert!(p.point.x >= -0.4 - 1e-12 && p.point.x <= 0.5 + 1e-12);
    }
}

#[test]
fn rotated_box_on_box_reduces_octagon_to_four_points() {
    let i = Matrix3::identity();
    let r = exp_so3(&Vec3::new(0.0, 0.0, std::f64::consts::FRAC_PI_4));
    let m = contact(
        cube(0.5),
        i,
        Vec3::zeros(),
        cube(0.5),
        r,
        Vec3::new(0.0, 0.0, 0.98),
    );
    assert_eq!(m.points().len(), 4);
    assert!((m.normal - Vec3::z()).norm() < 1e-12);
    // The 4 kept points span the overlap in both directions.
    let xs: Vec<f64> = m.points().iter().map(|p| p.point.x).collect();
    let ys: Vec<f64> = m.points().iter().map(|p| p.point.y).collect();
    let span = |v: &[f64]| {
        v.iter().cloned().fold(f64::MIN, f64::max) - v.iter().cloned().fold(f64::MAX, f64::min)
    };
    assert!(span(&xs) > 0.5 && span(&ys) > 0.5, "{xs:?} {ys:?}");
}

#[test]
fn crossed_edges_give_one_point() {
    let ra = exp_so3(&Vec3::new(std::f64::consts::FRAC_PI_4, 0.0, 0.0));
    let rb = exp_so3(&Vec3::new(0.0, std::f64::consts::FRAC_PI_4, 0.0));
    let d = 2.0 * 0.5 * std::f64::consts::SQRT_2 - 0.02;
    let m = contact(
        cube(0.5),
        ra,
        Vec3::zeros(),
        cube(0.5),
        rb,
        Vec3::new(0.0, 0.0, d),
    );
    assert_eq!(m.points().len(), 1);
    assert!((m.normal - Vec3::z()).norm() < 1e-9, "{:?}", m.normal);
    assert!((m.points()[0].separation + 0.02).abs() < 1e-9);
}

#[test]
fn separated_boxes_give_nothing() {
    let i = Matrix3::identity();
    let m = contact(
        cube(0.5),
        i,
        Vec3::zeros(),
        cube(0.5),
        i,
        Vec3::new(0.0, 1.2, 0.0),
    );
    assert_eq!(m.points().len(), 0);
}

#[test]
fn spheres_capsules_cylinders_and_planes() {
    let i = Matrix3::identity();
    let plane = Shape::HalfSpace { normal: Vec3::z() };
    // Sphere on a box face and a box edge.
    let s = Shape::Sphere { radius: 0.1 };
    let m = contact(
        cube(0.5),
        i,
        Vec3::zeros(),
        &s,
        i,
        Vec3::new(0.2, 0.0, 0.59),
    );
    assert!(
        (m.normal - Vec3::z()).norm() < 1e-12 && (m.points()[0].separation + 0.01).abs() < 1e-12
    );
    let m = contact(
        cube(0.5),
        i,
        Vec3::zeros(),
        &s,
        i,
        Vec3::new(0.55, 0.0, 0.55),
    );
    let n = Vec3::new(1.0, 0.0, 1.0).normalize();
    assert!((m.normal - n).norm() < 1e-12);
    // Capsule lying on a plane: both ends.
    let cap = Shape::Capsule {
        radius: 0.05,
        half_height: 0.3,
    };
    let lying = exp_so3(&Vec3::new(0.0, std::f64::consts::FRAC_PI_2, 0.0));
    let m = contact(
        &plane,
        i,
        Vec3::zeros(),
        &cap,
        lying,
        Vec3::new(0.0, 0.0, 0.049),
    );
    assert_eq!(m.points().len(), 2);
    // Cylinder standing on a plane: a rim, reduced to 4 points; lying: a line of points.
    let cyl = Shape::Cylinder {
        radius: 0.1,
        half_height: 0.2,
    };
    let m = contact(
        &plane,
        i,
        Vec3::zeros(),
        &cyl,
        i,
        Vec3::new(0.0, 0.0, 0.199),
    );
    assert_eq!(m.points().len(), 4);
    let m = contact(
        &plane,
        i,
        Vec3::zeros(),
        &cyl,
        lying,
        Vec3::new(0.0, 0.0, 0.099),
    );
    assert!(m.points().len() >= 2);
    // Sphere against a cylinder side.
    let m = contact(&cyl, i, Vec3::zeros(), &s, i, Vec3::new(0.19, 0.0, 0.0));
    assert!(
        (m.normal - Vec3::x()).norm() < 1e-12 && (m.points()[0].separation + 0.01).abs() < 1e-12
    );
    // Capsule against capsule, crossed.
    let along_y = exp_so3(&Vec3::new(std::f64::consts::FRAC_PI_2, 0.0, 0.0));
    let m = contact(
        &cap,
        lying,
        Vec3::zeros(),
        &cap,
        along_y,
        Vec3::new(0.0, 0.0, 0.09),
    );
    assert_eq!(m.points().len(), 1);
    assert!((m.points()[0].separation + 0.01).abs() < 1e-12);
}

#[test]
fn cylinders_against_boxes_capsules_and_cylinders_by_probing() {
    use virtual_physics::pipeline::Effect;
    use virtual_physics::scene::builtin::{ground, unit_cube};
    use virtual_physics::scene::{BodyKindDesc, ShapeDesc};
    // A standing cylinder dropped on a fixed box, a box dropped across a lying cylinder (a
    // foosball man on a rod), a capsule and a cylinder on a lying cylinder: all come to rest on
    // top, nothing passes through.
    let mut s = virtual_physics::scene::builtin::towers(1, 1, 0);
    s.effects = vec![Effect::Gravity, Effect::Contacts, Effect::Friction];
    s.bodies = vec![ground(None)];
    let mut table = unit_cube([0.0, 0.0, 0.5]);
    table.kind = BodyKindDesc::Fixed;
    table.mass = None;
    s.bodies.push(table);
    let mut cyl = unit_cube([0.0, 0.0, 1.25]);
    cyl.shape = ShapeDesc::Cylinder {
        radius: 0.1,
        half_height: 0.2,
    };
    s.bodies.push(cyl);
    let lying = [0.0, std::f64::consts::FRAC_PI_2, 0.0];
    for (x, shape) in [
        (
            3.0,
            ShapeDesc::Box {
                half_extents: [0.05, 0.05, 0.05],
            },
        ),
        (
            6.0,
            ShapeDesc::Capsule {
                radius: 0.05,
                half_height: 0.1,
            },
        ),
        (
            9.0,
            ShapeDesc::Cylinder {
                radius: 0.05,
                half_height: 0.1,
            },
        ),
    ] {
        let mut rod = unit_cube([x, 0.0, 0.5]);
        rod.kind = BodyKindDesc::Fixed;
        rod.mass = None;
        rod.rotation = lying;
        rod.shape = ShapeDesc::Cylinder {
            radius: 0.1,
            half_height: 1.0,
        };
        s.bodies.push(rod);
        // Set down 1 cm above the rod: the probes balance a body on a round rod only near
        // the top (they agree with the deepest one within ~25°); one that lands off the top,
        // dropped from higher, rocks off.
        let mut b = unit_cube([x, 0.0, 0.66]);
        b.shape = shape;
        b.mass = Some(0.2);
        b.rotation = [std::f64::consts::FRAC_PI_2, 0.0, 0.0];
        s.bodies.push(b);
    }
    let mut w = s.build().unwrap();
    for _ in 0..120 {
        w.step().unwrap();
        assert_eq!(w.counters().unsupported_pairs, 0);
    }
    // Cylinder on the box top (z = 1): centre at 1.2.
    assert!(
        (body_at(&w, 2).position().z - 1.2).abs() < 0.01,
        "cylinder z {}",
        body_at(&w, 2).position().z
    );
    // Each small body rests on its rod (top of the rod at z = 0.6), not on the ground.
    for k in [4, 6, 8] {
        let z = body_at(&w, k).position().z;
        assert!(z > 0.62 && z < 0.72, "body {k} z {z}");
        assert!(
            body_at(&w, k).linear_velocity().norm() < 0.05,
            "body {k} still moving"
        );
    }
}

/// A box thinner than the contact margin, lying flat on a plane: the four corners of its
/// bottom face, never one of its top face (those would hold it up at one corner and rock it).
#[test]
fn a_box_thinner_than_the_margin_touches_a_plane_with_its_bottom_face() {
    let plane = Shape::HalfSpace { normal: Vec3::z() };
    let domino = Shape::Cuboid {
        half: Vec3::new(0.024, 0.012, 0.0045),
    };
    let i = Matrix3::identity();
    let mut m = Manifold::new(0, 1);
    let pos = Vec3::new(0.0, 0.0, 0.0045);
    collide(&plane, &i, &Vec3::zeros(), &domino, &i, &pos, 0.02, &mut m).expect("supported pair");
    assert_eq!(m.points().len(), 4);
    for p in m.points() {
        assert!(p.separation.abs() < 1e-12, "a top corner: {p:?}");
    }
}

/// A capsule lying across the top edge of a tall box: the contact holds the segment's point
/// deepest in the box, where neither end nor the point nearest the box's centre is.
#[test]
fn a_capsule_across_a_box_edge_touches_at_the_edge() {
    let step = cube(0.5);
    let cap = Shape::Capsule {
        radius: 0.03,
        half_height: 0.4,
    };
    // The capsule's axis along x (a quarter turn about y), descending 0.3 rad to +x, passes
    // 1 cm above the box's top edge at x = 0.5, z = 0.5: above the top face to the left of
    // the edge, beside the side face to its right. Neither end nor the point nearest the
    // box's centre touches.
    let r = exp_so3(&Vec3::new(0.0, std::f64::consts::FRAC_PI_2 + 0.3, 0.0));
    let up = Vec3::new(0.3f64.sin(), 0.0, 0.3f64.cos());
    let centre = Vec3::new(0.5, 0.0, 0.5) + up * 0.01;
    let mut m = Manifold::new(0, 1);
    let i = Matrix3::identity();
    collide(&step, &i, &Vec3::zeros(), &cap, &r, &centre, 0.0, &mut m).expect("supported pair");
    let deepest = m
        .points()
        .iter()
        .map(|p| p.separation)
        .fold(f64::INFINITY, f64::min);
    // The edge lies 1 cm from the axis on the capsule's side: 2 cm inside its surface.
    assert!((deepest + 0.02).abs() < 1e-6, "deepest {deepest}");
}

/// A capsule parallel to a box's side, as a rod's bar beside a wall piece: a gap just
/// beyond the margin gives no contact, one just within it a contact at that gap.
#[test]
fn a_capsule_beside_a_box_is_in_reach_only_within_the_margin() {
    let wall = cube(0.5);
    let cap = Shape::Capsule {
        radius: 0.008,
        half_height: 0.6,
    };
    // The bar along y (a quarter turn about x), its axis 0.5 + 0.008 + gap from the
    // box's centre along x: its surface `gap` from the side face.
    let r = exp_so3(&Vec3::new(std::f64::consts::FRAC_PI_2, 0.0, 0.0));
    let i = Matrix3::identity();
    let margin = 0.004;
    for (gap, touches) in [(margin * 1.001, false), (margin * 0.999, true)] {
        let centre = Vec3::new(0.5 + 0.008 + gap, 0.3, 0.2);
        let mut m = Manifold::new(0, 1);
        let hit = collide(&wall, &i, &Vec3::zeros(), &cap, &r, &centre, margin, &mut m)
            .expect("supported pair");
        assert_eq!(hit, touches, "gap {gap}");
        for p in m.points() {
            assert!((p.separation - gap).abs() < 1e-12, "gap {gap}: {p:?}");
        }
    }
}

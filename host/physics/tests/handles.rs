//! The world through handles: bodies keep their handles across inserting and removing other
//! bodies, a removed body's handle goes stale, its joints leave with it, and a world built
//! with the builders steps as one described in a scene.

use virtual_physics::algebra::Mat3;
use virtual_physics::algebra::{Inertia, Sym3, Vec3, SE3};
use virtual_physics::dynamics::BodyKind;
use virtual_physics::geometry::{Material, Shape};
use virtual_physics::model::{ArticulatedTree, Revolute};
use virtual_physics::pipeline::ArticulatedSystem;
use virtual_physics::pipeline::{BodyBuilder, Effect, Effects, World};

const G: f64 = 9.81;

fn effects() -> Effects {
    Effects::of(&[Effect::Gravity, Effect::Contacts, Effect::Friction])
}

fn cube(x: f64, z: f64) -> BodyBuilder {
    BodyBuilder::dynamic(Shape::Cuboid {
        half: Vec3::new(0.1, 0.1, 0.1),
    })
    .mass(1.0)
    .position(Vec3::new(x, 0.0, z))
}

/// Three boxes resting on the ground; removing the first moves the last into its storage
/// index. Every other handle still names its own body (by name and by position), the removed
/// handle is stale, and the rest keep resting: a box at rest on the ground at `z = 0.1` m
/// stays there to within the solver's steady-state sink (1 mm, the contact slop).
#[test]
fn handles_survive_removal_of_other_bodies() {
    let mut w = World::builder(effects()).build();
    let ground = w.insert_body(
        BodyBuilder::fixed(Shape::HalfSpace { normal: Vec3::z() })
            .name("ground")
            .material(Material::default()),
    );
    let a = w.insert_body(cube(0.0, 0.1).name("a"));
    let b = w.insert_body(cube(1.0, 0.1).name("b"));
    let c = w.insert_body(cube(2.0, 0.1).name("c"));
    for _ in 0..200 {
        w.step().unwrap();
    }
    assert!(w.remove_body(a));
    assert!(w.body(a).is_none(), "a removed body's handle is stale");
    assert!(!w.remove_body(a), "removing twice does nothing");
    let d = w.insert_body(cube(3.0, 0.1).name("d"));
    assert_ne!(d, a, "a new body never takes a removed body's handle");
    assert!(w.body(a).is_none());
    for _ in 0..500 {
        w.step().unwrap();
    }
    for (h, name, x) in [(b, "b", 1.0), (c, "c", 2.0), (d, "d", 3.0)] {
        let body = w.body(h).expect("live handle");
        assert_eq!(body.name(), name);
        assert_eq!(w.body_named(name), Some(h));
        let p = body.position();
        assert!((p.x - x).abs() < 1e-3, "{name} at x = {} m", p.x);
        assert!((p.z - 0.1).abs() < 1e-3, "{name} at z = {} m", p.z);
    }
    assert_eq!(w.body(ground).unwrap().kind(), BodyKind::Fixed);
    assert_eq!(w.body_count(), 4);
}

/// Setting state through a handle: a ball given 2 m/s upward rises `v²/2g` = 0.2039 m.
#[test]
fn set_velocity_through_a_handle() {
    let mut w = World::builder(Effects::of(&[Effect::Gravity])).build();
    let ball = w.insert_body(
        BodyBuilder::dynamic(Shape::Sphere { radius: 0.02 })
            .mass(0.03)
            .position(Vec3::zeros()),
    );
    w.body_mut(ball)
        .unwrap()
        .set_linear_velocity(Vec3::new(0.0, 0.0, 2.0));
    let mut top: f64 = 0.0;
    for _ in 0..400 {
        w.step().unwrap();
        top = top.max(w.body(ball).unwrap().position().z);
    }
    let expected = 2.0 * 2.0 / (2.0 * G);
    // Semi-implicit Euler at h = 1 ms undershoots the apex by at most v·h = 2 mm.
    assert!((top - expected).abs() < 2.0 * 1e-3, "apex {top} m");
}

/// A link with a shape is reached through its proxy body and back.
#[test]
fn a_link_and_its_proxy_body_name_each_other() {
    let mut w = World::builder(Effects::of(&[
        Effect::Gravity,
        Effect::Contacts,
        Effect::Articulated,
    ]))
    .build();
    let mut tree = ArticulatedTree::new(Vec3::new(0.0, 0.0, -G));
    let inertia = Inertia::from_com(
        1.0,
        Vec3::zeros(),
        Sym3::diagonal(&Vec3::new(0.01, 0.01, 0.01)),
    );
    tree.add_body(
        "arm",
        None,
        SE3::new(Mat3::identity(), Vec3::new(0.0, 0.0, 1.0)),
        Revolute::new(Vec3::y()),
        inertia,
    )
    .unwrap();
    let sys = ArticulatedSystem::new(tree, vec![0.0], vec![0.0]).with_link_shape(
        0,
        Shape::Sphere { radius: 0.05 },
        SE3::identity(),
        Material::default(),
    );
    let extra = w.insert_body(cube(5.0, 0.1));
    let t = w.insert_tree(sys);
    let link = t.link(0);
    let proxy = w
        .link_body(link)
        .expect("a link with a shape has a proxy body");
    assert_eq!(w.link_of(proxy), Some(link));
    assert_eq!(w.link_of(extra), None);
    assert!(!w.remove_body(proxy), "a link leaves only with its tree");
    assert!(w.remove_body(extra));
    assert_eq!(w.link_body(link), Some(proxy), "the proxy keeps its handle");
    assert_eq!(w.tree(t).unwrap().q().len(), 1);
}

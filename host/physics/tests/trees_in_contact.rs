//! Links of articulated trees in contact with free bodies, fixed geometry and links of other
//! trees, solved on the trees' generalised coordinates in the same passes as the free-body
//! contacts. Checked against physics: resting heights, and the analytic impulse of an
//! inelastic impact.

use std::f64::consts::FRAC_PI_2;
use virtual_physics::algebra::{exp_so3, Inertia, Sym3, Vec3, SE3};
use virtual_physics::dynamics::BodyKind;
use virtual_physics::geometry::{Material, Shape};
use virtual_physics::model::{ArticulatedTree, Free, Prismatic, Revolute};
use virtual_physics::pipeline::ArticulatedSystem;
use virtual_physics::pipeline::{BodyBuilder, BodyHandle, Effect, Effects, SolverSettings, World};

mod scene_order;
use scene_order::*;

const G: f64 = 9.81;

fn world(effects: &[Effect], dt: f64) -> World {
    World::builder(Effects::of(effects))
        .dt(dt)
        .gravity(Vec3::new(0.0, 0.0, -G))
        .build()
}

/// A world with the ground plane `z = 0` (a fixed half-space, default material).
fn with_ground(effects: &[Effect], dt: f64) -> (World, BodyHandle) {
    let mut w = world(effects, dt);
    let ground =
        w.insert_body(BodyBuilder::fixed(Shape::HalfSpace { normal: Vec3::z() }).name("ground"));
    (w, ground)
}

/// A solid box's inertia about its centre (kg·m²).
fn box_inertia(m: f64, half: Vec3) -> Sym3<f64> {
    let (x, y, z) = (
        4.0 * half.x * half.x,
        4.0 * half.y * half.y,
        4.0 * half.z * half.z,
    );
    Sym3::diagonal(&Vec3::new(
        m * (y + z) / 12.0,
        m * (x + z) / 12.0,
        m * (x + y) / 12.0,
    ))
}

/// A 20-link chain of capsules (each 0.1 m from joint to joint, radius 2 cm, 0.1 kg) on a
/// floating base, hinged about `y`, dropped flat from 0.3 m: it comes to rest on the ground
/// with no link more than 1 mm below it.
#[test]
fn a_twenty_link_chain_dropped_on_the_ground_rests_on_it() {
    let (n, len, radius, m) = (20, 0.1, 0.02, 0.1);
    let mut tree = ArticulatedTree::new(Vec3::new(0.0, 0.0, -G));
    let inertia = Inertia::from_com(
        m,
        Vec3::new(0.5 * len, 0.0, 0.0),
        box_inertia(m, Vec3::new(0.5 * len, radius, radius)),
    );
    for k in 0..n {
        let (parent, placement) = if k == 0 {
            (None, SE3::identity())
        } else {
            (Some(k - 1), SE3::from_translation(Vec3::new(len, 0.0, 0.0)))
        };
        let name = format!("link{k}");
        if k == 0 {
            tree.add_body(name, parent, placement, Free, inertia)
                .unwrap();
        } else {
            let hinge = Revolute::new(Vec3::y());
            tree.add_body(name, parent, placement, hinge, inertia)
                .unwrap();
        }
    }
    let mut q = tree.neutral_configuration();
    q[5] = 0.3; // the base 0.3 m up
    let nv = tree.nv();
    let capsule = Shape::Capsule {
        radius,
        half_height: 0.5 * len - radius,
    };
    // Along the link's x axis, centred between its joint and the next.
    let pose = SE3::new(
        exp_so3(&Vec3::new(0.0, FRAC_PI_2, 0.0)),
        Vec3::new(0.5 * len, 0.0, 0.0),
    );
    let mut sys = ArticulatedSystem::new(tree, q, vec![0.0; nv]);
    for k in 0..n {
        sys = sys.with_link_shape(k, capsule.clone(), pose, Material::default());
    }
    let effects = [
        Effect::Gravity,
        Effect::Contacts,
        Effect::Friction,
        Effect::Articulated,
    ];
    let (mut w, _) = with_ground(&effects, 1.0 / 60.0);
    w.insert_tree(sys);
    assert_eq!(
        w.body_count(),
        1 + n,
        "one proxy body per link with a shape"
    );
    let mut deepest: f64 = 0.0;
    for step in 0..240 {
        w.step().expect("finite");
        if step >= 60 {
            deepest = deepest.max(w.max_penetration());
        }
    }
    assert!(deepest <= 1e-3, "a link sank {deepest} m into the ground");
    // Every link lies on the ground (its capsule's lowest point within 1 mm of z = 0) …
    for i in 1..=n {
        let b = body_at(&w, i);
        let lowest = b.position().z + (b.rotation() * Vec3::new(0.5 * len, 0.0, 0.0)).z - radius;
        assert!(
            lowest.abs() <= 1e-3,
            "link {} lowest point at {lowest} m",
            i - 1
        );
    }
    // … at rest.
    let speed = tree_at(&w, 0)
        .qd()
        .iter()
        .map(|v| v * v)
        .sum::<f64>()
        .sqrt();
    assert!(speed < 1e-2, "|q̇| = {speed}");
}

/// A plate on a vertical slider (one tree) rests on the ground, and a box on a floating base
/// (another tree) rests on the plate: link on link.
#[test]
fn a_link_of_one_tree_rests_on_a_link_of_another() {
    let plate = Vec3::new(0.3, 0.3, 0.02);
    let cube = Vec3::new(0.05, 0.05, 0.05);
    let mut slider = ArticulatedTree::new(Vec3::new(0.0, 0.0, -G));
    let plate_inertia = Inertia::from_com(2.0, Vec3::zeros(), box_inertia(2.0, plate));
    slider
        .add_body(
            "plate",
            None,
            SE3::identity(),
            Prismatic::new(Vec3::z()),
            plate_inertia,
        )
        .unwrap();
    let plate_sys = ArticulatedSystem::new(slider, vec![0.05], vec![0.0]).with_link_shape(
        0,
        Shape::Cuboid { half: plate },
        SE3::identity(),
        Material::default(),
    );
    let mut floating = ArticulatedTree::new(Vec3::new(0.0, 0.0, -G));
    let cube_inertia = Inertia::from_com(1.0, Vec3::zeros(), box_inertia(1.0, cube));
    floating
        .add_body("cube", None, SE3::identity(), Free, cube_inertia)
        .unwrap();
    let mut q = floating.neutral_configuration();
    q[3] = 0.05;
    q[5] = 0.3;
    let cube_sys = ArticulatedSystem::new(floating, q, vec![0.0; 6]).with_link_shape(
        0,
        Shape::Cuboid { half: cube },
        SE3::identity(),
        Material::default(),
    );
    let effects = [
        Effect::Gravity,
        Effect::Contacts,
        Effect::Friction,
        Effect::Articulated,
    ];
    let (mut w, _) = with_ground(&effects, 1.0 / 60.0);
    w.insert_tree(plate_sys);
    w.insert_tree(cube_sys);
    for _ in 0..180 {
        w.step().expect("finite");
    }
    let (plate_z, cube_z) = (tree_at(&w, 0).q()[0], tree_at(&w, 1).q()[5]);
    assert!(
        (plate_z - plate.z).abs() < 1e-3,
        "plate centre at {plate_z} m"
    );
    assert!(
        (cube_z - (2.0 * plate.z + cube.z)).abs() < 1e-3,
        "cube centre at {cube_z} m, plate top at {} m",
        2.0 * plate.z
    );
    assert!(tree_at(&w, 0).qd()[0].abs() < 1e-2 && tree_at(&w, 1).qd()[5].abs() < 1e-2);
}

/// A pendulum (a 1 kg bob of radius 5 cm, 0.5 m below a hinge about `y`) swings through
/// the vertical into a 2 kg box at rest, without gravity, friction or restitution; the bob
/// meets the box's face at the height of its centre just as the pendulum is vertical. The
/// impulse the box receives is the analytic impulse of that inelastic impact,
/// `λ = L ω₀ / (1/M + L² / I_pivot)` (the line of the impulse passes through the box's centre),
/// and the pendulum loses `λ L` of angular momentum about its hinge.
#[test]
fn a_pendulum_strikes_a_free_box_with_the_analytic_impulse() {
    let (l, r, m): (f64, f64, f64) = (0.5, 0.05, 1.0);
    let pivot = Vec3::new(0.0, 0.0, 1.0);
    let mut tree = ArticulatedTree::new(Vec3::zeros());
    let bob = Inertia::from_com(
        m,
        Vec3::new(0.0, 0.0, -l),
        Sym3::diagonal(&Vec3::repeat(0.4 * m * r * r)),
    );
    tree.add_body(
        "pendulum",
        None,
        SE3::from_translation(pivot),
        Revolute::new(Vec3::y()),
        bob,
    )
    .unwrap();
    let i_pivot = m * l * l + 0.4 * m * r * r;
    // A positive rotation about y moves the bob towards −x at ω L = 1 m/s; it starts 12.3 mm
    // on the +x side of the vertical.
    let omega0 = 2.0;
    let theta0 = -(0.0123_f64 / l).asin();
    let frictionless = Material {
        friction: 0.0,
        ..Material::default()
    };
    let sys = ArticulatedSystem::new(tree, vec![theta0], vec![omega0]).with_link_shape(
        0,
        Shape::Sphere { radius: r },
        SE3::from_translation(Vec3::new(0.0, 0.0, -l)),
        frictionless,
    );
    let (big_m, half) = (2.0, Vec3::repeat(0.05));
    let mut w = world(&[Effect::Contacts, Effect::Articulated], 1e-3);
    let bx = w.insert_body(
        BodyBuilder::dynamic(Shape::Cuboid { half })
            .name("box")
            .material(frictionless)
            .mass(big_m)
            .position(Vec3::new(-(r + half.x), 0.0, pivot.z - l)),
    );
    w.insert_tree(sys);
    // The impact comes at 12.3 ms; run on past it while the pendulum swings away.
    for _ in 0..60 {
        w.step().expect("finite");
    }
    let lambda = l * omega0 / (1.0 / big_m + l * l / i_pivot);
    let received = big_m * w.body(bx).unwrap().linear_velocity().norm();
    assert!(
        ((received - lambda) / lambda).abs() < 1e-6,
        "box momentum {received} N·s, analytic impulse {lambda} N·s"
    );
    assert!(
        w.body(bx).unwrap().linear_velocity().x < 0.0,
        "the box is pushed towards −x"
    );
    let lost = i_pivot * (omega0 - tree_at(&w, 0).qd()[0]);
    assert!(
        ((lost - lambda * l) / (lambda * l)).abs() < 1e-6,
        "angular momentum lost {lost}, expected {}",
        lambda * l
    );
}

/// `scenes/chain-on-boxes.json`: a 10-link chain on ball joints falls onto a pile of twelve
/// boxes. Everything comes to rest with no overlap deeper than 1 cm (the soft contacts'
/// sink under the pile's weight is millimetres), and nothing is left moving fast.
#[test]
fn the_chain_on_boxes_scene_settles() {
    let path = format!("{}/scenes/chain-on-boxes.json", env!("CARGO_MANIFEST_DIR"));
    let scene = virtual_physics::scene::SceneFile::from_path(&path).expect("scene loads");
    let mut w = scene.build().expect("scene builds");
    assert_eq!(tree_at(&w, 0).link_poses().len(), 10);
    let mut deepest: f64 = 0.0;
    for _ in 0..240 {
        w.step().expect("finite");
        deepest = deepest.max(w.max_penetration());
    }
    assert!(deepest < 1e-2, "deepest overlap {deepest} m");
    let fastest = (0..w.body_count())
        .filter(|&i| body_at(&w, i).kind() == BodyKind::Dynamic)
        .map(|i| body_at(&w, i).linear_velocity().norm())
        .fold(0.0, f64::max);
    assert!(fastest < 0.05, "a box still moves at {fastest} m/s");
    // The chain lies on the pile or the ground: no link below the ground.
    for (i, p) in tree_at(&w, 0).link_poses().iter().enumerate() {
        assert!(p.p.z > 0.0, "link {i} at z = {} m", p.p.z);
    }
}

/// A 3-link arm hinged about `y` (links of 0.3, 0.3 and 0.2 m, 0.5 kg each, centres at
/// mid-length) holds its first two joints level with stiff servos, and its last servo, limited
/// to 2 N·m, turns the frictionless tip (a 2 cm sphere) down onto a 1 kg box on the ground. At
/// static equilibrium the last link is level on the box, so about its joint
/// `F · 0.2 m = τ_max + m₃ g · 0.1 m`, and the ground carries the box's weight plus `F`.
#[test]
fn an_arm_whose_motors_press_a_box_onto_the_ground_reaches_static_equilibrium() {
    use virtual_physics::pipeline::Motor;
    let (m_link, tau_max, m_box) = (0.5, 2.0, 1.0);
    let lengths = [0.3, 0.3, 0.2];
    let tip = 0.02;
    let half = Vec3::repeat(0.05);
    let mut tree = ArticulatedTree::new(Vec3::new(0.0, 0.0, -G));
    let base = Vec3::new(0.0, 0.0, 2.0 * half.z + tip);
    for (k, &len) in lengths.iter().enumerate() {
        let inertia = Inertia::from_com(
            m_link,
            Vec3::new(0.5 * len, 0.0, 0.0),
            box_inertia(m_link, Vec3::new(0.5 * len, 0.01, 0.01)),
        );
        let (parent, placement) = if k == 0 {
            (None, SE3::from_translation(base))
        } else {
            (
                Some(k - 1),
                SE3::from_translation(Vec3::new(lengths[k - 1], 0.0, 0.0)),
            )
        };
        tree.add_body(
            format!("link{k}"),
            parent,
            placement,
            Revolute::new(Vec3::y()),
            inertia,
        )
        .unwrap();
    }
    let hold = Motor {
        target_position: Some(0.0),
        target_velocity: 0.0,
        stiffness: 1e4,
        damping: 100.0,
        max_force: 1e3,
    };
    let press = Motor {
        target_position: Some(0.5),
        max_force: tau_max,
        ..hold
    };
    let frictionless = Material {
        friction: 0.0,
        ..Material::default()
    };
    let sys = ArticulatedSystem::new(tree, vec![0.0; 3], vec![0.0; 3])
        .with_motor(0, hold)
        .with_motor(1, hold)
        .with_motor(2, press)
        .with_link_shape(
            2,
            Shape::Sphere { radius: tip },
            SE3::from_translation(Vec3::new(lengths[2], 0.0, 0.0)),
            frictionless,
        );
    let effects = [
        Effect::Gravity,
        Effect::Contacts,
        Effect::Friction,
        Effect::Articulated,
    ];
    let dt = 1e-3;
    let (mut w, ground) = with_ground(&effects, dt);
    let reach: f64 = lengths.iter().sum();
    // Grips the ground; against the frictionless tip the pair has no friction.
    let bx = w.insert_body(
        BodyBuilder::dynamic(Shape::Cuboid { half })
            .name("box")
            .mass(m_box)
            .position(Vec3::new(reach, 0.0, half.z)),
    );
    w.insert_tree(sys);
    for _ in 0..1500 {
        w.step().expect("finite");
    }
    // Static: over the last half second the tip and the box move less than the contacts'
    // allowed overlap (0.1 mm, the linear slop), as the soft contacts finish settling.
    let tip_of = |w: &World| {
        let p = tree_at(w, 0).link_poses()[2];
        p.transform_point(&Vec3::new(lengths[2], 0.0, 0.0))
    };
    let tip_before = tip_of(&w);
    let box_before = w.body(bx).unwrap().position();
    for _ in 0..500 {
        w.step().expect("finite");
    }
    // Normal impulses are per substep: force = impulse / substep, which `force` divides.
    let h = dt / SolverSettings::default().substeps as f64;
    let force_on = |body: BodyHandle| -> f64 {
        let on = || w.contacts().filter(|c| c.a == ground && c.b == body);
        let force: f64 = on().map(|c| c.force()).sum();
        let impulse: f64 = on().map(|c| c.normal_impulse()).sum();
        assert!((force - impulse / h).abs() <= 1e-9 * force.abs());
        force
    };
    let push = (tau_max + m_link * G * 0.5 * lengths[2]) / lengths[2];
    let expected = m_box * G + push;
    let ground = force_on(bx);
    assert!(
        ((ground - expected) / expected).abs() < 0.01,
        "ground carries {ground} N, expected {expected} N (weight {} N + push {push} N)",
        m_box * G
    );
    let a = tree_at(&w, 0);
    let moved = (tip_of(&w) - tip_before).norm();
    assert!(moved < 1e-4, "the tip moved {moved} m in 0.5 s");
    let box_moved = w.body(bx).unwrap().position() - box_before;
    assert!(box_moved.norm() < 1e-4, "the box moved {box_moved:?}");
    // The last servo is at its limit, pressing.
    assert!((a.drive_force(2, dt) - tau_max).abs() < 1e-6 * tau_max);
}

/// An arm falling across stairs moves farther in a 1/60 s step than its contacts see, so
/// some of its steps are taken in parts: each step still ends exactly `dt` later, and its
/// counters add up to the scene's substeps and solver passes.
#[test]
fn a_fast_arm_on_stairs_steps_in_parts_that_add_up_to_the_step() {
    let scene = virtual_physics::scene::hard::arm_on_stairs(4, 0.3, 1.0, 0.2, 4);
    let mut w = scene.build().expect("arm on stairs");
    let (dt, substeps) = (w.dt(), w.settings().substeps);
    let (mut t, mut split) = (0.0, 0);
    for k in 1..=90 {
        w.step().expect("step");
        t += dt;
        assert_eq!(w.time(), t, "the clock after step {k}");
        let c = w.counters();
        assert_eq!(c.substeps, substeps, "substeps of step {k}");
        assert_eq!(c.solver_iterations, 2 * substeps, "passes of step {k}");
        assert!((1..=4).contains(&c.parts), "step {k} in {} parts", c.parts);
        split += usize::from(c.parts > 1);
    }
    assert!(split > 0, "no step of the falling arm was taken in parts");
}

/// Removing the stairs an arm lies on between steps (last step's contacts then name bodies
/// that are gone or moved) neither panics nor stops the arm's steps.
#[test]
fn the_stairs_removed_under_a_falling_arm_leave_it_stepping() {
    let scene = virtual_physics::scene::hard::arm_on_stairs(4, 0.3, 1.0, 0.2, 4);
    let mut w = scene.build().expect("arm on stairs");
    let mut split = false;
    while !split && w.time() < 3.0 {
        w.step().expect("step");
        split = w.counters().parts > 1;
    }
    assert!(split, "the arm never took a step in parts");
    let stairs: Vec<_> = w
        .bodies()
        .filter(|b| b.kind() == BodyKind::Fixed && b.shape().bounding_radius() > 0.0)
        .map(|b| b.handle())
        .collect();
    assert!(!stairs.is_empty());
    for h in stairs {
        assert!(w.remove_body(h), "a stair");
    }
    for _ in 0..30 {
        w.step().expect("step without the stairs");
    }
}

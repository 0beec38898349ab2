//! Compound bodies: several shapes in one body, with their poses and materials; mass
//! properties from the parts; resting and colliding as one rigid body.

use std::f64::consts::PI;
use virtual_physics::algebra::Vec3;
use virtual_physics::algebra::{exp_so3, SE3};
use virtual_physics::geometry::{Compound, Material, PartDesc, Shape};
use virtual_physics::scene::{BodyDesc, BodyKindDesc, PartShapeDesc, SceneFile, ShapeDesc};

fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs()
}

fn scene_path(name: &str) -> String {
    format!("{}/scenes/{name}", env!("CARGO_MANIFEST_DIR"))
}

/// The spinning top of `scenes/spinning-top.json`, computed by hand: a steel capsule stem
/// (radius 3 mm, core half-length 20 mm, centre at z = 23 mm) and a cylinder disk (radius
/// 35 mm, half-height 4 mm, centre at z = 30 mm), density 7800 kg/m³.
#[test]
fn disk_on_stem_mass_properties_match_a_hand_computation() {
    let rho = 7800.0;
    // Stem: a cylinder of length 2h plus two hemispheres (together one sphere).
    let (r, h, zs) = (0.003, 0.02, 0.023);
    let m_core = rho * PI * r * r * 2.0 * h;
    let m_caps = rho * 4.0 / 3.0 * PI * r * r * r;
    // Disk.
    let (rd, hd, zd) = (0.035, 0.004, 0.03);
    let m_disk = rho * PI * rd * rd * 2.0 * hd;
    let m = m_core + m_caps + m_disk;
    let zc = ((m_core + m_caps) * zs + m_disk * zd) / m;
    // About the stem axis.
    let izz = 0.5 * m_core * r * r + 0.4 * m_caps * r * r + 0.5 * m_disk * rd * rd;
    // About a horizontal axis through the centre of mass. Each hemisphere (mass m_caps/2):
    // 2/5 (m/2) r² about its flat face, centre of mass 3r/8 from the face, the face h from
    // the stem's centre: I = (m/2)(2/5 r² − (3r/8)²) + (m/2)(h + 3r/8)².
    let d = 3.0 * r / 8.0;
    let hemi = 0.5 * m_caps * (0.4 * r * r - d * d) + 0.5 * m_caps * (h + d) * (h + d);
    let ixx = m_core * (3.0 * r * r + 4.0 * h * h) / 12.0
        + 2.0 * hemi
        + (m_core + m_caps) * (zs - zc) * (zs - zc)
        + m_disk * (3.0 * rd * rd + 4.0 * hd * hd) / 12.0
        + m_disk * (zd - zc) * (zd - zc);

    let scene = SceneFile::from_path(&scene_path("spinning-top.json")).expect("scene loads");
    let world = scene.build().expect("scene builds");
    let top = world.body_named("top").expect("a body named top");
    let b = world.body(top).unwrap();
    let tol = 1e-12;
    assert!(rel(b.mass(), m) < tol, "mass {} vs {m}", b.mass());
    let i = b.principal_inertia();
    assert!(
        rel(i.x, ixx) < tol && rel(i.y, ixx) < tol,
        "Ixx {i:?} vs {ixx}"
    );
    assert!(rel(i.z, izz) < tol, "Izz {} vs {izz}", i.z);
    // The body frame sits at the centre of mass, on the (tilted) stem axis.
    let tilt = exp_so3(&Vec3::new(0.2, 0.0, 0.0));
    assert!((b.position() - tilt * Vec3::new(0.0, 0.0, zc)).norm() < 1e-15);
    assert!((b.rotation() - tilt).norm() < 1e-15);
}

/// A compound stated off its axes gets the same mass properties as `Inertia::xform` of the
/// whole: rotating the reference frame rotates the principal frame and nothing else.
#[test]
fn mass_properties_do_not_depend_on_the_reference_frame() {
    let parts = |t: SE3<f64>| {
        let bar = Shape::Cuboid {
            half: Vec3::new(0.3, 0.02, 0.05),
        };
        let ball = Shape::Sphere { radius: 0.08 };
        let mut p = vec![
            PartDesc {
                shape: bar,
                pose: SE3::identity(),
                mass: 1.5,
                material: Material::default(),
            },
            PartDesc {
                shape: ball,
                pose: SE3::new(
                    exp_so3(&Vec3::new(0.1, 0.4, -0.2)),
                    Vec3::new(0.3, 0.1, 0.0),
                ),
                mass: 0.7,
                material: Material::default(),
            },
        ];
        for q in &mut p {
            q.pose = t * q.pose;
        }
        p
    };
    let (_, a) = Compound::new(&parts(SE3::identity())).expect("valid");
    let t = SE3::new(
        exp_so3(&Vec3::new(-0.7, 0.2, 1.1)),
        Vec3::new(1.0, -2.0, 0.5),
    );
    let (_, b) = Compound::new(&parts(t)).expect("valid");
    let mut ma: Vec<f64> = a.principal_inertia.iter().copied().collect();
    let mut mb: Vec<f64> = b.principal_inertia.iter().copied().collect();
    ma.sort_by(f64::total_cmp);
    mb.sort_by(f64::total_cmp);
    for (x, y) in ma.iter().zip(&mb) {
        assert!(rel(*x, *y) < 1e-12, "{ma:?} vs {mb:?}");
    }
    let com_a = t.transform_point(&a.body_in_reference.p);
    assert!((com_a - b.body_in_reference.p).norm() < 1e-12);
}

fn part(shape: ShapeDesc, position: [f64; 3], material: Option<&str>) -> PartShapeDesc {
    PartShapeDesc {
        shape,
        position,
        rotation: [0.0; 3],
        mass: None,
        density: None,
        material: material.map(str::to_string),
    }
}

fn ground_scene(effects: &str, dt: f64) -> SceneFile {
    let mut s: SceneFile = serde_json::from_str(&format!(
        r#"{{"dt": {dt}, "effects": {effects},
            "materials": [{{"name": "dead", "restitution": 0.0}},
                          {{"name": "bouncy", "restitution": 0.9}}],
            "bodies": []}}"#
    ))
    .expect("test scene");
    s.bodies.push(virtual_physics::scene::builtin::ground(None));
    s
}

/// A table: a 0.6 × 0.4 × 0.04 m top on four 0.3 m legs (cylinders), one body. It stands on
/// its feet, and a box dropped on it comes to rest on the top.
#[test]
fn a_four_legged_table_stands_on_its_legs_and_carries_a_box() {
    let mut s = ground_scene(r#"["gravity", "contacts", "friction"]"#, 1.0 / 60.0);
    let leg = ShapeDesc::Cylinder {
        radius: 0.02,
        half_height: 0.15,
    };
    let mut parts = vec![part(
        ShapeDesc::Box {
            half_extents: [0.3, 0.2, 0.02],
        },
        [0.0, 0.0, 0.32],
        None,
    )];
    for (x, y) in [(0.25, 0.15), (-0.25, 0.15), (0.25, -0.15), (-0.25, -0.15)] {
        parts.push(part(leg.clone(), [x, y, 0.15], None));
    }
    s.bodies.push(BodyDesc {
        name: "table".into(),
        shape: ShapeDesc::Compound { parts },
        kind: BodyKindDesc::Dynamic,
        mass: None,
        density: Some(600.0),
        position: [0.0, 0.0, 0.01],
        rotation: [0.0; 3],
        velocity: [0.0; 3],
        angular_velocity: [0.0; 3],
        material: None,
    });
    let mut cargo = virtual_physics::scene::builtin::unit_cube([0.05, 0.0, 0.6]);
    cargo.shape = ShapeDesc::Box {
        half_extents: [0.05; 3],
    };
    cargo.mass = Some(2.0);
    cargo.density = None;
    cargo.name = "cargo".into();
    cargo.material = None;
    s.bodies.push(cargo);
    let mut w = s.build().expect("builds");
    let (table, cargo) = (
        w.body_named("table").unwrap(),
        w.body_named("cargo").unwrap(),
    );
    // Where the table's centre of mass rests: the body frame's height over the reference
    // frame's origin (the feet), from the build.
    let feet_to_com = w.body(table).unwrap().position().z - 0.01;
    for _ in 0..180 {
        w.step().expect("finite");
    }
    let (t, c) = (w.body(table).unwrap(), w.body(cargo).unwrap());
    // Feet on the ground: the centre of mass at its height over the feet, within 1 mm.
    assert!(
        (t.position().z - feet_to_com).abs() < 1e-3,
        "table centre of mass at {} m, expected {feet_to_com} m",
        t.position().z
    );
    // Level, and at rest.
    assert!(t.rotation().column(2).dot(&Vec3::z()) > 1.0 - 1e-6);
    assert!(t.linear_velocity().norm() < 1e-2 && c.linear_velocity().norm() < 1e-2);
    // The box rests on the top (top face at 0.34 m), not in it.
    assert!(
        (c.position().z - 0.39).abs() < 1e-3,
        "box centre at {} m, expected 0.39 m",
        c.position().z
    );
    // Four feet and one box–top contact: manifolds name the parts that touch.
    let parts_on_ground: Vec<u16> = w
        .contacts()
        .filter(|c| c.a != cargo && c.b == table)
        .map(|c| c.parts().1)
        .collect();
    assert_eq!(parts_on_ground.len(), 4, "{parts_on_ground:?}");
    assert!(parts_on_ground.iter().all(|&p| (1..=4).contains(&p)));
}

/// A dumbbell (two spheres on a bar) falls flat: one ball is bouncy, the other dead, so the
/// bouncy end comes back up and the dead end does not — each part contacts with its own
/// material.
#[test]
fn each_part_collides_with_its_own_material() {
    let mut s = ground_scene(
        r#"["gravity", "contacts", "friction", "restitution"]"#,
        1e-3,
    );
    let ball = ShapeDesc::Sphere { radius: 0.05 };
    let parts = vec![
        part(ball.clone(), [-0.3, 0.0, 0.0], Some("bouncy")),
        part(ball, [0.3, 0.0, 0.0], Some("dead")),
        part(
            ShapeDesc::Capsule {
                radius: 0.01,
                half_height: 0.25,
            },
            [0.0; 3],
            Some("dead"),
        ),
    ];
    let mut parts = parts;
    parts[2].rotation = [0.0, PI / 2.0, 0.0];
    s.bodies.push(BodyDesc {
        name: "dumbbell".into(),
        shape: ShapeDesc::Compound { parts },
        kind: BodyKindDesc::Dynamic,
        mass: Some(2.0),
        density: None,
        position: [0.0, 0.0, 0.3],
        rotation: [0.0; 3],
        velocity: [0.0; 3],
        angular_velocity: [0.0; 3],
        material: None,
    });
    let mut w = s.build().expect("builds");
    let d = w.body_named("dumbbell").unwrap();
    // It reaches the ground after √(2 · 0.25 m / g) = 0.226 s; look 34 ms later.
    let mut touched = false;
    for _ in 0..260 {
        w.step().expect("finite");
        touched |= w.max_penetration() > 0.0;
    }
    assert!(touched, "the dumbbell reached the ground");
    let b = w.body(d).unwrap();
    // Velocity of each ball's centre: v + ω × r.
    let end = |x: f64| b.point_velocity(&(b.position() + b.rotation() * Vec3::new(x, 0.0, 0.0)));
    let (bouncy, dead) = (end(-0.3), end(0.3));
    assert!(bouncy.z > 0.5, "the bouncy end rebounds: {bouncy:?}");
    assert!(
        bouncy.z > dead.z + 0.5,
        "bouncy end {bouncy:?}, dead end {dead:?}"
    );
}

//! Joints between free bodies stated by the model's joint types, with motors, limits and
//! armature on their coordinates, checked against statics, kinematics and the pendulum.

use std::f64::consts::{PI, TAU};
use virtual_physics::algebra::{Mat3, Vec3};
use virtual_physics::geometry::Shape;
use virtual_physics::model::{Ball, Cylindrical, Fixed, Prismatic, Revolute, Universal};
use virtual_physics::pipeline::{
    BodyBuilder, BodyHandle, Effect, Effects, JointBuilder, JointError, Motor, SolverSettings,
    World,
};

const G: f64 = 9.81;

fn world(dt: f64, gravity: bool) -> World {
    let mut effects = vec![Effect::Joints];
    if gravity {
        effects.push(Effect::Gravity);
    }
    World::builder(Effects::of(&effects))
        .dt(dt)
        .gravity(Vec3::new(0.0, 0.0, -G))
        .build()
}

/// A fixed body at the origin (the world side of a joint).
fn ground(w: &mut World) -> BodyHandle {
    w.insert_body(BodyBuilder::fixed(Shape::Sphere { radius: 0.01 }))
}

/// A sphere of `mass` kg and radius 2 cm centred at `p`.
fn ball(w: &mut World, mass: f64, p: Vec3) -> BodyHandle {
    w.insert_body(
        BodyBuilder::dynamic(Shape::Sphere { radius: 0.02 })
            .mass(mass)
            .position(p),
    )
}

/// A horizontal arm: 1 kg at 0.4 m along x from a hinge about y at the origin. Gravity's
/// torque about the hinge is `m g 0.4 = 3.924 N·m`, positive about +y.
fn arm_with_motor(max_force: f64) -> (World, BodyHandle, virtual_physics::pipeline::JointHandle) {
    let mut w = world(1e-3, true);
    let g = ground(&mut w);
    let b = ball(&mut w, 1.0, Vec3::new(0.4, 0.0, 0.0));
    let j = w
        .insert_joint(
            JointBuilder::new(&Revolute::new(Vec3::y()), g, b)
                .anchor(Vec3::zeros())
                .motor(
                    0,
                    Motor {
                        target_position: Some(0.0),
                        target_velocity: 0.0,
                        stiffness: 2000.0,
                        damping: 100.0,
                        max_force,
                    },
                ),
        )
        .unwrap();
    (w, b, j)
}

const LOAD: f64 = 1.0 * G * 0.4;

#[test]
fn a_torque_limited_position_motor_holds_a_load_below_its_limit() {
    let (mut w, _, j) = arm_with_motor(1.5 * LOAD);
    for _ in 0..3000 {
        w.step().unwrap();
    }
    let jr = w.joint(j).unwrap();
    let q = jr.position(0).unwrap();
    let tau = jr.motor_force(0).unwrap();
    // Static equilibrium: the motor's torque on the arm balances gravity's, and the PD
    // servo's deflection is load / stiffness.
    assert!(
        (tau + LOAD).abs() < 0.01 * LOAD,
        "motor torque {tau} N·m, load {LOAD}"
    );
    assert!(
        (q - LOAD / 2000.0).abs() < 0.1 * LOAD / 2000.0,
        "angle {q} rad, expected {}",
        LOAD / 2000.0
    );
    assert!(jr.gap() < 1e-3, "anchor gap {} m", jr.gap());
}

#[test]
fn a_torque_limited_position_motor_slips_above_its_limit() {
    let (mut w, _, j) = arm_with_motor(0.5 * LOAD);
    for _ in 0..300 {
        w.step().unwrap();
    }
    let jr = w.joint(j).unwrap();
    let tau = jr.motor_force(0).unwrap();
    // Gravity turns the arm about +y (down): the motor pushes back at its limit and slips.
    assert!(
        (tau + 0.5 * LOAD).abs() < 1e-9 * LOAD,
        "motor torque {tau} N·m, limit {}",
        0.5 * LOAD
    );
    let q = jr.position(0).unwrap();
    assert!(q > 0.3, "the arm should have fallen, angle {q} rad");
}

/// A 1 kg slider on a vertical prismatic joint falls 0.5 m onto its lower limit.
fn slider_onto_its_limit(dt: f64) {
    let mut w = world(dt, true);
    let g = ground(&mut w);
    let b = ball(&mut w, 1.0, Vec3::zeros());
    let j = w
        .insert_joint(
            JointBuilder::new(&Prismatic::new(Vec3::z()), g, b)
                .anchor(Vec3::zeros())
                .limits(0, -0.5, 0.5),
        )
        .unwrap();
    let steps = (2.0 / dt) as usize;
    let mut lowest = f64::INFINITY;
    for _ in 0..steps {
        w.step().unwrap();
        lowest = lowest.min(w.joint(j).unwrap().position(0).unwrap());
    }
    let jr = w.joint(j).unwrap();
    let q = jr.position(0).unwrap();
    assert!(lowest > -0.5 - 1e-3, "dt {dt}: overshot to {lowest} m");
    assert!((q + 0.5).abs() < 1e-3, "dt {dt}: rests at {q} m");
    let f = jr.limit_force(0).unwrap();
    assert!((f - G).abs() < 0.01 * G, "dt {dt}: limit carries {f} N");
    // The slide's constrained directions hold.
    assert!(jr.gap() < 1e-4 && jr.angular_gap() < 1e-4);
    let _ = b;
}

#[test]
fn a_prismatic_limit_stops_within_a_millimetre_at_1_khz() {
    slider_onto_its_limit(1e-3);
}

#[test]
fn a_prismatic_limit_stops_within_a_millimetre_at_60_hz() {
    slider_onto_its_limit(1.0 / 60.0);
}

#[test]
fn a_revolute_spun_a_thousand_turns_stays_aligned() {
    // No gravity. A velocity servo spins body B at 100 turns/s for 10 s about a hinge
    // through its centre, tilted from the world axes, on a kinematic body A that itself turns
    // at 1 rad/s about x (so the hinge's axis and anchor move all the time). The hinge's
    // angular error does not depend on the angle, so after 1000 turns the axes stay aligned
    // and the anchors together.
    let mut w = world(1e-3, false);
    let a = w.insert_body(
        BodyBuilder::kinematic(Shape::Cuboid {
            half: Vec3::new(0.1, 0.1, 0.1),
        })
        .angular_velocity(Vec3::new(1.0, 0.0, 0.0)),
    );
    let axis = Vec3::new(0.0, 0.3, 1.0).normalize();
    // B is a disk on the hinge (its symmetry axis, z, turned onto the hinge), so its world
    // inertia does not change as it turns.
    let r = virtual_physics::algebra::exp_so3(
        &(Vec3::z().cross(&axis).normalize() * Vec3::z().angle(&axis)),
    );
    let b = w.insert_body(
        BodyBuilder::dynamic(Shape::Cylinder {
            radius: 0.03,
            half_height: 0.01,
        })
        .mass(0.5)
        .position(Vec3::new(0.0, 0.0, 0.3))
        .rotation(r),
    );
    let rate = 100.0 * TAU;
    let j = w
        .insert_joint(
            JointBuilder::new(&Revolute::new(axis), a, b)
                .anchor(Vec3::new(0.0, 0.0, 0.3))
                .motor(
                    0,
                    Motor {
                        target_position: None,
                        target_velocity: rate,
                        stiffness: 0.0,
                        damping: 10.0,
                        max_force: 50.0,
                    },
                ),
        )
        .unwrap();
    let mut worst = (0.0f64, 0.0f64);
    for _ in 0..10_000 {
        w.step().unwrap();
        let jr = w.joint(j).unwrap();
        worst = (worst.0.max(jr.gap()), worst.1.max(jr.angular_gap()));
    }
    let jr = w.joint(j).unwrap();
    let turns = jr.position(0).unwrap() / TAU;
    // It reaches the target rate within a few milliseconds (servo damping 10 N·m·s/rad on
    // 2.3e-4 kg·m²): 1000 turns less a fraction of one.
    assert!((turns - 1000.0).abs() < 1.0, "{turns} turns");
    let now = jr.rate(0).unwrap();
    assert!((now - rate).abs() < 1e-3 * rate, "rate {now} rad/s");
    assert!(worst.0 < 1e-3, "anchor gap {} m", worst.0);
    assert!(worst.1 < 1e-3, "axis misalignment {} rad", worst.1);
}

#[test]
fn a_cylindrical_joint_slides_and_spins_freely() {
    // No gravity. Body B turns about and slides along a fixed axis that passes 3 cm from
    // its centre, so the joint holds it on a circle against the centrifugal load of its
    // spin (20 rad/s: 12 m/s² at the centre). Nothing drives the coordinates, so B's kinetic
    // energy, spin and slide rate are constant in the exact motion. The soft step allows an
    // error of the constrained directions (its 60 Hz spring under this load sits at
    // a / (2π 60)² ≈ 0.08 mm) and loses energy: each substep's solve lets go of the share
    // `s_i` (the softness' impulse scale) of the joint's accumulated impulse, so B's velocity
    // is turned by only part of the `ω h` its circle needs, and the relax pass removes the
    // rest as a velocity error along the rows, ½ m (s_i v ω h)² per substep and about as much
    // in the solve itself. The bound is twice that over the run, and energy never rises.
    let mut w = world(1e-3, false);
    let a = ground(&mut w);
    let b = w.insert_body(
        BodyBuilder::dynamic(Shape::Cuboid {
            half: Vec3::new(0.04, 0.04, 0.04),
        })
        .mass(1.0)
        .position(Vec3::new(0.03, 0.0, 0.3))
        .velocity(Vec3::new(0.0, 0.6, 0.2))
        .angular_velocity(Vec3::new(0.0, 0.0, 20.0)),
    );
    // B's initial velocity is the spin about the axis at its centre (ω × r = 20 ẑ × 0.03 x̂)
    // plus 0.2 m/s along it.
    let j = w
        .insert_joint(
            JointBuilder::new(&Cylindrical::new(Vec3::z()), a, b).anchor(Vec3::new(0.0, 0.0, 0.3)),
        )
        .unwrap();
    let e0 = w.energy();
    let mut worst = (0.0f64, 0.0f64, 0.0f64);
    for _ in 0..5000 {
        w.step().unwrap();
        let jr = w.joint(j).unwrap();
        worst = (
            worst.0.max(jr.gap()),
            worst.1.max(jr.angular_gap()),
            worst.2.max((e0 - w.energy()) / e0),
        );
    }
    let jr = w.joint(j).unwrap();
    let (angle, slide) = (jr.position(0).unwrap(), jr.position(1).unwrap());
    assert!(worst.0 < 1e-3, "gap {} m", worst.0);
    assert!(worst.1 < 1e-3, "misalignment {} rad", worst.1);
    let h = 1e-3 / SolverSettings::default().substeps as f64;
    let settings = SolverSettings::default();
    // The soft step's impulse scale (Box2D's soft constraint: a spring of the joint's
    // frequency and damping ratio over the substep).
    let hz = settings.joint_hertz.min(0.25 / h);
    let wh = TAU * hz * h;
    let s_i = 1.0 / (1.0 + wh * (2.0 * settings.joint_damping_ratio + wh));
    let (v, omega) = (0.6, 20.0);
    let bound = 2.0 * 0.5 * 1.0 * (s_i * v * omega * h).powi(2) * (5.0 / h) / e0;
    assert!(
        worst.2 < bound && w.energy() <= e0,
        "energy changed by {} of {e0} J (bound {bound})",
        worst.2
    );
    // 20 rad/s and 0.2 m/s for 5 s.
    // The spin and slide rates lose at most the share of the energy the bound allows.
    assert!(
        angle < 100.0 && angle > 100.0 * (1.0 - bound),
        "angle {angle} rad"
    );
    assert!((slide - 1.0).abs() < 1e-3, "slide {slide} m");
}

/// The period (s) of a pendulum: 1 kg at 0.5 m below a hinge about y, released at 0.05 rad,
/// with `armature` on the hinge; from the times of the angle's downward zero crossings.
fn pendulum_period(armature: f64) -> f64 {
    let dt = 1e-3;
    let mut w = world(dt, true);
    let g = ground(&mut w);
    let (l, th) = (0.5, 0.05f64);
    let b = ball(&mut w, 1.0, Vec3::new(0.0, 0.0, -l));
    let j = w
        .insert_joint(
            JointBuilder::new(&Revolute::new(Vec3::y()), g, b)
                .anchor(Vec3::zeros())
                .armature(0, armature),
        )
        .unwrap();
    // Swing it out by θ about the hinge (rotation about y) and let go.
    let r = virtual_physics::algebra::exp_so3(&Vec3::new(0.0, th, 0.0));
    w.body_mut(b)
        .unwrap()
        .set_position(r * Vec3::new(0.0, 0.0, -l))
        .set_rotation(r);
    let mut crossings = Vec::new();
    let mut prev = w.joint(j).unwrap().position(0).unwrap();
    for k in 0..20_000 {
        w.step().unwrap();
        let q = w.joint(j).unwrap().position(0).unwrap();
        if prev > 0.0 && q <= 0.0 {
            let t = (k as f64 + prev / (prev - q)) * dt;
            crossings.push(t);
        }
        prev = q;
    }
    assert!(crossings.len() >= 4, "{crossings:?}");
    (crossings[crossings.len() - 1] - crossings[0]) / (crossings.len() - 1) as f64
}

#[test]
fn armature_lengthens_a_pendulum_period_as_the_added_inertia_says() {
    let (m, l, r) = (1.0, 0.5, 0.02);
    let inertia = m * l * l + 0.4 * m * r * r;
    for armature in [0.0, 0.25, 1.0] {
        let expected = TAU * ((inertia + armature) / (m * G * l)).sqrt();
        let t = pendulum_period(armature);
        assert!(
            (t - expected).abs() < 0.01 * expected,
            "armature {armature} kg·m²: period {t} s, expected {expected} s"
        );
    }
}

/// Ten 0.1 m links on ball joints from a fixed anchor, 1 kg and `heavy` kg alternating,
/// released horizontal and swinging for 5 s at a step of `dt` seconds, default settings:
/// the largest joint gap (m) at any step.
fn swinging_chain_gap(heavy: f64, dt: f64) -> f64 {
    let mut w = world(dt, true);
    let g = ground(&mut w);
    let mut prev = g;
    let mut joints = Vec::new();
    for k in 0..10 {
        let mass = if k % 2 == 0 { 1.0 } else { heavy };
        let b = w.insert_body(
            BodyBuilder::dynamic(Shape::Sphere { radius: 0.03 })
                .mass(mass)
                .position(Vec3::new(0.1 * (k as f64 + 1.0), 0.0, 0.0)),
        );
        let anchor = Vec3::new(0.1 * k as f64, 0.0, 0.0);
        joints.push(
            w.insert_joint(JointBuilder::new(&Ball, prev, b).anchor(anchor))
                .unwrap(),
        );
        prev = b;
    }
    let mut worst = 0.0f64;
    for _ in 0..(5.0 / dt).round() as usize {
        w.step().unwrap();
        for &j in &joints {
            worst = worst.max(w.joint(j).unwrap().gap());
        }
    }
    worst
}

/// The joints form a forest (a chain from the still world), so they are solved as one
/// system and the mass ratio does not open them (one joint after another, 1:100 opened
/// 6 cm), at both of a game's steps. Printed: the largest gap per ratio and step
/// (`--nocapture`).
#[test]
fn chains_with_mass_ratios_to_1_to_10000_hang_together() {
    let game_steps = [1e-3, 1.0 / 60.0];
    for (heavy, dt) in [1.0, 1e3, 1e4]
        .into_iter()
        .flat_map(|m| game_steps.map(|dt| (m, dt)))
    {
        let worst = swinging_chain_gap(heavy, dt);
        eprintln!(
            "1:{heavy} at {:.1} ms: largest joint gap {:.4} mm",
            dt * 1e3,
            worst * 1e3
        );
        assert!(
            worst <= 1e-3,
            "1:{heavy} at {dt} s: largest joint gap {worst} m"
        );
    }
}

#[test]
fn a_universal_joint_keeps_its_cross_and_turns_both_ways() {
    // A universal joint passes rotation about the shaft (z) from A to B, while B may tilt
    // about the two cross axes. A is kinematic, turning at 5 rad/s about z.
    let mut w = world(1e-3, false);
    let a = w.insert_body(
        BodyBuilder::kinematic(Shape::Sphere { radius: 0.02 })
            .angular_velocity(Vec3::new(0.0, 0.0, 5.0)),
    );
    let b = ball(&mut w, 1.0, Vec3::new(0.0, 0.0, -0.2));
    let j = w
        .insert_joint(
            JointBuilder::new(&Universal::new(Vec3::x(), Vec3::y()), a, b)
                .anchor(Vec3::zeros())
                .limits(0, -0.2, 0.2)
                .limits(1, -0.2, 0.2),
        )
        .unwrap();
    for _ in 0..2000 {
        w.step().unwrap();
    }
    let jr = w.joint(j).unwrap();
    let spin = w.body(b).unwrap().angular_velocity().z;
    assert!((spin - 5.0).abs() < 1e-2, "B turns at {spin} rad/s");
    assert!(jr.gap() < 1e-3 && jr.angular_gap() < 1e-3);
}

#[test]
fn a_fixed_joint_welds_and_removing_it_frees_the_body() {
    let mut w = world(1e-3, true);
    let g = ground(&mut w);
    let b = ball(&mut w, 1.0, Vec3::new(0.2, 0.0, 0.0));
    let j = w
        .insert_joint(JointBuilder::new(&Fixed, g, b).anchor(Vec3::zeros()))
        .unwrap();
    for _ in 0..500 {
        w.step().unwrap();
    }
    let p = w.body(b).unwrap().position();
    assert!((p - Vec3::new(0.2, 0.0, 0.0)).norm() < 1e-3, "{p:?}");
    assert!(w.remove_joint(j));
    assert!(!w.remove_joint(j), "a removed joint's handle is stale");
    assert!(w.joint(j).is_none());
    for _ in 0..100 {
        w.step().unwrap();
    }
    assert!(w.body(b).unwrap().linear_velocity().z < -0.5);
}

#[test]
fn bad_joints_are_errors_that_name_the_problem() {
    let mut w = world(1e-3, true);
    let g = ground(&mut w);
    let b = ball(&mut w, 1.0, Vec3::zeros());
    let c = ball(&mut w, 1.0, Vec3::x());
    let rev = Revolute::new(Vec3::y());
    assert_eq!(
        w.insert_joint(JointBuilder::new(&rev, b, b)),
        Err(JointError::SameBody)
    );
    assert!(matches!(
        w.insert_joint(JointBuilder::new(&Revolute::new(Vec3::zeros()), g, b)),
        Err(JointError::Kind(_))
    ));
    assert_eq!(
        w.insert_joint(JointBuilder::new(&rev, g, b).axes(Mat3::identity() * 2.0)),
        Err(JointError::InvalidAxes)
    );
    assert!(matches!(
        w.insert_joint(JointBuilder::new(&rev, g, b).motor(
            1,
            Motor {
                target_position: None,
                target_velocity: 0.0,
                stiffness: 0.0,
                damping: 1.0,
                max_force: 1.0
            }
        )),
        Err(JointError::NoSuchDof { dof: 1, .. })
    ));
    assert!(matches!(
        w.insert_joint(JointBuilder::new(&Ball, g, b).armature(0, 1.0)),
        Err(JointError::NoSuchDof { dof: 0, .. })
    ));
    assert!(matches!(
        w.insert_joint(JointBuilder::new(&rev, g, b).limits(0, 1.0, -1.0)),
        Err(JointError::InvalidValue { .. })
    ));
    assert!(matches!(
        w.insert_joint(JointBuilder::new(&rev, g, b).armature(0, f64::NAN)),
        Err(JointError::InvalidValue { .. })
    ));
    // A removed body's handle is stale.
    assert!(w.remove_body(c));
    assert_eq!(
        w.insert_joint(JointBuilder::new(&rev, g, c)),
        Err(JointError::StaleBody(c))
    );
    assert_eq!(w.joint_count(), 0, "nothing was inserted");
    let msg = JointError::NoSuchDof {
        dof: 1,
        joint: "revolute",
        driven: 1,
    }
    .to_string();
    assert!(msg.contains("revolute") && msg.contains('1'), "{msg}");
    let _ = PI;
}

#[test]
fn a_motor_target_set_each_step_is_followed() {
    // A velocity servo on a hinge, its target changed from Rust every step.
    let mut w = world(1e-3, false);
    let g = ground(&mut w);
    let b = ball(&mut w, 1.0, Vec3::new(0.1, 0.0, 0.0));
    let j = w
        .insert_joint(JointBuilder::new(&Revolute::new(Vec3::z()), g, b).motor(
            0,
            Motor {
                target_position: None,
                target_velocity: 0.0,
                stiffness: 0.0,
                damping: 50.0,
                max_force: 100.0,
            },
        ))
        .unwrap();
    for k in 0..1000 {
        let target = 2.0 * (k as f64 * 1e-3);
        w.joint_mut(j)
            .unwrap()
            .set_motor_target(0, None, target)
            .unwrap();
        w.step().unwrap();
    }
    let rate = w.joint(j).unwrap().rate(0).unwrap();
    // The target ramps at 2 rad/s²; a damper of 50 N·m·s/rad on 0.01 kg·m² lags it by
    // (I / c) × 2 = 4e-4 rad/s.
    assert!((rate - 2.0).abs() < 0.01, "rate {rate} rad/s");
}

/// A scene with two boxes and `joint` (JSON) between them.
fn scene_with_joint(joint: &str) -> String {
    format!(
        r#"{{"effects": ["gravity", "joints"],
            "bodies": [
              {{"name": "base", "kind": "fixed", "shape": {{"type": "box", "half_extents": [0.1, 0.1, 0.1]}}}},
              {{"name": "slider", "shape": {{"type": "box", "half_extents": [0.05, 0.05, 0.05]}}, "mass": 1,
                "position": [0, 0, -0.3]}}
            ],
            "joints": [{joint}]}}"#
    )
}

#[test]
fn a_scene_states_joints_by_the_model_types_with_motors_limits_and_armature() {
    let text = scene_with_joint(
        r#"{"type": "cylindrical", "body1": "base", "body2": "slider", "anchor": [0, 0, -0.3],
            "axis": [0, 0, 1],
            "motors": [{"coordinate": 0, "target_velocity": 3, "damping": 5, "max_force": 10}],
            "limits": [{"coordinate": 1, "lower": -0.2, "upper": 0.2}],
            "armature": [0.001, 0]}"#,
    );
    let scene = virtual_physics::scene::SceneFile::from_json(&text).unwrap();
    let mut w = scene.build().unwrap();
    for _ in 0..120 {
        w.step().unwrap();
    }
    let j = w.joint_handles().next().unwrap();
    let jr = w.joint(j).unwrap();
    assert_eq!(jr.kind().type_name(), "cylindrical");
    // The slide falls onto its lower limit; the velocity servo turns it at 3 rad/s.
    assert!((jr.position(1).unwrap() + 0.2).abs() < 1e-3);
    assert!((jr.rate(0).unwrap() - 3.0).abs() < 1e-2);
    assert_eq!(jr.armature(0), Some(0.001));
    // Today's key, "kind", still reads.
    let old = scene_with_joint(
        r#"{"kind": "fixed", "body1": "base", "body2": "slider", "anchor": [0, 0, -0.2]}"#,
    );
    assert!(virtual_physics::scene::SceneFile::from_json(&old)
        .unwrap()
        .build()
        .is_ok());
}

#[test]
fn bad_scene_joints_are_reported_with_their_locations() {
    let text = scene_with_joint(
        r#"{"type": "universal", "body1": "base", "body2": "slider", "anchor": [0, 0, 0],
            "axis": [1, 0, 0],
            "motors": [{"coordinate": 2, "max_force": 1}, {"coordinate": 0, "max_force": -1}],
            "limits": [{"coordinate": 1, "lower": 1, "upper": -1, "restitution": 2}],
            "armature": [0, 0, 1]}"#,
    );
    let err = scene_error(&text, "an invalid joint");
    let msg = err;
    for needle in [
        "joints[0].axis2: a universal joint needs a second axis",
        "joints[0].motors[0].coordinate: a universal joint has 2 driven coordinate(s)",
        "joints[0].motors[1].max_force: must be within 0",
        "joints[0].limits[0].upper: must be at least lower",
        "joints[0].limits[0].restitution: must be within 0",
        "joints[0].armature: a universal joint has 2 driven coordinate(s), got 3",
    ] {
        assert!(msg.contains(needle), "missing '{needle}' in: {msg}");
    }
    let ball = scene_with_joint(
        r#"{"type": "ball", "body1": "base", "body2": "slider", "anchor": [0, 0, 0],
            "limits": [{"lower": 0, "upper": 1}]}"#,
    );
    let msg = scene_error(&ball, "a ball joint has no driven coordinates");
    assert!(
        msg.contains("joints[0].limits[0].coordinate: a ball joint has no driven coordinates"),
        "{msg}"
    );
    let unknown = scene_with_joint(
        r#"{"type": "screw", "body1": "base", "body2": "slider", "anchor": [0, 0, 0]}"#,
    );
    let msg = scene_error(&unknown, "an unknown type").to_string();
    assert!(
        msg.contains("joints[0].type: unknown joint type 'screw'"),
        "{msg}"
    );
}

/// The error a scene gives when read and built (it must give one).
fn scene_error(text: &str, why: &str) -> String {
    match virtual_physics::scene::SceneFile::from_json(text).and_then(|s| s.build()) {
        Err(e) => e.to_string(),
        Ok(_) => panic!("the scene loads: expected {why}"),
    }
}

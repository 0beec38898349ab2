//! The hard-case scenes: each at the engine's defaults (no solver settings, the default
//! integrator), stating only its time step, gravity and effects, as a user would write it.
//! `measure::hard` (feature `measure`) runs them with their bounds (`vphys hard`).
//!
//! * [`heavy_on_pyramid`] — a heavy unit cube dropped onto a stepped pyramid of 1 kg cubes.
//! * [`ball_in_box`] — a foosball-sized ball at tens of m/s in a closed box of 5 mm walls,
//!   restitution, no gravity, at 1/60 s with continuous collision.
//! * [`arm_on_stairs`] — a floating arm of revolute links (capsules) dropped across stairs.
//! * [`newtons_cradle`] — touching spheres in a row, restitution 1, the first one moving.
//! * [`dominoes`] — a row of dominoes, the first one tipped.

use super::builtin::{empty, ground};
use super::format::{
    ArticulatedDesc, BodyDesc, BodyKindDesc, LinkShapeDesc, MaterialDesc, SceneFile, ShapeDesc,
};
use crate::model::description::{
    BodyDescription, InertiaDescription, JointDescription, ModelDescription, PlacementDescription,
};
use crate::pipeline::Effect;

fn body(shape: ShapeDesc, kind: BodyKindDesc, mass: Option<f64>, position: [f64; 3]) -> BodyDesc {
    BodyDesc {
        name: String::new(),
        shape,
        kind,
        mass,
        density: None,
        position,
        rotation: [0.0; 3],
        velocity: [0.0; 3],
        angular_velocity: [0.0; 3],
        material: None,
    }
}

fn cube(half: f64, mass: f64, position: [f64; 3]) -> BodyDesc {
    let shape = ShapeDesc::Box {
        half_extents: [half; 3],
    };
    body(shape, BodyKindDesc::Dynamic, Some(mass), position)
}

fn fixed_box(name: String, half_extents: [f64; 3], position: [f64; 3]) -> BodyDesc {
    let shape = ShapeDesc::Box { half_extents };
    BodyDesc {
        name,
        ..body(shape, BodyKindDesc::Fixed, None, position)
    }
}

/// A cube of `mass` (kg) and 1 m side dropped `drop` (m) onto a stepped pyramid of `layers`
/// layers of 1 kg unit cubes (layers `n×n` … `1×1`); 3 s at 1/60 s.
pub fn heavy_on_pyramid(mass: f64, layers: usize, drop: f64) -> SceneFile {
    let mut s = empty(
        &format!("a {mass} kg cube dropped {drop} m onto a {layers}-layer pyramid of 1 kg cubes"),
        vec![Effect::Gravity, Effect::Contacts, Effect::Friction],
    );
    s.steps = Some(180);
    s.bodies.push(ground(None));
    for layer in 0..layers {
        let m = layers - layer;
        let o = (m as f64 - 1.0) * 0.5;
        for i in 0..m {
            for j in 0..m {
                let p = [i as f64 - o, j as f64 - o, 0.5 + layer as f64];
                s.bodies.push(cube(0.5, 1.0, p));
            }
        }
    }
    let mut heavy = cube(0.5, mass, [0.0, 0.0, layers as f64 + 0.5 + drop]);
    heavy.name = "heavy".into();
    s.bodies.push(heavy);
    s
}

/// The ball in [`ball_in_box`]: radius (m) and mass (kg).
pub const BOX_BALL: (f64, f64) = (0.0175, 0.027);

/// A closed cube of inner side `inner` (m) and 5 mm walls, no gravity, and a ball
/// ([`BOX_BALL`]) at its centre moving at `velocity` (m/s); friction 0 and `restitution`
/// on ball and walls; 1 s at step `dt` (s) with continuous collision.
pub fn ball_in_box(velocity: [f64; 3], inner: f64, restitution: f64, dt: f64) -> SceneFile {
    let speed = velocity.iter().map(|v| v * v).sum::<f64>().sqrt();
    let mut s = empty(
        &format!("a 35 mm ball at {speed:.0} m/s in a closed {inner} m box of 5 mm walls"),
        vec![
            Effect::Contacts,
            Effect::ContinuousCollision,
            Effect::Restitution,
        ],
    );
    s.dt = dt;
    s.steps = Some((1.0 / dt).round() as u64);
    s.gravity = [0.0; 3];
    s.materials.push(MaterialDesc {
        name: "bouncy".into(),
        friction: 0.0,
        restitution,
        rolling_resistance: 0.0,
    });
    let (radius, mass) = BOX_BALL;
    let mut ball = body(
        ShapeDesc::Sphere { radius },
        BodyKindDesc::Dynamic,
        Some(mass),
        [0.0; 3],
    );
    ball.name = "ball".into();
    ball.velocity = velocity;
    ball.material = Some("bouncy".into());
    s.bodies.push(ball);
    let wall = 0.005;
    let span = inner / 2.0 + wall;
    for axis in 0..3 {
        for sign in [-1.0, 1.0] {
            let mut half = [span; 3];
            half[axis] = wall / 2.0;
            let mut pos = [0.0; 3];
            pos[axis] = sign * (inner / 2.0 + wall / 2.0);
            let name = format!(
                "wall {}{}",
                ["x", "y", "z"][axis],
                if sign > 0.0 { '+' } else { '-' }
            );
            let mut w = fixed_box(name, half, pos);
            w.material = Some("bouncy".into());
            s.bodies.push(w);
        }
    }
    s
}

/// `n` unit directions spread over the sphere (a Fibonacci lattice), none along an axis.
pub fn spread_directions(n: usize) -> Vec<[f64; 3]> {
    let golden = std::f64::consts::PI * (3.0 - 5f64.sqrt());
    (0..n)
        .map(|i| {
            let z = 1.0 - (i as f64 + 0.5) * 2.0 / n as f64;
            let r = (1.0 - z * z).sqrt();
            let a = golden * i as f64;
            [r * a.cos(), r * a.sin(), z]
        })
        .collect()
}

/// A floating arm of `links` revolute links (about `y`), each `length` (m) and `mass` (kg), a
/// capsule of radius 3 cm along its `x`, lying along `x` `drop` (m) above the top of
/// `steps` stairs of `rise` (m) and 0.3 m run, and dropped onto them; 3 s at 1/60 s.
pub fn arm_on_stairs(links: usize, length: f64, mass: f64, rise: f64, steps: usize) -> SceneFile {
    let mut s = empty(
        &format!("a {links}-link revolute arm ({length} m, {mass} kg links) dropped onto stairs ({rise} m rise)"),
        vec![
            Effect::Gravity,
            Effect::Contacts,
            Effect::Friction,
            Effect::ContinuousCollision,
            Effect::Articulated,
        ],
    );
    s.steps = Some(180);
    s.bodies.push(ground(None));
    let run = 0.3;
    for k in 0..steps {
        let top = rise * (k + 1) as f64;
        let half = [run / 2.0, 0.5, top / 2.0];
        let name = format!("step {k}");
        s.bodies.push(fixed_box(
            name,
            half,
            [run * (k as f64 + 0.5), 0.0, top / 2.0],
        ));
    }
    let radius = 0.03;
    let (ix, iyz) = (
        0.5 * mass * radius * radius,
        mass * (3.0 * radius * radius + length * length) / 12.0,
    );
    let identity = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    let mut bodies = Vec::new();
    let mut shapes = Vec::new();
    for k in 0..links {
        let name = format!("link{k}");
        bodies.push(BodyDescription {
            name: name.clone(),
            parent: k.checked_sub(1),
            joint: if k == 0 {
                JointDescription::new("free")
            } else {
                JointDescription::with_axis("revolute", [0.0, 1.0, 0.0])
            },
            placement: PlacementDescription {
                rotation: identity,
                translation: [if k == 0 { 0.0 } else { length }, 0.0, 0.0],
            },
            inertia: InertiaDescription {
                mass,
                com: [length / 2.0, 0.0, 0.0],
                inertia_com: [ix, iyz, iyz, 0.0, 0.0, 0.0],
            },
        });
        shapes.push(LinkShapeDesc {
            link: name,
            shape: ShapeDesc::Capsule {
                radius,
                half_height: length / 2.0 - radius,
            },
            position: [length / 2.0, 0.0, 0.0],
            rotation: [0.0, std::f64::consts::FRAC_PI_2, 0.0],
            material: None,
        });
    }
    let mut q = vec![0.0, 0.0, 0.0, 0.05, 0.0, rise * steps as f64 + 0.3];
    q.resize(6 + links - 1, 0.0);
    s.articulated.push(ArticulatedDesc {
        model: ModelDescription {
            name: "arm".into(),
            gravity: [0.0; 3],
            bodies,
        },
        q: Some(q),
        qd: None,
        shapes,
        drives: Vec::new(),
    });
    s
}

/// `n` touching spheres of 5 cm radius and 1 kg in a row along `x`, restitution 1 and no
/// friction, no gravity; the first moves at `speed` (m/s) into the row; 1 s at 1/60 s.
pub fn newtons_cradle(n: usize, speed: f64) -> SceneFile {
    let mut s = empty(
        &format!(
            "a Newton's cradle: {n} touching spheres, restitution 1, the first at {speed} m/s"
        ),
        vec![Effect::Contacts, Effect::Restitution],
    );
    s.steps = Some(60);
    s.gravity = [0.0; 3];
    s.materials.push(MaterialDesc {
        name: "steel".into(),
        friction: 0.0,
        restitution: 1.0,
        rolling_resistance: 0.0,
    });
    let radius = 0.05;
    for i in 0..n {
        let shape = ShapeDesc::Sphere { radius };
        let mut b = body(
            shape,
            BodyKindDesc::Dynamic,
            Some(1.0),
            [2.0 * radius * i as f64, 0.0, 0.0],
        );
        b.name = format!("sphere {i}");
        b.material = Some("steel".into());
        if i == 0 {
            b.velocity = [speed, 0.0, 0.0];
        }
        s.bodies.push(b);
    }
    s
}

/// `n` dominoes of half extents `half` (m; thin along `x`) and a density of 1000 kg/m³,
/// `spacing` (m) apart along `x` on the ground; the first tipped towards the
/// others with its top moving at 1 m/s; `steps` steps at 1/60 s.
pub fn dominoes(n: usize, half: [f64; 3], spacing: f64, steps: u64) -> SceneFile {
    let mut s = empty(
        &format!("{n} dominoes falling in a row"),
        vec![Effect::Gravity, Effect::Contacts, Effect::Friction],
    );
    s.steps = Some(steps);
    s.bodies.push(ground(None));
    let mass = 1000.0 * 8.0 * half[0] * half[1] * half[2];
    for i in 0..n {
        let shape = ShapeDesc::Box { half_extents: half };
        let mut b = body(
            shape,
            BodyKindDesc::Dynamic,
            Some(mass),
            [spacing * i as f64, 0.0, half[2]],
        );
        if i == 0 {
            b.angular_velocity = [0.0, 1.0 / (2.0 * half[2]), 0.0];
        }
        s.bodies.push(b);
    }
    s
}

/// Unit cubes of `masses` (kg, bottom first) stacked exactly touching on the ground; 10 s at
/// 1/60 s.
pub fn mass_ratio_stack(masses: &[f64]) -> SceneFile {
    let list: Vec<String> = masses.iter().map(|m| format!("{m}")).collect();
    let mut s = empty(
        &format!("unit cubes of {} kg stacked, bottom first", list.join(", ")),
        vec![Effect::Gravity, Effect::Contacts, Effect::Friction],
    );
    s.bodies.push(ground(None));
    for (k, &m) in masses.iter().enumerate() {
        s.bodies.push(cube(0.5, m, [0.0, 0.0, 0.5 + k as f64]));
    }
    s
}

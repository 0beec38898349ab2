//! Built-in scenes, available by name (`vphys run towers-1120`).
//!
//! * `towers-1120` — an 8 × 7 grid of towers 2 m apart, each 20 unit cubes (1 kg, half extent
//!   0.5 m) starting exactly touching, on a fixed ground (half-space `z ≤ 0`), friction 0.5,
//!   step 1/60 s, 600 steps.
//! * `pyramid-1240` — a stepped square pyramid of the same cubes: layers 15×15, 14×14 … 1×1.
//! * `towers-80`, `pyramid-55` — reduced versions (2 × 2 towers; a 5-layer pyramid) for tests.
//! * `ball-roll` — a 35 mm foosball ball rolling at 1 m/s on cloth (rolling resistance).
//! * `ball-wall` — the same ball at 30 m/s towards a fixed 5 mm wall (continuous collision).

use super::format::{BodyDesc, BodyKindDesc, MaterialDesc, SceneFile, ShapeDesc, SolverDesc};
use super::SceneError;
use crate::pipeline::Effect;

/// Names of the built-in scenes.
pub const NAMES: [&str; 6] = [
    "towers-1120",
    "pyramid-1240",
    "towers-80",
    "pyramid-55",
    "ball-roll",
    "ball-wall",
];

/// A built-in scene by name.
pub fn by_name(name: &str) -> Result<SceneFile, SceneError> {
    Ok(match name {
        "towers-1120" => towers(8, 7, 20),
        "pyramid-1240" => pyramid(15),
        "towers-80" => towers(2, 2, 20),
        "pyramid-55" => pyramid(5),
        "ball-roll" => ball_roll(),
        "ball-wall" => ball_wall(1.0 / 60.0),
        _ => {
            return Err(SceneError::UnknownBuiltin(
                name.to_string(),
                NAMES.join(", "),
            ))
        }
    })
}

pub(super) fn empty(name: &str, effects: Vec<Effect>) -> SceneFile {
    SceneFile {
        name: name.to_string(),
        dt: 1.0 / 60.0,
        steps: Some(600),
        gravity: [0.0, 0.0, -9.81],
        effects,
        integrator: Default::default(),
        solver: SolverDesc::default(),
        damping: Default::default(),
        materials: Vec::new(),
        bodies: Vec::new(),
        joints: Vec::new(),
        articulated: Vec::new(),
    }
}

/// A fixed ground: the half-space `z ≤ 0`.
pub fn ground(material: Option<&str>) -> BodyDesc {
    BodyDesc {
        name: "ground".into(),
        shape: ShapeDesc::HalfSpace {
            normal: [0.0, 0.0, 1.0],
        },
        kind: BodyKindDesc::Fixed,
        mass: None,
        density: None,
        position: [0.0; 3],
        rotation: [0.0; 3],
        velocity: [0.0; 3],
        angular_velocity: [0.0; 3],
        material: material.map(str::to_string),
    }
}

/// A dynamic unit cube (1 kg, half extent 0.5 m) at `position`.
pub fn unit_cube(position: [f64; 3]) -> BodyDesc {
    BodyDesc {
        name: String::new(),
        shape: ShapeDesc::Box {
            half_extents: [0.5; 3],
        },
        kind: BodyKindDesc::Dynamic,
        mass: Some(1.0),
        density: None,
        position,
        rotation: [0.0; 3],
        velocity: [0.0; 3],
        angular_velocity: [0.0; 3],
        material: Some("box".into()),
    }
}

fn stacking(name: &str) -> SceneFile {
    let mut s = empty(
        name,
        vec![Effect::Gravity, Effect::Contacts, Effect::Friction],
    );
    s.materials.push(MaterialDesc {
        name: "box".into(),
        friction: 0.5,
        restitution: 0.0,
        rolling_resistance: 0.0,
    });
    s.bodies.push(ground(Some("box")));
    s
}

/// `nx × ny` towers of `h` unit cubes, 2 m apart, exactly touching, on the ground.
pub fn towers(nx: usize, ny: usize, h: usize) -> SceneFile {
    let mut s = stacking(&format!("towers-{}", nx * ny * h));
    let (ox, oy) = ((nx as f64 - 1.0), (ny as f64 - 1.0));
    for i in 0..nx {
        for j in 0..ny {
            for k in 0..h {
                s.bodies.push(unit_cube([
                    2.0 * i as f64 - ox,
                    2.0 * j as f64 - oy,
                    0.5 + k as f64,
                ]));
            }
        }
    }
    s
}

/// A stepped square pyramid: layers `n×n`, `(n−1)×(n−1)` … `1×1` of unit cubes.
pub fn pyramid(n: usize) -> SceneFile {
    let count: usize = (1..=n).map(|k| k * k).sum();
    let mut s = stacking(&format!("pyramid-{count}"));
    for layer in 0..n {
        let m = n - layer;
        let o = (m as f64 - 1.0) * 0.5;
        for i in 0..m {
            for j in 0..m {
                s.bodies
                    .push(unit_cube([i as f64 - o, j as f64 - o, 0.5 + layer as f64]));
            }
        }
    }
    s
}

/// Foosball ball: 35 mm diameter, 24 g.
pub fn ball(position: [f64; 3], velocity: [f64; 3]) -> BodyDesc {
    BodyDesc {
        name: "ball".into(),
        shape: ShapeDesc::Sphere { radius: 0.0175 },
        kind: BodyKindDesc::Dynamic,
        mass: Some(0.024),
        density: None,
        position,
        rotation: [0.0; 3],
        velocity,
        angular_velocity: [0.0; 3],
        material: Some("ball".into()),
    }
}

/// The ball rolling at 1 m/s on cloth.
pub fn ball_roll() -> SceneFile {
    let mut s = empty(
        "ball-roll",
        vec![
            Effect::Gravity,
            Effect::Contacts,
            Effect::Friction,
            Effect::RollingResistance,
        ],
    );
    s.steps = Some(600);
    s.materials.push(MaterialDesc {
        name: "cloth".into(),
        friction: 0.4,
        restitution: 0.0,
        rolling_resistance: 0.05,
    });
    s.materials.push(MaterialDesc {
        name: "ball".into(),
        friction: 0.4,
        restitution: 0.0,
        rolling_resistance: 0.0,
    });
    s.bodies.push(ground(Some("cloth")));
    let mut b = ball([0.0, 0.0, 0.0175], [1.0, 0.0, 0.0]);
    b.angular_velocity = [0.0, 1.0 / 0.0175, 0.0];
    s.bodies.push(b);
    s
}

/// The ball at 30 m/s towards a fixed wall 5 mm thick, 0.3 m away; no gravity.
pub fn ball_wall(dt: f64) -> SceneFile {
    let mut s = empty(
        "ball-wall",
        vec![
            Effect::Contacts,
            Effect::ContinuousCollision,
            Effect::Restitution,
        ],
    );
    s.dt = dt;
    s.steps = Some((0.1 / dt).ceil() as u64);
    s.materials.push(MaterialDesc {
        name: "ball".into(),
        friction: 0.3,
        restitution: 0.8,
        rolling_resistance: 0.0,
    });
    s.bodies.push(ball([0.0, 0.0, 0.1], [30.0, 0.0, 0.0]));
    s.bodies.push(BodyDesc {
        name: "wall".into(),
        shape: ShapeDesc::Box {
            half_extents: [0.0025, 0.3, 0.3],
        },
        kind: BodyKindDesc::Fixed,
        mass: None,
        density: None,
        position: [0.3, 0.0, 0.1],
        rotation: [0.0; 3],
        velocity: [0.0; 3],
        angular_velocity: [0.0; 3],
        material: Some("ball".into()),
    });
    s
}

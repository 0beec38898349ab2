//! The goal-mouth scene of `tests/goal_mouth.rs` and `benches/ccd.rs`: the game's standard
//! table around one goal (`host/game/tables/standard.toml` and the arena's walls). A goal
//! mouth 205 mm wide and 75 mm high in a 50 mm thick end wall at `x = 0.6 m`; the posts are
//! the end wall's boxes beside the mouth, the lintel above it, and a goal box 100 mm deep
//! behind it (sides, back, roof), all fixed boxes; the field is the half-space `z ≤ 0`. The
//! ball is 35 mm and 27 g. No gravity: a ball that touches nothing keeps its velocity exactly.
#![allow(dead_code)]
use virtual_physics::algebra::Vec3;
use virtual_physics::pipeline::World;
use virtual_physics::scene::SceneFile;

/// Ball radius (m) and mass (kg), the standard table's.
pub const R: f64 = 0.0175;
pub const MASS: f64 = 0.027;
/// Half the field length: the goal line (m).
pub const HL: f64 = 0.6;
/// Half the field width (m).
pub const HW: f64 = 0.35;
/// Half the goal width (m), its height and depth (m).
pub const GW: f64 = 0.1025;
pub const GH: f64 = 0.075;
pub const GD: f64 = 0.1;
/// The arena's wall thickness and the height of its walls (the cover) (m).
pub const T: f64 = 0.05;
pub const WH: f64 = 0.12;
/// One world step per millisecond.
pub const DT: f64 = 1e-3;

/// An axis-aligned box by its corners.
pub struct Wall {
    /// Body name.
    pub name: &'static str,
    /// Lower corner (m).
    pub min: Vec3,
    /// Upper corner (m).
    pub max: Vec3,
    /// Material name.
    pub material: &'static str,
}

pub fn walls() -> Vec<Wall> {
    let w = |name, min: [f64; 3], max: [f64; 3], material| Wall {
        name,
        min: Vec3::from(min),
        max: Vec3::from(max),
        material,
    };
    vec![
        w("post_left", [HL, GW, -T], [HL + T, HW + T, WH], "wall"),
        w("post_right", [HL, -HW - T, -T], [HL + T, -GW, WH], "wall"),
        w("lintel", [HL, -GW, GH], [HL + T, GW, WH], "wall"),
        w(
            "goal_left",
            [HL, GW, -T],
            [HL + GD + T, GW + T, GH + T],
            "goal",
        ),
        w(
            "goal_right",
            [HL, -GW - T, -T],
            [HL + GD + T, -GW, GH + T],
            "goal",
        ),
        w(
            "goal_back",
            [HL + GD, -GW - T, -T],
            [HL + GD + T, GW + T, GH + T],
            "goal",
        ),
        w(
            "goal_roof",
            [HL, -GW - T, GH],
            [HL + GD + T, GW + T, GH + T],
            "goal",
        ),
    ]
}

/// The goal-mouth scene as scene JSON, with the ball at `p` moving at `v`; `friction`
/// selects the friction effect (contacts, restitution and continuous collision always).
pub fn scene(p: Vec3, v: Vec3, friction: bool) -> World {
    let effects = if friction {
        r#"["contacts", "friction", "restitution", "continuous_collision"]"#
    } else {
        r#"["contacts", "restitution", "continuous_collision"]"#
    };
    scene_with(p, v, effects)
}

/// The goal-mouth scene with the effects `effects` (a JSON list of effect names).
pub fn scene_with(p: Vec3, v: Vec3, effects: &str) -> World {
    let mut bodies = vec![
        r#"{"name": "field", "kind": "fixed", "shape": {"type": "half_space", "normal": [0, 0, 1]}, "material": "cloth"}"#.to_string(),
    ];
    for w in walls() {
        let c = (w.min + w.max) * 0.5;
        let h = (w.max - w.min) * 0.5;
        bodies.push(format!(
            r#"{{"name": "{}", "kind": "fixed", "shape": {{"type": "box", "half_extents": [{}, {}, {}]}}, "position": [{}, {}, {}], "material": "{}"}}"#,
            w.name, h.x, h.y, h.z, c.x, c.y, c.z, w.material
        ));
    }
    bodies.push(format!(
        r#"{{"name": "ball", "shape": {{"type": "sphere", "radius": {R}}}, "mass": {MASS}, "position": [{}, {}, {}], "velocity": [{}, {}, {}], "material": "ball"}}"#,
        p.x, p.y, p.z, v.x, v.y, v.z
    ));
    let json = format!(
        r#"{{"name": "goal mouth", "dt": {DT}, "effects": {effects},
            "materials": [
              {{"name": "cloth", "friction": 0.4, "restitution": 0.3}},
              {{"name": "wall", "friction": 0.3, "restitution": 0.8}},
              {{"name": "goal", "friction": 0.3, "restitution": 0.1}},
              {{"name": "ball", "friction": 0.3, "restitution": 0.8}}
            ],
            "bodies": [{}]}}"#,
        bodies.join(",\n")
    );
    SceneFile::from_json(&json).unwrap().build().unwrap()
}

/// The ball's position and velocity.
pub fn ball(w: &World) -> (Vec3, Vec3) {
    let b = w.body(w.body_named("ball").unwrap()).unwrap();
    (b.position(), b.linear_velocity())
}

//! Bad scenes: every problem is reported with its location, and loading never panics.

use virtual_physics::scene::{SceneError, SceneFile};

const BOX: &str = r#"{"shape": {"type": "box", "half_extents": [0.5, 0.5, 0.5]}, "mass": 1}"#;

fn scene(effects: &str, bodies: &str, extra: &str) -> String {
    format!(r#"{{"effects": [{effects}], "bodies": [{bodies}] {extra}}}"#)
}

fn problems(text: &str) -> Vec<String> {
    match SceneFile::from_json(text) {
        Ok(_) => panic!("scene should be rejected:\n{text}"),
        Err(SceneError::Invalid(p)) => p.iter().map(|p| p.to_string()).collect(),
        Err(e) => vec![e.to_string()],
    }
}

fn has(ps: &[String], needle: &str) {
    assert!(
        ps.iter().any(|p| p.contains(needle)),
        "expected a problem containing {needle:?}, got {ps:#?}"
    );
}

#[test]
fn good_scene_loads_and_builds() {
    let s = SceneFile::from_json(&scene(r#""gravity", "contacts""#, BOX, "")).unwrap();
    assert!(s.build().is_ok());
}

#[test]
fn negative_mass() {
    let b = r#"{"shape": {"type": "sphere", "radius": 0.1}, "mass": -1}"#;
    let ps = problems(&scene(
        r#""gravity""#,
        &format!("{BOX}, {BOX}, {BOX}, {b}"),
        "",
    ));
    has(&ps, "bodies[3].mass: must be within 1e-6 … 1e6 kg, got -1");
}

#[test]
fn mass_and_density_missing_or_both() {
    let none = r#"{"shape": {"type": "sphere", "radius": 0.1}}"#;
    let both = r#"{"shape": {"type": "sphere", "radius": 0.1}, "mass": 1, "density": 2}"#;
    let ps = problems(&scene(r#""gravity""#, &format!("{none}, {both}"), ""));
    has(&ps, "bodies[0]: a dynamic body needs 'mass'");
    has(&ps, "bodies[1]: give either 'mass' or 'density'");
}

#[test]
fn bad_shape_dimensions() {
    let b = r#"{"shape": {"type": "box", "half_extents": [0.5, 0, -2]}, "density": 1000},
               {"shape": {"type": "capsule", "radius": -0.1, "half_height": 0.2}, "mass": 1}"#;
    let ps = problems(&scene("", b, ""));
    has(
        &ps,
        "bodies[0].shape.half_extents[1]: must be within 1e-4 … 1e4 m, got 0",
    );
    has(
        &ps,
        "bodies[0].shape.half_extents[2]: must be within 1e-4 … 1e4 m, got -2",
    );
    has(
        &ps,
        "bodies[1].shape.radius: must be within 1e-4 … 1e4 m, got -0.1",
    );
}

#[test]
fn dynamic_half_space() {
    let b = r#"{"shape": {"type": "half_space", "normal": [0, 0, 0]}, "mass": 1}"#;
    let ps = problems(&scene("", b, ""));
    has(&ps, "bodies[0].kind: a half-space is infinite");
    has(&ps, "bodies[0].shape.normal: must be a non-zero vector");
}

#[test]
fn unknown_material_and_bad_material_values() {
    let b = r#"{"shape": {"type": "sphere", "radius": 0.1}, "mass": 1, "material": "ice"}"#;
    let m = r#", "materials": [{"name": "felt", "friction": -0.2, "restitution": 1.5, "rolling_resistance": -1},
                              {"name": "felt"}]"#;
    let ps = problems(&scene("", b, m));
    has(&ps, "bodies[0].material: unknown material 'ice'");
    has(
        &ps,
        "materials[0].friction: must be within 0 … 10, got -0.2",
    );
    has(
        &ps,
        "materials[0].restitution: must be within 0 … 1, got 1.5",
    );
    has(&ps, "materials[0].rolling_resistance");
    has(
        &ps,
        "materials[1].name: 'felt' is already the name of materials[0]",
    );
}

#[test]
fn effect_requirements_and_duplicates() {
    let ps = problems(&scene(
        r#""friction", "restitution", "gravity", "gravity""#,
        BOX,
        "",
    ));
    has(&ps, "effects[0]: 'friction' requires the 'contacts' effect");
    has(
        &ps,
        "effects[1]: 'restitution' requires the 'contacts' effect",
    );
    has(
        &ps,
        "effects[3]: 'gravity' is already declared at effects[2]",
    );
}

#[test]
fn joints_with_unknown_bodies_and_missing_effect() {
    let b = r#"{"name": "rod", "shape": {"type": "box", "half_extents": [0.5, 0.01, 0.01]}, "kind": "kinematic"},
               {"name": "man", "shape": {"type": "box", "half_extents": [0.1, 0.1, 0.1]}, "mass": 1}"#;
    let j = r#", "joints": [{"type": "revolute", "body1": "rod", "body2": "woman", "anchor": [0, 0, 0]},
                           {"type": "hinge", "body1": "man", "body2": "man", "anchor": [0, 0, 0]}]"#;
    let ps = problems(&scene(r#""gravity""#, b, j));
    has(
        &ps,
        "joints: 2 joint(s) given but the 'joints' effect is not declared",
    );
    has(&ps, "joints[0].body2: unknown body 'woman'");
    has(&ps, "joints[0].axis: a revolute joint needs an axis");
    has(&ps, "joints[1].type: unknown joint type 'hinge'");
    has(&ps, "joints[1]: joins body 'man' to itself");
}

#[test]
fn articulated_unknown_parent_and_mass() {
    let model = r#"{"model": {"name": "arm", "gravity": [0, 0, -9.81], "bodies": [
        {"name": "a", "parent": null, "joint": {"type": "revolute", "axis": [1, 0, 0]},
         "placement": {"rotation": [[1,0,0],[0,1,0],[0,0,1]], "translation": [0,0,0]},
         "inertia": {"mass": 1, "com": [0,0,0.1], "inertia_com": [0.01,0.01,0.01,0,0,0]}},
        {"name": "b", "parent": 5, "joint": {"type": "revolute", "axis": [1, 0, 0]},
         "placement": {"rotation": [[1,0,0],[0,1,0],[0,0,1]], "translation": [0,0,0.2]},
         "inertia": {"mass": -3, "com": [0,0,0.1], "inertia_com": [0.01,0.01,0.01,0,0,0]}}]}}"#;
    let ps = problems(&format!(
        r#"{{"effects": ["articulated"], "articulated": [{model}]}}"#
    ));
    has(
        &ps,
        "articulated[0].model.bodies[1].parent: unknown parent 5",
    );
    has(
        &ps,
        "articulated[0].model.bodies[1].inertia.mass: must be within 1e-6 … 1e6 kg, got -3",
    );
}

#[test]
fn articulated_wrong_state_length() {
    let model = r#"{"model": {"name": "arm", "gravity": [0, 0, -9.81], "bodies": [
        {"name": "a", "parent": null, "joint": {"type": "revolute", "axis": [1, 0, 0]},
         "placement": {"rotation": [[1,0,0],[0,1,0],[0,0,1]], "translation": [0,0,0]},
         "inertia": {"mass": 1, "com": [0,0,0.1], "inertia_com": [0.01,0.01,0.01,0,0,0]}}]},
         "q": [0.1, 0.2], "qd": []}"#;
    let ps = problems(&format!(
        r#"{{"effects": ["articulated"], "articulated": [{model}]}}"#
    ));
    has(
        &ps,
        "articulated[0].q: has 2 values, the model has 1 coordinates",
    );
    has(
        &ps,
        "articulated[0].qd: has 0 values, the model has 1 velocities",
    );
}

#[test]
fn non_finite_values_in_a_built_scene() {
    // JSON has no NaN; scenes built in code are validated the same way.
    let mut s = virtual_physics::scene::builtin::towers(1, 1, 2);
    s.bodies[2].position[1] = f64::NAN;
    s.bodies[1].velocity[0] = f64::INFINITY;
    s.dt = 0.0;
    let ps: Vec<String> = s.problems().iter().map(|p| p.to_string()).collect();
    has(&ps, "bodies[2].position[1]: must be finite, got NaN");
    has(&ps, "bodies[1].velocity[0]: must be finite, got inf");
    has(&ps, "dt: must be within 1e-6 … 0.1 s, got 0");
    assert!(s.build().is_err());
}

#[test]
fn fixed_body_with_velocity_and_duplicate_names() {
    let b = r#"{"name": "w", "shape": {"type": "box", "half_extents": [1, 1, 1]}, "kind": "fixed", "velocity": [1, 0, 0]},
               {"name": "w", "shape": {"type": "sphere", "radius": 1}, "mass": 1}"#;
    let ps = problems(&scene(
        "",
        b,
        r#", "solver": {"substeps": 0, "contact_hertz": 30, "restitution_threshold": 1}"#,
    ));
    has(&ps, "bodies[0].velocity: a fixed body cannot move");
    has(&ps, "bodies[1].name: 'w' is already the name of bodies[0]");
    has(&ps, "solver.substeps: must be 1 … 64, got 0");
}

#[test]
fn syntax_unknown_fields_and_unknown_effects_name_the_place() {
    for (text, needle) in [
        (
            r#"{"effects": ["gravity"], "bodies": [{"shape": {"type": "box", "half_extents": [1,1,1]}, "mas": 1}]}"#,
            "unknown field `mas`",
        ),
        (
            r#"{"effects": ["gravity", "magnetism"]}"#,
            "unknown variant `magnetism`",
        ),
        (
            r#"{"effects": ["gravity"], "bodies": [{"shape": {"type": "torus"}}]}"#,
            "unknown variant `torus`",
        ),
        ("{\"effects\": [\n\"gravity\",\n]}", "line 3"),
        (r#"{"effects": ["gravity"], "dt": "fast"}"#, "invalid type"),
    ] {
        let e = SceneFile::from_json(text).unwrap_err();
        assert!(matches!(e, SceneError::Syntax(_)), "{e}");
        let m = e.to_string();
        assert!(m.contains(needle) && m.contains("line"), "{m}");
    }
}

#[test]
fn every_problem_is_reported_at_once() {
    let b = r#"{"shape": {"type": "sphere", "radius": -1}, "mass": -1, "material": "x"}"#;
    let ps = problems(&scene(r#""friction""#, b, r#", "dt": -1"#));
    assert!(ps.len() >= 5, "{ps:#?}");
    let msg = SceneFile::from_json(&scene(r#""friction""#, b, r#", "dt": -1"#))
        .unwrap_err()
        .to_string();
    assert!(
        msg.contains("problems in the scene: ")
            && !msg.contains('\n')
            && msg.contains("dt: must be within 1e-6 … 0.1 s, got -1"),
        "{msg}"
    );
}

#[test]
fn the_readme_example_scene_loads_and_runs() {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/example.json");
    let s = SceneFile::from_path(path).unwrap();
    let mut w = s.build().unwrap();
    for _ in 0..120 {
        w.step().unwrap();
    }
    let man = w.body_named("man").unwrap();
    let joint = w.joint_handles().next().unwrap();
    assert!(w.joint(joint).unwrap().gap() < 2e-3);
    assert!((w.body(man).unwrap().angular_velocity().x - 5.0).abs() < 0.2);
    let ball = w.body_named("ball").unwrap();
    assert!(
        w.body(ball).unwrap().linear_velocity().x < 1.0
            && w.body(ball).unwrap().linear_velocity().x > 0.0
    );
}

/// `n` unit boxes at `position(k)` on a ground plane, as scene text.
fn boxes_at(n: usize, position: impl Fn(usize) -> [f64; 3]) -> String {
    let ground = r#"{"kind": "fixed", "shape": {"type": "half_space", "normal": [0, 0, 1]}}"#;
    let mut bodies = vec![ground.to_string()];
    for k in 0..n {
        let [x, y, z] = position(k);
        bodies.push(format!(
            r#"{{"shape": {{"type": "box", "half_extents": [0.5, 0.5, 0.5]}}, "mass": 1, "position": [{x}, {y}, {z}]}}"#
        ));
    }
    scene(r#""gravity", "contacts""#, &bodies.join(","), "")
}

#[test]
fn bodies_placed_on_one_another_en_masse_are_refused_before_the_first_step() {
    // 2000 boxes at one point: 2 million pairs, whose contacts the first step would build.
    let s = SceneFile::from_json(&boxes_at(2000, |_| [0.0, 0.0, 0.5])).unwrap();
    match s.build() {
        Err(e @ SceneError::TooMany { .. }) => {
            let text = e.to_string();
            assert!(text.contains("overlapping bounding boxes"), "{text}");
        }
        Err(e) => panic!("another error: {e}"),
        Ok(_) => panic!("2000 boxes at one point were built"),
    }
    // The same boxes in a touching grid, ten layers of 200: a dense pile, built.
    let grid = |k: usize| {
        let (layer, i) = (k / 200, k % 200);
        [(i % 20) as f64, (i / 20) as f64, 0.5 + layer as f64]
    };
    let s = SceneFile::from_json(&boxes_at(2000, grid)).unwrap();
    assert!(s.build().is_ok());
}

#[test]
fn a_thousand_small_trees_at_one_point_are_refused_before_the_first_step() {
    // A new user's scene: one tree of the examples copied a thousand times, unmoved.
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/chain-on-boxes.json");
    let mut s = SceneFile::from_path(path).unwrap();
    let tree = s.articulated[0].clone();
    s.articulated = vec![tree; 1000];
    // Refused by counting pairs no further than the limit, before any contact is built
    // (`vphys run` on this scene took 26 s and 2.3 GB in its first step without the check).
    let result = s.build();
    assert!(
        matches!(result, Err(SceneError::TooMany { .. })),
        "{:?}",
        result.err()
    );
}

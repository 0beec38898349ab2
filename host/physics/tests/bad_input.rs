//! Input that once broke the engine (an abort on allocation, or a world that went NaN while
//! `step` said `Ok`) now gives a typed error that names the problem: scene files, scenes
//! built in code, and state set through the public API.

use std::io::Read;
use std::path::PathBuf;

use virtual_physics::scene::{SceneError, SceneFile};

mod scene_order;

fn bad_scenes() -> PathBuf {
    PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/tests/bad_scenes"))
}

/// Each file of `tests/bad_scenes/` and a part of the one-line message it must give.
const EXPECTED: &[(&str, &str)] = &[
    (
        "half-extent-1.6e19",
        "bodies[1].shape.half_extents[0]: must be within 1e-4 … 1e4 m, got 1.6e19",
    ),
    (
        "half-extents-1e30",
        "bodies[1].shape.half_extents[2]: must be within 1e-4 … 1e4 m, got 1e30",
    ),
    ("dt-1e300", "dt: must be within 1e-6 … 0.1 s, got 1e300"),
    ("dt-negative", "dt: must be within 1e-6 … 0.1 s, got -0.01"),
    (
        "gravity-1e300",
        "gravity[2]: must be within -1000 … 1000 m/s², got -1e300",
    ),
    (
        "rotation-1e300",
        "bodies[1].rotation[0]: must be within -1000 … 1000 rad, got 1e300",
    ),
    (
        "angular-velocity-1e300",
        "bodies[1].angular_velocity[1]: must be within -1e4 … 1e4 rad/s, got 1e300",
    ),
    (
        "velocity-1e300",
        "bodies[1].velocity[0]: must be within -1000 … 1000 m/s, got 1e300",
    ),
    (
        "position-1e300",
        "bodies[1].position[2]: must be within -1e5 … 1e5 m, got 1e300",
    ),
    (
        "mass-subnormal-5e-324",
        "bodies[1].mass: must be within 1e-6 … 1e6 kg, got 5e-324",
    ),
    (
        "mass-zero",
        "bodies[1].mass: must be within 1e-6 … 1e6 kg, got 0",
    ),
    (
        "mass-negative",
        "bodies[1].mass: must be within 1e-6 … 1e6 kg, got -1",
    ),
    (
        "mass-1e308",
        "bodies[1].mass: must be within 1e-6 … 1e6 kg, got 1e308",
    ),
    (
        "density-gives-huge-mass",
        "bodies[1].density: gives a mass of 8e11 kg (density × volume), outside 1e-6 … 1e6 kg",
    ),
    (
        "half-space-normal-1e300",
        "bodies[0].shape.normal: must be a non-zero vector of length 1e-6 … 1e6, got length 1e300",
    ),
    (
        "half-space-normal-zero",
        "bodies[0].shape.normal: must be a non-zero vector",
    ),
    (
        "sphere-radius-1e-30",
        "bodies[1].shape.radius: must be within 1e-4 … 1e4 m, got 1e-30",
    ),
    (
        "tree-bodies-over-limit",
        "articulated[0].model.bodies: at least 1001 bodies, more than the limit of 1000",
    ),
    (
        "bodies-over-limit",
        "bodies: at least 100001 bodies, more than the limit of 100000",
    ),
];

#[test]
fn every_bad_scene_file_gives_its_one_line_error() {
    let mut files: Vec<String> = std::fs::read_dir(bad_scenes())
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|x| x == "json"))
        .map(|p| p.file_stem().unwrap().to_string_lossy().into_owned())
        .collect();
    files.sort();
    let mut named: Vec<String> = EXPECTED.iter().map(|(f, _)| f.to_string()).collect();
    named.sort();
    assert_eq!(
        files, named,
        "every file in bad_scenes/ has its expected message"
    );
    for (file, needle) in EXPECTED {
        let path = bad_scenes().join(format!("{file}.json"));
        let e = SceneFile::from_path(path.to_str().unwrap())
            .expect_err(&format!("{file} must be rejected"));
        let m = e.to_string();
        assert!(m.contains(needle), "{file}: expected {needle:?} in {m:?}");
        assert!(!m.contains('\n'), "{file}: one line, got {m:?}");
    }
}

/// The text of a scene with `n` unit boxes, produced as it is read (never held whole).
struct Boxes {
    left: usize,
    pending: Vec<u8>,
    at: usize,
    done: bool,
    served: usize,
}

impl Boxes {
    fn new(n: usize) -> Self {
        Self {
            left: n,
            pending: br#"{"name": "boxes", "effects": ["gravity", "contacts"], "bodies": ["#
                .to_vec(),
            at: 0,
            done: false,
            served: 0,
        }
    }
}

impl Read for Boxes {
    fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
        if self.at == self.pending.len() {
            self.pending.clear();
            self.at = 0;
            if self.left > 0 {
                self.left -= 1;
                self.pending.extend_from_slice(
                    br#"{"shape": {"type": "box", "half_extents": [0.5, 0.5, 0.5]}, "mass": 1}"#,
                );
                if self.left > 0 {
                    self.pending.push(b',');
                }
            } else if !self.done {
                self.done = true;
                self.pending.extend_from_slice(b"]}");
            } else {
                return Ok(0);
            }
        }
        let n = buf.len().min(self.pending.len() - self.at);
        buf[..n].copy_from_slice(&self.pending[self.at..self.at + n]);
        self.at += n;
        self.served += n;
        Ok(n)
    }
}

#[test]
fn ten_million_boxes_are_refused_while_reading() {
    // 10⁷ boxes are about 710 MB of JSON: reading stops at the first box past the limit.
    let mut boxes = Boxes::new(10_000_000);
    let e = SceneFile::from_reader(&mut boxes).unwrap_err();
    match &e {
        SceneError::TooMany {
            path,
            at_least,
            limit,
            ..
        } => {
            assert_eq!(path, "bodies");
            assert_eq!((*at_least, *limit), (100_001, 100_000));
        }
        other => panic!("expected TooMany, got {other}"),
    }
    assert_eq!(
        e.to_string(),
        "bodies: at least 100001 bodies, more than the limit of 100000"
    );
    // What was read is the boxes up to the limit (71 bytes each) and one read buffer.
    assert!(boxes.served < 100_001 * 71 + 64 * 1024, "{}", boxes.served);
}

#[test]
fn compound_parts_count_as_shapes() {
    // One body whose compound has 10⁵ parts: with the compound itself, one shape over the
    // limit, refused while counting (before serde builds the parts).
    let parts = vec![r#"{"shape": {}}"#; 100_000].join(",");
    let text = format!(
        r#"{{"effects": [], "bodies": [{{"shape": {{"type": "compound", "parts": [{parts}]}}}}]}}"#
    );
    let e = SceneFile::from_json(&text).unwrap_err();
    assert_eq!(
        e.to_string(),
        "bodies: at least 100001 shapes, more than the limit of 100000"
    );
}

#[test]
fn a_scene_at_the_body_limit_is_read() {
    // The limit itself passes the count (and the scene parses and validates).
    let mut boxes = Boxes::new(1000);
    let s = SceneFile::from_reader(&mut boxes).unwrap();
    assert_eq!(s.bodies.len(), 1000);
}

#[test]
fn too_many_bodies_in_a_scene_built_in_code() {
    let mut s = virtual_physics::scene::builtin::towers(1, 1, 1);
    let body = s.bodies[1].clone();
    s.bodies.resize(100_001, body);
    let ps = s.problems();
    assert_eq!(ps.len(), 1, "{ps:?}");
    assert_eq!(
        ps[0].to_string(),
        "bodies: 100001 bodies, more than the limit of 100000"
    );
    assert!(s.build().is_err());
}

#[test]
fn a_file_larger_than_the_limit_is_refused_unread() {
    let dir = std::env::temp_dir().join(format!("vphys-bad-input-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("huge.json");
    // Sparse: no disk space, and the loader must not read it.
    let f = std::fs::File::create(&path).unwrap();
    f.set_len(65 << 20).unwrap();
    drop(f);
    let e = SceneFile::from_path(path.to_str().unwrap()).unwrap_err();
    std::fs::remove_dir_all(&dir).unwrap();
    assert!(
        matches!(
            e,
            SceneError::TooLarge {
                bytes: 68_157_440,
                limit: 67_108_864
            }
        ),
        "{e}"
    );
}

#[test]
fn an_endless_stream_is_cut_at_the_size_limit() {
    // One string that never ends.
    let text = std::io::Read::chain(&b"{\"name\": \""[..], std::io::repeat(b'a'));
    let e = SceneFile::from_reader(text).unwrap_err();
    assert!(matches!(e, SceneError::TooLarge { .. }), "{e}");
}

#[test]
fn huge_values_in_a_scene_built_in_code() {
    let mut s = virtual_physics::scene::builtin::towers(1, 1, 1);
    s.dt = 1e300;
    s.gravity = [0.0, 0.0, f64::NEG_INFINITY];
    s.bodies[1].angular_velocity = [1e300, 0.0, 0.0];
    let ps: Vec<String> = s.problems().iter().map(|p| p.to_string()).collect();
    assert!(ps.contains(&"dt: must be within 1e-6 … 0.1 s, got 1e300".to_string()));
    assert!(ps.contains(&"gravity[2]: must be finite, got -inf".to_string()));
    assert!(ps.contains(
        &"bodies[1].angular_velocity[0]: must be within -1e4 … 1e4 rad/s, got 1e300".to_string()
    ));
}

// ---------------------------------------------------------------------------------------
// The public API: state the step cannot use is refused before anything moves, and a step
// that goes non-finite is undone.

mod api {
    use super::scene_order::*;
    use virtual_physics::algebra::Vec3;
    use virtual_physics::dynamics::DynamicsError;
    use virtual_physics::geometry::Shape;
    use virtual_physics::pipeline::{BodyBuilder, Effect, World};

    /// A ground and a resting unit cube, stepped once (so the first bodies are checked).
    fn world() -> World {
        let mut w = virtual_physics::scene::builtin::towers(1, 1, 1)
            .build()
            .unwrap();
        w.step().unwrap();
        w
    }

    /// Adds a dynamic body through the API; returns its storage index (the step guard's
    /// errors name bodies by index and name).
    fn push(w: &mut World, shape: Shape, mass: f64) -> usize {
        w.insert_body(
            BodyBuilder::dynamic(shape)
                .name("probe")
                .mass(mass)
                .position(Vec3::new(3.0, 0.0, 1.0)),
        );
        w.body_count() - 1
    }

    fn cube() -> Shape {
        Shape::Cuboid {
            half: Vec3::repeat(0.5),
        }
    }

    /// The state `step` must leave untouched when it fails.
    fn state(w: &World) -> Vec<u64> {
        let mut s = vec![w.time().to_bits()];
        for b in w.bodies() {
            let vs = [b.position(), b.linear_velocity(), b.angular_velocity()];
            s.extend(vs.iter().flat_map(|v| v.iter()).map(|x| x.to_bits()));
            s.extend(b.rotation().iter().map(|x| x.to_bits()));
            s.push(b.is_awake() as u64);
        }
        s
    }

    /// `step` fails with an error on body `body` naming `what`, and changes nothing.
    fn refused(w: &mut World, body: usize, what: &str) {
        let before = state(w);
        let e = w.step().expect_err("the step must be refused");
        match &e {
            DynamicsError::InvalidBody {
                body: b, what: w, ..
            } => {
                assert_eq!((*b, *w), (body, what), "{e}")
            }
            other => panic!("expected InvalidBody, got {other}"),
        }
        assert_eq!(state(w), before, "a refused step changes nothing");
    }

    #[test]
    fn mass_zero_or_negative_is_refused() {
        for mass in [0.0, -1.0] {
            let mut w = world();
            let i = push(&mut w, cube(), mass);
            refused(&mut w, i, "inverse mass");
        }
    }

    #[test]
    fn mass_nan_infinite_or_subnormal_is_refused() {
        for mass in [f64::NAN, f64::INFINITY, 5e-324] {
            let mut w = world();
            let i = push(&mut w, cube(), mass);
            let e = w.step().unwrap_err();
            assert!(
                matches!(&e, DynamicsError::InvalidBody { body, .. } if *body == i),
                "mass {mass}: {e}"
            );
            assert!(e.to_string().contains("probe"), "{e}");
        }
    }

    #[test]
    fn non_finite_shape_size_is_refused() {
        let mut w = world();
        let i = push(
            &mut w,
            Shape::Sphere {
                radius: f64::INFINITY,
            },
            1.0,
        );
        // The inertia of an infinite sphere is infinite too: either names the body.
        assert!(matches!(
            w.step().unwrap_err(),
            DynamicsError::InvalidBody { body, .. } if body == i
        ));

        let mut w = world();
        let i = push(
            &mut w,
            Shape::Cuboid {
                half: Vec3::new(0.5, f64::NAN, 0.5),
            },
            1.0,
        );
        // A NaN size makes the inertia NaN too: either names the body.
        let before = state(&w);
        assert!(matches!(
            w.step().unwrap_err(),
            DynamicsError::InvalidBody { body, .. } if body == i
        ));
        assert_eq!(state(&w), before, "a refused step changes nothing");
    }

    #[test]
    fn bad_dt_and_gravity_are_refused() {
        for dt in [-0.01, 0.0, f64::NAN, f64::INFINITY, 1e300] {
            let mut w = world();
            w.set_dt(dt);
            let before = state(&w);
            let e = w.step().unwrap_err();
            assert!(
                matches!(&e, DynamicsError::InvalidParameter { what, .. } if what == "dt"),
                "dt {dt}: {e}"
            );
            assert_eq!(state(&w), before);
        }
        for g in [f64::NAN, f64::NEG_INFINITY, -1e300] {
            let mut w = world();
            w.set_gravity(Vec3::new(0.0, 0.0, g));
            let e = w.step().unwrap_err();
            assert!(
                matches!(&e, DynamicsError::InvalidParameter { what, .. } if what == "gravity[2]"),
                "gravity {g}: {e}"
            );
        }
    }

    #[test]
    fn huge_or_non_finite_pose_and_velocity_are_refused() {
        let mut w = world();
        body_at_mut(&mut w, 1).set_angular_velocity(Vec3::new(0.0, 1e300, 0.0));
        refused(&mut w, 1, "angular velocity");
        let mut w = world();
        body_at_mut(&mut w, 1).set_linear_velocity(Vec3::new(f64::NAN, 0.0, 0.0));
        refused(&mut w, 1, "velocity");
        let mut w = world();
        let p = body_at(&w, 1).position();
        body_at_mut(&mut w, 1).set_position(Vec3::new(p.x, p.y, 1e300));
        refused(&mut w, 1, "position");
        // The fixed ground too.
        let mut w = world();
        body_at_mut(&mut w, 0).set_linear_velocity(Vec3::new(0.0, 0.0, f64::NAN));
        refused(&mut w, 0, "velocity");
    }

    /// The world of [`world`], with sleeping, once its cube sleeps: its steps only advance
    /// the clock.
    fn asleep() -> World {
        let mut s = virtual_physics::scene::builtin::towers(1, 1, 1);
        s.effects.retain(|e| *e != Effect::Sleeping);
        s.effects.push(Effect::Sleeping);
        let mut w = s.build().unwrap();
        for _ in 0..600 {
            w.step().unwrap();
            if !body_at(&w, 1).is_awake() {
                return w;
            }
        }
        panic!("the resting cube never fell asleep in 10 s");
    }

    /// An all-asleep world's step checks less and keeps no snapshot, yet refuses what the
    /// full step refuses.
    #[test]
    fn an_all_asleep_world_still_refuses_bad_state() {
        let mut w = asleep();
        let (before, t) = (state(&w), w.time());
        w.step().unwrap();
        assert_eq!(w.time(), t + 1.0 / 60.0);
        assert_eq!(state(&w)[1..], before[1..], "only the clock moves");
        // The fixed ground cannot wake: its state is checked all the same.
        let p = body_at(&w, 0).position();
        body_at_mut(&mut w, 0).set_position(Vec3::new(p.x, p.y, 1e300));
        refused(&mut w, 0, "position");
        // A sleeping body set to NaN wakes, and the full check names it.
        let mut w = asleep();
        body_at_mut(&mut w, 1).set_linear_velocity(Vec3::new(f64::NAN, 0.0, 0.0));
        refused(&mut w, 1, "velocity");
    }

    #[test]
    fn a_step_that_goes_non_finite_returns_an_error_and_is_undone() {
        let mut w = world();
        for _ in 0..5 {
            w.step().unwrap();
        }
        // An infinite applied force is not a state the guard inspects before the step: the
        // step makes the cube's velocity non-finite.
        body_at_mut(&mut w, 1).set_force(Vec3::new(0.0, 0.0, f64::INFINITY));
        let before = state(&w);
        let e = w.step().unwrap_err();
        // The cube, not the ground its NaN impulse also reached.
        match &e {
            DynamicsError::NonFinite { body, quantity, .. } => {
                assert_eq!(*body, 1, "{e}");
                assert!(["position", "velocity"].contains(quantity), "{e}");
            }
            other => panic!("expected NonFinite, got {other}"),
        }
        assert_eq!(state(&w), before, "the world is as it was before the step");
        // With the force removed the world steps on, and stays at rest on the ground.
        body_at_mut(&mut w, 1).set_force(Vec3::zeros());
        for _ in 0..60 {
            w.step().unwrap();
        }
        assert!(
            (body_at(&w, 1).position().z - 0.5).abs() < 0.01,
            "{}",
            body_at(&w, 1).position()
        );
    }

    #[test]
    fn huge_boxes_step_in_bounded_memory() {
        // A 1.6e19 m half-extent once wrapped the broad phase's cell count and its loop
        // over cells allocated until the process aborted; 1e30 made the world NaN.
        for half in [
            Vec3::new(1.6e19, 0.5, 0.5),
            Vec3::new(1.6e19, 1.6e19, 0.5),
            Vec3::repeat(1e30),
        ] {
            let mut w = world();
            let i = push(&mut w, Shape::Cuboid { half }, 1.0);
            for _ in 0..10 {
                let before = state(&w);
                match w.step() {
                    Ok(()) => {
                        // Ok means a finite state.
                        for (j, b) in w.bodies().enumerate() {
                            assert!(
                                b.position()
                                    .iter()
                                    .chain(b.linear_velocity().iter())
                                    .all(|x| x.is_finite()),
                                "half {half}: body {j} is not finite after an Ok step"
                            );
                        }
                    }
                    Err(e) => {
                        assert!(
                            matches!(
                                e,
                                DynamicsError::NonFinite { .. } | DynamicsError::InvalidBody { .. }
                            ),
                            "half {half}: {e}"
                        );
                        assert_eq!(state(&w), before, "half {half}: rolled back");
                        break;
                    }
                }
            }
            assert!(w.body_count() > i);
        }
    }

    /// A three-link chain (articulated), stepped once.
    fn tree_world() -> World {
        let model = serde_json::to_string(&virtual_physics::model::builders::chain(3)).unwrap();
        let text = format!(
            r#"{{"effects": ["gravity", "articulated"], "articulated": [{{"model": {model}}}]}}"#
        );
        let mut w = virtual_physics::scene::SceneFile::from_json(&text)
            .unwrap()
            .build()
            .unwrap();
        w.step().unwrap();
        w
    }

    #[test]
    fn non_finite_or_huge_tree_state_is_refused() {
        for (what, index, value) in [
            ("q", 1, f64::NAN),
            ("qd", 0, 1e300),
            ("tau", 2, f64::INFINITY),
        ] {
            let mut w = tree_world();
            let a = tree_at_mut(&mut w, 0);
            match what {
                "q" => a.q_mut()[index] = value,
                "qd" => a.qd_mut()[index] = value,
                _ => a.tau_mut()[index] = value,
            }
            let time = w.time();
            let e = w.step().unwrap_err();
            assert!(
                matches!(
                    &e,
                    DynamicsError::InvalidTree { tree: 0, what: w, index: i, .. }
                        if *w == what && *i == index
                ),
                "{what}: {e}"
            );
            assert_eq!(w.time(), time, "nothing stepped");
        }
    }
}

#[test]
fn bodies_moved_onto_one_another_en_masse_stop_the_step_and_leave_the_world_as_it_was() {
    use virtual_physics::dynamics::DynamicsError;
    let mut w = virtual_physics::scene::builtin::towers(10, 10, 10)
        .build()
        .unwrap();
    let handles: Vec<_> = w.body_handles().collect();
    for &h in &handles {
        if w.body(h).unwrap().kind() == virtual_physics::dynamics::BodyKind::Dynamic {
            w.body_mut(h)
                .unwrap()
                .set_position(nalgebra::Vector3::new(0.0, 0.0, 0.5));
        }
    }
    let before: Vec<_> = w.bodies().map(|b| b.position()).collect();
    let t = w.time();
    match w.step() {
        Err(e @ DynamicsError::TooManyContactPairs { .. }) => {
            assert!(e.to_string().contains("overlap en masse"), "{e}");
        }
        other => panic!("{other:?}"),
    }
    let after: Vec<_> = w.bodies().map(|b| b.position()).collect();
    assert_eq!(before, after);
    assert_eq!(w.time(), t);
}

//! `vphys` as a user meets it: the binary spawned with arguments, its stdout, stderr and exit
//! code. Per-body JSON lines against the motion of a thrown, spinning box; one-line errors
//! without a backtrace; a quiet end on a closed pipe; every bad-scene reproducer rejected.

use std::io::{BufRead, BufReader};
use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};

use serde_json::Value;

const VPHYS: &str = env!("CARGO_BIN_EXE_vphys");

/// Step of the test scenes (s) and gravity (m/s²).
const H: f64 = 0.01;
const G: f64 = 9.81;

/// A fresh folder for this test's files.
fn scratch(test: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("vphys-cli-{}-{test}", std::process::id()));
    std::fs::create_dir_all(&d).expect("scratch folder");
    d
}

/// A scene file with two 1 kg boxes and nothing to touch: "box" thrown with velocity
/// (3, 0, 4) m/s from (0, 0, 10), not spinning, and "spinner" at (5, 0, 10), spinning at
/// 2 rad/s about the world z axis (a principal axis); `effects` as given.
fn thrown_box(dir: &Path, effects: &str) -> PathBuf {
    let p = dir.join("thrown.json");
    let text = format!(
        r#"{{"name": "thrown box", "dt": {H}, "gravity": [0, 0, -{G}], "effects": [{effects}],
            "bodies": [{{"name": "box", "shape": {{"type": "box", "half_extents": [0.1, 0.2, 0.3]}},
                         "mass": 1, "position": [0, 0, 10], "velocity": [3, 0, 4]}},
                       {{"name": "spinner", "shape": {{"type": "box", "half_extents": [0.1, 0.2, 0.3]}},
                         "mass": 1, "position": [5, 0, 10], "angular_velocity": [0, 0, 2]}}]}}"#
    );
    std::fs::write(&p, text).expect("write scene");
    p
}

fn vphys(args: &[&str]) -> Output {
    Command::new(VPHYS)
        .args(args)
        .env("RUST_BACKTRACE", "1")
        .env("RUST_LIB_BACKTRACE", "1")
        .output()
        .expect("spawn vphys")
}

fn json_lines(out: &Output) -> Vec<Value> {
    String::from_utf8_lossy(&out.stdout)
        .lines()
        .map(|l| serde_json::from_str(l).unwrap_or_else(|e| panic!("not JSON ({e}): {l}")))
        .collect()
}

fn v3(v: &Value) -> [f64; 3] {
    let a = v.as_array().expect("array");
    assert_eq!(a.len(), 3, "{v}");
    [0, 1, 2].map(|i| a[i].as_f64().expect("number"))
}

/// Asserts the user-error contract: status 1, exactly one line on stderr that starts with
/// `error: `, no panic and no backtrace (the test runs with `RUST_BACKTRACE=1`).
fn assert_one_line_error(out: &Output, what: &str) -> String {
    let err = String::from_utf8_lossy(&out.stderr).to_string();
    assert_eq!(out.status.code(), Some(1), "{what}: status; stderr: {err}");
    let lines: Vec<&str> = err.lines().collect();
    assert_eq!(lines.len(), 1, "{what}: one line on stderr, got {err:?}");
    assert!(lines[0].starts_with("error: "), "{what}: {err}");
    for bad in [
        "panicked",
        "backtrace",
        "Backtrace",
        "stack backtrace",
        "at src/",
    ] {
        assert!(!err.contains(bad), "{what}: '{bad}' in {err}");
    }
    err
}

#[test]
fn bodies_lines_follow_a_thrown_spinning_box() {
    let dir = scratch("bodies");
    let scene = thrown_box(&dir, r#""gravity""#);
    let scene = scene.to_str().expect("utf-8 path");
    let out = vphys(&["run", scene, "--steps", "50", "--every", "10", "--bodies"]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let lines = json_lines(&out);
    assert_eq!(lines.len(), 10, "two bodies at steps 10, 20, …, 50");
    for (n, l) in lines.iter().enumerate() {
        let step = 10 * (n as u64 / 2 + 1);
        let which = n % 2;
        assert_eq!(l["step"].as_u64(), Some(step));
        assert_eq!(l["body"].as_u64(), Some(which as u64));
        assert_eq!(l["name"], ["box", "spinner"][which]);
        assert_eq!(l["kind"], "dynamic");
        let t = l["t"].as_f64().expect("t");
        assert!((t - step as f64 * H).abs() < 1e-12, "t = {t}");
        // Free fall: the velocity is exact for any of the Euler steps (gravity is constant).
        let v = v3(&l["linear_velocity_mps"]);
        let v0 = [[3.0, 0.0, 4.0], [0.0; 3]][which];
        for (got, want) in v.iter().zip([v0[0], v0[1], v0[2] - G * t]) {
            assert!((got - want).abs() < 1e-9, "velocity {v:?} at t = {t}");
        }
        // Position: a first-order step is off the parabola by at most g h t (semi-implicit
        // Euler by g h t / 2); sideways it is exact.
        let p = v3(&l["position_m"]);
        let p0 = [[0.0, 0.0, 10.0], [5.0, 0.0, 10.0]][which];
        assert!(
            (p[0] - p0[0] - v0[0] * t).abs() < 1e-9 && p[1].abs() < 1e-9,
            "{p:?}"
        );
        let z = p0[2] + v0[2] * t - 0.5 * G * t * t;
        assert!((p[2] - z).abs() <= G * H * t, "z = {} against {z}", p[2]);
        // Torque-free spin about a principal axis: ω constant and the rotation exp(ω t), the
        // quaternion (cos t, 0, 0, sin t) for 2 rad/s about z; the thrown box keeps (1, 0, 0, 0).
        let w = v3(&l["angular_velocity_radps"]);
        let wz = [0.0, 2.0][which];
        assert!(w[0].abs() < 1e-12 && w[1].abs() < 1e-12 && (w[2] - wz).abs() < 1e-12);
        let q: Vec<f64> = l["quaternion_wxyz"]
            .as_array()
            .expect("quaternion")
            .iter()
            .map(|x| x.as_f64().expect("number"))
            .collect();
        assert_eq!(q.len(), 4);
        let norm = q.iter().map(|x| x * x).sum::<f64>().sqrt();
        assert!((norm - 1.0).abs() < 1e-12, "|q| = {norm}");
        let half = 0.5 * wz * t;
        let want = [half.cos(), 0.0, 0.0, half.sin()];
        for (got, want) in q.iter().zip(want) {
            assert!(
                (got - want).abs() < 1e-9,
                "q = {q:?} at t = {t}, want {want:?}"
            );
        }
        let d = l["displacement_m"].as_f64().expect("displacement");
        let from_p = ((p[0] - p0[0]).powi(2) + p[1].powi(2) + (p[2] - p0[2]).powi(2)).sqrt();
        assert!(
            (d - from_p).abs() < 1e-12,
            "displacement {d} against {from_p}"
        );
    }
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn the_step_line_reports_displacement_as_a_3d_distance() {
    let dir = scratch("displacement");
    // No effects: the box flies straight at 5 m/s, 3 sideways and 4 up; the spinner stays.
    let scene = thrown_box(&dir, "");
    let out = vphys(&["run", scene.to_str().expect("utf-8"), "--steps", "100"]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let lines = json_lines(&out);
    assert_eq!(lines.len(), 100);
    let last = &lines[99];
    let t = 100.0 * H;
    let d = last["max_displacement"].as_f64().expect("max_displacement");
    assert!(
        (d - 5.0 * t).abs() < 1e-9,
        "3D distance {d}, want {}",
        5.0 * t
    );
    let h = last["max_horizontal_displacement"]
        .as_f64()
        .expect("horizontal");
    let v = last["max_vertical_displacement"]
        .as_f64()
        .expect("vertical");
    assert!(
        (h - 3.0 * t).abs() < 1e-9 && (v - 4.0 * t).abs() < 1e-9,
        "{h} {v}"
    );
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn body_selects_by_name_and_an_unknown_name_is_an_error() {
    let dir = scratch("select");
    let scene = thrown_box(&dir, "");
    let scene = scene.to_str().expect("utf-8");
    let out = vphys(&["run", scene, "--steps", "3", "--body", "box"]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let lines = json_lines(&out);
    assert_eq!(lines.len(), 3, "one body, three steps");
    assert!(lines.iter().all(|l| l["name"] == "box"));
    let out = vphys(&["run", scene, "--steps", "3", "--body", "woman"]);
    let err = assert_one_line_error(&out, "unknown body");
    assert!(err.contains("'woman'") && err.contains("box"), "{err}");
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn a_missing_scene_file_is_named_as_missing() {
    let out = vphys(&["run", "/missing.json"]);
    let err = assert_one_line_error(&out, "missing file");
    assert!(
        err.contains("/missing.json") && err.contains("does not exist"),
        "{err}"
    );
    assert!(!err.contains("built-in scene named"), "{err}");
    let out = vphys(&["run", "no-such-scene"]);
    let err = assert_one_line_error(&out, "unknown name");
    assert!(
        err.contains("towers-1120"),
        "lists the built-in scenes: {err}"
    );
}

#[test]
fn user_errors_are_one_line_without_a_backtrace() {
    let dir = scratch("errors");
    let bad = dir.join("bad.json");
    std::fs::write(
        &bad,
        r#"{"dt": -1, "effects": [], "bodies": [{"shape": {"type": "sphere", "radius": 1}, "mass": -1},
                                 {"shape": {"type": "sphere", "radius": 1}}]}"#,
    )
    .expect("write");
    let bad = bad.to_str().expect("utf-8");
    let syntax = dir.join("syntax.json");
    std::fs::write(&syntax, "{\"bodies\": [ {\"mas\": 1} ]").expect("write");
    let syntax = syntax.to_str().expect("utf-8");
    let cases: Vec<(&str, Vec<&str>)> = vec![
        ("several problems", vec!["run", bad]),
        ("bench, several problems", vec!["bench", bad]),
        ("syntax", vec!["run", syntax]),
        ("--every 0", vec!["run", "towers-80", "--every", "0"]),
        (
            "--steps too large",
            vec!["run", "towers-80", "--steps", "100000000000"],
        ),
        ("unknown option", vec!["run", "towers-80", "--frobnicate"]),
        ("unknown command", vec!["jump"]),
        ("no command", vec![]),
        (
            "negative hertz",
            vec![
                "bench",
                "towers-80",
                "--steps",
                "1",
                "--contact-hertz",
                "-5",
            ],
        ),
    ];
    for (what, args) in cases {
        for bt in ["1", "full"] {
            let out = Command::new(VPHYS)
                .args(&args)
                .env("RUST_BACKTRACE", bt)
                .env("RUST_LIB_BACKTRACE", bt)
                .output()
                .expect("spawn");
            assert_one_line_error(&out, what);
        }
    }
    // The several problems of one scene all appear on the one line.
    let err = assert_one_line_error(&vphys(&["run", bad]), "several problems");
    assert!(
        err.contains("dt") && err.contains("bodies[0].mass"),
        "{err}"
    );
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn a_closed_stdout_ends_the_run_quietly() {
    let dir = scratch("pipe");
    let scene = thrown_box(&dir, "");
    let mut child = Command::new(VPHYS)
        .args(["run", scene.to_str().expect("utf-8"), "--steps", "1000000"])
        .args(["--bodies"])
        .env("RUST_BACKTRACE", "1")
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("spawn");
    // Read one line, as `head -1` does, then close the pipe.
    let mut first = String::new();
    BufReader::new(child.stdout.take().expect("stdout"))
        .read_line(&mut first)
        .expect("first line");
    assert!(first.starts_with('{'), "{first}");
    let out = child.wait_with_output().expect("wait");
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.is_empty(), "nothing on stderr, got {err}");
    assert_eq!(out.status.code(), Some(0), "quiet success on a broken pipe");
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn a_missing_peer_is_status_2_with_one_line() {
    if cfg!(feature = "rapier-peer") {
        return;
    }
    for peer in ["parry", "front"] {
        let out = vphys(&["peers", peer]);
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{peer}: {err}");
        assert_eq!(err.lines().count(), 1, "{peer}: {err}");
        assert!(err.contains("--features rapier-peer"), "{peer}: {err}");
    }
}

/// The peer panels come with the full report only: `--peers` with `--quick` is refused as a
/// usage error before anything runs.
#[test]
fn the_peer_panels_refuse_the_quick_sweep() {
    let out = vphys(&["accuracy", "--quick", "--peers"]);
    let err = assert_one_line_error(&out, "--peers with --quick");
    assert_eq!(out.status.code(), Some(1), "{err}");
    assert!(err.contains("--quick") || err.contains("--peers"), "{err}");
}

/// The bad-input reproducers of the library's tests: each file is a scene that must be
/// rejected, before or during the run, with a user error (none present: nothing to check).
#[test]
fn every_bad_scene_reproducer_is_rejected_with_one_line() {
    let folder = Path::new(env!("CARGO_MANIFEST_DIR")).join("../physics/tests/bad_scenes");
    let Ok(entries) = std::fs::read_dir(&folder) else {
        return;
    };
    let mut files: Vec<PathBuf> = entries
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "json"))
        .collect();
    files.sort();
    for f in files {
        let out = vphys(&["run", f.to_str().expect("utf-8 path"), "--steps", "100"]);
        assert_one_line_error(&out, &f.display().to_string());
    }
}

/// `vphys bench` shares the median step over every contact point of every substep taken: the
/// field is `median_ms · 10⁶ / (mean points × mean substeps taken)`, and null for a scene
/// without contacts.
#[test]
fn bench_reports_ns_per_contact_point_per_substep() {
    let out = vphys(&["bench", "towers-80", "--steps", "3", "--sleeping", "false"]);
    assert!(out.status.success(), "{out:?}");
    let v = &json_lines(&out)[0];
    let points = v["mean_contact_points"].as_f64().expect("points");
    let substeps = v["mean_substeps_taken"].as_f64().expect("substeps taken");
    // Three steps are too few for the world to rest: it takes the scene's 12.
    assert_eq!(substeps, 12.0, "{v}");
    let median = v["median_ms"].as_f64().expect("median");
    let ns = v["ns_per_contact_point_substep"].as_f64().expect("ns");
    // 80 boxes, each resting on a face: at least 4 points per box.
    assert!(points >= 4.0 * 80.0, "{points} points");
    let expected = median * 1e6 / (points * substeps);
    assert!(
        (ns - expected).abs() <= 1e-9 * expected,
        "{ns} vs {expected}"
    );

    let dir = scratch("bench-points");
    let scene = thrown_box(&dir, r#""gravity""#);
    let out = vphys(&["bench", scene.to_str().unwrap(), "--steps", "3"]);
    assert!(out.status.success(), "{out:?}");
    let v = &json_lines(&out)[0];
    assert_eq!(v["mean_contact_points"].as_f64(), Some(0.0));
    assert!(v["ns_per_contact_point_substep"].is_null(), "{v}");
    std::fs::remove_dir_all(&dir).ok();
}

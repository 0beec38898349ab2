//! Calibration: fitting on the emulated board, and the calibration file.

use board_link::Board;
use foosball_sim::motion::script::MotionScript;
use foosball_sim::{BoardConfig, InProcessBoard, Pacing};
use space_foosball::input::calibration::{Calibration, CalibrationError, PaddleCalibration};
use space_foosball::input::guided::{GuidedCollector, GuidedMotion};
use space_foosball::input::paddles::BoardInput;
use space_foosball::Table;
use std::time::Duration;

const PORT: usize = 3;
const TRAVEL_M: f64 = 0.116;
const MOVE_S: f64 = 1.0;
const HOLD_S: f64 = 0.3;
/// Sensors finish their self-test after 0.5 s; counting starts at 0.9 s.
const START_S: f64 = 1.0;

/// Validation moves after the guided motion: poses the fit never saw.
const CHECK_POSES: [[f64; 2]; 4] = [[0.031, 7.3], [-0.042, -2.0], [0.058, 1.0], [-0.01, 12.5]];

/// A script for `PORT`: hold, then each pose in turn (move, hold).
fn script(poses: &[[f64; 2]]) -> MotionScript {
    let mut segments = vec![format!(r#"{{"hold":{{"duration_s":{START_S}}}}}"#)];
    for p in &poses[1..] {
        segments.push(format!(
            r#"{{"move_to":{{"duration_s":{MOVE_S},"axial_m":{},"angle_rad":{}}}}}"#,
            p[0], p[1]
        ));
        segments.push(format!(r#"{{"hold":{{"duration_s":{HOLD_S}}}}}"#));
    }
    let json = format!(
        r#"{{"rods":[{{"rod":{PORT},"start":{{"axial_m":{},"angle_rad":{}}},"segments":[{}]}}]}}"#,
        poses[0][0],
        poses[0][1],
        segments.join(",")
    );
    MotionScript::from_json(&json).unwrap()
}

fn sensor_config(gain_axial: f64, gain_rotation: f64, cross_talk: f64) -> BoardConfig {
    let mut config = BoardConfig::default();
    let s = &mut config.sensors[PORT];
    s.axial_gain_error = gain_axial;
    s.rotation_gain_error = gain_rotation;
    s.cross_talk = cross_talk;
    config
}

fn poll(board: &mut InProcessBoard, collector: &mut GuidedCollector, ms: u64) {
    for _ in 0..ms {
        let r = board.poll_report(Duration::ZERO).unwrap().unwrap();
        collector.push(&r);
    }
}

/// Runs the guided motion then the validation moves in lockstep; returns the fitted
/// map and the count sums at the end of the guided motion and at each validation pose.
fn calibrate(config: BoardConfig) -> (PaddleCalibration, Vec<[f64; 2]>) {
    let guided = GuidedMotion::standard(TRAVEL_M, 2);
    let mut poses: Vec<[f64; 2]> = guided.steps.iter().map(|s| s.pose).collect();
    poses.extend(CHECK_POSES);
    let mut board =
        InProcessBoard::with_motion(config, Box::new(script(&poses)), Pacing::Lockstep).unwrap();
    let mut collector = GuidedCollector::new(PORT);
    // Self-test, then start counting while the rod rests at the first pose.
    poll(&mut board, &mut collector, 900);
    collector.start();
    poll(&mut board, &mut collector, 100);
    collector.checkpoint(guided.steps[0].pose);
    let step_ms = ((MOVE_S + HOLD_S) * 1e3) as u64;
    for step in &guided.steps[1..] {
        poll(&mut board, &mut collector, step_ms);
        assert!(collector.still_ms() > 100, "rod at rest at the checkpoint");
        collector.checkpoint(step.pose);
    }
    let fitted = collector.fit().unwrap();
    let s = collector.sums();
    let mut sums = vec![[s[0] as f64, s[1] as f64]];
    for _ in CHECK_POSES {
        poll(&mut board, &mut collector, step_ms);
        let s = collector.sums();
        sums.push([s[0] as f64, s[1] as f64]);
    }
    (fitted, sums)
}

/// The largest error of the map's motion between consecutive validation poses (from
/// the end of the guided motion on), as a fraction of the true motion, per axis.
fn worst_motion_error(cal: &PaddleCalibration, sums: &[[f64; 2]]) -> [f64; 2] {
    let mut truths = vec![
        GuidedMotion::standard(TRAVEL_M, 2)
            .steps
            .last()
            .unwrap()
            .pose,
    ];
    truths.extend(CHECK_POSES);
    let mut worst = [0.0f64; 2];
    for w in 1..truths.len() {
        let d = cal.apply_delta([sums[w][0] - sums[w - 1][0], sums[w][1] - sums[w - 1][1]]);
        for axis in 0..2 {
            let true_motion = truths[w][axis] - truths[w - 1][axis];
            worst[axis] = worst[axis].max((d[axis] - true_motion).abs() / true_motion.abs());
        }
    }
    worst
}

#[test]
fn gain_error_and_cross_talk_are_calibrated_to_within_one_percent() {
    let (fitted, sums) = calibrate(sensor_config(0.04, -0.03, 0.05));
    let worst = worst_motion_error(&fitted, &sums);
    assert!(worst[0] < 0.01 && worst[1] < 0.01, "fitted: {worst:?}");
    // The nominal map is off by the gain error and cross-talk: the test can fail.
    let worst_nominal = worst_motion_error(&PaddleCalibration::default(), &sums);
    assert!(
        worst_nominal[0] > 0.02 && worst_nominal[1] > 0.02,
        "nominal: {worst_nominal:?}"
    );
    eprintln!("worst motion error: fitted {worst:?}, nominal {worst_nominal:?}");
    // The fitted matrix undoes the sensor: M ≈ inverse of (gain · cross-talk) at 8/mm.
    let ideal = PaddleCalibration::default();
    assert!((fitted.matrix[0][0] / ideal.matrix[0][0] - 1.0 / 1.04).abs() < 0.02);
    assert!(
        fitted.matrix[0][1] < 0.0,
        "cross-talk is subtracted: {fitted:?}"
    );
    // The offset is the first step's pose (the near stop, upright).
    assert!(
        (fitted.offset[0] + 0.5 * TRAVEL_M).abs() < 1e-3,
        "{fitted:?}"
    );
    assert!(fitted.offset[1].abs() < 0.02, "{fitted:?}");
}

#[test]
fn an_ideal_sensor_calibrates_to_the_nominal_map() {
    let (fitted, _) = calibrate(sensor_config(0.0, 0.0, 0.0));
    let nominal = PaddleCalibration::default();
    for r in 0..2 {
        let rel = (fitted.matrix[r][r] / nominal.matrix[r][r] - 1.0).abs();
        assert!(rel < 0.002, "{fitted:?}");
        let cross = (fitted.matrix[r][1 - r] / nominal.matrix[r][r]).abs();
        assert!(cross < 0.002, "{fitted:?}");
    }
}

#[test]
fn the_fitted_calibration_drives_rods_through_board_input() {
    let config = sensor_config(0.04, -0.03, 0.05);
    let (fitted, _) = calibrate(config.clone());
    let mut calibration = Calibration::default();
    calibration.paddles[PORT] = fitted;
    // The standard table's rod 3 (home midfield, 116 mm travel) is on port 3.
    let table = Table::standard();
    let guided = GuidedMotion::standard(TRAVEL_M, 2);
    let poses: Vec<[f64; 2]> = guided.steps.iter().map(|s| s.pose).collect();
    let board =
        InProcessBoard::with_motion(config, Box::new(script(&poses)), Pacing::Lockstep).unwrap();
    let mut input = BoardInput::new(board, &table, calibration);
    for _ in 0..900 {
        input.poll(1);
    }
    // Counting starts here with the rod at the near stop, upright: the fitted offset.
    input.tracker_mut().rehome(3, -0.5 * TRAVEL_M, 0.0);
    let step_ms = ((MOVE_S + HOLD_S) * 1e3) as u64;
    for _ in 0..100 {
        input.poll(1);
    }
    for step in &guided.steps[1..] {
        for _ in 0..step_ms {
            input.poll(1);
        }
        let rod = input.tracker().rod(3).unwrap();
        assert!(
            (rod.slide_m - step.pose[0]).abs() < 0.01 * TRAVEL_M,
            "{rod:?} {step:?}"
        );
        assert!((rod.angle_rad - step.pose[1]).abs() < 0.01 * 4.0 * std::f64::consts::PI);
        assert!(rod.present);
    }
}

fn sample_calibration() -> Calibration {
    let mut c = Calibration::default();
    c.paddles[2].matrix[0][1] = -3.0e-6;
    c.paddles[2].offset = [-0.058, 0.01];
    c
}

#[test]
fn calibration_file_round_trips_exactly() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("calibration.json");
    let c = sample_calibration();
    c.save(&path).unwrap();
    assert_eq!(Calibration::load(&path).unwrap(), c);
    let (loaded, warning) = Calibration::load_or_default(&path);
    assert_eq!(loaded, c);
    assert!(warning.is_none());
    // No file: the defaults, silently.
    let (d, warning) = Calibration::load_or_default(&dir.path().join("none.json"));
    assert_eq!(d, Calibration::default());
    assert!(warning.is_none());
}

#[test]
fn corrupt_files_fall_back_to_defaults_with_a_warning_and_are_left_alone() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("calibration.json");
    let good = sample_calibration().to_json();
    let seven = good.replacen("{\n      \"matrix\"", "{\"matrix\"", 1);
    let mut seven_paddles: serde_json::Value = serde_json::from_str(&seven).unwrap();
    seven_paddles["paddles"].as_array_mut().unwrap().pop();
    let mut singular: serde_json::Value = serde_json::from_str(&good).unwrap();
    singular["paddles"][4]["matrix"] = serde_json::json!([[1e-4, 2e-4], [2e-4, 4e-4]]);
    let mut wrong_version: serde_json::Value = serde_json::from_str(&good).unwrap();
    wrong_version["version"] = serde_json::json!(99);
    let cases: Vec<(String, &str)> = vec![
        (String::new(), "malformed"),
        ("\u{0}\u{ff}garbage".into(), "malformed"),
        (good[..good.len() / 2].to_string(), "malformed"), // half-written
        (good.replace("0.000125", "NaN"), "malformed"),
        (good.replace("0.000125", "1e999"), "malformed"),
        (seven_paddles.to_string(), "7 paddles"),
        (singular.to_string(), "singular"),
        (wrong_version.to_string(), "version 99"),
        (good.replace("\"offset\"", "\"offsets\""), "malformed"),
    ];
    for (text, expect) in cases {
        std::fs::write(&path, &text).unwrap();
        let err = Calibration::load(&path).unwrap_err();
        assert!(err.to_string().contains(expect), "{expect}: {err}");
        let (c, warning) = Calibration::load_or_default(&path);
        assert_eq!(c, Calibration::default());
        assert!(warning.is_some());
        assert_eq!(std::fs::read_to_string(&path).unwrap(), text, "left alone");
    }
}

#[test]
fn saving_never_leaves_a_half_written_file() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("calibration.json");
    let a = Calibration::default();
    let b = sample_calibration();
    a.save(&path).unwrap();
    // An invalid calibration is refused before anything is written.
    let mut bad = b;
    bad.paddles[1].matrix[1][1] = f64::INFINITY;
    let before = std::fs::read(&path).unwrap();
    assert!(matches!(
        bad.save(&path),
        Err(CalibrationError::NotFinite { paddle: 1 })
    ));
    assert_eq!(std::fs::read(&path).unwrap(), before);
    // Readers racing a writer always see a whole file, old or new.
    let stop = std::sync::Arc::new(std::sync::atomic::AtomicBool::new(false));
    let reader = {
        let path = path.clone();
        let stop = stop.clone();
        std::thread::spawn(move || {
            let mut reads = 0;
            while !stop.load(std::sync::atomic::Ordering::Relaxed) {
                let c = Calibration::load(&path).expect("always a whole file");
                assert!(c == a || c == b);
                reads += 1;
            }
            reads
        })
    };
    for i in 0..200 {
        if i % 2 == 0 { b } else { a }.save(&path).unwrap();
    }
    stop.store(true, std::sync::atomic::Ordering::Relaxed);
    assert!(reader.join().unwrap() > 0);
    // Only the calibration file is left: no temporary files.
    assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 1);
}

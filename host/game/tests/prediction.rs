//! Pose prediction between mouse packets (`PaddleTracker::set_prediction_ms`).
//!
//! A rod slides at a constant 0.2 m/s; its mouse sends a packet every 5 ms (8 counts/mm:
//! 8 counts per packet), the board a report every 1 ms. Without prediction the pose is
//! a staircase 0–5 ms behind; with a 5 ms horizon it follows the motion between
//! packets, and when the rod stops it overshoots by at most `v × horizon`, then settles.

use foosball_protocol::InReport;
use space_foosball::input::calibration::Calibration;
use space_foosball::input::paddles::{PaddleTracker, MOUSE_PACKET_PREDICTION_MS};
use space_foosball::Table;

const PORT: usize = 3; // Home midfield: table slide = paddle slide
const COUNTS_PER_PACKET: i16 = 8; // 1 mm per 5 ms = 0.2 m/s
const SPEED: f64 = 0.2;

fn report(sequence: u16, axial: i16) -> InReport {
    let mut r = InReport::all_present(sequence);
    r.paddles[PORT].axial = axial;
    r
}

/// Runs 200 ms of motion then 50 ms at rest; per report `(true slide, tracked slide)`.
fn track(prediction_ms: u64) -> Vec<(f64, f64)> {
    let mut t = PaddleTracker::new(&Table::standard(), Calibration::default());
    t.set_prediction_ms(prediction_ms);
    let mut out = Vec::new();
    for ms in 0..250u16 {
        // A packet lands every 5 ms with the motion up to its sample time.
        let moving = ms < 200;
        let packet = moving && ms % 5 == 4;
        t.apply_report(&report(ms, if packet { COUNTS_PER_PACKET } else { 0 }));
        let truth = SPEED * 1e-3 * f64::from(ms.min(199) + 1);
        out.push((truth, t.inputs().rods[PORT].slide_m));
    }
    out
}

#[test]
fn prediction_follows_the_rod_between_packets_and_settles_after_a_stop() {
    let raw = track(0);
    let predicted = track(MOUSE_PACKET_PREDICTION_MS);
    // In steady motion (after the velocity window filled): the worst lag behind the
    // truth, in ms of motion.
    let lag = |v: &[(f64, f64)]| {
        v[30..195]
            .iter()
            .map(|(truth, got)| (truth - got) / SPEED * 1e3)
            .fold(f64::NEG_INFINITY, f64::max)
    };
    let (raw_lag, predicted_lag) = (lag(&raw), lag(&predicted));
    assert!(
        raw_lag > 3.5,
        "the staircase lags up to a packet: {raw_lag} ms"
    );
    assert!(predicted_lag < 1.5, "predicted lag {predicted_lag} ms");
    // After the stop: a bounded overshoot, then the measured pose.
    let end = SPEED * 0.2;
    let overshoot = predicted[200..]
        .iter()
        .map(|(_, got)| got - end)
        .fold(f64::NEG_INFINITY, f64::max);
    let bound = SPEED * MOUSE_PACKET_PREDICTION_MS as f64 * 1e-3;
    assert!(overshoot <= bound + 1e-12, "{overshoot} > {bound}");
    let settled = predicted.last().unwrap().1;
    assert!((settled - end).abs() < 1e-9, "{settled} vs {end}");
    // Off by default: the tracker reports what it measured.
    let t = PaddleTracker::new(&Table::standard(), Calibration::default());
    assert_eq!(t.prediction_ms(), 0);
}

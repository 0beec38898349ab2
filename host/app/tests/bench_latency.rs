//! `bench match`: the input latency on the board's clock (version 2 reports, no
//! prediction horizon) is at most 2 ms median, beside the report-time figures.
//!
//! The latency runs are in emulated time (lockstep board), so the figures are the same
//! on any machine; 2 ms is the product's target for input without prediction.

mod common;

use common::run;

#[test]
fn board_time_tracking_keeps_the_median_latency_within_2_ms() {
    let out = run(&["bench", "match", "--json", "--steps", "10"]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).expect("one JSON object");
    let get = |key: &str| {
        v[key]
            .as_f64()
            .unwrap_or_else(|| panic!("{key} missing: {v}"))
    };
    let board_time = get("input_latency_board_time_median_ms");
    assert!(board_time.abs() <= 2.0, "board time median {board_time} ms");
    // Beside today's figures: report time without prediction lags by the mice's
    // packet period and the PS/2 wire (over 2.6 ms at 12.5 kHz).
    let unpredicted = get("input_latency_unpredicted_median_ms");
    assert!(unpredicted > 2.6, "unpredicted median {unpredicted} ms");
    for key in [
        "input_latency_median_ms",
        "input_latency_board_time_ms",
        "input_latency_board_time_worst_ms",
        "board_time_overshoot_slide_mm",
    ] {
        assert!(get(key).is_finite(), "{key}");
    }
}

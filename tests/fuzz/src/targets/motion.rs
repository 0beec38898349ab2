//! The emulator's motion sources from files: scripts and recordings. The loader
//! rejects the file, or the poses it gives at 100 times spread over its duration (and
//! past its end) are finite and within the script limits (`MAX_AXIAL_M`,
//! `MAX_ANGLE_RAD`), and a script's faults name existing ports.

use super::{text, Verdict};
use foosball_protocol::PADDLES;
use foosball_sim::motion::recording::Playback;
use foosball_sim::motion::script::{MotionScript, MAX_ANGLE_RAD, MAX_AXIAL_M};
use foosball_sim::motion::{MotionSource, RodPoses};

/// Times sampled per accepted input.
const SAMPLES: u64 = 100;

pub(super) fn script(input: &[u8]) -> Verdict {
    let Some(text) = text(input) else {
        return Verdict::Rejected;
    };
    let Ok(mut script) = MotionScript::from_json(text) else {
        return Verdict::Rejected;
    };
    for fault in script.faults() {
        assert!(fault.port < PADDLES, "fault on port {}", fault.port);
    }
    let duration = script.duration_us();
    sample(&mut script, duration);
    Verdict::Accepted
}

pub(super) fn playback(input: &[u8]) -> Verdict {
    let Some(text) = text(input) else {
        return Verdict::Rejected;
    };
    let Ok(mut playback) = Playback::from_json(text) else {
        return Verdict::Rejected;
    };
    let duration = playback.duration_us();
    sample(&mut playback, duration);
    Verdict::Accepted
}

/// Samples `source` at non-decreasing times from 0 to 10 % past `duration_us`.
fn sample(source: &mut dyn MotionSource, duration_us: u64) {
    let end = duration_us.saturating_add(duration_us / 10).max(1);
    for k in 0..=SAMPLES {
        let t_us = (u128::from(end) * u128::from(k) / u128::from(SAMPLES)) as u64;
        check(&source.poses_at(t_us), t_us);
    }
}

fn check(poses: &RodPoses, t_us: u64) {
    for (rod, pose) in poses.iter().enumerate() {
        assert!(
            pose.is_finite(),
            "t = {t_us} µs: rod {rod} pose not finite: {pose:?}"
        );
        // Linear interpolation between two poses within the limits stays within them,
        // up to the rounding of one multiply-add.
        let slack = 1.0 + 4.0 * f64::EPSILON;
        assert!(
            pose.axial_m.abs() <= MAX_AXIAL_M * slack,
            "t = {t_us} µs: rod {rod} axial {} m beyond ±{MAX_AXIAL_M} m",
            pose.axial_m
        );
        assert!(
            pose.angle_rad.abs() <= MAX_ANGLE_RAD * slack,
            "t = {t_us} µs: rod {rod} angle {} rad beyond ±{MAX_ANGLE_RAD} rad",
            pose.angle_rad
        );
    }
}

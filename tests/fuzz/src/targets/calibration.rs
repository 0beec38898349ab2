//! Calibration files: the loader rejects the file, or its calibration turns 100 IN
//! reports of the most extreme motion a board can send (every paddle at the `i16`
//! limits, one way, then the other, then alternating) into rod poses and velocities
//! that are all finite, with every slide within its rod's travel. An accepted file
//! also survives a save/load round trip unchanged.

use super::{text, Verdict};
use foosball_protocol::{InReport, PaddleMotion, PaddleStatus, PADDLES};
use space_foosball::input::calibration::Calibration;
use space_foosball::input::paddles::PaddleTracker;
use space_foosball::Table;

/// Reports fed to an accepted calibration.
const REPORTS: u16 = 100;

pub(super) fn run(input: &[u8]) -> Verdict {
    let Some(text) = text(input) else {
        return Verdict::Rejected;
    };
    let Ok(calibration) = Calibration::from_json(text, "fuzz input") else {
        return Verdict::Rejected;
    };
    let again = Calibration::from_json(&calibration.to_json(), "saved")
        .expect("a loaded calibration saves to a file that loads");
    assert_eq!(again, calibration, "calibration round trip");

    let table = Table::standard();
    let mut tracker = PaddleTracker::new(&table, calibration);
    for sequence in 0..REPORTS {
        let counts = match sequence {
            0..40 => [i16::MAX, i16::MAX],
            40..80 => [i16::MIN, i16::MIN],
            s if s % 2 == 0 => [i16::MAX, i16::MIN],
            _ => [i16::MIN, i16::MAX],
        };
        let report = InReport {
            sequence,
            paddles: [PaddleMotion {
                axial: counts[0],
                rotation: counts[1],
                status: PaddleStatus::PRESENT,
            }; PADDLES],
        };
        tracker.apply_report(&report);
        for (i, rod) in tracker.inputs().rods.iter().enumerate() {
            let values = [
                rod.slide_m,
                rod.angle_rad,
                rod.slide_velocity_m_per_s,
                rod.angular_velocity_rad_per_s,
            ];
            assert!(
                values.iter().all(|v| v.is_finite()),
                "report {sequence}: rod {i} state not finite: {rod:?}"
            );
            let half = table.rods[i].half_travel_m();
            assert!(
                rod.slide_m.abs() <= half,
                "report {sequence}: rod {i} slide {} beyond ±{half}",
                rod.slide_m
            );
        }
    }
    Verdict::Accepted
}

//! End to end, no hardware: scripted rod motion on the emulated board (sensors, PS/2
//! mice at wire level, the firmware's own library) arrives at the host, through
//! `board_link::Board`, as counts whose sums match the motion.

use board_link::Board;
use foosball_protocol::{PaddleStatus, PADDLES};
use foosball_sim::motion::script::{MotionScript, RodTrack, ScriptSpec, Segment};
use foosball_sim::motion::RodPose;
use foosball_sim::sensor_model::{SensorAxis, SensorMount};
use foosball_sim::{BoardConfig, InProcessBoard, Pacing};
use sensor_board::Resolution;
use std::time::Duration;

/// Rods start moving at this time, s (the sensors initialise before).
const START_S: f64 = 0.8;

/// Net motion of each rod: (axial metres, angle radians), all different, both signs.
fn targets() -> [RodPose; PADDLES] {
    core::array::from_fn(|rod| {
        let sign = if rod % 2 == 0 { 1.0 } else { -1.0 };
        RodPose::new(
            sign * 0.0137 * (rod + 1) as f64,
            -sign * 0.71 * (rod + 1) as f64,
        )
    })
}

/// Each rod: hold, sweep out past the target and back, end at its target, hold.
fn script() -> MotionScript {
    let rods = targets()
        .iter()
        .enumerate()
        .map(|(rod, target)| RodTrack {
            rod,
            start: RodPose::default(),
            segments: vec![
                Segment::Hold {
                    duration_s: START_S,
                },
                Segment::Velocity {
                    duration_s: 0.3,
                    axial_m_per_s: target.axial_m * 5.0,
                    angle_rad_per_s: target.angle_rad * 5.0,
                },
                Segment::MoveTo {
                    duration_s: 0.4,
                    axial_m: target.axial_m,
                    angle_rad: target.angle_rad,
                },
                Segment::Hold { duration_s: 0.3 },
            ],
        })
        .collect();
    MotionScript::from_spec(ScriptSpec {
        rods,
        faults: Vec::new(),
    })
    .expect("valid script")
}

fn config(resolution: Resolution) -> BoardConfig {
    let mut config = BoardConfig::default();
    config.firmware_mouse.resolution = resolution;
    // Sensors mounted every which way; the firmware's axis maps follow the mounts.
    for (rod, sensor) in config.sensors.iter_mut().enumerate() {
        sensor.mount = SensorMount {
            axial_axis: if rod % 2 == 0 {
                SensorAxis::X
            } else {
                SensorAxis::Y
            },
            invert_axial: rod % 4 >= 2,
            invert_rotation: rod % 3 == 0,
        };
    }
    config
}

fn run(resolution: Resolution) {
    let cpm = f64::from(resolution.counts_per_mm());
    let mut board: Box<dyn Board> = Box::new(
        InProcessBoard::with_motion(config(resolution), Box::new(script()), Pacing::Lockstep)
            .expect("board"),
    );
    let mut sums = [(0i64, 0i64); PADDLES];
    let total_ms = 2_200;
    for ms in 0..total_ms {
        let report = board
            .poll_report(Duration::ZERO)
            .expect("poll")
            .expect("lockstep always has a report");
        assert_eq!(report.sequence, ms as u16);
        for (rod, paddle) in report.paddles.iter().enumerate() {
            sums[rod].0 += i64::from(paddle.axial);
            sums[rod].1 += i64::from(paddle.rotation);
            if ms >= 700 {
                assert!(
                    paddle.status.contains(PaddleStatus::PRESENT),
                    "rod {rod} at {ms} ms"
                );
                let bad = PaddleStatus::AXIAL_OVERFLOW.bits()
                    | PaddleStatus::ROTATION_OVERFLOW.bits()
                    | PaddleStatus::PARITY_ERROR.bits()
                    | PaddleStatus::FRAMING_ERROR.bits()
                    | PaddleStatus::SATURATED.bits();
                assert_eq!(paddle.status.bits() & bad, 0, "rod {rod} at {ms} ms");
            }
        }
    }
    let stats = board.stats();
    assert_eq!(
        (stats.received, stats.lost, stats.malformed),
        (total_ms, 0, 0)
    );
    let radius_m = BoardConfig::default().sensors[0].rod_radius_m;
    for (rod, target) in targets().iter().enumerate() {
        let want_axial = target.axial_m * 1000.0 * cpm;
        let want_rotation = target.angle_rad * radius_m * 1000.0 * cpm;
        let (axial, rotation) = sums[rod];
        eprintln!(
            "{cpm} counts/mm, rod {rod}: axial {axial} (motion {want_axial:.2}), \
             rotation {rotation} (motion {want_rotation:.2})"
        );
        assert!(
            (axial as f64 - want_axial).abs() <= 1.0,
            "{cpm} counts/mm, rod {rod}: axial sum {axial}, motion {want_axial:.3} counts"
        );
        assert!(
            (rotation as f64 - want_rotation).abs() <= 1.0,
            "{cpm} counts/mm, rod {rod}: rotation sum {rotation}, motion {want_rotation:.3} counts"
        );
    }
}

#[test]
fn scripted_motion_arrives_as_matching_counts_at_1_count_per_mm() {
    run(Resolution::CountsPerMm1);
}

#[test]
fn scripted_motion_arrives_as_matching_counts_at_4_counts_per_mm() {
    run(Resolution::CountsPerMm4);
}

#[test]
fn scripted_motion_arrives_as_matching_counts_at_8_counts_per_mm() {
    run(Resolution::CountsPerMm8);
}

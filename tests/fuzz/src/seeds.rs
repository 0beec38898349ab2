//! The seed corpus: real inputs made by the project's own encoders and fixtures, plus
//! edge cases. `foosball-fuzz seed-corpus` writes them to `corpus/<target>/`.
//!
//! Names say what a seed is for: `valid-*` seeds must be accepted by their target (a
//! test checks it), so every target starts from inputs that reach past its parser;
//! `edge-*` seeds sit on a boundary (a wrong length, an unknown version, a value just
//! outside its range) and may be accepted or rejected.

use board_link::socket_wire::Message;
use foosball_protocol::{
    BoardSettings, DeviceInfo, FeatureKind, FeatureReport, HapticPulse, InReport, InReportV2,
    LedState, OutReport, PacketAge, PaddleMotion, PaddleStatus, PaddleTiming, PortCounters,
    PortDiagnostics, PortSettings, ReportTiming, ResetReason, FEATURE_REPORT_LEN, PADDLES,
};
use foosball_sim::motion::recording::{RecordingFile, Sample, RECORDING_VERSION};
use foosball_sim::motion::RodPose;
use sensor_board::mouse::command::{ACK, DEVICE_ID_MOUSE, SELF_TEST_PASSED};
use space_foosball::input::calibration::{Calibration, PaddleCalibration};
use space_foosball::play::{idle_inputs, Match, MatchConfig};
use space_foosball::recording::MatchRecording;
use space_foosball::rules::RulesConfig;
use space_foosball::table::presets::{PAPER_TOML, STANDARD_TOML};
use space_foosball::Table;
use virtual_physics::scene::builtin;

use crate::targets::ps2::{Op, Script};

/// One seed: its file name and bytes.
pub type Seed = (String, Vec<u8>);

/// The seeds of `target` (empty for an unknown name).
pub fn seeds(target: &str) -> Vec<Seed> {
    match target {
        "in-report" => in_reports(),
        "in-report-v2" => in_reports_v2(),
        "out-report" => out_reports(),
        "feature-report" => feature_reports(),
        "ps2" => ps2(),
        "socket-frames" => socket_frames(),
        "scene" => scenes(),
        "table" => tables(),
        "calibration" => calibrations(),
        "recording" => recordings(),
        "motion-script" => motion_scripts(),
        "motion-recording" => motion_recordings(),
        _ => Vec::new(),
    }
}

fn seed(name: &str, bytes: impl Into<Vec<u8>>) -> Seed {
    (name.to_string(), bytes.into())
}

fn moving_report(sequence: u16) -> InReport {
    let mut report = InReport::all_present(sequence);
    for (i, paddle) in report.paddles.iter_mut().enumerate() {
        paddle.axial = 37 * i as i16 - 100;
        paddle.rotation = -(i as i16) * 250;
    }
    report
}

fn in_reports() -> Vec<Seed> {
    let extreme = InReport {
        sequence: u16::MAX,
        paddles: [PaddleMotion {
            axial: i16::MIN,
            rotation: i16::MAX,
            status: PaddleStatus::from_bits(PaddleStatus::KNOWN_BITS).unwrap_or_default(),
        }; PADDLES],
    };
    let good = moving_report(7).to_bytes();
    let mut version_2 = good;
    version_2[0] = 2;
    let mut unknown_status = good;
    unknown_status[7] = 0x80;
    vec![
        seed("valid-idle", InReport::all_present(0).to_bytes()),
        seed("valid-moving", good),
        seed("valid-extreme", extreme.to_bytes()),
        seed("valid-absent", InReport::default().to_bytes()),
        seed("edge-short", &good[..good.len() - 1]),
        seed("edge-version-2", version_2),
        seed("edge-unknown-status-bit", unknown_status),
    ]
}

fn in_reports_v2() -> Vec<Seed> {
    let mut timing = ReportTiming {
        device_time_us: 1_234_567,
        paddles: [PaddleTiming::default(); PADDLES],
    };
    for (i, t) in timing.paddles.iter_mut().enumerate() {
        t.newest_packet_age = PacketAge::from_micros(700 * i as u64);
        t.dropped = 3 * i as u8;
    }
    timing.paddles[7].newest_packet_age = PacketAge::NONE;
    let v2 = InReportV2 {
        report: moving_report(9),
        timing,
    };
    let good = v2.to_bytes();
    let wrapped = InReportV2 {
        report: InReport::all_present(u16::MAX),
        timing: ReportTiming {
            device_time_us: u32::MAX,
            ..timing
        },
    };
    let mut version_3 = good;
    version_3[0] = 3;
    let mut unknown_status = good;
    unknown_status[11] = 0x80;
    vec![
        seed("valid-v2-moving", good),
        seed("valid-v2-clock-wrap", wrapped.to_bytes()),
        seed("valid-v2-default", InReportV2::default().to_bytes()),
        seed("valid-v1-moving", moving_report(7).to_bytes()),
        seed("edge-v2-short", &good[..good.len() - 1]),
        seed(
            "edge-v2-as-v1-length",
            &good[..foosball_protocol::IN_REPORT_LEN],
        ),
        seed("edge-version-3", version_3),
        seed("edge-v2-unknown-status-bit", unknown_status),
        seed("edge-empty", Vec::new()),
    ]
}

fn out_reports() -> Vec<Seed> {
    let mut pulses = OutReport::default();
    for (i, p) in pulses.haptics.iter_mut().enumerate() {
        *p = HapticPulse {
            strength: 255 - 30 * i as u8,
            duration_ms: 10 * i as u8,
        };
    }
    pulses.led = LedState::FastBlink;
    let good = pulses.to_bytes();
    let mut bad_led = good;
    bad_led[good.len() - 1] = 4;
    let mut long = good.to_vec();
    long.push(0);
    vec![
        seed("valid-off", OutReport::default().to_bytes()),
        seed("valid-pulses", good),
        seed("edge-led-4", bad_led),
        seed("edge-long", long),
    ]
}

fn feature_reports() -> Vec<Seed> {
    let info = FeatureReport::DeviceInfo(DeviceInfo {
        firmware_version: [0, 1, 0],
        git_hash: *b"0123456789ab",
        reset_reason: ResetReason::WatchdogTimeout,
        uptime_us: 123_456_789_012,
        present_ports: 0b1011_0111,
    });
    let diagnostics = FeatureReport::PortDiagnostics(PortDiagnostics {
        port: 7,
        present: true,
        device_id: Some(3),
        counters: PortCounters {
            frames: 100_000,
            packets: 33_000,
            parity_errors: 2,
            resends: 2,
            inits: 1,
            line_faults: u32::MAX,
            ..PortCounters::default()
        },
    });
    let mut settings = BoardSettings::DEFAULT;
    settings.ports[2] = PortSettings {
        axial_is_y: true,
        invert_axial: true,
        invert_rotation: false,
        resolution_code: 0,
        sample_rate: 10,
    };
    let settings = FeatureReport::Settings(settings);
    let select = FeatureReport::Select {
        kind: FeatureKind::PortDiagnostics,
        port: 5,
    };
    let mut wrong_version = select.to_bytes();
    wrong_version[0] = 2;
    let mut select_port_8 = select.to_bytes();
    select_port_8[3] = 8;
    let mut reserved = FeatureReport::EnterBootloader.to_bytes();
    reserved[FEATURE_REPORT_LEN - 1] = 1;
    let mut bad_magic = FeatureReport::EnterBootloader.to_bytes();
    bad_magic[5] = b't';
    let mut bad_rate = settings.to_bytes();
    bad_rate[4] = 199;
    let mut long = info.to_bytes().to_vec();
    long.push(0);
    vec![
        seed("valid-device-info", info.to_bytes()),
        seed("valid-port-diagnostics", diagnostics.to_bytes()),
        seed("valid-settings", settings.to_bytes()),
        seed("valid-select", select.to_bytes()),
        seed(
            "valid-bootloader",
            FeatureReport::EnterBootloader.to_bytes(),
        ),
        seed("edge-version-2", wrong_version),
        seed("edge-select-port-8", select_port_8),
        seed("edge-reserved-byte", reserved),
        seed("edge-bootloader-magic", bad_magic),
        seed("edge-sample-rate-199", bad_rate),
        seed("edge-long", long),
        seed("edge-short", &info.to_bytes()[..FEATURE_REPORT_LEN - 1]),
    ]
}

/// Reply indices of the PS/2 target's [`Op::Reply`].
const REPLY_ACK: u8 = 0;
const REPLY_RESEND: u8 = 1;
const REPLY_BAT: u8 = 3;
const REPLY_ID: u8 = 4;

/// The whole initialisation of the mouse on `port`, as a well-behaved mouse answers it:
/// reset, self-test, id, sample rate, resolution, enable reporting.
fn handshake(mut s: Script, port: u8) -> Script {
    assert_eq!((ACK, SELF_TEST_PASSED, DEVICE_ID_MOUSE), (0xFA, 0xAA, 0x00));
    s = s
        .op(port, Op::Poll)
        .op(port, Op::Sent(0))
        .op(port, Op::Reply(REPLY_ACK))
        .op(port, Op::Reply(REPLY_BAT))
        .op(port, Op::Reply(REPLY_ID));
    // Set sample rate, its value, set resolution, its value, enable reporting.
    for _ in 0..5 {
        s = s
            .op(port, Op::Poll)
            .op(port, Op::Sent(0))
            .op(port, Op::Reply(REPLY_ACK));
    }
    s
}

fn ps2() -> Vec<Seed> {
    let mut all = Script::starting_at(0);
    for port in 0..8 {
        all = handshake(all, port);
    }
    let mut streaming = all.clone().op(0, Op::Report);
    for k in 0..20u8 {
        streaming = streaming
            .op(
                k % 8,
                Op::Packet([0x08 | (k & 0x30), k.wrapping_mul(13), 200 - k]),
            )
            .op(0, Op::Wait(1_000))
            .op(0, Op::Report);
    }
    let garbled = handshake(Script::starting_at(5_000), 2)
        .op(2, Op::Frame(0x0001))
        .op(2, Op::Frame(0x03FE))
        .op(2, Op::Byte(0x55))
        .op(2, Op::Packet([0x18, 0xFF, 0x01]))
        .op(2, Op::Report);
    let resends = Script::starting_at(0)
        .op(1, Op::Poll)
        .op(1, Op::Sent(0))
        .op(1, Op::Reply(REPLY_RESEND))
        .op(1, Op::Poll)
        .op(1, Op::Sent(0))
        .op(1, Op::Reply(REPLY_RESEND))
        .op(1, Op::Poll)
        .op(1, Op::Sent(1))
        .op(1, Op::Report);
    let unplugged = handshake(Script::starting_at(0), 4)
        .op(4, Op::Report)
        .op(0, Op::Wait(50_000))
        .op(4, Op::Poll)
        .op(4, Op::Sent(0))
        .op(0, Op::Wait(100_000))
        .op(4, Op::Report)
        .op(0, Op::Wait(300_000))
        .op(4, Op::Report);
    let faults = handshake(Script::starting_at(0), 5)
        .op(5, Op::Packet([0x08, 10, 20]))
        .op(5, Op::Snapshot(1))
        .op(5, Op::Packet([0x08, 1, 2]))
        .op(5, Op::Snapshot(0))
        .op(5, Op::RxStall)
        .op(0, Op::Wait(1_000))
        .op(5, Op::LineFault(0))
        .op(0, Op::Wait(100_000))
        .op(6, Op::LineFault(1))
        .op(5, Op::Report);
    let late = handshake(Script::starting_at(u64::MAX - 2_000_000), 7)
        .op(0, Op::Wait(u64::MAX))
        .op(7, Op::Poll)
        .op(7, Op::Report);
    vec![
        seed(
            "valid-handshake-all-ports",
            all.op(0, Op::Report).into_bytes(),
        ),
        seed("valid-streaming", streaming.into_bytes()),
        seed("valid-garbled-frames", garbled.into_bytes()),
        seed("valid-resends", resends.into_bytes()),
        seed("valid-unplugged", unplugged.into_bytes()),
        seed("valid-snapshots-and-line-faults", faults.into_bytes()),
        seed("edge-time-at-the-end", late.into_bytes()),
        seed(
            "edge-port-9",
            handshake(Script::starting_at(0), 9)
                .op(9, Op::Report)
                .into_bytes(),
        ),
    ]
}

fn frames(messages: &[Message]) -> Vec<u8> {
    let mut out = Vec::new();
    for m in messages {
        m.encode_into(&mut out).expect("seed messages fit a frame");
    }
    out
}

fn socket_frames() -> Vec<Seed> {
    let stream = frames(&[
        Message::hello(),
        Message::in_report(&InReport::all_present(0)),
        Message::in_report(&moving_report(1)),
        Message::in_report(&moving_report(3)),
        Message::InReport(
            InReportV2 {
                report: moving_report(4),
                timing: ReportTiming::default(),
            }
            .to_bytes()
            .to_vec(),
        ),
        Message::out_report(&OutReport::default()),
        Message::InReport(vec![1, 2, 3]),
        Message::InReport(vec![0xAB; 64]),
        Message::InReport(Vec::new()),
    ]);
    let with_splits = |sizes: &[u8]| {
        let mut out = vec![sizes.len() as u8];
        out.extend_from_slice(sizes);
        out.extend_from_slice(&stream);
        out
    };
    let mut truncated = with_splits(&[]);
    truncated.truncate(truncated.len() - 3);
    vec![
        seed("valid-one-read", with_splits(&[])),
        seed("valid-split-reads", with_splits(&[1, 1, 2, 5, 40, 0, 3])),
        seed("valid-byte-by-byte", with_splits(&[1; 60])),
        seed("valid-truncated-frame", truncated),
        seed("edge-unknown-kind", [0, 0x01, 0x01, 0x01, 0x04, 0x00]),
        seed("edge-hello-length-2", [0, 0x01, 0x02, 0x01, 0x01]),
        seed("edge-payload-65", {
            let mut v = vec![0, 0x02, 65];
            v.extend([0; 65]);
            v
        }),
    ]
}

fn scenes() -> Vec<Seed> {
    let mut out: Vec<Seed> = ["ball-roll", "ball-wall"]
        .iter()
        .filter_map(|name| {
            let scene = builtin::by_name(name).ok()?;
            Some(seed(&format!("valid-{name}.json"), scene.to_json()))
        })
        .collect();
    // A built-in stack, small: 100 steps of the larger ones take seconds each run.
    out.push(seed(
        "valid-tower-4.json",
        builtin::towers(1, 1, 4).to_json(),
    ));
    let mut two = builtin::ball_roll();
    two.bodies.truncate(2);
    two.steps = Some(10);
    out.push(seed("valid-two-bodies.json", two.to_json()));
    // The crate's example scenes: every shape kind, and a compound body.
    out.push(seed(
        "valid-example.json",
        include_str!("../../../host/physics/scenes/example.json"),
    ));
    out.push(seed(
        "valid-spinning-top.json",
        include_str!("../../../host/physics/scenes/spinning-top.json"),
    ));
    out.push(seed("edge-empty-object.json", "{}"));
    out.push(seed("edge-no-bodies.json", r#"{"effects":["gravity"]}"#));
    out
}

/// The standard table's TOML with `rods` copies of its first rod appended (a large
/// input for the runner's heap-cap test).
pub fn table_with_rods(rods: usize) -> Vec<u8> {
    let first_rod = STANDARD_TOML
        .split("[[rods]]")
        .nth(1)
        .map(|r| format!("[[rods]]{r}"))
        .unwrap_or_default();
    let mut text = STANDARD_TOML.to_string();
    for _ in 0..rods {
        text.push('\n');
        text.push_str(&first_rod);
    }
    text.into_bytes()
}

fn tables() -> Vec<Seed> {
    let mut narrow = Table::standard();
    narrow.name = "one rod".into();
    narrow.rods.truncate(1);
    vec![
        seed("valid-standard.toml", STANDARD_TOML),
        seed("valid-paper.toml", PAPER_TOML),
        seed("valid-standard-resaved.toml", Table::standard().to_toml()),
        seed("edge-one-rod.toml", narrow.to_toml()),
        seed(
            "edge-no-rods.toml",
            STANDARD_TOML
                .split("[[rods]]")
                .next()
                .unwrap_or(STANDARD_TOML),
        ),
    ]
}

fn calibrations() -> Vec<Seed> {
    let mut crosstalk = Calibration::default();
    for (i, p) in crosstalk.paddles.iter_mut().enumerate() {
        let gain = 1.0 + 0.01 * i as f64;
        p.matrix[0][0] *= gain;
        p.matrix[0][1] = 2e-6;
        p.matrix[1][0] = -3e-4;
        p.offset = [0.001 * i as f64, -0.02];
    }
    let mut singular = Calibration::default();
    singular.paddles[3] = PaddleCalibration {
        matrix: [[1e-4, 2e-4], [2e-4, 4e-4]],
        offset: [0.0, 0.0],
    };
    let default = Calibration::default().to_json();
    let seven = {
        let mut v: serde_json::Value =
            serde_json::from_str(&default).expect("the default calibration is JSON");
        if let Some(p) = v["paddles"].as_array_mut() {
            p.pop();
        }
        v.to_string()
    };
    vec![
        seed("valid-default.json", default.clone()),
        seed("valid-crosstalk.json", crosstalk.to_json()),
        seed("edge-singular.json", singular.to_json()),
        seed("edge-seven-paddles.json", seven),
        seed(
            "edge-version-2.json",
            default.replace("\"version\": 1", "\"version\": 2"),
        ),
    ]
}

fn recordings() -> Vec<Seed> {
    let table = Table::paper();
    let mut poses = Vec::new();
    if let Ok(mut game) = Match::new(MatchConfig::computer_vs_computer(table.clone(), 3)) {
        let idle = idle_inputs(&table);
        for _ in 0..60 {
            game.step(&idle);
        }
        poses.push(seed(
            "valid-computer-match.json",
            game.recording().to_json(),
        ));
    }
    let mut reports = MatchRecording::of_reports(9, table.clone(), RulesConfig::default());
    for sequence in 0..40 {
        reports.push_report(&moving_report(sequence));
    }
    let empty = MatchRecording::of_poses(1, table, RulesConfig::default());
    poses.push(seed("valid-reports.json", reports.to_json()));
    poses.push(seed("valid-empty.json", empty.to_json()));
    poses
}

fn motion_scripts() -> Vec<Seed> {
    vec![
        seed(
            "valid-demo.json",
            include_str!("../../../sim/scripts/demo.json"),
        ),
        seed("valid-empty.json", r#"{"rods":[]}"#),
        seed(
            "valid-limits.json",
            r#"{"rods":[{"rod":7,"start":{"axial_m":10.0,"angle_rad":-1e7},"segments":[{"move_to":{"duration_s":1e-9,"axial_m":-10.0,"angle_rad":1e7}},{"velocity":{"duration_s":0.01,"axial_m_per_s":100.0,"angle_rad_per_s":-10000.0}}]}]}"#,
        ),
        seed(
            "edge-rod-8.json",
            r#"{"rods":[{"rod":8,"segments":[{"hold":{"duration_s":1.0}}]}]}"#,
        ),
        seed(
            "edge-zero-duration.json",
            r#"{"rods":[{"rod":0,"segments":[{"hold":{"duration_s":0.0}}]}]}"#,
        ),
    ]
}

fn motion_recordings() -> Vec<Seed> {
    let samples: Vec<Sample> = (0..20u64)
        .map(|k| {
            let mut poses = [RodPose::default(); PADDLES];
            for (rod, pose) in poses.iter_mut().enumerate() {
                let t = k as f64 * 0.005;
                *pose = RodPose::new(0.05 * (t * rod as f64).sin(), 3.0 * t);
            }
            Sample {
                t_us: k * 5_000,
                poses,
            }
        })
        .collect();
    let file = |samples: Vec<Sample>| {
        serde_json::to_string(&RecordingFile {
            version: RECORDING_VERSION,
            samples,
        })
        .expect("a recording serialises")
    };
    let one = samples[..1].to_vec();
    let mut repeated = samples[..3].to_vec();
    repeated[2].t_us = repeated[1].t_us;
    vec![
        seed("valid-sine.json", file(samples)),
        seed("valid-one-sample.json", file(one)),
        seed("edge-repeated-time.json", file(repeated)),
        seed("edge-no-samples.json", file(Vec::new())),
    ]
}

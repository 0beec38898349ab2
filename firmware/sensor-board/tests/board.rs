//! The whole board: eight emulated mice → IN reports.

mod common;

use common::{FakeMouse, MS};
use foosball_protocol::{BoardSettings, InReport, PaddleStatus, PortSettings};
use sensor_board::{
    AxisMap, BoardConfig, DriverState, MouseAxis, MouseConfig, MousePacket, Ps2Frame, Resolution,
    SendError, SensorBoard, PORTS,
};

/// A board wired to eight emulated mice, stepped once per millisecond.
struct Bench {
    board: SensorBoard,
    mice: Vec<FakeMouse>,
    now: u64,
}

impl Bench {
    fn new(config: BoardConfig) -> Self {
        Self {
            board: SensorBoard::new(config),
            mice: (0..PORTS).map(|_| FakeMouse::new()).collect(),
            now: 0,
        }
    }

    /// One millisecond: deliver frames, poll every port, perform commands, report.
    fn tick(&mut self) -> InReport {
        self.now += MS;
        for (port, mouse) in self.mice.iter_mut().enumerate() {
            for byte in mouse.frames_due(self.now) {
                self.board.on_frame(port, self.now, Ps2Frame::encode(byte));
            }
            if let Some(command) = self.board.poll(port, self.now) {
                let result = mouse.command(self.now, command);
                self.board.on_command_sent(port, self.now, result);
            }
        }
        self.board.take_report(self.now)
    }

    /// Runs until every mouse is present (at most 2 s), returning the reports.
    fn bring_up(&mut self) -> Vec<InReport> {
        let mut reports = Vec::new();
        while self.board.present_mask() != 0xFF {
            assert!(self.now < 2_000 * MS, "bring-up took too long");
            reports.push(self.tick());
        }
        reports
    }
}

fn all_present(report: &InReport) -> bool {
    report
        .paddles
        .iter()
        .all(|p| p.status.contains(PaddleStatus::PRESENT))
}

#[test]
fn bring_up_reports_present_and_reinitialised_once() {
    let mut bench = Bench::new(BoardConfig::default());
    let reports = bench.bring_up();
    assert!(reports.len() > 500, "the self-test takes 500 ms");
    // Before: nobody present.
    assert!(reports[0]
        .paddles
        .iter()
        .all(|p| p.status == PaddleStatus::empty()));
    let last = reports.last().expect("reports");
    for paddle in &last.paddles {
        assert_eq!(
            paddle.status,
            PaddleStatus::PRESENT | PaddleStatus::REINITIALISED
        );
    }
    // REINITIALISED is for one report only.
    let next = bench.tick();
    assert!(next
        .paddles
        .iter()
        .all(|p| p.status == PaddleStatus::PRESENT));
}

#[test]
fn report_sequence_numbers_count_and_wrap() {
    let mut board = SensorBoard::default();
    for expected in 0..=u16::MAX {
        assert_eq!(board.take_report(0).sequence, expected);
    }
    assert_eq!(board.next_sequence(), 0);
    assert_eq!(board.take_report(0).sequence, 0, "wraps after 65535");
    assert_eq!(board.take_report(0).sequence, 1);
}

#[test]
fn unplugged_sensor_is_absent_within_100_ms_and_the_others_unaffected() {
    let mut bench = Bench::new(BoardConfig::default());
    bench.bring_up();
    bench.tick();
    // Some running for a second, with motion on the odd ports.
    for t in 0..1_000 {
        if t % 5 == 0 {
            for port in (1..PORTS).step_by(2) {
                let now = bench.now;
                bench.mice[port].move_by(now, 3, -2);
            }
        }
        assert!(all_present(&bench.tick()));
    }

    bench.mice[2].unplug();
    bench.mice[3].unplug(); // a moving one too
    let unplugged_at = bench.now;
    let mut absent_after = None;
    for _ in 0..150 {
        let report = bench.tick();
        for (port, paddle) in report.paddles.iter().enumerate() {
            if port == 2 || port == 3 {
                continue;
            }
            assert_eq!(paddle.status, PaddleStatus::PRESENT, "port {port}");
        }
        let gone = [2, 3]
            .iter()
            .all(|&p| !report.paddles[p].status.contains(PaddleStatus::PRESENT));
        if gone && absent_after.is_none() {
            absent_after = Some(bench.now - unplugged_at);
        }
    }
    let absent_after = absent_after.expect("reported absent");
    assert!(absent_after <= 100 * MS, "absent after {absent_after} µs");
    assert_eq!(
        bench.board.driver(2).map(|d| d.state()),
        Some(DriverState::Absent)
    );

    // Replugged: back initialised, flagged once.
    let now = bench.now;
    bench.mice[2].plug_in(now);
    bench.mice[3].plug_in(now);
    let mut reinitialised = [0; PORTS];
    for _ in 0..1_500 {
        let report = bench.tick();
        for (port, paddle) in report.paddles.iter().enumerate() {
            if paddle.status.contains(PaddleStatus::REINITIALISED) {
                reinitialised[port] += 1;
                assert!(paddle.status.contains(PaddleStatus::PRESENT));
            }
        }
    }
    assert_eq!(reinitialised, [0, 0, 1, 1, 0, 0, 0, 0]);
    assert_eq!(bench.board.present_mask(), 0xFF);
}

#[test]
fn axis_maps_are_per_port() {
    let mut config = BoardConfig::default();
    config.axis_maps[1] = AxisMap {
        axial: MouseAxis::Y,
        invert_axial: false,
        invert_rotation: false,
    };
    config.axis_maps[2] = AxisMap {
        axial: MouseAxis::X,
        invert_axial: true,
        invert_rotation: true,
    };
    config.axis_maps[3] = AxisMap {
        axial: MouseAxis::Y,
        invert_axial: true,
        invert_rotation: false,
    };
    let mut bench = Bench::new(config);
    bench.bring_up();
    bench.tick();
    for port in 0..4 {
        let now = bench.now;
        bench.mice[port].move_by(now, 10, -3);
    }
    let report = bench.tick();
    let motion: Vec<(i16, i16)> = report.paddles[..4]
        .iter()
        .map(|p| (p.axial, p.rotation))
        .collect();
    assert_eq!(motion, [(10, -3), (-3, 10), (-10, 3), (3, 10)]);
    assert!(report.paddles[4..]
        .iter()
        .all(|p| (p.axial, p.rotation) == (0, 0)));
}

#[test]
fn set_port_changes_one_ports_map_and_mouse_while_streaming() {
    let mut bench = Bench::new(BoardConfig::default());
    bench.bring_up();
    let map = AxisMap {
        axial: MouseAxis::Y,
        invert_axial: false,
        invert_rotation: true,
    };
    let mouse = MouseConfig {
        sample_rate: 100,
        resolution: Resolution::CountsPerMm4,
        ..MouseConfig::default()
    };
    bench.board.set_port(5, mouse, map);
    bench.board.set_port(PORTS, mouse, map); // out of range: ignored
    for _ in 0..50 {
        bench.tick();
    }
    assert_eq!(bench.mice[5].sample_rate, 100);
    assert_eq!(bench.mice[5].resolution, 2);
    assert_eq!(
        bench.mice[4].sample_rate, 200,
        "the other ports keep theirs"
    );
    assert_eq!(bench.board.driver(5).unwrap().config(), &mouse);
    assert_eq!(bench.board.config().axis_maps[5], map);
    assert!(bench.board.is_present(5), "streaming again");
    // Configured again without a reset: one more completed initialisation, no absence.
    let stats = bench.board.driver(5).unwrap().stats();
    assert_eq!(
        (stats.inits, stats.reconfigurations, stats.absences),
        (2, 1, 0)
    );
    for port in [4, 5] {
        let now = bench.now;
        bench.mice[port].move_by(now, 10, -3);
    }
    let mut sum = [(0, 0); 2];
    for _ in 0..20 {
        let report = bench.tick();
        for (s, p) in sum.iter_mut().zip(&report.paddles[4..6]) {
            s.0 += p.axial;
            s.1 += p.rotation;
        }
    }
    assert_eq!(sum, [(10, -3), (-3, -10)]);
}

#[test]
fn feature_report_views_of_the_board() {
    let mut bench = Bench::new(BoardConfig::default());
    assert_eq!(bench.board.settings(), BoardSettings::DEFAULT);
    bench.bring_up();
    let diag = bench.board.port_diagnostics(3).expect("port 3");
    assert!(diag.present);
    assert_eq!(diag.port, 3);
    assert_eq!(diag.counters.inits, 1);
    assert!(diag.counters.frames > 0);
    assert_eq!(bench.board.port_diagnostics(8), None);

    let mut settings = BoardSettings::DEFAULT;
    settings.ports[6] = PortSettings {
        axial_is_y: true,
        invert_axial: true,
        invert_rotation: false,
        resolution_code: 1,
        sample_rate: 40,
    };
    bench.board.apply_settings(&settings);
    assert_eq!(bench.board.settings(), settings);
    for _ in 0..50 {
        bench.tick();
    }
    assert_eq!(
        (bench.mice[6].sample_rate, bench.mice[6].resolution),
        (40, 1)
    );
}

#[test]
fn overflow_flags_follow_the_axis_map() {
    let mut config = BoardConfig::default();
    config.axis_maps[1].axial = MouseAxis::Y;
    let mut bench = Bench::new(config);
    bench.bring_up();
    bench.tick();
    // X overflow on ports 0 and 1.
    let bytes = MousePacket {
        dx: 255,
        x_overflow: true,
        ..MousePacket::default()
    }
    .to_bytes();
    for port in 0..2 {
        for byte in bytes {
            bench
                .board
                .on_frame(port, bench.now, Ps2Frame::encode(byte));
        }
    }
    let report = bench.board.take_report(bench.now);
    assert!(report.paddles[0]
        .status
        .contains(PaddleStatus::AXIAL_OVERFLOW));
    assert!(!report.paddles[0]
        .status
        .contains(PaddleStatus::ROTATION_OVERFLOW));
    assert!(report.paddles[1]
        .status
        .contains(PaddleStatus::ROTATION_OVERFLOW));
    assert!(!report.paddles[1]
        .status
        .contains(PaddleStatus::AXIAL_OVERFLOW));
    assert_eq!(report.paddles[0].axial, 255);
    assert_eq!(report.paddles[1].rotation, 255);
}

#[test]
fn accumulators_saturate_between_reports_and_drain() {
    let mut bench = Bench::new(BoardConfig::default());
    bench.bring_up();
    bench.tick();
    let bytes = MousePacket {
        dx: 255,
        dy: -256,
        ..MousePacket::default()
    }
    .to_bytes();
    // 200 packets between two reports: 51 000 counts, beyond i16.
    for _ in 0..200 {
        for byte in bytes {
            bench.board.on_frame(5, bench.now, Ps2Frame::encode(byte));
        }
    }
    let report = bench.board.take_report(bench.now);
    let paddle = report.paddles[5];
    assert_eq!((paddle.axial, paddle.rotation), (i16::MAX, i16::MIN));
    assert!(paddle.status.contains(PaddleStatus::SATURATED));
    assert!(paddle.status.contains(PaddleStatus::PRESENT));
    // Drained: the next report is empty again.
    let paddle = bench.board.take_report(bench.now).paddles[5];
    assert_eq!((paddle.axial, paddle.rotation), (0, 0));
    assert_eq!(paddle.status, PaddleStatus::PRESENT);
}

#[test]
fn frame_errors_flag_only_their_port_for_one_report() {
    let mut bench = Bench::new(BoardConfig::default());
    bench.bring_up();
    bench.tick();
    let parity = Ps2Frame::from_raw(Ps2Frame::encode(0x08).raw() ^ (1 << 9));
    let framing = Ps2Frame::from_raw(Ps2Frame::encode(0x08).raw() | 1);
    bench.board.on_frame(4, bench.now, parity);
    bench.board.on_frame(6, bench.now, framing);
    let report = bench.board.take_report(bench.now);
    for (port, paddle) in report.paddles.iter().enumerate() {
        let expected = match port {
            4 => PaddleStatus::PRESENT | PaddleStatus::PARITY_ERROR,
            6 => PaddleStatus::PRESENT | PaddleStatus::FRAMING_ERROR,
            _ => PaddleStatus::PRESENT,
        };
        assert_eq!(paddle.status, expected, "port {port}");
    }
    assert!(all_present(&bench.board.take_report(bench.now)));
    assert!(bench
        .board
        .take_report(bench.now)
        .paddles
        .iter()
        .all(|p| p.status == PaddleStatus::PRESENT));
}

#[test]
fn motion_is_reported_once() {
    let mut bench = Bench::new(BoardConfig::default());
    bench.bring_up();
    bench.tick();
    let now = bench.now;
    bench.mice[0].move_by(now, 7, 1);
    let mut total = (0i32, 0i32);
    for _ in 0..10 {
        let p = bench.tick().paddles[0];
        total.0 += i32::from(p.axial);
        total.1 += i32::from(p.rotation);
    }
    assert_eq!(total, (7, 1));
}

#[test]
fn ports_out_of_range_are_ignored() {
    let mut board = SensorBoard::default();
    board.on_frame(PORTS, 0, Ps2Frame::encode(0xAA));
    board.on_frame(usize::MAX, 0, Ps2Frame::encode(0x00));
    assert_eq!(board.poll(PORTS, 0), None);
    assert_eq!(board.poll(usize::MAX, 0), None);
    board.on_command_sent(PORTS, 0, Err(SendError::NoAck));
    assert!(board.driver(PORTS).is_none());
    assert!(board.accumulator(PORTS).is_none());
    assert!(!board.is_present(PORTS));
    // The real ports are untouched.
    assert_eq!(board.poll(0, 0), Some(0xFF));
}

#[test]
fn mouse_config_reaches_every_driver() {
    let mut config = BoardConfig::default();
    config.mouse.sample_rate = 80;
    let mut board = SensorBoard::new(config);
    for port in 0..PORTS {
        assert_eq!(board.driver(port).map(|d| d.config().sample_rate), Some(80));
        assert_eq!(board.poll(port, 0), Some(0xFF));
    }
    assert_eq!(board.config().mouse.sample_rate, 80);
}

/// A report that was snapshot but never committed loses nothing; one that was
/// committed removes exactly what it carried, and motion after the snapshot stays.
#[test]
fn snapshot_commit_removes_only_what_was_sent() {
    let mut bench = Bench::new(BoardConfig::default());
    bench.bring_up();
    bench.tick();
    let packet = |board: &mut SensorBoard, dx: i16, dy: i16| {
        let bytes = MousePacket {
            dx,
            dy,
            ..MousePacket::default()
        }
        .to_bytes();
        for byte in bytes {
            board.on_frame(0, 0, Ps2Frame::encode(byte));
        }
    };
    packet(&mut bench.board, 10, 4);
    let unsent = bench.board.snapshot_report(bench.now);
    packet(&mut bench.board, 3, -1);
    let sent = bench.board.snapshot_report(bench.now);
    assert_eq!(
        unsent.sequence, sent.sequence,
        "a refreshed report keeps its number"
    );
    assert_eq!((sent.paddles[0].axial, sent.paddles[0].rotation), (13, 3));
    packet(&mut bench.board, 5, 2);
    bench.board.commit(&sent);
    let next = bench.board.take_report(bench.now);
    assert_eq!(next.sequence, sent.sequence.wrapping_add(1));
    assert_eq!((next.paddles[0].axial, next.paddles[0].rotation), (5, 2));
    assert_eq!(next.paddles[0].status, PaddleStatus::PRESENT);
}

/// The version 2 snapshot: the v1 motion, the device time, each paddle's newest
/// packet age (none yet: `PacketAge::NONE`) and its dropped count.
#[test]
fn v2_snapshot_carries_time_packet_age_and_drops() {
    use foosball_protocol::PacketAge;
    let mut bench = Bench::new(BoardConfig::default());
    bench.bring_up();
    bench.tick();
    let packet = MousePacket {
        dx: 9,
        ..MousePacket::default()
    }
    .to_bytes();
    let at = bench.now;
    for byte in packet {
        bench.board.on_frame(2, at, Ps2Frame::encode(byte));
    }
    let report = bench.board.snapshot_report_v2(at + 1_234);
    assert_eq!(report.report.paddles[2].axial, 9);
    assert_eq!(report.timing.device_time_us, (at + 1_234) as u32);
    assert_eq!(
        report.timing.paddles[2].newest_packet_age.as_micros(),
        Some(1_200)
    );
    assert_eq!(report.timing.paddles[0].newest_packet_age, PacketAge::NONE);
    assert_eq!(report.timing.paddles[2].dropped, 0);
    // Committing the v2 snapshot's motion drains it like a v1 report.
    bench.board.commit(&report.report);
    assert_eq!(bench.board.take_report(at + 2_000).paddles[2].axial, 0);
}

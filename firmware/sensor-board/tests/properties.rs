//! Property tests: arbitrary frames, bytes, send outcomes and timestamps never make the
//! driver or the board panic, keep their invariants, and never stop a well-behaved
//! mouse from being initialised afterwards.

mod common;

use common::{step, FakeMouse, MS};
use foosball_protocol::{InReport, PaddleStatus};
use proptest::prelude::*;
use sensor_board::{
    DriverState, MouseConfig, MouseDriver, Ps2Frame, Resolution, SendError, SensorBoard,
};

#[derive(Debug, Clone)]
enum Op {
    /// Any 16 bits as a frame (mostly garbage).
    Frame(u16),
    /// A well-formed frame carrying a byte.
    Byte(u8),
    /// A byte the driver is likely to care about.
    Interesting(u8),
    Poll,
    Sent(Option<SendError>),
    /// Time moves on a little.
    Advance(u64),
    /// Time jumps anywhere (backwards included).
    Jump(u64),
}

fn send_error() -> impl Strategy<Value = Option<SendError>> {
    prop_oneof![
        Just(None),
        Just(Some(SendError::NoClock)),
        Just(Some(SendError::Timeout)),
        Just(Some(SendError::NoAck)),
    ]
}

fn op(max_time: u64) -> impl Strategy<Value = Op> {
    prop_oneof![
        3 => any::<u16>().prop_map(Op::Frame),
        3 => any::<u8>().prop_map(Op::Byte),
        3 => prop::sample::select(vec![0xFA, 0xFE, 0xFC, 0xAA, 0x00, 0x08, 0x18, 0x28, 0xC8])
            .prop_map(Op::Interesting),
        4 => Just(Op::Poll),
        2 => send_error().prop_map(Op::Sent),
        3 => (0..100 * MS).prop_map(Op::Advance),
        1 => (0..=max_time).prop_map(Op::Jump),
    ]
}

fn config() -> impl Strategy<Value = MouseConfig> {
    (
        any::<u8>(),
        0..4u8,
        prop_oneof![Just(0), Just(u64::MAX), 0..5_000_000u64],
        prop_oneof![Just(0), Just(u64::MAX), 0..100_000u64],
        prop_oneof![Just(0), Just(u64::MAX), 0..100_000u64],
        prop_oneof![Just(0), Just(u64::MAX), 0..200_000u64],
    )
        .prop_map(
            |(sample_rate, code, self_test, send, reply, probe)| MouseConfig {
                sample_rate,
                resolution: Resolution::from_code(code).unwrap_or_default(),
                self_test_timeout_us: self_test,
                send_timeout_us: send,
                reply_timeout_us: reply,
                probe_after_us: probe,
            },
        )
}

/// Applies `ops` to `driver`, checking invariants; returns the last time used.
fn apply(driver: &mut MouseDriver, ops: &[Op]) -> u64 {
    let mut now = 0u64;
    let mut latest = 0u64;
    for op in ops {
        match *op {
            Op::Frame(raw) => {
                let packet = driver.on_frame(now, Ps2Frame::from_raw(raw));
                check_packet(driver, packet.is_some());
            }
            Op::Byte(byte) | Op::Interesting(byte) => {
                let packet = driver.on_byte(now, byte);
                check_packet(driver, packet.is_some());
            }
            Op::Poll => {
                if driver.poll(now).is_some() && driver.config().send_timeout_us > 0 {
                    assert_eq!(driver.poll(now), None, "one command at a time");
                }
            }
            Op::Sent(error) => driver.on_command_sent(now, error.map_or(Ok(()), Err)),
            Op::Advance(us) => now = now.saturating_add(us),
            Op::Jump(to) => now = to,
        }
        latest = latest.max(now);
        assert_eq!(
            driver.is_present(),
            driver.state() == DriverState::Streaming
        );
    }
    latest
}

fn check_packet(driver: &MouseDriver, got_packet: bool) {
    if got_packet {
        assert_eq!(
            driver.state(),
            DriverState::Streaming,
            "packets only when streaming"
        );
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 2_000, ..ProptestConfig::default() })]

    #[test]
    fn driver_never_panics(config in config(), ops in prop::collection::vec(op(u64::MAX), 0..300)) {
        let mut driver = MouseDriver::new(config);
        apply(&mut driver, &ops);
        let _ = driver.take_events();
        let _ = driver.stats();
    }

    #[test]
    fn well_behaved_mouse_recovers_from_any_garbage(
        ops in prop::collection::vec(op(1 << 40), 0..300),
    ) {
        let mut driver = MouseDriver::new(MouseConfig::default());
        let start = apply(&mut driver, &ops) + 1_000 * MS;
        let mut mouse = FakeMouse::new();
        mouse.plug_in(start);
        let mut now = start;
        while now < start + 3_000 * MS && !(driver.is_present() && mouse.is_streaming()) {
            now += MS;
            step(&mut driver, &mut mouse, now);
        }
        prop_assert!(driver.is_present(), "state {:?}", driver.state());
        prop_assert!(mouse.is_streaming());
        prop_assert_eq!(mouse.sample_rate, 200);
        prop_assert_eq!(mouse.resolution, 3);
    }

    #[test]
    fn frames_decode_exactly_when_well_formed(raw in any::<u16>()) {
        let frame = Ps2Frame::from_raw(raw);
        match frame.decode() {
            Ok(byte) => prop_assert_eq!(Ps2Frame::encode(byte), frame),
            Err(_) => prop_assert!((0..=255u8).all(|b| Ps2Frame::encode(b) != frame)),
        }
    }

    #[test]
    fn board_never_panics_and_reports_stay_valid(
        ops in prop::collection::vec((0..10usize, op(u64::MAX), any::<bool>()), 0..400),
    ) {
        let mut board = SensorBoard::default();
        let mut now = 0u64;
        let mut sequence = 0u16;
        for (port, op, report) in ops {
            match op {
                Op::Frame(raw) => board.on_frame(port, now, Ps2Frame::from_raw(raw)),
                Op::Byte(byte) | Op::Interesting(byte) => {
                    board.on_frame(port, now, Ps2Frame::encode(byte));
                }
                Op::Poll => {
                    let _ = board.poll(port, now);
                }
                Op::Sent(error) => board.on_command_sent(port, now, error.map_or(Ok(()), Err)),
                Op::Advance(us) => now = now.saturating_add(us),
                Op::Jump(to) => now = to,
            }
            if report {
                let report = board.take_report(now);
                prop_assert_eq!(report.sequence, sequence);
                sequence = sequence.wrapping_add(1);
                prop_assert_eq!(InReport::decode(&report.to_bytes()), Ok(report));
                for (port, paddle) in report.paddles.iter().enumerate() {
                    prop_assert_eq!(
                        paddle.status.contains(PaddleStatus::PRESENT),
                        board.is_present(port)
                    );
                }
            }
        }
    }
}

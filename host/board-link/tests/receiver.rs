//! `ReportReceiver`: sequence-gap counting and malformed-report handling.

use board_link::{BoardError, LinkStats, ReportReceiver};
use foosball_protocol::{
    DecodeError, InReport, PaddleMotion, PaddleStatus, FORMAT_VERSION, IN_REPORT_LEN,
};
use proptest::prelude::*;

fn bytes(sequence: u16) -> [u8; IN_REPORT_LEN] {
    InReport {
        sequence,
        ..InReport::default()
    }
    .to_bytes()
}

fn feed(receiver: &mut ReportReceiver, sequences: &[u16]) {
    for &sequence in sequences {
        let report = receiver.accept(&bytes(sequence)).expect("good report");
        assert_eq!(report.sequence, sequence);
    }
}

#[test]
fn consecutive_reports_lose_nothing() {
    let mut receiver = ReportReceiver::new();
    feed(&mut receiver, &[0, 1, 2, 3, 4]);
    assert_eq!(
        receiver.stats(),
        LinkStats {
            received: 5,
            ..LinkStats::default()
        }
    );
    assert_eq!(receiver.expected_sequence(), Some(5));
}

#[test]
fn gaps_count_the_missing_reports() {
    let mut receiver = ReportReceiver::new();
    feed(&mut receiver, &[100, 101, 105, 106, 110]);
    assert_eq!(receiver.stats().lost, 3 + 3);
    assert_eq!(receiver.stats().received, 5);
}

#[test]
fn sequence_wraps_from_65535_to_0() {
    let mut receiver = ReportReceiver::new();
    feed(&mut receiver, &[65534, 65535, 0, 1]);
    assert_eq!(receiver.stats().lost, 0);
    // A gap across the wrap: 65535 → 2 misses 0 and 1.
    let mut receiver = ReportReceiver::new();
    feed(&mut receiver, &[65534, 65535, 2]);
    assert_eq!(receiver.stats().lost, 2);
    let mut receiver = ReportReceiver::new();
    feed(&mut receiver, &[65533, 1]);
    assert_eq!(receiver.stats().lost, 3);
}

#[test]
fn reconnect_is_not_counted_as_loss() {
    let mut receiver = ReportReceiver::new();
    feed(&mut receiver, &[10, 11, 12]);
    receiver.note_reconnect();
    assert_eq!(receiver.expected_sequence(), None);
    feed(&mut receiver, &[40_000, 40_001]);
    let stats = receiver.stats();
    assert_eq!((stats.lost, stats.reconnects, stats.received), (0, 1, 5));
    // Counting resumes after the reconnect.
    feed(&mut receiver, &[40_003]);
    assert_eq!(receiver.stats().lost, 1);
}

#[test]
fn duplicates_and_backward_jumps_resynchronise_without_loss() {
    let mut receiver = ReportReceiver::new();
    feed(&mut receiver, &[500, 500, 3, 4]);
    assert_eq!(receiver.stats().lost, 0);
    assert_eq!(receiver.stats().received, 4);
}

fn expect_malformed(receiver: &mut ReportReceiver, bytes: &[u8]) -> DecodeError {
    match receiver.accept(bytes) {
        Err(BoardError::Malformed(e)) => e,
        other => panic!("expected Malformed, got {other:?}"),
    }
}

#[test]
fn malformed_reports_are_rejected_naming_the_problem_and_play_goes_on() {
    let mut receiver = ReportReceiver::new();
    feed(&mut receiver, &[1]);

    let truncated = &bytes(2)[..IN_REPORT_LEN - 1];
    let error = expect_malformed(&mut receiver, truncated);
    assert_eq!(
        error,
        DecodeError::WrongLength {
            expected: IN_REPORT_LEN,
            actual: IN_REPORT_LEN - 1
        }
    );
    let message = BoardError::Malformed(error).to_string();
    assert!(message.contains("wrong report length"), "{message}");

    assert!(matches!(
        expect_malformed(&mut receiver, &[]),
        DecodeError::WrongLength { actual: 0, .. }
    ));

    // Version 3 is unknown; version 2 at version 1's length is a short v2 report.
    let mut wrong_version = bytes(2);
    wrong_version[0] = FORMAT_VERSION + 2;
    assert!(matches!(
        expect_malformed(&mut receiver, &wrong_version),
        DecodeError::UnknownVersion { found, .. } if found == FORMAT_VERSION + 2
    ));
    wrong_version[0] = FORMAT_VERSION + 1;
    assert_eq!(
        expect_malformed(&mut receiver, &wrong_version),
        DecodeError::WrongLength {
            expected: foosball_protocol::IN_REPORT_V2_LEN,
            actual: IN_REPORT_LEN
        }
    );

    let mut bad_status = bytes(2);
    bad_status[3 + 5 * 3 + 4] = 0x80;
    let error = expect_malformed(&mut receiver, &bad_status);
    assert_eq!(
        error,
        DecodeError::BadField {
            field: "status",
            paddle: Some(3),
            value: 0x80
        }
    );
    assert!(BoardError::Malformed(error).to_string().contains("status"));

    // The next good report is accepted; the dropped ones are not double-counted as
    // lost beyond their sequence gap.
    let mut good = InReport {
        sequence: 2,
        ..InReport::default()
    };
    good.paddles[3] = PaddleMotion {
        axial: -300,
        rotation: 12,
        status: PaddleStatus::PRESENT,
    };
    assert_eq!(receiver.accept(&good.to_bytes()).unwrap(), good);
    let stats = receiver.stats();
    assert_eq!((stats.received, stats.malformed, stats.lost), (2, 5, 0));
}

proptest! {
    #[test]
    fn arbitrary_bytes_never_panic(data in proptest::collection::vec(any::<u8>(), 0..100)) {
        let mut receiver = ReportReceiver::new();
        let accepted = receiver.accept(&data).is_ok();
        let stats = receiver.stats();
        prop_assert_eq!(stats.received + stats.malformed, 1);
        prop_assert_eq!(accepted, stats.received == 1);
    }

    #[test]
    fn lost_is_the_sum_of_forward_gaps(steps in proptest::collection::vec(1u16..2000, 1..200), start: u16) {
        let mut receiver = ReportReceiver::new();
        let mut sequence = start;
        receiver.accept(&bytes(sequence)).unwrap();
        let mut expected_lost = 0u64;
        for step in steps {
            sequence = sequence.wrapping_add(step);
            expected_lost += u64::from(step - 1);
            receiver.accept(&bytes(sequence)).unwrap();
        }
        prop_assert_eq!(receiver.stats().lost, expected_lost);
    }
}

/// A version 2 board: the motion as from version 1, the timing kept; a version 1
/// report after it clears the timing (a v1 board reconnected in its place).
#[test]
fn reads_version_2_reports_and_keeps_their_timing() {
    use foosball_protocol::{InReportV2, PacketAge, PaddleTiming, ReportTiming};
    let mut receiver = ReportReceiver::new();
    let mut v2 = InReportV2::default();
    v2.report.sequence = 5;
    v2.report.paddles[3] = PaddleMotion {
        axial: 12,
        rotation: -4,
        status: PaddleStatus::PRESENT,
    };
    v2.timing = ReportTiming {
        device_time_us: 1_234_567,
        paddles: [PaddleTiming {
            newest_packet_age: PacketAge::from_micros(800),
            dropped: 2,
        }; 8],
    };
    let report = receiver.accept(&v2.to_bytes()).expect("v2 report");
    assert_eq!(report, v2.report);
    assert_eq!(receiver.last_timing(), Some(v2.timing));
    let report = receiver.accept(&bytes(6)).expect("v1 report");
    assert_eq!(report.sequence, 6);
    assert_eq!(receiver.last_timing(), None);
    assert_eq!(receiver.stats().lost, 0);
    assert_eq!(receiver.stats().malformed, 0);
}

//! The version 2 IN report: round trips, typed errors, arbitrary input, and the
//! decoder that reads either version.

use foosball_protocol::*;
use proptest::prelude::*;

fn status() -> impl Strategy<Value = PaddleStatus> {
    (0..=PaddleStatus::KNOWN_BITS).prop_map(|b| PaddleStatus::from_bits(b).unwrap())
}

fn paddle() -> impl Strategy<Value = PaddleMotion> {
    (any::<i16>(), any::<i16>(), status()).prop_map(|(axial, rotation, status)| PaddleMotion {
        axial,
        rotation,
        status,
    })
}

fn timing() -> impl Strategy<Value = PaddleTiming> {
    (any::<u8>(), any::<u8>()).prop_map(|(age, dropped)| PaddleTiming {
        newest_packet_age: PacketAge::from_raw(age),
        dropped,
    })
}

fn v2() -> impl Strategy<Value = InReportV2> {
    (
        any::<u16>(),
        proptest::array::uniform8(paddle()),
        any::<u32>(),
        proptest::array::uniform8(timing()),
    )
        .prop_map(|(sequence, paddles, device_time_us, timings)| InReportV2 {
            report: InReport { sequence, paddles },
            timing: ReportTiming {
                device_time_us,
                paddles: timings,
            },
        })
}

proptest! {
    #[test]
    fn v2_round_trips(report in v2()) {
        let bytes = report.to_bytes();
        prop_assert_eq!(bytes.len(), IN_REPORT_V2_LEN);
        prop_assert_eq!(InReportV2::decode(&bytes), Ok(report));
        prop_assert_eq!(decode_in_report(&bytes), Ok((report.report, Some(report.timing))));
    }

    #[test]
    fn v1_still_decodes_without_timing(report in v2()) {
        let bytes = report.report.to_bytes();
        prop_assert_eq!(decode_in_report(&bytes), Ok((report.report, None)));
    }

    #[test]
    fn arbitrary_bytes_never_panic(bytes in proptest::collection::vec(any::<u8>(), 0..80)) {
        let _ = InReportV2::decode(&bytes);
        let _ = decode_in_report(&bytes);
    }

    #[test]
    fn arbitrary_bytes_of_the_v2_length_decode_or_name_the_field(
        mut bytes in proptest::collection::vec(any::<u8>(), IN_REPORT_V2_LEN)
    ) {
        bytes[0] = IN_REPORT_V2_VERSION;
        match InReportV2::decode(&bytes) {
            Ok(report) => prop_assert_eq!(report.to_bytes().to_vec(), bytes),
            Err(DecodeError::BadField { field: "status", paddle: Some(p), value }) => {
                prop_assert!(p < 8);
                prop_assert_eq!(value, bytes[7 + 7 * usize::from(p) + 4]);
                prop_assert!(value & !PaddleStatus::KNOWN_BITS != 0);
            }
            Err(other) => prop_assert!(false, "unexpected {other:?}"),
        }
    }

    #[test]
    fn packet_age_rounds_down_to_its_step(age_us in 0u64..30_000) {
        let age = PacketAge::from_micros(age_us);
        match age.as_micros() {
            Some(us) => {
                prop_assert!(u64::from(us) <= age_us && age_us - u64::from(us) < 100);
            }
            None => prop_assert!(age_us >= 25_500),
        }
    }
}

#[test]
fn v2_fits_one_full_speed_packet() {
    assert_eq!(IN_REPORT_V2_LEN, 63);
    const { assert!(IN_REPORT_V2_LEN <= usb::ENDPOINT_MAX_PACKET as usize) };
}

#[test]
fn v2_layout_is_as_documented() {
    let mut report = InReportV2::default();
    report.report.sequence = 0x1234;
    report.timing.device_time_us = 0xA1B2_C3D4;
    report.report.paddles[1] = PaddleMotion {
        axial: -2,
        rotation: 0x0102,
        status: PaddleStatus::PRESENT,
    };
    report.timing.paddles[1] = PaddleTiming {
        newest_packet_age: PacketAge::from_micros(1_250),
        dropped: 7,
    };
    let bytes = report.to_bytes();
    assert_eq!(&bytes[..7], &[2, 0x34, 0x12, 0xD4, 0xC3, 0xB2, 0xA1]);
    assert_eq!(&bytes[14..21], &[0xFE, 0xFF, 0x02, 0x01, 0x01, 12, 7]);
}

#[test]
fn wrong_lengths_and_versions_are_named() {
    let bytes = InReportV2::default().to_bytes();
    assert_eq!(
        InReportV2::decode(&bytes[..IN_REPORT_V2_LEN - 1]),
        Err(DecodeError::WrongLength {
            expected: IN_REPORT_V2_LEN,
            actual: IN_REPORT_V2_LEN - 1
        })
    );
    // A v1-length report with version 2 is a wrong-length v2 report.
    let mut short = [0u8; IN_REPORT_LEN];
    short[0] = IN_REPORT_V2_VERSION;
    assert_eq!(
        decode_in_report(&short),
        Err(DecodeError::WrongLength {
            expected: IN_REPORT_V2_LEN,
            actual: IN_REPORT_LEN
        })
    );
    let mut v3 = bytes;
    v3[0] = 3;
    assert_eq!(
        decode_in_report(&v3),
        Err(DecodeError::UnknownVersion {
            found: 3,
            supported: IN_REPORT_V2_VERSION
        })
    );
    assert_eq!(
        InReportV2::decode(&InReport::default().to_bytes()),
        Err(DecodeError::WrongLength {
            expected: IN_REPORT_V2_LEN,
            actual: IN_REPORT_LEN
        })
    );
    assert_eq!(
        decode_in_report(&[]),
        Err(DecodeError::WrongLength {
            expected: IN_REPORT_LEN,
            actual: 0
        })
    );
}

#[test]
fn packet_age_limits() {
    assert_eq!(PacketAge::from_micros(0).as_micros(), Some(0));
    assert_eq!(PacketAge::from_micros(25_399).as_micros(), Some(25_300));
    assert_eq!(PacketAge::from_micros(25_499).as_micros(), Some(25_400));
    assert_eq!(PacketAge::from_micros(25_500), PacketAge::NONE);
    assert_eq!(PacketAge::from_micros(u64::MAX), PacketAge::NONE);
    assert_eq!(PacketAge::NONE.as_micros(), None);
}

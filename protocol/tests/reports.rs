//! Round trips, typed decode errors and arbitrary input for both reports.

use foosball_protocol::usb::HID_REPORT_DESCRIPTOR;
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

fn in_report() -> impl Strategy<Value = InReport> {
    (any::<u16>(), proptest::array::uniform8(paddle()))
        .prop_map(|(sequence, paddles)| InReport { sequence, paddles })
}

fn led() -> impl Strategy<Value = LedState> {
    prop_oneof![
        Just(LedState::Off),
        Just(LedState::On),
        Just(LedState::SlowBlink),
        Just(LedState::FastBlink)
    ]
}

fn out_report() -> impl Strategy<Value = OutReport> {
    (proptest::array::uniform8((any::<u8>(), any::<u8>())), led()).prop_map(|(pulses, led)| {
        OutReport {
            haptics: pulses.map(|(strength, duration_ms)| HapticPulse {
                strength,
                duration_ms,
            }),
            led,
        }
    })
}

proptest! {
    #[test]
    fn in_report_round_trips(report in in_report()) {
        let bytes = report.to_bytes();
        prop_assert_eq!(bytes.len(), IN_REPORT_LEN);
        prop_assert_eq!(InReport::decode(&bytes), Ok(report));
    }

    #[test]
    fn out_report_round_trips(report in out_report()) {
        let bytes = report.to_bytes();
        prop_assert_eq!(OutReport::decode(&bytes), Ok(report));
    }

    #[test]
    fn arbitrary_bytes_never_panic(bytes in proptest::collection::vec(any::<u8>(), 0..80)) {
        // Either a typed error or a report that re-encodes to the same bytes.
        if let Ok(report) = InReport::decode(&bytes) {
            prop_assert_eq!(&report.to_bytes()[..], &bytes[..]);
        }
        if let Ok(report) = OutReport::decode(&bytes) {
            prop_assert_eq!(&report.to_bytes()[..], &bytes[..]);
        }
    }

    #[test]
    fn version_byte_is_checked(report in in_report(), version in any::<u8>()) {
        let mut bytes = report.to_bytes();
        bytes[0] = version;
        let decoded = InReport::decode(&bytes);
        if version == FORMAT_VERSION {
            prop_assert!(decoded.is_ok());
        } else {
            prop_assert_eq!(decoded, Err(DecodeError::UnknownVersion { found: version, supported: FORMAT_VERSION }));
        }
    }
}

#[test]
fn wrong_lengths_are_typed_errors() {
    let bytes = InReport::default().to_bytes();
    assert_eq!(
        InReport::decode(&bytes[..IN_REPORT_LEN - 1]),
        Err(DecodeError::WrongLength {
            expected: IN_REPORT_LEN,
            actual: IN_REPORT_LEN - 1
        })
    );
    assert_eq!(
        InReport::decode(&[]),
        Err(DecodeError::WrongLength {
            expected: IN_REPORT_LEN,
            actual: 0
        })
    );
    let mut long = [0u8; OUT_REPORT_LEN + 1];
    long[0] = FORMAT_VERSION;
    assert_eq!(
        OutReport::decode(&long),
        Err(DecodeError::WrongLength {
            expected: OUT_REPORT_LEN,
            actual: OUT_REPORT_LEN + 1
        })
    );
}

#[test]
fn unknown_status_bits_name_the_paddle() {
    let mut bytes = InReport::default().to_bytes();
    bytes[3 + 5 * 6 + 4] = 0x80;
    assert_eq!(
        InReport::decode(&bytes),
        Err(DecodeError::BadField {
            field: "status",
            paddle: Some(6),
            value: 0x80
        })
    );
}

#[test]
fn undefined_led_state_is_rejected() {
    let mut bytes = OutReport::default().to_bytes();
    bytes[OUT_REPORT_LEN - 1] = 7;
    let err = OutReport::decode(&bytes).unwrap_err();
    assert_eq!(
        err,
        DecodeError::BadField {
            field: "led",
            paddle: None,
            value: 7
        }
    );
    // The message names the field.
    assert!(err.to_string().contains("led"), "{err}");
}

#[test]
fn encode_into_short_buffer_fails() {
    let mut buf = [0u8; 10];
    assert_eq!(
        InReport::default().encode(&mut buf),
        Err(EncodeError::BufferTooSmall {
            needed: IN_REPORT_LEN,
            available: 10
        })
    );
    assert!(OutReport::default().encode(&mut buf).is_err());
}

#[test]
fn layout_is_little_endian_at_documented_offsets() {
    let mut report = InReport {
        sequence: 0x1234,
        ..Default::default()
    };
    report.paddles[1] = PaddleMotion {
        axial: -2,
        rotation: 0x0102,
        status: PaddleStatus::PRESENT | PaddleStatus::PARITY_ERROR,
    };
    let bytes = report.to_bytes();
    assert_eq!(&bytes[..3], &[FORMAT_VERSION, 0x34, 0x12]);
    assert_eq!(&bytes[8..13], &[0xFE, 0xFF, 0x02, 0x01, 0x11]);
}

/// Walks the short items of the HID descriptor and returns the byte counts of the
/// input and output reports it declares.
fn declared_report_sizes(descriptor: &[u8]) -> (usize, usize) {
    let (mut size_bits, mut count, mut input, mut output) = (0usize, 0usize, 0usize, 0usize);
    let mut i = 0;
    while i < descriptor.len() {
        let prefix = descriptor[i];
        let len = match prefix & 0x03 {
            3 => 4,
            n => n as usize,
        };
        let mut value = 0usize;
        for k in 0..len {
            value |= (descriptor[i + 1 + k] as usize) << (8 * k);
        }
        match prefix & 0xFC {
            0x74 => size_bits = value,
            0x94 => count = value,
            0x80 => input += size_bits * count / 8,
            0x90 => output += size_bits * count / 8,
            _ => {}
        }
        i += 1 + len;
    }
    (input, output)
}

#[test]
fn hid_descriptor_declares_the_report_lengths() {
    assert_eq!(
        declared_report_sizes(HID_REPORT_DESCRIPTOR),
        (IN_REPORT_V2_LEN, OUT_REPORT_LEN)
    );
    // Vendor-defined usage page, so no OS driver claims the board as a mouse.
    assert_eq!(&HID_REPORT_DESCRIPTOR[..3], &[0x06, 0x00, 0xFF]);
}

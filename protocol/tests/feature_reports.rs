//! Feature reports: round trips of every kind, typed errors, arbitrary input, and
//! the HID descriptor declaring them.

use foosball_protocol::usb::HID_REPORT_DESCRIPTOR;
use foosball_protocol::*;
use proptest::prelude::*;

fn counters() -> impl Strategy<Value = PortCounters> {
    proptest::array::uniform12(any::<u32>()).prop_map(|c| PortCounters {
        frames: c[0],
        packets: c[1],
        framing_errors: c[2],
        parity_errors: c[3],
        resends: c[4],
        dropped: c[5],
        retries: c[6],
        absences: c[7],
        inits: c[8],
        restarts: c[9],
        fifo_stalls: c[10],
        line_faults: c[11],
    })
}

fn port_settings() -> impl Strategy<Value = PortSettings> {
    (
        any::<bool>(),
        any::<bool>(),
        any::<bool>(),
        0u8..=3,
        proptest::sample::select(SAMPLE_RATES.to_vec()),
    )
        .prop_map(
            |(axial_is_y, invert_axial, invert_rotation, resolution_code, sample_rate)| {
                PortSettings {
                    axial_is_y,
                    invert_axial,
                    invert_rotation,
                    resolution_code,
                    sample_rate,
                }
            },
        )
}

fn reset_reason() -> impl Strategy<Value = ResetReason> {
    (0u8..=3).prop_map(|r| ResetReason::from_raw(r).unwrap())
}

fn readable_kind() -> impl Strategy<Value = FeatureKind> {
    proptest::sample::select(vec![
        FeatureKind::DeviceInfo,
        FeatureKind::PortDiagnostics,
        FeatureKind::Settings,
    ])
}

fn feature_report() -> impl Strategy<Value = FeatureReport> {
    prop_oneof![
        (
            proptest::array::uniform3(any::<u8>()),
            proptest::array::uniform12(any::<u8>()),
            reset_reason(),
            any::<u64>(),
            any::<u8>()
        )
            .prop_map(
                |(firmware_version, git_hash, reset_reason, uptime_us, present_ports)| {
                    FeatureReport::DeviceInfo(DeviceInfo {
                        firmware_version,
                        git_hash,
                        reset_reason,
                        uptime_us,
                        present_ports,
                    })
                }
            ),
        (0u8..8, any::<bool>(), any::<Option<u8>>(), counters()).prop_map(
            |(port, present, device_id, counters)| {
                FeatureReport::PortDiagnostics(PortDiagnostics {
                    port,
                    present,
                    device_id,
                    counters,
                })
            }
        ),
        proptest::array::uniform8(port_settings())
            .prop_map(|ports| FeatureReport::Settings(BoardSettings { ports })),
        (readable_kind(), 0u8..8).prop_map(|(kind, port)| FeatureReport::Select {
            kind,
            port: if kind == FeatureKind::PortDiagnostics {
                port
            } else {
                0
            },
        }),
        Just(FeatureReport::EnterBootloader),
    ]
}

proptest! {
    #[test]
    fn every_kind_round_trips(report in feature_report()) {
        let bytes = report.to_bytes();
        prop_assert_eq!(bytes.len(), FEATURE_REPORT_LEN);
        prop_assert_eq!(bytes[0], FEATURE_REPORT_VERSION);
        prop_assert_eq!(bytes[1], report.kind() as u8);
        prop_assert_eq!(FeatureReport::decode(&bytes), Ok(report));
    }

    #[test]
    fn the_board_decodes_only_what_a_host_writes(report in feature_report()) {
        let bytes = report.to_bytes();
        if report.kind().is_board_only() {
            prop_assert_eq!(
                FeatureReport::decode_command(&bytes),
                Err(DecodeError::BadField { field: "kind", paddle: None, value: report.kind() as u8 })
            );
        } else {
            prop_assert_eq!(FeatureReport::decode_command(&bytes), Ok(report));
        }
    }

    #[test]
    fn settings_fields_round_trip(ports in proptest::array::uniform8(port_settings())) {
        let settings = BoardSettings { ports };
        prop_assert_eq!(BoardSettings::decode_fields(&settings.encode_fields()), Ok(settings));
    }

    #[test]
    fn arbitrary_bytes_never_panic(bytes in proptest::collection::vec(any::<u8>(), 0..80)) {
        let _ = FeatureReport::decode(&bytes);
        let _ = FeatureReport::decode_command(&bytes);
        let _ = BoardSettings::decode_fields(&bytes);
    }

    /// Bytes of the right length with a known header either decode to a report that
    /// encodes back to the very same bytes, or fail naming a field.
    #[test]
    fn arbitrary_bodies_decode_canonically_or_name_the_field(
        kind in proptest::sample::select(vec![1u8, 2, 3, 16, 17]),
        mut bytes in proptest::collection::vec(any::<u8>(), FEATURE_REPORT_LEN),
        zero_tail in any::<bool>(),
    ) {
        bytes[0] = FEATURE_REPORT_VERSION;
        bytes[1] = kind;
        if zero_tail {
            // Most random tails fail on a reserved byte; zero them to reach the fields.
            for b in &mut bytes[30..] {
                *b = 0;
            }
        }
        match FeatureReport::decode(&bytes) {
            Ok(report) => prop_assert_eq!(report.to_bytes().to_vec(), bytes),
            Err(DecodeError::BadField { field, .. }) => prop_assert!(matches!(
                field,
                "reserved" | "port" | "flags" | "device_id" | "reset_reason" | "axis_flags"
                    | "resolution" | "sample_rate" | "selected_kind" | "bootloader_magic"
            ), "field {}", field),
            Err(other) => prop_assert!(false, "unexpected {other:?}"),
        }
    }

    #[test]
    fn wrong_lengths_are_named(len in 0usize..80) {
        prop_assume!(len != FEATURE_REPORT_LEN);
        let bytes = vec![FEATURE_REPORT_VERSION; len];
        prop_assert_eq!(
            FeatureReport::decode(&bytes),
            Err(DecodeError::WrongLength { expected: FEATURE_REPORT_LEN, actual: len })
        );
    }
}

#[test]
fn header_errors_are_named() {
    let mut bytes = FeatureReport::EnterBootloader.to_bytes();
    bytes[0] = 2;
    assert_eq!(
        FeatureReport::decode(&bytes),
        Err(DecodeError::UnknownVersion {
            found: 2,
            supported: FEATURE_REPORT_VERSION
        })
    );
    bytes[0] = FEATURE_REPORT_VERSION;
    bytes[1] = 9;
    assert_eq!(
        FeatureReport::decode(&bytes),
        Err(DecodeError::BadField {
            field: "kind",
            paddle: None,
            value: 9
        })
    );
}

#[test]
fn field_errors_name_the_port() {
    let mut settings = BoardSettings::DEFAULT;
    settings.ports[5].sample_rate = 201;
    let bytes = FeatureReport::Settings(settings).to_bytes();
    assert_eq!(
        FeatureReport::decode(&bytes),
        Err(DecodeError::BadField {
            field: "sample_rate",
            paddle: Some(5),
            value: 201
        })
    );
    let mut bytes = FeatureReport::Settings(BoardSettings::DEFAULT).to_bytes();
    bytes[2 + 3 * 6 + 1] = 4; // port 6's resolution code
    assert_eq!(
        FeatureReport::decode(&bytes),
        Err(DecodeError::BadField {
            field: "resolution",
            paddle: Some(6),
            value: 4
        })
    );
}

#[test]
fn a_select_must_name_a_readable_kind_and_a_port() {
    let select = |kind: u8, port: u8| {
        let mut bytes = [0u8; FEATURE_REPORT_LEN];
        bytes[0] = FEATURE_REPORT_VERSION;
        bytes[1] = FeatureKind::Select as u8;
        bytes[2] = kind;
        bytes[3] = port;
        FeatureReport::decode(&bytes)
    };
    assert_eq!(
        select(2, 7),
        Ok(FeatureReport::Select {
            kind: FeatureKind::PortDiagnostics,
            port: 7
        })
    );
    assert!(matches!(
        select(2, 8),
        Err(DecodeError::BadField { field: "port", .. })
    ));
    assert!(matches!(
        select(17, 0),
        Err(DecodeError::BadField {
            field: "selected_kind",
            ..
        })
    ));
}

#[test]
fn the_bootloader_command_needs_its_magic() {
    let mut bytes = FeatureReport::EnterBootloader.to_bytes();
    assert_eq!(&bytes[2..6], b"BOOT");
    bytes[4] = b'X';
    assert_eq!(
        FeatureReport::decode(&bytes),
        Err(DecodeError::BadField {
            field: "bootloader_magic",
            paddle: None,
            value: b'X'
        })
    );
}

#[test]
fn the_descriptor_declares_the_feature_report() {
    let feature = HID_REPORT_DESCRIPTOR
        .windows(4)
        .any(|w| w == [0x95, FEATURE_REPORT_LEN as u8, 0xB1, 0x02]);
    assert!(
        feature,
        "Report Count {FEATURE_REPORT_LEN} then Feature (Data, Variable, Absolute)"
    );
}

//! `UsbBoard` without hardware: no board plugged in.

use std::time::Duration;

use board_link::{Board, BoardError, FeaturePipe, LinkState, UsbBoard};
use foosball_protocol::usb::{PRODUCT_ID, VENDOR_ID};
use foosball_protocol::OutReport;

#[test]
fn open_without_a_board_is_not_found() {
    match UsbBoard::open() {
        Err(BoardError::NotFound { vid, pid }) => {
            assert_eq!((vid, pid), (VENDOR_ID, PRODUCT_ID));
            let message = BoardError::NotFound { vid, pid }.to_string();
            assert!(message.contains("1209:0001"), "{message}");
        }
        // Developers with a board plugged in (and the udev rule installed) get here.
        Ok(board) => eprintln!("a real board is plugged in: {}", board.name()),
        Err(BoardError::AccessDenied { .. }) => {
            eprintln!("a real board is plugged in but not accessible (udev rule?)")
        }
        Err(other) => panic!("expected NotFound, got {other:?}"),
    }
}

#[test]
fn open_ids_of_an_absent_device_is_not_found() {
    // pid.codes test vendor with a product id no board uses.
    let error = UsbBoard::open_ids(VENDOR_ID, 0xFFF0).unwrap_err();
    assert!(
        matches!(
            error,
            BoardError::NotFound {
                vid: VENDOR_ID,
                pid: 0xFFF0
            }
        ),
        "{error:?}"
    );
}

#[test]
fn an_absent_board_is_polled_without_panicking() {
    let mut board = UsbBoard::new(VENDOR_ID, 0xFFF0);
    assert_eq!(board.ids(), (VENDOR_ID, 0xFFF0));
    assert_eq!(board.link_state(), LinkState::Disconnected);
    assert!(matches!(
        board.poll_report(Duration::ZERO),
        Err(BoardError::Disconnected)
    ));
    assert_eq!(board.link_state(), LinkState::Reconnecting);
    assert!(matches!(
        board.last_connect_error(),
        Some(BoardError::NotFound { .. })
    ));
    assert!(matches!(
        board.send(&OutReport::default()),
        Err(BoardError::Disconnected)
    ));
    assert!(board.name().contains("1209:fff0"), "{}", board.name());
}

#[test]
fn a_serial_number_no_board_has_is_not_found() {
    match UsbBoard::open_serial("NO-SUCH-SERIAL") {
        Err(BoardError::NotFound { vid, pid }) => assert_eq!((vid, pid), (VENDOR_ID, PRODUCT_ID)),
        // Developers with boards plugged in: the error lists what they have.
        Err(e @ BoardError::SerialNotFound { .. }) => {
            let message = e.to_string();
            assert!(message.contains("\"NO-SUCH-SERIAL\""), "{message}");
        }
        Err(BoardError::AccessDenied { .. }) => {}
        other => panic!("expected no board with that serial number, got {other:?}"),
    }
}

#[test]
fn feature_requests_to_an_absent_board_fail_cleanly() {
    let mut board = UsbBoard::new(VENDOR_ID, 0xFFF0);
    assert!(matches!(
        FeaturePipe::device_info(&mut board),
        Err(BoardError::NotFound { .. })
    ));
    assert!(matches!(
        FeaturePipe::enter_bootloader(&mut board),
        Err(BoardError::NotFound { .. })
    ));
    assert_eq!(board.serial_number(), None);
    assert_eq!(board.wanted_serial(), None);
}

#[test]
fn udev_rule_matches_the_protocol_ids() {
    let rules = include_str!("../udev/70-space-foosball.rules");
    let active: Vec<&str> = rules
        .lines()
        .filter(|line| !line.trim_start().starts_with('#') && !line.trim().is_empty())
        .collect();
    assert_eq!(active.len(), 2, "one usb and one hidraw rule");
    let vendor = format!("ATTRS{{idVendor}}==\"{VENDOR_ID:04x}\"");
    let product = format!("ATTRS{{idProduct}}==\"{PRODUCT_ID:04x}\"");
    for line in &active {
        assert!(line.contains(&vendor) && line.contains(&product), "{line}");
        assert!(line.contains("TAG+=\"uaccess\""), "{line}");
    }
    assert!(active[0].starts_with("SUBSYSTEM==\"usb\""));
    assert!(active[1].starts_with("SUBSYSTEM==\"hidraw\""));
}

#[test]
fn access_denied_names_the_udev_rule_file_that_exists() {
    let message = BoardError::AccessDenied {
        vid: VENDOR_ID,
        pid: PRODUCT_ID,
    }
    .to_string();
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("udev");
    let named: Vec<String> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|entry| entry.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|name| message.contains(name.as_str()))
        .collect();
    assert_eq!(named, ["70-space-foosball.rules"], "{message}");
}

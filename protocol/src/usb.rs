//! USB identity of the sensor board: ids, strings, endpoints, HID report descriptor.
//!
//! The ids are the pid.codes *test* ids (vendor 0x1209, product 0x0001), free for
//! development and not for products. To ship boards, request a product id from
//! pid.codes (open-source hardware) or use your own vendor id, change
//! [`VENDOR_ID`]/[`PRODUCT_ID`] here, and update the host's udev rule
//! (`host/board-link/udev/70-space-foosball.rules`): both ends read these constants.

use crate::{FEATURE_REPORT_LEN, IN_REPORT_LEN, IN_REPORT_V2_LEN, OUT_REPORT_LEN};

/// USB vendor id (pid.codes).
pub const VENDOR_ID: u16 = 0x1209;
/// USB product id (pid.codes test id).
pub const PRODUCT_ID: u16 = 0x0001;
/// Manufacturer string descriptor.
pub const MANUFACTURER: &str = "Space Foosball";
/// Product string descriptor.
pub const PRODUCT: &str = "Space Foosball sensor board";

/// Maximum packet size of both interrupt endpoints (full speed allows 64 bytes).
pub const ENDPOINT_MAX_PACKET: u16 = 64;
/// Polling interval of both interrupt endpoints, milliseconds.
pub const POLL_INTERVAL_MS: u8 = 1;

/// Vendor-defined usage page (0xFF00): no operating system binds a mouse or keyboard
/// driver to the board.
pub const VENDOR_USAGE_PAGE: u16 = 0xFF00;

/// HID report descriptor: one vendor-defined application collection with one input
/// report of [`IN_REPORT_V2_LEN`] bytes (the board sends version 2 IN reports), one
/// output report of [`OUT_REPORT_LEN`] bytes and one feature report of
/// [`FEATURE_REPORT_LEN`] bytes ([`crate::FeatureReport`]), no report ids.
#[rustfmt::skip]
pub const HID_REPORT_DESCRIPTOR: &[u8] = &[
    0x06, 0x00, 0xFF, // Usage Page (Vendor Defined 0xFF00)
    0x09, 0x01, // Usage (Vendor 1: sensor board)
    0xA1, 0x01, // Collection (Application)
    0x15, 0x00, //   Logical Minimum (0)
    0x26, 0xFF, 0x00, //   Logical Maximum (255)
    0x75, 0x08, //   Report Size (8 bits)
    0x09, 0x02, //   Usage (Vendor 2: paddle motion)
    0x95, IN_REPORT_V2_LEN as u8, //   Report Count
    0x81, 0x02, //   Input (Data, Variable, Absolute)
    0x09, 0x03, //   Usage (Vendor 3: haptics and LED)
    0x95, OUT_REPORT_LEN as u8, //   Report Count
    0x91, 0x02, //   Output (Data, Variable, Absolute)
    0x09, 0x04, //   Usage (Vendor 4: diagnostics and configuration)
    0x95, FEATURE_REPORT_LEN as u8, //   Report Count
    0xB1, 0x02, //   Feature (Data, Variable, Absolute)
    0xC0, // End Collection
];

// Both reports must fit one full-speed interrupt packet.
const _: () = assert!(IN_REPORT_LEN <= ENDPOINT_MAX_PACKET as usize);
const _: () = assert!(IN_REPORT_V2_LEN <= ENDPOINT_MAX_PACKET as usize);
const _: () = assert!(OUT_REPORT_LEN <= ENDPOINT_MAX_PACKET as usize);
// The Feature report fits one control packet (and the firmware's 64-byte control buffer).
const _: () = assert!(FEATURE_REPORT_LEN <= ENDPOINT_MAX_PACKET as usize);

//! The USB protocol between the Space Foosball sensor board and the host.
//!
//! `no_std`, no allocation: the firmware and the host compile this one crate, so the
//! byte layouts cannot drift apart.
//!
//! * [`InReport`]: device → host every 1 ms, the motion of all eight paddles since the
//!   previous report ([`PaddleMotion`]) plus a wrapping sequence number.
//! * [`InReportV2`]: the same motion plus the device time of the snapshot and, per
//!   paddle, the age of its newest packet and a dropped-packet count; a host reads
//!   either version with [`decode_in_report`].
//! * [`OutReport`]: host → device, a haptic pulse per paddle ([`HapticPulse`]) and the
//!   status LED.
//! * [`FeatureReport`]: both ways over the control pipe, the board's diagnostics
//!   ([`DeviceInfo`], [`PortDiagnostics`]), its configuration ([`BoardSettings`]),
//!   and the command that restarts it into its USB bootloader.
//! * [`usb`]: vendor/product ids, endpoint sizes and the HID report descriptor.
//!
//! All multi-byte fields are little-endian. Every report starts with its layout
//! version ([`FORMAT_VERSION`], [`IN_REPORT_V2_VERSION`], [`FEATURE_REPORT_VERSION`]);
//! a decoder rejects any other version.
#![no_std]
#![deny(missing_docs)]

mod error;
mod feature_report;
mod in_report;
mod in_report_v2;
mod out_report;
pub mod usb;

pub use error::{DecodeError, EncodeError};
pub use feature_report::{
    BoardSettings, DeviceInfo, FeatureKind, FeatureReport, PortCounters, PortDiagnostics,
    PortSettings, ResetReason, BOOTLOADER_MAGIC, FEATURE_REPORT_LEN, FEATURE_REPORT_VERSION,
    GIT_HASH_LEN, SAMPLE_RATES,
};
pub use in_report::{InReport, PaddleMotion, PaddleStatus, IN_REPORT_LEN};
pub use in_report_v2::{
    decode_in_report, InReportV2, PacketAge, PaddleTiming, ReportTiming, IN_REPORT_V2_LEN,
    IN_REPORT_V2_VERSION,
};
pub use out_report::{HapticPulse, LedState, OutReport, OUT_REPORT_LEN};

/// Number of paddles (rods) on the cabinet, and so of PS/2 sensors on the board.
pub const PADDLES: usize = 8;

/// Layout version carried in the first byte of every report.
pub const FORMAT_VERSION: u8 = 1;

//! PS/2 mouse command and reply bytes used by the driver.

/// Host → mouse: reset; the mouse answers [`ACK`], runs its self-test (BAT) and sends
/// [`SELF_TEST_PASSED`] then its device id ([`DEVICE_ID_MOUSE`]).
pub const RESET: u8 = 0xFF;
/// Host → mouse: set sample rate; the rate (samples/s) follows as a second byte.
pub const SET_SAMPLE_RATE: u8 = 0xF3;
/// Host → mouse: set resolution; the code (see [`super::Resolution`]) follows.
pub const SET_RESOLUTION: u8 = 0xE8;
/// Host → mouse: enable data reporting in stream mode.
pub const ENABLE_REPORTING: u8 = 0xF4;
/// Host → mouse: read data; the mouse answers [`ACK`] and one movement packet (then
/// clears its counters, so no motion is lost). Harmless in stream mode: the driver's
/// liveness probe.
pub const READ_DATA: u8 = 0xEB;
/// Host → mouse: status request; answered by [`ACK`] and three status bytes: flags
/// ([`STATUS_REMOTE_MODE`], [`STATUS_REPORTING`], scaling, buttons), the resolution
/// code and the sample rate.
pub const STATUS_REQUEST: u8 = 0xE9;
/// Status byte 1: the mouse is in remote (polled) mode, not stream mode.
pub const STATUS_REMOTE_MODE: u8 = 0x40;
/// Status byte 1: data reporting is enabled.
pub const STATUS_REPORTING: u8 = 0x20;
/// Host → mouse: get device id; answered by [`ACK`] and the id.
pub const GET_DEVICE_ID: u8 = 0xF2;

/// Mouse → host: command (or argument) acknowledged.
pub const ACK: u8 = 0xFA;
/// Mouse → host: the last byte was received garbled or invalid; send it again.
pub const RESEND: u8 = 0xFE;
/// Mouse → host: error (second invalid byte in a row, or self-test failed).
pub const ERROR: u8 = 0xFC;
/// Mouse → host: self-test (BAT) passed; also sent spontaneously at power-up, so a
/// hot-plugged mouse announces itself with it.
pub const SELF_TEST_PASSED: u8 = 0xAA;
/// Mouse → host: device id of a standard PS/2 mouse, sent after [`SELF_TEST_PASSED`].
pub const DEVICE_ID_MOUSE: u8 = 0x00;

/// The command the driver sends to a silent streaming mouse, and after a doubtful
/// byte, to check it is still there and still has its settings.
pub const PROBE: u8 = STATUS_REQUEST;

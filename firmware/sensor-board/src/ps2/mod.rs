//! The PS/2 wire as data: device-to-host frames and host-to-device commands.
//!
//! The caller (PIO on the RP2040, an emulated wire in the simulator) does the timing;
//! this module only says what the bits mean.

pub mod frame;
pub mod host_frame;

pub use frame::{FrameError, Ps2Frame};
pub use host_frame::{
    HostFrame, RequestToSendStep, SendError, HOST_FRAME_BITS, REQUEST_TO_SEND,
    REQUEST_TO_SEND_CLOCK_LOW_US,
};

/// Odd parity bit for `byte`: set when `byte` has an even number of ones, so that the
/// eight data bits plus the parity bit hold an odd number of ones.
pub(crate) const fn odd_parity_bit(byte: u8) -> bool {
    byte.count_ones() & 1 == 0
}

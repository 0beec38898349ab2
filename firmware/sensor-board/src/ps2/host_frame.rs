//! Host-to-device PS/2 commands, modelled as data.
//!
//! To send a byte the host performs *request-to-send* ([`REQUEST_TO_SEND`]): it holds
//! the clock low for at least [`REQUEST_TO_SEND_CLOCK_LOW_US`], pulls data low (this
//! is the start bit), releases the clock, and the device then generates the clock
//! (spec: starts within 15 ms, whole frame within 2 ms) and samples the
//! [`HOST_FRAME_BITS`] bits of a [`HostFrame`] on its rising edges, one per clock.
//! Finally the device acknowledges by pulling data low for one more clock.

use super::frame::FrameError;
use super::odd_parity_bit;

/// How long the host holds the clock line low to request to send, microseconds
/// (spec: at least 100 µs).
pub const REQUEST_TO_SEND_CLOCK_LOW_US: u64 = 100;

/// Bits the device clocks in after request-to-send: 8 data, parity, stop.
pub const HOST_FRAME_BITS: u8 = 10;

/// One step of request-to-send, in order ([`REQUEST_TO_SEND`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum RequestToSendStep {
    /// Hold the clock line low for at least `min_us` microseconds (inhibits the
    /// device; a frame it was sending is aborted and sent again later).
    InhibitClock {
        /// Minimum low time, microseconds.
        min_us: u64,
    },
    /// Pull the data line low: the start bit.
    PullDataLow,
    /// Release the clock line; the device starts clocking.
    ReleaseClock,
    /// The device clocks in `bits` bits of the [`HostFrame`], bit 0 first, each set
    /// by the host while the clock is low and sampled by the device on its rise.
    DeviceClocksBits {
        /// Number of bits ([`HOST_FRAME_BITS`]).
        bits: u8,
    },
    /// Release data and wait for the device to pull data low for one clock: the ACK.
    AwaitAck,
}

/// The request-to-send sequence, as data.
pub const REQUEST_TO_SEND: [RequestToSendStep; 5] = [
    RequestToSendStep::InhibitClock {
        min_us: REQUEST_TO_SEND_CLOCK_LOW_US,
    },
    RequestToSendStep::PullDataLow,
    RequestToSendStep::ReleaseClock,
    RequestToSendStep::DeviceClocksBits {
        bits: HOST_FRAME_BITS,
    },
    RequestToSendStep::AwaitAck,
];

/// Why a command byte could not be sent to the device; the caller reports it through
/// [`crate::MouseDriver::on_command_sent`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, thiserror::Error)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum SendError {
    /// The device did not start clocking after request-to-send (spec: within 15 ms):
    /// nothing is plugged in, or it is not powered.
    #[error("PS/2 device did not clock the command in")]
    NoClock,
    /// The device started clocking but did not finish the frame in time (spec: 2 ms).
    #[error("PS/2 command transfer timed out")]
    Timeout,
    /// The device clocked all bits in but did not acknowledge (data not pulled low).
    #[error("PS/2 device did not acknowledge the command")]
    NoAck,
}

/// The [`HOST_FRAME_BITS`] bits the device clocks in after request-to-send: bits 0..8
/// data least significant bit first, bit 8 odd parity, bit 9 stop (1). The start bit
/// (data pulled low in request-to-send) is not part of it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct HostFrame(u16);

/// Mask of the bits a [`HostFrame`] keeps.
const HOST_FRAME_MASK: u16 = (1 << HOST_FRAME_BITS) - 1;

impl HostFrame {
    /// The frame the host sends for `byte`.
    pub fn encode(byte: u8) -> Self {
        let parity = odd_parity_bit(byte) as u16;
        Self(u16::from(byte) | (parity << 8) | (1 << 9))
    }

    /// A frame from raw bits, bit 0 = first data bit. Bits above bit 9 are ignored
    /// (cleared), so any `u16` is accepted.
    pub const fn from_raw(bits: u16) -> Self {
        Self(bits & HOST_FRAME_MASK)
    }

    /// The 10 raw bits.
    pub const fn raw(self) -> u16 {
        self.0
    }

    /// The level of bit `i` on the data line (`true` = high), `i` in `0..10` in wire
    /// order. Beyond the frame the host has released the line, so `i >= 10` reads
    /// high (`true`).
    pub fn bit(self, i: usize) -> bool {
        if i < usize::from(HOST_FRAME_BITS) {
            self.0 & (1 << i) != 0
        } else {
            true
        }
    }

    /// Device side: the data byte, checking the stop bit (1), then odd parity.
    pub fn decode(self) -> Result<u8, FrameError> {
        if self.0 & (1 << 9) == 0 {
            return Err(FrameError::StopBit);
        }
        let byte = self.0 as u8;
        let parity = self.0 & (1 << 8) != 0;
        if parity != odd_parity_bit(byte) {
            return Err(FrameError::Parity);
        }
        Ok(byte)
    }
}

impl From<u8> for HostFrame {
    fn from(byte: u8) -> Self {
        Self::encode(byte)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_byte_round_trips() {
        for byte in 0..=u8::MAX {
            assert_eq!(HostFrame::encode(byte).decode(), Ok(byte));
        }
    }

    #[test]
    // Digit groups follow the frame fields: stop, parity, data.
    #[allow(clippy::unusual_byte_groupings)]
    fn bits_in_wire_order() {
        // 0xF4 (enable reporting) = 1111_0100: five ones → parity 0.
        let frame = HostFrame::encode(0xF4);
        assert_eq!(frame.raw(), 0b1_0_11110100);
        let bits: [bool; 10] = core::array::from_fn(|i| frame.bit(i));
        assert_eq!(
            bits,
            [false, false, true, false, true, true, true, true, false, true]
        );
        assert!(frame.bit(10));
        assert!(frame.bit(usize::MAX));
    }

    #[test]
    fn bad_stop_and_parity() {
        let good = HostFrame::encode(0xFF).raw();
        assert_eq!(
            HostFrame::from_raw(good & !(1 << 9)).decode(),
            Err(FrameError::StopBit)
        );
        assert_eq!(
            HostFrame::from_raw(good ^ (1 << 8)).decode(),
            Err(FrameError::Parity)
        );
        assert_eq!(
            HostFrame::from_raw(good ^ 1).decode(),
            Err(FrameError::Parity)
        );
    }

    #[test]
    fn from_raw_ignores_high_bits() {
        let frame = HostFrame::from_raw(HostFrame::encode(0xE8).raw() | 0xFC00);
        assert_eq!(frame, HostFrame::encode(0xE8));
    }

    #[test]
    fn request_to_send_sequence() {
        assert_eq!(
            REQUEST_TO_SEND[0],
            RequestToSendStep::InhibitClock { min_us: 100 }
        );
        assert_eq!(REQUEST_TO_SEND[1], RequestToSendStep::PullDataLow);
        assert_eq!(REQUEST_TO_SEND[2], RequestToSendStep::ReleaseClock);
        assert_eq!(
            REQUEST_TO_SEND[3],
            RequestToSendStep::DeviceClocksBits { bits: 10 }
        );
        assert_eq!(REQUEST_TO_SEND[4], RequestToSendStep::AwaitAck);
    }
}

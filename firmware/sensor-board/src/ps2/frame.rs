//! Device-to-host PS/2 frames.
//!
//! A device sends a byte as an 11-bit frame, one bit per falling clock edge
//! (10–16.7 kHz, so about 0.66–1.1 ms per frame):
//!
//! | bit | meaning |
//! |---|---|
//! | 0 | start bit, always 0 |
//! | 1..=8 | data, least significant bit first |
//! | 9 | odd parity over the data bits |
//! | 10 | stop bit, always 1 |

use super::odd_parity_bit;

/// Number of bits in a device-to-host frame.
pub const FRAME_BITS: u32 = 11;

/// Mask of the bits a [`Ps2Frame`] keeps.
const FRAME_MASK: u16 = (1 << FRAME_BITS) - 1;

/// One device-to-host frame: the 11 bits as sampled on the falling clock edges, bit 0
/// being the first bit on the wire (the start bit).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Ps2Frame(u16);

/// Why a received frame was rejected.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, thiserror::Error)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum FrameError {
    /// The start bit was 1 (a framing error).
    #[error("PS/2 framing error: start bit is 1")]
    StartBit,
    /// The data bits and the parity bit hold an even number of ones.
    #[error("PS/2 parity error")]
    Parity,
    /// The stop bit was 0 (a framing error).
    #[error("PS/2 framing error: stop bit is 0")]
    StopBit,
}

impl FrameError {
    /// Whether this is a framing error (bad start or stop bit) rather than a parity
    /// error.
    pub const fn is_framing(self) -> bool {
        matches!(self, Self::StartBit | Self::StopBit)
    }
}

impl Ps2Frame {
    /// A frame from raw bits, bit 0 = start bit. Bits above bit 10 are ignored
    /// (cleared), so any `u16` is accepted.
    pub const fn from_raw(bits: u16) -> Self {
        Self(bits & FRAME_MASK)
    }

    /// The 11 raw bits, bit 0 = start bit.
    pub const fn raw(self) -> u16 {
        self.0
    }

    /// The frame a well-behaved device sends for `byte`.
    pub fn encode(byte: u8) -> Self {
        let parity = odd_parity_bit(byte) as u16;
        Self((u16::from(byte) << 1) | (parity << 9) | (1 << 10))
    }

    /// The data byte, checking start bit (0), stop bit (1) and odd parity, in that
    /// order: a bad start or stop bit means the bits are misaligned, so parity is only
    /// meaningful when both are right.
    pub fn decode(self) -> Result<u8, FrameError> {
        if self.0 & 1 != 0 {
            return Err(FrameError::StartBit);
        }
        if self.0 & (1 << 10) == 0 {
            return Err(FrameError::StopBit);
        }
        let byte = (self.0 >> 1) as u8;
        let parity = self.0 & (1 << 9) != 0;
        if parity != odd_parity_bit(byte) {
            return Err(FrameError::Parity);
        }
        Ok(byte)
    }
}

impl From<u8> for Ps2Frame {
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
            assert_eq!(Ps2Frame::encode(byte).decode(), Ok(byte));
        }
    }

    #[test]
    // Digit groups follow the frame fields: stop, parity, data, start.
    #[allow(clippy::unusual_byte_groupings)]
    fn known_frames() {
        // 0xFA = 1111_1010: six ones → parity bit 1.
        // start 0, data LSB first 0,1,0,1,1,1,1,1, parity 1, stop 1.
        assert_eq!(Ps2Frame::encode(0xFA).raw(), 0b1_1_11111010_0);
        // 0x00: zero ones → parity bit 1.
        assert_eq!(Ps2Frame::encode(0x00).raw(), 0b1_1_00000000_0);
        // 0x01: one one → parity bit 0.
        assert_eq!(Ps2Frame::encode(0x01).raw(), 0b1_0_00000001_0);
    }

    #[test]
    fn bad_start_bit() {
        let frame = Ps2Frame::from_raw(Ps2Frame::encode(0x42).raw() | 1);
        assert_eq!(frame.decode(), Err(FrameError::StartBit));
        assert!(FrameError::StartBit.is_framing());
    }

    #[test]
    fn bad_stop_bit() {
        let frame = Ps2Frame::from_raw(Ps2Frame::encode(0x42).raw() & !(1 << 10));
        assert_eq!(frame.decode(), Err(FrameError::StopBit));
        assert!(FrameError::StopBit.is_framing());
    }

    #[test]
    fn bad_parity_on_every_byte() {
        for byte in 0..=u8::MAX {
            let frame = Ps2Frame::from_raw(Ps2Frame::encode(byte).raw() ^ (1 << 9));
            assert_eq!(frame.decode(), Err(FrameError::Parity), "byte {byte:#04x}");
        }
        assert!(!FrameError::Parity.is_framing());
    }

    #[test]
    fn single_data_bit_flip_is_a_parity_error() {
        for bit in 1..=8 {
            let frame = Ps2Frame::from_raw(Ps2Frame::encode(0x5A).raw() ^ (1 << bit));
            assert_eq!(frame.decode(), Err(FrameError::Parity), "bit {bit}");
        }
    }

    #[test]
    fn framing_checked_before_parity() {
        // Start bit 1 and parity wrong: reported as a framing error.
        let frame = Ps2Frame::from_raw((Ps2Frame::encode(0x42).raw() ^ (1 << 9)) | 1);
        assert_eq!(frame.decode(), Err(FrameError::StartBit));
        let frame = Ps2Frame::from_raw((Ps2Frame::encode(0x42).raw() ^ (1 << 9)) & !(1 << 10));
        assert_eq!(frame.decode(), Err(FrameError::StopBit));
    }

    #[test]
    fn from_raw_ignores_high_bits() {
        let frame = Ps2Frame::from_raw(Ps2Frame::encode(0x99).raw() | 0xF800);
        assert_eq!(frame.raw(), Ps2Frame::encode(0x99).raw());
        assert_eq!(frame.decode(), Ok(0x99));
    }

    #[test]
    fn all_zero_and_all_one_lines() {
        // Data line stuck low: stop bit missing (start bit is fine).
        assert_eq!(Ps2Frame::from_raw(0).decode(), Err(FrameError::StopBit));
        // Data line stuck high: start bit wrong.
        assert_eq!(
            Ps2Frame::from_raw(0xFFFF).decode(),
            Err(FrameError::StartBit)
        );
    }
}

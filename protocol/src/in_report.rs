//! The IN report: paddle motion, device → host, every 1 ms.
//!
//! Layout ([`IN_REPORT_LEN`] bytes, little-endian):
//!
//! | offset | size | field |
//! |---|---|---|
//! | 0 | 1 | format version ([`crate::FORMAT_VERSION`]) |
//! | 1 | 2 | sequence number, wrapping `u16` |
//! | 3 + 5·i | 2 | paddle i axial counts, `i16` |
//! | 5 + 5·i | 2 | paddle i rotation counts, `i16` |
//! | 7 + 5·i | 1 | paddle i [`PaddleStatus`] bits |

use crate::error::{check_buffer, check_header};
use crate::{DecodeError, EncodeError, FORMAT_VERSION, PADDLES};

/// Bytes per paddle in the IN report.
const PADDLE_BYTES: usize = 5;
/// Bytes before the first paddle.
const HEADER_BYTES: usize = 3;

/// Length of an encoded [`InReport`] in bytes.
pub const IN_REPORT_LEN: usize = HEADER_BYTES + PADDLES * PADDLE_BYTES;

/// Status bits of one paddle's sensor for one report period.
///
/// "Seen" flags are sticky over the period: they are set if the condition happened at
/// least once since the previous report.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct PaddleStatus(u8);

impl PaddleStatus {
    /// The sensor is initialised and streaming.
    pub const PRESENT: Self = Self(0x01);
    /// The mouse set its overflow bit on the axis mapped to the paddle's axial motion.
    pub const AXIAL_OVERFLOW: Self = Self(0x02);
    /// The mouse set its overflow bit on the axis mapped to the paddle's rotation.
    pub const ROTATION_OVERFLOW: Self = Self(0x04);
    /// A PS/2 frame with a bad start or stop bit was received.
    pub const FRAMING_ERROR: Self = Self(0x08);
    /// A PS/2 frame with bad odd parity was received.
    pub const PARITY_ERROR: Self = Self(0x10);
    /// The sensor was (re-)initialised since the previous report (power-up, hot-plug,
    /// spontaneous mouse restart).
    pub const REINITIALISED: Self = Self(0x20);
    /// An accumulator saturated at the `i16` limit: motion was lost.
    pub const SATURATED: Self = Self(0x40);
    /// Bits with a meaning in this format version; the others must be zero.
    pub const KNOWN_BITS: u8 = 0x7F;

    /// No flag set: sensor absent, nothing seen.
    pub const fn empty() -> Self {
        Self(0)
    }

    /// Builds a status from raw bits, rejecting unknown bits.
    pub const fn from_bits(bits: u8) -> Option<Self> {
        if bits & !Self::KNOWN_BITS == 0 {
            Some(Self(bits))
        } else {
            None
        }
    }

    /// The raw bits.
    pub const fn bits(self) -> u8 {
        self.0
    }

    /// Whether every flag of `other` is set in `self`.
    pub const fn contains(self, other: Self) -> bool {
        self.0 & other.0 == other.0
    }

    /// Sets the flags of `other`.
    pub fn insert(&mut self, other: Self) {
        self.0 |= other.0;
    }

    /// Clears the flags of `other`.
    pub fn remove(&mut self, other: Self) {
        self.0 &= !other.0;
    }

    /// `self` with the flags of `other` set as well.
    #[must_use]
    pub const fn union(self, other: Self) -> Self {
        Self(self.0 | other.0)
    }
}

impl core::ops::BitOr for PaddleStatus {
    type Output = Self;
    fn bitor(self, rhs: Self) -> Self {
        self.union(rhs)
    }
}

impl core::ops::BitOrAssign for PaddleStatus {
    fn bitor_assign(&mut self, rhs: Self) {
        self.insert(rhs);
    }
}

/// Motion of one paddle accumulated over one report period.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct PaddleMotion {
    /// Counts along the rod's axis (sensor counts at its resolution; positive away from
    /// the player as mounted, after the port's axis map).
    pub axial: i16,
    /// Counts of the rod surface's motion from turning (sensor counts at its
    /// resolution; positive as mounted, after the port's axis map).
    pub rotation: i16,
    /// Sensor status over the period.
    pub status: PaddleStatus,
}

/// Device → host report, sent every 1 ms on the interrupt IN endpoint.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct InReport {
    /// Wrapping sequence number, incremented by one per report; gaps mean lost reports.
    pub sequence: u16,
    /// Motion of each paddle since the previous report, indexed by port (0..8).
    pub paddles: [PaddleMotion; PADDLES],
}

impl InReport {
    /// A report with sequence number `sequence` in which every sensor is present and no
    /// paddle moved: the starting point for a report that moves some paddles.
    pub const fn all_present(sequence: u16) -> Self {
        Self {
            sequence,
            paddles: [PaddleMotion {
                axial: 0,
                rotation: 0,
                status: PaddleStatus::PRESENT,
            }; PADDLES],
        }
    }

    /// Writes the report into `buf`, returning the number of bytes written
    /// ([`IN_REPORT_LEN`]).
    pub fn encode(&self, buf: &mut [u8]) -> Result<usize, EncodeError> {
        check_buffer(buf, IN_REPORT_LEN)?;
        buf[0] = FORMAT_VERSION;
        buf[1..3].copy_from_slice(&self.sequence.to_le_bytes());
        for (paddle, chunk) in self
            .paddles
            .iter()
            .zip(buf[HEADER_BYTES..IN_REPORT_LEN].chunks_exact_mut(PADDLE_BYTES))
        {
            chunk[0..2].copy_from_slice(&paddle.axial.to_le_bytes());
            chunk[2..4].copy_from_slice(&paddle.rotation.to_le_bytes());
            chunk[4] = paddle.status.bits();
        }
        Ok(IN_REPORT_LEN)
    }

    /// The encoded report as a fixed-size array.
    pub fn to_bytes(&self) -> [u8; IN_REPORT_LEN] {
        let mut out = [0; IN_REPORT_LEN];
        // The array has exactly the needed length, so encoding cannot fail.
        let _ = self.encode(&mut out);
        out
    }

    /// Parses a received report, rejecting wrong lengths, unknown versions and
    /// unknown status bits.
    pub fn decode(bytes: &[u8]) -> Result<Self, DecodeError> {
        check_header(bytes, IN_REPORT_LEN)?;
        let sequence = u16::from_le_bytes([bytes[1], bytes[2]]);
        let mut paddles = [PaddleMotion::default(); PADDLES];
        for (index, (paddle, chunk)) in paddles
            .iter_mut()
            .zip(bytes[HEADER_BYTES..].chunks_exact(PADDLE_BYTES))
            .enumerate()
        {
            let status = PaddleStatus::from_bits(chunk[4]).ok_or(DecodeError::BadField {
                field: "status",
                paddle: Some(index as u8),
                value: chunk[4],
            })?;
            *paddle = PaddleMotion {
                axial: i16::from_le_bytes([chunk[0], chunk[1]]),
                rotation: i16::from_le_bytes([chunk[2], chunk[3]]),
                status,
            };
        }
        Ok(Self { sequence, paddles })
    }
}

//! The version 2 IN report: the version 1 motion plus timing, device → host.
//!
//! Layout ([`IN_REPORT_V2_LEN`] bytes, little-endian):
//!
//! | offset | size | field |
//! |---|---|---|
//! | 0 | 1 | format version ([`IN_REPORT_V2_VERSION`]) |
//! | 1 | 2 | sequence number, wrapping `u16` |
//! | 3 | 4 | device time of the snapshot, microseconds since boot, wrapping `u32` |
//! | 7 + 7·i | 2 | paddle i axial counts, `i16` |
//! | 9 + 7·i | 2 | paddle i rotation counts, `i16` |
//! | 11 + 7·i | 1 | paddle i [`PaddleStatus`] bits |
//! | 12 + 7·i | 1 | paddle i age of its newest packet at the snapshot ([`PacketAge`]) |
//! | 13 + 7·i | 1 | paddle i packets dropped since boot, wrapping `u8` |
//!
//! With the device time and each paddle's packet age the host knows when each
//! paddle's newest motion happened on the board's clock, so it can rebuild velocity
//! from 200 Hz packets and measure its own latency. A host reads both versions with
//! [`decode_in_report`].

use crate::error::check_buffer;
use crate::{DecodeError, EncodeError, InReport, PaddleMotion, PaddleStatus, PADDLES};

/// Layout version of [`InReportV2`].
pub const IN_REPORT_V2_VERSION: u8 = 2;

/// Bytes per paddle in the v2 IN report.
const PADDLE_BYTES: usize = 7;
/// Bytes before the first paddle.
const HEADER_BYTES: usize = 7;

/// Length of an encoded [`InReportV2`] in bytes (fits one 64-byte packet).
pub const IN_REPORT_V2_LEN: usize = HEADER_BYTES + PADDLES * PADDLE_BYTES;

/// How long before the report's snapshot a paddle's newest packet arrived, in steps
/// of [`PacketAge::STEP_US`] (100 µs), up to 25.4 ms; [`PacketAge::NONE`] when there
/// was none that recent.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct PacketAge(u8);

impl PacketAge {
    /// One step, microseconds.
    pub const STEP_US: u32 = 100;
    /// No packet within the last 25.5 ms (or none since boot).
    pub const NONE: Self = Self(u8::MAX);

    /// The age of a packet `age_us` microseconds old, rounded down to a step;
    /// [`NONE`](Self::NONE) from 25.5 ms on.
    pub const fn from_micros(age_us: u64) -> Self {
        let steps = age_us / Self::STEP_US as u64;
        if steps >= u8::MAX as u64 {
            Self::NONE
        } else {
            Self(steps as u8)
        }
    }

    /// The age in microseconds (a multiple of the step), `None` for [`NONE`](Self::NONE).
    pub const fn as_micros(self) -> Option<u32> {
        if self.0 == u8::MAX {
            None
        } else {
            Some(self.0 as u32 * Self::STEP_US)
        }
    }

    /// The raw byte.
    pub const fn raw(self) -> u8 {
        self.0
    }

    /// From the raw byte (every value is valid).
    pub const fn from_raw(raw: u8) -> Self {
        Self(raw)
    }
}

/// Per-paddle timing and loss in a v2 IN report.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct PaddleTiming {
    /// Age of the paddle's newest packet at the snapshot.
    pub newest_packet_age: PacketAge,
    /// Packets lost for good since boot (garbled after every resend, cut short),
    /// wrapping.
    pub dropped: u8,
}

/// The timing part of a v2 IN report.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct ReportTiming {
    /// The board's clock at the snapshot, microseconds since boot, wrapping (every
    /// 71.6 minutes).
    pub device_time_us: u32,
    /// Per paddle, indexed by port (0..8).
    pub paddles: [PaddleTiming; PADDLES],
}

/// Device → host report, version 2: the motion of [`InReport`] and its timing.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct InReportV2 {
    /// Sequence number and motion, as in version 1.
    pub report: InReport,
    /// When it was taken and how fresh each paddle's motion is.
    pub timing: ReportTiming,
}

impl InReportV2 {
    /// Writes the report into `buf`, returning the number of bytes written
    /// ([`IN_REPORT_V2_LEN`]).
    pub fn encode(&self, buf: &mut [u8]) -> Result<usize, EncodeError> {
        check_buffer(buf, IN_REPORT_V2_LEN)?;
        buf[0] = IN_REPORT_V2_VERSION;
        buf[1..3].copy_from_slice(&self.report.sequence.to_le_bytes());
        buf[3..7].copy_from_slice(&self.timing.device_time_us.to_le_bytes());
        let paddles = self.report.paddles.iter().zip(self.timing.paddles.iter());
        for ((motion, timing), chunk) in
            paddles.zip(buf[HEADER_BYTES..IN_REPORT_V2_LEN].chunks_exact_mut(PADDLE_BYTES))
        {
            chunk[0..2].copy_from_slice(&motion.axial.to_le_bytes());
            chunk[2..4].copy_from_slice(&motion.rotation.to_le_bytes());
            chunk[4] = motion.status.bits();
            chunk[5] = timing.newest_packet_age.raw();
            chunk[6] = timing.dropped;
        }
        Ok(IN_REPORT_V2_LEN)
    }

    /// The encoded report as a fixed-size array.
    pub fn to_bytes(&self) -> [u8; IN_REPORT_V2_LEN] {
        let mut out = [0; IN_REPORT_V2_LEN];
        // The array has exactly the needed length, so encoding cannot fail.
        let _ = self.encode(&mut out);
        out
    }

    /// Parses a received v2 report, rejecting wrong lengths, other versions and
    /// unknown status bits.
    pub fn decode(bytes: &[u8]) -> Result<Self, DecodeError> {
        if bytes.len() != IN_REPORT_V2_LEN {
            return Err(DecodeError::WrongLength {
                expected: IN_REPORT_V2_LEN,
                actual: bytes.len(),
            });
        }
        if bytes[0] != IN_REPORT_V2_VERSION {
            return Err(DecodeError::UnknownVersion {
                found: bytes[0],
                supported: IN_REPORT_V2_VERSION,
            });
        }
        let sequence = u16::from_le_bytes([bytes[1], bytes[2]]);
        let device_time_us = u32::from_le_bytes([bytes[3], bytes[4], bytes[5], bytes[6]]);
        let mut paddles = [PaddleMotion::default(); PADDLES];
        let mut timings = [PaddleTiming::default(); PADDLES];
        for (index, ((motion, timing), chunk)) in paddles
            .iter_mut()
            .zip(timings.iter_mut())
            .zip(bytes[HEADER_BYTES..].chunks_exact(PADDLE_BYTES))
            .enumerate()
        {
            let status = PaddleStatus::from_bits(chunk[4]).ok_or(DecodeError::BadField {
                field: "status",
                paddle: Some(index as u8),
                value: chunk[4],
            })?;
            *motion = PaddleMotion {
                axial: i16::from_le_bytes([chunk[0], chunk[1]]),
                rotation: i16::from_le_bytes([chunk[2], chunk[3]]),
                status,
            };
            *timing = PaddleTiming {
                newest_packet_age: PacketAge::from_raw(chunk[5]),
                dropped: chunk[6],
            };
        }
        Ok(Self {
            report: InReport { sequence, paddles },
            timing: ReportTiming {
                device_time_us,
                paddles: timings,
            },
        })
    }
}

/// Decodes an IN report of either version: the motion, and the timing when the
/// board sent version 2. A first byte other than 1 or 2 is
/// [`DecodeError::UnknownVersion`] (naming 2, the newest this build reads); each
/// version's length and fields are checked as its own decoder does.
pub fn decode_in_report(bytes: &[u8]) -> Result<(InReport, Option<ReportTiming>), DecodeError> {
    match bytes.first() {
        Some(&IN_REPORT_V2_VERSION) => {
            InReportV2::decode(bytes).map(|v2| (v2.report, Some(v2.timing)))
        }
        Some(&crate::FORMAT_VERSION) | None => InReport::decode(bytes).map(|v1| (v1, None)),
        Some(&found) => Err(DecodeError::UnknownVersion {
            found,
            supported: IN_REPORT_V2_VERSION,
        }),
    }
}

//! The OUT report: haptics and the status LED, host → device.
//!
//! Layout ([`OUT_REPORT_LEN`] bytes):
//!
//! | offset | size | field |
//! |---|---|---|
//! | 0 | 1 | format version ([`crate::FORMAT_VERSION`]) |
//! | 1 + 2·i | 1 | paddle i pulse strength, 0–255 (PWM duty 0–100 %) |
//! | 2 + 2·i | 1 | paddle i pulse duration, milliseconds (0: no pulse) |
//! | 17 | 1 | [`LedState`] |

use crate::error::{check_buffer, check_header};
use crate::{DecodeError, EncodeError, FORMAT_VERSION, PADDLES};

/// Length of an encoded [`OutReport`] in bytes.
pub const OUT_REPORT_LEN: usize = 2 + 2 * PADDLES;

/// A vibration pulse on one paddle's haptic motor.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct HapticPulse {
    /// Motor drive strength: PWM duty cycle in 1/255 steps (255 = full on).
    pub strength: u8,
    /// Pulse length in milliseconds; 0 means no pulse (and cancels a running one).
    pub duration_ms: u8,
}

/// The board's status LED.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[repr(u8)]
pub enum LedState {
    /// LED off.
    #[default]
    Off = 0,
    /// LED on.
    On = 1,
    /// Blink at 1 Hz (e.g. waiting for the host game).
    SlowBlink = 2,
    /// Blink at 4 Hz (e.g. attention: a sensor is missing).
    FastBlink = 3,
}

impl LedState {
    /// Parses the wire value, `None` for values this version does not define.
    pub const fn from_u8(value: u8) -> Option<Self> {
        match value {
            0 => Some(Self::Off),
            1 => Some(Self::On),
            2 => Some(Self::SlowBlink),
            3 => Some(Self::FastBlink),
            _ => None,
        }
    }
}

/// Host → device report on the interrupt OUT endpoint.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct OutReport {
    /// A pulse per paddle, indexed by port (0..8). A pulse with `duration_ms == 0`
    /// stops that paddle's motor.
    pub haptics: [HapticPulse; PADDLES],
    /// Status LED.
    pub led: LedState,
}

impl OutReport {
    /// Writes the report into `buf`, returning the number of bytes written
    /// ([`OUT_REPORT_LEN`]).
    pub fn encode(&self, buf: &mut [u8]) -> Result<usize, EncodeError> {
        check_buffer(buf, OUT_REPORT_LEN)?;
        buf[0] = FORMAT_VERSION;
        for (pulse, chunk) in self.haptics.iter().zip(buf[1..].chunks_exact_mut(2)) {
            chunk[0] = pulse.strength;
            chunk[1] = pulse.duration_ms;
        }
        buf[OUT_REPORT_LEN - 1] = self.led as u8;
        Ok(OUT_REPORT_LEN)
    }

    /// The encoded report as a fixed-size array.
    pub fn to_bytes(&self) -> [u8; OUT_REPORT_LEN] {
        let mut out = [0; OUT_REPORT_LEN];
        // The array has exactly the needed length, so encoding cannot fail.
        let _ = self.encode(&mut out);
        out
    }

    /// Parses a received report, rejecting wrong lengths, unknown versions and
    /// undefined LED states.
    pub fn decode(bytes: &[u8]) -> Result<Self, DecodeError> {
        check_header(bytes, OUT_REPORT_LEN)?;
        let mut haptics = [HapticPulse::default(); PADDLES];
        for (pulse, chunk) in haptics.iter_mut().zip(bytes[1..].chunks_exact(2)) {
            *pulse = HapticPulse {
                strength: chunk[0],
                duration_ms: chunk[1],
            };
        }
        let raw_led = bytes[OUT_REPORT_LEN - 1];
        let led = LedState::from_u8(raw_led).ok_or(DecodeError::BadField {
            field: "led",
            paddle: None,
            value: raw_led,
        })?;
        Ok(Self { haptics, led })
    }
}

//! Configuration of one mouse port.

/// Mouse resolution; the discriminant is the code sent after `0xE8` (set resolution).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[repr(u8)]
pub enum Resolution {
    /// 1 count/mm.
    CountsPerMm1 = 0,
    /// 2 counts/mm.
    CountsPerMm2 = 1,
    /// 4 counts/mm (the PS/2 power-on default).
    CountsPerMm4 = 2,
    /// 8 counts/mm (this crate's default: the finest).
    #[default]
    CountsPerMm8 = 3,
}

impl Resolution {
    /// The code sent after `0xE8`.
    pub const fn code(self) -> u8 {
        self as u8
    }

    /// Counts per millimetre of motion.
    pub const fn counts_per_mm(self) -> u8 {
        1 << (self as u8)
    }

    /// The resolution for a code, `None` for codes above 3.
    pub const fn from_code(code: u8) -> Option<Self> {
        match code {
            0 => Some(Self::CountsPerMm1),
            1 => Some(Self::CountsPerMm2),
            2 => Some(Self::CountsPerMm4),
            3 => Some(Self::CountsPerMm8),
            _ => None,
        }
    }
}

/// While absent, the driver sends a reset this often to find a replugged mouse,
/// microseconds. (A replugged mouse normally announces itself sooner with its
/// power-up `0xAA 0x00`; this is the fallback.)
pub const ABSENT_RETRY_INTERVAL_US: u64 = 250_000;

/// While streaming, a partial packet whose next byte has not arrived within this long
/// is discarded, microseconds.
///
/// The bytes of one packet come back to back: one 11-bit frame takes 0.66 ms at a
/// 16.7 kHz PS/2 clock and 1.1 ms at 10 kHz, so consecutive bytes of a packet end at most
/// ~1.2 ms apart. At 200 samples/s packets start 5 ms apart, so the last byte of one
/// packet and the first of the next end at least ~2.6 ms apart (10 kHz). A timeout
/// between the two (2 ms, leaving room for the firmware's 250 µs polling jitter) makes a
/// lost status byte cost at most one packet, even when the delta bytes have bit 3 set
/// and so look like status bytes to the bit-3 resync.
pub const INTER_BYTE_TIMEOUT_US: u64 = 2_000;

/// Configuration of one mouse port. All times in microseconds.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct MouseConfig {
    /// Sample rate sent after `0xF3`, samples per second (PS/2 allows 10, 20, 40, 60,
    /// 80, 100, 200; default 200). A value the mouse rejects makes the port absent.
    pub sample_rate: u8,
    /// Resolution sent after `0xE8`.
    pub resolution: Resolution,
    /// After the reset is acknowledged, how long to wait for the self-test result
    /// (`0xAA`), microseconds. The mouse may take up to about 2.5 s; default 3 s
    /// leaves a margin (an absent mouse fails earlier: it does not acknowledge the
    /// reset).
    pub self_test_timeout_us: u64,
    /// How long a command may take from the moment [`crate::MouseDriver::poll`] hands
    /// it out until the mouse's reply arrives (request-to-send, clocking the byte in,
    /// the mouse's response time — spec: ≤ 20 ms), microseconds. Default 25 ms.
    pub reply_timeout_us: u64,
    /// A streaming port silent this long is declared absent, microseconds. A mouse
    /// with no motion sends nothing, so after `silence_timeout_us - reply_timeout_us`
    /// of silence the driver sends a probe (`0xEB` read data, answered by `0xFA`);
    /// an unanswered probe makes the port absent at `silence_timeout_us`. Should
    /// exceed `reply_timeout_us`. Default 75 ms (probe after 50 ms of silence), which
    /// reports an unplugged mouse absent well within 100 ms.
    pub silence_timeout_us: u64,
}

impl MouseConfig {
    /// The defaults: 200 samples/s, 8 counts/mm, 3 s self-test, 25 ms reply
    /// timeout, 75 ms silence timeout.
    pub const DEFAULT: Self = Self {
        sample_rate: 200,
        resolution: Resolution::CountsPerMm8,
        self_test_timeout_us: 3_000_000,
        reply_timeout_us: 25_000,
        silence_timeout_us: 75_000,
    };

    /// Silence after which a streaming mouse is probed, microseconds (at least 1 ms).
    pub const fn probe_after_us(&self) -> u64 {
        let after = self
            .silence_timeout_us
            .saturating_sub(self.reply_timeout_us);
        if after < 1_000 {
            1_000
        } else {
            after
        }
    }
}

impl Default for MouseConfig {
    fn default() -> Self {
        Self::DEFAULT
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn resolution_codes() {
        for code in 0..=3 {
            let resolution = Resolution::from_code(code).expect("valid code");
            assert_eq!(resolution.code(), code);
            assert_eq!(resolution.counts_per_mm(), 1 << code);
        }
        assert_eq!(Resolution::from_code(4), None);
    }

    #[test]
    fn defaults_detect_unplug_within_100_ms() {
        let config = MouseConfig::default();
        assert_eq!(config.sample_rate, 200);
        assert!(config.self_test_timeout_us >= 2_500_000);
        assert!(config.reply_timeout_us >= 20_000);
        assert_eq!(config.probe_after_us(), 50_000);
        assert!(config.silence_timeout_us < 100_000);
    }

    #[test]
    fn probe_interval_never_zero() {
        let config = MouseConfig {
            silence_timeout_us: 10,
            reply_timeout_us: 20,
            ..MouseConfig::DEFAULT
        };
        assert_eq!(config.probe_after_us(), 1_000);
    }
}

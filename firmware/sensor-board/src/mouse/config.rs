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

/// How many times one command is sent before its failure counts: a failed send
/// (no clock, no acknowledge, a stalled frame) or a missing reply is retried once.
pub const SEND_ATTEMPTS: u8 = 2;

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
    /// How long sending one command may take, from the moment
    /// [`crate::MouseDriver::poll`] hands it out until the device has clocked it in
    /// and acknowledged it, microseconds. PS/2: the device starts clocking within
    /// 15 ms of request-to-send and the frame takes at most 2 ms; default 20 ms.
    pub send_timeout_us: u64,
    /// How long the mouse may take to answer a command once it has received it,
    /// microseconds. PS/2: 20 ms; default 25 ms.
    pub reply_timeout_us: u64,
    /// A streaming mouse silent this long is probed with a status request (`0xE9`):
    /// a present mouse answers `0xFA` and its three status bytes, which also show
    /// whether it still has the settings the driver gave it. Default 30 ms, so an
    /// unplugged mouse is absent within [`unplug_detection_us`](Self::unplug_detection_us).
    pub probe_after_us: u64,
}

impl MouseConfig {
    /// The defaults: 200 samples/s, 8 counts/mm, 3 s self-test, 20 ms to send a
    /// command, 25 ms for its reply, probe after 30 ms of silence.
    pub const DEFAULT: Self = Self {
        sample_rate: 200,
        resolution: Resolution::CountsPerMm8,
        self_test_timeout_us: 3_000_000,
        send_timeout_us: 20_000,
        reply_timeout_us: 25_000,
        probe_after_us: 30_000,
    };

    /// Longest time from a streaming mouse's last byte until the driver declares it
    /// absent when it is unplugged (it never clocks the probe in): the probe's
    /// silence, then [`SEND_ATTEMPTS`] sends that fail, microseconds.
    pub const fn unplug_detection_us(&self) -> u64 {
        self.probe_after_us
            .saturating_add(self.send_timeout_us.saturating_mul(SEND_ATTEMPTS as u64))
    }

    /// Longest time a present, slow but compliant mouse may take to answer a probe
    /// (send, then reply), microseconds.
    pub const fn command_budget_us(&self) -> u64 {
        self.send_timeout_us.saturating_add(self.reply_timeout_us)
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
    fn defaults_detect_unplug_within_100_ms_and_fit_a_slow_mouse() {
        let config = MouseConfig::default();
        assert_eq!(config.sample_rate, 200);
        assert!(config.self_test_timeout_us >= 2_500_000);
        // PS/2: 15 ms to start clocking + 2 ms frame; 20 ms to reply.
        assert!(config.send_timeout_us >= 17_000);
        assert!(config.reply_timeout_us >= 20_000);
        assert!(config.command_budget_us() >= 37_000);
        assert!(config.unplug_detection_us() < 100_000);
    }
}

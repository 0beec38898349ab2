//! The watchdog: resets the chip if the sensor loop stops running.
//!
//! The sensor loop feeds it every pass (every 250 µs); if the executor wedges, a
//! task hogs the CPU, or a PS/2 port's handling loops, the chip resets after
//! [`TIMEOUT`] and the mice are re-initialised from scratch. It is paused while a
//! debugger halts the core.

use embassy_rp::peripherals::WATCHDOG;
use embassy_rp::watchdog::{ResetReason, Watchdog as RpWatchdog};
use embassy_rp::Peri;
use embassy_time::Duration;

/// How long the sensor loop may go without feeding the watchdog.
pub const TIMEOUT: Duration = Duration::from_millis(100);

/// The running watchdog.
pub struct Watchdog(RpWatchdog);

impl Watchdog {
    /// Logs why the chip last reset if the watchdog did it, then starts the watchdog.
    pub fn start(peripheral: Peri<'static, WATCHDOG>) -> Self {
        let mut watchdog = RpWatchdog::new(peripheral);
        match watchdog.reset_reason() {
            Some(ResetReason::TimedOut) => defmt::warn!("reset by the watchdog (timed out)"),
            Some(ResetReason::Forced) => defmt::info!("reset by the watchdog (forced)"),
            None => {}
        }
        watchdog.pause_on_debug(true);
        watchdog.start(TIMEOUT);
        Self(watchdog)
    }

    /// Restarts the countdown.
    pub fn feed(&mut self) {
        self.0.feed(TIMEOUT);
    }
}

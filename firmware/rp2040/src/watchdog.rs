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
use foosball_protocol::ResetReason as BootReason;

/// How long the sensor loop may go without feeding the watchdog.
pub const TIMEOUT: Duration = Duration::from_millis(100);

/// The running watchdog.
pub struct Watchdog(RpWatchdog);

impl Watchdog {
    /// Logs why the chip last reset if the watchdog did it, then starts the watchdog.
    /// Returns it and the reset reason (`panicked`: the previous run left a panic
    /// message, so its forced reset was the panic's).
    pub fn start(peripheral: Peri<'static, WATCHDOG>, panicked: bool) -> (Self, BootReason) {
        let mut watchdog = RpWatchdog::new(peripheral);
        let reason = match watchdog.reset_reason() {
            Some(ResetReason::TimedOut) => {
                defmt::warn!("reset by the watchdog (timed out)");
                BootReason::WatchdogTimeout
            }
            Some(ResetReason::Forced) => {
                defmt::info!("reset by the watchdog (forced)");
                BootReason::Forced
            }
            None => BootReason::PowerOn,
        };
        watchdog.pause_on_debug(true);
        watchdog.start(TIMEOUT);
        let reason = if panicked { BootReason::Panic } else { reason };
        (Self(watchdog), reason)
    }

    /// Restarts the countdown.
    pub fn feed(&mut self) {
        self.0.feed(TIMEOUT);
    }
}

/// Gives the running watchdog `timeout` from now (at most 8 s), without the
/// [`Watchdog`] handle: for a long flash operation with interrupts off. The sensor
/// loop's next feed puts it back to [`TIMEOUT`].
pub fn allow(timeout: Duration) {
    // RP2040-E1: the counter decrements twice per microsecond, so the load value is
    // twice the microseconds (as embassy-rp's `feed`); 24 bits.
    let ticks = timeout.as_micros().saturating_mul(2).min(0xFF_FFFF) as u32;
    embassy_rp::pac::WATCHDOG
        .load()
        .write_value(embassy_rp::pac::watchdog::regs::Load(ticks));
}

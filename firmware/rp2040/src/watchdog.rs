//! The watchdog: resets the chip if the sensor loop or the IN reports stop running.
//!
//! The sensor loop feeds it every pass (every 250 µs), but only once every task of
//! [`Task`] has checked in since the last feed ([`check_in`]); if the executor wedges,
//! a task hogs the CPU or waits forever, or a PS/2 port's handling loops, the chip
//! resets after [`TIMEOUT`] and the mice are re-initialised from scratch. It is paused
//! while a debugger halts the core.

use core::cell::Cell;

use embassy_rp::peripherals::WATCHDOG;
use embassy_rp::watchdog::{ResetReason, Watchdog as RpWatchdog};
use embassy_rp::Peri;
use embassy_sync::blocking_mutex::raw::CriticalSectionRawMutex;
use embassy_sync::blocking_mutex::Mutex;
use embassy_time::Duration;
use foosball_protocol::ResetReason as BootReason;

/// How long the sensor loop may go without feeding the watchdog.
pub const TIMEOUT: Duration = Duration::from_millis(100);

/// The tasks that must check in between two feeds.
#[derive(Clone, Copy)]
pub enum Task {
    /// The sensor loop (each pass).
    Sensors = 0,
    /// The IN report task (each report, each replacement, and while it waits for the
    /// host to enable the endpoint).
    ReportsIn = 1,
}

/// Every [`Task`]'s bit.
const ALL_TASKS: u8 = 0b11;

/// The tasks checked in since the last feed, one bit each.
static CHECKED_IN: Mutex<CriticalSectionRawMutex, Cell<u8>> = Mutex::new(Cell::new(0));

/// `task` is running.
pub fn check_in(task: Task) {
    CHECKED_IN.lock(|bits| bits.set(bits.get() | 1 << task as u8));
}

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

    /// Restarts the countdown if every task has checked in since the last time it did.
    pub fn feed(&mut self) {
        let all = CHECKED_IN.lock(|bits| {
            let all = bits.get() == ALL_TASKS;
            if all {
                bits.set(0);
            }
            all
        });
        if all {
            self.0.feed(TIMEOUT);
        }
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

//! The status LED (the Pico's on-board LED): on, off, or blinking, as the host says.
//!
//! Until the host sends its first OUT report the LED blinks slowly, which shows the
//! firmware is running before any host software is.

use embassy_futures::select::{select, Either};
use embassy_rp::gpio::{Level, Output};
use embassy_rp::peripherals::PIN_25;
use embassy_rp::Peri;
use embassy_sync::blocking_mutex::raw::ThreadModeRawMutex;
use embassy_sync::signal::Signal;
use embassy_time::{Duration, Instant, Timer};
use foosball_protocol::LedState;

/// The LED state the host asked for last.
pub static STATE: Signal<ThreadModeRawMutex, LedState> = Signal::new();

/// What the LED shows before the host says otherwise.
pub const BOOT_STATE: LedState = LedState::SlowBlink;

/// Time the LED spends on (and off) per blink: 1 Hz and 4 Hz blinking.
fn half_period(state: LedState) -> Option<Duration> {
    match state {
        LedState::SlowBlink => Some(Duration::from_millis(500)),
        LedState::FastBlink => Some(Duration::from_millis(125)),
        LedState::Off | LedState::On => None,
    }
}

/// Drives the LED from [`STATE`]. A repeated state keeps the blink rhythm.
#[embassy_executor::task]
pub async fn led_task(pin: Peri<'static, PIN_25>) -> ! {
    let mut led = Output::new(pin, Level::Low);
    let mut state = BOOT_STATE;
    let mut next_toggle = Instant::now();
    loop {
        let new = match half_period(state) {
            Some(half) => {
                let now = Instant::now();
                if now >= next_toggle {
                    led.toggle();
                    next_toggle = now + half;
                }
                match select(STATE.wait(), Timer::at(next_toggle)).await {
                    Either::First(new) => new,
                    Either::Second(()) => continue,
                }
            }
            None => {
                let level = if state == LedState::On {
                    Level::High
                } else {
                    Level::Low
                };
                led.set_level(level);
                STATE.wait().await
            }
        };
        if new != state {
            state = new;
            // A new blink mode starts with a toggle right away.
            next_toggle = Instant::now();
        }
    }
}

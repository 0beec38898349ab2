//! Haptic motors: eight PWM outputs, each pulsed for a time at a strength.
//!
//! Each output drives the gate of a logic-level MOSFET (or a motor driver input),
//! never a motor directly. A [`HapticPulse`] from the host's OUT report sets the duty
//! cycle (`strength / 255`) and how long it lasts (`duration_ms`); then the output
//! goes back to 0 %. A new report replaces every motor's pulse; `duration_ms == 0`
//! (or strength 0) stops that motor at once.

use embassy_futures::select::{select, Either};
use embassy_rp::pwm::{self, Pwm};
use embassy_sync::blocking_mutex::raw::ThreadModeRawMutex;
use embassy_sync::signal::Signal;
use embassy_time::{Duration, Instant, Timer};
use foosball_protocol::{HapticPulse, PADDLES};

use crate::pins::HapticPins;

/// PWM frequency: above hearing, low enough for MOSFET gate switching losses.
const PWM_HZ: u32 = 20_000;

/// The latest haptic pulses from the host (a newer report replaces an unread one:
/// each report carries all eight motors).
pub static PULSES: Signal<ThreadModeRawMutex, [HapticPulse; PADDLES]> = Signal::new();

/// Which PWM channel of which slice drives a motor.
#[derive(Clone, Copy)]
enum Channel {
    A,
    B,
}

/// Motor index → (index into [`Haptics::slices`], channel); must match the pin map.
const MOTOR_CHANNELS: [(usize, Channel); PADDLES] = [
    (0, Channel::A),
    (0, Channel::B),
    (1, Channel::A),
    (1, Channel::B),
    (2, Channel::A),
    (2, Channel::B),
    (3, Channel::A),
    (4, Channel::A),
];

/// The eight motor outputs and their running pulses.
pub struct Haptics {
    slices: [Pwm<'static>; 5],
    configs: [pwm::Config; 5],
    /// When each motor's pulse ends (`None`: off).
    ends: [Option<Instant>; PADDLES],
}

impl Haptics {
    /// Sets up the five PWM slices behind the eight outputs, all off.
    pub fn new(pins: HapticPins) -> Self {
        let mut config = pwm::Config::default();
        // Counter runs 0..=top at clk_sys: top + 1 = clk_sys / PWM_HZ.
        let top = embassy_rp::clocks::clk_sys_freq() / PWM_HZ - 1;
        config.top = top.min(u32::from(u16::MAX - 1)) as u16;
        config.compare_a = 0;
        config.compare_b = 0;
        let (s0, p16, p17) = pins.slice0;
        let (s1, p18, p19) = pins.slice1;
        let (s2, p20, p21) = pins.slice2;
        let (s3, p22) = pins.slice3;
        let (s6, p28) = pins.slice6;
        Self {
            slices: [
                Pwm::new_output_ab(s0, p16, p17, config.clone()),
                Pwm::new_output_ab(s1, p18, p19, config.clone()),
                Pwm::new_output_ab(s2, p20, p21, config.clone()),
                Pwm::new_output_a(s3, p22, config.clone()),
                Pwm::new_output_a(s6, p28, config.clone()),
            ],
            configs: [
                config.clone(),
                config.clone(),
                config.clone(),
                config.clone(),
                config,
            ],
            ends: [None; PADDLES],
        }
    }

    /// Starts (or with `duration_ms == 0` / `strength == 0`, stops) every motor's pulse.
    pub fn apply(&mut self, pulses: &[HapticPulse; PADDLES], now: Instant) {
        for (motor, pulse) in pulses.iter().enumerate() {
            if pulse.duration_ms == 0 || pulse.strength == 0 {
                self.set_strength(motor, 0);
                self.ends[motor] = None;
            } else {
                self.set_strength(motor, pulse.strength);
                self.ends[motor] = Some(now + Duration::from_millis(pulse.duration_ms.into()));
            }
        }
    }

    /// Turns off the motors whose pulse has ended by `now`.
    pub fn expire(&mut self, now: Instant) {
        for motor in 0..PADDLES {
            if self.ends[motor].is_some_and(|end| end <= now) {
                self.set_strength(motor, 0);
                self.ends[motor] = None;
            }
        }
    }

    /// When the next running pulse ends.
    pub fn next_end(&self) -> Option<Instant> {
        self.ends.iter().flatten().min().copied()
    }

    /// Sets one motor's duty cycle to `strength / 255` (255 = always on).
    fn set_strength(&mut self, motor: usize, strength: u8) {
        let (slice, channel) = MOTOR_CHANNELS[motor];
        let config = &mut self.configs[slice];
        // Compare = top + 1 is 100 %; scale 0..=255 onto 0..=top + 1.
        let full = u32::from(config.top) + 1;
        let compare = (full * u32::from(strength) / 255) as u16;
        match channel {
            Channel::A => config.compare_a = compare,
            Channel::B => config.compare_b = compare,
        }
        self.slices[slice].set_config(config);
    }
}

/// Applies the host's pulses and ends them on time.
#[embassy_executor::task]
pub async fn haptics_task(mut haptics: Haptics) -> ! {
    loop {
        let pulses = match haptics.next_end() {
            Some(end) => match select(PULSES.wait(), Timer::at(end)).await {
                Either::First(pulses) => Some(pulses),
                Either::Second(()) => None,
            },
            // Nothing running: only the host can change anything.
            None => Some(PULSES.wait().await),
        };
        let now = Instant::now();
        match pulses {
            Some(pulses) => haptics.apply(&pulses, now),
            None => haptics.expire(now),
        }
    }
}

//! Haptics: a kick felt in the paddle (paper §6).
//!
//! The match reports a kick as (paddle index `0..8`, kick speed in m/s); [`Haptics`]
//! turns it into the [`OutReport`] to send, whose [`HapticPulse`] drives that paddle's
//! motor (PWM duty `strength / 255` for `duration_ms`, see `firmware/README.md`).
//!
//! # The mapping ([`KickFeel::DEFAULT`])
//!
//! With `x = clamp((speed − 0.3 m/s) / (6.0 m/s − 0.3 m/s), 0, 1)`:
//!
//! | kick speed | pulse |
//! |---|---|
//! | below 0.3 m/s, zero, negative, NaN | none (a touch, not a kick) |
//! | 0.3 m/s | strength 80, 20 ms |
//! | in between | strength `80 + 175·x`, duration `20 + 40·x` ms (linear, rounded) |
//! | 6.0 m/s and faster | strength 255, 60 ms (saturated) |
//!
//! The floor of 80/255 is about where a small vibration motor starts turning; a pulse
//! shorter than ~20 ms is not felt through a rod handle, one longer than ~60 ms blurs
//! into the next kick.
//!
//! # Several motors
//!
//! The board replaces all eight pulses with every OUT report and a pulse with
//! `duration_ms == 0` stops its motor, so a report for one kick must carry the
//! remainder of every pulse still running. [`Haptics`] keeps track of them: each
//! report it builds gives the other paddles their remaining time (rounded up to
//! whole milliseconds) at their strength. A kick on a paddle whose motor is still
//! running keeps the stronger strength and the later end.

use std::time::Duration;

use foosball_protocol::{HapticPulse, LedState, OutReport, PADDLES};

/// How kick speed maps to a pulse: a linear ramp between two speeds, saturating.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct KickFeel {
    /// Slower kicks (and non-finite or negative speeds) give no pulse, m/s.
    pub min_speed_m_s: f32,
    /// Kicks at least this fast give the strongest, longest pulse, m/s.
    pub full_speed_m_s: f32,
    /// Strength of a kick at `min_speed_m_s` (0–255).
    pub min_strength: u8,
    /// Strength from `full_speed_m_s` on (0–255).
    pub max_strength: u8,
    /// Duration of a kick at `min_speed_m_s`, milliseconds.
    pub min_duration_ms: u8,
    /// Duration from `full_speed_m_s` on, milliseconds.
    pub max_duration_ms: u8,
}

impl KickFeel {
    /// The mapping documented in the [module](self) docs.
    pub const DEFAULT: Self = Self {
        min_speed_m_s: 0.3,
        full_speed_m_s: 6.0,
        min_strength: 80,
        max_strength: 255,
        min_duration_ms: 20,
        max_duration_ms: 60,
    };

    /// The pulse for a kick at `speed_m_s`; `None` for speeds below the threshold
    /// (and NaN).
    pub fn pulse(&self, speed_m_s: f32) -> Option<HapticPulse> {
        if speed_m_s.is_nan() || speed_m_s < self.min_speed_m_s {
            return None;
        }
        let span = self.full_speed_m_s - self.min_speed_m_s;
        let x = if span > 0.0 {
            ((speed_m_s - self.min_speed_m_s) / span).clamp(0.0, 1.0)
        } else {
            1.0
        };
        let lerp = |lo: u8, hi: u8| -> u8 {
            let value = f32::from(lo) + (f32::from(hi) - f32::from(lo)) * x;
            // `as` saturates: the value is already within lo..=hi.
            value.round() as u8
        };
        Some(HapticPulse {
            strength: lerp(self.min_strength, self.max_strength),
            duration_ms: lerp(self.min_duration_ms, self.max_duration_ms),
        })
    }
}

impl Default for KickFeel {
    fn default() -> Self {
        Self::DEFAULT
    }
}

/// A pulse being played on one motor.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct Running {
    strength: u8,
    /// When it ends, on the caller's clock.
    end: Duration,
}

/// Turns kicks into OUT reports, keeping the pulses of the other paddles running.
///
/// Time is whatever monotonic clock the caller uses (e.g. time since the match
/// started), passed as `now`.
#[derive(Debug, Clone)]
pub struct Haptics {
    feel: KickFeel,
    led: LedState,
    running: [Option<Running>; PADDLES],
}

impl Haptics {
    /// No pulse running; the LED is reported `On`.
    pub fn new(feel: KickFeel) -> Self {
        Self {
            feel,
            led: LedState::On,
            running: [None; PADDLES],
        }
    }

    /// The LED state carried by the following reports.
    pub fn set_led(&mut self, led: LedState) {
        self.led = led;
    }

    /// A kick by `paddle` (`0..8`) at `speed_m_s`: the report to send now, or `None`
    /// when nothing changes (paddle out of range, kick too soft).
    pub fn kick(&mut self, paddle: usize, speed_m_s: f32, now: Duration) -> Option<OutReport> {
        let pulse = self.feel.pulse(speed_m_s)?;
        let slot = self.running.get_mut(paddle)?;
        let new = Running {
            strength: pulse.strength,
            end: now + Duration::from_millis(pulse.duration_ms.into()),
        };
        *slot = Some(match *slot {
            Some(old) if old.end > now => Running {
                strength: old.strength.max(new.strength),
                end: old.end.max(new.end),
            },
            _ => new,
        });
        Some(self.report(now))
    }

    /// The report that keeps every running pulse going as planned (remaining time
    /// rounded up to whole milliseconds, at most 255 ms) and stops the others.
    pub fn report(&self, now: Duration) -> OutReport {
        let mut haptics = [HapticPulse::default(); PADDLES];
        for (pulse, running) in haptics.iter_mut().zip(&self.running) {
            if let Some(running) = running.filter(|r| r.end > now) {
                let remaining_us = (running.end - now).as_micros();
                let remaining_ms = remaining_us.div_ceil(1000).min(u128::from(u8::MAX));
                *pulse = HapticPulse {
                    strength: running.strength,
                    duration_ms: remaining_ms as u8,
                };
            }
        }
        OutReport {
            haptics,
            led: self.led,
        }
    }
}

impl Default for Haptics {
    fn default() -> Self {
        Self::new(KickFeel::DEFAULT)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const FEEL: KickFeel = KickFeel::DEFAULT;

    fn ms(value: u64) -> Duration {
        Duration::from_millis(value)
    }

    #[test]
    fn soft_or_invalid_kicks_give_no_pulse() {
        for speed in [0.0, 0.29, -3.0, f32::NAN, f32::NEG_INFINITY] {
            assert_eq!(FEEL.pulse(speed), None, "speed {speed}");
        }
    }

    #[test]
    fn threshold_kick_is_the_weakest_pulse() {
        assert_eq!(
            FEEL.pulse(0.3),
            Some(HapticPulse {
                strength: 80,
                duration_ms: 20
            })
        );
    }

    #[test]
    fn fast_kicks_saturate() {
        let full = Some(HapticPulse {
            strength: 255,
            duration_ms: 60,
        });
        for speed in [6.0, 7.5, 100.0, f32::INFINITY, f32::MAX] {
            assert_eq!(FEEL.pulse(speed), full, "speed {speed}");
        }
    }

    #[test]
    fn midway_kick_is_midway() {
        // x = 0.5: strength 80 + 87.5 → 168 (rounded), duration 40 ms.
        assert_eq!(
            FEEL.pulse(3.15),
            Some(HapticPulse {
                strength: 168,
                duration_ms: 40
            })
        );
    }

    #[test]
    fn harder_kicks_never_feel_weaker() {
        let mut previous = HapticPulse::default();
        for step in 0..=700 {
            let speed = step as f32 * 0.01;
            if let Some(pulse) = FEEL.pulse(speed) {
                assert!(pulse.strength >= previous.strength, "speed {speed}");
                assert!(pulse.duration_ms >= previous.duration_ms, "speed {speed}");
                assert!((20..=60).contains(&pulse.duration_ms));
                previous = pulse;
            }
        }
        assert_eq!(previous.strength, 255);
    }

    #[test]
    fn kick_drives_only_its_paddle() {
        let mut haptics = Haptics::default();
        let report = haptics.kick(5, 6.0, ms(1000)).unwrap();
        for (paddle, pulse) in report.haptics.iter().enumerate() {
            if paddle == 5 {
                assert_eq!(
                    *pulse,
                    HapticPulse {
                        strength: 255,
                        duration_ms: 60
                    }
                );
            } else {
                assert_eq!(*pulse, HapticPulse::default(), "paddle {paddle}");
            }
        }
        assert_eq!(report.led, LedState::On);
        // It encodes as a valid OUT report.
        assert_eq!(OutReport::decode(&report.to_bytes()), Ok(report));
    }

    #[test]
    fn out_of_range_paddle_or_soft_kick_sends_nothing() {
        let mut haptics = Haptics::default();
        assert_eq!(haptics.kick(8, 5.0, ms(0)), None);
        assert_eq!(haptics.kick(usize::MAX, 5.0, ms(0)), None);
        assert_eq!(haptics.kick(2, 0.1, ms(0)), None);
        assert_eq!(
            haptics.report(ms(0)),
            OutReport {
                haptics: [HapticPulse::default(); PADDLES],
                led: LedState::On
            }
        );
    }

    #[test]
    fn a_second_kick_keeps_the_first_pulse_running() {
        let mut haptics = Haptics::default();
        haptics.kick(1, 6.0, ms(0)).unwrap(); // 255 for 60 ms
        let report = haptics.kick(6, 0.3, Duration::from_micros(25_500)).unwrap();
        // Paddle 1 has 34.5 ms left: rounded up to 35.
        assert_eq!(
            report.haptics[1],
            HapticPulse {
                strength: 255,
                duration_ms: 35
            }
        );
        assert_eq!(
            report.haptics[6],
            HapticPulse {
                strength: 80,
                duration_ms: 20
            }
        );
    }

    #[test]
    fn finished_pulses_are_not_repeated() {
        let mut haptics = Haptics::default();
        haptics.kick(1, 6.0, ms(0)).unwrap();
        let report = haptics.kick(2, 6.0, ms(60)).unwrap();
        assert_eq!(report.haptics[1], HapticPulse::default());
        assert_eq!(report.haptics[2].duration_ms, 60);
    }

    #[test]
    fn kicking_a_running_paddle_keeps_the_stronger_and_longer() {
        let mut haptics = Haptics::default();
        haptics.kick(4, 6.0, ms(0)).unwrap(); // 255 until 60 ms
        let report = haptics.kick(4, 0.3, ms(50)).unwrap(); // 80 until 70 ms
        assert_eq!(
            report.haptics[4],
            HapticPulse {
                strength: 255,
                duration_ms: 20
            }
        );
    }

    #[test]
    fn led_state_is_carried() {
        let mut haptics = Haptics::default();
        haptics.set_led(LedState::FastBlink);
        assert_eq!(
            haptics.kick(0, 1.0, ms(0)).unwrap().led,
            LedState::FastBlink
        );
    }
}

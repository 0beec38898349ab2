//! The sounds, synthesised in code: mono `f32` samples at [`SAMPLE_RATE_HZ`], every
//! sample finite and within `[-1, 1]`, a pure function of the parameters (no global
//! state, no randomness beyond a fixed-seed generator), so tests and replays hear the
//! same thing every time.
//!
//! Units: durations in seconds, frequencies in hertz, speeds in metres per second,
//! amplitudes as linear full-scale fractions (1 = 0 dBFS).

use std::f32::consts::TAU;

/// Sample rate of every buffer, Hz.
pub const SAMPLE_RATE_HZ: u32 = 48_000;

/// Duration of [`kick`], s.
pub const KICK_S: f32 = 0.15;
/// Kick speed at which [`kick`] is loudest and highest, m/s (faster kicks sound the same).
pub const KICK_SPEED_FULL_M_S: f32 = 8.0;
/// Peak amplitude of a kick at speed 0.
pub const KICK_PEAK_MIN: f32 = 0.2;
/// Peak amplitude of a kick at [`KICK_SPEED_FULL_M_S`] and above.
pub const KICK_PEAK_MAX: f32 = 0.9;

/// Duration of [`bounce`], s.
pub const BOUNCE_S: f32 = 0.08;
/// Impact speed at which [`bounce`] is loudest, m/s.
pub const BOUNCE_SPEED_FULL_M_S: f32 = 5.0;
/// Peak amplitude of a bounce at impact speed 0.
pub const BOUNCE_PEAK_MIN: f32 = 0.08;
/// Peak amplitude of a bounce at [`BOUNCE_SPEED_FULL_M_S`] and above.
pub const BOUNCE_PEAK_MAX: f32 = 0.55;

/// Duration of [`goal_fanfare`], s (the renderer's goal burst lasts as long).
pub const GOAL_FANFARE_S: f32 = 1.6;
/// Peak amplitude of [`goal_fanfare`].
pub const GOAL_FANFARE_PEAK: f32 = 0.8;

/// Duration of [`menu_tick`], s.
pub const MENU_TICK_S: f32 = 0.03;
/// Peak amplitude of [`menu_tick`].
pub const MENU_TICK_PEAK: f32 = 0.3;

/// Duration of [`menu_confirm`], s.
pub const MENU_CONFIRM_S: f32 = 0.2;
/// Peak amplitude of [`menu_confirm`].
pub const MENU_CONFIRM_PEAK: f32 = 0.5;

/// Length of the fade-out that ends every sound (no click at the end), s.
const FADE_OUT_S: f32 = 0.003;

/// Number of samples in `duration_s` seconds at [`SAMPLE_RATE_HZ`].
pub fn samples_for(duration_s: f32) -> usize {
    (duration_s * SAMPLE_RATE_HZ as f32).round() as usize
}

/// `speed / full`, clamped to `[0, 1]`; a non-finite or negative speed counts as 0.
fn speed_fraction(speed_m_s: f32, full_m_s: f32) -> f32 {
    if speed_m_s.is_finite() {
        (speed_m_s / full_m_s).clamp(0.0, 1.0)
    } else {
        0.0
    }
}

/// A kick: a low thump whose pitch drops as it decays, with a short noise click on
/// the strike. Faster kicks are louder and higher:
///
/// with `s = clamp(speed / 8 m/s, 0, 1)`, peak amplitude `0.2 + 0.7·s`, start pitch
/// `110 + 190·s` Hz sliding down to 40 % of it; 2 ms attack, decay time constant 35 ms,
/// 4 ms click. Lasts [`KICK_S`] (0.15 s).
pub fn kick(speed_m_s: f32) -> Vec<f32> {
    let s = speed_fraction(speed_m_s, KICK_SPEED_FULL_M_S);
    let f0 = 110.0 + 190.0 * s;
    let n = samples_for(KICK_S);
    let mut noise = Noise::new(0x6b69_636b);
    let mut phase = 0.0f32;
    let mut out = Vec::with_capacity(n);
    for i in 0..n {
        let t = i as f32 / SAMPLE_RATE_HZ as f32;
        // Exponential glide from f0 to 0.4·f0 over the sound.
        let f = f0 * 0.4f32.powf(t / KICK_S);
        phase = (phase + TAU * f / SAMPLE_RATE_HZ as f32) % TAU;
        let body = phase.sin() * (-t / 0.035).exp();
        let click = if t < 0.004 {
            0.6 * noise.next() * (1.0 - t / 0.004)
        } else {
            0.0
        };
        out.push((body + click) * attack(t, 0.002));
    }
    finish(out, KICK_PEAK_MIN + (KICK_PEAK_MAX - KICK_PEAK_MIN) * s)
}

/// A bounce of the ball on the cloth or a wall: a short wooden "tock" (partials at
/// 520 and 1370 Hz, decay time constant 14 ms). With `s = clamp(speed / 5 m/s, 0, 1)`
/// (impact speed), peak amplitude `0.08 + 0.47·s`. Lasts [`BOUNCE_S`] (0.08 s).
pub fn bounce(speed_m_s: f32) -> Vec<f32> {
    let s = speed_fraction(speed_m_s, BOUNCE_SPEED_FULL_M_S);
    let n = samples_for(BOUNCE_S);
    let out = (0..n)
        .map(|i| {
            let t = i as f32 / SAMPLE_RATE_HZ as f32;
            let tone = (TAU * 520.0 * t).sin() + 0.45 * (TAU * 1370.0 * t).sin();
            tone * (-t / 0.014).exp() * attack(t, 0.001)
        })
        .collect();
    finish(
        out,
        BOUNCE_PEAK_MIN + (BOUNCE_PEAK_MAX - BOUNCE_PEAK_MIN) * s,
    )
}

/// The goal ceremony fanfare: a brassy rising arpeggio C5–E5–G5 (0.15 s each) into a
/// held C major chord (C5, E5, G5, C6) with vibrato that swells and fades out by
/// [`GOAL_FANFARE_S`] (1.6 s). Brass timbre: odd harmonics 1, 1/3, 1/5. Peak
/// [`GOAL_FANFARE_PEAK`].
pub fn goal_fanfare() -> Vec<f32> {
    const C5: f32 = 523.25;
    const E5: f32 = 659.26;
    const G5: f32 = 783.99;
    const C6: f32 = 1046.50;
    const STEP_S: f32 = 0.15;
    // (start s, frequency Hz, length s)
    let notes = [
        (0.0, C5, STEP_S),
        (STEP_S, E5, STEP_S),
        (2.0 * STEP_S, G5, STEP_S),
        (3.0 * STEP_S, C5, GOAL_FANFARE_S - 3.0 * STEP_S),
        (3.0 * STEP_S, E5, GOAL_FANFARE_S - 3.0 * STEP_S),
        (3.0 * STEP_S, G5, GOAL_FANFARE_S - 3.0 * STEP_S),
        (3.0 * STEP_S, C6, GOAL_FANFARE_S - 3.0 * STEP_S),
    ];
    let n = samples_for(GOAL_FANFARE_S);
    let mut out = vec![0.0f32; n];
    for (start, freq, len) in notes {
        let held = len > STEP_S;
        let first = samples_for(start);
        let last = samples_for(start + len).min(n);
        for (k, y) in out[first..last].iter_mut().enumerate() {
            let t = k as f32 / SAMPLE_RATE_HZ as f32;
            let vibrato = if held {
                1.0 + 0.006 * (TAU * 5.5 * t).sin() * (t / 0.4).min(1.0)
            } else {
                1.0
            };
            let p = TAU * freq * vibrato * t;
            let tone = p.sin() + (3.0 * p).sin() / 3.0 + (5.0 * p).sin() / 5.0;
            let env = if held {
                // Swell, then a slow fade to silence at the end.
                attack(t, 0.03) * (1.0 - t / len).max(0.0).powf(0.7)
            } else {
                attack(t, 0.01) * (1.0 - 0.5 * t / len)
            };
            *y += tone * env;
        }
    }
    finish(out, GOAL_FANFARE_PEAK)
}

/// A menu tick (spinning a rod moves the choice): a 1800 Hz blip, decay time
/// constant 6 ms, lasting [`MENU_TICK_S`] (0.03 s), peak [`MENU_TICK_PEAK`].
pub fn menu_tick() -> Vec<f32> {
    let n = samples_for(MENU_TICK_S);
    let out = (0..n)
        .map(|i| {
            let t = i as f32 / SAMPLE_RATE_HZ as f32;
            (TAU * 1800.0 * t).sin() * (-t / 0.006).exp() * attack(t, 0.0005)
        })
        .collect();
    finish(out, MENU_TICK_PEAK)
}

/// A menu confirm (pushing a rod chooses): two rising notes, 880 Hz then 1320 Hz
/// (a fifth up), 0.07 s apart, each decaying with time constant 40 ms; lasts
/// [`MENU_CONFIRM_S`] (0.2 s), peak [`MENU_CONFIRM_PEAK`].
pub fn menu_confirm() -> Vec<f32> {
    let n = samples_for(MENU_CONFIRM_S);
    let out = (0..n)
        .map(|i| {
            let t = i as f32 / SAMPLE_RATE_HZ as f32;
            let note = |start: f32, f: f32| {
                if t < start {
                    0.0
                } else {
                    let u = t - start;
                    let p = TAU * f * u;
                    (p.sin() + 0.25 * (2.0 * p).sin()) * (-u / 0.04).exp() * attack(u, 0.002)
                }
            };
            note(0.0, 880.0) + note(0.07, 1320.0)
        })
        .collect();
    finish(out, MENU_CONFIRM_PEAK)
}

/// Linear attack over `attack_s` seconds: 0 at `t = 0`, 1 from `attack_s` on.
fn attack(t: f32, attack_s: f32) -> f32 {
    (t / attack_s).min(1.0)
}

/// Fades the last [`FADE_OUT_S`] out and scales the buffer so its largest magnitude is
/// exactly `peak` (a silent buffer stays silent).
fn finish(mut out: Vec<f32>, peak: f32) -> Vec<f32> {
    let fade = samples_for(FADE_OUT_S).min(out.len());
    let n = out.len();
    for (k, y) in out[n - fade..].iter_mut().enumerate() {
        *y *= 1.0 - (k + 1) as f32 / fade as f32;
    }
    let max = out.iter().fold(0.0f32, |m, y| m.max(y.abs()));
    if max > 0.0 && max.is_finite() {
        let g = peak / max;
        for y in &mut out {
            *y = (*y * g).clamp(-1.0, 1.0);
        }
    }
    out
}

/// A small deterministic white-noise generator (xorshift32), samples in `[-1, 1)`.
struct Noise(u32);

impl Noise {
    fn new(seed: u32) -> Noise {
        Noise(seed.max(1))
    }

    fn next(&mut self) -> f32 {
        let mut x = self.0;
        x ^= x << 13;
        x ^= x >> 17;
        x ^= x << 5;
        self.0 = x;
        (x as f32 / u32::MAX as f32) * 2.0 - 1.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn peak(b: &[f32]) -> f32 {
        b.iter().fold(0.0f32, |m, y| m.max(y.abs()))
    }

    fn rms(b: &[f32]) -> f32 {
        (b.iter().map(|y| y * y).sum::<f32>() / b.len() as f32).sqrt()
    }

    /// Every sound with its documented duration and the peak it promises.
    fn all() -> Vec<(&'static str, Vec<f32>, f32, f32)> {
        vec![
            ("kick(0)", kick(0.0), KICK_S, KICK_PEAK_MIN),
            ("kick(3)", kick(3.0), KICK_S, 0.2 + 0.7 * 3.0 / 8.0),
            ("kick(20)", kick(20.0), KICK_S, KICK_PEAK_MAX),
            ("bounce(0)", bounce(0.0), BOUNCE_S, BOUNCE_PEAK_MIN),
            ("bounce(9)", bounce(9.0), BOUNCE_S, BOUNCE_PEAK_MAX),
            (
                "goal_fanfare",
                goal_fanfare(),
                GOAL_FANFARE_S,
                GOAL_FANFARE_PEAK,
            ),
            ("menu_tick", menu_tick(), MENU_TICK_S, MENU_TICK_PEAK),
            (
                "menu_confirm",
                menu_confirm(),
                MENU_CONFIRM_S,
                MENU_CONFIRM_PEAK,
            ),
        ]
    }

    #[test]
    fn every_sound_is_finite_bounded_non_silent_and_of_its_duration() {
        for (name, b, dur, want_peak) in all() {
            assert_eq!(b.len(), samples_for(dur), "{name}: length");
            assert!(
                (b.len() as f32 / SAMPLE_RATE_HZ as f32 - dur).abs() < 1e-4,
                "{name}: duration"
            );
            assert!(b.iter().all(|y| y.is_finite()), "{name}: non-finite sample");
            assert!(
                b.iter().all(|y| (-1.0..=1.0).contains(y)),
                "{name}: out of range"
            );
            assert!(
                (peak(&b) - want_peak).abs() < 1e-4,
                "{name}: peak {}",
                peak(&b)
            );
            assert!(rms(&b) > 0.01, "{name}: nearly silent (rms {})", rms(&b));
            // Ends faded out: no click.
            assert!(b.last().unwrap().abs() < 1e-3, "{name}: ends abruptly");
        }
    }

    #[test]
    fn sounds_are_deterministic() {
        assert_eq!(kick(4.2), kick(4.2));
        assert_eq!(goal_fanfare(), goal_fanfare());
        assert_eq!(bounce(1.0), bounce(1.0));
    }

    #[test]
    fn kick_loudness_grows_with_speed_and_saturates() {
        let speeds = [0.0, 0.5, 1.0, 2.0, 4.0, 6.0, 8.0];
        let kicks: Vec<_> = speeds.iter().map(|&v| kick(v)).collect();
        for w in kicks.windows(2) {
            assert!(peak(&w[1]) > peak(&w[0]) + 0.01, "peak must grow");
            assert!(rms(&w[1]) > rms(&w[0]), "rms must grow");
        }
        assert_eq!(kick(8.0), kick(30.0), "saturates at full speed");
        assert_eq!(kick(f32::NAN), kick(0.0));
        assert_eq!(kick(-3.0), kick(0.0));
    }

    #[test]
    fn faster_kicks_are_higher_pitched() {
        // Zero crossings in the first 40 ms count the pitch of the body.
        let crossings = |b: &[f32]| {
            b[samples_for(0.005)..samples_for(0.04)]
                .windows(2)
                .filter(|w| (w[0] < 0.0) != (w[1] < 0.0))
                .count()
        };
        assert!(crossings(&kick(8.0)) > crossings(&kick(0.0)) + 5);
    }

    #[test]
    fn bounce_loudness_grows_with_speed() {
        assert!(peak(&bounce(4.0)) > peak(&bounce(1.0)));
        assert!(rms(&bounce(4.0)) > rms(&bounce(1.0)));
    }

    #[test]
    fn fanfare_rises_through_the_arpeggio() {
        // The dominant pitch of each 0.15 s step, by zero crossings (odd harmonics are
        // weak enough that the fundamental dominates the crossing count).
        let b = goal_fanfare();
        let pitch = |start: f32| {
            let w = &b[samples_for(start + 0.02)..samples_for(start + 0.13)];
            let c = w
                .windows(2)
                .filter(|p| (p[0] < 0.0) != (p[1] < 0.0))
                .count();
            c as f32 / 2.0 / 0.11
        };
        let (c, e, g) = (pitch(0.0), pitch(0.15), pitch(0.30));
        assert!((c - 523.25).abs() < 40.0, "C5 measured {c}");
        assert!((e - 659.26).abs() < 40.0, "E5 measured {e}");
        assert!((g - 783.99).abs() < 40.0, "G5 measured {g}");
    }
}

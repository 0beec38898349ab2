//! The game's sound mixed offline: a timeline of sounds rendered to samples and
//! written as a WAV file, so sound can be checked where there is no sound card.

use crate::{Mixer, Sound, SAMPLE_RATE_HZ};
use std::sync::Arc;

/// Longest timeline [`mix_timeline`] renders, s: 20 minutes, 230 MB of samples (a
/// match of the computer against itself to five goals lasts a few minutes).
pub const MAX_TIMELINE_S: f64 = 20.0 * 60.0;

/// Mixes `cues` (start time in s, sound) into one mono track at [`SAMPLE_RATE_HZ`]
/// lasting `duration_s` (cut to `0…`[`MAX_TIMELINE_S`]), exactly as the live output mixes
/// them: each sound starts on the sample of its time, the sum is clamped to `[-1, 1]`.
/// Cues need not be sorted; cues at a non-finite or negative time are skipped.
pub fn mix_timeline(cues: &[(f64, Sound)], duration_s: f64) -> Vec<f32> {
    let duration_s = if duration_s.is_finite() {
        duration_s.clamp(0.0, MAX_TIMELINE_S)
    } else {
        0.0
    };
    let total = (duration_s * f64::from(SAMPLE_RATE_HZ)).round() as usize;
    let mut cues: Vec<(usize, Sound)> = cues
        .iter()
        .filter(|(t, _)| t.is_finite() && *t >= 0.0)
        .map(|&(t, s)| ((t * f64::from(SAMPLE_RATE_HZ)).round() as usize, s))
        .filter(|(i, _)| *i < total)
        .collect();
    cues.sort_by_key(|c| c.0);
    let mut mixer = Mixer::new(SAMPLE_RATE_HZ, 1);
    let mut out = vec![0.0f32; total];
    let mut at = 0;
    for (start, sound) in cues {
        mixer.fill(&mut out[at..start]);
        at = start;
        mixer.add(Arc::from(sound.samples()));
    }
    mixer.fill(&mut out[at..]);
    out
}

/// `samples` (mono, [`SAMPLE_RATE_HZ`], `[-1, 1]`) as a 16-bit PCM WAV file. The format
/// is a 44-byte RIFF header and the samples; too small to be worth a dependency.
pub fn wav_bytes(samples: &[f32]) -> Vec<u8> {
    let data_len = (samples.len() * 2) as u32;
    let mut b = Vec::with_capacity(44 + samples.len() * 2);
    b.extend_from_slice(b"RIFF");
    b.extend_from_slice(&(36 + data_len).to_le_bytes());
    b.extend_from_slice(b"WAVEfmt ");
    b.extend_from_slice(&16u32.to_le_bytes()); // fmt chunk size
    b.extend_from_slice(&1u16.to_le_bytes()); // PCM
    b.extend_from_slice(&1u16.to_le_bytes()); // mono
    b.extend_from_slice(&SAMPLE_RATE_HZ.to_le_bytes());
    b.extend_from_slice(&(SAMPLE_RATE_HZ * 2).to_le_bytes()); // bytes per second
    b.extend_from_slice(&2u16.to_le_bytes()); // block align
    b.extend_from_slice(&16u16.to_le_bytes()); // bits per sample
    b.extend_from_slice(b"data");
    b.extend_from_slice(&data_len.to_le_bytes());
    for &s in samples {
        let s = if s.is_finite() {
            s.clamp(-1.0, 1.0)
        } else {
            0.0
        };
        b.extend_from_slice(&((s * 32767.0).round() as i16).to_le_bytes());
    }
    b
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sounds_start_where_the_timeline_says() {
        let track = mix_timeline(
            &[
                (0.5, Sound::GoalFanfare),
                (0.1, Sound::Kick { speed_m_s: 6.0 }),
            ],
            2.5,
        );
        assert_eq!(track.len(), (2.5 * SAMPLE_RATE_HZ as f64) as usize);
        let first = track.iter().position(|s| s.abs() > 1e-4).unwrap();
        // The kick starts on its sample (its very first sample may be a zero crossing).
        let at = (0.1 * SAMPLE_RATE_HZ as f64) as usize;
        assert!((at..at + 48).contains(&first), "{first}");
        assert!(track[..at].iter().all(|s| *s == 0.0));
        let rate = SAMPLE_RATE_HZ as usize;
        // Silent between the kick's end (0.25 s) and the fanfare (0.5 s).
        assert!(track[rate * 30 / 100..rate / 2].iter().all(|s| *s == 0.0));
        assert!(track[rate / 2..rate].iter().any(|s| s.abs() > 0.1));
        // Past the fanfare (1.6 s from 0.5 s): silent again.
        assert!(track[rate * 22 / 10..].iter().all(|s| *s == 0.0));
        // Bad cues are skipped, bad durations give nothing.
        assert!(mix_timeline(&[(f64::NAN, Sound::MenuTick)], 1.0)
            .iter()
            .all(|s| *s == 0.0));
        assert!(mix_timeline(&[], f64::INFINITY).is_empty());
    }

    #[test]
    fn wav_header_and_samples() {
        let b = wav_bytes(&[0.0, 1.0, -1.0, 2.0]);
        assert_eq!(&b[0..4], b"RIFF");
        assert_eq!(&b[8..16], b"WAVEfmt ");
        assert_eq!(
            u32::from_le_bytes(b[24..28].try_into().unwrap()),
            SAMPLE_RATE_HZ
        );
        assert_eq!(u32::from_le_bytes(b[40..44].try_into().unwrap()), 8);
        let s: Vec<i16> = b[44..]
            .chunks(2)
            .map(|c| i16::from_le_bytes([c[0], c[1]]))
            .collect();
        assert_eq!(s, vec![0, 32767, -32767, 32767]);
    }
}

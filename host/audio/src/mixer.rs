//! Mixing the playing sounds into the device's buffer: a plain value, so it is tested
//! without any audio device.

use std::sync::Arc;

/// At most this many sounds play at once; a new one beyond it replaces the oldest.
pub const MAX_VOICES: usize = 16;

/// One playing sound.
#[derive(Debug, Clone)]
struct Voice {
    samples: Arc<[f32]>,
    /// Read position, in source samples (fractional when resampling).
    pos: f64,
}

/// Sums the playing sounds into interleaved output frames, resampling from
/// [`crate::SAMPLE_RATE_HZ`] to the device rate by linear interpolation, copying the
/// mono signal to every channel and clamping the sum to `[-1, 1]`.
#[derive(Debug, Clone)]
pub struct Mixer {
    voices: Vec<Voice>,
    /// Source samples per output frame: `SAMPLE_RATE_HZ / device rate`.
    step: f64,
    channels: usize,
}

impl Mixer {
    /// A mixer for a device at `device_rate_hz` with `channels` interleaved channels
    /// (both at least 1).
    pub fn new(device_rate_hz: u32, channels: usize) -> Mixer {
        Mixer {
            voices: Vec::new(),
            step: f64::from(crate::SAMPLE_RATE_HZ) / f64::from(device_rate_hz.max(1)),
            channels: channels.max(1),
        }
    }

    /// Starts playing `samples` (mono, [`crate::SAMPLE_RATE_HZ`]).
    pub fn add(&mut self, samples: Arc<[f32]>) {
        if samples.is_empty() {
            return;
        }
        if self.voices.len() >= MAX_VOICES {
            self.voices.remove(0);
        }
        self.voices.push(Voice { samples, pos: 0.0 });
    }

    /// Sounds still playing.
    pub fn playing(&self) -> usize {
        self.voices.len()
    }

    /// Fills `out` (interleaved frames of `channels` samples) with the mix and advances
    /// the voices; finished voices are dropped. Silence when nothing plays.
    pub fn fill(&mut self, out: &mut [f32]) {
        for frame in out.chunks_mut(self.channels) {
            let mut sum = 0.0f32;
            for v in &mut self.voices {
                let i = v.pos as usize;
                if i < v.samples.len() {
                    let frac = (v.pos - i as f64) as f32;
                    let a = v.samples[i];
                    let b = v.samples.get(i + 1).copied().unwrap_or(0.0);
                    sum += a + (b - a) * frac;
                }
                v.pos += self.step;
            }
            let y = if sum.is_finite() {
                sum.clamp(-1.0, 1.0)
            } else {
                0.0
            };
            frame.fill(y);
            self.voices.retain(|v| (v.pos as usize) < v.samples.len());
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn one_voice_at_the_native_rate_is_copied_to_every_channel() {
        let mut m = Mixer::new(crate::SAMPLE_RATE_HZ, 2);
        m.add(Arc::from(vec![0.1, -0.2, 0.3]));
        let mut out = [9.0f32; 10];
        m.fill(&mut out);
        assert_eq!(out, [0.1, 0.1, -0.2, -0.2, 0.3, 0.3, 0.0, 0.0, 0.0, 0.0]);
        assert_eq!(m.playing(), 0);
    }

    #[test]
    fn voices_add_and_clamp() {
        let mut m = Mixer::new(crate::SAMPLE_RATE_HZ, 1);
        m.add(Arc::from(vec![0.7, 0.2]));
        m.add(Arc::from(vec![0.7, -0.5]));
        let mut out = [0.0f32; 2];
        m.fill(&mut out);
        assert_eq!(out[0], 1.0);
        assert!((out[1] + 0.3).abs() < 1e-6);
    }

    #[test]
    fn resampling_keeps_the_duration() {
        // 48 kHz source on a 44.1 kHz device: 4800 samples (0.1 s) take 4410 frames.
        let mut m = Mixer::new(44_100, 1);
        m.add(Arc::from(vec![0.5f32; 4800]));
        let mut out = vec![0.0f32; 4409];
        m.fill(&mut out);
        assert_eq!(m.playing(), 1);
        assert!(out[..4000].iter().all(|&y| y == 0.5));
        assert!(out.iter().all(|y| (0.0..=0.5).contains(y)));
        let mut rest = [0.0f32; 2];
        m.fill(&mut rest);
        assert_eq!(m.playing(), 0);
    }

    #[test]
    fn too_many_voices_drop_the_oldest() {
        let mut m = Mixer::new(crate::SAMPLE_RATE_HZ, 1);
        for _ in 0..MAX_VOICES + 5 {
            m.add(Arc::from(vec![0.01f32; 100]));
        }
        assert_eq!(m.playing(), MAX_VOICES);
    }
}

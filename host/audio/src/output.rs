//! Playing sounds on the default output device with cpal, or silently where there is
//! none.

use crate::mixer::Mixer;
use crate::{synth, Sound};
use cpal::traits::{DeviceTrait, HostTrait, StreamTrait};
use cpal::{FromSample, SampleFormat, SizedSample, StreamConfig};
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::mpsc::{self, Receiver, SyncSender};
use std::sync::Arc;
use std::time::Duration;
// web-time: std's Instant natively, `performance.now()` in a browser (std's panics there).
use web_time::Instant;

/// Set this environment variable to `0` or `off` to open a silent output even where an
/// audio device exists (quiet test runs, benchmarks).
pub const DISABLE_ENV: &str = "SPACE_FOOSBALL_AUDIO";

/// Where sounds go: the default audio device, or nowhere.
///
/// Fixed sounds (fanfare, menu) are synthesised once when the output opens; kicks and
/// bounces, which depend on speed, when played (well under a millisecond each). [`AudioOutput::play`]
/// never blocks on the device: it hands the samples to the audio thread over a channel.
pub struct AudioOutput {
    sink: Sink,
    played: AtomicU64,
    goal_fanfare: Arc<[f32]>,
    menu_tick: Arc<[f32]>,
    menu_confirm: Arc<[f32]>,
}

enum Sink {
    Device {
        /// Kept alive: dropping the stream stops the sound.
        stream: cpal::Stream,
        to_audio_thread: SyncSender<Queued>,
        description: String,
    },
    Silent {
        reason: String,
    },
}

impl std::fmt::Debug for AudioOutput {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match &self.sink {
            Sink::Device { description, .. } => write!(f, "AudioOutput(device: {description})"),
            Sink::Silent { reason } => write!(f, "AudioOutput(silent: {reason})"),
        }
    }
}

impl AudioOutput {
    /// Opens the default output device of the platform's default host (ALSA on Linux).
    /// Never fails: with no device, a device that refuses to open, or [`DISABLE_ENV`]
    /// set to `0`/`off`, the output is silent and a notice saying why is logged
    /// (`log::warn!`, or `log::info!` when disabled on purpose) and kept in
    /// [`AudioOutput::notice`].
    pub fn open() -> AudioOutput {
        if let Ok(v) = std::env::var(DISABLE_ENV) {
            if matches!(
                v.trim().to_ascii_lowercase().as_str(),
                "0" | "off" | "false"
            ) {
                let reason = format!("sound disabled by {DISABLE_ENV}={v}");
                log::info!("{reason}; playing silently");
                return AudioOutput::silent(reason);
            }
        }
        match open_device_quietly() {
            Ok((stream, to_audio_thread, description)) => {
                log::info!("sound on {description}");
                AudioOutput::with_sink(Sink::Device {
                    stream,
                    to_audio_thread,
                    description,
                })
            }
            Err(reason) => {
                log::warn!("no sound: {reason}; playing silently");
                AudioOutput::silent(reason)
            }
        }
    }

    /// A silent output: [`AudioOutput::play`] accepts sounds and plays nothing.
    /// `reason` is what [`AudioOutput::notice`] returns.
    pub fn silent(reason: impl Into<String>) -> AudioOutput {
        AudioOutput::with_sink(Sink::Silent {
            reason: reason.into(),
        })
    }

    fn with_sink(sink: Sink) -> AudioOutput {
        AudioOutput {
            sink,
            played: AtomicU64::new(0),
            goal_fanfare: synth::goal_fanfare().into(),
            menu_tick: synth::menu_tick().into(),
            menu_confirm: synth::menu_confirm().into(),
        }
    }

    /// Plays `sound` now, mixed with whatever is playing. Never blocks, never fails:
    /// on a silent output, or if the device went away, the sound is dropped.
    pub fn play(&self, sound: Sound) {
        let samples: Arc<[f32]> = match sound {
            Sound::GoalFanfare => self.goal_fanfare.clone(),
            Sound::MenuTick => self.menu_tick.clone(),
            Sound::MenuConfirm => self.menu_confirm.clone(),
            Sound::Kick { .. } | Sound::Bounce { .. } => {
                if self.is_silent() {
                    // Nothing will hear it: skip the synthesis.
                    self.played.fetch_add(1, Ordering::Relaxed);
                    return;
                }
                sound.samples().into()
            }
        };
        if let Sink::Device {
            to_audio_thread, ..
        } = &self.sink
        {
            // A full queue means the device is not taking sound (a browser's audio before
            // a gesture, a stalled device): the sound is dropped rather than queued
            // without bound. A closed one means the stream died. Sound is best effort.
            let _ = to_audio_thread.try_send(Queued {
                samples,
                at: Instant::now(),
            });
        }
        self.played.fetch_add(1, Ordering::Relaxed);
    }

    /// Asks the device to (re)start playing. Where the platform holds audio back until a
    /// person's gesture (a browser's Web Audio), call it from a key press or a click;
    /// elsewhere the stream already plays and this does nothing. Never fails: a refusal
    /// leaves the output as it was.
    pub fn resume(&self) {
        if let Sink::Device { stream, .. } = &self.sink {
            if let Err(e) = stream.play() {
                log::debug!("audio did not resume: {e}");
            }
        }
    }

    /// Whether this output plays nothing.
    pub fn is_silent(&self) -> bool {
        matches!(self.sink, Sink::Silent { .. })
    }

    /// Why the output is silent; `None` when it plays on a device.
    pub fn notice(&self) -> Option<&str> {
        match &self.sink {
            Sink::Silent { reason } => Some(reason),
            Sink::Device { .. } => None,
        }
    }

    /// The device and stream format (`"ALSA default: 48000 Hz × 2, F32"`), when there is one.
    pub fn device_description(&self) -> Option<&str> {
        match &self.sink {
            Sink::Device { description, .. } => Some(description),
            Sink::Silent { .. } => None,
        }
    }

    /// Sounds accepted by [`AudioOutput::play`] so far (silent outputs count too).
    pub fn played(&self) -> u64 {
        self.played.load(Ordering::Relaxed)
    }
}

type Opened = (cpal::Stream, SyncSender<Queued>, String);

/// Sounds waiting for the audio thread at most; more are dropped (a burst of kicks and
/// bounces in one frame is well under this).
const QUEUE_SOUNDS: usize = 64;

/// A sound that waited longer than this for the device is dropped, not played: it no
/// longer belongs to the kick or bounce that made it (a browser's audio starting only
/// after a gesture would otherwise open with a burst of old sounds). Several device
/// buffers long, so a device that takes its sound in large blocks loses nothing.
pub const STALE_AFTER: Duration = Duration::from_millis(250);

/// A sound on its way to the audio thread, and when it was played.
struct Queued {
    samples: Arc<[f32]>,
    at: Instant,
}

impl Queued {
    /// Whether it waited too long to be played at `now` ([`STALE_AFTER`]).
    fn is_stale(&self, now: Instant) -> bool {
        now.saturating_duration_since(self.at) > STALE_AFTER
    }
}

/// [`open_device`] with ALSA's own error messages (which it otherwise prints to stderr,
/// e.g. "cannot find card '0'" on a machine without sound) captured and passed to
/// `log::debug!`: the one notice from [`AudioOutput::open`] says it all.
#[cfg(any(
    target_os = "linux",
    target_os = "dragonfly",
    target_os = "freebsd",
    target_os = "netbsd"
))]
fn open_device_quietly() -> Result<Opened, String> {
    // Thread-local handler on this thread, where cpal opens the device.
    let captured = alsa::Output::local_error_handler().ok();
    let result = open_device();
    if let Some(c) = captured {
        let text = c.borrow().to_string();
        if !text.trim().is_empty() {
            log::debug!("ALSA: {}", text.trim());
        }
    }
    result
}

/// [`open_device`] (no ALSA on this platform, nothing to quieten).
#[cfg(not(any(
    target_os = "linux",
    target_os = "dragonfly",
    target_os = "freebsd",
    target_os = "netbsd"
)))]
fn open_device_quietly() -> Result<Opened, String> {
    open_device()
}

/// Opens the default output device and starts a stream that mixes what arrives on the
/// returned channel. Every failure is a message, never a panic.
fn open_device() -> Result<Opened, String> {
    let host = cpal::default_host();
    let device = host
        .default_output_device()
        .ok_or_else(|| format!("no audio output device found ({:?} host)", host.id()))?;
    let name = device
        .id()
        .map(|id| id.to_string())
        .unwrap_or_else(|_| "default".into());
    let supported = device
        .default_output_config()
        .map_err(|e| format!("audio device {name} has no usable output format: {e}"))?;
    let format = supported.sample_format();
    let config: StreamConfig = supported.config();
    let description = format!(
        "{:?} {name}: {} Hz × {}, {format:?}",
        host.id(),
        config.sample_rate,
        config.channels
    );
    let (tx, rx) = mpsc::sync_channel(QUEUE_SOUNDS);
    let stream = match format {
        SampleFormat::F32 => build::<f32>(&device, config, rx),
        SampleFormat::F64 => build::<f64>(&device, config, rx),
        SampleFormat::I16 => build::<i16>(&device, config, rx),
        SampleFormat::I32 => build::<i32>(&device, config, rx),
        SampleFormat::U16 => build::<u16>(&device, config, rx),
        SampleFormat::U8 => build::<u8>(&device, config, rx),
        SampleFormat::I8 => build::<i8>(&device, config, rx),
        other => {
            return Err(format!(
                "audio device {name}: unsupported sample format {other:?}"
            ))
        }
    }
    .map_err(|e| format!("could not open audio stream on {name}: {e}"))?;
    stream
        .play()
        .map_err(|e| format!("could not start audio on {name}: {e}"))?;
    Ok((stream, tx, description))
}

/// Builds the output stream for sample type `T`: the callback drains the channel into
/// a [`Mixer`] and converts its `f32` mix to `T`.
fn build<T>(
    device: &cpal::Device,
    config: StreamConfig,
    rx: Receiver<Queued>,
) -> Result<cpal::Stream, cpal::Error>
where
    T: SizedSample + FromSample<f32>,
{
    let mut mixer = Mixer::new(config.sample_rate, usize::from(config.channels));
    let mut scratch: Vec<f32> = Vec::new();
    let reported = AtomicBool::new(false);
    device.build_output_stream::<T, _, _>(
        config,
        move |data: &mut [T], _| {
            let now = Instant::now();
            while let Ok(q) = rx.try_recv() {
                if !q.is_stale(now) {
                    mixer.add(q.samples);
                }
            }
            scratch.resize(data.len(), 0.0);
            mixer.fill(&mut scratch);
            for (d, &y) in data.iter_mut().zip(&scratch) {
                *d = T::from_sample(y);
            }
        },
        move |e| {
            // Report the first stream error; later ones (e.g. repeated underruns) would
            // flood the log.
            if !reported.swap(true, Ordering::Relaxed) {
                log::warn!("audio stream error (further ones not reported): {e}");
            }
        },
        None,
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_sound_that_waited_past_the_limit_is_stale() {
        let at = Instant::now();
        let q = Queued {
            samples: Arc::from(vec![0.0f32; 4]),
            at,
        };
        assert!(!q.is_stale(at));
        assert!(!q.is_stale(at + STALE_AFTER));
        assert!(q.is_stale(at + STALE_AFTER + Duration::from_millis(1)));
        // A clock that reads earlier than the queueing (never on a monotonic clock)
        // counts as no wait.
        assert!(!Queued {
            samples: q.samples.clone(),
            at: at + STALE_AFTER * 4
        }
        .is_stale(at));
    }

    #[test]
    fn a_silent_output_accepts_every_sound() {
        let out = AudioOutput::silent("testing");
        assert!(out.is_silent());
        assert_eq!(out.notice(), Some("testing"));
        assert_eq!(out.device_description(), None);
        for s in [
            Sound::Kick { speed_m_s: 3.0 },
            Sound::Bounce { speed_m_s: 1.0 },
            Sound::GoalFanfare,
            Sound::MenuTick,
            Sound::MenuConfirm,
        ] {
            out.play(s);
        }
        assert_eq!(out.played(), 5);
    }
}

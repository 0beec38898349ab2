//! Recorded rod motion: poses sampled over time, saved as JSON and played back.
//!
//! File format (`version` 1):
//!
//! ```json
//! { "version": 1,
//!   "samples": [ { "t_us": 0,    "poses": [ {"axial_m": 0.0, "angle_rad": 0.0}, … 8 ] },
//!                { "t_us": 1000, "poses": [ … ] } ] }
//! ```
//!
//! Playback interpolates linearly between samples and holds the last pose after the
//! end. Times must be strictly increasing; poses finite and within the limits of motion
//! scripts ([`super::script::MAX_AXIAL_M`], [`super::script::MAX_ANGLE_RAD`]).

use super::script::check_pose;
use super::{MotionSource, RodPose, RodPoses};
use foosball_protocol::PADDLES;
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex, PoisonError};

/// Format version written and accepted.
pub const RECORDING_VERSION: u32 = 1;

/// Why a recording could not be loaded or saved.
#[derive(Debug, thiserror::Error)]
pub enum RecordingError {
    /// Reading or writing the file failed.
    #[error("recording {path}: {source}")]
    Io {
        /// The file.
        path: PathBuf,
        /// The cause.
        source: std::io::Error,
    },
    /// The text is not a recording.
    #[error("recording is not valid JSON of the expected shape: {0}")]
    Parse(#[from] serde_json::Error),
    /// The recording parses but is inconsistent.
    #[error("recording: {0}")]
    Invalid(String),
}

/// Poses of all rods at one time.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Sample {
    /// Emulated time, µs.
    pub t_us: u64,
    /// Pose per rod.
    pub poses: RodPoses,
}

/// A recording as stored.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RecordingFile {
    /// [`RECORDING_VERSION`].
    pub version: u32,
    /// Samples in increasing time.
    pub samples: Vec<Sample>,
}

/// Records poses from any [`MotionSource`] (e.g. live play) as it is driven. The
/// recorder goes into the board; its [`RecordingHandle`] stays with the caller to save
/// the recording during or after the run.
#[derive(Debug)]
pub struct Recorder<S> {
    inner: S,
    samples: Arc<Mutex<Vec<Sample>>>,
    min_interval_us: u64,
}

/// Access to what a [`Recorder`] recorded.
#[derive(Debug, Clone, Default)]
pub struct RecordingHandle {
    samples: Arc<Mutex<Vec<Sample>>>,
}

impl RecordingHandle {
    /// Number of samples so far.
    pub fn len(&self) -> usize {
        self.lock().len()
    }

    /// Whether nothing was recorded yet.
    pub fn is_empty(&self) -> bool {
        self.lock().is_empty()
    }

    /// The recording so far, ready to save.
    pub fn recording(&self) -> RecordingFile {
        RecordingFile {
            version: RECORDING_VERSION,
            samples: self.lock().clone(),
        }
    }

    fn lock(&self) -> std::sync::MutexGuard<'_, Vec<Sample>> {
        // Samples are appended whole: a panic elsewhere cannot leave them inconsistent.
        self.samples.lock().unwrap_or_else(PoisonError::into_inner)
    }
}

impl<S: MotionSource> Recorder<S> {
    /// Wraps `inner`, keeping a sample at most every `min_interval_us` µs.
    pub fn new(inner: S, min_interval_us: u64) -> Self {
        Self {
            inner,
            samples: Arc::default(),
            min_interval_us: min_interval_us.max(1),
        }
    }

    /// The handle to read the recording.
    pub fn handle(&self) -> RecordingHandle {
        RecordingHandle {
            samples: self.samples.clone(),
        }
    }
}

impl<S: MotionSource> MotionSource for Recorder<S> {
    fn poses_at(&mut self, t_us: u64) -> RodPoses {
        let poses = self.inner.poses_at(t_us);
        let mut samples = self.samples.lock().unwrap_or_else(PoisonError::into_inner);
        let due = match samples.last() {
            None => true,
            Some(last) => t_us >= last.t_us + self.min_interval_us,
        };
        if due {
            samples.push(Sample { t_us, poses });
        }
        poses
    }
}

impl RecordingFile {
    /// Writes the recording as JSON.
    pub fn save(&self, path: &Path) -> Result<(), RecordingError> {
        let text = serde_json::to_string(self)?;
        std::fs::write(path, text).map_err(|source| RecordingError::Io {
            path: path.to_owned(),
            source,
        })
    }
}

/// Playback of a validated recording.
#[derive(Debug, Clone)]
pub struct Playback {
    samples: Vec<Sample>,
    cursor: usize,
}

impl Playback {
    /// Reads and validates a recording file.
    pub fn load(path: &Path) -> Result<Self, RecordingError> {
        let text = std::fs::read_to_string(path).map_err(|source| RecordingError::Io {
            path: path.to_owned(),
            source,
        })?;
        Self::from_json(&text)
    }

    /// Parses and validates a recording from JSON text.
    pub fn from_json(text: &str) -> Result<Self, RecordingError> {
        Self::new(serde_json::from_str(text)?)
    }

    /// Validates a recording.
    pub fn new(file: RecordingFile) -> Result<Self, RecordingError> {
        if file.version != RECORDING_VERSION {
            return Err(RecordingError::Invalid(format!(
                "version {} not supported (this build reads version {RECORDING_VERSION})",
                file.version
            )));
        }
        if file.samples.is_empty() {
            return Err(RecordingError::Invalid("no samples".into()));
        }
        for (i, pair) in file.samples.windows(2).enumerate() {
            if pair[1].t_us <= pair[0].t_us {
                return Err(RecordingError::Invalid(format!(
                    "samples[{}]: t_us {} not after the previous sample's {}",
                    i + 1,
                    pair[1].t_us,
                    pair[0].t_us
                )));
            }
        }
        for (i, sample) in file.samples.iter().enumerate() {
            for (rod, pose) in sample.poses.iter().enumerate() {
                // The limits of motion scripts: beyond them, interpolating between two
                // huge poses overflows to a non-finite pose.
                check_pose(*pose).map_err(|reason| {
                    RecordingError::Invalid(format!("samples[{i}]: rod {rod}: {reason}"))
                })?;
            }
        }
        Ok(Self {
            samples: file.samples,
            cursor: 0,
        })
    }

    /// Time of the last sample, µs.
    pub fn duration_us(&self) -> u64 {
        self.samples.last().map_or(0, |s| s.t_us)
    }
}

impl MotionSource for Playback {
    fn poses_at(&mut self, t_us: u64) -> RodPoses {
        let s = &self.samples;
        if t_us <= s[0].t_us {
            self.cursor = 0;
            return s[0].poses;
        }
        let mut i = self.cursor.min(s.len() - 1);
        while i > 0 && s[i].t_us > t_us {
            i -= 1;
        }
        while i + 1 < s.len() && s[i + 1].t_us <= t_us {
            i += 1;
        }
        self.cursor = i;
        if i + 1 == s.len() {
            return s[i].poses;
        }
        let (a, b) = (&s[i], &s[i + 1]);
        let f = (t_us - a.t_us) as f64 / (b.t_us - a.t_us) as f64;
        let mut out = [RodPose::default(); PADDLES];
        for (rod, pose) in out.iter_mut().enumerate() {
            *pose = a.poses[rod].lerp(b.poses[rod], f);
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::motion::script::MotionScript;

    #[test]
    fn record_save_load_and_play_back() {
        let script = MotionScript::from_json(
            r#"{"rods":[{"rod":5,"segments":[
                {"velocity":{"duration_s":0.1,"axial_m_per_s":0.5,"angle_rad_per_s":-10}}]}]}"#,
        )
        .unwrap();
        let mut rec = Recorder::new(script.clone(), 1000);
        let handle = rec.handle();
        assert!(handle.is_empty());
        for t in (0..=200_000).step_by(250) {
            rec.poses_at(t);
        }
        assert_eq!(handle.len(), 201);
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("rec.json");
        handle.recording().save(&path).unwrap();
        let mut play = Playback::load(&path).unwrap();
        assert_eq!(play.duration_us(), 200_000);
        for t in [0u64, 12_345, 50_000, 99_999, 150_000, 1_000_000] {
            let want = script.pose_of(5, t as f64);
            let got = play.poses_at(t)[5];
            assert!((got.axial_m - want.axial_m).abs() < 1e-9, "{t}");
            assert!((got.angle_rad - want.angle_rad).abs() < 1e-9, "{t}");
        }
    }

    #[test]
    fn bad_recordings_rejected() {
        let pose = r#"{"axial_m":0,"angle_rad":0}"#;
        let poses = format!("[{}]", [pose; 8].join(","));
        let ok = format!(r#"{{"version":1,"samples":[{{"t_us":0,"poses":{poses}}}]}}"#);
        assert!(Playback::from_json(&ok).is_ok());
        let e = Playback::from_json(&ok.replace("\"version\":1", "\"version\":2"))
            .unwrap_err()
            .to_string();
        assert!(e.contains("version 2"), "{e}");
        let two = format!(
            r#"{{"version":1,"samples":[{{"t_us":5,"poses":{poses}}},{{"t_us":5,"poses":{poses}}}]}}"#
        );
        let e = Playback::from_json(&two).unwrap_err().to_string();
        assert!(e.contains("samples[1]"), "{e}");
        let e = Playback::from_json(r#"{"version":1,"samples":[]}"#)
            .unwrap_err()
            .to_string();
        assert!(e.contains("no samples"), "{e}");
        let seven = format!("[{}]", [pose; 7].join(","));
        let e = Playback::from_json(&format!(
            r#"{{"version":1,"samples":[{{"t_us":0,"poses":{seven}}}]}}"#
        ))
        .unwrap_err()
        .to_string();
        assert!(e.contains("JSON"), "{e}");
    }

    #[test]
    fn recordings_with_poses_beyond_the_limits_rejected() {
        // Two samples at ±1e308 m: interpolating between them overflowed to a NaN pose.
        let at = |axial: f64| {
            let pose = format!(r#"{{"axial_m":{axial:e},"angle_rad":0}}"#);
            format!("[{}]", [pose.as_str(); 8].join(","))
        };
        let text = |a: f64, b: f64| {
            format!(
                r#"{{"version":1,"samples":[{{"t_us":0,"poses":{}}},{{"t_us":10,"poses":{}}}]}}"#,
                at(a),
                at(b)
            )
        };
        let e = Playback::from_json(&text(-1e308, 1e308))
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("samples[0]: rod 0") && e.contains("beyond"),
            "{e}"
        );
        let e = Playback::from_json(&text(0.0, 10.5))
            .unwrap_err()
            .to_string();
        assert!(e.contains("samples[1]"), "{e}");
        let mut ok = Playback::from_json(&text(-10.0, 10.0)).expect("within the limits");
        assert_eq!(ok.poses_at(5)[3].axial_m, 0.0);
    }
}

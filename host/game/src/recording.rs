//! A match's input stream, saved and loaded, so that a match can be replayed exactly.
//!
//! A recording holds everything a replay needs besides the code: the seed, the table,
//! the rules, and the input of every 1 ms step — either the rod poses the physics
//! consumed ([`RecordedInput::Poses`], `[slide_m, angle_rad]` per rod, table frame) or
//! the raw IN reports ([`RecordedInput::Reports`], the protocol bytes in hex, one per
//! report, replayed through calibration). JSON with exact float round-tripping;
//! saved atomically.

use crate::atomic_file::write_atomic;
use crate::input::paddles::RodInputs;
use crate::rules::RulesConfig;
use crate::table::Table;
use foosball_protocol::InReport;
use serde::{Deserialize, Serialize};
use std::io::Read;
use std::path::Path;

/// The `format` string of recordings.
pub const FORMAT: &str = "space-foosball-recording";
/// The recording format version.
pub const VERSION: u32 = 1;

/// Why a recording could not be loaded or saved.
#[derive(Debug, thiserror::Error)]
pub enum RecordingError {
    /// Reading or writing failed.
    #[error("recording {path}: {source}")]
    Io {
        /// The file.
        path: String,
        /// The operating-system error.
        #[source]
        source: std::io::Error,
    },
    /// The text is not a valid recording.
    #[error("recording is malformed: {0}")]
    Malformed(String),
}

/// Largest recording loaded (bytes of JSON): room for the longest headless match (an hour
/// of match time, `MAX_MATCH_MS` of `play --headless`) recorded at the board's report rate.
pub const MAX_RECORDING_BYTES: u64 = 1 << 30;

/// The per-step input.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum RecordedInput {
    /// Per step, per rod `[slide_m, angle_rad]`.
    Poses(Vec<Vec<[f64; 2]>>),
    /// Per report, the encoded IN report in lowercase hex.
    Reports(Vec<String>),
}

/// A recorded match.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MatchRecording {
    /// Always [`FORMAT`].
    pub format: String,
    /// Always [`VERSION`].
    pub version: u32,
    /// Seed of everything random in the match (serve jitter, AI, emulated board).
    pub seed: u64,
    /// The table played on.
    pub table: Table,
    /// The rules played by.
    pub rules: RulesConfig,
    /// The input stream.
    pub input: RecordedInput,
}

fn hex(bytes: &[u8]) -> String {
    bytes.iter().map(|b| format!("{b:02x}")).collect()
}

/// Decodes plain hex (pairs of `0-9a-fA-F`, nothing else: no sign, no spaces, no
/// prefix); `None` for anything else.
fn unhex(text: &str) -> Option<Vec<u8>> {
    fn digit(c: u8) -> Option<u8> {
        // `to_digit` takes only the 16 hex digits, unlike `from_str_radix`, which
        // also takes a leading `+`.
        char::from(c).to_digit(16).map(|d| d as u8)
    }
    let bytes = text.as_bytes();
    if bytes.len() % 2 != 0 {
        return None;
    }
    bytes
        .chunks_exact(2)
        .map(|pair| Some(digit(pair[0])? << 4 | digit(pair[1])?))
        .collect()
}

impl MatchRecording {
    /// An empty recording of poses.
    pub fn of_poses(seed: u64, table: Table, rules: RulesConfig) -> Self {
        Self {
            format: FORMAT.into(),
            version: VERSION,
            seed,
            table,
            rules,
            input: RecordedInput::Poses(Vec::new()),
        }
    }

    /// An empty recording of raw reports.
    pub fn of_reports(seed: u64, table: Table, rules: RulesConfig) -> Self {
        Self {
            input: RecordedInput::Reports(Vec::new()),
            ..Self::of_poses(seed, table, rules)
        }
    }

    /// Appends one step's rod poses (a pose recording; ignored for a report recording).
    pub fn push_poses(&mut self, inputs: &RodInputs) {
        if let RecordedInput::Poses(steps) = &mut self.input {
            steps.push(
                inputs
                    .rods
                    .iter()
                    .map(|r| [r.slide_m, r.angle_rad])
                    .collect(),
            );
        }
    }

    /// The steps a pose recording holds (0 for a report recording).
    pub fn pose_steps(&self) -> usize {
        match &self.input {
            RecordedInput::Poses(steps) => steps.len(),
            RecordedInput::Reports(_) => 0,
        }
    }

    /// Cuts a pose recording back to its first `steps` steps (a rolled-back match);
    /// a report recording is left as it is.
    pub fn truncate_poses(&mut self, steps: usize) {
        if let RecordedInput::Poses(recorded) = &mut self.input {
            recorded.truncate(steps);
        }
    }

    /// Appends one report (a report recording; ignored for a pose recording).
    pub fn push_report(&mut self, report: &InReport) {
        if let RecordedInput::Reports(reports) = &mut self.input {
            reports.push(hex(&report.to_bytes()));
        }
    }

    /// Number of recorded steps (or reports).
    pub fn len(&self) -> usize {
        match &self.input {
            RecordedInput::Poses(p) => p.len(),
            RecordedInput::Reports(r) => r.len(),
        }
    }

    /// Whether nothing is recorded.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The recorded poses of step `step`, if this is a pose recording.
    pub fn poses(&self, step: usize) -> Option<&[[f64; 2]]> {
        match &self.input {
            RecordedInput::Poses(p) => p.get(step).map(Vec::as_slice),
            RecordedInput::Reports(_) => None,
        }
    }

    /// The recorded reports, decoded (a report recording; empty otherwise).
    pub fn reports(&self) -> Result<Vec<InReport>, RecordingError> {
        match &self.input {
            RecordedInput::Poses(_) => Ok(Vec::new()),
            RecordedInput::Reports(r) => r
                .iter()
                .enumerate()
                .map(|(i, h)| {
                    let bytes = unhex(h)
                        .ok_or_else(|| RecordingError::Malformed(format!("report {i}: not hex")))?;
                    InReport::decode(&bytes)
                        .map_err(|e| RecordingError::Malformed(format!("report {i}: {e}")))
                })
                .collect(),
        }
    }

    /// Checks format, version, table, rules, and every step's shape and numbers.
    pub fn validate(&self) -> Result<(), RecordingError> {
        let bad = |m: String| Err(RecordingError::Malformed(m));
        if self.format != FORMAT {
            return bad(format!("format {:?}, expected {FORMAT:?}", self.format));
        }
        if self.version != VERSION {
            return bad(format!("version {} is not supported", self.version));
        }
        self.table
            .validate()
            .map_err(|e| RecordingError::Malformed(format!("table: {e}")))?;
        self.rules
            .validate(&self.table)
            .map_err(|e| RecordingError::Malformed(e.to_string()))?;
        match &self.input {
            RecordedInput::Poses(steps) => {
                for (i, step) in steps.iter().enumerate() {
                    if step.len() != self.table.rods.len() {
                        return bad(format!(
                            "step {i}: {} rods, the table has {}",
                            step.len(),
                            self.table.rods.len()
                        ));
                    }
                    if step.iter().flatten().any(|v| !v.is_finite()) {
                        return bad(format!("step {i}: a pose is not finite"));
                    }
                }
                Ok(())
            }
            RecordedInput::Reports(_) => self.reports().map(|_| ()),
        }
    }

    /// The recording as JSON.
    pub fn to_json(&self) -> String {
        serde_json::to_string(self).unwrap_or_default()
    }

    /// Parses and validates a recording.
    pub fn from_json(text: &str) -> Result<Self, RecordingError> {
        let r: Self =
            serde_json::from_str(text).map_err(|e| RecordingError::Malformed(e.to_string()))?;
        r.validate()?;
        Ok(r)
    }

    /// Saves atomically.
    pub fn save(&self, path: &Path) -> Result<(), RecordingError> {
        self.validate()?;
        write_atomic(path, self.to_json().as_bytes()).map_err(|source| RecordingError::Io {
            path: path.display().to_string(),
            source,
        })
    }

    /// Loads and validates; a file larger than [`MAX_RECORDING_BYTES`] is refused before it
    /// is read.
    pub fn load(path: &Path) -> Result<Self, RecordingError> {
        let io = |source| RecordingError::Io {
            path: path.display().to_string(),
            source,
        };
        let too_large = || {
            RecordingError::Malformed(format!(
                "{} is larger than {} MiB",
                path.display(),
                MAX_RECORDING_BYTES >> 20
            ))
        };
        let file = std::fs::File::open(path).map_err(io)?;
        if file.metadata().map_err(io)?.len() > MAX_RECORDING_BYTES {
            return Err(too_large());
        }
        // Read to the bound only: a file that grows while it is read stays within it.
        let mut text = String::new();
        file.take(MAX_RECORDING_BYTES + 1)
            .read_to_string(&mut text)
            .map_err(io)?;
        if text.len() as u64 > MAX_RECORDING_BYTES {
            return Err(too_large());
        }
        Self::from_json(&text)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::input::calibration::Calibration;
    use crate::input::paddles::PaddleTracker;
    use foosball_protocol::{PaddleMotion, PaddleStatus};

    #[test]
    fn a_file_past_the_bound_is_refused_before_it_is_read() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("huge.json");
        // Sparse: its length past the bound, nothing written.
        let f = std::fs::File::create(&path).unwrap();
        f.set_len(MAX_RECORDING_BYTES + 1).unwrap();
        drop(f);
        let err = MatchRecording::load(&path).unwrap_err();
        assert!(err.to_string().contains("larger than 1024 MiB"), "{err}");
    }

    #[test]
    fn poses_round_trip_bit_exactly() {
        let table = Table::standard();
        let mut rec = MatchRecording::of_poses(42, table.clone(), RulesConfig::default());
        let mut tracker = PaddleTracker::new(&table, Calibration::default());
        for s in 0..50u16 {
            let mut r = InReport {
                sequence: s,
                paddles: [PaddleMotion {
                    axial: 3,
                    rotation: -7,
                    status: PaddleStatus::PRESENT,
                }; 8],
            };
            r.paddles[2].axial = 11;
            tracker.apply_report(&r);
            rec.push_poses(&tracker.inputs());
        }
        let back = MatchRecording::from_json(&rec.to_json()).unwrap();
        assert_eq!(back, rec);
        assert_eq!(back.len(), 50);
        // Bit-exact, not merely close.
        let a = rec.poses(49).unwrap()[2][1].to_bits();
        assert_eq!(back.poses(49).unwrap()[2][1].to_bits(), a);
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("m.json");
        rec.save(&path).unwrap();
        assert_eq!(MatchRecording::load(&path).unwrap(), rec);
    }

    #[test]
    fn reports_round_trip_and_bad_recordings_are_rejected() {
        let mut rec = MatchRecording::of_reports(7, Table::paper(), RulesConfig::default());
        let report = InReport {
            sequence: 65535,
            ..Default::default()
        };
        rec.push_report(&report);
        let back = MatchRecording::from_json(&rec.to_json()).unwrap();
        assert_eq!(back.reports().unwrap(), vec![report]);
        let mut bad = rec.clone();
        bad.input = RecordedInput::Reports(vec!["zz".into()]);
        assert!(MatchRecording::from_json(&bad.to_json()).is_err());
        let mut bad = MatchRecording::of_poses(1, Table::standard(), RulesConfig::default());
        bad.input = RecordedInput::Poses(vec![vec![[0.0, 0.0]; 7]]);
        let err = MatchRecording::from_json(&bad.to_json()).unwrap_err();
        assert!(err.to_string().contains("7 rods"), "{err}");
        assert!(MatchRecording::from_json("{}").is_err());
        // Rules out of range (a serve at -1.8e308 m/s sent the ball to infinity in one step).
        let mut bad = MatchRecording::of_poses(1, Table::standard(), RulesConfig::default());
        bad.rules.serve_speed_m_per_s = -1.797e308;
        let err = MatchRecording::from_json(&bad.to_json()).unwrap_err();
        assert!(err.to_string().contains("serve_speed_m_per_s"), "{err}");
        let text = rec.to_json().replace("\"version\":1", "\"version\":2");
        assert!(MatchRecording::from_json(&text).is_err());
    }

    #[test]
    fn report_hex_takes_plain_hex_digits_only() {
        assert_eq!(unhex("00ff7Fa0"), Some(vec![0x00, 0xff, 0x7f, 0xa0]));
        assert_eq!(unhex(""), Some(vec![]));
        // `u8::from_str_radix` would take "+1" as 1; none of these is plain hex.
        for bad in ["+1", "+f", "-1", " 1", "1 ", "0x", "g0", "é0", "0", "abc"] {
            assert_eq!(unhex(bad), None, "{bad:?}");
        }
        // Through a recording: a sign in place of a leading zero digit is refused.
        let mut rec = MatchRecording::of_reports(7, Table::paper(), RulesConfig::default());
        rec.push_report(&InReport::default());
        let RecordedInput::Reports(hexes) = &rec.input else {
            unreachable!("a report recording")
        };
        let good = hexes[0].clone();
        let zero_pair = (0..good.len())
            .step_by(2)
            .find(|&i| good.as_bytes()[i] == b'0')
            .expect("a default report has a byte below 0x10");
        let mut signed = good.clone();
        signed.replace_range(zero_pair..zero_pair + 1, "+");
        rec.input = RecordedInput::Reports(vec![signed]);
        let err = rec.reports().unwrap_err();
        assert!(err.to_string().contains("report 0: not hex"), "{err}");
        assert!(MatchRecording::from_json(&rec.to_json()).is_err());
    }
}

//! Scripted rod motion: per rod, a start pose and a list of segments of given duration.
//!
//! A script is JSON (see `sim/README.md` for a full example):
//!
//! ```json
//! {
//!   "rods": [
//!     { "rod": 0, "start": { "axial_m": 0.0, "angle_rad": 0.0 },
//!       "segments": [
//!         { "velocity": { "duration_s": 0.5, "axial_m_per_s": 0.2, "angle_rad_per_s": 6.0 } },
//!         { "move_to":  { "duration_s": 0.25, "axial_m": 0.0, "angle_rad": 0.0 } },
//!         { "hold":     { "duration_s": 1.0 } } ] }
//!   ],
//!   "faults": [ { "at_s": 1.0, "port": 3, "fault": "unplug" } ]
//! }
//! ```
//!
//! Rods not listed stay at pose zero; after its last segment a rod holds its final pose.
//! Loading validates everything and reports the first problem with its place in the
//! file; nothing in a script can make the emulator panic.

use super::{MotionSource, RodPose, RodPoses};
use crate::faults::ScheduledFault;
use foosball_protocol::PADDLES;
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

/// Longest script accepted, seconds of emulated time (one week).
pub const MAX_SCRIPT_DURATION_S: f64 = 7.0 * 24.0 * 3600.0;
/// Largest axial position accepted, metres.
pub const MAX_AXIAL_M: f64 = 10.0;
/// Largest angle accepted, radians.
pub const MAX_ANGLE_RAD: f64 = 1.0e7;
/// Largest axial speed accepted, m/s.
pub const MAX_AXIAL_SPEED_M_PER_S: f64 = 100.0;
/// Largest angular speed accepted, rad/s.
pub const MAX_ANGULAR_SPEED_RAD_PER_S: f64 = 10_000.0;
/// Most segments accepted per rod.
pub const MAX_SEGMENTS_PER_ROD: usize = 100_000;

/// Why a script could not be loaded.
#[derive(Debug, thiserror::Error)]
pub enum ScriptError {
    /// The file could not be read.
    #[error("cannot read motion script {path}: {source}")]
    Io {
        /// The file.
        path: PathBuf,
        /// The cause.
        source: std::io::Error,
    },
    /// The text is not a script (JSON syntax, unknown or missing fields, wrong types).
    #[error("motion script is not valid JSON of the expected shape: {0}")]
    Parse(#[from] serde_json::Error),
    /// The script parses but a value is out of range or inconsistent.
    #[error("motion script: {location}: {reason}")]
    Invalid {
        /// Where: `rods[1] (rod 4), segment 3`, `faults[0]`, …
        location: String,
        /// What is wrong.
        reason: String,
    },
}

/// One piece of a rod's motion.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum Segment {
    /// Constant velocity for a duration.
    Velocity {
        /// Length of the segment, seconds (> 0).
        duration_s: f64,
        /// Axial speed, m/s.
        #[serde(default)]
        axial_m_per_s: f64,
        /// Angular speed, rad/s.
        #[serde(default)]
        angle_rad_per_s: f64,
    },
    /// Straight-line move to a target pose, reached at the end of the duration.
    MoveTo {
        /// Length of the segment, seconds (> 0).
        duration_s: f64,
        /// Target axial position, metres.
        axial_m: f64,
        /// Target angle, radians.
        angle_rad: f64,
    },
    /// Stand still for a duration.
    Hold {
        /// Length of the segment, seconds (> 0).
        duration_s: f64,
    },
}

impl Segment {
    fn duration_s(&self) -> f64 {
        match *self {
            Segment::Velocity { duration_s, .. }
            | Segment::MoveTo { duration_s, .. }
            | Segment::Hold { duration_s } => duration_s,
        }
    }
}

/// The motion of one rod.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RodTrack {
    /// Port (rod) index, 0–7.
    pub rod: usize,
    /// Pose at time zero (default: zero).
    #[serde(default)]
    pub start: RodPose,
    /// Segments, played one after the other from time zero.
    pub segments: Vec<Segment>,
}

/// A motion script as written in the file.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ScriptSpec {
    /// Tracks, at most one per rod.
    #[serde(default)]
    pub rods: Vec<RodTrack>,
    /// Faults to inject at given times.
    #[serde(default)]
    pub faults: Vec<ScheduledFault>,
}

/// A linear piece of motion between two times (µs, as `f64` so that no rounding
/// accumulates over segments).
#[derive(Debug, Clone, Copy)]
struct Piece {
    t0_us: f64,
    t1_us: f64,
    from: RodPose,
    to: RodPose,
}

/// A validated motion script, ready to play.
#[derive(Debug, Clone)]
pub struct MotionScript {
    pieces: [Vec<Piece>; PADDLES],
    start: RodPoses,
    cursor: [usize; PADDLES],
    faults: Vec<ScheduledFault>,
    duration_us: f64,
}

impl MotionScript {
    /// Reads and validates a script file.
    pub fn load(path: &Path) -> Result<Self, ScriptError> {
        let text = std::fs::read_to_string(path).map_err(|source| ScriptError::Io {
            path: path.to_owned(),
            source,
        })?;
        Self::from_json(&text)
    }

    /// Parses and validates a script from JSON text.
    pub fn from_json(text: &str) -> Result<Self, ScriptError> {
        let spec: ScriptSpec = serde_json::from_str(text)?;
        Self::from_spec(spec)
    }

    /// Validates a script built in code.
    pub fn from_spec(spec: ScriptSpec) -> Result<Self, ScriptError> {
        let mut pieces: [Vec<Piece>; PADDLES] = Default::default();
        let mut start = [RodPose::default(); PADDLES];
        let mut seen = [false; PADDLES];
        let mut duration_us: f64 = 0.0;
        for (track_index, track) in spec.rods.iter().enumerate() {
            let here = |what: &str| format!("rods[{track_index}] (rod {}){what}", track.rod);
            let invalid =
                |location: String, reason: String| ScriptError::Invalid { location, reason };
            if track.rod >= PADDLES {
                return Err(invalid(
                    format!("rods[{track_index}]"),
                    format!("rod must be 0–{}, got {}", PADDLES - 1, track.rod),
                ));
            }
            if std::mem::replace(&mut seen[track.rod], true) {
                return Err(invalid(here(""), "rod listed twice".into()));
            }
            if track.segments.len() > MAX_SEGMENTS_PER_ROD {
                return Err(invalid(
                    here(""),
                    format!("more than {MAX_SEGMENTS_PER_ROD} segments"),
                ));
            }
            check_pose(track.start).map_err(|reason| invalid(here(", start"), reason))?;
            let mut pose = track.start;
            let mut t_s = 0.0;
            let rod_pieces = &mut pieces[track.rod];
            for (segment_index, segment) in track.segments.iter().enumerate() {
                let location = || here(&format!(", segment {segment_index}"));
                let d = segment.duration_s();
                if !(d.is_finite() && d > 0.0) {
                    return Err(invalid(
                        location(),
                        format!("duration_s must be a finite number > 0, got {d}"),
                    ));
                }
                let to = match *segment {
                    Segment::Velocity {
                        axial_m_per_s,
                        angle_rad_per_s,
                        ..
                    } => {
                        check_speed(axial_m_per_s, angle_rad_per_s)
                            .map_err(|reason| invalid(location(), reason))?;
                        RodPose::new(
                            pose.axial_m + axial_m_per_s * d,
                            pose.angle_rad + angle_rad_per_s * d,
                        )
                    }
                    Segment::MoveTo {
                        axial_m, angle_rad, ..
                    } => RodPose::new(axial_m, angle_rad),
                    Segment::Hold { .. } => pose,
                };
                check_pose(to).map_err(|reason| {
                    invalid(
                        location(),
                        format!("pose at the end of the segment: {reason}"),
                    )
                })?;
                let t1_s = t_s + d;
                if t1_s > MAX_SCRIPT_DURATION_S {
                    return Err(invalid(
                        location(),
                        format!("script longer than {MAX_SCRIPT_DURATION_S} s"),
                    ));
                }
                rod_pieces.push(Piece {
                    t0_us: t_s * 1e6,
                    t1_us: t1_s * 1e6,
                    from: pose,
                    to,
                });
                pose = to;
                t_s = t1_s;
            }
            start[track.rod] = track.start;
            duration_us = duration_us.max(t_s * 1e6);
        }
        for (index, fault) in spec.faults.iter().enumerate() {
            let location = format!("faults[{index}]");
            if fault.port >= PADDLES {
                return Err(ScriptError::Invalid {
                    location,
                    reason: format!("port must be 0–{}, got {}", PADDLES - 1, fault.port),
                });
            }
            if !(fault.at_s.is_finite() && (0.0..=MAX_SCRIPT_DURATION_S).contains(&fault.at_s)) {
                return Err(ScriptError::Invalid {
                    location,
                    reason: format!(
                        "at_s must be between 0 and {MAX_SCRIPT_DURATION_S}, got {}",
                        fault.at_s
                    ),
                });
            }
            fault
                .fault
                .validate()
                .map_err(|reason| ScriptError::Invalid { location, reason })?;
        }
        Ok(Self {
            pieces,
            start,
            cursor: [0; PADDLES],
            faults: spec.faults,
            duration_us,
        })
    }

    /// The faults the script schedules.
    pub fn faults(&self) -> &[ScheduledFault] {
        &self.faults
    }

    /// Time at which the last rod finishes its last segment, µs.
    pub fn duration_us(&self) -> u64 {
        self.duration_us.ceil() as u64
    }

    /// Pose of `rod` at `t_us`, without moving the playback cursor.
    pub fn pose_of(&self, rod: usize, t_us: f64) -> RodPose {
        pose_in(&self.pieces[rod], self.start[rod], 0, t_us).0
    }
}

/// Pose at `t_us` searching from piece `from_index`; also returns the piece index to
/// start from next time.
fn pose_in(pieces: &[Piece], start: RodPose, from_index: usize, t_us: f64) -> (RodPose, usize) {
    let Some(first) = pieces.first() else {
        return (start, 0);
    };
    if t_us <= first.t0_us {
        return (first.from, 0);
    }
    let mut i = from_index.min(pieces.len() - 1);
    // Times are non-decreasing in normal use; step back only if asked for the past.
    while i > 0 && t_us < pieces[i].t0_us {
        i -= 1;
    }
    while i + 1 < pieces.len() && t_us >= pieces[i].t1_us {
        i += 1;
    }
    let piece = pieces[i];
    if t_us >= piece.t1_us {
        return (piece.to, i);
    }
    let f = (t_us - piece.t0_us) / (piece.t1_us - piece.t0_us);
    (piece.from.lerp(piece.to, f), i)
}

/// Checks a pose is finite and within [`MAX_AXIAL_M`] and [`MAX_ANGLE_RAD`]; the reason
/// otherwise.
pub(super) fn check_pose(pose: RodPose) -> Result<(), String> {
    if !pose.is_finite() {
        return Err(format!("pose must be finite, got {pose:?}"));
    }
    if pose.axial_m.abs() > MAX_AXIAL_M {
        return Err(format!(
            "axial position {} m beyond ±{MAX_AXIAL_M} m",
            pose.axial_m
        ));
    }
    if pose.angle_rad.abs() > MAX_ANGLE_RAD {
        return Err(format!(
            "angle {} rad beyond ±{MAX_ANGLE_RAD} rad",
            pose.angle_rad
        ));
    }
    Ok(())
}

fn check_speed(axial: f64, angular: f64) -> Result<(), String> {
    if !(axial.is_finite() && axial.abs() <= MAX_AXIAL_SPEED_M_PER_S) {
        return Err(format!(
            "axial_m_per_s must be finite and within ±{MAX_AXIAL_SPEED_M_PER_S}, got {axial}"
        ));
    }
    if !(angular.is_finite() && angular.abs() <= MAX_ANGULAR_SPEED_RAD_PER_S) {
        return Err(format!(
            "angle_rad_per_s must be finite and within ±{MAX_ANGULAR_SPEED_RAD_PER_S}, got {angular}"
        ));
    }
    Ok(())
}

impl MotionSource for MotionScript {
    fn poses_at(&mut self, t_us: u64) -> RodPoses {
        let t = t_us as f64;
        let mut out = self.start;
        for (rod, pose) in out.iter_mut().enumerate() {
            let (at, cursor) = pose_in(&self.pieces[rod], self.start[rod], self.cursor[rod], t);
            *pose = at;
            self.cursor[rod] = cursor;
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const EXAMPLE: &str = r#"{
        "rods": [
            { "rod": 2, "start": { "axial_m": 0.01, "angle_rad": 0.0 },
              "segments": [
                { "velocity": { "duration_s": 0.5, "axial_m_per_s": 0.2, "angle_rad_per_s": 4.0 } },
                { "move_to": { "duration_s": 0.25, "axial_m": 0.0, "angle_rad": 1.0 } },
                { "hold": { "duration_s": 1.0 } } ] }
        ],
        "faults": [ { "at_s": 1.0, "port": 3, "fault": "unplug" } ]
    }"#;

    #[test]
    fn plays_segments_and_holds_the_end() {
        let mut s = MotionScript::from_json(EXAMPLE).unwrap();
        assert_eq!(s.duration_us(), 1_750_000);
        assert_eq!(s.faults().len(), 1);
        let p = s.poses_at(0);
        assert_eq!(p[2], RodPose::new(0.01, 0.0));
        assert_eq!(p[0], RodPose::default());
        let p = s.poses_at(250_000);
        assert!((p[2].axial_m - 0.06).abs() < 1e-12);
        assert!((p[2].angle_rad - 1.0).abs() < 1e-12);
        let p = s.poses_at(500_000);
        assert!((p[2].axial_m - 0.11).abs() < 1e-12);
        assert!((p[2].angle_rad - 2.0).abs() < 1e-12);
        let p = s.poses_at(625_000);
        assert!((p[2].axial_m - 0.055).abs() < 1e-12);
        assert!((p[2].angle_rad - 1.5).abs() < 1e-12);
        for t in [750_000, 1_000_000, 99_000_000] {
            assert_eq!(s.poses_at(t)[2], RodPose::new(0.0, 1.0));
        }
        // Asking for the past still answers correctly.
        assert!((s.poses_at(250_000)[2].axial_m - 0.06).abs() < 1e-12);
    }

    fn error_of(text: &str) -> String {
        MotionScript::from_json(text).unwrap_err().to_string()
    }

    #[test]
    fn bad_scripts_give_clear_errors() {
        let e = error_of(r#"{"rods":[{"rod":9,"segments":[]}]}"#);
        assert!(
            e.contains("rods[0]") && e.contains("rod must be 0–7, got 9"),
            "{e}"
        );
        let e = error_of(r#"{"rods":[{"rod":1,"segments":[]},{"rod":1,"segments":[]}]}"#);
        assert!(e.contains("rods[1] (rod 1)") && e.contains("twice"), "{e}");
        let e = error_of(r#"{"rods":[{"rod":1,"segments":[{"hold":{"duration_s":-1}}]}]}"#);
        assert!(e.contains("segment 0") && e.contains("duration_s"), "{e}");
        let e = error_of(
            r#"{"rods":[{"rod":1,"segments":[{"velocity":{"duration_s":1,"axial_m_per_s":1e9}}]}]}"#,
        );
        assert!(e.contains("axial_m_per_s"), "{e}");
        let e = error_of(
            r#"{"rods":[{"rod":1,"segments":[{"velocity":{"duration_s":1000,"axial_m_per_s":1}}]}]}"#,
        );
        assert!(e.contains("beyond ±10 m"), "{e}");
        let e = error_of(r#"{"rods":[{"rod":1,"segments":[{"teleport":{}}]}]}"#);
        assert!(e.contains("unknown variant") && e.contains("line"), "{e}");
        let e = error_of(r#"{"rods":[{"rod":1,"segmets":[]}]}"#);
        assert!(e.contains("unknown field"), "{e}");
        let e = error_of(r#"{"faults":[{"at_s":1,"port":8,"fault":"plug"}]}"#);
        assert!(e.contains("faults[0]") && e.contains("port"), "{e}");
        let e =
            error_of(r#"{"faults":[{"at_s":1,"port":0,"fault":{"drop_rate":{"probability":2}}}]}"#);
        assert!(e.contains("probability"), "{e}");
        let e = error_of("not json");
        assert!(e.contains("not valid JSON"), "{e}");
        let e = MotionScript::load(Path::new("/nonexistent/script.json"))
            .unwrap_err()
            .to_string();
        assert!(e.contains("/nonexistent/script.json"), "{e}");
    }

    #[test]
    fn empty_script_is_stationary() {
        let mut s = MotionScript::from_json("{}").unwrap();
        assert_eq!(s.poses_at(5_000_000), [RodPose::default(); PADDLES]);
        assert_eq!(s.duration_us(), 0);
    }
}

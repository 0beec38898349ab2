//! Per-paddle calibration: raw sensor counts → rod slide (m) and angle (rad), paddle
//! frame (see [`crate::input`]).
//!
//! The map is linear with cross-talk:
//!
//! ```text
//! [slide_m  ]   [m00 m01] [axial counts   ]   [offset_slide_m ]
//! [angle_rad] = [m10 m11] [rotation counts] + [offset_angle_rad]
//! ```
//!
//! where the counts are summed since tracking started, so `offset` is the pose at that
//! moment. The off-diagonal terms undo the sensor's cross-talk (turning the rod also
//! reads as a little axial motion and vice versa), the diagonal its resolution and gain
//! error. [`PaddleCalibration::fit`] finds all six numbers by least squares from pairs
//! of known poses and measured count sums (the guided motion, [`super::guided`]).
//!
//! **Defaults** (no calibration file): the sensor's nominal resolution
//! [`DEFAULT_COUNTS_PER_MM`] = 8 counts/mm and a rod of radius [`DEFAULT_ROD_RADIUS_M`]
//! = 8 mm (a 16 mm rod), no cross-talk, offset 0 (the rod centred and upright when
//! tracking starts): `m00 = 1 / 8000` m/count, `m11 = 1 / (8000 × 0.008)` rad/count.
//!
//! **File** ([`Calibration::save`], [`Calibration::load`]): JSON,
//! `{"format":"space-foosball-calibration","version":1,"paddles":[{"matrix":[[m00,m01],[m10,m11]],"offset":[s,a]}, … 8 entries]}`,
//! written atomically ([`crate::atomic_file`]); loading checks the shape, finiteness,
//! the ranges ([`MAX_GAIN_PER_COUNT`], [`MAX_OFFSET_SLIDE_M`], [`MAX_OFFSET_ANGLE_RAD`])
//! and that every matrix is invertible. [`Calibration::load_or_default`] never fails:
//! a missing file gives the defaults, a bad one the defaults and a warning.

use crate::atomic_file::write_atomic;
use foosball_protocol::PADDLES;
use nalgebra::{DMatrix, Matrix2, Vector2};
use serde::{Deserialize, Serialize};
use std::path::Path;

/// Nominal sensor resolution the firmware configures, counts per millimetre.
pub const DEFAULT_COUNTS_PER_MM: f64 = 8.0;
/// Radius of the rod surface the sensor looks at, metres (a 16 mm rod).
pub const DEFAULT_ROD_RADIUS_M: f64 = 0.008;
/// The `format` string of calibration files.
pub const FILE_FORMAT: &str = "space-foosball-calibration";
/// The version of the calibration file format.
pub const FILE_VERSION: u32 = 1;

/// Largest magnitude of a matrix entry: metres of slide or radians of angle per count.
/// The nominal map is 1.25e-4 m and 0.016 rad per count; a sensor whose single count
/// moves the rod a metre or turns it a radian does not exist, and larger gains turn the
/// count sums of a long match into infinite poses.
pub const MAX_GAIN_PER_COUNT: f64 = 1.0;
/// Largest magnitude of the slide offset (the slide when tracking starts), metres: more
/// than any table's width.
pub const MAX_OFFSET_SLIDE_M: f64 = 1.0;
/// Largest magnitude of the angle offset (the angle when tracking starts, whole turns
/// included), radians.
pub const MAX_OFFSET_ANGLE_RAD: f64 = 1000.0;

/// A calibration matrix is rejected when `|det| ≤ SINGULAR_TOLERANCE · |m00 m11| +
/// |m01 m10|`-scale, i.e. when its rows are parallel to about one part in 10⁹.
const SINGULAR_TOLERANCE: f64 = 1e-9;

/// Why a calibration could not be fitted, loaded or saved.
#[derive(Debug, thiserror::Error)]
pub enum CalibrationError {
    /// The file could not be read or written.
    #[error("calibration file {path}: {source}")]
    Io {
        /// The file.
        path: String,
        /// The operating-system error.
        #[source]
        source: std::io::Error,
    },
    /// The file is not a calibration (syntax, wrong shape, wrong format string/version).
    #[error("calibration file {path} is malformed: {message}")]
    Malformed {
        /// The file.
        path: String,
        /// What is wrong.
        message: String,
    },
    /// A number is NaN or infinite.
    #[error("paddle {paddle}: calibration value is not finite")]
    NotFinite {
        /// The paddle (port).
        paddle: usize,
    },
    /// A number is outside its physical range ([`MAX_GAIN_PER_COUNT`],
    /// [`MAX_OFFSET_SLIDE_M`], [`MAX_OFFSET_ANGLE_RAD`]).
    #[error("paddle {paddle}: calibration {field} = {value:e} is beyond ±{max}")]
    OutOfRange {
        /// The paddle (port).
        paddle: usize,
        /// Which number: `matrix[r][c]`, `offset[0]` (slide, m) or `offset[1]` (angle, rad).
        field: &'static str,
        /// Its value.
        value: f64,
        /// The largest magnitude allowed.
        max: f64,
    },
    /// The matrix cannot be inverted: the two readings are not independent.
    #[error("paddle {paddle}: calibration matrix is singular (det = {det:e})")]
    Singular {
        /// The paddle (port).
        paddle: usize,
        /// Its determinant.
        det: f64,
    },
    /// The guided motion did not excite both axes (or too few samples were taken).
    #[error("cannot fit a calibration: {0}")]
    Underdetermined(String),
}

/// The calibration of one paddle (see the module docs for the map).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PaddleCalibration {
    /// Row 0: metres of slide per axial and per rotation count; row 1: radians of angle
    /// per axial and per rotation count.
    pub matrix: [[f64; 2]; 2],
    /// Pose at zero counts: `[slide_m, angle_rad]`.
    pub offset: [f64; 2],
}

impl Default for PaddleCalibration {
    fn default() -> Self {
        Self::nominal(DEFAULT_COUNTS_PER_MM, DEFAULT_ROD_RADIUS_M)
    }
}

impl PaddleCalibration {
    /// The map of an ideal sensor at `counts_per_mm` on a rod of radius `rod_radius_m`:
    /// no cross-talk, no gain error, offset zero.
    pub fn nominal(counts_per_mm: f64, rod_radius_m: f64) -> Self {
        let counts_per_m = counts_per_mm * 1e3;
        Self {
            matrix: [
                [1.0 / counts_per_m, 0.0],
                [0.0, 1.0 / (counts_per_m * rod_radius_m)],
            ],
            offset: [0.0, 0.0],
        }
    }

    /// The pose `[slide_m, angle_rad]` (paddle frame) for count sums
    /// `[axial, rotation]`.
    pub fn apply(&self, counts: [f64; 2]) -> [f64; 2] {
        let m = &self.matrix;
        [
            m[0][0] * counts[0] + m[0][1] * counts[1] + self.offset[0],
            m[1][0] * counts[0] + m[1][1] * counts[1] + self.offset[1],
        ]
    }

    /// The pose change for a change of counts (the matrix alone).
    pub fn apply_delta(&self, counts: [f64; 2]) -> [f64; 2] {
        let m = &self.matrix;
        [
            m[0][0] * counts[0] + m[0][1] * counts[1],
            m[1][0] * counts[0] + m[1][1] * counts[1],
        ]
    }

    /// The count sums that give `pose` (the inverse map), if the matrix is invertible.
    pub fn counts_for(&self, pose: [f64; 2]) -> Option<[f64; 2]> {
        let m = Matrix2::new(
            self.matrix[0][0],
            self.matrix[0][1],
            self.matrix[1][0],
            self.matrix[1][1],
        );
        let inv = m.try_inverse()?;
        let c = inv * Vector2::new(pose[0] - self.offset[0], pose[1] - self.offset[1]);
        Some([c[0], c[1]])
    }

    /// Determinant of the matrix.
    pub fn det(&self) -> f64 {
        let m = &self.matrix;
        m[0][0] * m[1][1] - m[0][1] * m[1][0]
    }

    /// Checks every value is finite and within its range, and the matrix invertible;
    /// `paddle` names it in the error.
    pub fn validate(&self, paddle: usize) -> Result<(), CalibrationError> {
        let values = self.matrix.iter().flatten().chain(self.offset.iter());
        if values.clone().any(|v| !v.is_finite()) {
            return Err(CalibrationError::NotFinite { paddle });
        }
        const MATRIX: [[&str; 2]; 2] = [
            ["matrix[0][0]", "matrix[0][1]"],
            ["matrix[1][0]", "matrix[1][1]"],
        ];
        let ranged = MATRIX
            .iter()
            .flatten()
            .zip(self.matrix.iter().flatten())
            .map(|(&field, &value)| (field, value, MAX_GAIN_PER_COUNT))
            .chain([
                ("offset[0]", self.offset[0], MAX_OFFSET_SLIDE_M),
                ("offset[1]", self.offset[1], MAX_OFFSET_ANGLE_RAD),
            ]);
        for (field, value, max) in ranged {
            if value.abs() > max {
                return Err(CalibrationError::OutOfRange {
                    paddle,
                    field,
                    value,
                    max,
                });
            }
        }
        let m = &self.matrix;
        let scale = (m[0][0] * m[1][1]).abs() + (m[0][1] * m[1][0]).abs();
        let det = self.det();
        if scale == 0.0 || det.abs() <= SINGULAR_TOLERANCE * scale {
            return Err(CalibrationError::Singular { paddle, det });
        }
        Ok(())
    }

    /// Fits the map by least squares to `samples`: each is the count sums `[axial,
    /// rotation]` measured from the start of the motion and the true pose `[slide_m,
    /// angle_rad]` at that moment. Needs at least three samples that move both axes.
    ///
    /// Each output row is fitted independently (`[c_axial, c_rotation, 1] · row = pose`)
    /// through a singular value decomposition; the columns are scaled first so counts
    /// (thousands) and the constant column (1) are conditioned alike.
    pub fn fit(samples: &[([f64; 2], [f64; 2])]) -> Result<Self, CalibrationError> {
        if samples.len() < 3 {
            return Err(CalibrationError::Underdetermined(format!(
                "{} samples, at least 3 needed",
                samples.len()
            )));
        }
        let n = samples.len();
        let mut scale = [1.0f64; 2];
        for axis in 0..2 {
            let max = samples
                .iter()
                .map(|(c, _)| c[axis].abs())
                .fold(0.0, f64::max);
            if !max.is_finite() {
                return Err(CalibrationError::Underdetermined(
                    "counts are not finite".into(),
                ));
            }
            if max == 0.0 {
                let name = ["axial", "rotation"][axis];
                return Err(CalibrationError::Underdetermined(format!(
                    "no {name} motion was measured"
                )));
            }
            scale[axis] = max;
        }
        let a = DMatrix::from_fn(n, 3, |i, j| match j {
            0 => samples[i].0[0] / scale[0],
            1 => samples[i].0[1] / scale[1],
            _ => 1.0,
        });
        let b = DMatrix::from_fn(n, 2, |i, j| samples[i].1[j]);
        let svd = a.svd(true, true);
        let smax = svd.singular_values.max();
        let smin = svd.singular_values.min();
        if smin.is_nan() || smin <= 1e-9 * smax {
            return Err(CalibrationError::Underdetermined(format!(
                "the motion does not separate the axes (singular values {smax:e}, {smin:e})"
            )));
        }
        let x = svd
            .solve(&b, 1e-12 * smax)
            .map_err(|e| CalibrationError::Underdetermined(e.to_string()))?;
        let fitted = Self {
            matrix: [
                [x[(0, 0)] / scale[0], x[(1, 0)] / scale[1]],
                [x[(0, 1)] / scale[0], x[(1, 1)] / scale[1]],
            ],
            offset: [x[(2, 0)], x[(2, 1)]],
        };
        fitted.validate(0).map_err(|e| {
            CalibrationError::Underdetermined(format!("the fitted map is unusable: {e}"))
        })?;
        Ok(fitted)
    }
}

/// The calibration of every paddle of a board, indexed by port.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Calibration {
    /// Per port.
    pub paddles: [PaddleCalibration; PADDLES],
}

/// The calibration file's layout.
#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct CalibrationFile {
    format: String,
    version: u32,
    paddles: Vec<PaddleCalibration>,
}

impl Calibration {
    /// Checks every paddle's map.
    pub fn validate(&self) -> Result<(), CalibrationError> {
        for (i, p) in self.paddles.iter().enumerate() {
            p.validate(i)?;
        }
        Ok(())
    }

    /// The calibration as the file's JSON text.
    pub fn to_json(&self) -> String {
        let file = CalibrationFile {
            format: FILE_FORMAT.into(),
            version: FILE_VERSION,
            paddles: self.paddles.to_vec(),
        };
        // Plain numbers and strings: serialisation cannot fail (non-finite values are
        // rejected before saving).
        serde_json::to_string_pretty(&file).unwrap_or_default()
    }

    /// Parses and validates the file's JSON text; `path` names it in errors.
    pub fn from_json(text: &str, path: &str) -> Result<Self, CalibrationError> {
        let malformed = |message: String| CalibrationError::Malformed {
            path: path.into(),
            message,
        };
        let file: CalibrationFile =
            serde_json::from_str(text).map_err(|e| malformed(e.to_string()))?;
        if file.format != FILE_FORMAT {
            return Err(malformed(format!(
                "format is {:?}, expected {FILE_FORMAT:?}",
                file.format
            )));
        }
        if file.version != FILE_VERSION {
            return Err(malformed(format!(
                "version {} is not supported (this build reads {FILE_VERSION})",
                file.version
            )));
        }
        let paddles: [PaddleCalibration; PADDLES] =
            file.paddles
                .try_into()
                .map_err(|v: Vec<PaddleCalibration>| {
                    malformed(format!("{} paddles, expected {PADDLES}", v.len()))
                })?;
        let calibration = Self { paddles };
        calibration.validate()?;
        Ok(calibration)
    }

    /// Loads and validates a calibration file.
    pub fn load(path: &Path) -> Result<Self, CalibrationError> {
        let text = std::fs::read_to_string(path).map_err(|source| CalibrationError::Io {
            path: path.display().to_string(),
            source,
        })?;
        Self::from_json(&text, &path.display().to_string())
    }

    /// Loads `path`; a missing file gives the defaults with no warning, an unreadable or
    /// invalid one the defaults and the reason as a warning (the game goes on with
    /// nominal input and tells the player to recalibrate). Never panics, never writes.
    pub fn load_or_default(path: &Path) -> (Self, Option<CalibrationError>) {
        match Self::load(path) {
            Ok(c) => (c, None),
            Err(CalibrationError::Io { source, .. })
                if source.kind() == std::io::ErrorKind::NotFound =>
            {
                (Self::default(), None)
            }
            Err(e) => (Self::default(), Some(e)),
        }
    }

    /// Saves atomically: the old file stays whole until the new one is complete on disk.
    /// An invalid calibration is refused before anything is written.
    pub fn save(&self, path: &Path) -> Result<(), CalibrationError> {
        self.validate()?;
        write_atomic(path, self.to_json().as_bytes()).map_err(|source| CalibrationError::Io {
            path: path.display().to_string(),
            source,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nominal_map_matches_resolution_and_radius() {
        let c = PaddleCalibration::default();
        // 8000 counts = 1 m of slide.
        assert!((c.apply([8000.0, 0.0])[0] - 1.0).abs() < 1e-12);
        // One turn moves the surface 2π·8 mm = 50.27 mm = 402.1 counts.
        let counts_per_turn = 2.0 * std::f64::consts::PI * 8.0 * 8.0;
        let angle = c.apply([0.0, counts_per_turn])[1];
        assert!((angle - 2.0 * std::f64::consts::PI).abs() < 1e-12);
        let back = c.counts_for([0.01, 1.0]).unwrap();
        let pose = c.apply(back);
        assert!((pose[0] - 0.01).abs() < 1e-15 && (pose[1] - 1.0).abs() < 1e-12);
    }

    #[test]
    fn fit_recovers_an_exact_map() {
        let truth = PaddleCalibration {
            matrix: [[1.2e-4, -3.0e-6], [2.0e-4, 1.6e-2]],
            offset: [-0.09, 0.1],
        };
        let inv_samples: Vec<([f64; 2], [f64; 2])> = [
            [0.0, 0.0],
            [0.19, 0.0],
            [0.19, 12.0],
            [-0.1, 12.0],
            [-0.1, -3.0],
        ]
        .into_iter()
        .map(|pose| (truth.counts_for(pose).unwrap(), pose))
        .collect();
        let fitted = PaddleCalibration::fit(&inv_samples).unwrap();
        for r in 0..2 {
            for c in 0..2 {
                let rel =
                    (fitted.matrix[r][c] - truth.matrix[r][c]).abs() / truth.matrix[r][r].abs();
                assert!(rel < 1e-9, "{r}{c}: {fitted:?}");
            }
            assert!((fitted.offset[r] - truth.offset[r]).abs() < 1e-9);
        }
    }

    #[test]
    fn fit_refuses_motion_on_one_axis_only() {
        let samples = [
            ([0.0, 0.0], [0.0, 0.0]),
            ([1000.0, 0.0], [0.125, 0.0]),
            ([2000.0, 0.0], [0.25, 0.0]),
        ];
        let err = PaddleCalibration::fit(&samples).unwrap_err();
        assert!(err.to_string().contains("rotation"), "{err}");
        let samples = [([0.0, 0.0], [0.0, 0.0]), ([1.0, 1.0], [0.0, 0.0])];
        assert!(matches!(
            PaddleCalibration::fit(&samples),
            Err(CalibrationError::Underdetermined(_))
        ));
        // Both axes move, but always together: the axes cannot be separated.
        let samples = [
            ([0.0, 0.0], [0.0, 0.0]),
            ([100.0, 100.0], [0.01, 1.0]),
            ([200.0, 200.0], [0.02, 2.0]),
            ([300.0, 300.0], [0.03, 3.0]),
        ];
        assert!(matches!(
            PaddleCalibration::fit(&samples),
            Err(CalibrationError::Underdetermined(_))
        ));
    }

    #[test]
    fn validation_rejects_nan_and_singular() {
        let mut c = Calibration::default();
        c.validate().unwrap();
        c.paddles[3].offset[1] = f64::NAN;
        assert!(matches!(
            c.validate(),
            Err(CalibrationError::NotFinite { paddle: 3 })
        ));
        let mut c = Calibration::default();
        c.paddles[5].matrix = [[1e-4, 2e-4], [1e-2, 2e-2]];
        assert!(matches!(
            c.validate(),
            Err(CalibrationError::Singular { paddle: 5, .. })
        ));
    }

    #[test]
    fn validation_rejects_gains_and_offsets_out_of_range() {
        // A gain of 1e300 per count made 32767 counts an infinite angle, and a slide
        // gain of -1.8e308 an infinite slide, whose clamping then gave NaN.
        for (row, col, gain) in [(1, 1, 1e300), (1, 0, -f64::MAX), (0, 1, 2.0)] {
            let mut c = Calibration::default();
            c.paddles[6].matrix[row][col] = gain;
            let err = c.validate().unwrap_err();
            assert!(
                matches!(err, CalibrationError::OutOfRange { paddle: 6, max, .. } if max == MAX_GAIN_PER_COUNT),
                "{err}"
            );
            assert!(
                err.to_string().contains(&format!("matrix[{row}][{col}]")),
                "{err}"
            );
        }
        let mut c = Calibration::default();
        c.paddles[3].offset[0] = 1e7;
        assert!(matches!(
            c.validate(),
            Err(CalibrationError::OutOfRange {
                paddle: 3,
                field: "offset[0]",
                ..
            })
        ));
        let mut c = Calibration::default();
        c.paddles[0].offset[1] = -1e4;
        assert!(matches!(
            c.validate(),
            Err(CalibrationError::OutOfRange {
                paddle: 0,
                field: "offset[1]",
                ..
            })
        ));
        // At the limits, the map is accepted.
        let mut c = Calibration::default();
        c.paddles[1].matrix[1][1] = MAX_GAIN_PER_COUNT;
        c.paddles[1].offset = [-MAX_OFFSET_SLIDE_M, MAX_OFFSET_ANGLE_RAD];
        c.validate().unwrap();
    }
}

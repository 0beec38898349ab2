//! Checking that a table makes physical sense.

use super::Table;
use crate::side::Side;
use foosball_protocol::PADDLES;

/// Why a table was rejected.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum TableError {
    /// The file could not be read.
    #[error("cannot read table file {path}: {message}")]
    Io {
        /// The file.
        path: String,
        /// What went wrong.
        message: String,
    },
    /// The TOML did not parse into a table (syntax, unknown or missing fields).
    #[error("table file does not parse: {0}")]
    Parse(String),
    /// A size or parameter is not a positive finite number (or out of its range).
    #[error("{what} must be {expected}, got {value}")]
    BadValue {
        /// Which value ("field.width_m", "rod 3 travel_m", …).
        what: String,
        /// What it must be.
        expected: &'static str,
        /// What it is.
        value: f64,
    },
    /// The men of a rod do not fit the field's width over their travel.
    #[error(
        "rod {rod}: {men} men {spacing_m} m apart with travel {travel_m} m need {needed_m:.4} m \
         of width, the field has {width_m} m"
    )]
    MenDoNotFit {
        /// Rod index.
        rod: usize,
        /// Men on it.
        men: usize,
        /// Their spacing, m.
        spacing_m: f64,
        /// Their travel, m.
        travel_m: f64,
        /// Width they need, m.
        needed_m: f64,
        /// Field width, m.
        width_m: f64,
    },
    /// Neighbouring men on a rod overlap.
    #[error("rod {rod}: men {spacing_m} m apart overlap (each is {width_m} m wide)")]
    MenOverlap {
        /// Rod index.
        rod: usize,
        /// Their spacing, m.
        spacing_m: f64,
        /// Width of one man, m.
        width_m: f64,
    },
    /// A rod lies outside the field, or rods are not in order along `x`.
    #[error("rod {rod}: x_m = {x_m} must be inside the field and after the previous rod")]
    RodPlacement {
        /// Rod index.
        rod: usize,
        /// Its position, m.
        x_m: f64,
    },
    /// Two rods use one board port, or a port does not exist.
    #[error("rod {rod}: port {port} is out of range (0…{max}) or already used")]
    Port {
        /// Rod index.
        rod: usize,
        /// The port.
        port: usize,
        /// Highest port.
        max: usize,
    },
    /// The men cannot play the ball: they do not reach down to it, or they hit the field.
    #[error("{side:?} men: {reason}")]
    Reach {
        /// The team.
        side: Side,
        /// What is wrong.
        reason: String,
    },
    /// A number outside its physical range (the table format docs list the ranges).
    #[error("{what} must be within {} … {}, got {}", num(*.lo), num(*.hi), num(*.value))]
    OutOfRange {
        /// Which value ("goal.height_m", "Home params.mass_kg", …).
        what: String,
        /// What it is.
        value: f64,
        /// Lowest allowed (SI unit of the field).
        lo: f64,
        /// Highest allowed.
        hi: f64,
    },
    /// A rod has too few or too many men.
    #[error("rod {rod}: {men} men, must be {lo} … {hi}")]
    Men {
        /// Rod index.
        rod: usize,
        /// Men on it.
        men: usize,
        /// Fewest allowed.
        lo: usize,
        /// Most allowed.
        hi: usize,
    },
    /// Something else is inconsistent (teams, goal vs field, no rods).
    #[error("{0}")]
    Inconsistent(String),
}

/// A number as people write it: plain in `1e-3 … 1e4`, scientific outside (so `1e19`, not
/// twenty digits).
fn num(x: f64) -> String {
    if x == 0.0 || !x.is_finite() || (1e-3..1e4).contains(&x.abs()) {
        format!("{x}")
    } else {
        format!("{x:e}")
    }
}

fn positive(what: impl Into<String>, value: f64) -> Result<(), TableError> {
    if value.is_finite() && value > 0.0 {
        Ok(())
    } else {
        Err(TableError::BadValue {
            what: what.into(),
            expected: "a positive number",
            value,
        })
    }
}

fn in_range(
    what: impl Into<String>,
    value: f64,
    lo: f64,
    hi: f64,
    expected: &'static str,
) -> Result<(), TableError> {
    if value.is_finite() && (lo..=hi).contains(&value) {
        Ok(())
    } else {
        Err(TableError::BadValue {
            what: what.into(),
            expected,
            value,
        })
    }
}

/// A value that must lie in `lo … hi` (finite); the message states the range and unit.
fn ranged(what: impl Into<String>, value: f64, (lo, hi): (f64, f64)) -> Result<(), TableError> {
    if value.is_finite() && (lo..=hi).contains(&value) {
        Ok(())
    } else {
        Err(TableError::OutOfRange {
            what: what.into(),
            value,
            lo,
            hi,
        })
    }
}

/// The physical ranges of a table's numbers (SI units). Real tables are about 1.2 × 0.7 m
/// with 100 mm high rods, a 35 mm ball of 24–29 g and men of 70–140 g, 1 to 5 on a rod;
/// each range holds those with a generous margin (custom and toy tables, the lighter men
/// of the presets) and keeps the physics world small: a table is at most 5 m × 3 m with at
/// most 8 rods (one per board port) of at most 11 men.
mod ranges {
    /// Field length, goal line to goal line (m).
    pub const FIELD_LENGTH_M: (f64, f64) = (0.3, 5.0);
    /// Field width (m).
    pub const FIELD_WIDTH_M: (f64, f64) = (0.2, 3.0);
    /// Shortest corner ramp (m), when there is one.
    pub const MIN_RAMP_M: f64 = 1e-3;
    /// Wall height (m).
    pub const WALL_HEIGHT_M: (f64, f64) = (0.01, 1.0);
    /// Rod height above the field (m).
    pub const ROD_HEIGHT_M: (f64, f64) = (0.01, 1.0);
    /// Goal mouth width (m); also at most the field width.
    pub const GOAL_WIDTH_M: (f64, f64) = (0.01, 3.0);
    /// Goal mouth height (m).
    pub const GOAL_HEIGHT_M: (f64, f64) = (0.01, 1.0);
    /// Goal box depth (m).
    pub const GOAL_DEPTH_M: (f64, f64) = (0.01, 1.0);
    /// Ball diameter (m): a 35 mm ball, from 5 mm to 200 mm.
    pub const BALL_DIAMETER_M: (f64, f64) = (0.005, 0.2);
    /// Ball mass (kg): 24–29 g real, from 1 g to 1 kg.
    pub const BALL_MASS_KG: (f64, f64) = (1e-3, 1.0);
    /// Men on one rod: 1 (goalkeeper) to 5 real, at most 11.
    pub const MEN: (usize, usize) = (1, 11);
    /// A man's mass (kg): 70–140 g real (the presets' 40–60 g included), from 5 g to 2 kg.
    pub const MAN_MASS_KG: (f64, f64) = (5e-3, 2.0);
    /// A man's widths and depth (m).
    pub const MAN_WIDTH_M: (f64, f64) = (2e-3, 0.2);
    /// A man's head height above the rod, and his foot reach below it (m).
    pub const MAN_HEIGHT_M: (f64, f64) = (2e-3, 0.5);
}

/// The ranges of a team's character parameters.
fn character_ranges(side: Side, p: &super::CharacterParams) -> Result<(), TableError> {
    let name = |field: &str| format!("{side:?} params.{field}");
    ranged(name("body_width_m"), p.body_width_m, ranges::MAN_WIDTH_M)?;
    ranged(name("body_depth_m"), p.body_depth_m, ranges::MAN_WIDTH_M)?;
    ranged(name("foot_width_m"), p.foot_width_m, ranges::MAN_WIDTH_M)?;
    ranged(name("head_height_m"), p.head_height_m, ranges::MAN_HEIGHT_M)?;
    ranged(name("foot_reach_m"), p.foot_reach_m, ranges::MAN_HEIGHT_M)?;
    ranged(name("mass_kg"), p.mass_kg, ranges::MAN_MASS_KG)
}

impl Table {
    /// Checks the table: positive finite sizes, the goal fits the end wall, the men fit
    /// the width over their travel without overlapping, rods inside the field in order
    /// along `x`, one port per rod, teams `[home, away]`, and the men can reach the ball
    /// without touching the field.
    pub fn validate(&self) -> Result<(), TableError> {
        let f = &self.field;
        ranged("field.length_m", f.length_m, ranges::FIELD_LENGTH_M)?;
        ranged("field.width_m", f.width_m, ranges::FIELD_WIDTH_M)?;
        ranged(
            "field.wall_height_m",
            f.wall_height_m,
            ranges::WALL_HEIGHT_M,
        )?;
        ranged("field.rod_height_m", f.rod_height_m, ranges::ROD_HEIGHT_M)?;
        in_range(
            "field.corner_ramp_m",
            f.corner_ramp_m,
            0.0,
            0.5 * f.width_m.min(f.length_m),
            "within 0…half the smaller field size",
        )?;
        // A ramp is absent (0) or at least a millimetre: its slope is height / length, and a
        // subnormal length (5e-324 m) made the ramp's normal NaN.
        if f.corner_ramp_m > 0.0 && f.corner_ramp_m < ranges::MIN_RAMP_M {
            return Err(TableError::OutOfRange {
                what: "field.corner_ramp_m (0 for no ramp)".into(),
                value: f.corner_ramp_m,
                lo: ranges::MIN_RAMP_M,
                hi: 0.5 * f.width_m.min(f.length_m),
            });
        }
        in_range(
            "field.corner_ramp_height_m",
            f.corner_ramp_height_m,
            0.0,
            f.wall_height_m,
            "within 0…the wall height",
        )?;
        let g = &self.goal;
        ranged("goal.width_m", g.width_m, ranges::GOAL_WIDTH_M)?;
        ranged("goal.height_m", g.height_m, ranges::GOAL_HEIGHT_M)?;
        ranged("goal.depth_m", g.depth_m, ranges::GOAL_DEPTH_M)?;
        if g.width_m + 2.0 * f.corner_ramp_m > f.width_m {
            return Err(TableError::Inconsistent(format!(
                "goal ({} m) and corner ramps ({} m each) are wider than the end wall ({} m)",
                g.width_m, f.corner_ramp_m, f.width_m
            )));
        }
        let b = &self.ball;
        ranged("ball.diameter_m", b.diameter_m, ranges::BALL_DIAMETER_M)?;
        ranged("ball.mass_kg", b.mass_kg, ranges::BALL_MASS_KG)?;
        in_range("ball.restitution", b.restitution, 0.0, 1.0, "within 0…1")?;
        in_range("ball.friction", b.friction, 0.0, 10.0, "within 0…10")?;
        in_range(
            "ball.rolling_resistance_m",
            b.rolling_resistance_m,
            0.0,
            b.diameter_m,
            "within 0…the ball diameter",
        )?;
        if b.diameter_m >= g.height_m.min(g.width_m) {
            return Err(TableError::Inconsistent(format!(
                "the ball ({} m) does not fit the goal mouth ({} × {} m)",
                b.diameter_m, g.width_m, g.height_m
            )));
        }
        for (i, side) in Side::BOTH.into_iter().enumerate() {
            let team = &self.teams[i];
            if team.side != side {
                return Err(TableError::Inconsistent(format!(
                    "teams must be listed [home, away]; entry {i} is {:?}",
                    team.side
                )));
            }
            let p = team.character_params();
            character_ranges(side, &p)?;
            p.validate()
                .map_err(|reason| TableError::Reach { side, reason })?;
            if p.foot_reach_m >= f.rod_height_m {
                return Err(TableError::Reach {
                    side,
                    reason: format!(
                        "foot reach {} m touches the field (rods at {} m)",
                        p.foot_reach_m, f.rod_height_m
                    ),
                });
            }
            if f.rod_height_m - p.foot_reach_m >= b.diameter_m * 0.75 {
                return Err(TableError::Reach {
                    side,
                    reason: format!(
                        "feet end {:.4} m above the field: they cannot kick a {} m ball",
                        f.rod_height_m - p.foot_reach_m,
                        b.diameter_m
                    ),
                });
            }
            if self.rods.iter().all(|r| r.team != side) {
                return Err(TableError::Inconsistent(format!("{side:?} has no rods")));
            }
        }
        self.validate_rods()
    }

    /// The rods' part of [`Table::validate`]: at most one per board port, inside the
    /// field in order along `x`, their men within range, not overlapping and fitting the
    /// width over their travel.
    fn validate_rods(&self) -> Result<(), TableError> {
        let f = &self.field;
        if self.rods.len() > PADDLES {
            return Err(TableError::Inconsistent(format!(
                "{} rods: at most {PADDLES}, one per board port",
                self.rods.len()
            )));
        }
        let mut ports = [false; PADDLES];
        let mut previous_x = -0.5 * f.length_m;
        for (i, rod) in self.rods.iter().enumerate() {
            if !(rod.x_m.is_finite() && rod.x_m > previous_x && rod.x_m < 0.5 * f.length_m) {
                return Err(TableError::RodPlacement {
                    rod: i,
                    x_m: rod.x_m,
                });
            }
            previous_x = rod.x_m;
            if rod.port >= PADDLES || ports[rod.port] {
                return Err(TableError::Port {
                    rod: i,
                    port: rod.port,
                    max: PADDLES - 1,
                });
            }
            ports[rod.port] = true;
            let (lo, hi) = ranges::MEN;
            if !(lo..=hi).contains(&rod.men) {
                return Err(TableError::Men {
                    rod: i,
                    men: rod.men,
                    lo,
                    hi,
                });
            }
            in_range(
                format!("rod {i} travel_m"),
                rod.travel_m,
                0.0,
                f.width_m,
                "within 0…the field width",
            )?;
            let half_width = self.team(rod.team).character_params().half_width_m();
            if rod.men > 1 {
                positive(format!("rod {i} spacing_m"), rod.spacing_m)?;
                if rod.spacing_m <= 2.0 * half_width {
                    return Err(TableError::MenOverlap {
                        rod: i,
                        spacing_m: rod.spacing_m,
                        width_m: 2.0 * half_width,
                    });
                }
            } else if !rod.spacing_m.is_finite() || rod.spacing_m < 0.0 {
                return Err(TableError::BadValue {
                    what: format!("rod {i} spacing_m"),
                    expected: "a non-negative number",
                    value: rod.spacing_m,
                });
            }
            let span = (rod.men as f64 - 1.0) * rod.spacing_m;
            let needed = span + rod.travel_m + 2.0 * half_width;
            if needed > f.width_m {
                return Err(TableError::MenDoNotFit {
                    rod: i,
                    men: rod.men,
                    spacing_m: rod.spacing_m,
                    travel_m: rod.travel_m,
                    needed_m: needed,
                    width_m: f.width_m,
                });
            }
        }
        Ok(())
    }
}

//! The ranges of [`RulesConfig`]: rules come from recordings and settings files, so every
//! number is checked before a match is built on it.

use super::RulesConfig;
use crate::table::Table;

/// Why a [`RulesConfig`] cannot be played.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum RulesError {
    /// A number is not finite or lies outside its range.
    #[error("rules.{what} is {value}, outside {lo}…{hi}")]
    OutOfRange {
        /// The field.
        what: &'static str,
        /// Its value.
        value: f64,
        /// The least value allowed.
        lo: f64,
        /// The greatest value allowed.
        hi: f64,
    },
    /// The rules do not fit the table.
    #[error("rules do not fit the table: {0}")]
    Inconsistent(String),
}

/// Goals to win: a match ends.
const GOALS: (u32, u32) = (1, 999);
/// Any speed threshold or serve speed (m/s): 50 m/s is the fastest ball the engine's
/// continuous collision is held to (the 5 mm walls of the hard cases).
const SPEED_M_PER_S: (f64, f64) = (0.0, 50.0);
/// Any duration (ms of match time): a day, so that match time plus any pause stays far
/// from the end of `u64`.
const DURATION_MS: u64 = 86_400_000;

fn ranged(what: &'static str, value: f64, (lo, hi): (f64, f64)) -> Result<(), RulesError> {
    // `contains` is false for NaN.
    if (lo..=hi).contains(&value) {
        Ok(())
    } else {
        Err(RulesError::OutOfRange {
            what,
            value,
            lo,
            hi,
        })
    }
}

impl RulesConfig {
    /// Checks every number against its range, and the serve against `table`: goals to win
    /// 1…999; speeds finite, 0…50 m/s; durations at most a day; the stuck radius within
    /// the field's length; the served ball (its diameter plus the drop height) below the
    /// walls' top.
    pub fn validate(&self, table: &Table) -> Result<(), RulesError> {
        let goals = f64::from(self.goals_to_win);
        ranged(
            "goals_to_win",
            goals,
            (f64::from(GOALS.0), f64::from(GOALS.1)),
        )?;
        for (what, v) in [
            ("slow_speed_m_per_s", self.slow_speed_m_per_s),
            ("serve_speed_m_per_s", self.serve_speed_m_per_s),
            ("kick_threshold_m_per_s", self.kick_threshold_m_per_s),
            ("bounce_threshold_m_per_s", self.bounce_threshold_m_per_s),
        ] {
            ranged(what, v, SPEED_M_PER_S)?;
        }
        for (what, ms) in [
            ("dead_ball_ms", self.dead_ball_ms),
            ("stuck_ms", self.stuck_ms),
            ("possession_ms", self.possession_ms),
            ("goal_pause_ms", self.goal_pause_ms),
            ("serve_pause_ms", self.serve_pause_ms),
        ] {
            // Exact for every duration in range; larger ones only need to stay larger.
            ranged(what, ms as f64, (0.0, DURATION_MS as f64))?;
        }
        let field = &table.field;
        ranged("stuck_radius_m", self.stuck_radius_m, (0.0, field.length_m))?;
        let room = field.wall_height_m - table.ball.diameter_m;
        ranged(
            "serve_drop_height_m",
            self.serve_drop_height_m,
            (0.0, f64::MAX),
        )?;
        if self.serve_drop_height_m >= room {
            return Err(RulesError::Inconsistent(format!(
                "a ball of {} m served {} m above the field would top the {} m walls",
                table.ball.diameter_m, self.serve_drop_height_m, field.wall_height_m
            )));
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_default_rules_fit_both_tables() {
        for table in [Table::standard(), Table::paper()] {
            assert_eq!(RulesConfig::default().validate(&table), Ok(()));
        }
    }

    /// Each bad number is named; NaN and infinities are out of every range.
    #[test]
    fn every_bad_number_is_named() {
        let table = Table::standard();
        let cases: [(RulesConfig, &str); 7] = [
            (
                RulesConfig {
                    serve_speed_m_per_s: -1.797e308,
                    ..RulesConfig::default()
                },
                "serve_speed_m_per_s",
            ),
            (
                RulesConfig {
                    slow_speed_m_per_s: f64::NAN,
                    ..RulesConfig::default()
                },
                "slow_speed_m_per_s",
            ),
            (
                RulesConfig {
                    kick_threshold_m_per_s: f64::INFINITY,
                    ..RulesConfig::default()
                },
                "kick_threshold_m_per_s",
            ),
            (
                RulesConfig {
                    goals_to_win: 0,
                    ..RulesConfig::default()
                },
                "goals_to_win",
            ),
            (
                RulesConfig {
                    goal_pause_ms: u64::MAX,
                    ..RulesConfig::default()
                },
                "goal_pause_ms",
            ),
            (
                RulesConfig {
                    stuck_radius_m: 65.0,
                    ..RulesConfig::default()
                },
                "stuck_radius_m",
            ),
            (
                RulesConfig {
                    serve_drop_height_m: 1.0,
                    ..RulesConfig::default()
                },
                "walls",
            ),
        ];
        for (rules, named) in cases {
            let e = rules.validate(&table).expect_err(named).to_string();
            assert!(e.contains(named), "{named}: {e}");
        }
    }
}

//! The built-in tables, kept as TOML files in `host/game/tables/` (also the reference
//! examples of the file format).

use super::{Table, TableError};

/// `standard`: the usual men per side — goalkeeper 1, defence 2, midfield 5, attack 3 —
/// so 1-2-3-5-5-3-2-1 along the table, rods 150 mm apart, alternating teams as on a real
/// table (from the `Home` goal: own goalkeeper, own defence, opponent attack, own
/// midfield, opponent midfield, own attack, opponent defence, opponent goalkeeper).
/// Men 118 / 208 / 238 mm apart on the 5 / 3 / 2-man rods, axial travel 190 / 356 /
/// 116 / 180 mm (goalkeeper / defence / midfield / attack). Rod `i` is driven by port `i`.
pub const STANDARD_TOML: &str = include_str!("../../tables/standard.toml");

/// `paper`: four characters on every rod (paper §5.1), 150 mm apart, 180 mm of travel;
/// the home team tall-and-thin, the away team short-and-wide.
pub const PAPER_TOML: &str = include_str!("../../tables/paper.toml");

/// Names of the presets, for command lines.
pub const NAMES: [&str; 2] = ["standard", "paper"];

impl Table {
    /// The `standard` table.
    pub fn standard() -> Table {
        // The preset is checked by the tests: it always parses and validates.
        Table::from_toml(STANDARD_TOML).expect("standard preset is valid")
    }

    /// The `paper` table.
    pub fn paper() -> Table {
        Table::from_toml(PAPER_TOML).expect("paper preset is valid")
    }

    /// A preset by name.
    pub fn preset(name: &str) -> Result<Table, TableError> {
        match name {
            "standard" => Table::from_toml(STANDARD_TOML),
            "paper" => Table::from_toml(PAPER_TOML),
            other => Err(TableError::Inconsistent(format!(
                "no preset table named {other:?} (presets: {})",
                NAMES.join(", ")
            ))),
        }
    }
}

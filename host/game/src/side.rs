//! The two teams and which way each attacks.

use serde::{Deserialize, Serialize};

/// One of the two teams, named by the goal it defends.
///
/// Table frame (see [`crate::table`]): `Home` defends the goal at `x = −length/2` and
/// attacks towards `+x`; `Away` defends `x = +length/2` and attacks towards `−x`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize, PartialOrd, Ord)]
#[serde(rename_all = "snake_case")]
pub enum Side {
    /// Defends the goal at `−x`, attacks `+x`.
    Home,
    /// Defends the goal at `+x`, attacks `−x`.
    Away,
}

impl Side {
    /// Both sides, `Home` first (the order of scores: `[home, away]`).
    pub const BOTH: [Side; 2] = [Side::Home, Side::Away];

    /// The other team.
    pub fn other(self) -> Side {
        match self {
            Side::Home => Side::Away,
            Side::Away => Side::Home,
        }
    }

    /// Direction of attack along the table's x axis: `+1.0` for `Home`, `−1.0` for `Away`.
    pub fn attack_dir(self) -> f64 {
        match self {
            Side::Home => 1.0,
            Side::Away => -1.0,
        }
    }

    /// Index into score arrays: `Home` 0, `Away` 1.
    pub fn index(self) -> usize {
        match self {
            Side::Home => 0,
            Side::Away => 1,
        }
    }
}

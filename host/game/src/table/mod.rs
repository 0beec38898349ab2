//! The table as data: field, goals, ball, rods and the characters on them.
//!
//! # Frame and units
//!
//! Metres, kilograms, radians. **Table frame**: origin at the centre of the playing
//! surface, `x` along the table from the `Home` goal (`x = −length/2`) to the `Away`
//! goal (`x = +length/2`), `y` across the table, `z` up (the field surface is `z = 0`).
//! Rods lie along `y` at height [`Field::rod_height_m`]. A rod's pose is its **slide**
//! `s` (m, along `+y`, 0 = centred, limited to `±travel/2`) and its **angle** `θ` (rad,
//! right-handed about `+y`, unbounded, 0 = men hanging feet down): a man whose centre
//! is at `offset` along the rod stands at `y = offset + s`, and its foot sole at
//! `x = x_rod − reach · sin θ`, `z = rod_height − reach · cos θ`.
//!
//! # File format
//!
//! Tables are TOML (human-edited, comments allowed), the same fields as [`Table`]:
//! see [`presets::STANDARD_TOML`] for a complete example. `Table::from_toml` parses
//! and validates; `Table::to_toml` writes one back.

pub mod character;
mod geometry;
pub mod presets;
mod validate;

pub use character::{CharacterParams, CharacterType, ManBox};
pub use validate::TableError;

use crate::side::Side;
use serde::{Deserialize, Serialize};

/// A whole table: what the physics builds and what rules and AI reason about.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Table {
    /// Name shown to players ("standard", "paper", …).
    pub name: String,
    /// The playing field and its walls.
    pub field: Field,
    /// The two goals (one in each end wall, same size).
    pub goal: Goal,
    /// The ball.
    pub ball: Ball,
    /// The teams, `[home, away]`.
    pub teams: [Team; 2],
    /// The rods, in order along `x` (from the `Home` goal).
    pub rods: Vec<Rod>,
}

/// The playing field. Metres.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Field {
    /// Length along `x`, goal line to goal line, m (≈ 1.20).
    pub length_m: f64,
    /// Width along `y`, side wall to side wall, m (≈ 0.70).
    pub width_m: f64,
    /// Height of the walls above the field, m.
    pub wall_height_m: f64,
    /// Height of the rod axes above the field, m.
    pub rod_height_m: f64,
    /// Size of the corner ramps, m: in each of the four corners a ramp rises from the
    /// field along both walls over this distance, so a ball cannot come to rest in a
    /// corner. Sized to the corners beside the goals that no man reaches (the standard
    /// table's 240 mm: see `tables/standard.toml`).
    pub corner_ramp_m: f64,
    /// Height of the corner ramps at the walls, m.
    pub corner_ramp_height_m: f64,
}

/// A goal: an opening in the end wall, centred on `y = 0`. Metres.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Goal {
    /// Width of the mouth along `y`, m.
    pub width_m: f64,
    /// Height of the mouth above the field, m.
    pub height_m: f64,
    /// Depth of the goal box behind the goal line, m.
    pub depth_m: f64,
}

/// The ball. The physics parameters are tuned for play, not reality (paper §5).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Ball {
    /// Diameter, m (≈ 0.035).
    pub diameter_m: f64,
    /// Mass, kg (≈ 0.027).
    pub mass_kg: f64,
    /// Coefficient of restitution against men and walls, 0…1 (deliberately high).
    pub restitution: f64,
    /// Coulomb friction coefficient against the cloth and the men.
    pub friction: f64,
    /// Rolling resistance on the cloth, as a length (m): the lever of the resisting
    /// moment, `M = rolling_resistance_m · N`.
    pub rolling_resistance_m: f64,
}

impl Ball {
    /// Radius, m.
    pub fn radius_m(&self) -> f64 {
        0.5 * self.diameter_m
    }
}

/// A team: its side and its character type.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Team {
    /// Which goal it defends.
    pub side: Side,
    /// The character type of all its men.
    pub character: CharacterType,
    /// Parameters overriding the type's defaults ([`CharacterType::params`]), if any.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub params: Option<CharacterParams>,
}

impl Team {
    /// The physical parameters of this team's men.
    pub fn character_params(&self) -> CharacterParams {
        self.params.unwrap_or_else(|| self.character.params())
    }
}

/// What a rod is for (its place in the team). Decides the AI's behaviour.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Role {
    /// The rod in front of the own goal.
    Goalkeeper,
    /// The 2-man rod.
    Defence,
    /// The 5-man rod.
    Midfield,
    /// The 3-man rod.
    Attack,
}

/// A rod with its men.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Rod {
    /// The team that plays it. Its handles stick out of the table on that team's
    /// side: `Home` at `−y`, `Away` at `+y` (see [`Rod::handle_sign`]).
    pub team: Side,
    /// Its place in the team.
    pub role: Role,
    /// Position of the rod axis along the table, m.
    pub x_m: f64,
    /// Number of men on it.
    pub men: usize,
    /// Distance between neighbouring men (centre to centre), m; ignored for one man.
    pub spacing_m: f64,
    /// Axial travel, m: the slide ranges over `±travel_m / 2` from centred.
    pub travel_m: f64,
    /// The board port (paddle, 0…7) that drives it.
    pub port: usize,
}

impl Rod {
    /// Offsets of the men's centres along the rod at slide 0, m, symmetric about `y = 0`.
    pub fn man_offsets(&self) -> Vec<f64> {
        let mid = (self.men as f64 - 1.0) * 0.5;
        (0..self.men)
            .map(|i| (i as f64 - mid) * self.spacing_m)
            .collect()
    }

    /// Positions of the men's centres along `y` at slide `slide_m`, m.
    pub fn man_positions(&self, slide_m: f64) -> Vec<f64> {
        self.man_offsets()
            .into_iter()
            .map(|o| o + slide_m)
            .collect()
    }

    /// Half the axial travel, m: the slide's limit either way.
    pub fn half_travel_m(&self) -> f64 {
        0.5 * self.travel_m
    }

    /// Sign from the player's paddle frame to the table frame for this rod: `+1` for
    /// `Home` (handles at `−y`: pushing the handle away from the player moves the men
    /// towards `+y`), `−1` for `Away` (handles at `+y`). The same sign applies to the
    /// angle (the rod axis as the player sees it points away from them).
    pub fn handle_sign(&self) -> f64 {
        match self.team {
            Side::Home => 1.0,
            Side::Away => -1.0,
        }
    }
}

impl Table {
    /// Parses a table from TOML and validates it.
    pub fn from_toml(text: &str) -> Result<Self, TableError> {
        let table: Table = toml::from_str(text).map_err(|e| TableError::Parse(e.to_string()))?;
        table.validate()?;
        Ok(table)
    }

    /// Loads a table file (TOML) and validates it.
    pub fn load(path: &std::path::Path) -> Result<Self, TableError> {
        let text = std::fs::read_to_string(path).map_err(|e| TableError::Io {
            path: path.display().to_string(),
            message: e.to_string(),
        })?;
        Self::from_toml(&text)
    }

    /// The table as TOML.
    pub fn to_toml(&self) -> String {
        // Every field is a plain number, string or enum: serialisation cannot fail.
        toml::to_string_pretty(self).unwrap_or_default()
    }

    /// The team playing `side`.
    pub fn team(&self, side: Side) -> &Team {
        &self.teams[side.index()]
    }

    /// Character parameters of the men on rod `rod`.
    pub fn character_of(&self, rod: usize) -> CharacterParams {
        self.team(self.rods[rod].team).character_params()
    }

    /// Indices of the rods played by `side`, in order along `x`.
    pub fn rods_of(&self, side: Side) -> impl Iterator<Item = usize> + '_ {
        self.rods
            .iter()
            .enumerate()
            .filter(move |(_, r)| r.team == side)
            .map(|(i, _)| i)
    }

    /// `x` of the goal line that `side` defends, m.
    pub fn goal_line_x(&self, side: Side) -> f64 {
        -side.attack_dir() * 0.5 * self.field.length_m
    }
}

//! The Space Foosball game: the table as data, calibrated board input, match rules, a
//! computer opponent and match recordings (paper §5, §5.1).
//!
//! Every module here is free of the physics and of threads, so each is tested alone and
//! plugs into the 1 kHz match loop when the physics world of the table lands:
//!
//! * [`table`]: field, goals, ball, rods, characters (TOML, presets `standard`, `paper`).
//! * [`input`]: raw counts → rod slide/angle ([`input::calibration`]), and any
//!   [`board_link::Board`] → the newest rod poses per step ([`input::paddles`]).
//! * [`rules`]: serve, goal, dead ball, match over — a state machine over ball states.
//! * [`ai`]: the computer opponent: ball state → target rod poses.
//! * [`recording`]: a match's input stream, saved and loaded for replay.
#![deny(missing_docs)]

pub mod ai;
pub mod atomic_file;
pub mod input;
pub mod recording;
pub mod rules;
pub mod side;
pub mod table;

pub use side::Side;
pub use table::Table;

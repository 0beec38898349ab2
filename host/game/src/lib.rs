//! The Space Foosball game: the table as data, calibrated board input, match rules, a
//! computer opponent, the table as a physics world and the match (paper §5, §5.1).
//!
//! "The paper" and its section numbers (§5, §5.1, §6) refer to Bang, Heo, Kim and Kim, "Space
//! Foosball: Coupling Tangible Interfaces with a Real-time Game Physics Engine"; what the
//! project takes from it, section by section, is in docs/paper.md in the repository.
//!
//! * [`table`]: field, goals, ball, rods, characters (TOML, presets `standard`, `paper`).
//! * [`input`]: raw counts → rod slide/angle ([`input::calibration`]), and any
//!   [`board_link::Board`] → the newest rod poses per step ([`input::paddles`]).
//! * [`rules`]: serve, goal, dead ball, match over — a state machine over ball states.
//! * [`ai`]: the computer opponent: ball state → target rod poses.
//! * [`arena`]: the table as a Virtual Physics world stepped at 1 kHz (rods driven,
//!   ball, contacts for the rules).
//! * [`play`]: the match (arena + rules + computer + recording, deterministic, replay),
//!   its 1 kHz thread, kicks → haptics.
//! * [`recording`]: a match's input stream, saved and loaded for replay.
//!
//! Everything but [`play::PhysicsThread`] is free of threads and clocks, so each part is
//! tested alone and a match replays bit for bit.
#![deny(missing_docs)]

pub mod ai;
pub mod arena;
pub mod atomic_file;
pub mod input;
pub mod play;
pub mod recording;
pub mod rules;
pub mod side;
pub mod table;

pub use side::Side;
pub use table::Table;

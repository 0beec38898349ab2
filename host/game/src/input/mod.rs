//! Board input: raw paddle counts → calibrated rod poses, every millisecond.
//!
//! * [`calibration`]: the per-paddle linear map (2 × 2 with cross-talk, plus offset),
//!   its least-squares fit, defaults, and the calibration file.
//! * [`guided`]: the guided motion a player (or the emulated board) performs to
//!   calibrate, and the collector that pairs its known poses with the measured counts.
//! * [`paddles`]: any [`board_link::Board`] → the newest pose and velocity of every
//!   rod, with lost boards, sequence gaps and absent sensors handled.
//! * [`tracker`]: rod motion on the board's clock, from version 2 reports' device time
//!   and packet ages: packets placed at their board time, velocity rebuilt from them.
//!
//! **Paddle frame**: what the player does with a handle — slide (m, positive pushing
//! the handle away from the player) and angle (rad, right-handed about the rod axis
//! pointing away from the player). Calibration works in this frame;
//! [`paddles`] turns it into the table frame with [`crate::table::Rod::handle_sign`].

pub mod calibration;
pub mod guided;
pub mod paddles;
pub mod tracker;

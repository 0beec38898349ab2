//! The emulated Space Foosball sensor board.
//!
//! Nobody should need the cabinet to play or to test: this crate emulates the whole
//! sensor board — eight rods, their optical sensors, the PS/2 mice at the level of the
//! wire — and runs the firmware's own library (`sensor-board`) on it, so the host
//! sees exactly the reports a real board would send.
//!
//! * [`sensor_model`]: rod motion → mouse counts (resolution, gain error, cross-talk,
//!   noise, tracking-speed limit, sub-count remainders).
//! * [`motion`]: where the rods are — scripts, live input, recordings.
//! * [`ps2_device`]: the emulated mouse ([`ps2_device::mouse`]) and the bit-level
//!   wire with the emulated PIO ([`ps2_device::wire`]).
//! * [`faults`]: misbehaviour to inject (parity errors, dropped bytes, silence,
//!   unplug/replug, spontaneous restarts).
//! * [`board`]: eight ports + the firmware library in emulated time → IN reports.
//! * [`in_process`]: the board as a [`board_link::Board`] (lockstep or real time).
//! * [`serve`]: the board as a process serving reports over a Unix socket
//!   ([`board_link::socket_wire`]).
//! * [`interactive`]: a person plays the board from the keyboard (`sim serve
//!   --interactive`).
//! * [`usbip`]: the board as a USB device over USB/IP.
//! * [`bench`](mod@bench): how fast the emulation runs.
#![deny(missing_docs)]

pub mod bench;
pub mod board;
pub mod error;
pub mod faults;
pub mod in_process;
pub mod interactive;
pub mod motion;
pub mod pacing;
pub mod ps2_device;
pub mod rng;
pub mod sensor_model;
pub mod serve;
pub mod usb_device;
pub mod usbip;

pub use board::{BoardConfig, EmulatedBoard, HapticEvent, PortStats};
pub use error::SimError;
pub use faults::Fault;
pub use in_process::{InProcessBoard, Pacing};
pub use motion::{MotionSource, RodPose};

//! Platform-free logic of the Space Foosball sensor board.
//!
//! `no_std`, no allocation, no panics on any input. The board watches eight rods, each
//! with an optical PS/2 mouse sensor; this crate holds everything between the PS/2 wire
//! and the USB IN report, so the RP2040 binary (PIO does the wire timing) and the
//! emulated board (an emulated wire does) share one tested implementation:
//!
//! * [`ps2`]: device-to-host frames ([`Ps2Frame`]) and host-to-device commands
//!   ([`HostFrame`], the request-to-send sequence as data).
//! * [`mouse`]: one PS/2 mouse per port: the [`MouseDriver`] state machine (reset,
//!   configure, stream, probe, hot-plug, absent) and 3-byte [`MousePacket`]s.
//! * [`paddle`]: per-paddle saturating accumulators and the per-port [`AxisMap`].
//! * [`board`]: eight ports → one [`foosball_protocol::InReport`] per millisecond.
//! * [`store`]: a record store in NOR flash that survives power cuts (the settings),
//!   and [`save_schedule`]: when changed settings are written, as fast as the flash lasts.
//! * the Feature reports' view of the board: [`SensorBoard::settings`],
//!   [`SensorBoard::apply_settings`], [`SensorBoard::port_diagnostics`].
//!
//! Time is `u64` microseconds since boot everywhere (`*_us`).
#![no_std]
#![deny(missing_docs)]

pub mod board;
pub mod mouse;
pub mod paddle;
pub mod ps2;
pub mod save_schedule;
mod settings;
pub mod store;

pub use board::{BoardConfig, SensorBoard};
pub use mouse::{
    DriverEvents, DriverState, DriverStats, LineFault, MouseConfig, MouseDriver, MousePacket,
    Resolution,
};
pub use paddle::{AxisMap, MouseAxis, PaddleAccumulator};
pub use ps2::{
    FrameError, HostFrame, Ps2Frame, RequestToSendStep, SendError, REQUEST_TO_SEND,
    REQUEST_TO_SEND_CLOCK_LOW_US,
};

/// Number of PS/2 ports on the board (one per paddle).
pub const PORTS: usize = foosball_protocol::PADDLES;

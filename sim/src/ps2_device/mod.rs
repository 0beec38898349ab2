//! The emulated PS/2 mouse and the wire between it and the emulated PIO.
//!
//! * [`mouse`]: the device at byte level — commands, replies, self-test, stream
//!   packets from its optical sensor.
//! * [`wire`]: the clock and data lines at bit level — device frames sampled on falling
//!   clock edges by the emulated PIO, the host's request-to-send, the device's ACK, and
//!   the injected faults that act on bits and bytes.

pub mod mouse;
pub mod wire;

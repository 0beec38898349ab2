//! One PS/2 mouse per port: configuration, stream packets and the driver state machine.

pub mod command;
pub mod config;
pub mod driver;
pub mod events;
pub mod packet;

pub use config::{
    MouseConfig, Resolution, ABSENT_RETRY_INTERVAL_US, INTER_BYTE_TIMEOUT_US, SEND_ATTEMPTS,
};
pub use driver::{DriverState, MouseDriver, MAX_INIT_ATTEMPTS, MAX_RESENDS};
pub use events::{DriverEvents, DriverStats, LineFault};
pub use packet::MousePacket;

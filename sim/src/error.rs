//! Errors of the emulated board's library API.

use crate::motion::recording::RecordingError;
use crate::motion::script::ScriptError;
use foosball_protocol::DecodeError;

/// Why an emulator operation failed.
#[derive(Debug, thiserror::Error)]
pub enum SimError {
    /// A configuration value is out of range; the message names it.
    #[error("invalid emulator configuration: {0}")]
    InvalidConfig(String),
    /// A port index outside 0–7.
    #[error("port {0} does not exist (ports are 0–7)")]
    NoSuchPort(usize),
    /// A fault's parameters are invalid.
    #[error("invalid fault for port {port}: {reason}")]
    InvalidFault {
        /// The port.
        port: usize,
        /// What is wrong.
        reason: String,
    },
    /// An OUT report from the host was rejected (wrong length, version, LED value).
    #[error("malformed OUT report rejected: {0}")]
    MalformedOutReport(#[from] DecodeError),
    /// A motion script could not be loaded.
    #[error(transparent)]
    Script(#[from] ScriptError),
    /// A recording could not be loaded or saved.
    #[error(transparent)]
    Recording(#[from] RecordingError),
}

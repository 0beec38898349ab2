//! The emulated board's Feature reports ([`foosball_protocol::FeatureReport`]), answered
//! as the RP2040 firmware answers them: GET_REPORT (Feature) returns the kind the last
//! `Select` chose (after a reset: device info); SET_REPORT (Feature) takes a `Select`,
//! new `Settings` or `EnterBootloader`, anything else is refused (STALL).

use foosball_protocol::{
    BoardSettings, DeviceInfo, FeatureKind, FeatureReport, ResetReason, GIT_HASH_LEN,
};
use sensor_board::SensorBoard;

/// What the emulated board writes as its git hash: it has no firmware commit.
const GIT_HASH: &[u8] = b"emulated";

/// A Feature report the host wrote that the board must act on.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum FeatureCommand {
    /// Apply these settings to the sensor board.
    Settings(BoardSettings),
    /// Restart into the bootloader: the device leaves the bus.
    EnterBootloader,
}

/// The Feature report selection: a readable kind and, for port diagnostics, the port.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct FeatureSelection {
    kind: FeatureKind,
    port: u8,
}

impl Default for FeatureSelection {
    fn default() -> Self {
        Self {
            kind: FeatureKind::DeviceInfo,
            port: 0,
        }
    }
}

impl FeatureSelection {
    /// The selected report of `board`, `uptime_us` µs after its power-up.
    pub(crate) fn report(&self, board: &SensorBoard, uptime_us: u64) -> FeatureReport {
        match self.kind {
            // A Select names a port in 0..8 (decoding checked it).
            FeatureKind::PortDiagnostics => FeatureReport::PortDiagnostics(
                board.port_diagnostics(self.port).unwrap_or_default(),
            ),
            FeatureKind::Settings => FeatureReport::Settings(board.settings()),
            _ => FeatureReport::DeviceInfo(device_info(board, uptime_us)),
        }
    }

    /// Takes a report the host wrote: `Err(())` to refuse it (STALL), else what the
    /// board must do, if anything (a `Select` only changes the selection).
    pub(crate) fn set(&mut self, bytes: &[u8]) -> Result<Option<FeatureCommand>, ()> {
        match FeatureReport::decode_command(bytes) {
            Ok(FeatureReport::Select { kind, port }) => {
                *self = Self { kind, port };
                Ok(None)
            }
            Ok(FeatureReport::Settings(settings)) => Ok(Some(FeatureCommand::Settings(settings))),
            Ok(FeatureReport::EnterBootloader) => Ok(Some(FeatureCommand::EnterBootloader)),
            // `decode_command` refuses the kinds only the board sends.
            Ok(FeatureReport::DeviceInfo(_) | FeatureReport::PortDiagnostics(_)) | Err(_) => {
                Err(())
            }
        }
    }
}

/// The sim crate's version as the firmware version (each part saturating at 255).
fn firmware_version() -> [u8; 3] {
    let part = |s: &str| s.parse::<u16>().map_or(0, |v| v.min(255) as u8);
    [
        part(env!("CARGO_PKG_VERSION_MAJOR")),
        part(env!("CARGO_PKG_VERSION_MINOR")),
        part(env!("CARGO_PKG_VERSION_PATCH")),
    ]
}

fn device_info(board: &SensorBoard, uptime_us: u64) -> DeviceInfo {
    // Unknown bytes are `?`, as the firmware writes them.
    let mut git_hash = [b'?'; GIT_HASH_LEN];
    for (out, byte) in git_hash.iter_mut().zip(GIT_HASH) {
        *out = *byte;
    }
    DeviceInfo {
        firmware_version: firmware_version(),
        git_hash,
        reset_reason: ResetReason::PowerOn,
        uptime_us,
        present_ports: board.present_mask(),
    }
}

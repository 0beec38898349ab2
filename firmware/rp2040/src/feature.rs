//! Feature reports on the control pipe ([`foosball_protocol::FeatureReport`]): the
//! board's diagnostics, its settings, and the restart into the USB bootloader.
//!
//! GET_REPORT (Feature) returns the kind the last `Select` chose (after a reset:
//! [`DeviceInfo`]). SET_REPORT (Feature) takes a `Select`, new `Settings` (applied to
//! the sensor board at once and handed to [`crate::config_store`] to keep), or
//! `EnterBootloader` (accepted, then [`bootloader_task`] restarts the chip into the
//! ROM's USB boot mode once the control transfer has finished). Anything else, or a
//! malformed report, is rejected (STALL) and logged.

use embassy_sync::blocking_mutex::raw::CriticalSectionRawMutex;
use embassy_sync::signal::Signal;
use embassy_time::{Duration, Timer};
use foosball_protocol::{
    DeviceInfo, FeatureKind, FeatureReport, ResetReason, GIT_HASH_LEN, PADDLES,
};
use sensor_board::SensorBoard;

use crate::{config_store, haptics, sensor_loop};

/// The firmware's git commit, from `build.rs`.
const GIT_HASH: &str = env!("FOOSBALL_GIT_HASH");

/// The answers to GET_REPORT and SET_REPORT (Feature).
pub struct FeatureHandler {
    /// What GET_REPORT returns: a readable kind and, for port diagnostics, the port.
    selected: (FeatureKind, u8),
    /// Why this run started.
    reset_reason: ResetReason,
}

impl FeatureHandler {
    /// A handler reporting `reset_reason`, device info selected.
    pub const fn new(reset_reason: ResetReason) -> Self {
        Self {
            selected: (FeatureKind::DeviceInfo, 0),
            reset_reason,
        }
    }

    /// Writes the selected report into `buf`; `None` if it does not fit.
    pub fn get(&self, buf: &mut [u8]) -> Option<usize> {
        let (kind, port) = self.selected;
        let report = sensor_loop::with_board(|board| match kind {
            // A Select names a port in 0..8 (decoding checked it).
            FeatureKind::PortDiagnostics => {
                FeatureReport::PortDiagnostics(board.port_diagnostics(port).unwrap_or_default())
            }
            FeatureKind::Settings => FeatureReport::Settings(board.settings()),
            _ => FeatureReport::DeviceInfo(self.device_info(board)),
        });
        report.encode(buf).ok()
    }

    /// Takes a report the host wrote; returns whether it was accepted.
    pub fn set(&mut self, bytes: &[u8]) -> bool {
        match FeatureReport::decode_command(bytes) {
            Ok(FeatureReport::Select { kind, port }) => {
                self.selected = (kind, port);
                true
            }
            Ok(FeatureReport::Settings(settings)) => {
                sensor_loop::with_board(|board| board.apply_settings(&settings));
                config_store::save(settings);
                defmt::info!("settings changed by the host");
                true
            }
            Ok(FeatureReport::EnterBootloader) => {
                BOOTLOADER.signal(());
                true
            }
            // `decode_command` refuses the kinds only the board sends.
            Ok(FeatureReport::DeviceInfo(_) | FeatureReport::PortDiagnostics(_)) => false,
            Err(err) => {
                defmt::warn!("ignoring malformed Feature report: {}", err);
                false
            }
        }
    }

    fn device_info(&self, board: &SensorBoard) -> DeviceInfo {
        let mut git_hash = [b'?'; GIT_HASH_LEN];
        for (out, byte) in git_hash.iter_mut().zip(GIT_HASH.bytes()) {
            *out = byte;
        }
        DeviceInfo {
            firmware_version: crate::version::FIRMWARE_VERSION,
            git_hash,
            reset_reason: self.reset_reason,
            uptime_us: sensor_loop::now_us(),
            present_ports: board.present_mask(),
        }
    }
}

/// Set when the host asked for the bootloader.
static BOOTLOADER: Signal<CriticalSectionRawMutex, ()> = Signal::new();

/// Time for the SET_REPORT's status stage to reach the host before the restart.
const BOOTLOADER_DELAY: Duration = Duration::from_millis(20);

/// Longest wait for settings not yet in flash to be written before the restart (a
/// sector erase takes at most 400 ms).
const FLUSH_TIMEOUT: Duration = Duration::from_millis(1_000);

/// Waits for `EnterBootloader`, stops the motors, writes settings not yet in flash,
/// then restarts the chip into the ROM's USB bootloader (the `RPI-RP2` drive and
/// PICOBOOT; no activity LED).
#[embassy_executor::task]
pub async fn bootloader_task() -> ! {
    BOOTLOADER.wait().await;
    defmt::warn!("restarting into the USB bootloader (host request)");
    haptics::PULSES.signal([foosball_protocol::HapticPulse::default(); PADDLES]);
    config_store::flush(FLUSH_TIMEOUT).await;
    Timer::after(BOOTLOADER_DELAY).await;
    embassy_rp::rom_data::reset_to_usb_boot(0, 0);
    // The ROM does not return; should it ever, the watchdog restarts the firmware.
    #[allow(clippy::empty_loop)]
    loop {}
}

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
    BoardSettings, DeviceInfo, FeatureKind, FeatureReport, PortCounters, PortDiagnostics,
    PortSettings, ResetReason, GIT_HASH_LEN, PADDLES,
};
use sensor_board::{AxisMap, MouseAxis, MouseConfig, Resolution, SensorBoard};

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
            FeatureKind::PortDiagnostics => {
                FeatureReport::PortDiagnostics(port_diagnostics(board, port))
            }
            FeatureKind::Settings => FeatureReport::Settings(settings_of(board)),
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
                sensor_loop::with_board(|board| apply_settings(board, &settings));
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
            firmware_version: crate::usb_hid::FIRMWARE_VERSION,
            git_hash,
            reset_reason: self.reset_reason,
            uptime_us: sensor_loop::now_us(),
            present_ports: board.present_mask(),
        }
    }
}

/// One port's state and counters.
fn port_diagnostics(board: &SensorBoard, port: u8) -> PortDiagnostics {
    let Some(driver) = board.driver(usize::from(port)) else {
        return PortDiagnostics {
            port,
            ..PortDiagnostics::default()
        };
    };
    let s = driver.stats();
    PortDiagnostics {
        port,
        present: driver.is_present(),
        device_id: driver.device_id(),
        counters: PortCounters {
            frames: s.frames,
            packets: s.packets,
            framing_errors: s.framing_errors,
            parity_errors: s.parity_errors,
            resends: s.resends,
            dropped: s.dropped,
            retries: s.retries,
            absences: s.absences,
            inits: s.inits,
            restarts: s.restarts,
            fifo_stalls: s.fifo_stalls,
            line_faults: s.line_faults,
        },
    }
}

/// The board's current settings, port by port.
pub fn settings_of(board: &SensorBoard) -> BoardSettings {
    let mut settings = BoardSettings::DEFAULT;
    for (index, port) in settings.ports.iter_mut().enumerate() {
        let (Some(driver), Some(map)) = (board.driver(index), board.config().axis_maps.get(index))
        else {
            continue;
        };
        let mouse = driver.config();
        *port = PortSettings {
            axial_is_y: map.axial == MouseAxis::Y,
            invert_axial: map.invert_axial,
            invert_rotation: map.invert_rotation,
            resolution_code: mouse.resolution.code(),
            sample_rate: mouse.sample_rate,
        };
    }
    settings
}

/// Applies `settings` to every port (axis maps at once, mouse settings as the
/// driver can send them).
pub fn apply_settings(board: &mut SensorBoard, settings: &BoardSettings) {
    for (index, port) in settings.ports.iter().enumerate().take(PADDLES) {
        let Some(driver) = board.driver(index) else {
            continue;
        };
        let mouse = MouseConfig {
            sample_rate: port.sample_rate,
            // Decoding checked the code (0..=3); the default stands in otherwise.
            resolution: Resolution::from_code(port.resolution_code).unwrap_or_default(),
            ..*driver.config()
        };
        let map = AxisMap {
            axial: if port.axial_is_y {
                MouseAxis::Y
            } else {
                MouseAxis::X
            },
            invert_axial: port.invert_axial,
            invert_rotation: port.invert_rotation,
        };
        board.set_port(index, mouse, map);
    }
}

/// Set when the host asked for the bootloader.
static BOOTLOADER: Signal<CriticalSectionRawMutex, ()> = Signal::new();

/// Time for the SET_REPORT's status stage to reach the host before the restart.
const BOOTLOADER_DELAY: Duration = Duration::from_millis(20);

/// Waits for `EnterBootloader`, stops the motors, then restarts the chip into the
/// ROM's USB bootloader (the `RPI-RP2` drive and PICOBOOT; no activity LED).
#[embassy_executor::task]
pub async fn bootloader_task() -> ! {
    BOOTLOADER.wait().await;
    defmt::warn!("restarting into the USB bootloader (host request)");
    haptics::PULSES.signal([foosball_protocol::HapticPulse::default(); PADDLES]);
    Timer::after(BOOTLOADER_DELAY).await;
    embassy_rp::rom_data::reset_to_usb_boot(0, 0);
    // The ROM does not return; should it ever, the watchdog restarts the firmware.
    #[allow(clippy::empty_loop)]
    loop {}
}

//! The board as the Feature reports show it: its settings
//! ([`foosball_protocol::BoardSettings`]) and each port's diagnostics
//! ([`foosball_protocol::PortDiagnostics`]), read from and applied to a
//! [`SensorBoard`], so the firmware and the emulated board answer alike.

use foosball_protocol::{BoardSettings, PortCounters, PortDiagnostics, PortSettings};

use crate::mouse::{MouseConfig, Resolution};
use crate::paddle::{AxisMap, MouseAxis};
use crate::SensorBoard;

impl SensorBoard {
    /// Every port's settings: its axis map and its mouse's resolution and sample
    /// rate.
    pub fn settings(&self) -> BoardSettings {
        let mut settings = BoardSettings::DEFAULT;
        for (index, port) in settings.ports.iter_mut().enumerate() {
            let (Some(driver), Some(map)) =
                (self.driver(index), self.config().axis_maps.get(index))
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

    /// Applies `settings` to every port with [`set_port`](Self::set_port) (the
    /// timeouts of each port's mouse configuration stay). A resolution code out of
    /// range (a decoded report has none) keeps the port's resolution.
    pub fn apply_settings(&mut self, settings: &BoardSettings) {
        for (index, port) in settings.ports.iter().enumerate() {
            let Some(current) = self.driver(index).map(|driver| *driver.config()) else {
                continue;
            };
            let mouse = MouseConfig {
                sample_rate: port.sample_rate,
                resolution: Resolution::from_code(port.resolution_code)
                    .unwrap_or(current.resolution),
                ..current
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
            self.set_port(index, mouse, map);
        }
    }

    /// Port `port`'s state and counters, `None` outside `0..8`.
    pub fn port_diagnostics(&self, port: u8) -> Option<PortDiagnostics> {
        let driver = self.driver(usize::from(port))?;
        let s = driver.stats();
        Some(PortDiagnostics {
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
        })
    }
}

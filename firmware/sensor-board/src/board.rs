//! The whole board: eight mouse ports → one IN report per millisecond.

use foosball_protocol::{
    InReport, InReportV2, PacketAge, PaddleMotion, PaddleStatus, PaddleTiming, ReportTiming,
};

use crate::mouse::{LineFault, MouseConfig, MouseDriver};
use crate::paddle::{AxisMap, PaddleAccumulator};
use crate::ps2::{Ps2Frame, SendError};
use crate::PORTS;

/// Configuration of the board.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct BoardConfig {
    /// Mouse configuration, shared by all ports.
    pub mouse: MouseConfig,
    /// How each port's sensor is mounted, indexed by port (0..8).
    pub axis_maps: [AxisMap; PORTS],
}

impl BoardConfig {
    /// Default mouse configuration, every axis map [`AxisMap::IDENTITY`].
    pub const DEFAULT: Self = Self {
        mouse: MouseConfig::DEFAULT,
        axis_maps: [AxisMap::IDENTITY; PORTS],
    };
}

/// Eight ports: a [`MouseDriver`] and a [`PaddleAccumulator`] each, and the report
/// sequence number.
///
/// Every method taking a `port` ignores ports outside `0..8` (no panic).
#[derive(Debug, Clone)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct SensorBoard {
    config: BoardConfig,
    drivers: [MouseDriver; PORTS],
    accumulators: [PaddleAccumulator; PORTS],
    /// When each port's newest packet arrived, microseconds (`None`: none yet).
    last_packet_us: [Option<u64>; PORTS],
    /// Sequence number of the next report.
    sequence: u16,
}

impl SensorBoard {
    /// A board whose drivers reset their mice on the first [`poll`](Self::poll).
    pub const fn new(config: BoardConfig) -> Self {
        Self {
            drivers: [const { MouseDriver::new(MouseConfig::DEFAULT) }; PORTS],
            accumulators: [PaddleAccumulator::new(); PORTS],
            last_packet_us: [None; PORTS],
            sequence: 0,
            config,
        }
        .with_mouse_config()
    }

    /// Applies `config.mouse` to every driver (const-friendly).
    const fn with_mouse_config(mut self) -> Self {
        let mut port = 0;
        while port < PORTS {
            self.drivers[port] = MouseDriver::new(self.config.mouse);
            port += 1;
        }
        self
    }

    /// A frame arrived on `port` at `now_us`; motion goes into the port's accumulator.
    pub fn on_frame(&mut self, port: usize, now_us: u64, frame: Ps2Frame) {
        let (Some(driver), Some(accumulator), Some(map)) = (
            self.drivers.get_mut(port),
            self.accumulators.get_mut(port),
            self.config.axis_maps.get(port),
        ) else {
            return;
        };
        if let Some(packet) = driver.on_frame(now_us, frame) {
            accumulator.add_packet(&packet, map);
            if let Some(last) = self.last_packet_us.get_mut(port) {
                *last = Some(now_us);
            }
        }
    }

    /// A line of `port` was found stuck low (see [`MouseDriver::on_line_fault`]).
    pub fn on_line_fault(&mut self, port: usize, now_us: u64, fault: LineFault) {
        if let Some(driver) = self.drivers.get_mut(port) {
            driver.on_line_fault(now_us, fault);
        }
    }

    /// The receiver of `port` overflowed and was restarted at `now_us` (see
    /// [`MouseDriver::on_rx_stall`]).
    pub fn on_rx_stall(&mut self, port: usize, now_us: u64) {
        if let Some(driver) = self.drivers.get_mut(port) {
            driver.on_rx_stall(now_us);
        }
    }

    /// Call for every port at least every millisecond: runs the port's timeouts and
    /// returns the command byte to send to its mouse, if any (then report the outcome
    /// with [`on_command_sent`](Self::on_command_sent)).
    pub fn poll(&mut self, port: usize, now_us: u64) -> Option<u8> {
        self.drivers.get_mut(port)?.poll(now_us)
    }

    /// The outcome of sending the byte [`poll`](Self::poll) returned for `port`.
    pub fn on_command_sent(&mut self, port: usize, now_us: u64, result: Result<(), SendError>) {
        if let Some(driver) = self.drivers.get_mut(port) {
            driver.on_command_sent(now_us, result);
        }
    }

    /// Drains all eight accumulators into the next IN report and advances the
    /// sequence number (wrapping; the first report is number 0): a
    /// [`snapshot_report`](Self::snapshot_report) immediately
    /// [`commit`](Self::commit)ted, for a transport that cannot fail to send.
    pub fn take_report(&mut self, now_us: u64) -> InReport {
        let report = self.snapshot_report(now_us);
        self.commit(&report);
        report
    }

    /// The next IN report, without draining anything: the motion accumulated since
    /// the last [`commit`](Self::commit) and the sequence number it will carry. Each
    /// paddle's status has [`PaddleStatus::PRESENT`] if its mouse is streaming now,
    /// plus the flags seen since the last commit. Calling it again later gives a
    /// newer report with the same sequence number (a report refreshed before it was
    /// sent). `now_us` is not needed today (timeouts run in [`poll`](Self::poll)).
    pub fn snapshot_report(&mut self, now_us: u64) -> InReport {
        let _ = now_us;
        let mut paddles = [PaddleMotion::default(); PORTS];
        for ((paddle, driver), accumulator) in paddles
            .iter_mut()
            .zip(self.drivers.iter_mut())
            .zip(self.accumulators.iter_mut())
        {
            // The driver's events move into the accumulator's sticky flags, where
            // they stay until a report that carries them is committed.
            let events = driver.take_events();
            let mut flags = PaddleStatus::empty();
            if events.framing_error {
                flags |= PaddleStatus::FRAMING_ERROR;
            }
            if events.parity_error {
                flags |= PaddleStatus::PARITY_ERROR;
            }
            if events.reinitialised {
                flags |= PaddleStatus::REINITIALISED;
            }
            accumulator.flag(flags);
            *paddle = accumulator.peek();
            if driver.is_present() {
                paddle.status |= PaddleStatus::PRESENT;
            }
        }
        InReport {
            sequence: self.sequence,
            paddles,
        }
    }

    /// [`snapshot_report`](Self::snapshot_report) as a version 2 report: the same
    /// motion plus the device time of the snapshot (`now_us`, wrapping to `u32`) and,
    /// per paddle, the age of its newest packet and the packets its driver dropped
    /// (wrapping to `u8`). Commit it with `commit(&report.report)`.
    pub fn snapshot_report_v2(&mut self, now_us: u64) -> InReportV2 {
        let report = self.snapshot_report(now_us);
        let mut paddles = [PaddleTiming::default(); PORTS];
        for ((timing, driver), last) in paddles
            .iter_mut()
            .zip(self.drivers.iter())
            .zip(self.last_packet_us.iter())
        {
            *timing = PaddleTiming {
                newest_packet_age: last.map_or(PacketAge::NONE, |at| {
                    PacketAge::from_micros(now_us.saturating_sub(at))
                }),
                dropped: driver.stats().dropped as u8,
            };
        }
        InReportV2 {
            report,
            timing: ReportTiming {
                device_time_us: now_us as u32,
                paddles,
            },
        }
    }

    /// The host has received `sent` (a [`snapshot_report`](Self::snapshot_report)):
    /// its motion and flags are removed from the accumulators, so motion that
    /// arrived after the snapshot stays for the next report, and the sequence number
    /// advances (wrapping). A report that was never sent is simply not committed and
    /// nothing is lost.
    pub fn commit(&mut self, sent: &InReport) {
        for (accumulator, paddle) in self.accumulators.iter_mut().zip(sent.paddles.iter()) {
            accumulator.remove(paddle);
        }
        self.sequence = sent.sequence.wrapping_add(1);
    }

    /// Changes how `port` is mounted and run: its axis map applies to the next
    /// packet, its mouse configuration as [`MouseDriver::set_config`] says (a
    /// streaming mouse is sent the new sample rate and resolution). Ports outside
    /// `0..8` are ignored.
    pub fn set_port(&mut self, port: usize, mouse: MouseConfig, axis_map: AxisMap) {
        if let (Some(driver), Some(map)) = (
            self.drivers.get_mut(port),
            self.config.axis_maps.get_mut(port),
        ) {
            driver.set_config(mouse);
            *map = axis_map;
        }
    }

    /// The configuration the board was built with, with every axis map as
    /// [`set_port`](Self::set_port) left it (each port's mouse configuration is its
    /// driver's: [`MouseDriver::config`]).
    pub const fn config(&self) -> &BoardConfig {
        &self.config
    }

    /// The driver of `port`, `None` outside `0..8`.
    pub fn driver(&self, port: usize) -> Option<&MouseDriver> {
        self.drivers.get(port)
    }

    /// The accumulator of `port` (motion since the last report), `None` outside `0..8`.
    pub fn accumulator(&self, port: usize) -> Option<&PaddleAccumulator> {
        self.accumulators.get(port)
    }

    /// Whether the mouse on `port` is initialised and streaming.
    pub fn is_present(&self, port: usize) -> bool {
        self.drivers.get(port).is_some_and(MouseDriver::is_present)
    }

    /// Bit `i` set when port `i`'s mouse is present (e.g. to blink the LED when one
    /// is missing).
    pub fn present_mask(&self) -> u8 {
        self.drivers
            .iter()
            .enumerate()
            .filter(|(_, driver)| driver.is_present())
            .fold(0, |mask, (port, _)| mask | (1 << port))
    }

    /// Sequence number the next report will carry.
    pub const fn next_sequence(&self) -> u16 {
        self.sequence
    }
}

impl Default for SensorBoard {
    fn default() -> Self {
        Self::new(BoardConfig::DEFAULT)
    }
}

//! The emulated sensor board: eight rods with optical PS/2 mice on emulated wires,
//! driven by the firmware's own [`SensorBoard`] library, in emulated time.
//!
//! [`EmulatedBoard::step_report`] advances emulated time to the next millisecond
//! boundary — rod motion sampled by the sensors every
//! [`BoardConfig::sensor_frame_interval_us`], mice streaming packets, frames clocked
//! bit by bit, commands sent by request-to-send, scheduled faults applied — then lets
//! the firmware run its per-millisecond poll and takes the IN report with
//! [`SensorBoard::take_report`], exactly as the RP2040 binary does. Everything is
//! deterministic for a given configuration (including [`BoardConfig::seed`]) and
//! motion.
//!
//! OUT reports from the host are decoded like the firmware does; malformed ones are
//! rejected with [`SimError::MalformedOutReport`]. Haptic pulses and LED changes are
//! recorded with their emulated time so tests can check them.

use crate::error::SimError;
use crate::faults::{Fault, PortFaults, ScheduledFault};
use crate::motion::MotionSource;
use crate::ps2_device::mouse::{MouseParams, Ps2Mouse};
use crate::ps2_device::wire::{Wire, WireEvent, WireParams};
use crate::rng::SimRng;
use crate::sensor_model::{SensorAxis, SensorModel, SensorParams};
use foosball_protocol::{InReport, InReportV2, LedState, OutReport, PADDLES};
use sensor_board::{AxisMap, BoardConfig as FirmwareConfig, MouseAxis, MouseConfig, SensorBoard};

/// Nanoseconds per microsecond.
const NS_PER_US: u64 = 1_000;
/// Nanoseconds per report period (1 ms).
const REPORT_PERIOD_NS: u64 = 1_000_000;

/// Everything that defines an emulated board.
#[derive(Debug, Clone, PartialEq)]
pub struct BoardConfig {
    /// The firmware's mouse configuration (sample rate, resolution, timeouts), as
    /// the RP2040 binary would pass it to [`SensorBoard::new`].
    pub firmware_mouse: MouseConfig,
    /// Behaviour of the emulated mice (self-test time, response delay).
    pub mouse: MouseParams,
    /// Timing of the PS/2 wires (clock frequency, host timeouts).
    pub wire: WireParams,
    /// The optical sensor of each port.
    pub sensors: [SensorParams; PADDLES],
    /// Sensor frame period: how often the sensors look at the rods, µs.
    pub sensor_frame_interval_us: u64,
    /// Seed of all randomness (noise, faults).
    pub seed: u64,
}

impl Default for BoardConfig {
    /// The firmware's default mouse configuration (200 samples/s, 8 counts/mm), default
    /// mice, wires and ideal sensors, 250 µs sensor frames (4000 frames/s), seed 1.
    fn default() -> Self {
        Self {
            firmware_mouse: MouseConfig::DEFAULT,
            mouse: MouseParams::default(),
            wire: WireParams::default(),
            sensors: [SensorParams::default(); PADDLES],
            sensor_frame_interval_us: 250,
            seed: 1,
        }
    }
}

impl BoardConfig {
    /// Checks every value; the error names the first bad one.
    pub fn validate(&self) -> Result<(), SimError> {
        let bad = SimError::InvalidConfig;
        self.wire.validate().map_err(bad)?;
        for (port, sensor) in self.sensors.iter().enumerate() {
            sensor
                .validate()
                .map_err(|e| SimError::InvalidConfig(format!("sensor of port {port}: {e}")))?;
        }
        if !(10..=100_000).contains(&self.sensor_frame_interval_us) {
            return Err(SimError::InvalidConfig(format!(
                "sensor frame interval must be 10–100000 µs, got {}",
                self.sensor_frame_interval_us
            )));
        }
        if !(1_000..=10_000_000).contains(&self.mouse.self_test_us) {
            return Err(SimError::InvalidConfig(format!(
                "mouse self-test must take 1 ms–10 s, got {} µs",
                self.mouse.self_test_us
            )));
        }
        if self.mouse.response_delay_us > 100_000 {
            return Err(SimError::InvalidConfig(format!(
                "mouse response delay must be ≤ 100 ms, got {} µs",
                self.mouse.response_delay_us
            )));
        }
        Ok(())
    }

    /// The firmware configuration matching this board: the mouse configuration and
    /// each port's axis map set to how its sensor is mounted.
    pub fn firmware_config(&self) -> FirmwareConfig {
        let mut axis_maps = [AxisMap::IDENTITY; PADDLES];
        for (map, sensor) in axis_maps.iter_mut().zip(&self.sensors) {
            *map = AxisMap {
                axial: match sensor.mount.axial_axis {
                    SensorAxis::X => MouseAxis::X,
                    SensorAxis::Y => MouseAxis::Y,
                },
                invert_axial: sensor.mount.invert_axial,
                invert_rotation: sensor.mount.invert_rotation,
            };
        }
        FirmwareConfig {
            mouse: self.firmware_mouse,
            axis_maps,
        }
    }
}

/// A haptic pulse the host asked for.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct HapticEvent {
    /// Emulated time the OUT report arrived, µs.
    pub t_us: u64,
    /// Paddle (port) 0–7.
    pub paddle: usize,
    /// Drive strength, 0–255.
    pub strength: u8,
    /// Pulse length, ms (0: stop a running pulse).
    pub duration_ms: u8,
}

/// Counters of one port, for tests and diagnostics.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct PortStats {
    /// Whether a mouse is plugged in.
    pub plugged: bool,
    /// Stream packets the mouse built.
    pub packets_sent: u64,
    /// Of them, packets with an overflow bit.
    pub overflow_packets: u64,
    /// Frames the emulated PIO completed.
    pub frames_received: u64,
    /// Commands the mouse clocked in and acknowledged.
    pub commands_acked: u64,
    /// Frames sent with an inverted parity bit.
    pub parity_errors_injected: u64,
    /// Bytes the mouse dropped.
    pub bytes_dropped: u64,
    /// Sensor frames whose motion was lost to the tracking-speed limit.
    pub sensor_frames_lost: u64,
}

/// One port: the mouse (with its sensor), its faults and its wire.
#[derive(Debug, Clone)]
struct Port {
    mouse: Ps2Mouse,
    faults: PortFaults,
    wire: Wire,
}

impl Port {
    fn next_event_ns(&self) -> Option<u64> {
        let mouse = self.mouse.next_wakeup_us().map(|us| us * NS_PER_US);
        let wire = self.wire.next_event_ns(&self.mouse, &self.faults);
        match (mouse, wire) {
            (Some(a), Some(b)) => Some(a.min(b)),
            (a, b) => a.or(b),
        }
    }
}

/// A fault waiting for its time.
#[derive(Debug, Clone, Copy)]
struct Pending {
    at_ns: u64,
    port: usize,
    fault: Fault,
}

/// The emulated board. See the [module documentation](self).
pub struct EmulatedBoard {
    config: BoardConfig,
    firmware: SensorBoard,
    ports: Vec<Port>,
    motion: Box<dyn MotionSource>,
    now_ns: u64,
    next_report_ns: u64,
    next_frame_ns: u64,
    /// Faults sorted by time (stable for equal times).
    schedule: Vec<Pending>,
    haptics: Vec<HapticEvent>,
    led: LedState,
    led_changes: Vec<(u64, LedState)>,
    out_reports: u64,
    out_rejected: u64,
    last_report: Option<InReport>,
}

impl std::fmt::Debug for EmulatedBoard {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("EmulatedBoard")
            .field("now_us", &self.now_us())
            .field("config", &self.config)
            .finish_non_exhaustive()
    }
}

impl EmulatedBoard {
    /// A board powered up at time 0 (all mice plugged in and starting their
    /// self-test), its rods moved by `motion`.
    pub fn new(config: BoardConfig, motion: Box<dyn MotionSource>) -> Result<Self, SimError> {
        config.validate()?;
        let ports = (0..PADDLES)
            .map(|port| {
                let stream = port as u64;
                let sensor = SensorModel::new(
                    config.sensors[port],
                    SimRng::derive(config.seed, 2 * stream),
                );
                let mut mouse = Ps2Mouse::new(config.mouse, sensor);
                mouse.power_on(0);
                Port {
                    mouse,
                    faults: PortFaults::new(SimRng::derive(config.seed, 2 * stream + 1)),
                    wire: Wire::new(config.wire),
                }
            })
            .collect();
        Ok(Self {
            firmware: SensorBoard::new(config.firmware_config()),
            ports,
            motion,
            now_ns: 0,
            next_report_ns: REPORT_PERIOD_NS,
            next_frame_ns: 0,
            schedule: Vec::new(),
            haptics: Vec::new(),
            led: LedState::Off,
            led_changes: Vec::new(),
            out_reports: 0,
            out_rejected: 0,
            last_report: None,
            config,
        })
    }

    /// The configuration.
    pub fn config(&self) -> &BoardConfig {
        &self.config
    }

    /// Emulated time, µs since power-up.
    pub fn now_us(&self) -> u64 {
        self.now_ns / NS_PER_US
    }

    /// The firmware library instance (drivers, accumulators) for inspection.
    pub fn firmware(&self) -> &SensorBoard {
        &self.firmware
    }

    /// Applies `settings` (axis maps, resolutions, sample rates) to the firmware
    /// library, as a Feature report from the host does
    /// ([`SensorBoard::apply_settings`]).
    pub fn apply_settings(&mut self, settings: &foosball_protocol::BoardSettings) {
        self.firmware.apply_settings(settings);
    }

    /// The emulated mouse of `port`.
    pub fn mouse(&self, port: usize) -> Option<&Ps2Mouse> {
        self.ports.get(port).map(|p| &p.mouse)
    }

    /// Counters of `port`.
    pub fn port_stats(&self, port: usize) -> Option<PortStats> {
        let p = self.ports.get(port)?;
        Some(PortStats {
            plugged: p.faults.plugged,
            packets_sent: p.mouse.packets_sent(),
            overflow_packets: p.mouse.overflow_packets(),
            frames_received: p.wire.frames_received(),
            commands_acked: p.wire.commands_sent(),
            parity_errors_injected: p.faults.parity_errors_injected,
            bytes_dropped: p.faults.bytes_dropped,
            sensor_frames_lost: p.mouse.sensor().frames_lost(),
        })
    }

    /// The last report taken, if any.
    pub fn last_report(&self) -> Option<&InReport> {
        self.last_report.as_ref()
    }

    /// Applies `fault` to `port` now.
    pub fn inject(&mut self, port: usize, fault: Fault) -> Result<(), SimError> {
        Self::check_fault(port, &fault)?;
        self.apply_fault(port, fault);
        Ok(())
    }

    /// Applies `fault` to `port` at emulated time `at_us` (now if already past).
    pub fn schedule(&mut self, at_us: u64, port: usize, fault: Fault) -> Result<(), SimError> {
        Self::check_fault(port, &fault)?;
        let at_ns = at_us.saturating_mul(NS_PER_US);
        let index = self.schedule.partition_point(|p| p.at_ns <= at_ns);
        self.schedule.insert(index, Pending { at_ns, port, fault });
        Ok(())
    }

    /// Schedules a script's faults.
    pub fn schedule_all(&mut self, faults: &[ScheduledFault]) -> Result<(), SimError> {
        for f in faults {
            if !(f.at_s.is_finite() && f.at_s >= 0.0) {
                return Err(SimError::InvalidFault {
                    port: f.port,
                    reason: format!("time must be ≥ 0 s, got {}", f.at_s),
                });
            }
            self.schedule((f.at_s * 1e6).round() as u64, f.port, f.fault)?;
        }
        Ok(())
    }

    fn check_fault(port: usize, fault: &Fault) -> Result<(), SimError> {
        if port >= PADDLES {
            return Err(SimError::NoSuchPort(port));
        }
        fault
            .validate()
            .map_err(|reason| SimError::InvalidFault { port, reason })
    }

    fn apply_fault(&mut self, port: usize, fault: Fault) {
        let now_ns = self.now_ns;
        let now_us = now_ns / NS_PER_US;
        let p = &mut self.ports[port];
        match fault {
            Fault::Unplug => {
                p.faults.plugged = false;
                p.mouse.power_off();
                p.wire.device_stopped(now_ns);
            }
            Fault::Plug => {
                if !p.faults.plugged {
                    p.faults.plugged = true;
                    p.mouse.power_on(now_us);
                }
            }
            Fault::Restart => {
                if p.faults.plugged {
                    p.mouse.restart(now_us);
                    p.wire.device_stopped(now_ns);
                }
            }
            Fault::Silence => {
                p.faults.silent = true;
                p.wire.device_stopped(now_ns);
            }
            Fault::Resume => p.faults.silent = false,
            Fault::DropBytes { count } => {
                p.faults.drop_pending = p.faults.drop_pending.saturating_add(count)
            }
            Fault::ParityErrorRate { probability } => {
                p.faults.parity_error_probability = probability
            }
            Fault::DropRate { probability } => p.faults.drop_probability = probability,
        }
    }

    /// Advances to the next millisecond boundary and returns the IN report the
    /// firmware builds there.
    pub fn step_report(&mut self) -> InReport {
        self.step_report_v2().report
    }

    /// [`step_report`](Self::step_report) as the version 2 report the RP2040 binary
    /// sends over USB: the same motion plus the device time (the emulation's
    /// microseconds) and per paddle the newest packet's age and the dropped count.
    pub fn step_report_v2(&mut self) -> InReportV2 {
        let t = self.next_report_ns;
        self.run_until(t);
        let now_us = t / NS_PER_US;
        for port in 0..PADDLES {
            self.poll_port(port);
        }
        let report = self.firmware.snapshot_report_v2(now_us);
        self.firmware.commit(&report.report);
        self.next_report_ns += REPORT_PERIOD_NS;
        self.last_report = Some(report.report);
        report
    }

    /// Runs `ms` report periods, returning the reports.
    pub fn run_reports(&mut self, ms: u64) -> Vec<InReport> {
        (0..ms).map(|_| self.step_report()).collect()
    }

    /// Processes every event up to and including `t_ns`.
    fn run_until(&mut self, t_ns: u64) {
        // Next event per port, recomputed only for the port an event touched (sensor
        // frames change no port's timing).
        let mut port_next: [Option<u64>; PADDLES] =
            core::array::from_fn(|i| self.ports[i].next_event_ns());
        loop {
            // The earliest of: sensor frame, scheduled fault, port events.
            let mut next = self.next_frame_ns;
            let mut which = Next::Frame;
            if let Some(f) = self.schedule.first() {
                if f.at_ns < next {
                    next = f.at_ns;
                    which = Next::Fault;
                }
            }
            for (i, t) in port_next.iter().enumerate() {
                if let Some(t) = *t {
                    if t < next {
                        next = t;
                        which = Next::Port(i);
                    }
                }
            }
            if next > t_ns {
                break;
            }
            self.now_ns = self.now_ns.max(next);
            match which {
                Next::Frame => self.sensor_frame(),
                Next::Fault => {
                    let f = self.schedule.remove(0);
                    self.apply_fault(f.port, f.fault);
                    port_next[f.port] = self.ports[f.port].next_event_ns();
                }
                Next::Port(i) => {
                    self.port_event(i);
                    port_next[i] = self.ports[i].next_event_ns();
                }
            }
        }
        self.now_ns = self.now_ns.max(t_ns);
    }

    fn sensor_frame(&mut self) {
        let t_us = self.next_frame_ns / NS_PER_US;
        let poses = self.motion.poses_at(t_us);
        for (port, pose) in self.ports.iter_mut().zip(poses) {
            port.mouse.observe(t_us, pose);
        }
        self.next_frame_ns += self.config.sensor_frame_interval_us * NS_PER_US;
    }

    fn port_event(&mut self, index: usize) {
        let now_us = self.now_ns / NS_PER_US;
        let port = &mut self.ports[index];
        port.mouse.tick(now_us);
        let event = port
            .wire
            .handle(self.now_ns, &mut port.mouse, &mut port.faults);
        match event {
            Some(WireEvent::Frame(frame)) => self.firmware.on_frame(index, now_us, frame),
            Some(WireEvent::CommandSent(result)) => {
                self.firmware.on_command_sent(index, now_us, result)
            }
            None => return,
        }
        // The firmware reacts at once to what arrived (its next command).
        self.poll_port(index);
    }

    /// The firmware's poll for `port`; a command it hands out goes on the wire.
    fn poll_port(&mut self, index: usize) {
        let port = &mut self.ports[index];
        if port.wire.is_host_sending() {
            return;
        }
        let now_us = self.now_ns / NS_PER_US;
        if let Some(byte) = self.firmware.poll(index, now_us) {
            port.wire
                .start_host_send(self.now_ns, byte, &mut port.mouse);
        }
    }

    /// Handles an OUT report from the host: records its haptic pulses and LED state
    /// with the current emulated time. Malformed bytes are rejected.
    pub fn receive_out_report(&mut self, bytes: &[u8]) -> Result<OutReport, SimError> {
        let report = OutReport::decode(bytes).inspect_err(|_| self.out_rejected += 1)?;
        self.out_reports += 1;
        let t_us = self.now_us();
        for (paddle, pulse) in report.haptics.iter().enumerate() {
            if pulse.duration_ms > 0 || pulse.strength > 0 {
                self.haptics.push(HapticEvent {
                    t_us,
                    paddle,
                    strength: pulse.strength,
                    duration_ms: pulse.duration_ms,
                });
            }
        }
        if report.led != self.led {
            self.led = report.led;
            self.led_changes.push((t_us, report.led));
        }
        Ok(report)
    }

    /// Haptic pulses received so far, in order.
    pub fn haptic_events(&self) -> &[HapticEvent] {
        &self.haptics
    }

    /// Whether `paddle`'s motor runs at emulated time `t_us` (the last pulse started
    /// at or before `t_us` lasts past it).
    pub fn haptic_running(&self, paddle: usize, t_us: u64) -> bool {
        self.haptics
            .iter()
            .rev()
            .find(|e| e.paddle == paddle && e.t_us <= t_us)
            .is_some_and(|e| t_us < e.t_us + u64::from(e.duration_ms) * 1000)
    }

    /// The status LED now.
    pub fn led(&self) -> LedState {
        self.led
    }

    /// LED changes with their emulated times, µs.
    pub fn led_changes(&self) -> &[(u64, LedState)] {
        &self.led_changes
    }

    /// OUT reports accepted and rejected so far.
    pub fn out_report_counts(&self) -> (u64, u64) {
        (self.out_reports, self.out_rejected)
    }
}

#[derive(Debug, Clone, Copy)]
enum Next {
    Frame,
    Fault,
    Port(usize),
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::motion::Stationary;
    use foosball_protocol::{HapticPulse, PaddleStatus};

    #[test]
    fn all_ports_come_up_and_report_present() {
        let mut board = EmulatedBoard::new(BoardConfig::default(), Box::new(Stationary)).unwrap();
        let reports = board.run_reports(700);
        assert_eq!(reports[0].sequence, 0);
        assert_eq!(reports[699].sequence, 699);
        let last = reports[699];
        for p in last.paddles {
            assert!(p.status.contains(PaddleStatus::PRESENT), "{p:?}");
        }
        let reinit = reports
            .iter()
            .filter(|r| r.paddles[0].status.contains(PaddleStatus::REINITIALISED))
            .count();
        assert_eq!(reinit, 1);
        assert_eq!(board.now_us(), 700_000);
        let stats = board.port_stats(3).unwrap();
        // 0xAA 0x00, then ACK for 0xF3, 200, 0xE8, 3, 0xF4, then probe answers.
        assert!(stats.frames_received >= 7, "{stats:?}");
        assert!(stats.commands_acked >= 5, "{stats:?}");
        assert_eq!(board.mouse(3).unwrap().counts_per_mm(), 8);
        assert_eq!(board.mouse(3).unwrap().sample_rate(), 200);
    }

    #[test]
    fn out_reports_recorded_and_malformed_rejected() {
        let mut board = EmulatedBoard::new(BoardConfig::default(), Box::new(Stationary)).unwrap();
        board.run_reports(5);
        let mut out = OutReport::default();
        out.haptics[2] = HapticPulse {
            strength: 200,
            duration_ms: 30,
        };
        out.led = LedState::FastBlink;
        board.receive_out_report(&out.to_bytes()).unwrap();
        assert_eq!(
            board.haptic_events(),
            &[HapticEvent {
                t_us: 5_000,
                paddle: 2,
                strength: 200,
                duration_ms: 30
            }]
        );
        assert!(board.haptic_running(2, 34_999));
        assert!(!board.haptic_running(2, 35_000));
        assert!(!board.haptic_running(1, 10_000));
        assert_eq!(board.led(), LedState::FastBlink);
        let err = board.receive_out_report(&[1, 2, 3]).unwrap_err();
        assert!(matches!(err, SimError::MalformedOutReport(_)), "{err}");
        let mut bad_led = out.to_bytes();
        bad_led[17] = 9;
        assert!(board.receive_out_report(&bad_led).is_err());
        assert_eq!(board.out_report_counts(), (1, 2));
    }

    #[test]
    fn bad_config_and_faults_are_errors() {
        let mut config = BoardConfig::default();
        config.wire.clock_hz = 5_000;
        let err = EmulatedBoard::new(config, Box::new(Stationary)).unwrap_err();
        assert!(err.to_string().contains("PS/2 clock"), "{err}");
        let mut board = EmulatedBoard::new(BoardConfig::default(), Box::new(Stationary)).unwrap();
        assert!(matches!(
            board.inject(8, Fault::Unplug),
            Err(SimError::NoSuchPort(8))
        ));
        assert!(board
            .schedule(0, 1, Fault::ParityErrorRate { probability: -1.0 })
            .is_err());
    }
}

//! The PS/2 clock and data lines of one port, at bit level, in emulated time.
//!
//! Two parties share the lines: the emulated mouse (which always generates the clock)
//! and the emulated PIO of the RP2040 (the host side). The wire is event-driven: it
//! computes the time of the next clock edge that matters and the board jumps there,
//! so no time is spent on idle microseconds.
//!
//! **Device → host.** When the bus has been idle for
//! [`WireParams::idle_before_send_us`] and the mouse has a byte ready, the mouse
//! clocks out an 11-bit frame (start 0, 8 data bits LSB first, odd parity, stop 1), one
//! bit per clock period of [`WireParams::clock_hz`] (10–16.7 kHz). The emulated PIO
//! samples the data line on each falling edge (at ½, 1½, … 10½ periods) into an 11-bit
//! shift register; the 11th sample completes a [`Ps2Frame`] for the firmware. A frame
//! thus takes 11 periods (0.66–1.1 ms) and a 3-byte packet about 3.5 ms, exactly as on
//! the cabinet. Faults act here: a byte can be dropped (never sent) or sent with its
//! parity bit inverted. The shift register is a plain PIO shift register: bits of a
//! frame cut off by an unplug stay in it until the host next sends (the firmware
//! restarts the state machine for every request-to-send).
//!
//! **Host → device.** The firmware's command byte is sent by interpreting
//! [`REQUEST_TO_SEND`] step by step: hold the clock low ≥ 100 µs (this aborts a device
//! frame in progress before its 11th clock; the mouse sends that byte again later),
//! pull data low, release the clock; the mouse notices after
//! [`WireParams::rts_response_us`] and clocks in the 10 bits of the [`HostFrame`] on
//! its rising edges, then acknowledges on the 11th clock. A mouse that does not start
//! clocking within [`WireParams::clock_start_timeout_us`] (unplugged, hung, in
//! self-test) fails the send with [`SendError::NoClock`]; one that stops midway fails
//! it with [`SendError::Timeout`] after [`WireParams::transfer_timeout_us`].
//!
//! Times in this module are nanoseconds of emulated time (`*_ns`) unless named `*_us`.

use super::mouse::Ps2Mouse;
use crate::faults::PortFaults;
use sensor_board::{HostFrame, Ps2Frame, RequestToSendStep, SendError, REQUEST_TO_SEND};

/// Bits in a device-to-host frame.
const DEVICE_FRAME_BITS: u8 = 11;

/// Lowest PS/2 clock frequency allowed by the spec, Hz.
pub const MIN_CLOCK_HZ: u32 = 10_000;
/// Highest PS/2 clock frequency allowed by the spec, Hz.
pub const MAX_CLOCK_HZ: u32 = 16_700;

/// Timing of the wire.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct WireParams {
    /// Clock frequency the mouse generates, Hz ([`MIN_CLOCK_HZ`]–[`MAX_CLOCK_HZ`]).
    pub clock_hz: u32,
    /// Idle time the mouse waits on the bus before starting a frame, µs (spec ≥ 50):
    /// this is the gap between the bytes of a packet.
    pub idle_before_send_us: u64,
    /// Time the mouse takes to notice a request-to-send and start clocking, µs.
    pub rts_response_us: u64,
    /// Host side: how long after releasing the clock the device must start clocking,
    /// µs (spec: 15 ms).
    pub clock_start_timeout_us: u64,
    /// Host side: how long the device may take to clock the frame in once started, µs
    /// (spec: 2 ms).
    pub transfer_timeout_us: u64,
}

impl Default for WireParams {
    /// 12.5 kHz clock, 100 µs idle before a frame, 100 µs request-to-send response,
    /// the spec's 15 ms / 2 ms host timeouts.
    fn default() -> Self {
        Self {
            clock_hz: 12_500,
            idle_before_send_us: 100,
            rts_response_us: 100,
            clock_start_timeout_us: 15_000,
            transfer_timeout_us: 2_000,
        }
    }
}

impl WireParams {
    /// Checks the clock frequency is within the PS/2 range and the times are sane.
    pub fn validate(&self) -> Result<(), String> {
        if !(MIN_CLOCK_HZ..=MAX_CLOCK_HZ).contains(&self.clock_hz) {
            return Err(format!(
                "PS/2 clock must be {MIN_CLOCK_HZ}–{MAX_CLOCK_HZ} Hz, got {}",
                self.clock_hz
            ));
        }
        if self.idle_before_send_us < 50 {
            return Err(format!(
                "idle before a device frame must be ≥ 50 µs, got {}",
                self.idle_before_send_us
            ));
        }
        for (name, value) in [
            ("rts_response_us", self.rts_response_us),
            ("clock_start_timeout_us", self.clock_start_timeout_us),
            ("transfer_timeout_us", self.transfer_timeout_us),
        ] {
            if value > 1_000_000 {
                return Err(format!("{name} must be ≤ 1 s, got {value} µs"));
            }
        }
        Ok(())
    }

    /// One clock period, ns.
    pub fn period_ns(&self) -> u64 {
        (1_000_000_000 + u64::from(self.clock_hz) / 2) / u64::from(self.clock_hz.max(1))
    }
}

/// What the host side (the firmware) must be told about.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum WireEvent {
    /// The PIO completed a device-to-host frame.
    Frame(Ps2Frame),
    /// The command byte being sent was clocked in and acknowledged, or failed.
    CommandSent(Result<(), SendError>),
}

/// A host-to-device send in progress.
#[derive(Debug, Clone, Copy)]
struct HostSend {
    frame: HostFrame,
    /// Index of the current step in [`REQUEST_TO_SEND`].
    step: usize,
    /// When the current step began, ns.
    step_start_ns: u64,
    /// When the device started clocking, ns.
    clock_start_ns: Option<u64>,
    /// Bits the device has clocked in.
    bits_clocked: u8,
    /// The bits as the device read them.
    device_rx: u16,
}

#[derive(Debug, Clone, Copy)]
enum Line {
    /// Both lines released since `since_ns`.
    Idle { since_ns: u64 },
    /// The device is clocking out `bits`; falling edge `next_bit` is next.
    DeviceFrame {
        byte: u8,
        bits: u16,
        start_ns: u64,
        next_bit: u8,
    },
    /// The host is sending a command.
    HostSend(HostSend),
}

/// The lines of one port and the emulated PIO's receive shift register.
#[derive(Debug, Clone)]
pub struct Wire {
    params: WireParams,
    period_ns: u64,
    line: Line,
    pio_bits: u16,
    pio_count: u8,
    frames_received: u64,
    commands_sent: u64,
}

/// The 11 bits a well-behaved device puts on the data line for `byte`, bit 0 first;
/// `invert_parity` flips the parity bit (fault injection).
pub fn device_frame_bits(byte: u8, invert_parity: bool) -> u16 {
    let odd_parity = byte.count_ones().is_multiple_of(2) != invert_parity;
    (u16::from(byte) << 1) | (u16::from(odd_parity) << 9) | (1 << 10)
}

/// Device side: decodes the 10 bits clocked in after request-to-send (8 data bits,
/// odd parity, stop); `Err` on a bad parity or stop bit.
fn device_decode(bits: u16) -> Result<u8, ()> {
    let byte = bits as u8;
    let parity = bits & (1 << 8) != 0;
    let stop = bits & (1 << 9) != 0;
    if stop && parity == byte.count_ones().is_multiple_of(2) {
        Ok(byte)
    } else {
        Err(())
    }
}

impl Wire {
    /// Idle lines.
    pub fn new(params: WireParams) -> Self {
        Self {
            period_ns: params.period_ns(),
            params,
            line: Line::Idle { since_ns: 0 },
            pio_bits: 0,
            pio_count: 0,
            frames_received: 0,
            commands_sent: 0,
        }
    }

    /// The timing.
    pub fn params(&self) -> &WireParams {
        &self.params
    }

    /// Whether a host-to-device send is in progress.
    pub fn is_host_sending(&self) -> bool {
        matches!(self.line, Line::HostSend(_))
    }

    /// Whether the device is clocking out a frame.
    pub fn is_device_sending(&self) -> bool {
        matches!(self.line, Line::DeviceFrame { .. })
    }

    /// Frames the PIO completed so far.
    pub fn frames_received(&self) -> u64 {
        self.frames_received
    }

    /// Commands acknowledged by the device so far.
    pub fn commands_sent(&self) -> u64 {
        self.commands_sent
    }

    /// Time of the next edge that changes something, ns; `None` if the wire waits for
    /// the mouse or the host.
    pub fn next_event_ns(&self, mouse: &Ps2Mouse, faults: &PortFaults) -> Option<u64> {
        let half = self.period_ns / 2;
        match self.line {
            Line::Idle { since_ns } => {
                if !faults.device_active() {
                    return None;
                }
                let ready_ns = mouse.ready_at_us()?.saturating_mul(1000);
                let idle_ns = since_ns + self.params.idle_before_send_us * 1000;
                Some(ready_ns.max(idle_ns))
            }
            Line::DeviceFrame {
                start_ns, next_bit, ..
            } => Some(start_ns + u64::from(next_bit) * self.period_ns + half),
            Line::HostSend(send) => {
                let active = faults.device_active() && mouse.is_powered();
                let Some(step) = REQUEST_TO_SEND.get(send.step) else {
                    return Some(send.step_start_ns);
                };
                match *step {
                    RequestToSendStep::InhibitClock { min_us } => {
                        Some(send.step_start_ns + min_us * 1000)
                    }
                    RequestToSendStep::PullDataLow | RequestToSendStep::ReleaseClock => {
                        Some(send.step_start_ns)
                    }
                    RequestToSendStep::DeviceClocksBits { .. } | RequestToSendStep::AwaitAck => {
                        match send.clock_start_ns {
                            None if faults.device_active() && mouse.accepts_commands() => {
                                Some(send.step_start_ns + self.params.rts_response_us * 1000)
                            }
                            None => {
                                Some(send.step_start_ns + self.params.clock_start_timeout_us * 1000)
                            }
                            Some(start) if active => {
                                Some(start + u64::from(send.bits_clocked) * self.period_ns + half)
                            }
                            Some(start) => Some(start + self.params.transfer_timeout_us * 1000),
                        }
                    }
                }
            }
        }
    }

    /// Handles the event due at `now_ns` (call when [`next_event_ns`](Self::next_event_ns)
    /// says so; calling early does nothing).
    pub fn handle(
        &mut self,
        now_ns: u64,
        mouse: &mut Ps2Mouse,
        faults: &mut PortFaults,
    ) -> Option<WireEvent> {
        let due = self.next_event_ns(mouse, faults)?;
        if now_ns < due {
            return None;
        }
        match self.line {
            Line::Idle { .. } => {
                self.start_device_frame(now_ns, mouse, faults);
                None
            }
            Line::DeviceFrame {
                byte,
                bits,
                start_ns,
                next_bit,
            } => {
                if !faults.device_active() {
                    // Cut off (unplugged or hung mid-frame); the PIO keeps its bits.
                    self.line = Line::Idle { since_ns: now_ns };
                    return None;
                }
                // Falling edge: the PIO samples the data line.
                let bit = (bits >> next_bit) & 1;
                self.pio_bits |= bit << self.pio_count;
                self.pio_count += 1;
                let next_bit = next_bit + 1;
                self.line = if next_bit == DEVICE_FRAME_BITS {
                    Line::Idle {
                        since_ns: start_ns + u64::from(DEVICE_FRAME_BITS) * self.period_ns,
                    }
                } else {
                    Line::DeviceFrame {
                        byte,
                        bits,
                        start_ns,
                        next_bit,
                    }
                };
                if self.pio_count == DEVICE_FRAME_BITS {
                    let frame = Ps2Frame::from_raw(self.pio_bits);
                    self.pio_bits = 0;
                    self.pio_count = 0;
                    self.frames_received += 1;
                    return Some(WireEvent::Frame(frame));
                }
                None
            }
            Line::HostSend(send) => self.step_host_send(now_ns, send, mouse, faults),
        }
    }

    fn start_device_frame(&mut self, now_ns: u64, mouse: &mut Ps2Mouse, faults: &mut PortFaults) {
        let Some(byte) = mouse.peek_ready(now_ns / 1000) else {
            return;
        };
        mouse.byte_sent();
        if faults.take_drop() {
            // Never appears on the wire.
            self.line = Line::Idle { since_ns: now_ns };
            return;
        }
        let bits = device_frame_bits(byte, faults.take_parity_error());
        self.line = Line::DeviceFrame {
            byte,
            bits,
            start_ns: now_ns,
            next_bit: 0,
        };
    }

    /// The host (firmware) starts sending `byte` at `now_ns` by request-to-send.
    /// Returns `false` (and does nothing) if a send is already in progress.
    pub fn start_host_send(&mut self, now_ns: u64, byte: u8, mouse: &mut Ps2Mouse) -> bool {
        match self.line {
            Line::HostSend(_) => return false,
            Line::DeviceFrame { byte: aborted, .. } => {
                // Inhibited before the 11th clock: the device aborts and resends later.
                mouse.requeue_front(aborted);
            }
            Line::Idle { .. } => {}
        }
        // The firmware restarts the PIO state machine to transmit: partial bits go.
        self.pio_bits = 0;
        self.pio_count = 0;
        self.line = Line::HostSend(HostSend {
            frame: HostFrame::encode(byte),
            step: 0,
            step_start_ns: now_ns,
            clock_start_ns: None,
            bits_clocked: 0,
            device_rx: 0,
        });
        true
    }

    /// The device stopped driving the lines (unplugged, hung, restarted): a frame it
    /// was sending is cut off where it is.
    pub fn device_stopped(&mut self, now_ns: u64) {
        if let Line::DeviceFrame { .. } = self.line {
            self.line = Line::Idle { since_ns: now_ns };
        }
    }

    fn finish_send(&mut self, now_ns: u64, result: Result<(), SendError>) -> Option<WireEvent> {
        self.line = Line::Idle { since_ns: now_ns };
        if result.is_ok() {
            self.commands_sent += 1;
        }
        Some(WireEvent::CommandSent(result))
    }

    fn step_host_send(
        &mut self,
        now_ns: u64,
        mut send: HostSend,
        mouse: &mut Ps2Mouse,
        faults: &mut PortFaults,
    ) -> Option<WireEvent> {
        let half = self.period_ns / 2;
        let active = faults.device_active() && mouse.is_powered();
        loop {
            let Some(step) = REQUEST_TO_SEND.get(send.step).copied() else {
                // The sequence ended without an ACK step: nothing acknowledged.
                return self.finish_send(now_ns, Err(SendError::NoAck));
            };
            match step {
                RequestToSendStep::InhibitClock { min_us } => {
                    if now_ns < send.step_start_ns + min_us * 1000 {
                        break;
                    }
                }
                RequestToSendStep::PullDataLow | RequestToSendStep::ReleaseClock => {}
                RequestToSendStep::DeviceClocksBits { bits } => match send.clock_start_ns {
                    None => {
                        if faults.device_active() && mouse.accepts_commands() {
                            if now_ns >= send.step_start_ns + self.params.rts_response_us * 1000 {
                                send.clock_start_ns = Some(now_ns);
                            }
                            break;
                        }
                        if now_ns >= send.step_start_ns + self.params.clock_start_timeout_us * 1000
                        {
                            return self.finish_send(now_ns, Err(SendError::NoClock));
                        }
                        break;
                    }
                    Some(start) => {
                        if !active {
                            if now_ns >= start + self.params.transfer_timeout_us * 1000 {
                                return self.finish_send(now_ns, Err(SendError::Timeout));
                            }
                            break;
                        }
                        let edge = start + u64::from(send.bits_clocked) * self.period_ns + half;
                        if now_ns < edge {
                            break;
                        }
                        // Rising edge: the device samples the host's bit.
                        let level = send.frame.bit(usize::from(send.bits_clocked));
                        send.device_rx |= u16::from(level) << send.bits_clocked;
                        send.bits_clocked += 1;
                        if send.bits_clocked < bits {
                            break;
                        }
                    }
                },
                RequestToSendStep::AwaitAck => {
                    let start = send.clock_start_ns.unwrap_or(send.step_start_ns);
                    if !active {
                        if now_ns >= start + self.params.transfer_timeout_us * 1000 {
                            return self.finish_send(now_ns, Err(SendError::Timeout));
                        }
                        break;
                    }
                    let edge = start + u64::from(send.bits_clocked) * self.period_ns + half;
                    if now_ns < edge {
                        break;
                    }
                    // The device pulls data low for the 11th clock: ACK. Then it acts.
                    mouse.on_host_byte(now_ns / 1000, device_decode(send.device_rx));
                    let release_ns = edge + half;
                    let event = self.finish_send(release_ns, Ok(()));
                    return event;
                }
            }
            send.step += 1;
            send.step_start_ns = now_ns;
        }
        self.line = Line::HostSend(send);
        None
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ps2_device::mouse::MouseParams;
    use crate::rng::SimRng;
    use crate::sensor_model::{SensorModel, SensorParams};

    struct Rig {
        wire: Wire,
        mouse: Ps2Mouse,
        faults: PortFaults,
        now_ns: u64,
    }

    impl Rig {
        fn new(clock_hz: u32) -> Self {
            let mut mouse = Ps2Mouse::new(
                MouseParams {
                    self_test_us: 1000,
                    ..MouseParams::default()
                },
                SensorModel::new(SensorParams::default(), SimRng::new(1)),
            );
            mouse.power_on(0);
            Self {
                wire: Wire::new(WireParams {
                    clock_hz,
                    ..WireParams::default()
                }),
                mouse,
                faults: PortFaults::new(SimRng::new(2)),
                now_ns: 0,
            }
        }

        /// Runs until `until_ns`, returning events with their times.
        fn run(&mut self, until_ns: u64) -> Vec<(u64, WireEvent)> {
            let mut out = Vec::new();
            loop {
                let mouse_ns = self.mouse.next_wakeup_us().map(|us| us * 1000);
                let wire_ns = self.wire.next_event_ns(&self.mouse, &self.faults);
                let next = [mouse_ns, wire_ns].into_iter().flatten().min();
                let Some(next) = next.filter(|&t| t <= until_ns) else {
                    break;
                };
                self.now_ns = self.now_ns.max(next);
                self.mouse.tick(self.now_ns / 1000);
                if let Some(event) =
                    self.wire
                        .handle(self.now_ns, &mut self.mouse, &mut self.faults)
                {
                    out.push((self.now_ns, event));
                }
            }
            self.now_ns = until_ns;
            out
        }
    }

    #[test]
    fn device_frames_take_eleven_clock_periods() {
        for clock_hz in [MIN_CLOCK_HZ, 12_500, MAX_CLOCK_HZ] {
            let mut rig = Rig::new(clock_hz);
            let events = rig.run(10_000_000);
            let period = WireParams {
                clock_hz,
                ..WireParams::default()
            }
            .period_ns();
            // Self-test ends at 1 ms: 0xAA goes out at once, then 0x00.
            assert_eq!(events.len(), 2, "{events:?}");
            let (t0, e0) = events[0];
            assert_eq!(e0, WireEvent::Frame(Ps2Frame::encode(0xAA)));
            assert_eq!(t0, 1_000_000 + 10 * period + period / 2);
            let (t1, e1) = events[1];
            assert_eq!(e1, WireEvent::Frame(Ps2Frame::encode(0x00)));
            // Next frame: after the first ends (11 periods) and 100 µs idle.
            assert_eq!(t1 - t0, period / 2 + 100_000 + 10 * period + period / 2);
        }
    }

    #[test]
    fn host_send_follows_request_to_send_and_gets_an_ack() {
        let mut rig = Rig::new(10_000);
        rig.run(5_000_000);
        let start = rig.now_ns;
        assert!(rig.wire.start_host_send(start, 0xF2, &mut rig.mouse));
        assert!(!rig.wire.start_host_send(start, 0xF2, &mut rig.mouse));
        let events = rig.run(start + 10_000_000);
        let period = 100_000;
        // Inhibit 100 µs, device responds after 100 µs, 10 bits + ACK clock.
        let ack_at = start + 100_000 + 100_000 + 10 * period + period / 2;
        assert_eq!(events[0], (ack_at, WireEvent::CommandSent(Ok(()))));
        assert_eq!(events[1].1, WireEvent::Frame(Ps2Frame::encode(0xFA)));
        assert_eq!(events[2].1, WireEvent::Frame(Ps2Frame::encode(0x00)));
        assert_eq!(events.len(), 3);
    }

    #[test]
    fn send_to_absent_or_vanishing_device_fails() {
        let mut rig = Rig::new(12_500);
        rig.run(5_000_000);
        rig.faults.plugged = false;
        rig.mouse.power_off();
        let start = rig.now_ns;
        rig.wire.start_host_send(start, 0xFF, &mut rig.mouse);
        let events = rig.run(start + 50_000_000);
        assert_eq!(
            events,
            vec![(
                start + 100_000 + 15_000_000,
                WireEvent::CommandSent(Err(SendError::NoClock))
            )]
        );
        // Unplugged while clocking the command in: transfer timeout.
        let mut rig = Rig::new(12_500);
        rig.run(5_000_000);
        let start = rig.now_ns;
        rig.wire.start_host_send(start, 0xF4, &mut rig.mouse);
        rig.run(start + 500_000);
        rig.faults.plugged = false;
        let events = rig.run(start + 10_000_000);
        assert_eq!(events.len(), 1);
        assert_eq!(events[0].1, WireEvent::CommandSent(Err(SendError::Timeout)));
    }

    #[test]
    fn inhibit_aborts_a_device_frame_which_is_not_delivered() {
        let mut rig = Rig::new(12_500);
        // Self-test ends at 1 ms; 0xAA starts then. Inhibit in its middle.
        rig.run(1_400_000);
        assert!(rig.wire.is_device_sending());
        rig.wire.start_host_send(1_400_000, 0xF5, &mut rig.mouse);
        let events = rig.run(20_000_000);
        // The command clears the mouse's output; only the ACK follows.
        assert_eq!(events[0].1, WireEvent::CommandSent(Ok(())));
        assert_eq!(events[1].1, WireEvent::Frame(Ps2Frame::encode(0xFA)));
        assert_eq!(events.len(), 2, "{events:?}");
    }

    #[test]
    fn parity_fault_and_drop_fault() {
        let mut rig = Rig::new(12_500);
        rig.faults.parity_error_probability = 1.0;
        let events = rig.run(5_000_000);
        assert_eq!(events.len(), 2);
        for (_, e) in &events {
            let WireEvent::Frame(f) = e else { panic!() };
            assert_eq!(f.decode(), Err(sensor_board::FrameError::Parity));
        }
        let mut rig = Rig::new(12_500);
        rig.faults.drop_pending = 1;
        let events = rig.run(5_000_000);
        assert_eq!(
            events,
            vec![(events[0].0, WireEvent::Frame(Ps2Frame::encode(0x00)))]
        );
    }

    #[test]
    fn frame_bits_match_the_firmware_encoding() {
        for byte in 0..=255u8 {
            assert_eq!(device_frame_bits(byte, false), Ps2Frame::encode(byte).raw());
            assert_eq!(device_decode(HostFrame::encode(byte).raw()), Ok(byte));
        }
        assert!(device_decode(HostFrame::encode(0x12).raw() ^ 1).is_err());
    }

    #[test]
    fn clock_range_is_validated() {
        let bad = WireParams {
            clock_hz: 20_000,
            ..WireParams::default()
        };
        assert!(bad.validate().unwrap_err().contains("10000–16700"));
        assert!(WireParams::default().validate().is_ok());
    }
}

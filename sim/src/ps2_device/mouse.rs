//! The emulated PS/2 mouse at byte level: what it answers to each command, when its
//! self-test ends, and the 3-byte stream packets it builds from its optical sensor.
//!
//! Implemented commands (every one answered by `0xFA` first, except `0xFE`):
//!
//! | command | effect |
//! |---|---|
//! | `0xFF` reset | defaults, streaming off; self-test (≈ 0.5–2.5 s, [`MouseParams::self_test_us`]), then `0xAA 0x00` |
//! | `0xF3 rate` set sample rate | rate ∈ {10, 20, 40, 60, 80, 100, 200}; another value → `0xFE` |
//! | `0xE8 code` set resolution | code 0–3 = 1, 2, 4, 8 counts/mm; another value → `0xFE` |
//! | `0xF4` enable | stream packets at the sample rate (counters cleared) |
//! | `0xF5` disable | stop streaming |
//! | `0xF6` set defaults | 100 samples/s, 4 counts/mm, streaming off |
//! | `0xF2` get id | `0x00` (standard mouse) |
//! | `0xEB` read data | one movement packet (counters cleared) |
//! | `0xE9` status request | three status bytes |
//! | `0xE6`/`0xE7` scaling 1:1 / 2:1, `0xEA` stream mode, `0xF0` remote mode | acknowledged |
//! | `0xFE` resend | the last reply or packet again |
//! | anything else | `0xFE` |
//!
//! Any command stops the output in progress (the pending packet is discarded), as on a
//! real mouse. In stream mode a packet is sent only when there is motion (unless
//! [`MouseParams::stream_when_still`]); while the previous packet is still waiting to
//! go out, motion keeps accumulating in the sensor.
//!
//! Time here is µs of emulated time.

use crate::sensor_model::SensorModel;
use std::collections::VecDeque;

/// Reply: acknowledge.
pub const ACK: u8 = 0xFA;
/// Reply: resend (the byte was invalid).
pub const RESEND: u8 = 0xFE;
/// Self-test passed.
pub const SELF_TEST_PASSED: u8 = 0xAA;
/// Device id of a standard PS/2 mouse.
pub const MOUSE_ID: u8 = 0x00;
/// Sample rates the mouse accepts, samples/s.
pub const VALID_SAMPLE_RATES: [u8; 7] = [10, 20, 40, 60, 80, 100, 200];
/// Power-on sample rate, samples/s.
pub const DEFAULT_SAMPLE_RATE: u8 = 100;
/// Power-on resolution code (4 counts/mm).
pub const DEFAULT_RESOLUTION_CODE: u8 = 2;

/// Timing and behaviour of the emulated mouse.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct MouseParams {
    /// Duration of the self-test after reset or power-up, µs (real mice: ≈ 0.5–2.5 s).
    pub self_test_us: u64,
    /// Time from receiving a command (its ACK bit) to being ready to send the reply, µs.
    pub response_delay_us: u64,
    /// Send a packet every sample even without motion (real mice do not).
    pub stream_when_still: bool,
}

impl Default for MouseParams {
    /// 500 ms self-test, 200 µs response delay, packets only with motion.
    fn default() -> Self {
        Self {
            self_test_us: 500_000,
            response_delay_us: 200,
            stream_when_still: false,
        }
    }
}

/// Power state of the mouse.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Power {
    /// Unplugged: drives nothing, remembers nothing.
    Off,
    /// Running its self-test until the given time (µs); ignores the host meanwhile.
    SelfTest {
        /// When the self-test ends and `0xAA 0x00` is queued, µs.
        done_us: u64,
    },
    /// Running.
    On,
}

/// The emulated mouse: its settings, its output queue and its sensor.
#[derive(Debug, Clone)]
pub struct Ps2Mouse {
    params: MouseParams,
    sensor: SensorModel,
    power: Power,
    streaming: bool,
    remote_mode: bool,
    sample_rate: u8,
    resolution_code: u8,
    scaling_2_to_1: bool,
    /// A command waiting for its argument byte (`0xF3`, `0xE8`).
    awaiting_argument: Option<u8>,
    /// Bytes waiting to be sent, in order.
    tx: VecDeque<u8>,
    /// Earliest time the next byte may start, µs.
    ready_at_us: u64,
    /// The last reply or packet, for `0xFE`.
    last_unit: Vec<u8>,
    /// When the next sample (packet) is due, µs.
    next_sample_us: u64,
    packets: u64,
    overflows: u64,
}

impl Ps2Mouse {
    /// A powered-off mouse with `sensor`. Call [`power_on`](Self::power_on) to start it.
    pub fn new(params: MouseParams, sensor: SensorModel) -> Self {
        Self {
            params,
            sensor,
            power: Power::Off,
            streaming: false,
            remote_mode: false,
            sample_rate: DEFAULT_SAMPLE_RATE,
            resolution_code: DEFAULT_RESOLUTION_CODE,
            scaling_2_to_1: false,
            awaiting_argument: None,
            tx: VecDeque::new(),
            ready_at_us: 0,
            last_unit: Vec::new(),
            next_sample_us: 0,
            packets: 0,
            overflows: 0,
        }
    }

    /// Power applied (plugged in): self-test, then `0xAA 0x00`.
    pub fn power_on(&mut self, now_us: u64) {
        self.restart(now_us);
    }

    /// Power removed (unplugged): everything is lost.
    pub fn power_off(&mut self) {
        self.power = Power::Off;
        self.defaults();
        self.tx.clear();
        self.awaiting_argument = None;
        self.sensor.clear();
    }

    /// Restart as after reset: defaults, self-test, then `0xAA 0x00`.
    pub fn restart(&mut self, now_us: u64) {
        self.defaults();
        self.tx.clear();
        self.awaiting_argument = None;
        self.sensor.clear();
        self.power = Power::SelfTest {
            done_us: now_us + self.params.self_test_us,
        };
    }

    fn defaults(&mut self) {
        self.streaming = false;
        self.remote_mode = false;
        self.sample_rate = DEFAULT_SAMPLE_RATE;
        self.resolution_code = DEFAULT_RESOLUTION_CODE;
        self.scaling_2_to_1 = false;
    }

    /// The power state.
    pub fn power(&self) -> Power {
        self.power
    }

    /// Whether the mouse listens for commands now (powered and not in self-test).
    pub fn accepts_commands(&self) -> bool {
        self.power == Power::On
    }

    /// Whether the mouse is powered (self-test or running).
    pub fn is_powered(&self) -> bool {
        self.power != Power::Off
    }

    /// Whether stream packets are enabled.
    pub fn is_streaming(&self) -> bool {
        self.streaming && !self.remote_mode
    }

    /// Current sample rate, samples/s.
    pub fn sample_rate(&self) -> u8 {
        self.sample_rate
    }

    /// Current resolution, counts/mm.
    pub fn counts_per_mm(&self) -> u8 {
        1 << self.resolution_code
    }

    /// The optical sensor.
    pub fn sensor(&self) -> &SensorModel {
        &self.sensor
    }

    /// The optical sensor, to feed it frames.
    pub fn sensor_mut(&mut self) -> &mut SensorModel {
        &mut self.sensor
    }

    /// One sensor frame: the rod is at `pose` at `t_us`.
    pub fn observe(&mut self, t_us: u64, pose: crate::motion::RodPose) {
        let cpm = f64::from(self.counts_per_mm());
        let powered = self.power == Power::On;
        self.sensor.observe(t_us, pose, cpm, powered);
    }

    /// Stream packets sent so far.
    pub fn packets_sent(&self) -> u64 {
        self.packets
    }

    /// Packets sent with an overflow bit set so far.
    pub fn overflow_packets(&self) -> u64 {
        self.overflows
    }

    /// Bytes waiting to be sent.
    pub fn pending_bytes(&self) -> usize {
        self.tx.len()
    }

    /// The next time the mouse has something to do on its own (self-test end, next
    /// sample), µs; `None` if nothing is scheduled.
    pub fn next_wakeup_us(&self) -> Option<u64> {
        match self.power {
            Power::Off => None,
            Power::SelfTest { done_us } => Some(done_us),
            Power::On if self.is_streaming() => Some(self.next_sample_us),
            Power::On => None,
        }
    }

    /// Runs the mouse's own timers up to `now_us`: ends the self-test, takes samples.
    pub fn tick(&mut self, now_us: u64) {
        if let Power::SelfTest { done_us } = self.power {
            if now_us < done_us {
                return;
            }
            self.power = Power::On;
            self.reply(done_us, &[SELF_TEST_PASSED, MOUSE_ID]);
            self.ready_at_us = done_us;
        }
        if self.power != Power::On || !self.is_streaming() {
            return;
        }
        if now_us < self.next_sample_us {
            return;
        }
        let period = self.sample_period_us();
        self.next_sample_us += period;
        if self.next_sample_us <= now_us {
            // Far behind (e.g. the line was inhibited for long): sample from now on.
            self.next_sample_us = now_us + period;
        }
        if !self.tx.is_empty() {
            // The previous packet has not gone out yet: keep accumulating.
            return;
        }
        if self.sensor.has_motion() || self.params.stream_when_still {
            let packet = self.build_packet();
            self.tx.extend(packet);
            self.last_unit = packet.to_vec();
        }
    }

    fn sample_period_us(&self) -> u64 {
        1_000_000 / u64::from(self.sample_rate.max(1))
    }

    /// Takes the sensor's counts into a packet, clamping to 9 bits (overflow bit set,
    /// the excess lost, as on a real mouse).
    fn build_packet(&mut self) -> [u8; 3] {
        let (x, y) = self.sensor.take_counts();
        let (x, x_overflow) = clamp9(x);
        let (y, y_overflow) = clamp9(y);
        let mut status = 0x08;
        if x < 0 {
            status |= 0x10;
        }
        if y < 0 {
            status |= 0x20;
        }
        if x_overflow {
            status |= 0x40;
        }
        if y_overflow {
            status |= 0x80;
        }
        self.packets += 1;
        if x_overflow || y_overflow {
            self.overflows += 1;
        }
        [status, x as u8, y as u8]
    }

    /// Queues a reply (and remembers it for `0xFE`).
    fn reply(&mut self, now_us: u64, bytes: &[u8]) {
        self.tx.extend(bytes.iter().copied());
        self.last_unit = bytes.to_vec();
        self.ready_at_us = now_us + self.params.response_delay_us;
    }

    /// A byte from the host arrived at `now_us`; `Err(())` if its parity or stop bit
    /// was wrong (the mouse asks for it again with `0xFE`).
    pub fn on_host_byte(&mut self, now_us: u64, received: Result<u8, ()>) {
        if self.power != Power::On {
            return;
        }
        // A command interrupts whatever was being sent.
        self.tx.clear();
        let Ok(byte) = received else {
            self.tx.push_back(RESEND);
            self.ready_at_us = now_us + self.params.response_delay_us;
            return;
        };
        if let Some(command) = self.awaiting_argument {
            if byte != 0xFF && byte != 0xFE {
                self.on_argument(now_us, command, byte);
                return;
            }
            self.awaiting_argument = None;
        }
        match byte {
            0xFF => {
                self.tx.push_back(ACK);
                self.ready_at_us = now_us + self.params.response_delay_us;
                // The ACK goes out first, then the self-test runs.
                self.defaults();
                self.sensor.clear();
                self.power = Power::SelfTest {
                    done_us: now_us + self.params.self_test_us,
                };
            }
            0xFE => {
                let again = self.last_unit.clone();
                self.tx.extend(again);
                self.ready_at_us = now_us + self.params.response_delay_us;
            }
            0xF3 | 0xE8 => {
                self.awaiting_argument = Some(byte);
                self.reply(now_us, &[ACK]);
            }
            0xF4 => {
                self.streaming = true;
                self.sensor.take_counts();
                self.next_sample_us = now_us + self.sample_period_us();
                self.reply(now_us, &[ACK]);
            }
            0xF5 => {
                self.streaming = false;
                self.reply(now_us, &[ACK]);
            }
            0xF6 => {
                self.defaults();
                self.reply(now_us, &[ACK]);
            }
            0xF2 => self.reply(now_us, &[ACK, MOUSE_ID]),
            0xEB => {
                let packet = self.build_packet();
                self.reply(now_us, &[ACK, packet[0], packet[1], packet[2]]);
            }
            0xE9 => {
                let mut status = 0u8;
                if self.remote_mode {
                    status |= 0x40;
                }
                if self.streaming {
                    status |= 0x20;
                }
                if self.scaling_2_to_1 {
                    status |= 0x10;
                }
                self.reply(
                    now_us,
                    &[ACK, status, self.resolution_code, self.sample_rate],
                );
            }
            0xE6 | 0xE7 => {
                self.scaling_2_to_1 = byte == 0xE7;
                self.reply(now_us, &[ACK]);
            }
            0xEA | 0xF0 => {
                self.remote_mode = byte == 0xF0;
                self.reply(now_us, &[ACK]);
            }
            _ => self.reply(now_us, &[RESEND]),
        }
    }

    fn on_argument(&mut self, now_us: u64, command: u8, value: u8) {
        let valid = match command {
            0xF3 => VALID_SAMPLE_RATES.contains(&value),
            _ => value <= 3,
        };
        if !valid {
            // Still waiting for a valid argument.
            self.reply(now_us, &[RESEND]);
            return;
        }
        self.awaiting_argument = None;
        if command == 0xF3 {
            self.sample_rate = value;
        } else {
            self.resolution_code = value;
        }
        self.reply(now_us, &[ACK]);
    }

    /// The next byte to send if one is waiting and may go out at `now_us`.
    pub fn peek_ready(&self, now_us: u64) -> Option<u8> {
        if self.power == Power::Off || now_us < self.ready_at_us {
            return None;
        }
        self.tx.front().copied()
    }

    /// Earliest time a waiting byte may start, µs (`None` if nothing waits).
    pub fn ready_at_us(&self) -> Option<u64> {
        if self.power == Power::Off || self.tx.is_empty() {
            None
        } else {
            Some(self.ready_at_us)
        }
    }

    /// The byte returned by [`peek_ready`](Self::peek_ready) has been sent (or dropped).
    pub fn byte_sent(&mut self) {
        self.tx.pop_front();
    }

    /// A frame carrying `byte` was aborted by the host inhibiting the clock: the mouse
    /// sends it again first (unless the command that follows clears its output).
    pub fn requeue_front(&mut self, byte: u8) {
        if self.power != Power::Off {
            self.tx.push_front(byte);
        }
    }
}

fn clamp9(v: i32) -> (i16, bool) {
    if v > 255 {
        (255, true)
    } else if v < -256 {
        (-256, true)
    } else {
        (v as i16, false)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::motion::RodPose;
    use crate::rng::SimRng;
    use crate::sensor_model::SensorParams;

    fn mouse() -> Ps2Mouse {
        let mut m = Ps2Mouse::new(
            MouseParams::default(),
            SensorModel::new(SensorParams::default(), SimRng::new(1)),
        );
        m.power_on(0);
        m
    }

    fn drain(m: &mut Ps2Mouse, now: u64) -> Vec<u8> {
        let mut out = Vec::new();
        while let Some(b) = m.peek_ready(now) {
            out.push(b);
            m.byte_sent();
        }
        out
    }

    #[test]
    fn power_up_self_test_then_bat() {
        let mut m = mouse();
        assert!(!m.accepts_commands());
        m.tick(499_999);
        assert_eq!(drain(&mut m, 499_999), Vec::<u8>::new());
        m.tick(500_000);
        assert_eq!(drain(&mut m, 500_000), vec![0xAA, 0x00]);
        assert!(m.accepts_commands());
    }

    #[test]
    fn commands_and_arguments() {
        let mut m = mouse();
        m.tick(500_000);
        drain(&mut m, 500_000);
        let t = 600_000;
        m.on_host_byte(t, Ok(0xF2));
        assert_eq!(drain(&mut m, t + 200), vec![ACK, 0x00]);
        m.on_host_byte(t, Ok(0xF3));
        m.on_host_byte(t, Ok(55));
        m.on_host_byte(t, Ok(200));
        assert_eq!(drain(&mut m, t + 200), vec![ACK]);
        assert_eq!(m.sample_rate(), 200);
        m.on_host_byte(t, Ok(0xF3));
        assert_eq!(drain(&mut m, t + 200), vec![ACK]);
        m.on_host_byte(t, Ok(55));
        assert_eq!(drain(&mut m, t + 200), vec![RESEND]);
        m.on_host_byte(t, Ok(40));
        assert_eq!(drain(&mut m, t + 200), vec![ACK]);
        assert_eq!(m.sample_rate(), 40);
        m.on_host_byte(t, Ok(0xE8));
        m.on_host_byte(t, Ok(3));
        assert_eq!(drain(&mut m, t + 200), vec![ACK]);
        assert_eq!(m.counts_per_mm(), 8);
        m.on_host_byte(t, Ok(0xE9));
        assert_eq!(drain(&mut m, t + 200), vec![ACK, 0x00, 3, 40]);
        m.on_host_byte(t, Ok(0xFE));
        assert_eq!(drain(&mut m, t + 200), vec![ACK, 0x00, 3, 40]);
        m.on_host_byte(t, Err(()));
        assert_eq!(drain(&mut m, t + 200), vec![RESEND]);
        m.on_host_byte(t, Ok(0x42));
        assert_eq!(drain(&mut m, t + 200), vec![RESEND]);
        // The reply waits for the response delay.
        m.on_host_byte(t, Ok(0xF5));
        assert_eq!(m.peek_ready(t + 199), None);
        assert_eq!(drain(&mut m, t + 200), vec![ACK]);
    }

    #[test]
    fn streams_motion_packets_and_flags_overflow() {
        let mut m = mouse();
        m.tick(500_000);
        drain(&mut m, 500_000);
        let t = 500_000;
        m.on_host_byte(t, Ok(0xE8));
        m.on_host_byte(t, Ok(3));
        m.on_host_byte(t, Ok(0xF4));
        drain(&mut m, t + 200);
        assert!(m.is_streaming());
        // No motion: nothing at the sample time.
        m.observe(t, RodPose::default());
        m.tick(t + 10_000);
        assert_eq!(drain(&mut m, t + 10_000), Vec::<u8>::new());
        // 10 mm axial (80 counts), −1 mm surface (−8 counts) by the next sample.
        m.observe(t + 15_000, RodPose::new(0.01, -0.125));
        m.tick(t + 20_000);
        assert_eq!(
            drain(&mut m, t + 20_000),
            vec![0x08 | 0x20, 80, (-8i16) as u8]
        );
        // 40 mm = 320 counts: clamped to 255 with X overflow.
        m.observe(t + 29_000, RodPose::new(0.05, -0.125));
        m.tick(t + 30_000);
        assert_eq!(drain(&mut m, t + 30_000), vec![0x08 | 0x40, 255, 0]);
        assert_eq!(m.overflow_packets(), 1);
        // Read data answers with a packet even when nothing moved.
        m.on_host_byte(t + 31_000, Ok(0xEB));
        assert_eq!(drain(&mut m, t + 32_000), vec![ACK, 0x08, 0, 0]);
    }

    #[test]
    fn reset_acks_then_self_tests() {
        let mut m = mouse();
        m.tick(500_000);
        drain(&mut m, 500_000);
        m.on_host_byte(600_000, Ok(0xFF));
        assert_eq!(drain(&mut m, 600_200), vec![ACK]);
        assert!(!m.accepts_commands());
        m.tick(1_100_000);
        assert_eq!(drain(&mut m, 1_100_000), vec![0xAA, 0x00]);
        m.power_off();
        assert_eq!(m.peek_ready(2_000_000), None);
        assert_eq!(m.next_wakeup_us(), None);
    }
}

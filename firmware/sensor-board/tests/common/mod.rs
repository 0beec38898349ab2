//! Test support: a scripted driver harness and an emulated PS/2 mouse.
#![allow(dead_code)]

use std::collections::VecDeque;

use sensor_board::{MouseConfig, MouseDriver, MousePacket, Ps2Frame, SendError};

/// 1 ms in microseconds.
pub const MS: u64 = 1_000;

/// Drives one [`MouseDriver`] by hand, with a clock.
pub struct Harness {
    pub driver: MouseDriver,
    pub now: u64,
}

impl Harness {
    pub fn new(config: MouseConfig) -> Self {
        Self {
            driver: MouseDriver::new(config),
            now: 0,
        }
    }

    /// Polls: the driver must hand out `byte`, which is then sent successfully.
    #[track_caller]
    pub fn expect_send(&mut self, byte: u8) {
        assert_eq!(
            self.driver.poll(self.now),
            Some(byte),
            "expected command {byte:#04x} in state {:?}",
            self.driver.state()
        );
        self.driver.on_command_sent(self.now, Ok(()));
    }

    /// Polls: the driver must have nothing to send.
    #[track_caller]
    pub fn expect_quiet(&mut self) {
        assert_eq!(
            self.driver.poll(self.now),
            None,
            "state {:?}",
            self.driver.state()
        );
    }

    /// The mouse sends `byte`.
    pub fn recv(&mut self, byte: u8) -> Option<MousePacket> {
        self.driver.on_frame(self.now, Ps2Frame::encode(byte))
    }

    /// The mouse sends the bytes; returns the packets completed.
    pub fn recv_all(&mut self, bytes: &[u8]) -> Vec<MousePacket> {
        bytes.iter().filter_map(|&b| self.recv(b)).collect()
    }

    /// Advances the clock by `us` in 1 ms polls; returns the commands handed out
    /// (reported as sent successfully).
    pub fn run_for(&mut self, us: u64) -> Vec<u8> {
        let end = self.now + us;
        let mut sent = Vec::new();
        while self.now < end {
            self.now = (self.now + MS).min(end);
            if let Some(byte) = self.driver.poll(self.now) {
                self.driver.on_command_sent(self.now, Ok(()));
                sent.push(byte);
            }
        }
        sent
    }

    /// Runs the whole initialisation from power-up with a well-behaved mouse.
    pub fn init(&mut self) {
        let config = *self.driver.config();
        self.expect_send(0xFF);
        self.recv(0xFA);
        self.now += 500 * MS;
        self.expect_quiet();
        self.recv(0xAA);
        self.recv(0x00);
        for byte in [
            0xF3,
            config.sample_rate,
            0xE8,
            config.resolution.code(),
            0xF4,
        ] {
            self.expect_send(byte);
            self.recv(0xFA);
        }
        assert!(self.driver.is_present());
    }
}

/// An emulated PS/2 mouse answering commands like a real one.
pub struct FakeMouse {
    plugged: bool,
    streaming: bool,
    awaiting_arg: Option<u8>,
    /// Running its self-test until then: it does not clock commands in.
    busy_until: u64,
    outbox: VecDeque<(u64, u8)>,
    /// Self-test (BAT) duration, microseconds.
    pub self_test_us: u64,
    /// Latency of replies, microseconds.
    pub reply_us: u64,
    /// Every command byte received.
    pub received: Vec<u8>,
    pub sample_rate: u8,
    pub resolution: u8,
    /// The last movement packet sent, for `0xFE`.
    last_packet: [u8; 3],
}

impl FakeMouse {
    /// Plugged in and booted (idle, not streaming).
    pub fn new() -> Self {
        Self {
            plugged: true,
            streaming: false,
            awaiting_arg: None,
            busy_until: 0,
            outbox: VecDeque::new(),
            self_test_us: 500 * MS,
            reply_us: 500,
            received: Vec::new(),
            sample_rate: 100,
            resolution: 2,
            last_packet: MousePacket::default().to_bytes(),
        }
    }

    pub fn is_streaming(&self) -> bool {
        self.plugged && self.streaming
    }

    fn defaults(&mut self) {
        self.streaming = false;
        self.awaiting_arg = None;
        self.sample_rate = 100;
        self.resolution = 2;
    }

    /// The host sends `byte` (request-to-send): fails when unplugged or during the
    /// self-test.
    pub fn command(&mut self, now: u64, byte: u8) -> Result<(), SendError> {
        if !self.plugged || now < self.busy_until {
            return Err(SendError::NoClock);
        }
        self.received.push(byte);
        // A command aborts whatever the mouse was about to send.
        self.outbox.clear();
        let at = now + self.reply_us;
        if let Some(command) = self.awaiting_arg.take() {
            match command {
                0xF3 => self.sample_rate = byte,
                _ => self.resolution = byte,
            }
            self.outbox.push_back((at, 0xFA));
            return Ok(());
        }
        match byte {
            0xFF => {
                self.defaults();
                self.outbox.push_back((at, 0xFA));
                self.outbox.push_back((now + self.self_test_us, 0xAA));
                self.outbox.push_back((now + self.self_test_us, 0x00));
                self.busy_until = now + self.self_test_us;
            }
            0xF3 | 0xE8 => {
                self.awaiting_arg = Some(byte);
                self.outbox.push_back((at, 0xFA));
            }
            0xF4 => {
                self.streaming = true;
                self.outbox.push_back((at, 0xFA));
            }
            0xF5 => {
                self.streaming = false;
                self.outbox.push_back((at, 0xFA));
            }
            0xEB => {
                self.outbox.push_back((at, 0xFA));
                for b in MousePacket::default().to_bytes() {
                    self.outbox.push_back((at, b));
                }
            }
            0xE9 => {
                let flags = if self.streaming { 0x20 } else { 0x00 };
                for b in [0xFA, flags, self.resolution, self.sample_rate] {
                    self.outbox.push_back((at, b));
                }
            }
            0xFE => {
                for b in self.last_packet {
                    self.outbox.push_back((at, b));
                }
            }
            0xF2 => {
                self.outbox.push_back((at, 0xFA));
                self.outbox.push_back((at, 0x00));
            }
            _ => self.outbox.push_back((at, 0xFE)),
        }
        Ok(())
    }

    /// Bytes the mouse has put on the wire by `now`.
    pub fn frames_due(&mut self, now: u64) -> Vec<u8> {
        let mut out = Vec::new();
        while let Some(&(at, byte)) = self.outbox.front() {
            if at > now {
                break;
            }
            self.outbox.pop_front();
            out.push(byte);
        }
        out
    }

    /// Moves the mouse: a packet goes out if it is streaming.
    pub fn move_by(&mut self, now: u64, dx: i16, dy: i16) {
        if self.is_streaming() {
            let packet = MousePacket {
                dx,
                dy,
                ..MousePacket::default()
            };
            self.last_packet = packet.to_bytes();
            for b in packet.to_bytes() {
                self.outbox.push_back((now, b));
            }
        }
    }

    /// Restarts at `now` (a brown-out): power-on defaults, and its `0xAA 0x00`
    /// announcement is lost on the wire.
    pub fn restart_unannounced(&mut self, now: u64) {
        self.defaults();
        self.outbox.clear();
        self.busy_until = now + self.self_test_us;
    }

    pub fn unplug(&mut self) {
        self.plugged = false;
        self.outbox.clear();
        self.defaults();
    }

    /// Plugged in at `now`: announces itself with `0xAA 0x00` after its self-test.
    pub fn plug_in(&mut self, now: u64) {
        self.plugged = true;
        self.defaults();
        self.outbox.clear();
        self.outbox.push_back((now + self.self_test_us, 0xAA));
        self.outbox.push_back((now + self.self_test_us, 0x00));
        self.busy_until = now + self.self_test_us;
    }
}

/// One step of a driver with its emulated mouse at `now`: deliver the mouse's bytes,
/// then poll and perform any command. Returns the packets completed.
pub fn step(driver: &mut MouseDriver, mouse: &mut FakeMouse, now: u64) -> Vec<MousePacket> {
    let packets = mouse
        .frames_due(now)
        .into_iter()
        .filter_map(|b| driver.on_frame(now, Ps2Frame::encode(b)))
        .collect();
    if let Some(command) = driver.poll(now) {
        let result = mouse.command(now, command);
        driver.on_command_sent(now, result);
    }
    packets
}

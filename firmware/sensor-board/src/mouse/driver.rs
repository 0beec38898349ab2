//! The per-port PS/2 mouse driver state machine.
//!
//! The driver does no I/O: the caller feeds it received frames ([`MouseDriver::on_frame`]),
//! asks it every millisecond what to send ([`MouseDriver::poll`]), performs the
//! request-to-send itself and reports the outcome ([`MouseDriver::on_command_sent`]).
//!
//! | state | sends | expects | next |
//! |---|---|---|---|
//! | [`Reset`](DriverState::Reset) | `0xFF` | `0xFA` | `ResetSelfTest` |
//! | [`ResetSelfTest`](DriverState::ResetSelfTest) | — | `0xAA` within `self_test_timeout_us` | `ResetDeviceId` |
//! | [`ResetDeviceId`](DriverState::ResetDeviceId) | — | device id (`0x00`) | `SetSampleRate` |
//! | [`SetSampleRate`](DriverState::SetSampleRate) | `0xF3` | `0xFA` | `SetSampleRateValue` |
//! | [`SetSampleRateValue`](DriverState::SetSampleRateValue) | rate (200) | `0xFA` | `SetResolution` |
//! | [`SetResolution`](DriverState::SetResolution) | `0xE8` | `0xFA` | `SetResolutionValue` |
//! | [`SetResolutionValue`](DriverState::SetResolutionValue) | code | `0xFA` | `EnableReporting` |
//! | [`EnableReporting`](DriverState::EnableReporting) | `0xF4` | `0xFA` | `Streaming` (REINITIALISED) |
//! | [`Streaming`](DriverState::Streaming) | `0xE9` status probe after silence or a doubtful byte; `0xFE` after a garbled frame | packets; `0xFA` + 3 status bytes to a probe; the packet again to `0xFE` | `SetSampleRate` if the status shows other settings |
//! | [`Absent`](DriverState::Absent) | `0xFF` every 250 ms | `0xFA` | `ResetSelfTest` |
//!
//! In every state:
//!
//! * Sending a command may take [`MouseConfig::send_timeout_us`] (PS/2: clocking starts
//!   within 15 ms, the frame takes ≤ 2 ms), its reply [`MouseConfig::reply_timeout_us`]
//!   (PS/2: 20 ms). A failed send ([`SendError`]) or a missing reply is retried once
//!   ([`SEND_ATTEMPTS`]; an early failure waits out the attempt's send time first);
//!   the second failure makes the port [`Absent`](DriverState::Absent). The absent
//!   port retries the reset every [`ABSENT_RETRY_INTERVAL_US`], so a replugged mouse
//!   is found.
//! * `0xFE` (resend) from the mouse repeats the command, up to [`MAX_RESENDS`] times;
//!   more, or `0xFC` (error), or a garbled reply restarts the initialisation from
//!   `Reset`; after [`MAX_INIT_ATTEMPTS`] failed attempts in a row the port is absent.
//! * A spontaneous `0xAA 0x00` (self-test passed + id: the mouse was plugged in or
//!   restarted, and is now in its power-on defaults) restarts the configuration at
//!   `SetSampleRate`: no second reset is needed.
//!
//! **Idle, unplugged, or restarted unseen.** A mouse in stream mode with no motion
//! sends nothing. After [`MouseConfig::probe_after_us`] of silence (default 30 ms), or
//! at once after a doubtful byte (a lone `0x00` where a packet starts, a lone `0xAA`
//! cut short: a restart whose `0xAA 0x00` was lost in part), the driver sends a status
//! request (`0xE9`): a present mouse answers `0xFA` and three status bytes. If they
//! show reporting off, remote mode, or another resolution or sample rate, the mouse
//! restarted into its defaults and is configured again. An unanswered probe is
//! retried once, then the port is absent — an unplugged mouse within
//! [`MouseConfig::unplug_detection_us`]. Any other byte arriving meanwhile proves the
//! mouse is alive and cancels the verdict.
//!
//! **Packet framing.** Byte 0 of a packet always has bit 3 set; a byte without it
//! where byte 0 is expected is dropped (resynchronisation). A command that goes out
//! while a packet is partly received cuts it short: the mouse answers the command and
//! then sends that motion again, so the partial packet is dropped when the command is
//! sent. A partial packet whose next
//! byte is later than [`INTER_BYTE_TIMEOUT_US`] is dropped. A garbled frame (framing or
//! parity error) sets its sticky error event, drops the partial packet and asks for
//! it again with `0xFE`, which makes the mouse send its last packet again; after
//! [`MAX_RESENDS`] garbled copies the packet is dropped ([`DriverStats::dropped`]).

use super::command::{
    ACK, DEVICE_ID_MOUSE, ENABLE_REPORTING, ERROR, PROBE, RESEND, RESET, SELF_TEST_PASSED,
    SET_RESOLUTION, SET_SAMPLE_RATE, STATUS_REMOTE_MODE, STATUS_REPORTING,
};
use super::config::{MouseConfig, ABSENT_RETRY_INTERVAL_US, INTER_BYTE_TIMEOUT_US, SEND_ATTEMPTS};
use super::events::{DriverEvents, DriverStats, LineFault};
use super::packet::{MousePacket, PACKET_LEN};
use crate::ps2::{FrameError, Ps2Frame, SendError};

/// How many times one command is repeated on `0xFE` (resend) before initialisation
/// is restarted.
pub const MAX_RESENDS: u8 = 3;

/// Failed initialisation attempts in a row after which the port is declared absent.
pub const MAX_INIT_ATTEMPTS: u8 = 3;

/// Where a port's driver is. See the [module documentation](self) for the table.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum DriverState {
    /// Sending reset (`0xFF`), awaiting its `0xFA`.
    Reset,
    /// Reset acknowledged; the mouse runs its self-test, awaiting `0xAA`.
    ResetSelfTest,
    /// Self-test passed, awaiting the device id.
    ResetDeviceId,
    /// Sending set sample rate (`0xF3`), awaiting `0xFA`.
    SetSampleRate,
    /// Sending the sample rate, awaiting `0xFA`.
    SetSampleRateValue,
    /// Sending set resolution (`0xE8`), awaiting `0xFA`.
    SetResolution,
    /// Sending the resolution code, awaiting `0xFA`.
    SetResolutionValue,
    /// Sending enable reporting (`0xF4`), awaiting `0xFA`.
    EnableReporting,
    /// Initialised: movement packets arrive; silent mice are probed.
    Streaming,
    /// No mouse answers; a reset is retried every [`ABSENT_RETRY_INTERVAL_US`].
    Absent,
}

/// The command a streaming driver sends.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
enum StreamCommand {
    /// Status request: liveness, and the mouse's settings compared with the config.
    Probe,
    /// A packet arrived garbled: the mouse sends its last packet again.
    Resend,
}

/// Progress of the command of the current state.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
enum Phase {
    /// No command outstanding.
    Idle,
    /// The state's command is due: the next `poll` returns it.
    Due,
    /// `poll` handed the command out at `since`; awaiting `on_command_sent`.
    Sending { since: u64 },
    /// Sent; the reply (or, in `ResetSelfTest`/`ResetDeviceId`, the byte) is due by
    /// `deadline`.
    AwaitReply { deadline: u64 },
    /// A send failed early (e.g. a device busy in its self-test); the retry goes
    /// out at `until`, when the failed attempt's send time is used up.
    Backoff { until: u64 },
}

/// Driver of one PS/2 mouse port. See the [module documentation](self).
#[derive(Debug, Clone)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct MouseDriver {
    config: MouseConfig,
    state: DriverState,
    phase: Phase,
    /// `0xFE` replies to the current command so far.
    resends: u8,
    /// Failed sends (or missing replies) of the current command so far.
    attempts: u8,
    /// What a streaming driver's command is.
    stream_command: StreamCommand,
    /// The probe's `0xFA` has arrived; its status bytes follow.
    probe_acked: bool,
    /// The probe's status bytes so far.
    status: [u8; 3],
    /// How many of `status` have arrived.
    status_len: u8,
    /// Resends asked for the packet being received.
    packet_resends: u8,
    /// Failed initialisation attempts in a row.
    init_attempts: u8,
    /// The previous byte was `0xAA` outside a packet: a following `0x00` means the
    /// mouse restarted.
    bat_pending: bool,
    /// Bytes of the packet being assembled.
    packet: [u8; PACKET_LEN],
    /// Slots of `packet` filled (garbled frames count).
    packet_len: u8,
    /// A garbled frame took a slot: discard the packet when complete.
    packet_corrupt: bool,
    /// When the last frame (good or bad) arrived, or streaming started: the silence
    /// reference, microseconds.
    last_frame_us: u64,
    /// A frame arrived since the probe was handed out: the mouse is alive.
    probe_alive: bool,
    /// While absent: when to retry the reset, microseconds.
    next_retry_us: u64,
    /// The id the mouse sent after its self-test.
    device_id: Option<u8>,
    /// [`set_config`](Self::set_config) changed the settings of a streaming mouse:
    /// send them at the next moment with no command outstanding.
    config_changed: bool,
    /// A line found stuck low, until a frame shows the port works again.
    line_fault: Option<LineFault>,
    events: DriverEvents,
    stats: DriverStats,
}

impl MouseDriver {
    /// A driver that resets the mouse on its first [`poll`](Self::poll).
    pub const fn new(config: MouseConfig) -> Self {
        Self {
            config,
            state: DriverState::Reset,
            phase: Phase::Due,
            resends: 0,
            attempts: 0,
            stream_command: StreamCommand::Probe,
            probe_acked: false,
            status: [0; 3],
            status_len: 0,
            packet_resends: 0,
            init_attempts: 0,
            bat_pending: false,
            packet: [0; PACKET_LEN],
            packet_len: 0,
            packet_corrupt: false,
            last_frame_us: 0,
            probe_alive: false,
            next_retry_us: 0,
            device_id: None,
            config_changed: false,
            line_fault: None,
            events: DriverEvents {
                framing_error: false,
                parity_error: false,
                reinitialised: false,
            },
            stats: DriverStats {
                frames: 0,
                packets: 0,
                framing_errors: 0,
                parity_errors: 0,
                resyncs: 0,
                absences: 0,
                inits: 0,
                restarts: 0,
                probes: 0,
                retries: 0,
                resends: 0,
                dropped: 0,
                line_faults: 0,
                fifo_stalls: 0,
                reconfigurations: 0,
            },
        }
    }

    /// A frame arrived from the device at `now_us`. Returns a movement packet when
    /// this frame completed one while streaming.
    pub fn on_frame(&mut self, now_us: u64, frame: Ps2Frame) -> Option<MousePacket> {
        self.on_received(now_us, frame.decode())
    }

    /// A correctly framed byte arrived (for callers that decode frames themselves).
    pub fn on_byte(&mut self, now_us: u64, byte: u8) -> Option<MousePacket> {
        self.on_received(now_us, Ok(byte))
    }

    /// A decoded frame, or its error, arrived at `now_us`.
    pub fn on_received(
        &mut self,
        now_us: u64,
        received: Result<u8, FrameError>,
    ) -> Option<MousePacket> {
        self.stats.frames = self.stats.frames.wrapping_add(1);
        // Something clocked a frame in: both lines work.
        self.line_fault = None;
        let previous_frame_us = self.last_frame_us;
        self.last_frame_us = now_us;
        match received {
            Ok(byte) => self.on_good_byte(now_us, byte, previous_frame_us),
            Err(error) => {
                self.on_bad_frame(now_us, error);
                None
            }
        }
    }

    /// The platform found one of the port's lines stuck low at `now_us` (after a
    /// failed send, with the host's drivers released): the port is absent, and
    /// [`line_fault`](Self::line_fault) says why until a frame arrives again.
    pub fn on_line_fault(&mut self, now_us: u64, fault: LineFault) {
        if self.line_fault != Some(fault) {
            self.stats.line_faults = self.stats.line_faults.wrapping_add(1);
        }
        self.line_fault = Some(fault);
        self.go_absent(now_us);
    }

    /// A line stuck low, if one was found and no frame has arrived since: a wiring
    /// fault, not an unplugged mouse.
    pub const fn line_fault(&self) -> Option<LineFault> {
        self.line_fault
    }

    /// The port's receiver overflowed (the RX FIFO was full, so bits were lost and
    /// the receiver was restarted) at `now_us`: counted, flagged as a framing error
    /// (bytes went missing), and while streaming the packet under way is asked for
    /// again as after a garbled frame.
    pub fn on_rx_stall(&mut self, now_us: u64) {
        self.stats.fifo_stalls = self.stats.fifo_stalls.wrapping_add(1);
        self.events.framing_error = true;
        self.after_lost_byte(now_us);
    }

    /// Call at least every millisecond: runs the timeouts, and returns the next
    /// command byte to send (the caller performs request-to-send, clocks it out and
    /// then calls [`on_command_sent`](Self::on_command_sent)).
    pub fn poll(&mut self, now_us: u64) -> Option<u8> {
        if self.config_changed && self.phase == Phase::Idle && self.state == DriverState::Streaming
        {
            self.stats.reconfigurations = self.stats.reconfigurations.wrapping_add(1);
            self.enter(DriverState::SetSampleRate, now_us);
        }
        match self.phase {
            Phase::Due => return Some(self.hand_out(now_us)),
            Phase::Sending { since } => {
                if now_us.saturating_sub(since) >= self.config.send_timeout_us {
                    return self.timed_out_retry(now_us);
                }
            }
            Phase::AwaitReply { deadline } => {
                if now_us >= deadline {
                    return self.timed_out_retry(now_us);
                }
            }
            Phase::Backoff { until } => {
                if now_us >= until {
                    return Some(self.hand_out(now_us));
                }
            }
            Phase::Idle => match self.state {
                DriverState::Streaming => {
                    let silent_us = now_us.saturating_sub(self.last_frame_us);
                    if silent_us >= self.config.probe_after_us {
                        if self.packet_len > 0 {
                            // A packet cut short long ago.
                            self.drop_packet();
                        }
                        self.start_probe();
                        return Some(self.hand_out(now_us));
                    }
                }
                DriverState::Absent if now_us >= self.next_retry_us => {
                    return Some(self.hand_out(now_us));
                }
                _ => {}
            },
        }
        None
    }

    /// The caller reports the outcome of sending the byte [`poll`](Self::poll)
    /// returned. `Err`: the device did not clock it in or did not acknowledge it.
    /// Ignored when no command is being sent.
    pub fn on_command_sent(&mut self, now_us: u64, result: Result<(), SendError>) {
        let Phase::Sending { since } = self.phase else {
            return;
        };
        match result {
            // The mouse has the byte: the spec's reply time runs from now.
            Ok(()) => {
                if self.state == DriverState::Streaming && self.packet_len > 0 {
                    // The request-to-send cut a packet short: the mouse answers the
                    // command first and sends that motion again after it, so the bytes
                    // so far would only pair with the answer.
                    self.clear_packet();
                    self.stats.resyncs = self.stats.resyncs.wrapping_add(1);
                }
                self.phase = Phase::AwaitReply {
                    deadline: now_us.saturating_add(self.config.reply_timeout_us),
                };
            }
            Err(_) => {
                self.timed_out(now_us);
                if self.phase == Phase::Due {
                    let until = since.saturating_add(self.config.send_timeout_us);
                    if until > now_us {
                        self.phase = Phase::Backoff { until };
                    }
                }
            }
        }
    }

    /// Where the driver is.
    pub const fn state(&self) -> DriverState {
        self.state
    }

    /// Whether the mouse is initialised and streaming.
    pub fn is_present(&self) -> bool {
        self.state == DriverState::Streaming
    }

    /// Replaces the configuration. A streaming mouse gets the new sample rate and
    /// resolution as soon as no command is outstanding, without a reset: set sample
    /// rate, set resolution, enable (a few milliseconds in which the port is not
    /// present; counted in [`DriverStats::reconfigurations`] and, once streaming
    /// again, [`DriverStats::inits`]). A mouse being initialised gets them from the
    /// step that sends them; the timeouts apply from the next command on.
    pub fn set_config(&mut self, config: MouseConfig) {
        let settings_changed = config.sample_rate != self.config.sample_rate
            || config.resolution != self.config.resolution;
        self.config = config;
        if settings_changed && self.state == DriverState::Streaming {
            self.config_changed = true;
        }
    }

    /// The configuration.
    pub const fn config(&self) -> &MouseConfig {
        &self.config
    }

    /// The device id the mouse sent after its last self-test (`0x00` for a standard
    /// mouse), `None` before the first.
    pub const fn device_id(&self) -> Option<u8> {
        self.device_id
    }

    /// The sticky events since the last [`take_events`](Self::take_events), without
    /// clearing them.
    pub const fn events(&self) -> DriverEvents {
        self.events
    }

    /// The sticky events since the last call, clearing them.
    pub fn take_events(&mut self) -> DriverEvents {
        core::mem::take(&mut self.events)
    }

    /// Diagnostic counters.
    pub const fn stats(&self) -> &DriverStats {
        &self.stats
    }

    /// The command byte of the current state.
    fn command(&self) -> u8 {
        match self.state {
            DriverState::SetSampleRate => SET_SAMPLE_RATE,
            DriverState::SetSampleRateValue => self.config.sample_rate,
            DriverState::SetResolution => SET_RESOLUTION,
            DriverState::SetResolutionValue => self.config.resolution.code(),
            DriverState::EnableReporting => ENABLE_REPORTING,
            DriverState::Streaming => match self.stream_command {
                StreamCommand::Probe => PROBE,
                StreamCommand::Resend => RESEND,
            },
            DriverState::Reset
            | DriverState::ResetSelfTest
            | DriverState::ResetDeviceId
            | DriverState::Absent => RESET,
        }
    }

    /// Hands out the current state's command.
    fn hand_out(&mut self, now_us: u64) -> u8 {
        self.phase = Phase::Sending { since: now_us };
        self.command()
    }

    /// Whether a command is out and its reply not yet in.
    fn command_outstanding(&self) -> bool {
        matches!(
            self.phase,
            Phase::Sending { .. } | Phase::AwaitReply { .. } | Phase::Backoff { .. }
        )
    }

    /// A reply did not come in time, or the command could not be sent: the command
    /// is sent again, up to [`SEND_ATTEMPTS`] times in all, before the port counts
    /// as absent.
    fn timed_out(&mut self, now_us: u64) {
        if self.state == DriverState::Streaming && self.probe_alive {
            // Unanswered, but the mouse has sent other bytes since: it is there.
            if self.stream_command == StreamCommand::Resend {
                self.drop_packet();
            }
            self.phase = Phase::Idle;
            return;
        }
        let retryable = !matches!(
            self.state,
            DriverState::Absent | DriverState::ResetSelfTest | DriverState::ResetDeviceId
        );
        if retryable && self.attempts.saturating_add(1) < SEND_ATTEMPTS {
            self.attempts += 1;
            self.stats.retries = self.stats.retries.wrapping_add(1);
            self.probe_acked = false;
            self.status_len = 0;
            self.phase = Phase::Due;
        } else {
            self.go_absent(now_us);
        }
    }

    /// [`timed_out`](Self::timed_out) from `poll`: a retry goes out at once.
    fn timed_out_retry(&mut self, now_us: u64) -> Option<u8> {
        self.timed_out(now_us);
        (self.phase == Phase::Due).then(|| self.hand_out(now_us))
    }

    /// Makes the next command a status request (liveness and settings).
    fn start_probe(&mut self) {
        self.stream_command = StreamCommand::Probe;
        self.probe_alive = false;
        self.probe_acked = false;
        self.status_len = 0;
        self.attempts = 0;
        self.stats.probes = self.stats.probes.wrapping_add(1);
    }

    /// A doubtful byte while streaming (one that does not fit the packet stream: the
    /// mouse may have restarted and lost part of its `0xAA 0x00`): check its
    /// settings now.
    fn check_settings_soon(&mut self) {
        if self.phase == Phase::Idle {
            self.start_probe();
            self.phase = Phase::Due;
        }
    }

    /// The probe's three status bytes arrived: configure the mouse again if they
    /// are not the settings it was given (it restarted into its defaults unseen).
    fn on_status(&mut self, now_us: u64) {
        let [flags, resolution, rate] = self.status;
        let as_configured = flags & STATUS_REPORTING != 0
            && flags & STATUS_REMOTE_MODE == 0
            && resolution == self.config.resolution.code()
            && rate == self.config.sample_rate;
        if as_configured {
            self.phase = Phase::Idle;
        } else {
            self.stats.reconfigurations = self.stats.reconfigurations.wrapping_add(1);
            self.enter(DriverState::SetSampleRate, now_us);
        }
    }

    /// A packet is lost for good.
    fn drop_packet(&mut self) {
        self.clear_packet();
        self.packet_resends = 0;
        self.stats.dropped = self.stats.dropped.wrapping_add(1);
    }

    fn on_good_byte(
        &mut self,
        now_us: u64,
        byte: u8,
        previous_frame_us: u64,
    ) -> Option<MousePacket> {
        match self.state {
            DriverState::Streaming => return self.on_stream_byte(now_us, byte, previous_frame_us),
            DriverState::ResetSelfTest => match byte {
                SELF_TEST_PASSED => self.enter(DriverState::ResetDeviceId, now_us),
                ERROR => self.init_failed(now_us),
                // A repeated acknowledge, or stale stream bytes: keep waiting.
                _ => {}
            },
            DriverState::ResetDeviceId => {
                self.device_id = Some(byte);
                self.enter(DriverState::SetSampleRate, now_us);
            }
            DriverState::Reset | DriverState::Absent
                if self.command_outstanding() && byte == SELF_TEST_PASSED =>
            {
                // The acknowledge was lost but the self-test result came.
                self.enter(DriverState::ResetDeviceId, now_us);
            }
            DriverState::Reset
            | DriverState::Absent
            | DriverState::SetSampleRate
            | DriverState::SetSampleRateValue
            | DriverState::SetResolution
            | DriverState::SetResolutionValue
            | DriverState::EnableReporting => {
                if self.restart_announced(byte) {
                    self.on_restart(now_us);
                } else if self.command_outstanding() {
                    self.on_reply(now_us, byte);
                }
            }
        }
        None
    }

    /// Tracks `0xAA 0x00` outside packets: `true` when `byte` completes it.
    fn restart_announced(&mut self, byte: u8) -> bool {
        let announced = self.bat_pending && byte == DEVICE_ID_MOUSE;
        self.bat_pending = byte == SELF_TEST_PASSED;
        announced
    }

    /// The reply to an initialisation command (or to the absent port's reset).
    fn on_reply(&mut self, now_us: u64, byte: u8) {
        match byte {
            ACK => {
                self.attempts = 0;
                let next = match self.state {
                    DriverState::Reset | DriverState::Absent => DriverState::ResetSelfTest,
                    DriverState::SetSampleRate => DriverState::SetSampleRateValue,
                    DriverState::SetSampleRateValue => DriverState::SetResolution,
                    DriverState::SetResolution => DriverState::SetResolutionValue,
                    DriverState::SetResolutionValue => DriverState::EnableReporting,
                    _ => DriverState::Streaming,
                };
                self.enter(next, now_us);
            }
            RESEND => {
                if self.resends < MAX_RESENDS {
                    self.resends += 1;
                    self.phase = Phase::Due;
                } else {
                    self.init_failed(now_us);
                }
            }
            ERROR => self.init_failed(now_us),
            // Not a reply (e.g. a stream byte from before the reset): keep waiting.
            _ => {}
        }
    }

    /// Enters `state` at `now_us`, setting up its command or deadline.
    fn enter(&mut self, state: DriverState, now_us: u64) {
        if state == DriverState::SetSampleRate {
            // The settings about to be sent are the current ones.
            self.config_changed = false;
        }
        self.state = state;
        self.resends = 0;
        self.attempts = 0;
        self.stream_command = StreamCommand::Probe;
        self.probe_acked = false;
        self.status_len = 0;
        self.packet_resends = 0;
        self.bat_pending = false;
        self.clear_packet();
        self.phase = match state {
            DriverState::ResetSelfTest => Phase::AwaitReply {
                deadline: now_us.saturating_add(self.config.self_test_timeout_us),
            },
            DriverState::ResetDeviceId => Phase::AwaitReply {
                deadline: now_us.saturating_add(self.config.reply_timeout_us),
            },
            DriverState::Streaming | DriverState::Absent => Phase::Idle,
            _ => Phase::Due,
        };
        match state {
            DriverState::Streaming => {
                self.init_attempts = 0;
                self.last_frame_us = now_us;
                self.events.reinitialised = true;
                self.stats.inits = self.stats.inits.wrapping_add(1);
            }
            DriverState::Absent => {
                self.init_attempts = 0;
                self.next_retry_us = now_us.saturating_add(ABSENT_RETRY_INTERVAL_US);
            }
            _ => {}
        }
    }

    /// The port does not answer: absent, retrying later.
    fn go_absent(&mut self, now_us: u64) {
        if self.state != DriverState::Absent {
            self.stats.absences = self.stats.absences.wrapping_add(1);
        }
        self.enter(DriverState::Absent, now_us);
    }

    /// Initialisation failed (error reply, too many resends, garbled reply).
    fn init_failed(&mut self, now_us: u64) {
        self.init_attempts = self.init_attempts.saturating_add(1);
        if self.state == DriverState::Absent || self.init_attempts >= MAX_INIT_ATTEMPTS {
            self.go_absent(now_us);
        } else {
            let attempts = self.init_attempts;
            self.enter(DriverState::Reset, now_us);
            self.init_attempts = attempts;
        }
    }

    /// The mouse announced a restart (`0xAA 0x00`): it is in its power-on defaults,
    /// so configure it again, no reset needed.
    fn on_restart(&mut self, now_us: u64) {
        self.stats.restarts = self.stats.restarts.wrapping_add(1);
        self.device_id = Some(DEVICE_ID_MOUSE);
        self.init_attempts = 0;
        self.enter(DriverState::SetSampleRate, now_us);
    }

    fn clear_packet(&mut self) {
        self.packet_len = 0;
        self.packet_corrupt = false;
    }

    /// Drops a partial packet whose next byte came too late.
    fn drop_stale_packet(&mut self, now_us: u64, previous_frame_us: u64) {
        if self.packet_len > 0 && now_us.saturating_sub(previous_frame_us) > INTER_BYTE_TIMEOUT_US {
            // A lone `0xAA`: a restart whose `0x00` was lost.
            let lone_self_test = self.packet_len == 1 && self.packet[0] == SELF_TEST_PASSED;
            self.drop_packet();
            self.stats.resyncs = self.stats.resyncs.wrapping_add(1);
            if lone_self_test {
                self.check_settings_soon();
            }
        }
    }

    fn on_stream_byte(
        &mut self,
        now_us: u64,
        byte: u8,
        previous_frame_us: u64,
    ) -> Option<MousePacket> {
        if self.stream_command == StreamCommand::Resend
            && matches!(self.phase, Phase::Due | Phase::Sending { .. })
        {
            // The rest of the garbled packet, before the resend went out: the
            // resend brings the whole packet again.
            return None;
        }
        if self.command_outstanding() {
            self.probe_alive = true;
            match self.stream_command {
                StreamCommand::Probe if self.probe_acked => {
                    self.status[usize::from(self.status_len).min(2)] = byte;
                    self.status_len = self.status_len.saturating_add(1);
                    if usize::from(self.status_len) == self.status.len() {
                        self.on_status(now_us);
                    }
                    return None;
                }
                StreamCommand::Probe if self.packet_len == 0 => match byte {
                    ACK => {
                        self.probe_acked = true;
                        return None;
                    }
                    RESEND | ERROR => {
                        // Answered, if not as asked: the mouse is there.
                        self.phase = Phase::Idle;
                        return None;
                    }
                    _ => {}
                },
                StreamCommand::Probe => {}
                // Some mice acknowledge a resend before the packet.
                StreamCommand::Resend if self.packet_len == 0 && byte == ACK => return None,
                // The packet again: the resend is answered.
                StreamCommand::Resend => self.phase = Phase::Idle,
            }
        }
        self.drop_stale_packet(now_us, previous_frame_us);
        if self.packet_len == 0 && !MousePacket::is_first_byte(byte) {
            self.stats.resyncs = self.stats.resyncs.wrapping_add(1);
            if byte == DEVICE_ID_MOUSE {
                // A lone `0x00` where a packet starts: maybe a restart whose `0xAA`
                // was lost.
                self.check_settings_soon();
            }
            return None;
        }
        let slot = usize::from(self.packet_len).min(PACKET_LEN - 1);
        self.packet[slot] = byte;
        self.packet_len = self.packet_len.saturating_add(1);
        if slot == 1
            && !self.packet_corrupt
            && self.packet[0] == SELF_TEST_PASSED
            && byte == DEVICE_ID_MOUSE
        {
            // `0xAA 0x00` where a packet starts: the mouse restarted (hot-plug).
            self.on_restart(now_us);
            return None;
        }
        self.finish_slot()
    }

    /// After a slot was filled: completes the packet if it was the last.
    fn finish_slot(&mut self) -> Option<MousePacket> {
        if usize::from(self.packet_len) < PACKET_LEN {
            return None;
        }
        let corrupt = self.packet_corrupt;
        self.clear_packet();
        if corrupt {
            return None;
        }
        self.packet_resends = 0;
        self.stats.packets = self.stats.packets.wrapping_add(1);
        Some(MousePacket::from_bytes(self.packet))
    }

    fn on_bad_frame(&mut self, now_us: u64, error: FrameError) {
        if error.is_framing() {
            self.events.framing_error = true;
            self.stats.framing_errors = self.stats.framing_errors.wrapping_add(1);
        } else {
            self.events.parity_error = true;
            self.stats.parity_errors = self.stats.parity_errors.wrapping_add(1);
        }
        self.after_lost_byte(now_us);
    }

    /// A byte arrived garbled, or went missing: what it means depends on the state.
    fn after_lost_byte(&mut self, now_us: u64) {
        self.bat_pending = false;
        match self.state {
            DriverState::Streaming => {
                let resending = self.stream_command == StreamCommand::Resend;
                if self.command_outstanding() && !resending {
                    // Most likely the probe's garbled answer: the mouse is there.
                    self.probe_alive = true;
                    self.phase = Phase::Idle;
                    self.clear_packet();
                    return;
                }
                if resending && matches!(self.phase, Phase::Due | Phase::Sending { .. }) {
                    // More of the packet already being resent.
                    return;
                }
                // Ask for the packet again (`0xFE`: the mouse resends its last
                // packet), up to `MAX_RESENDS` times, before it counts as dropped.
                self.clear_packet();
                if self.packet_resends < MAX_RESENDS {
                    self.packet_resends += 1;
                    self.stats.resends = self.stats.resends.wrapping_add(1);
                    self.stream_command = StreamCommand::Resend;
                    self.probe_alive = false;
                    self.attempts = 0;
                    self.phase = Phase::Due;
                } else {
                    self.drop_packet();
                    self.phase = Phase::Idle;
                }
            }
            // Noise on an absent port changes nothing; the retry goes on.
            DriverState::Absent => {}
            _ => {
                if self.command_outstanding() {
                    // A garbled reply: start the initialisation over.
                    self.init_failed(now_us);
                }
            }
        }
    }
}

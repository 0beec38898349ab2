//! The emulated board as a [`board_link::Board`], in the host's own process.
//!
//! Two pacings:
//! * [`Pacing::Lockstep`] (tests): every [`Board::poll_report`] advances emulated time
//!   by exactly 1 ms and returns that report at once, whatever the timeout — runs as
//!   fast as the CPU allows and is fully deterministic.
//! * [`Pacing::RealTime`] (the game): one report per wall-clock millisecond; a poll
//!   waits (at most its timeout) for the next one.
//!
//! Reports are the version 2 reports the RP2040 binary sends (motion plus the device
//! time and per-paddle packet ages and drop counts, [`Board::last_timing`]); they go
//! through their byte encoding and [`ReportReceiver`], exactly like the socket and USB
//! boards, so [`Board::stats`] means the same thing.
//!
//! The board answers Feature reports ([`FeaturePipe`]) as the firmware does, with the
//! same code as the USB/IP device ([`crate::usb_device`]): device info (uptime = the
//! emulated time since power-up, µs), each port's diagnostics and the settings, read
//! from the firmware library; settings written are applied to it; `EnterBootloader`
//! takes the board off the bus for good (polls, OUT reports and Feature reports then
//! answer [`BoardError::Disconnected`], and the link state is disconnected).

use crate::board::{BoardConfig, EmulatedBoard};
use crate::error::SimError;
use crate::motion::live::{LiveHandle, LiveLimits, LiveMotion};
use crate::motion::MotionSource;
use crate::pacing::RealTimePacer;
use crate::usb_device::{FeatureCommand, FeatureSelection};
use board_link::{Board, BoardError, FeaturePipe, LinkState, LinkStats, ReportReceiver};
use foosball_protocol::{InReport, InReportV2, OutReport, ReportTiming, FEATURE_REPORT_LEN};
use std::time::{Duration, Instant};

/// How many reports a real-time board catches up at most after a stall.
const MAX_BACKLOG_REPORTS: u64 = 100;

/// How an in-process board advances emulated time.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Pacing {
    /// Each poll advances 1 ms of emulated time and returns its report immediately.
    Lockstep,
    /// One report per wall-clock millisecond.
    RealTime,
}

/// An [`EmulatedBoard`] behind the [`Board`] trait.
pub struct InProcessBoard {
    board: EmulatedBoard,
    pacing: Pacing,
    pacer: Option<RealTimePacer>,
    receiver: ReportReceiver,
    /// What GET_REPORT (Feature) returns.
    feature: FeatureSelection,
    /// The host sent the board into its bootloader: it has left the bus.
    in_bootloader: bool,
}

impl std::fmt::Debug for InProcessBoard {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("InProcessBoard")
            .field("pacing", &self.pacing)
            .field("now_us", &self.board.now_us())
            .field("stats", &self.receiver.stats())
            .field("in_bootloader", &self.in_bootloader)
            .finish()
    }
}

impl InProcessBoard {
    /// Wraps `board` with `pacing`.
    pub fn new(board: EmulatedBoard, pacing: Pacing) -> Self {
        Self {
            board,
            pacing,
            pacer: None,
            receiver: ReportReceiver::new(),
            feature: FeatureSelection::default(),
            in_bootloader: false,
        }
    }

    /// A board whose rods are moved by `motion`.
    pub fn with_motion(
        config: BoardConfig,
        motion: Box<dyn MotionSource>,
        pacing: Pacing,
    ) -> Result<Self, SimError> {
        Ok(Self::new(EmulatedBoard::new(config, motion)?, pacing))
    }

    /// A board whose rods follow live targets (keyboard/mouse of the game), with the
    /// setter for them.
    pub fn live(
        config: BoardConfig,
        limits: LiveLimits,
        pacing: Pacing,
    ) -> Result<(Self, LiveHandle), SimError> {
        let motion = LiveMotion::new(LiveHandle::default(), limits);
        let handle = motion.handle();
        Ok((Self::with_motion(config, Box::new(motion), pacing)?, handle))
    }

    /// The emulated board (haptics, faults, statistics).
    pub fn emulated(&self) -> &EmulatedBoard {
        &self.board
    }

    /// The emulated board, to inject faults.
    pub fn emulated_mut(&mut self) -> &mut EmulatedBoard {
        &mut self.board
    }

    fn deliver(&mut self, report: InReportV2) -> Result<Option<InReport>, BoardError> {
        // Through the bytes, as every other board does.
        self.receiver.accept(&report.to_bytes()).map(Some)
    }
}

impl Board for InProcessBoard {
    fn name(&self) -> String {
        match self.pacing {
            Pacing::Lockstep => "emulated (in-process, lockstep)".into(),
            Pacing::RealTime => "emulated (in-process)".into(),
        }
    }

    fn poll_report(&mut self, timeout: Duration) -> Result<Option<InReport>, BoardError> {
        if self.in_bootloader {
            return Err(BoardError::Disconnected);
        }
        if self.pacing == Pacing::Lockstep {
            let report = self.board.step_report_v2();
            return self.deliver(report);
        }
        let start = Instant::now();
        let deadline = start.checked_add(timeout).unwrap_or(start);
        let pacer = self
            .pacer
            .get_or_insert_with(|| RealTimePacer::starting_at(start, MAX_BACKLOG_REPORTS));
        loop {
            let now = Instant::now();
            if pacer.due(now) > 0 {
                pacer.emitted();
                let report = self.board.step_report_v2();
                return self.deliver(report);
            }
            let next = pacer.next_due_at();
            if next > deadline {
                if deadline > now {
                    std::thread::sleep(deadline - now);
                }
                return Ok(None);
            }
            std::thread::sleep(next.saturating_duration_since(now));
        }
    }

    fn send(&mut self, report: &OutReport) -> Result<(), BoardError> {
        if self.in_bootloader {
            return Err(BoardError::Disconnected);
        }
        self.board
            .receive_out_report(&report.to_bytes())
            .map(|_| ())
            .map_err(|e| match e {
                SimError::MalformedOutReport(d) => BoardError::Malformed(d),
                other => BoardError::Usb(other.to_string()),
            })
    }

    fn link_state(&self) -> LinkState {
        if self.in_bootloader {
            LinkState::Disconnected
        } else {
            LinkState::Connected
        }
    }

    fn stats(&self) -> LinkStats {
        self.receiver.stats()
    }

    fn last_timing(&self) -> Option<ReportTiming> {
        self.receiver.last_timing()
    }
}

/// Feature reports answered as the firmware answers them (see the
/// [module documentation](self)); a refused write is [`BoardError::FeatureUnsupported`],
/// as a STALL is on USB.
impl FeaturePipe for InProcessBoard {
    fn get_feature(&mut self, buf: &mut [u8; FEATURE_REPORT_LEN]) -> Result<usize, BoardError> {
        if self.in_bootloader {
            return Err(BoardError::Disconnected);
        }
        let report = self
            .feature
            .report(self.board.firmware(), self.board.now_us());
        // `buf` is one Feature report long: encoding cannot fail.
        report
            .encode(buf)
            .map_err(|e| BoardError::Usb(format!("encoding a Feature report: {e}")))
    }

    fn set_feature(&mut self, report: &[u8; FEATURE_REPORT_LEN]) -> Result<(), BoardError> {
        if self.in_bootloader {
            return Err(BoardError::Disconnected);
        }
        match self.feature.set(report) {
            Ok(None) => {}
            Ok(Some(FeatureCommand::Settings(settings))) => self.board.apply_settings(&settings),
            Ok(Some(FeatureCommand::EnterBootloader)) => self.in_bootloader = true,
            Err(()) => return Err(BoardError::FeatureUnsupported),
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::motion::RodPose;
    use foosball_protocol::{HapticPulse, PaddleStatus};

    #[test]
    fn lockstep_advances_one_ms_per_poll() {
        let mut board = InProcessBoard::with_motion(
            BoardConfig::default(),
            Box::new(crate::motion::Stationary),
            Pacing::Lockstep,
        )
        .unwrap();
        for i in 0..10u16 {
            let r = board.poll_report(Duration::ZERO).unwrap().unwrap();
            assert_eq!(r.sequence, i);
        }
        assert_eq!(board.emulated().now_us(), 10_000);
        // Version 2 reports: the device time of the last snapshot, µs.
        let timing = board.last_timing().expect("version 2 timing");
        assert_eq!(timing.device_time_us, 10_000);
        assert_eq!(board.stats().received, 10);
        assert_eq!(board.stats().lost, 0);
        assert!(board.link_state().is_connected());
        let mut out = OutReport::default();
        out.haptics[7] = HapticPulse {
            strength: 9,
            duration_ms: 1,
        };
        board.send(&out).unwrap();
        assert_eq!(board.emulated().haptic_events()[0].t_us, 10_000);
    }

    #[test]
    fn real_time_paces_at_one_report_per_ms() {
        let (mut board, live) = InProcessBoard::live(
            BoardConfig::default(),
            LiveLimits::default(),
            Pacing::RealTime,
        )
        .unwrap();
        assert!(live.set_target(0, RodPose::new(0.05, 0.0)));
        assert_eq!(board.poll_report(Duration::ZERO).unwrap(), None);
        let start = Instant::now();
        let mut n = 0;
        while start.elapsed() < Duration::from_millis(200) {
            if board
                .poll_report(Duration::from_millis(5))
                .unwrap()
                .is_some()
            {
                n += 1;
            }
        }
        // 200 ms of wall time: about 200 reports (scheduling jitter allowed).
        assert!((150..=205).contains(&n), "{n}");
        let r = board.emulated().last_report().unwrap();
        assert_eq!(r.paddles[0].status.bits() & PaddleStatus::PRESENT.bits(), 0);
    }

    #[test]
    fn feature_reports_are_answered_as_the_firmware_answers_them() {
        use foosball_protocol::{BoardSettings, FeatureReport, ResetReason};
        let mut board = InProcessBoard::with_motion(
            BoardConfig::default(),
            Box::new(crate::motion::Stationary),
            Pacing::Lockstep,
        )
        .unwrap();
        for _ in 0..1_000 {
            board.poll_report(Duration::ZERO).unwrap();
        }
        let info = board.device_info().unwrap();
        assert_eq!(info.uptime_us, 1_000_000, "the emulated time, µs");
        assert_eq!(info.present_ports, 0xFF, "every mouse past its self-test");
        assert_eq!(info.reset_reason, ResetReason::PowerOn);
        assert_eq!(&info.git_hash, b"emulated????");
        for port in 0..8 {
            let diag = board.port_diagnostics(port).unwrap();
            let firmware = board.emulated().firmware().port_diagnostics(port).unwrap();
            assert_eq!(diag, firmware, "port {port}");
            assert!(diag.present && diag.counters.frames > 0, "{diag:?}");
        }
        assert_eq!(board.settings().unwrap(), BoardSettings::DEFAULT);
        let mut settings = BoardSettings::DEFAULT;
        settings.ports[3].sample_rate = 100;
        settings.ports[5].invert_rotation = true;
        board.set_settings(&settings).unwrap();
        assert_eq!(board.settings().unwrap(), settings);
        assert_eq!(board.emulated().firmware().settings(), settings);
        // A kind only the board sends is refused, as the firmware stalls it.
        let info_bytes = FeatureReport::DeviceInfo(info).to_bytes();
        assert!(matches!(
            board.set_feature(&info_bytes),
            Err(BoardError::FeatureUnsupported)
        ));
        board.enter_bootloader().unwrap();
        assert_eq!(board.link_state(), LinkState::Disconnected);
        assert!(matches!(
            board.poll_report(Duration::ZERO),
            Err(BoardError::Disconnected)
        ));
        assert!(matches!(board.device_info(), Err(BoardError::Disconnected)));
        assert!(matches!(
            board.send(&OutReport::default()),
            Err(BoardError::Disconnected)
        ));
    }
}

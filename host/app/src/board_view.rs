//! `space-foosball board`: the sensor board's health, live.
//!
//! Opens a board as `play` does (`--board auto|usb|emulated|socket[:PATH]`, through
//! [`crate::window::board::open`]), the `sim serve` emulator at `--socket PATH` or the
//! USB board with serial number `--serial S` ([`crate::board_tool::target`]), reads its
//! IN reports and prints, every `--interval-ms` (one *frame* of the view):
//!
//! * the board's name, the link state, the protocol version of the newest report
//!   (1: motion only; 2: with timing) and, for version 2, the device time (µs since the
//!   board booted, wrapping);
//! * the reports of the frame: how many, their first and last sequence numbers, the
//!   report rate on the host's clock and, for version 2, on the board's clock (Hz);
//! * the host's counters since the board was opened: reports received, lost (the sum of
//!   the sequence gaps), sequence gaps (how many times the sequence jumped), malformed
//!   reports dropped, reconnects;
//! * per paddle (port 0–7): present or absent, in the newest report; the age of its
//!   newest PS/2 packet and the packets dropped since boot as the board counts them
//!   (version 2); the axial and rotation counts of the frame and since the view
//!   started; the status flags seen during the frame.
//!
//! `--once` prints one frame, `--frames N` that many; otherwise it runs until stopped.
//! `--format json` (or `--json`) prints each frame as one JSON object per line, for
//! scripts. Every figure is taken from the reports as the board sent them (through
//! [`board_link::ReportReceiver`]) and the link's own counters: nothing is estimated.
//! With no report within `--wait-ms` of opening, it fails (one line, exit status 1).
//!
//! The options choosing the board (`--board`, `--socket`, `--serial`) are
//! [`crate::board_tool`]'s, shared with the board's diagnostics and settings commands.

use anyhow::{bail, Context, Result};
use board_link::{Board, BoardError, LinkState, LinkStats, ReportTiming};
use foosball_protocol::{InReport, PaddleStatus, FORMAT_VERSION, IN_REPORT_V2_VERSION, PADDLES};
use std::io::{self, IsTerminal, Write};
use std::time::{Duration, Instant};

/// Default of `--interval-ms`.
const DEFAULT_INTERVAL_MS: u64 = 500;
/// Default of `--wait-ms`.
const DEFAULT_WAIT_MS: u64 = 3_000;

/// Options of the live view (`space-foosball board` or `space-foosball board live`).
#[derive(clap::Args, Debug, Clone, Default, PartialEq, Eq)]
pub struct LiveArgs {
    /// Print one frame and stop (the same as `--frames 1`).
    #[arg(long, conflicts_with = "frames")]
    pub once: bool,
    /// Print this many frames and stop (default: until stopped).
    #[arg(long, value_parser = clap::value_parser!(u64).range(1..))]
    pub frames: Option<u64>,
    /// How long one frame of the view gathers reports, ms (10–60000; default 500).
    #[arg(long, value_parser = clap::value_parser!(u64).range(10..=60_000))]
    pub interval_ms: Option<u64>,
    /// How long to wait for the first report, ms (1–60000; default 3000).
    #[arg(long, value_parser = clap::value_parser!(u64).range(1..=60_000))]
    pub wait_ms: Option<u64>,
    /// Output: readable text (default), or one JSON object per frame and line (the
    /// same as `--json`).
    #[arg(long, value_parser = ["text", "json"])]
    pub format: Option<String>,
}

impl LiveArgs {
    /// Whether any option was given.
    pub fn any_given(&self) -> bool {
        *self != Self::default()
    }

    /// These options, with those of `other` where it gives one (`board --once live
    /// --frames 3` takes both).
    pub fn or(&self, other: &Self) -> Self {
        Self {
            once: self.once || other.once,
            frames: other.frames.or(self.frames),
            interval_ms: other.interval_ms.or(self.interval_ms),
            wait_ms: other.wait_ms.or(self.wait_ms),
            format: other.format.clone().or_else(|| self.format.clone()),
        }
    }

    /// Checks the options together (`json`: `--json` was given) and tells whether
    /// the frames are printed as JSON.
    pub fn json_output(&self, json: bool) -> Result<bool> {
        if self.once && self.frames.is_some() {
            bail!("--once and --frames cannot be used together");
        }
        match (self.format.as_deref(), json) {
            (Some("text"), true) => bail!("--json and --format text contradict each other"),
            (format, json) => Ok(json || format == Some("json")),
        }
    }
}

/// Runs the live view of `board` (opened by [`crate::board_tool`]), printing JSON
/// lines when `json` ([`LiveArgs::json_output`]).
pub fn run(mut board: Box<dyn Board>, args: &LiveArgs, json: bool) -> Result<()> {
    let frames = if args.once { Some(1) } else { args.frames };
    let clear = !json && frames.is_none() && io::stdout().is_terminal();
    let mut view = HealthView::new();
    wait_for_first_report(
        board.as_mut(),
        &mut view,
        Duration::from_millis(args.wait_ms.unwrap_or(DEFAULT_WAIT_MS)),
    )?;
    let interval = Duration::from_millis(args.interval_ms.unwrap_or(DEFAULT_INTERVAL_MS));
    let mut printed = 0u64;
    let mut out = io::stdout().lock();
    while frames.is_none_or(|n| printed < n) {
        let frame = gather(board.as_mut(), &mut view, interval);
        let text = if json {
            frame.to_json().to_string()
        } else {
            frame.to_text()
        };
        let written = if clear {
            write!(out, "\x1b[2J\x1b[H{text}")
        } else {
            writeln!(out, "{text}")
        };
        match written.and_then(|()| out.flush()) {
            Ok(()) => {}
            // `space-foosball board | head`: a closed stdout ends the view quietly.
            Err(e) if e.kind() == io::ErrorKind::BrokenPipe => return Ok(()),
            Err(e) => return Err(e).context("writing the view"),
        }
        printed += 1;
    }
    Ok(())
}

/// Polls until the first report arrives, or fails after `wait`.
fn wait_for_first_report(
    board: &mut dyn Board,
    view: &mut HealthView,
    wait: Duration,
) -> Result<()> {
    let deadline = Instant::now() + wait;
    let mut last_error: Option<String> = None;
    while view.total_reports == 0 {
        let left = deadline.saturating_duration_since(Instant::now());
        if left.is_zero() {
            let why = last_error.map_or_else(String::new, |e| format!(" (last: {e})"));
            bail!(
                "no report from {} within {} ms{why}",
                board.name(),
                wait.as_millis()
            );
        }
        if let Err(e) = poll_once(board, view, left.min(POLL_TIMEOUT)) {
            last_error = Some(e.to_string());
        }
    }
    Ok(())
}

/// The longest a single poll waits, so a frame ends on time.
const POLL_TIMEOUT: Duration = Duration::from_millis(5);

/// Takes one report (or error) from `board` into `view`.
fn poll_once(
    board: &mut dyn Board,
    view: &mut HealthView,
    timeout: Duration,
) -> Result<(), BoardError> {
    match board.poll_report(timeout) {
        Ok(Some(report)) => {
            view.accept(&report, board.last_timing(), board.stats());
            Ok(())
        }
        Ok(None) => Ok(()),
        Err(e) => {
            if e.is_link_down() && !timeout.is_zero() {
                // A board that is away answers at once: do not spin.
                std::thread::sleep(timeout);
            }
            Err(e)
        }
    }
}

/// Reads reports for `interval` and returns the frame they make.
fn gather(board: &mut dyn Board, view: &mut HealthView, interval: Duration) -> Frame {
    let start = Instant::now();
    let end = start + interval;
    loop {
        let left = end.saturating_duration_since(Instant::now());
        if left.is_zero() {
            break;
        }
        // Link trouble shows in the frame (link state, counters); the view goes on.
        let _ = poll_once(board, view, left.min(POLL_TIMEOUT));
    }
    view.finish_frame(
        board.name(),
        board.link_state(),
        board.stats(),
        start.elapsed(),
    )
}

/// What the view keeps per paddle across frames.
#[derive(Debug, Clone, Copy, Default)]
struct PaddleAcc {
    /// Counts since the view started: axial, rotation.
    total: [i64; 2],
    /// Counts of the current frame.
    frame: [i64; 2],
    /// Status bits seen in the current frame.
    seen: u8,
}

/// The reports seen so far, and those of the frame being gathered.
#[derive(Debug, Clone, Default)]
struct HealthView {
    paddles: [PaddleAcc; PADDLES],
    total_reports: u64,
    /// Sequence jumps seen (each gap of one or more lost reports counts once).
    sequence_gaps: u64,
    /// The next expected sequence number.
    expected: Option<u16>,
    /// Reconnects the link had counted at the previous report.
    reconnects_seen: u64,
    last: Option<(InReport, Option<ReportTiming>)>,
    frame_reports: u64,
    frame_first: Option<(u16, Option<u32>)>,
}

impl HealthView {
    fn new() -> Self {
        Self::default()
    }

    /// Takes one report with its timing (version 2) and the link's counters after it.
    fn accept(&mut self, report: &InReport, timing: Option<ReportTiming>, stats: LinkStats) {
        if stats.reconnects != self.reconnects_seen {
            // The board's sequence restarts across a reconnect: no gap.
            self.reconnects_seen = stats.reconnects;
            self.expected = None;
        }
        if let Some(expected) = self.expected {
            let gap = report.sequence.wrapping_sub(expected);
            if gap != 0 && gap < 0x8000 {
                self.sequence_gaps += 1;
            }
        }
        self.expected = Some(report.sequence.wrapping_add(1));
        for (acc, paddle) in self.paddles.iter_mut().zip(&report.paddles) {
            let counts = [i64::from(paddle.axial), i64::from(paddle.rotation)];
            for ((total, frame), count) in acc.total.iter_mut().zip(&mut acc.frame).zip(counts) {
                *total += count;
                *frame += count;
            }
            acc.seen |= paddle.status.bits();
        }
        self.total_reports += 1;
        self.frame_reports += 1;
        if self.frame_first.is_none() {
            self.frame_first = Some((report.sequence, timing.map(|t| t.device_time_us)));
        }
        self.last = Some((*report, timing));
    }

    /// Closes the frame being gathered and starts the next.
    fn finish_frame(
        &mut self,
        name: String,
        link: LinkState,
        stats: LinkStats,
        elapsed: Duration,
    ) -> Frame {
        let (report, timing) = match self.last {
            Some((report, timing)) => (Some(report), timing),
            None => (None, None),
        };
        let first = self.frame_first.take();
        let device_rate_hz = match (first.and_then(|f| f.1), timing) {
            (Some(first_us), Some(last)) if self.frame_reports > 1 => {
                let span_us = last.device_time_us.wrapping_sub(first_us);
                (span_us > 0).then(|| (self.frame_reports - 1) as f64 * 1e6 / f64::from(span_us))
            }
            _ => None,
        };
        let paddles = core::array::from_fn(|port| {
            let acc = &mut self.paddles[port];
            let view = PaddleView {
                present: report
                    .is_some_and(|r| r.paddles[port].status.contains(PaddleStatus::PRESENT)),
                packet_age_us: timing.and_then(|t| t.paddles[port].newest_packet_age.as_micros()),
                dropped: timing.map(|t| t.paddles[port].dropped),
                frame_counts: acc.frame,
                total_counts: acc.total,
                flags: flag_names(acc.seen),
            };
            acc.frame = [0; 2];
            acc.seen = 0;
            view
        });
        let secs = elapsed.as_secs_f64();
        let frame = Frame {
            board: name,
            link,
            protocol_version: report.map(|_| {
                if timing.is_some() {
                    IN_REPORT_V2_VERSION
                } else {
                    FORMAT_VERSION
                }
            }),
            device_time_us: timing.map(|t| t.device_time_us),
            reports: self.frame_reports,
            first_sequence: first.map(|f| f.0),
            last_sequence: (self.frame_reports > 0)
                .then(|| report.map(|r| r.sequence))
                .flatten(),
            host_rate_hz: if secs > 0.0 {
                self.frame_reports as f64 / secs
            } else {
                0.0
            },
            device_rate_hz,
            stats,
            sequence_gaps: self.sequence_gaps,
            paddles,
        };
        self.frame_reports = 0;
        frame
    }
}

/// The names of the status flags in `bits`, leaving out PRESENT (shown on its own).
fn flag_names(bits: u8) -> Vec<&'static str> {
    const NAMES: [(PaddleStatus, &str); 6] = [
        (PaddleStatus::AXIAL_OVERFLOW, "axial-overflow"),
        (PaddleStatus::ROTATION_OVERFLOW, "rotation-overflow"),
        (PaddleStatus::FRAMING_ERROR, "framing-error"),
        (PaddleStatus::PARITY_ERROR, "parity-error"),
        (PaddleStatus::REINITIALISED, "reinitialised"),
        (PaddleStatus::SATURATED, "saturated"),
    ];
    NAMES
        .iter()
        .filter(|(flag, _)| bits & flag.bits() != 0)
        .map(|&(_, name)| name)
        .collect()
}

/// One paddle in one frame.
#[derive(Debug, Clone)]
struct PaddleView {
    /// PRESENT in the newest report.
    present: bool,
    /// Age of the newest PS/2 packet at the newest report's snapshot, µs (version 2;
    /// `None` also when the board had no packet within 25.4 ms).
    packet_age_us: Option<u32>,
    /// Packets the board dropped since boot, wrapping at 256 (version 2).
    dropped: Option<u8>,
    /// Axial and rotation counts of the frame.
    frame_counts: [i64; 2],
    /// Axial and rotation counts since the view started.
    total_counts: [i64; 2],
    /// Status flags seen during the frame (PRESENT left out).
    flags: Vec<&'static str>,
}

/// One frame of the view.
#[derive(Debug, Clone)]
struct Frame {
    board: String,
    link: LinkState,
    /// Layout version of the newest report (`None` before any).
    protocol_version: Option<u8>,
    /// Device time of the newest report, µs since boot, wrapping (version 2).
    device_time_us: Option<u32>,
    /// Reports in the frame.
    reports: u64,
    first_sequence: Option<u16>,
    last_sequence: Option<u16>,
    /// Reports per second of the host's clock over the frame.
    host_rate_hz: f64,
    /// Reports per second of the board's clock over the frame (version 2).
    device_rate_hz: Option<f64>,
    stats: LinkStats,
    sequence_gaps: u64,
    paddles: [PaddleView; PADDLES],
}

fn link_name(link: LinkState) -> &'static str {
    match link {
        LinkState::Connected => "connected",
        LinkState::Disconnected => "disconnected",
        LinkState::Reconnecting => "reconnecting",
    }
}

impl Frame {
    fn to_json(&self) -> serde_json::Value {
        let paddles: Vec<serde_json::Value> = self
            .paddles
            .iter()
            .enumerate()
            .map(|(port, p)| {
                serde_json::json!({
                    "port": port,
                    "present": p.present,
                    "packet_age_us": p.packet_age_us,
                    "dropped": p.dropped,
                    "axial_counts": p.frame_counts[0],
                    "rotation_counts": p.frame_counts[1],
                    "axial_counts_total": p.total_counts[0],
                    "rotation_counts_total": p.total_counts[1],
                    "flags": p.flags,
                })
            })
            .collect();
        serde_json::json!({
            "board": self.board,
            "link": link_name(self.link),
            "protocol_version": self.protocol_version,
            "device_time_us": self.device_time_us,
            "reports": self.reports,
            "first_sequence": self.first_sequence,
            "last_sequence": self.last_sequence,
            "report_rate_hz": self.host_rate_hz,
            "device_report_rate_hz": self.device_rate_hz,
            "received": self.stats.received,
            "lost": self.stats.lost,
            "sequence_gaps": self.sequence_gaps,
            "malformed": self.stats.malformed,
            "reconnects": self.stats.reconnects,
            "paddles": paddles,
        })
    }

    fn to_text(&self) -> String {
        let mut s = String::new();
        let version = self
            .protocol_version
            .map_or_else(|| "no report yet".to_string(), |v| format!("protocol v{v}"));
        let time = self.device_time_us.map_or_else(
            || "no device time (v1)".to_string(),
            |us| format!("device time {:.6} s", f64::from(us) * 1e-6),
        );
        s += &format!(
            "{} · link {} · {version} · {time}\n",
            self.board,
            link_name(self.link)
        );
        let sequences = match (self.first_sequence, self.last_sequence) {
            (Some(a), Some(b)) => format!(" · sequence {a}..{b}"),
            _ => String::new(),
        };
        let device_rate = self
            .device_rate_hz
            .map_or_else(String::new, |r| format!(", {r:.1}/s on the board's clock"));
        s += &format!(
            "reports: {} this frame, {:.1}/s{device_rate}{sequences}\n",
            self.reports, self.host_rate_hz
        );
        s += &format!(
            "host: received {}, lost {} in {} sequence gaps, malformed {}, reconnects {}\n",
            self.stats.received,
            self.stats.lost,
            self.sequence_gaps,
            self.stats.malformed,
            self.stats.reconnects
        );
        s +=
            "port  sensor   packet age  dropped  axial  rotation  (total axial, rotation)  flags\n";
        for (port, p) in self.paddles.iter().enumerate() {
            let age = match (p.packet_age_us, p.dropped) {
                (Some(us), _) => format!("{:.1} ms", f64::from(us) * 1e-3),
                (None, Some(_)) => "none".to_string(),
                (None, None) => "-".to_string(),
            };
            let dropped = p.dropped.map_or_else(|| "-".to_string(), |d| d.to_string());
            s += &format!(
                "{port:<4}  {:<7}  {age:>10}  {dropped:>7}  {:>5}  {:>8}  ({}, {})  {}\n",
                if p.present { "present" } else { "absent" },
                p.frame_counts[0],
                p.frame_counts[1],
                p.total_counts[0],
                p.total_counts[1],
                p.flags.join(" ")
            );
        }
        s
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use foosball_protocol::{PacketAge, PaddleMotion, PaddleTiming};

    fn report(sequence: u16, axial: i16) -> InReport {
        let mut r = InReport::all_present(sequence);
        r.paddles[2] = PaddleMotion {
            axial,
            rotation: -1,
            status: PaddleStatus::PRESENT | PaddleStatus::PARITY_ERROR,
        };
        r.paddles[5].status = PaddleStatus::empty();
        r
    }

    fn timing(device_time_us: u32) -> ReportTiming {
        let mut t = ReportTiming {
            device_time_us,
            ..ReportTiming::default()
        };
        t.paddles[2] = PaddleTiming {
            newest_packet_age: PacketAge::from_micros(1_300),
            dropped: 4,
        };
        t.paddles[5].newest_packet_age = PacketAge::NONE;
        t
    }

    #[test]
    fn a_frame_shows_what_the_reports_carried() {
        let mut view = HealthView::new();
        let stats = LinkStats::default();
        view.accept(&report(10, 3), Some(timing(5_000)), stats);
        view.accept(&report(11, 4), Some(timing(6_000)), stats);
        // 12 and 13 lost: one gap of two reports.
        view.accept(&report(14, 5), Some(timing(9_000)), stats);
        let frame = view.finish_frame(
            "test".into(),
            LinkState::Connected,
            LinkStats {
                received: 3,
                lost: 2,
                ..LinkStats::default()
            },
            Duration::from_millis(4),
        );
        assert_eq!(frame.protocol_version, Some(2));
        assert_eq!(frame.device_time_us, Some(9_000));
        assert_eq!(
            (frame.first_sequence, frame.last_sequence),
            (Some(10), Some(14))
        );
        assert_eq!(frame.sequence_gaps, 1);
        assert_eq!(frame.stats.lost, 2);
        assert_eq!(frame.device_rate_hz, Some(2.0 * 1e6 / 4_000.0));
        let p = &frame.paddles[2];
        assert!(p.present);
        assert_eq!(p.packet_age_us, Some(1_300));
        assert_eq!(p.dropped, Some(4));
        assert_eq!(p.frame_counts, [12, -3]);
        assert_eq!(p.flags, vec!["parity-error"]);
        assert!(!frame.paddles[5].present);
        assert_eq!(frame.paddles[5].packet_age_us, None);
        let json = frame.to_json();
        assert_eq!(json["paddles"][2]["dropped"], 4);
        assert_eq!(json["sequence_gaps"], 1);
        assert!(frame.to_text().contains("lost 2 in 1 sequence gaps"));
        // The next frame starts from zero counts and keeps the totals.
        view.accept(&report(15, 1), None, stats);
        let next = view.finish_frame(
            "test".into(),
            LinkState::Connected,
            stats,
            Duration::from_millis(1),
        );
        assert_eq!(next.protocol_version, Some(1));
        assert_eq!(next.paddles[2].frame_counts, [1, -1]);
        assert_eq!(next.paddles[2].total_counts, [13, -4]);
        assert_eq!(next.paddles[2].dropped, None);
        assert!(next.to_text().contains("no device time (v1)"));
    }

    #[test]
    fn a_reconnect_is_no_sequence_gap() {
        let mut view = HealthView::new();
        view.accept(&report(100, 0), None, LinkStats::default());
        let after = LinkStats {
            reconnects: 1,
            ..LinkStats::default()
        };
        view.accept(&report(0, 0), None, after);
        view.accept(&report(1, 0), None, after);
        assert_eq!(view.sequence_gaps, 0);
        view.accept(&report(3, 0), None, after);
        assert_eq!(view.sequence_gaps, 1);
    }
}

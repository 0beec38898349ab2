//! `space-foosball board` end to end: the health view of the built-in emulated board
//! and of a socket board (the `sim serve` server, on a thread) shows exactly what the
//! board sent — device time, presence, packet ages, dropped packets, motion — and the
//! host's counters; a missing emulator is one line and exit status 1.
//!
//! The figures are checked against the reports themselves: for the emulated board
//! against a lockstep twin (the emulation is deterministic, so report `n` is the same
//! whatever the pacing), for the socket board against a second client of the same
//! server (every client gets every report).

use std::collections::BTreeMap;
use std::path::Path;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::Duration;

use board_link::{Board, ReportTiming, SocketBoard};
use foosball_protocol::{InReport, PaddleStatus, PADDLES};
use foosball_sim::motion::live::LiveLimits;
use foosball_sim::motion::script::MotionScript;
use foosball_sim::serve::SocketServer;
use foosball_sim::{BoardConfig, EmulatedBoard, Fault, InProcessBoard, Pacing};
use serde_json::Value;

mod common;

use common::run;

/// The frames printed by `space-foosball board ARGS --format json`.
fn frames(args: &[&str]) -> Vec<Value> {
    let mut all = args.to_vec();
    all.extend(["--format", "json"]);
    let out = run(&all);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "board {args:?} failed: {stderr}");
    String::from_utf8(out.stdout)
        .expect("utf-8")
        .lines()
        .map(|l| serde_json::from_str(l).unwrap_or_else(|e| panic!("{e}: {l}")))
        .collect()
}

fn u64_of(v: &Value, key: &str) -> u64 {
    v[key]
        .as_u64()
        .unwrap_or_else(|| panic!("{key} missing in {v}"))
}

/// Checks one frame against the reports the board sent, by sequence number: the
/// newest report's device time, presence, packet ages and drop counts, the frame's
/// count sums and flags.
fn check_frame(frame: &Value, sent: &BTreeMap<u16, (InReport, Option<ReportTiming>)>) {
    let first = u64_of(frame, "first_sequence") as u16;
    let last = u64_of(frame, "last_sequence") as u16;
    let in_frame: Vec<_> = (first..=last)
        .map(|s| {
            sent.get(&s)
                .unwrap_or_else(|| panic!("report {s} was never sent"))
        })
        .collect();
    assert_eq!(u64_of(frame, "reports"), in_frame.len() as u64, "{frame}");
    let (newest, timing) = in_frame.last().copied().expect("a report");
    let timing = timing.expect("the emulated board sends version 2");
    assert_eq!(frame["protocol_version"], 2);
    assert_eq!(
        u64_of(frame, "device_time_us"),
        u64::from(timing.device_time_us)
    );
    for port in 0..PADDLES {
        let shown = &frame["paddles"][port];
        let status = newest.paddles[port].status;
        assert_eq!(
            shown["present"],
            status.contains(PaddleStatus::PRESENT),
            "port {port}: {shown}"
        );
        let age = timing.paddles[port].newest_packet_age.as_micros();
        assert_eq!(
            shown["packet_age_us"].as_u64(),
            age.map(u64::from),
            "port {port}"
        );
        assert_eq!(
            u64_of(shown, "dropped"),
            u64::from(timing.paddles[port].dropped),
            "port {port}"
        );
        let axial: i64 = in_frame
            .iter()
            .map(|(r, _)| i64::from(r.paddles[port].axial))
            .sum();
        let rotation: i64 = in_frame
            .iter()
            .map(|(r, _)| i64::from(r.paddles[port].rotation))
            .sum();
        assert_eq!(shown["axial_counts"].as_i64(), Some(axial), "port {port}");
        assert_eq!(
            shown["rotation_counts"].as_i64(),
            Some(rotation),
            "port {port}"
        );
        let reinit = in_frame
            .iter()
            .any(|(r, _)| r.paddles[port].status.contains(PaddleStatus::REINITIALISED));
        let flags = shown["flags"].as_array().expect("flags");
        assert_eq!(
            flags.iter().any(|f| f == "reinitialised"),
            reinit,
            "port {port}: {shown}"
        );
    }
}

#[test]
fn the_emulated_board_shows_the_reports_it_sent() {
    let frames = frames(&[
        "board",
        "--board",
        "emulated",
        "--frames",
        "3",
        "--interval-ms",
        "250",
    ]);
    assert_eq!(frames.len(), 3);
    let last_sequence = u64_of(&frames[2], "last_sequence");
    // The same board, stepped by hand: it is deterministic.
    let (mut twin, _live) = InProcessBoard::live(
        BoardConfig::default(),
        LiveLimits::default(),
        Pacing::Lockstep,
    )
    .unwrap();
    let mut sent = BTreeMap::new();
    for _ in 0..=last_sequence {
        let report = twin.poll_report(Duration::ZERO).unwrap().unwrap();
        sent.insert(report.sequence, (report, twin.last_timing()));
    }
    for frame in &frames {
        check_frame(frame, &sent);
        assert_eq!(frame["link"], "connected");
        // In-process nothing is lost: every report the board built arrived.
        assert_eq!(u64_of(frame, "lost"), 0);
        assert_eq!(u64_of(frame, "sequence_gaps"), 0);
        assert_eq!(
            u64_of(frame, "received"),
            u64_of(frame, "last_sequence") + 1
        );
        // One report per millisecond of the board's clock.
        assert_eq!(frame["device_report_rate_hz"].as_f64(), Some(1000.0));
    }
    // The mice finish their 500 ms self-test: every sensor present by 750 ms.
    let last = &frames[2];
    assert!(u64_of(last, "device_time_us") >= 600_000, "{last}");
    for port in 0..PADDLES {
        assert_eq!(last["paddles"][port]["present"], true, "port {port}");
    }
}

/// Every rod moving for 4 s.
fn moving_script() -> MotionScript {
    let rods: Vec<String> = (0..PADDLES)
        .map(|rod| {
            format!(
                r#"{{"rod":{rod},"segments":[{{"velocity":{{"duration_s":4.0,"axial_m_per_s":{:.3},"angle_rad_per_s":{:.1}}}}}]}}"#,
                0.02 * (rod as f64 + 1.0),
                3.0 - rod as f64
            )
        })
        .collect();
    MotionScript::from_json(&format!(r#"{{"rods":[{}]}}"#, rods.join(","))).unwrap()
}

/// The server on a thread, until dropped.
struct Served {
    stop: Arc<AtomicBool>,
    thread: Option<std::thread::JoinHandle<()>>,
}

impl Drop for Served {
    fn drop(&mut self) {
        self.stop.store(true, Ordering::Relaxed);
        if let Some(t) = self.thread.take() {
            let _ = t.join();
        }
    }
}

fn serve(path: &Path) -> Served {
    let mut config = BoardConfig::default();
    config.mouse.self_test_us = 20_000;
    let mut board = EmulatedBoard::new(config, Box::new(moving_script())).unwrap();
    board.inject(6, Fault::Unplug).unwrap();
    // Port 1 loses bytes on the wire: the board drops the packets they cut short.
    board
        .schedule(100_000, 1, Fault::DropRate { probability: 0.05 })
        .unwrap();
    let mut server = SocketServer::bind(path).unwrap();
    let stop = Arc::new(AtomicBool::new(false));
    let flag = Arc::clone(&stop);
    let thread = std::thread::spawn(move || {
        server.run(&mut board, &flag).unwrap();
    });
    Served {
        stop,
        thread: Some(thread),
    }
}

#[test]
fn the_socket_board_shows_the_reports_it_sent() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("board.sock");
    let served = serve(&path);
    // A second client records what the server sends.
    let mut witness = SocketBoard::connect(path.clone()).unwrap();
    let done = Arc::new(AtomicBool::new(false));
    let recorder = {
        let done = Arc::clone(&done);
        std::thread::spawn(move || {
            let mut sent = BTreeMap::new();
            while !done.load(Ordering::Relaxed) {
                if let Ok(Some(r)) = witness.poll_report(Duration::from_millis(5)) {
                    sent.insert(r.sequence, (r, witness.last_timing()));
                }
            }
            sent
        })
    };
    let frames = frames(&[
        "board",
        "--socket",
        path.to_str().unwrap(),
        "--frames",
        "3",
        "--interval-ms",
        "300",
    ]);
    done.store(true, Ordering::Relaxed);
    let sent = recorder.join().unwrap();
    drop(served);
    assert_eq!(frames.len(), 3);
    for frame in &frames {
        check_frame(frame, &sent);
        assert_eq!(frame["link"], "connected");
        assert!(
            frame["board"].as_str().unwrap().contains("board.sock"),
            "{frame}"
        );
    }
    let last = &frames[2];
    // The host's counters: what arrived, and the gaps in what arrived.
    let first_seen = u64_of(&frames[0], "first_sequence");
    let span = u64_of(last, "last_sequence") - first_seen + 1;
    assert_eq!(
        u64_of(last, "received") + u64_of(last, "lost"),
        span,
        "{last}"
    );
    // The rods move, port 6 is unplugged, port 1 has dropped packets.
    for port in (0..PADDLES).filter(|&p| p != 6) {
        let p = &last["paddles"][port];
        assert_eq!(p["present"], true, "port {port}");
        assert_ne!(p["axial_counts"], 0, "port {port}: {p}");
    }
    assert_eq!(last["paddles"][6]["present"], false);
    assert!(u64_of(&last["paddles"][1], "dropped") > 0, "{last}");
}

#[test]
fn no_emulator_is_one_line_and_status_1() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("nobody.sock");
    let out = run(&["board", "--socket", path.to_str().unwrap(), "--once"]);
    assert_eq!(out.status.code(), Some(1));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(stderr.trim_end().lines().count(), 1, "{stderr}");
    assert!(stderr.contains("no emulator answers at"), "{stderr}");
    assert!(out.stdout.is_empty());
    let out = run(&["board", "--frames", "0"]);
    assert_eq!(out.status.code(), Some(1));
}

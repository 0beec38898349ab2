//! `space-foosball board info|ports|settings|set|bootloader` end to end, on the
//! built-in emulated board: what the commands print (JSON and text) is checked
//! against a lockstep twin of that board asked the same Feature reports (the
//! emulation is deterministic, and the command powers its board up for exactly
//! 1000 ms of emulated time); `set` must read the new value back; bad keys and values,
//! the socket board and `--serial` with the emulated board are one line on stderr and
//! exit status 1.

use std::process::Output;
use std::time::Duration;

use board_link::{Board, FeaturePipe};
use foosball_protocol::{PortCounters, PADDLES, SAMPLE_RATES};
use foosball_sim::motion::live::LiveLimits;
use foosball_sim::{BoardConfig, InProcessBoard, Pacing};
use serde_json::Value;

mod common;

use common::run;

/// The emulated board as the command opens it: the game's configuration, lockstep,
/// 1000 ms after power-up.
fn twin() -> InProcessBoard {
    let (mut board, _live) = InProcessBoard::live(
        BoardConfig::default(),
        LiveLimits::default(),
        Pacing::Lockstep,
    )
    .unwrap();
    for _ in 0..1_000 {
        board.poll_report(Duration::ZERO).unwrap();
    }
    board
}

fn stdout(out: &Output) -> String {
    String::from_utf8(out.stdout.clone()).expect("utf-8")
}

fn stderr(out: &Output) -> String {
    String::from_utf8_lossy(&out.stderr).into_owned()
}

/// `space-foosball board ARGS --board emulated`, which must succeed.
fn board_ok(args: &[&str]) -> Output {
    let mut all = vec!["board"];
    all.extend(args);
    all.extend(["--board", "emulated"]);
    let out = run(&all);
    assert!(
        out.status.success(),
        "board {args:?} failed: {}",
        stderr(&out)
    );
    out
}

/// The one JSON object `space-foosball board ARGS --board emulated --json` prints.
fn board_json(args: &[&str]) -> Value {
    let mut all = args.to_vec();
    all.push("--json");
    let text = stdout(&board_ok(&all));
    assert_eq!(
        text.lines().count(),
        1,
        "one JSON object on one line: {text}"
    );
    serde_json::from_str(&text).unwrap_or_else(|e| panic!("{e}: {text}"))
}

/// Runs `space-foosball board ARGS`, which must fail with status 1 and one line on
/// stderr; returns that line.
fn board_fails(args: &[&str]) -> String {
    let mut all = vec!["board"];
    all.extend(args);
    let out = run(&all);
    let err = stderr(&out);
    assert_eq!(out.status.code(), Some(1), "board {args:?}: {err}");
    assert_eq!(err.trim_end().lines().count(), 1, "{err}");
    assert!(err.starts_with("space-foosball: error: "), "{err}");
    assert!(!err.contains("panicked"), "{err}");
    assert!(out.stdout.is_empty(), "{}", stdout(&out));
    err
}

fn counters_json(c: &PortCounters) -> Value {
    serde_json::json!({
        "frames": c.frames,
        "packets": c.packets,
        "framing_errors": c.framing_errors,
        "parity_errors": c.parity_errors,
        "resends": c.resends,
        "dropped": c.dropped,
        "retries": c.retries,
        "absences": c.absences,
        "inits": c.inits,
        "restarts": c.restarts,
        "fifo_stalls": c.fifo_stalls,
        "line_faults": c.line_faults,
    })
}

#[test]
fn info_is_what_the_board_answers() {
    let expected = twin().device_info().unwrap();
    let info = board_json(&["info"]);
    assert_eq!(info["board"], "emulated (in-process, lockstep)", "{info}");
    assert_eq!(info["serial_number"], "EMULATED");
    let [major, minor, patch] = expected.firmware_version;
    assert_eq!(info["firmware_version"], format!("{major}.{minor}.{patch}"));
    assert_eq!(
        info["git_hash"],
        String::from_utf8(expected.git_hash.to_vec()).unwrap()
    );
    assert_eq!(info["reset_reason"], "power-on");
    assert_eq!(info["uptime_us"], expected.uptime_us);
    assert_eq!(info["uptime_us"], 1_000_000);
    let present: Vec<u64> = (0..8)
        .filter(|p| expected.present_ports & (1 << p) != 0)
        .collect();
    assert_eq!(info["present_ports"], serde_json::json!(present));
    assert_eq!(present.len(), PADDLES, "every mouse past its self-test");

    let text = stdout(&board_ok(&["info"]));
    for part in [
        "serial number:  EMULATED",
        "reset reason:   power-on",
        "uptime:         1.000 s",
        "mice present:   0 1 2 3 4 5 6 7 (8 of 8)",
        &format!("firmware:       {major}.{minor}.{patch} (git emulated????)"),
    ] {
        assert!(text.contains(part), "{part:?} missing:\n{text}");
    }
}

#[test]
fn ports_show_every_counter_and_the_port_settings() {
    let mut board = twin();
    let settings = board.settings().unwrap();
    let ports = board_json(&["ports"]);
    let shown = ports["ports"].as_array().expect("ports");
    assert_eq!(shown.len(), PADDLES, "{ports}");
    for (port, p) in shown.iter().enumerate() {
        let diag = board.port_diagnostics(port as u8).unwrap();
        assert_eq!(p["port"], port, "{p}");
        assert_eq!(p["present"], diag.present, "{p}");
        assert_eq!(p["device_id"], serde_json::json!(diag.device_id), "{p}");
        assert_eq!(p["counters"], counters_json(&diag.counters), "port {port}");
        assert_eq!(p["sample_rate"], settings.ports[port].sample_rate);
        assert_eq!(p["resolution_code"], settings.ports[port].resolution_code);
        assert_eq!(p["counts_per_mm"], 8);
        assert!(diag.present && diag.counters.frames > 0, "{diag:?}");
    }
    // `diag` is the same command; the text has one column per port, one row per figure.
    let text = stdout(&board_ok(&["diag"]));
    let frames = board.port_diagnostics(0).unwrap().counters.frames;
    let row = text
        .lines()
        .find(|l| l.starts_with("frames"))
        .unwrap_or_else(|| panic!("no frames row:\n{text}"));
    assert_eq!(row.split_whitespace().count(), 1 + PADDLES, "{row}");
    assert!(row.contains(&frames.to_string()), "{row}");
    for label in [
        "mouse",
        "device id",
        "samples/s",
        "counts/mm",
        "packets",
        "framing errors",
        "parity errors",
        "resends",
        "dropped",
        "retries",
        "absences",
        "inits",
        "restarts",
        "fifo stalls",
        "line faults",
    ] {
        assert!(
            text.lines().any(|l| l.starts_with(label)),
            "no {label} row:\n{text}"
        );
    }
}

#[test]
fn settings_are_printed_per_port() {
    let settings = twin().settings().unwrap();
    let json = board_json(&["settings"]);
    let ports = json["ports"].as_array().expect("ports");
    assert_eq!(ports.len(), PADDLES);
    for (port, p) in ports.iter().enumerate() {
        let s = settings.ports[port];
        assert_eq!(p["port"], port);
        assert_eq!(p["axial_is_y"], s.axial_is_y);
        assert_eq!(p["invert_axial"], s.invert_axial);
        assert_eq!(p["invert_rotation"], s.invert_rotation);
        assert_eq!(p["resolution_code"], s.resolution_code);
        assert_eq!(p["sample_rate"], s.sample_rate);
    }
    let text = stdout(&board_ok(&["settings"]));
    let rows = text
        .lines()
        .filter(|l| l.ends_with(&format!("{}/s", settings.ports[0].sample_rate)))
        .count();
    assert_eq!(rows, PADDLES, "{text}");
}

#[test]
fn set_writes_and_reads_the_value_back() {
    let set = board_json(&["set", "port.3.sample_rate", "100"]);
    assert_eq!(set["key"], "port.3.sample_rate");
    assert_eq!(set["old"], 200);
    assert_eq!(set["new"], 100);
    assert_eq!(set["read_back"], 100);
    let ports = set["settings"].as_array().expect("settings read back");
    for (port, p) in ports.iter().enumerate() {
        let rate = if port == 3 { 100 } else { 200 };
        assert_eq!(p["sample_rate"], rate, "port {port}");
    }
    let set = board_json(&["set", "port.6.invert_rotation", "true"]);
    assert_eq!(
        (&set["old"], &set["read_back"]),
        (&false.into(), &true.into())
    );
    assert_eq!(set["settings"][6]["invert_rotation"], true);
    assert_eq!(set["settings"][5]["invert_rotation"], false);
    let text = stdout(&board_ok(&["set", "port.0.resolution_code", "1"]));
    assert!(
        text.contains("port.0.resolution_code 3 -> 1 (read back"),
        "{text}"
    );
}

#[test]
fn a_bad_key_or_value_names_the_problem() {
    let e = board_fails(&["set", "port.3.colour", "1", "--board", "emulated"]);
    assert!(
        e.contains("\"port.3.colour\"") && e.contains("sample_rate"),
        "{e}"
    );
    let e = board_fails(&["set", "port.8.sample_rate", "100", "--board", "emulated"]);
    assert!(
        e.contains("port.8.sample_rate") && e.contains("0 to 7"),
        "{e}"
    );
    let rates: Vec<String> = SAMPLE_RATES.iter().map(u8::to_string).collect();
    for bad in ["150", "-5", "fast", "300"] {
        let e = board_fails(&["set", "port.3.sample_rate", bad, "--board", "emulated"]);
        assert!(
            e.contains("port.3.sample_rate") && e.contains(bad) && e.contains(&rates.join(", ")),
            "{e}"
        );
    }
    let e = board_fails(&["set", "port.2.resolution_code", "4", "--board", "emulated"]);
    assert!(
        e.contains("port.2.resolution_code") && e.contains("0 to 3"),
        "{e}"
    );
    let e = board_fails(&["set", "port.2.axial_is_y", "maybe", "--board", "emulated"]);
    assert!(e.contains("true or false"), "{e}");
}

#[test]
fn bootloader_takes_the_emulated_board_off_the_bus() {
    let json = board_json(&["bootloader"]);
    assert_eq!(json["entered_bootloader"], true, "{json}");
    assert_eq!(json["emulated"], true);
    assert!(json["left_bus_after_ms"].as_u64().is_some(), "{json}");
    let text = stdout(&board_ok(&["bootloader"]));
    assert!(
        text.contains("restarted into its USB bootloader: it left the bus"),
        "{text}"
    );
}

#[test]
fn boards_that_cannot_answer_say_why() {
    let dir = tempfile::tempdir().unwrap();
    let socket = dir.path().join("board.sock");
    let socket = socket.to_str().unwrap();
    for command in ["info", "ports", "settings", "bootloader"] {
        let e = board_fails(&[command, "--socket", socket]);
        assert!(
            e.contains("the socket link carries IN/OUT reports only"),
            "{e}"
        );
    }
    let e = board_fails(&["set", "port.0.sample_rate", "100", "--board", "socket"]);
    assert!(e.contains("IN/OUT reports only"), "{e}");
    let e = board_fails(&["info", "--board", "emulated", "--serial", "E661"]);
    assert!(e.contains("--serial E661") && e.contains("USB"), "{e}");
    // The live view's options do not go with the other commands.
    let e = board_fails(&["--once", "info", "--board", "emulated"]);
    assert!(e.contains("live view"), "{e}");
}

#[test]
fn the_live_view_is_still_the_default() {
    for args in [
        &["board", "--board", "emulated", "--once", "--json"][..],
        &[
            "board", "live", "--board", "emulated", "--once", "--format", "json",
        ],
    ] {
        let out = run(args);
        assert!(out.status.success(), "{args:?}: {}", stderr(&out));
        let text = stdout(&out);
        assert_eq!(text.lines().count(), 1, "{text}");
        let frame: Value = serde_json::from_str(&text).unwrap();
        assert_eq!(frame["link"], "connected", "{frame}");
        assert_eq!(frame["paddles"].as_array().map(Vec::len), Some(PADDLES));
    }
}

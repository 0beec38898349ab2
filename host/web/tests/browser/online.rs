//! The page against a desktop process, online: `matchbox_server` (the signalling server)
//! on 127.0.0.1, `space-foosball host --room` (built with `enhanced-determinism`, the
//! page's math) spinning Home's rods from a script, and the page joining the same room
//! as Away. Both must end on the same state, bit for bit, with no desync, and on the
//! state of the offline run of the inputs they played. Then the page times its own
//! rollbacks of eight frames and the test prints the figure.
//!
//! The desktop program and the server come from `$SPACE_FOOSBALL_DETERMINISTIC_BIN` and
//! `$MATCHBOX_SERVER` (the web step of `scripts/test-all` builds and installs them).

use super::open_with;
use serde_json::Value;
use std::io::Read;
use std::net::{TcpListener, TcpStream};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

/// Chromium's WebRTC on one machine: plain host candidates (not mDNS names a native peer
/// cannot resolve), loopback allowed.
const WEBRTC_FLAGS: [&str; 2] = [
    "--disable-features=WebRtcHideLocalIpsWithMdns",
    "--allow-loopback-in-peer-connection",
];

/// A child process killed when the test ends, however it ends.
struct Killed(Child);

impl Drop for Killed {
    fn drop(&mut self) {
        let _ = self.0.kill();
        let _ = self.0.wait();
    }
}

fn program(var: &str, what: &str) -> PathBuf {
    let path = std::env::var_os(var)
        .map(PathBuf::from)
        .unwrap_or_else(|| panic!("set ${var} to {what} (scripts/test-all's web step does)"));
    assert!(path.is_file(), "${var}: no file {}", path.display());
    path
}

fn free_port() -> u16 {
    TcpListener::bind("127.0.0.1:0")
        .unwrap()
        .local_addr()
        .unwrap()
        .port()
}

/// Starts the signalling server on a free port of 127.0.0.1; its `ws://` address.
fn signalling_server() -> (Killed, String) {
    let port = free_port();
    let child = Command::new(program("MATCHBOX_SERVER", "matchbox_server"))
        .arg(format!("127.0.0.1:{port}"))
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .expect("starting matchbox_server");
    let started = Instant::now();
    while TcpStream::connect(("127.0.0.1", port)).is_err() {
        assert!(
            started.elapsed() < Duration::from_secs(20),
            "matchbox_server did not listen on port {port}"
        );
        std::thread::sleep(Duration::from_millis(50));
    }
    (Killed(child), format!("ws://127.0.0.1:{port}"))
}

#[test]
#[ignore = "needs the wasm bundle, Chromium, matchbox_server and a desktop build: run by the web step of scripts/test-all"]
fn the_page_plays_a_desktop_through_the_signalling_server_and_times_its_rollbacks() {
    let dir = tempfile::tempdir().unwrap();
    let (_server, signal) = signalling_server();
    let (room, seed, frames) = ("browser-test", "5", "480");
    let bin = program(
        "SPACE_FOOSBALL_DETERMINISTIC_BIN",
        "space-foosball built with --features space-foosball/enhanced-determinism",
    );
    let recording = dir.path().join("online.json");
    let desktop = Command::new(&bin)
        .args(["host", "--room", room, "--signal", &signal])
        .args(["--seed", seed, "--max-frames", frames, "--script"])
        // Home's rods held for 1 s, then spun (the tests' committed motion script).
        .arg(Path::new(env!("CARGO_MANIFEST_DIR")).join("../../sim/scripts/spin-home.json"))
        .arg("--record")
        .arg(&recording)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("starting the desktop program");
    let mut desktop = Killed(desktop);
    let mut b = open_with(
        &format!("room={room}&signal={signal}&seed={seed}&frames={frames}"),
        &WEBRTC_FLAGS,
    );
    let s = b.wait_for(
        "spaceFoosball.status().online",
        240.0,
        "the match's end",
        |v| matches!(v["stage"].as_str(), Some("over" | "stopped")),
    );
    assert_eq!(s["stage"], "over", "the page's online match: {s}");
    let started = Instant::now();
    let status = loop {
        if let Some(status) = desktop.0.try_wait().unwrap() {
            break status;
        }
        assert!(
            started.elapsed() < Duration::from_secs(60),
            "the desktop side did not end"
        );
        std::thread::sleep(Duration::from_millis(100));
    };
    let (mut out, mut err) = (String::new(), String::new());
    desktop
        .0
        .stdout
        .take()
        .unwrap()
        .read_to_string(&mut out)
        .unwrap();
    desktop
        .0
        .stderr
        .take()
        .unwrap()
        .read_to_string(&mut err)
        .unwrap();
    assert!(status.success(), "the desktop side: {err}\n{out}");
    let theirs: Value = serde_json::from_str(out.lines().last().unwrap_or("")).unwrap();
    eprintln!("desktop: {theirs}\npage: {s}");
    assert_eq!(theirs["event"], "OnlineOver", "{out}");
    assert_eq!(s["side"], "away");
    for key in ["frames", "score", "state_hash", "match_over"] {
        assert_eq!(
            s[key], theirs[key],
            "{key}: the page {s}, the desktop {theirs}"
        );
    }
    assert_eq!(
        (s["desyncs"].as_u64(), theirs["desyncs"].as_u64()),
        (Some(0), Some(0))
    );
    assert!(s["ping_ms"].is_u64(), "{s}");
    assert_eq!(theirs["frames"].as_u64(), Some(480));
    // The offline run of the inputs both played ends on the same state.
    let replay = Command::new(&bin)
        .args([
            "replay",
            "--home",
            "player",
            "--away",
            "player",
            "--state-hash",
        ])
        .arg(&recording)
        .output()
        .unwrap();
    assert!(
        replay.status.success(),
        "{}",
        String::from_utf8_lossy(&replay.stderr)
    );
    let text = String::from_utf8(replay.stdout).unwrap();
    let offline: Value = serde_json::from_str(text.lines().last().unwrap_or("")).unwrap();
    assert_eq!(
        offline["state_hash"], s["state_hash"],
        "offline run {offline}"
    );

    let f = b.eval("spaceFoosball.benchRollback(10)");
    assert!(f.get("error").is_none(), "{f}");
    let ms = f["rollback_ms_median"].as_f64().expect("a figure");
    println!(
        "rollback of {} frames ({} steps) in the browser: median {ms:.2} ms, worst {:.2} ms; \
         save {:.0} µs, restore {:.0} µs (median of {})",
        f["frames"],
        f["steps"],
        f["rollback_ms_worst"].as_f64().unwrap_or(f64::NAN),
        f["save_us_median"].as_f64().unwrap_or(f64::NAN),
        f["restore_us_median"].as_f64().unwrap_or(f64::NAN),
        f["repeats"]
    );
    assert!(ms > 0.0 && ms.is_finite(), "{f}");
}

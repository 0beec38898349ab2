//! The real `sim serve` process behind a `board_link::SocketBoard`: reports flow, and
//! keep flowing after the emulator process is killed and restarted.

use board_link::{Board, BoardError, SocketBoard};
use foosball_protocol::{LedState, OutReport};
use std::path::Path;
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

struct Emulator(Child);

impl Emulator {
    fn start(socket: &Path) -> Self {
        let child = Command::new(env!("CARGO_BIN_EXE_sim"))
            .args(["serve", "--socket"])
            .arg(socket)
            .args(["--self-test-ms", "100"])
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .spawn()
            .expect("start sim serve");
        Self(child)
    }

    fn kill(&mut self) {
        self.0.kill().expect("kill sim serve");
        self.0.wait().expect("reap sim serve");
    }
}

impl Drop for Emulator {
    fn drop(&mut self) {
        let _ = self.0.kill();
        let _ = self.0.wait();
    }
}

/// Polls until `n` reports arrived (in order, no gaps), or panics after `limit`.
fn receive(board: &mut SocketBoard, n: usize, limit: Duration) -> Vec<u16> {
    let deadline = Instant::now() + limit;
    let mut sequences = Vec::new();
    while sequences.len() < n {
        assert!(
            Instant::now() < deadline,
            "only {} of {n} reports within {limit:?} (state {:?}, last error {:?})",
            sequences.len(),
            board.link_state(),
            board.last_connect_error()
        );
        match board.poll_report(Duration::from_millis(20)) {
            Ok(Some(report)) => sequences.push(report.sequence),
            Ok(None) | Err(BoardError::Disconnected) => {}
            Err(e) if e.is_link_down() => {}
            Err(e) => panic!("unexpected error: {e}"),
        }
    }
    sequences
}

#[test]
fn socket_board_survives_emulator_kill_and_restart() {
    let dir = tempfile::tempdir().unwrap();
    let socket = dir.path().join("run").join("board.sock");
    let mut emulator = Emulator::start(&socket);
    let mut board = SocketBoard::new(&socket);
    board.set_retry_interval(Duration::from_millis(20));

    let first = receive(&mut board, 200, Duration::from_secs(20));
    assert!(
        first.windows(2).all(|w| w[1] == w[0].wrapping_add(1)),
        "gaps: {first:?}"
    );
    assert!(board.link_state().is_connected());
    let out = OutReport {
        led: LedState::On,
        ..OutReport::default()
    };
    board.send(&out).unwrap();

    // Kill the emulator: the link goes down, polls report it without panicking.
    emulator.kill();
    let deadline = Instant::now() + Duration::from_secs(5);
    loop {
        match board.poll_report(Duration::from_millis(20)) {
            Err(e) if e.is_link_down() => break,
            Ok(_) => {}
            Err(e) => panic!("unexpected error: {e}"),
        }
        assert!(Instant::now() < deadline, "link never reported down");
    }
    assert!(!board.link_state().is_connected());
    assert!(board.send(&out).is_err());

    // Restart it on the same path (the killed one left its socket file behind).
    assert!(socket.exists());
    let _emulator = Emulator::start(&socket);
    let second = receive(&mut board, 200, Duration::from_secs(20));
    assert!(
        second.windows(2).all(|w| w[1] == w[0].wrapping_add(1)),
        "gaps: {second:?}"
    );
    // A new emulator counts from the start again.
    assert!(second[0] < 1000, "{second:?}");
    assert!(board.link_state().is_connected());
    let stats = board.stats();
    assert_eq!(stats.reconnects, 1, "{stats:?}");
    assert_eq!(stats.lost, 0, "{stats:?}");
    assert!(stats.received >= 400, "{stats:?}");
    board.send(&out).unwrap();
}

#[test]
fn the_demo_script_is_valid() {
    let script = concat!(env!("CARGO_MANIFEST_DIR"), "/scripts/demo.json");
    let out = Command::new(env!("CARGO_BIN_EXE_sim"))
        .args(["check-script", script])
        .output()
        .expect("run sim");
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{stdout} {}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(
        stdout.contains("valid; motion lasts 3.100 s; 4 fault(s)"),
        "{stdout}"
    );
}

#[test]
fn serve_rejects_bad_arguments_clearly() {
    let run = |args: &[&str]| {
        let out = Command::new(env!("CARGO_BIN_EXE_sim"))
            .args(args)
            .output()
            .expect("run sim");
        assert!(!out.status.success(), "{args:?} succeeded");
        let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
        assert!(!stderr.contains("panicked"), "{stderr}");
        stderr
    };
    let dir = tempfile::tempdir().unwrap();
    let sock = dir.path().join("s.sock");
    let sock = sock.to_str().unwrap();
    let e = run(&["serve", "--socket", sock, "--resolution", "3"]);
    assert!(e.contains("--resolution must be 1, 2, 4 or 8"), "{e}");
    let e = run(&["serve", "--socket", sock, "--clock-khz", "20"]);
    assert!(e.contains("10–16.7"), "{e}");
    let e = run(&["serve", "--socket", sock, "--parity-error-rate", "2"]);
    assert!(e.contains("probability"), "{e}");
    let e = run(&["serve", "--socket", sock, "--unplugged", "9"]);
    assert!(e.contains("port 9"), "{e}");
    let bad = dir.path().join("bad.json");
    std::fs::write(
        &bad,
        r#"{"rods":[{"rod":0,"segments":[{"hold":{"duration_s":0}}]}]}"#,
    )
    .unwrap();
    let e = run(&["serve", "--socket", sock, "--script", bad.to_str().unwrap()]);
    assert!(e.contains("segment 0") && e.contains("duration_s"), "{e}");
    let e = run(&["check-script", "/nonexistent.json"]);
    assert!(e.contains("/nonexistent.json"), "{e}");
    let e = run(&["bench", "--seconds", "0"]);
    assert!(e.contains("0.001–3600"), "{e}");
}

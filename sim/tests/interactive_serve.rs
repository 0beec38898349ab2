//! Playing a separate `sim serve --interactive` process by hand: characters typed on
//! its standard input (a pipe here, a terminal for a person) move the rods that a
//! `board_link::SocketBoard` reads, with the game's key map.
//!
//! Expected counts come from the rod motion: at the default 8 counts/mm and an 8 mm rod
//! surface radius, a slide of `x` m is `8000·x` counts and a turn of `θ` rad is
//! `64·θ` counts; the sensor model keeps the sum within half a count of the motion, so
//! sums are checked to ±1 count.

use board_link::{Board, BoardError, SocketBoard};
use foosball_protocol::{PaddleStatus, PADDLES};
use foosball_sim::interactive::hands::{HALF_TRAVEL_M, SLIDE_STEP_M};
use std::f64::consts::TAU;
use std::io::{BufRead, BufReader, Write};
use std::path::Path;
use std::process::{Child, ChildStdin, Command, Stdio};
use std::sync::mpsc;
use std::time::{Duration, Instant};

/// Counts per metre of slide.
const COUNTS_PER_M: f64 = 8000.0;
/// Counts per radian of turn (8 mm radius × 8 counts/mm).
const COUNTS_PER_RAD: f64 = 64.0;
/// Longest wait for anything; reached only when a test fails.
const PATIENCE: Duration = Duration::from_secs(30);

/// A `sim serve` process whose stderr lines arrive on a channel.
struct Emulator {
    child: Child,
    lines: mpsc::Receiver<String>,
}

impl Emulator {
    fn start(socket: &Path, extra: &[&str]) -> Self {
        let mut child = Command::new(env!("CARGO_BIN_EXE_sim"))
            .args(["serve", "--self-test-ms", "100", "--socket"])
            .arg(socket)
            .args(extra)
            .stdin(Stdio::piped())
            .stdout(Stdio::null())
            .stderr(Stdio::piped())
            .spawn()
            .expect("start sim serve");
        let stderr = child.stderr.take().unwrap();
        let (tx, lines) = mpsc::channel();
        std::thread::spawn(move || {
            for line in BufReader::new(stderr).lines().map_while(Result::ok) {
                if tx.send(line).is_err() {
                    return;
                }
            }
        });
        Self { child, lines }
    }

    /// Waits for a stderr line containing `text`; returns every line up to it.
    fn wait_for_line(&self, text: &str) -> Vec<String> {
        let deadline = Instant::now() + PATIENCE;
        let mut seen = Vec::new();
        loop {
            let left = deadline.saturating_duration_since(Instant::now());
            match self.lines.recv_timeout(left) {
                Ok(line) => {
                    let found = line.contains(text);
                    seen.push(line);
                    if found {
                        return seen;
                    }
                }
                Err(_) => panic!("no stderr line with {text:?}; saw {seen:?}"),
            }
        }
    }

    fn keys(&mut self) -> &mut ChildStdin {
        self.child.stdin.as_mut().unwrap()
    }

    fn type_keys(&mut self, keys: &str) {
        self.keys().write_all(keys.as_bytes()).unwrap();
        self.keys().flush().unwrap();
    }
}

impl Drop for Emulator {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

/// The rods as the game sees them: counts summed over every report.
#[derive(Default)]
struct Rods {
    axial: [i64; PADDLES],
    rotation: [i64; PADDLES],
    /// Largest axial sum seen, per port.
    peak_axial: [i64; PADDLES],
    all_present: bool,
}

impl Rods {
    /// Polls `board` for `duration`, summing the counts.
    fn follow(&mut self, board: &mut SocketBoard, duration: Duration) {
        let until = Instant::now() + duration;
        while Instant::now() < until {
            match board.poll_report(Duration::from_millis(20)) {
                Ok(Some(report)) => {
                    for (port, paddle) in report.paddles.iter().enumerate() {
                        self.axial[port] += i64::from(paddle.axial);
                        self.rotation[port] += i64::from(paddle.rotation);
                        self.peak_axial[port] = self.peak_axial[port].max(self.axial[port]);
                    }
                    self.all_present = report
                        .paddles
                        .iter()
                        .all(|p| p.status.contains(PaddleStatus::PRESENT));
                }
                Ok(None) => {}
                Err(BoardError::Disconnected) => {}
                Err(e) => panic!("poll failed: {e}"),
            }
        }
    }
}

fn connect(socket: &Path) -> SocketBoard {
    let deadline = Instant::now() + PATIENCE;
    loop {
        match SocketBoard::connect(socket) {
            Ok(board) => return board,
            Err(e) => {
                assert!(Instant::now() < deadline, "cannot connect: {e}");
                std::thread::sleep(Duration::from_millis(20));
            }
        }
    }
}

fn assert_counts(what: &str, actual: i64, expected_counts: f64) {
    assert!(
        (actual as f64 - expected_counts).abs() <= 1.0,
        "{what}: {actual} counts, expected {expected_counts:.1} ± 1"
    );
}

#[test]
fn keys_piped_to_sim_serve_interactive_move_the_rods_a_socket_board_reads() {
    let dir = tempfile::tempdir().unwrap();
    let socket = dir.path().join("board.sock");
    let mut emulator = Emulator::start(&socket, &["--interactive"]);
    let start = emulator.wait_for_line("keys drive Home rod 1");
    assert!(
        start.iter().any(|l| l.contains("Enter push")),
        "the help line: {start:?}"
    );
    let mut board = connect(&socket);
    let mut rods = Rods::default();
    let started = Instant::now();
    while !rods.all_present {
        assert!(started.elapsed() < PATIENCE, "sensors never all present");
        rods.follow(&mut board, Duration::from_millis(50));
    }
    let lost_before = board.stats().lost;

    // Enter: Home's goalkeeper (port 0) pushed to its far stop, then back.
    emulator.type_keys("\n");
    rods.follow(&mut board, Duration::from_millis(800));
    assert_counts(
        "push peak, port 0",
        rods.peak_axial[0],
        HALF_TRAVEL_M[0] * COUNTS_PER_M,
    );
    assert_counts("after the push, port 0", rods.axial[0], 0.0);

    // 2, W W W: Home's defence (port 1) slid three steps away.
    emulator.type_keys("2www");
    emulator.wait_for_line("keys drive Home rod 2 (defence, port 1)");
    rods.follow(&mut board, Duration::from_millis(600));
    assert_counts(
        "slide, port 1",
        rods.axial[1],
        3.0 * SLIDE_STEP_M * COUNTS_PER_M,
    );

    // Space: a kick, one full turn forward (negative in the paddle frame).
    emulator.type_keys(" ");
    rods.follow(&mut board, Duration::from_millis(600));
    assert_counts("kick, port 1", rods.rotation[1], -TAU * COUNTS_PER_RAD);

    // Tab, then S: Away's goalkeeper (port 7) slid one step towards its player.
    emulator.type_keys("\ts");
    emulator.wait_for_line("keys drive Away rod 1 (goalkeeper, port 7)");
    rods.follow(&mut board, Duration::from_millis(600));
    assert_counts("slide, port 7", rods.axial[7], -SLIDE_STEP_M * COUNTS_PER_M);

    // The rods nobody drove did not move.
    for port in [2, 3, 4, 5, 6] {
        assert_eq!(
            (rods.axial[port], rods.rotation[port]),
            (0, 0),
            "port {port}"
        );
    }
    assert_eq!(rods.rotation[0], 0);
    assert_eq!(
        board.stats().lost,
        lost_before,
        "reports lost while driving: counts would be missing"
    );

    // q: the server stops and removes its socket.
    emulator.type_keys("q");
    let deadline = Instant::now() + PATIENCE;
    let status = loop {
        if let Some(status) = emulator.child.try_wait().unwrap() {
            break status;
        }
        assert!(Instant::now() < deadline, "sim serve did not stop on q");
        std::thread::sleep(Duration::from_millis(20));
    };
    assert!(status.success(), "{status}");
    assert!(!socket.exists());
}

#[test]
fn serve_without_motion_says_the_rods_sit_still_and_how_to_drive_them() {
    let dir = tempfile::tempdir().unwrap();
    let socket = dir.path().join("board.sock");
    let emulator = Emulator::start(&socket, &[]);
    let lines = emulator.wait_for_line("sit still");
    let notice = lines.last().unwrap();
    assert!(
        notice.contains("--interactive") && notice.contains("--script"),
        "{notice}"
    );
}

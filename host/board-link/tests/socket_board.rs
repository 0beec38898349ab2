//! `SocketBoard` against an in-test emulator server on a temporary socket path.
//!
//! Timeouts are generous upper bounds only: no test depends on timing.

use std::io::{ErrorKind, Read, Write};
use std::os::unix::net::UnixListener;
use std::path::{Path, PathBuf};
use std::sync::mpsc::{self, Receiver, Sender};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use board_link::socket_wire::{bind_listener, FrameReader, Message, WireError};
use board_link::{Board, BoardError, LinkState, SocketBoard};
use foosball_protocol::{
    DecodeError, HapticPulse, InReport, LedState, OutReport, FORMAT_VERSION, IN_REPORT_LEN,
};

/// Upper bound for anything to happen; only reached when a test fails.
const PATIENCE: Duration = Duration::from_secs(30);
const POLL: Duration = Duration::from_secs(5);

enum Command {
    /// Write these bytes to the client.
    Write(Vec<u8>),
    /// Close the connection and the listener (the emulator process dies).
    Close,
}

/// What the server received from the client.
#[derive(Debug, PartialEq)]
enum Seen {
    Hello(u8),
    Out(OutReport),
}

/// A one-connection emulator server on its own thread.
struct Server {
    commands: Sender<Command>,
    seen: Receiver<Seen>,
    thread: Option<JoinHandle<()>>,
}

impl Server {
    /// Listens on `path`; greets the client with `hello` (raw bytes) on connection.
    fn start_with_hello(path: &Path, hello: Vec<u8>) -> Self {
        let listener = bind_listener(path).expect("bind the test socket");
        let (commands, command_rx) = mpsc::channel();
        let (seen_tx, seen) = mpsc::channel();
        let thread = std::thread::spawn(move || serve(listener, hello, command_rx, seen_tx));
        Self {
            commands,
            seen,
            thread: Some(thread),
        }
    }

    fn start(path: &Path) -> Self {
        Self::start_with_hello(path, Message::hello().encode().unwrap())
    }

    fn write(&self, bytes: Vec<u8>) {
        self.commands.send(Command::Write(bytes)).unwrap();
    }

    fn send_reports(&self, sequences: impl IntoIterator<Item = u16>) {
        for sequence in sequences {
            self.write(Message::in_report(&report(sequence)).encode().unwrap());
        }
    }

    fn next_seen(&self) -> Seen {
        self.seen
            .recv_timeout(PATIENCE)
            .expect("server saw nothing")
    }

    /// Kills the server: connection and listener closed, thread joined.
    fn stop(mut self) {
        let _ = self.commands.send(Command::Close);
        if let Some(thread) = self.thread.take() {
            thread.join().unwrap();
        }
    }
}

impl Drop for Server {
    fn drop(&mut self) {
        let _ = self.commands.send(Command::Close);
    }
}

fn serve(listener: UnixListener, hello: Vec<u8>, commands: Receiver<Command>, seen: Sender<Seen>) {
    listener.set_nonblocking(true).unwrap();
    let started = Instant::now();
    // Commands given before the client connects are kept for after.
    let mut pending = std::collections::VecDeque::new();
    let mut stream = loop {
        match listener.accept() {
            Ok((stream, _)) => break stream,
            Err(e) if e.kind() == ErrorKind::WouldBlock => {
                while let Ok(command) = commands.try_recv() {
                    if matches!(command, Command::Close) {
                        return;
                    }
                    pending.push_back(command);
                }
                if started.elapsed() > PATIENCE {
                    return;
                }
                std::thread::sleep(Duration::from_millis(5));
            }
            Err(e) => panic!("accept: {e}"),
        }
    };
    stream.set_nonblocking(false).unwrap();
    stream
        .set_read_timeout(Some(Duration::from_millis(5)))
        .unwrap();
    stream.write_all(&hello).unwrap();
    let mut reader = FrameReader::new();
    loop {
        let next = pending
            .pop_front()
            .map(Ok)
            .unwrap_or_else(|| commands.try_recv());
        match next {
            Ok(Command::Write(bytes)) => {
                if stream.write_all(&bytes).is_err() {
                    return;
                }
                continue;
            }
            Ok(Command::Close) | Err(mpsc::TryRecvError::Disconnected) => return,
            Err(mpsc::TryRecvError::Empty) => {}
        }
        let mut chunk = [0; 256];
        match stream.read(&mut chunk) {
            Ok(0) => return,
            Ok(n) => reader.push(&chunk[..n]),
            Err(e) if matches!(e.kind(), ErrorKind::WouldBlock | ErrorKind::TimedOut) => {}
            Err(_) => return,
        }
        while let Ok(Some(message)) = reader.next_message() {
            let event = match message {
                Message::Hello { version } => Seen::Hello(version),
                Message::OutReport(bytes) => Seen::Out(OutReport::decode(&bytes).unwrap()),
                Message::InReport(_) => panic!("client sent an IN report"),
            };
            let _ = seen.send(event);
        }
    }
}

fn report(sequence: u16) -> InReport {
    let mut report = InReport {
        sequence,
        ..InReport::default()
    };
    report.paddles[0].axial = sequence as i16;
    report
}

fn socket_path() -> (tempfile::TempDir, PathBuf) {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("board.sock");
    (dir, path)
}

/// Polls until a report arrives; any error fails the test.
fn next_report(board: &mut SocketBoard) -> InReport {
    let started = Instant::now();
    loop {
        match board.poll_report(POLL) {
            Ok(Some(report)) => return report,
            Ok(None) => assert!(started.elapsed() < PATIENCE, "no report arrived"),
            Err(e) => panic!("poll failed: {e}"),
        }
    }
}

/// Polls until an error; reports before it are returned.
fn poll_until_error(board: &mut SocketBoard) -> (Vec<InReport>, BoardError) {
    let started = Instant::now();
    let mut reports = Vec::new();
    loop {
        match board.poll_report(POLL) {
            Ok(Some(report)) => reports.push(report),
            Ok(None) => assert!(started.elapsed() < PATIENCE, "no error came"),
            Err(e) => return (reports, e),
        }
    }
}

#[test]
fn receives_reports_and_the_server_sees_out_reports() {
    let (_dir, path) = socket_path();
    let server = Server::start(&path);
    let mut board = SocketBoard::connect(&path).unwrap();
    assert_eq!(board.link_state(), LinkState::Connected);
    assert!(board.name().contains("board.sock"), "{}", board.name());
    assert_eq!(server.next_seen(), Seen::Hello(FORMAT_VERSION));

    server.send_reports(0..5);
    for sequence in 0..5 {
        assert_eq!(next_report(&mut board), report(sequence));
    }

    let mut out = OutReport {
        led: LedState::SlowBlink,
        ..OutReport::default()
    };
    out.haptics[5] = HapticPulse {
        strength: 255,
        duration_ms: 40,
    };
    board.send(&out).unwrap();
    assert_eq!(server.next_seen(), Seen::Out(out));

    let stats = board.stats();
    assert_eq!((stats.received, stats.lost, stats.malformed), (5, 0, 0));
    // Nothing more sent: a zero-timeout poll returns at once with nothing.
    assert!(matches!(board.poll_report(Duration::ZERO), Ok(None)));
    server.stop();
}

#[test]
fn emulator_restart_disconnects_then_reconnects() {
    let (_dir, path) = socket_path();
    let server = Server::start(&path);
    let mut board = SocketBoard::connect(&path).unwrap();
    board.set_retry_interval(Duration::from_millis(10));
    server.send_reports(0..3);
    server.stop();

    let (reports, error) = poll_until_error(&mut board);
    assert_eq!(reports, (0..3).map(report).collect::<Vec<_>>());
    assert!(matches!(error, BoardError::Disconnected), "{error}");
    assert!(!board.link_state().is_connected());
    let out = OutReport::default();
    assert!(matches!(board.send(&out), Err(BoardError::Disconnected)));
    // While nothing listens, polls keep reporting Disconnected.
    assert!(matches!(
        board.poll_report(Duration::ZERO),
        Err(BoardError::Disconnected)
    ));
    assert_eq!(board.link_state(), LinkState::Reconnecting);
    assert!(board.last_connect_error().is_some());

    // The emulator comes back on the same path, with its sequence elsewhere.
    let server = Server::start(&path);
    server.send_reports(9000..9003);
    assert_eq!(next_report(&mut board), report(9000));
    assert_eq!(board.link_state(), LinkState::Connected);
    assert_eq!(next_report(&mut board).sequence, 9001);
    assert_eq!(next_report(&mut board).sequence, 9002);
    assert_eq!(server.next_seen(), Seen::Hello(FORMAT_VERSION));
    board.send(&out).unwrap();
    assert_eq!(server.next_seen(), Seen::Out(out));

    let stats = board.stats();
    assert_eq!(
        (stats.received, stats.lost, stats.reconnects),
        (6, 0, 1),
        "the jump across the reconnect is not loss"
    );
    server.stop();
}

#[test]
fn client_started_before_the_emulator_connects_when_it_appears() {
    let (_dir, path) = socket_path();
    assert!(matches!(
        SocketBoard::connect(&path),
        Err(BoardError::Io(e)) if e.kind() == ErrorKind::NotFound
    ));
    let mut board = SocketBoard::new(&path);
    board.set_retry_interval(Duration::from_millis(10));
    assert_eq!(board.link_state(), LinkState::Disconnected);
    assert!(matches!(
        board.poll_report(Duration::ZERO),
        Err(BoardError::Disconnected)
    ));
    assert_eq!(board.link_state(), LinkState::Reconnecting);
    assert!(board.name().contains("not connected"), "{}", board.name());

    let server = Server::start(&path);
    server.send_reports([42, 44]);
    assert_eq!(next_report(&mut board).sequence, 42);
    assert_eq!(next_report(&mut board).sequence, 44);
    let stats = board.stats();
    assert_eq!((stats.lost, stats.reconnects), (1, 0));
    server.stop();
}

#[test]
fn malformed_report_frames_are_dropped_and_play_goes_on() {
    let (_dir, path) = socket_path();
    let server = Server::start(&path);
    let mut board = SocketBoard::connect(&path).unwrap();
    server.send_reports([1]);
    let truncated = report(2).to_bytes()[..IN_REPORT_LEN - 3].to_vec();
    server.write(Message::InReport(truncated).encode().unwrap());
    let mut bad_status = report(2).to_bytes();
    bad_status[7] = 0xFF;
    server.write(Message::InReport(bad_status.to_vec()).encode().unwrap());
    server.send_reports([2]);

    assert_eq!(next_report(&mut board).sequence, 1);
    let (_, error) = poll_until_error(&mut board);
    assert!(
        matches!(
            error,
            BoardError::Malformed(DecodeError::WrongLength {
                expected: IN_REPORT_LEN,
                actual
            }) if actual == IN_REPORT_LEN - 3
        ),
        "{error}"
    );
    let (_, error) = poll_until_error(&mut board);
    assert!(
        matches!(
            error,
            BoardError::Malformed(DecodeError::BadField {
                field: "status",
                paddle: Some(0),
                value: 0xFF
            })
        ),
        "{error}"
    );
    assert_eq!(board.link_state(), LinkState::Connected);
    assert_eq!(next_report(&mut board).sequence, 2);
    let stats = board.stats();
    assert_eq!((stats.received, stats.malformed, stats.lost), (2, 2, 0));
    server.stop();
}

#[test]
fn broken_framing_drops_the_connection_with_a_typed_error() {
    let (_dir, path) = socket_path();
    let server = Server::start(&path);
    let mut board = SocketBoard::connect(&path).unwrap();
    server.send_reports([5]);
    server.write(vec![0xEE, 0x00]);
    assert_eq!(next_report(&mut board).sequence, 5);
    let (_, error) = poll_until_error(&mut board);
    assert!(
        matches!(error, BoardError::Wire(WireError::UnknownKind(0xEE))),
        "{error}"
    );
    assert!(!board.link_state().is_connected());
    server.stop();
}

#[test]
fn version_mismatch_is_refused() {
    let (_dir, path) = socket_path();
    let server = Server::start_with_hello(
        &path,
        Message::Hello {
            version: FORMAT_VERSION + 1,
        }
        .encode()
        .unwrap(),
    );
    let mut board = SocketBoard::connect(&path).unwrap();
    server.send_reports([1]);
    let (reports, error) = poll_until_error(&mut board);
    assert!(reports.is_empty());
    assert!(
        matches!(error, BoardError::VersionMismatch { peer, ours } if peer == FORMAT_VERSION + 1 && ours == FORMAT_VERSION),
        "{error}"
    );
    assert!(!board.link_state().is_connected());
    server.stop();
}

#[test]
fn reports_before_the_hello_are_refused() {
    let (_dir, path) = socket_path();
    let server = Server::start_with_hello(&path, Vec::new());
    let mut board = SocketBoard::connect(&path).unwrap();
    server.send_reports([1]);
    let (_, error) = poll_until_error(&mut board);
    assert!(
        matches!(error, BoardError::Wire(WireError::UnexpectedFrame { .. })),
        "{error}"
    );
    server.stop();
}

#[test]
fn boards_are_usable_as_trait_objects() {
    let (_dir, path) = socket_path();
    let server = Server::start(&path);
    let mut board: Box<dyn Board> = Box::new(SocketBoard::connect(&path).unwrap());
    server.send_reports([77]);
    let started = Instant::now();
    let report = loop {
        if let Some(report) = board.poll_report(POLL).unwrap() {
            break report;
        }
        assert!(started.elapsed() < PATIENCE);
    };
    assert_eq!(report.sequence, 77);
    assert_eq!(board.stats().received, 1);
    server.stop();
}

//! `SocketBoard::poll_report(t)` against hostile emulator peers: it returns within
//! `t + 10 ms` whatever the peer does (the bound of the board-link contract).
//!
//! Each peer is a thread on a Unix socket in a temporary directory: one floods valid
//! hello frames without pause, one sends hello frames one byte per write, one sends
//! garbage, one says nothing at all; and a server that stopped accepting connections
//! (its queue full) must not hold a poll's reconnect either.
//!
//! The bound is checked on the median of [`CALLS`] polls with `t` = [`TIMEOUT`]: the
//! median is under `t + 10 ms` only if the poll itself honours its deadline, while one
//! call that the shared test machine deschedules (the peer thread and the test share
//! two cores) cannot fail the test on its own. Before the poll checked its deadline
//! while reading, a flooding peer held every call for as long as the flood kept the
//! socket readable (up to seconds), so the median failed by far.

use std::io::Write;
use std::os::unix::net::UnixListener;
use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use board_link::socket_wire::{bind_listener, Message};
use board_link::{Board, BoardError, SocketBoard};

/// The poll timeout under test.
const TIMEOUT: Duration = Duration::from_millis(10);
/// The contract: a poll returns within its timeout plus this.
const SLACK: Duration = Duration::from_millis(10);
/// Polls measured per peer.
const CALLS: usize = 15;

/// What the peer sends after accepting the client.
#[derive(Clone, Copy)]
enum Behaviour {
    /// Its hello, then hello frames as fast as the socket takes them.
    FloodHellos,
    /// Its hello, then hello frames, one byte per write.
    OneByteAtATime,
    /// Its hello, then bytes that are no frame.
    Garbage,
    /// Nothing, ever.
    Silent,
}

struct Peer {
    stop: Arc<AtomicBool>,
    thread: Option<JoinHandle<()>>,
}

impl Peer {
    fn start(listener: UnixListener, behaviour: Behaviour) -> Self {
        let stop = Arc::new(AtomicBool::new(false));
        let flag = Arc::clone(&stop);
        let thread = std::thread::spawn(move || {
            let Ok((mut stream, _)) = listener.accept() else {
                return;
            };
            let hello = Message::hello().encode().unwrap();
            if !matches!(behaviour, Behaviour::Silent) && stream.write_all(&hello).is_err() {
                return;
            }
            let burst: Vec<u8> = match behaviour {
                Behaviour::FloodHellos | Behaviour::OneByteAtATime => hello.repeat(2048),
                Behaviour::Garbage => (0..4096u32).map(|i| (i * 37 + 0xE0) as u8).collect(),
                Behaviour::Silent => Vec::new(),
            };
            while !flag.load(Ordering::Relaxed) {
                let written = match behaviour {
                    Behaviour::FloodHellos | Behaviour::Garbage => stream.write_all(&burst),
                    Behaviour::OneByteAtATime => burst
                        .chunks(1)
                        .take(64)
                        .try_for_each(|byte| stream.write_all(byte)),
                    Behaviour::Silent => {
                        std::thread::sleep(Duration::from_millis(1));
                        Ok(())
                    }
                };
                if written.is_err() {
                    return;
                }
            }
        });
        Self {
            stop,
            thread: Some(thread),
        }
    }
}

impl Drop for Peer {
    fn drop(&mut self) {
        self.stop.store(true, Ordering::Relaxed);
        if let Some(thread) = self.thread.take() {
            let _ = thread.join();
        }
    }
}

fn socket_path() -> (tempfile::TempDir, PathBuf) {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("board.sock");
    (dir, path)
}

/// Polls [`CALLS`] times with [`TIMEOUT`] against a peer behaving as `behaviour`;
/// returns the sorted durations and the results' descriptions.
fn measure(behaviour: Behaviour) -> (Vec<Duration>, Vec<String>) {
    let (_dir, path) = socket_path();
    let listener = bind_listener(&path).unwrap();
    let peer = Peer::start(listener, behaviour);
    let mut board = SocketBoard::connect(&path).unwrap();
    let mut times = Vec::with_capacity(CALLS);
    let mut results = Vec::with_capacity(CALLS);
    for _ in 0..CALLS {
        let started = Instant::now();
        let result = board.poll_report(TIMEOUT);
        times.push(started.elapsed());
        results.push(match result {
            Ok(Some(report)) => format!("report {}", report.sequence),
            Ok(None) => "nothing".to_owned(),
            Err(BoardError::Wire(e)) => format!("wire error: {e}"),
            Err(BoardError::Disconnected) => "disconnected".to_owned(),
            Err(e) => format!("error: {e}"),
        });
    }
    drop(board);
    drop(peer);
    times.sort();
    (times, results)
}

fn assert_within_bound(behaviour: Behaviour, name: &str) -> Vec<String> {
    let (times, results) = measure(behaviour);
    let median = times[CALLS / 2];
    eprintln!("{name}: polls of {TIMEOUT:?} took {times:?}");
    assert!(
        median < TIMEOUT + SLACK,
        "{name}: median poll {median:?} with timeout {TIMEOUT:?} (bound {:?}); all {times:?}",
        TIMEOUT + SLACK
    );
    results
}

#[test]
fn a_peer_flooding_hello_frames_cannot_hold_a_poll() {
    let results = assert_within_bound(Behaviour::FloodHellos, "flooding peer");
    assert!(results.iter().all(|r| r == "nothing"), "{results:?}");
}

#[test]
fn a_peer_sending_one_byte_at_a_time_cannot_hold_a_poll() {
    let results = assert_within_bound(Behaviour::OneByteAtATime, "one-byte peer");
    assert!(results.iter().all(|r| r == "nothing"), "{results:?}");
}

#[test]
fn a_peer_sending_garbage_is_dropped_in_time() {
    let results = assert_within_bound(Behaviour::Garbage, "garbage peer");
    assert!(
        results
            .iter()
            .any(|r| r.starts_with("wire error: unknown frame kind")),
        "{results:?}"
    );
}

#[test]
fn a_silent_peer_times_out_in_time() {
    let results = assert_within_bound(Behaviour::Silent, "silent peer");
    assert!(results.iter().all(|r| r == "nothing"), "{results:?}");
}

#[test]
fn the_client_refuses_a_socket_folder_others_can_write() {
    use std::os::unix::fs::PermissionsExt;
    let (dir, path) = socket_path();
    let _listener = bind_listener(&path).unwrap();
    std::fs::set_permissions(dir.path(), std::fs::Permissions::from_mode(0o777)).unwrap();
    let error = SocketBoard::connect(&path).unwrap_err();
    assert!(
        matches!(&error, BoardError::Io(e) if e.kind() == std::io::ErrorKind::PermissionDenied),
        "{error}"
    );
    assert!(
        error.to_string().contains("writable by group or others"),
        "{error}"
    );
}

#[test]
fn a_server_that_stopped_accepting_cannot_hold_a_poll() {
    use std::os::fd::AsRawFd;
    let (_dir, path) = socket_path();
    let listener = bind_listener(&path).unwrap();
    // A backlog of 0: the kernel queues one connection, then the queue is full.
    // SAFETY: listen(2) on the listener's open socket.
    assert_eq!(unsafe { libc::listen(listener.as_raw_fd(), 0) }, 0);
    // On a thread: a blocking connect would hang there, failing the wait below.
    let (tx, rx) = std::sync::mpsc::channel();
    std::thread::spawn(move || {
        let mut queued = Vec::new();
        let full = loop {
            match SocketBoard::connect(&path) {
                Ok(board) => queued.push(board),
                Err(e) => break e,
            }
            assert!(queued.len() < 64, "the queue never filled");
        };
        let mut board = SocketBoard::new(&path);
        let mut times = Vec::with_capacity(CALLS);
        let mut results = Vec::with_capacity(CALLS);
        for _ in 0..CALLS {
            let started = Instant::now();
            let result = board.poll_report(TIMEOUT);
            times.push(started.elapsed());
            results.push(format!("{result:?}"));
        }
        let _ = tx.send((full, times, results));
    });
    let (full, mut times, results) = rx
        .recv_timeout(Duration::from_secs(30))
        .expect("connecting to a full queue hung");
    assert!(
        matches!(&full, BoardError::Io(e) if e.kind() == std::io::ErrorKind::WouldBlock),
        "{full}"
    );
    assert!(full.to_string().contains("queue is full"), "{full}");
    assert!(
        results.iter().all(|r| r == "Err(Disconnected)"),
        "{results:?}"
    );
    times.sort();
    eprintln!("full queue: polls of {TIMEOUT:?} took {times:?}");
    assert!(times[CALLS / 2] < TIMEOUT + SLACK, "{times:?}");
    drop(listener);
}

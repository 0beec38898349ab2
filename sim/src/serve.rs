//! The emulated board as its own process: reports served to the host over a
//! Unix-domain stream socket, framed by [`board_link::socket_wire`], in real time.
//!
//! The server binds with [`socket_wire::bind_listener`] (which removes the stale socket
//! file a killed server leaves behind), sends each client its hello, then an IN report
//! frame every millisecond; OUT report frames from clients go to the board. Clients can
//! come and go at any time, several at once; each gets every report. A client that
//! does not read has reports skipped (it sees the sequence gap) rather than stalling
//! the board; one that sends bad framing or a wrong version is disconnected.

use crate::board::EmulatedBoard;
use crate::pacing::RealTimePacer;
use board_link::socket_wire::{self, FrameReader, Message};
use foosball_protocol::FORMAT_VERSION;
use std::io::{self, Write};
use std::os::unix::net::{UnixListener, UnixStream};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

/// Unsent bytes a client may have queued before reports to it are skipped
/// (≈ 1400 reports, 1.4 s).
const MAX_CLIENT_BACKLOG: usize = 64 * 1024;
/// Reads (of up to 4 KiB) taken from one client per millisecond at most.
const MAX_READS_PER_TICK: usize = 16;
/// Most clients served at once; more are refused (closed at once).
pub const MAX_CLIENTS: usize = 16;

/// Why the socket server failed.
#[derive(Debug, thiserror::Error)]
pub enum ServeError {
    /// The socket could not be bound (another server listens there, no permission…).
    #[error("cannot listen on {path}: {source}")]
    Bind {
        /// The socket path.
        path: PathBuf,
        /// The cause.
        source: io::Error,
    },
    /// Accepting a connection failed.
    #[error("socket server I/O error: {0}")]
    Io(#[from] io::Error),
}

struct Client {
    stream: UnixStream,
    reader: FrameReader,
    out: Vec<u8>,
    open: bool,
    skipped: u64,
}

impl Client {
    /// Appends a frame unless the client is too far behind.
    fn queue(&mut self, frame: &[u8]) {
        if self.out.len() + frame.len() > MAX_CLIENT_BACKLOG {
            self.skipped += 1;
        } else {
            self.out.extend_from_slice(frame);
        }
    }

    fn flush(&mut self) {
        while self.open && !self.out.is_empty() {
            match self.stream.write(&self.out) {
                Ok(0) => self.open = false,
                Ok(n) => {
                    self.out.drain(..n);
                }
                Err(e) if e.kind() == io::ErrorKind::WouldBlock => break,
                Err(e) if e.kind() == io::ErrorKind::Interrupted => {}
                Err(_) => self.open = false,
            }
        }
    }
}

/// Counters of a server run.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct ServeStats {
    /// Reports produced.
    pub reports: u64,
    /// Clients accepted.
    pub clients: u64,
    /// OUT reports accepted.
    pub out_reports: u64,
    /// OUT reports rejected as malformed.
    pub out_rejected: u64,
    /// Clients dropped for bad framing or version.
    pub protocol_errors: u64,
}

/// The socket server. See the [module documentation](self).
pub struct SocketServer {
    listener: UnixListener,
    path: PathBuf,
    clients: Vec<Client>,
    hello: Vec<u8>,
    stats: ServeStats,
    verbose: bool,
}

impl SocketServer {
    /// Binds the socket at `path` (creating its directory, replacing a stale socket).
    pub fn bind(path: &Path) -> Result<Self, ServeError> {
        let listener = socket_wire::bind_listener(path).map_err(|source| ServeError::Bind {
            path: path.to_owned(),
            source,
        })?;
        listener.set_nonblocking(true)?;
        Ok(Self {
            listener,
            path: path.to_owned(),
            clients: Vec::new(),
            hello: encode(&Message::hello()),
            stats: ServeStats::default(),
            verbose: false,
        })
    }

    /// Logs connections and client errors to stderr.
    pub fn set_verbose(&mut self, verbose: bool) {
        self.verbose = verbose;
    }

    /// The socket path.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// Counters so far.
    pub fn stats(&self) -> ServeStats {
        self.stats
    }

    fn log(&self, msg: &str) {
        if self.verbose {
            // A closed stderr must not stop the board.
            let _ = writeln!(io::stderr(), "sim serve: {msg}");
        }
    }

    /// Serves `board` in real time until `stop` is set, then removes the socket file.
    pub fn run(&mut self, board: &mut EmulatedBoard, stop: &AtomicBool) -> Result<(), ServeError> {
        let mut pacer = RealTimePacer::new(100);
        while !stop.load(Ordering::Relaxed) {
            self.accept()?;
            self.read_clients(board);
            let due = pacer.due(Instant::now());
            for _ in 0..due {
                pacer.emitted();
                // The version 2 report, as the RP2040 binary sends it over USB.
                let report = board.step_report_v2().to_bytes();
                self.stats.reports += 1;
                let frame = encode(&Message::InReport(report.to_vec()));
                for client in &mut self.clients {
                    client.queue(&frame);
                }
            }
            for client in &mut self.clients {
                client.flush();
            }
            let before = self.clients.len();
            self.clients.retain(|c| c.open);
            if self.clients.len() < before {
                self.log(&format!("{} client(s) left", before - self.clients.len()));
            }
            let wait = pacer
                .next_due_at()
                .saturating_duration_since(Instant::now())
                .min(Duration::from_millis(1));
            std::thread::sleep(wait);
        }
        let _ = std::fs::remove_file(&self.path);
        Ok(())
    }

    fn accept(&mut self) -> Result<(), ServeError> {
        loop {
            match self.listener.accept() {
                Ok((stream, _)) => {
                    if self.clients.len() >= MAX_CLIENTS {
                        self.log("too many clients; refusing one");
                        continue;
                    }
                    stream.set_nonblocking(true)?;
                    let mut client = Client {
                        stream,
                        reader: FrameReader::new(),
                        out: Vec::new(),
                        open: true,
                        skipped: 0,
                    };
                    client.queue(&self.hello);
                    client.flush();
                    self.stats.clients += 1;
                    self.log("client connected");
                    self.clients.push(client);
                }
                Err(e) if e.kind() == io::ErrorKind::WouldBlock => return Ok(()),
                Err(e)
                    if matches!(
                        e.kind(),
                        io::ErrorKind::Interrupted | io::ErrorKind::ConnectionAborted
                    ) => {}
                Err(e) => return Err(e.into()),
            }
        }
    }

    fn read_clients(&mut self, board: &mut EmulatedBoard) {
        let mut logs = Vec::new();
        for client in &mut self.clients {
            // Bounded, so a client that writes without pause cannot stall the board.
            for _ in 0..MAX_READS_PER_TICK {
                match client.reader.read_from(&mut client.stream) {
                    Ok(0) => {
                        client.open = false;
                        break;
                    }
                    Ok(_) => {}
                    Err(e) if e.kind() == io::ErrorKind::WouldBlock => break,
                    Err(_) => {
                        client.open = false;
                        break;
                    }
                }
            }
            loop {
                match client.reader.next_message() {
                    Ok(None) => break,
                    Ok(Some(Message::Hello { version })) => {
                        if version != FORMAT_VERSION {
                            logs.push(format!(
                                "client speaks report format {version}, this board {FORMAT_VERSION}; disconnecting it"
                            ));
                            self.stats.protocol_errors += 1;
                            client.open = false;
                            break;
                        }
                    }
                    Ok(Some(Message::OutReport(bytes))) => match board.receive_out_report(&bytes) {
                        Ok(_) => self.stats.out_reports += 1,
                        Err(e) => {
                            self.stats.out_rejected += 1;
                            logs.push(e.to_string());
                        }
                    },
                    Ok(Some(Message::InReport(_))) => {
                        logs.push("client sent an IN report; disconnecting it".into());
                        self.stats.protocol_errors += 1;
                        client.open = false;
                        break;
                    }
                    Err(e) => {
                        logs.push(format!("bad framing from client ({e}); disconnecting it"));
                        self.stats.protocol_errors += 1;
                        client.open = false;
                        break;
                    }
                }
            }
        }
        for msg in logs {
            self.log(&msg);
        }
    }
}

fn encode(message: &Message) -> Vec<u8> {
    // Our own messages are within the framing limits (hello, 43-byte reports).
    message.encode().unwrap_or_default()
}

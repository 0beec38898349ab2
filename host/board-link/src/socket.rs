//! [`SocketBoard`]: the game's client of the emulator process over a Unix-domain socket.

use std::io;
use std::os::fd::{AsRawFd, OwnedFd};
use std::os::unix::net::UnixStream;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use foosball_protocol::{InReport, OutReport, ReportTiming, FORMAT_VERSION};
use socket2::{Domain, SockAddr, Socket, Type};

use crate::link::{Connector, Link, ReportBuf, SystemClock, Transport, TransportError};
use crate::socket_wire::{self, FrameKind, FrameReader, Message, WireError};
use crate::{Board, BoardError, LinkState, LinkStats, DEFAULT_RETRY_INTERVAL};

/// How long a send may wait for room in the socket buffer before giving up.
const SEND_TIMEOUT: Duration = Duration::from_secs(1);

/// A board served by the emulator process (`sim serve`) on a Unix-domain stream socket,
/// framed by [`socket_wire`].
///
/// The client sends a hello when it connects and requires the server's hello (same
/// [`FORMAT_VERSION`]) before any report. When the emulator goes away (end of stream,
/// socket error, bad framing) the poll reports the error ([`BoardError::Disconnected`]
/// for end of stream and errors), and later polls reconnect, at most once per retry
/// interval ([`DEFAULT_RETRY_INTERVAL`]), while honouring their timeout.
pub struct SocketBoard {
    link: Link<SocketConnector>,
}

impl SocketBoard {
    /// A board at `path`, not connected yet: the first poll connects, and polls keep
    /// trying until the emulator is there.
    pub fn new(path: impl Into<PathBuf>) -> Self {
        Self {
            link: Link::new(
                SocketConnector { path: path.into() },
                SystemClock,
                DEFAULT_RETRY_INTERVAL,
            ),
        }
    }

    /// [`SocketBoard::new`] at [`socket_wire::default_socket_path`].
    pub fn at_default_path() -> Self {
        Self::new(socket_wire::default_socket_path())
    }

    /// Connects to the emulator at `path` now, failing (typically
    /// [`BoardError::Io`] with `NotFound` or `ConnectionRefused`) if none listens there,
    /// or with `PermissionDenied` if the socket's folder is not safe to use
    /// ([`socket_wire::check_socket_dir`]).
    pub fn connect(path: impl Into<PathBuf>) -> Result<Self, BoardError> {
        let mut board = Self::new(path);
        board.link.connect_now()?;
        Ok(board)
    }

    /// The socket path.
    pub fn path(&self) -> &Path {
        &self.link.connector().path
    }

    /// How often a lost emulator is looked for again.
    pub fn retry_interval(&self) -> Duration {
        self.link.retry_interval()
    }

    /// Why the last attempt to reach the emulator failed (`NotFound`, `AccessDenied`,
    /// a refused connection, …), while it is not connected; polls meanwhile report
    /// [`BoardError::Disconnected`].
    pub fn last_connect_error(&self) -> Option<&BoardError> {
        self.link.last_connect_error()
    }

    /// Sets how often a lost emulator is looked for again.
    pub fn set_retry_interval(&mut self, interval: Duration) {
        self.link.set_retry_interval(interval);
    }
}

impl Board for SocketBoard {
    fn name(&self) -> String {
        self.link.name()
    }
    fn poll_report(&mut self, timeout: Duration) -> Result<Option<InReport>, BoardError> {
        self.link.poll_report(timeout)
    }
    fn send(&mut self, report: &OutReport) -> Result<(), BoardError> {
        self.link.send(report)
    }
    fn link_state(&self) -> LinkState {
        self.link.state()
    }
    fn stats(&self) -> LinkStats {
        self.link.stats()
    }
    fn last_timing(&self) -> Option<ReportTiming> {
        self.link.last_timing()
    }
}

impl std::fmt::Debug for SocketBoard {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("SocketBoard")
            .field("path", &self.path())
            .field("state", &self.link.state())
            .field("stats", &self.link.stats())
            .finish()
    }
}

struct SocketConnector {
    path: PathBuf,
}

impl Connector for SocketConnector {
    type Transport = SocketTransport;

    fn describe(&self) -> String {
        format!("emulated board at {} (not connected)", self.path.display())
    }

    fn connect(&mut self) -> Result<SocketTransport, BoardError> {
        // Another user's folder could hold another user's emulator.
        if let Some(dir) = socket_wire::socket_dir(&self.path) {
            socket_wire::check_socket_dir(dir)?;
        }
        let stream = connect_without_waiting(&self.path)?;
        let mut transport = SocketTransport {
            stream,
            reader: FrameReader::new(),
            got_hello: false,
            path: self.path.clone(),
        };
        let hello = Message::hello().encode()?;
        match transport.send_all(&hello) {
            Ok(()) => Ok(transport),
            Err(TransportError::Gone) => Err(BoardError::Disconnected),
            Err(TransportError::Broken(e) | TransportError::Transient(e)) => Err(e),
        }
    }
}

/// Connects a non-blocking Unix stream socket to `path` without waiting: a server
/// whose queue of unaccepted connections is full (one that stopped calling `accept`)
/// is an [`io::ErrorKind::WouldBlock`] error at once, where a blocking connect would
/// wait for it indefinitely.
fn connect_without_waiting(path: &Path) -> io::Result<UnixStream> {
    let addr = SockAddr::unix(path).map_err(|e| {
        io::Error::new(
            io::ErrorKind::InvalidInput,
            format!("socket path {} is not usable: {e}", path.display()),
        )
    })?;
    // socket2 opens it close-on-exec.
    let socket = Socket::new(Domain::UNIX, Type::STREAM, None)?;
    socket.set_nonblocking(true)?;
    if let Err(e) = socket.connect(&addr) {
        return Err(if e.kind() == io::ErrorKind::WouldBlock {
            io::Error::new(
                io::ErrorKind::WouldBlock,
                format!(
                    "the emulator at {} accepts no connections (its queue is full)",
                    path.display()
                ),
            )
        } else {
            e
        });
    }
    Ok(UnixStream::from(OwnedFd::from(socket)))
}

struct SocketTransport {
    stream: UnixStream,
    reader: FrameReader,
    got_hello: bool,
    path: PathBuf,
}

/// Whether a socket error means the peer is gone.
fn is_gone(e: &io::Error) -> bool {
    !matches!(
        e.kind(),
        io::ErrorKind::WouldBlock | io::ErrorKind::Interrupted | io::ErrorKind::TimedOut
    )
}

impl SocketTransport {
    /// Waits until the socket is readable (`POLLIN`) or writable (`POLLOUT`), at most
    /// `timeout`. `Ok(false)`: timed out.
    fn wait(&self, events: libc::c_short, timeout: Duration) -> io::Result<bool> {
        // Round up so that a sub-millisecond wait does not become a busy loop.
        let millis = timeout.as_nanos().div_ceil(1_000_000).min(i32::MAX as u128) as i32;
        let mut fd = libc::pollfd {
            fd: self.stream.as_raw_fd(),
            events,
            revents: 0,
        };
        // SAFETY: `fd` is a valid pollfd for the duration of the call, count 1.
        let ready = unsafe { libc::poll(&mut fd, 1, millis) };
        match ready {
            -1 => {
                let e = io::Error::last_os_error();
                if e.kind() == io::ErrorKind::Interrupted {
                    Ok(true)
                } else {
                    Err(e)
                }
            }
            0 => Ok(false),
            _ => Ok(true),
        }
    }

    /// Writes all of `bytes` with `MSG_NOSIGNAL` (a closed peer is an error, not a
    /// SIGPIPE), waiting up to [`SEND_TIMEOUT`] for buffer room.
    fn send_all(&mut self, bytes: &[u8]) -> Result<(), TransportError> {
        let deadline = Instant::now() + SEND_TIMEOUT;
        let mut written = 0;
        while written < bytes.len() {
            let rest = &bytes[written..];
            // SAFETY: `rest` is a valid buffer of `rest.len()` bytes; the fd is open.
            let n = unsafe {
                libc::send(
                    self.stream.as_raw_fd(),
                    rest.as_ptr().cast(),
                    rest.len(),
                    libc::MSG_NOSIGNAL,
                )
            };
            if n >= 0 {
                written += n as usize;
                continue;
            }
            let e = io::Error::last_os_error();
            match e.kind() {
                io::ErrorKind::Interrupted => continue,
                io::ErrorKind::WouldBlock => {
                    let left = deadline.saturating_duration_since(Instant::now());
                    let ready = !left.is_zero()
                        && self
                            .wait(libc::POLLOUT, left)
                            .map_err(|_| TransportError::Gone)?;
                    if !ready {
                        let err = BoardError::Io(io::Error::new(
                            io::ErrorKind::TimedOut,
                            "emulator socket send timed out (the emulator is not reading)",
                        ));
                        // A partly written frame leaves the stream out of sync.
                        return Err(if written == 0 {
                            TransportError::Transient(err)
                        } else {
                            TransportError::Broken(err)
                        });
                    }
                }
                _ => return Err(TransportError::Gone),
            }
        }
        Ok(())
    }

    /// Goes through the frames already received until an IN report, copied into `buf`
    /// (`Some(len)`). The reader holds at most one read's worth of bytes beyond a
    /// partial frame, so this is bounded work.
    fn take_buffered(&mut self, buf: &mut ReportBuf) -> Result<Option<usize>, TransportError> {
        while let Some(message) = self
            .reader
            .next_message()
            .map_err(|e| TransportError::Broken(e.into()))?
        {
            if let Some(len) = self.handle(message, buf).map_err(TransportError::Broken)? {
                return Ok(Some(len));
            }
        }
        Ok(None)
    }

    /// Handles one received message: `Some(len)` for an IN report copied into `buf`.
    fn handle(
        &mut self,
        message: Message,
        buf: &mut ReportBuf,
    ) -> Result<Option<usize>, BoardError> {
        match message {
            Message::Hello { version } if version != FORMAT_VERSION => {
                Err(BoardError::VersionMismatch {
                    peer: version,
                    ours: FORMAT_VERSION,
                })
            }
            Message::Hello { .. } => {
                self.got_hello = true;
                Ok(None)
            }
            Message::InReport(_) if !self.got_hello => Err(WireError::UnexpectedFrame {
                kind: FrameKind::InReport,
                context: "the server's hello must come first",
            }
            .into()),
            Message::InReport(bytes) => {
                // The reader bounds payloads by MAX_PAYLOAD, the buffer's size.
                buf[..bytes.len()].copy_from_slice(&bytes);
                Ok(Some(bytes.len()))
            }
            Message::OutReport(_) => Err(WireError::UnexpectedFrame {
                kind: FrameKind::OutReport,
                context: "a server sends only hello and IN reports",
            }
            .into()),
        }
    }
}

impl Transport for SocketTransport {
    fn name(&self) -> String {
        format!("emulated board at {}", self.path.display())
    }

    /// Returns by `timeout` whatever the peer does, give or take one read (at most
    /// [`socket_wire::READ_CHUNK`] bytes) and the frames it brought: the deadline is
    /// checked after every read, so a peer that keeps the socket readable (a flood of
    /// hellos, one byte at a time) cannot hold the poll. A zero timeout still takes
    /// what has arrived.
    fn recv(
        &mut self,
        buf: &mut ReportBuf,
        timeout: Duration,
    ) -> Result<Option<usize>, TransportError> {
        let deadline = Instant::now().checked_add(timeout);
        let mut read_since_wait = false;
        loop {
            if let Some(len) = self.take_buffered(buf)? {
                return Ok(Some(len));
            }
            let left = match deadline {
                Some(deadline) => deadline.saturating_duration_since(Instant::now()),
                None => Duration::from_secs(3600),
            };
            if left.is_zero() && read_since_wait {
                return Ok(None);
            }
            read_since_wait = true;
            match self.reader.read_from(&mut self.stream) {
                Ok(0) => return Err(TransportError::Gone),
                Ok(_) => {}
                Err(e) if e.kind() == io::ErrorKind::WouldBlock => {
                    if left.is_zero() {
                        return Ok(None);
                    }
                    self.wait(libc::POLLIN, left)
                        .map_err(|e| TransportError::Transient(e.into()))?;
                    read_since_wait = false;
                }
                Err(e) if is_gone(&e) => return Err(TransportError::Gone),
                Err(e) => return Err(TransportError::Transient(e.into())),
            }
        }
    }

    fn send(&mut self, bytes: &[u8]) -> Result<(), TransportError> {
        let frame = Message::OutReport(bytes.to_vec())
            .encode()
            .map_err(|e| TransportError::Transient(e.into()))?;
        self.send_all(&frame)
    }
}

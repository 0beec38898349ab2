//! Framing of reports over a local stream socket, shared by the emulator's server
//! (`sim serve`) and [`crate::SocketBoard`].
//!
//! # Wire format
//!
//! A stream of frames, each:
//!
//! | offset | size | field |
//! |---|---|---|
//! | 0 | 1 | kind: [`FrameKind`] (`0x01` hello, `0x02` IN report, `0x03` OUT report) |
//! | 1 | 1 | payload length `n` |
//! | 2 | `n` | payload |
//!
//! * **Hello** (`0x01`), `n = 1`: the sender's [`foosball_protocol::FORMAT_VERSION`].
//!   Each side sends one hello first thing after connecting; the client requires the
//!   server's hello before any report and drops the connection on a version mismatch.
//! * **IN report** (`0x02`), `0 ≤ n ≤` [`MAX_PAYLOAD`], server → client: the encoded
//!   [`InReport`] bytes, exactly as the USB board sends them in one interrupt packet.
//! * **OUT report** (`0x03`), `0 ≤ n ≤` [`MAX_PAYLOAD`], client → server: the encoded
//!   [`OutReport`] bytes.
//!
//! The framing only checks kinds and lengths. A report payload that does not decode is
//! the report layer's business ([`crate::ReportReceiver`] rejects it and play goes on);
//! the stream stays in sync. An unknown kind or a bad length means the stream is out of
//! sync: the reader reports a [`WireError`] and the connection should be dropped.
//!
//! The socket lives at [`default_socket_path`] unless the user picks another;
//! [`bind_listener`] prepares and binds it for a server.

use std::ffi::OsString;
use std::io::{self, Read, Write};
use std::os::unix::fs::DirBuilderExt;
use std::os::unix::net::{UnixListener, UnixStream};
use std::path::{Path, PathBuf};

use foosball_protocol::usb::ENDPOINT_MAX_PACKET;
use foosball_protocol::{InReport, OutReport, FORMAT_VERSION};

/// Bytes before the payload: kind and length.
pub const HEADER_LEN: usize = 2;
/// Largest report payload: one full-speed interrupt packet, as on USB.
pub const MAX_PAYLOAD: usize = ENDPOINT_MAX_PACKET as usize;
/// Largest frame on the wire.
pub const MAX_FRAME_LEN: usize = HEADER_LEN + MAX_PAYLOAD;
/// Payload length of a hello frame.
pub const HELLO_LEN: usize = 1;

/// The kind byte of a frame.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[repr(u8)]
pub enum FrameKind {
    /// Protocol handshake: payload is the sender's format version.
    Hello = 0x01,
    /// An IN report, emulator → game.
    InReport = 0x02,
    /// An OUT report, game → emulator.
    OutReport = 0x03,
}

impl FrameKind {
    /// Parses the kind byte, `None` for unknown kinds.
    pub const fn from_u8(byte: u8) -> Option<Self> {
        match byte {
            0x01 => Some(Self::Hello),
            0x02 => Some(Self::InReport),
            0x03 => Some(Self::OutReport),
            _ => None,
        }
    }

    /// Allowed payload lengths, inclusive.
    pub const fn payload_range(self) -> (usize, usize) {
        match self {
            Self::Hello => (HELLO_LEN, HELLO_LEN),
            Self::InReport | Self::OutReport => (0, MAX_PAYLOAD),
        }
    }
}

/// Bytes on the socket that are not valid framing.
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
pub enum WireError {
    /// The kind byte names no known frame kind.
    #[error("unknown frame kind {0:#04x}")]
    UnknownKind(u8),
    /// The length byte is outside the range allowed for the frame kind.
    #[error("bad payload length {len} for a {kind:?} frame (allowed {min}..={max})")]
    BadLength {
        /// Kind of the frame.
        kind: FrameKind,
        /// Length received (or asked to encode).
        len: usize,
        /// Smallest allowed length.
        min: usize,
        /// Largest allowed length.
        max: usize,
    },
    /// A well-formed frame arrived where the protocol does not allow it (a report
    /// before the hello, an OUT report sent to the client, …).
    #[error("unexpected {kind:?} frame: {context}")]
    UnexpectedFrame {
        /// Kind of the frame.
        kind: FrameKind,
        /// What was expected instead.
        context: &'static str,
    },
}

/// One frame's content.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub enum Message {
    /// Handshake carrying the sender's report format version.
    Hello {
        /// The sender's [`foosball_protocol::FORMAT_VERSION`].
        version: u8,
    },
    /// Raw IN report bytes (decode with [`InReport::decode`] or
    /// [`crate::ReportReceiver::accept`]).
    InReport(Vec<u8>),
    /// Raw OUT report bytes (decode with [`OutReport::decode`]).
    OutReport(Vec<u8>),
}

impl Message {
    /// A hello with this build's [`FORMAT_VERSION`].
    pub fn hello() -> Self {
        Self::Hello {
            version: FORMAT_VERSION,
        }
    }

    /// An IN report frame carrying `report` encoded.
    pub fn in_report(report: &InReport) -> Self {
        Self::InReport(report.to_bytes().to_vec())
    }

    /// An OUT report frame carrying `report` encoded.
    pub fn out_report(report: &OutReport) -> Self {
        Self::OutReport(report.to_bytes().to_vec())
    }

    /// The frame kind.
    pub fn kind(&self) -> FrameKind {
        match self {
            Self::Hello { .. } => FrameKind::Hello,
            Self::InReport(_) => FrameKind::InReport,
            Self::OutReport(_) => FrameKind::OutReport,
        }
    }

    /// Appends the framed message to `out`. Fails (writing nothing) if a report
    /// payload is longer than [`MAX_PAYLOAD`].
    pub fn encode_into(&self, out: &mut Vec<u8>) -> Result<(), WireError> {
        let kind = self.kind();
        let payload: &[u8] = match self {
            Self::Hello { version } => std::slice::from_ref(version),
            Self::InReport(bytes) | Self::OutReport(bytes) => bytes,
        };
        check_length(kind, payload.len())?;
        out.reserve(HEADER_LEN + payload.len());
        out.push(kind as u8);
        // check_length bounds the length by MAX_PAYLOAD (64), so it fits a byte.
        out.push(payload.len() as u8);
        out.extend_from_slice(payload);
        Ok(())
    }

    /// The framed message as bytes.
    pub fn encode(&self) -> Result<Vec<u8>, WireError> {
        let mut out = Vec::with_capacity(MAX_FRAME_LEN);
        self.encode_into(&mut out)?;
        Ok(out)
    }
}

fn check_length(kind: FrameKind, len: usize) -> Result<(), WireError> {
    let (min, max) = kind.payload_range();
    if (min..=max).contains(&len) {
        Ok(())
    } else {
        Err(WireError::BadLength {
            kind,
            len,
            min,
            max,
        })
    }
}

/// Writes one framed message (blocking `write_all`). A payload too long to frame is an
/// [`io::ErrorKind::InvalidInput`] error wrapping the [`WireError`].
pub fn write_message<W: Write + ?Sized>(writer: &mut W, message: &Message) -> io::Result<()> {
    let bytes = message
        .encode()
        .map_err(|e| io::Error::new(io::ErrorKind::InvalidInput, e))?;
    writer.write_all(&bytes)
}

/// Incremental frame decoder: feed it bytes as they arrive (any split, partial reads
/// included) and take whole messages out.
///
/// A header is checked as soon as its two bytes are there, so garbage is rejected
/// without waiting for a payload. After an error the stream is out of sync and the
/// reader keeps returning that error: drop the connection (and the reader).
#[derive(Debug, Clone, Default)]
pub struct FrameReader {
    buf: Vec<u8>,
}

impl FrameReader {
    /// An empty reader.
    pub fn new() -> Self {
        Self::default()
    }

    /// Appends received bytes.
    pub fn push(&mut self, bytes: &[u8]) {
        self.buf.extend_from_slice(bytes);
    }

    /// Bytes received but not yet taken out as messages.
    pub fn buffered(&self) -> usize {
        self.buf.len()
    }

    /// Takes the next whole message out: `Ok(None)` if more bytes are needed.
    pub fn next_message(&mut self) -> Result<Option<Message>, WireError> {
        let [kind_byte, len_byte, ..] = self.buf[..] else {
            return Ok(None);
        };
        let kind = FrameKind::from_u8(kind_byte).ok_or(WireError::UnknownKind(kind_byte))?;
        let len = usize::from(len_byte);
        check_length(kind, len)?;
        let Some(payload) = self.buf.get(HEADER_LEN..HEADER_LEN + len) else {
            return Ok(None);
        };
        let message = match kind {
            FrameKind::Hello => Message::Hello {
                version: payload[0],
            },
            FrameKind::InReport => Message::InReport(payload.to_vec()),
            FrameKind::OutReport => Message::OutReport(payload.to_vec()),
        };
        self.buf.drain(..HEADER_LEN + len);
        Ok(Some(message))
    }

    /// Performs one `read` from `reader` into the buffer, returning the bytes read
    /// (`Ok(0)`: end of stream). `Interrupted` is retried; `WouldBlock` (non-blocking
    /// sockets) and other errors are returned.
    pub fn read_from<R: Read + ?Sized>(&mut self, reader: &mut R) -> io::Result<usize> {
        let mut chunk = [0u8; 4096];
        loop {
            match reader.read(&mut chunk) {
                Ok(n) => {
                    self.push(&chunk[..n]);
                    return Ok(n);
                }
                Err(e) if e.kind() == io::ErrorKind::Interrupted => continue,
                Err(e) => return Err(e),
            }
        }
    }
}

/// Where the emulator's socket lives by default:
/// `$XDG_RUNTIME_DIR/space-foosball/board.sock` if `XDG_RUNTIME_DIR` is set to an
/// absolute path, else `/tmp/space-foosball-<uid>/board.sock`.
pub fn default_socket_path() -> PathBuf {
    // SAFETY: getuid has no preconditions and cannot fail.
    let uid = unsafe { libc::getuid() };
    socket_path_for(std::env::var_os("XDG_RUNTIME_DIR"), uid)
}

/// [`default_socket_path`] for a given `XDG_RUNTIME_DIR` value and user id.
pub fn socket_path_for(xdg_runtime_dir: Option<OsString>, uid: u32) -> PathBuf {
    match xdg_runtime_dir.map(PathBuf::from) {
        Some(dir) if dir.is_absolute() => dir.join("space-foosball").join("board.sock"),
        _ => PathBuf::from(format!("/tmp/space-foosball-{uid}")).join("board.sock"),
    }
}

/// Binds a listening socket at `path` for a server: creates the parent directory
/// (mode 0700) if needed and removes a stale socket file left by a killed server.
/// Fails with [`io::ErrorKind::AddrInUse`] if a live server already listens there.
pub fn bind_listener(path: &Path) -> io::Result<UnixListener> {
    if let Some(parent) = path.parent().filter(|p| !p.as_os_str().is_empty()) {
        std::fs::DirBuilder::new()
            .recursive(true)
            .mode(0o700)
            .create(parent)?;
    }
    match UnixListener::bind(path) {
        Ok(listener) => Ok(listener),
        Err(e) if e.kind() == io::ErrorKind::AddrInUse => {
            if UnixStream::connect(path).is_ok() {
                return Err(io::Error::new(
                    io::ErrorKind::AddrInUse,
                    format!("a server already listens on {}", path.display()),
                ));
            }
            std::fs::remove_file(path)?;
            UnixListener::bind(path)
        }
        Err(e) => Err(e),
    }
}

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
//!   IN report bytes (version 1, [`InReport`], or version 2 with the board's timing, as
//!   `sim serve` sends), exactly as the USB board sends them in one interrupt packet.
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
use std::os::unix::fs::{DirBuilderExt, MetadataExt, PermissionsExt};
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
    /// Bytes of `buf` before this are taken out already.
    start: usize,
}

/// Most bytes one [`FrameReader::read_from`] takes from the stream.
pub const READ_CHUNK: usize = 4096;

impl FrameReader {
    /// An empty reader.
    pub fn new() -> Self {
        Self::default()
    }

    /// Appends received bytes.
    pub fn push(&mut self, bytes: &[u8]) {
        if self.start > 0 {
            // Taken-out bytes go now, so taking frames out stays linear.
            self.buf.drain(..self.start);
            self.start = 0;
        }
        self.buf.extend_from_slice(bytes);
    }

    /// Bytes received but not yet taken out as messages.
    pub fn buffered(&self) -> usize {
        self.buf.len() - self.start
    }

    /// Takes the next whole message out: `Ok(None)` if more bytes are needed.
    pub fn next_message(&mut self) -> Result<Option<Message>, WireError> {
        let rest = &self.buf[self.start..];
        let [kind_byte, len_byte, ..] = rest[..] else {
            return Ok(None);
        };
        let kind = FrameKind::from_u8(kind_byte).ok_or(WireError::UnknownKind(kind_byte))?;
        let len = usize::from(len_byte);
        check_length(kind, len)?;
        let Some(payload) = rest.get(HEADER_LEN..HEADER_LEN + len) else {
            return Ok(None);
        };
        let message = match kind {
            FrameKind::Hello => Message::Hello {
                version: payload[0],
            },
            FrameKind::InReport => Message::InReport(payload.to_vec()),
            FrameKind::OutReport => Message::OutReport(payload.to_vec()),
        };
        self.start += HEADER_LEN + len;
        if self.start == self.buf.len() {
            self.buf.clear();
            self.start = 0;
        }
        Ok(Some(message))
    }

    /// Performs one `read` of at most [`READ_CHUNK`] bytes from `reader` into the
    /// buffer, returning the bytes read (`Ok(0)`: end of stream). `Interrupted` is
    /// retried; `WouldBlock` (non-blocking sockets) and other errors are returned.
    pub fn read_from<R: Read + ?Sized>(&mut self, reader: &mut R) -> io::Result<usize> {
        let mut chunk = [0u8; READ_CHUNK];
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

/// Binds a listening socket at `path` for a server: prepares its folder
/// ([`prepare_socket_dir`]) and removes a stale socket file left by a killed server.
/// Fails with [`io::ErrorKind::AddrInUse`] if a live server already listens there, and
/// with [`io::ErrorKind::PermissionDenied`] if the folder is not safe to use.
pub fn bind_listener(path: &Path) -> io::Result<UnixListener> {
    if let Some(parent) = socket_dir(path) {
        prepare_socket_dir(parent)?;
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

/// The folder a socket path lives in, `None` for a bare file name (the current
/// directory).
pub(crate) fn socket_dir(path: &Path) -> Option<&Path> {
    path.parent().filter(|p| !p.as_os_str().is_empty())
}

/// Makes sure `dir` can hold the board's socket: creates it (and missing parents) with
/// mode 0700 if it does not exist, then checks it with [`check_socket_dir`].
pub fn prepare_socket_dir(dir: &Path) -> io::Result<()> {
    if dir.symlink_metadata().is_err() {
        std::fs::DirBuilder::new()
            .recursive(true)
            .mode(0o700)
            .create(dir)?;
        // Exactly 0700 whatever the umask.
        std::fs::set_permissions(dir, std::fs::Permissions::from_mode(0o700))?;
    }
    check_socket_dir(dir)
}

/// Checks that the folder `dir` is safe for the board's socket, so that no other user
/// can put their own socket in its place: it must be a real directory (not a symbolic
/// link), owned by this user, and writable by nobody else (no group or world write
/// bit). One exception: a shared temporary directory such as `/tmp` (owned by root,
/// sticky bit set, where nobody can remove or rename another user's files) is
/// accepted. A refusal is a [`io::ErrorKind::PermissionDenied`] error naming the folder
/// and the problem; a missing folder is the [`io::ErrorKind::NotFound`] error of the
/// lookup.
pub fn check_socket_dir(dir: &Path) -> io::Result<()> {
    // SAFETY: geteuid has no preconditions and cannot fail.
    check_socket_dir_for(dir, unsafe { libc::geteuid() })
}

/// [`check_socket_dir`] as the user `uid`.
fn check_socket_dir_for(dir: &Path, uid: u32) -> io::Result<()> {
    let refuse = |why: String| {
        Err(io::Error::new(
            io::ErrorKind::PermissionDenied,
            format!("refusing the socket folder {}: {why}", dir.display()),
        ))
    };
    let meta = dir
        .symlink_metadata()
        .map_err(|e| io::Error::new(e.kind(), format!("socket folder {}: {e}", dir.display())))?;
    if meta.file_type().is_symlink() {
        return refuse("it is a symbolic link; remove it".into());
    }
    if !meta.is_dir() {
        return refuse("it is not a directory".into());
    }
    let mode = meta.mode() & 0o7777;
    let shared_tmp = meta.uid() == 0 && mode & 0o1000 != 0;
    if shared_tmp {
        return Ok(());
    }
    if meta.uid() != uid {
        return refuse(format!(
            "it is owned by user id {}, not by this user (id {uid}); remove it",
            meta.uid()
        ));
    }
    if mode & 0o022 != 0 {
        return refuse(format!(
            "it is writable by group or others (mode {mode:04o}); `chmod 700` it or remove it"
        ));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::os::unix::fs::PermissionsExt;

    fn chmod(path: &Path, mode: u32) {
        std::fs::set_permissions(path, std::fs::Permissions::from_mode(mode)).unwrap();
    }

    fn me() -> u32 {
        // SAFETY: geteuid has no preconditions and cannot fail.
        unsafe { libc::geteuid() }
    }

    fn refusal(result: io::Result<()>) -> String {
        let e = result.expect_err("the folder should be refused");
        assert_eq!(e.kind(), io::ErrorKind::PermissionDenied, "{e}");
        e.to_string()
    }

    #[test]
    fn a_new_socket_folder_is_created_with_mode_0700() {
        let tmp = tempfile::tempdir().unwrap();
        let dir = tmp.path().join("space-foosball-test");
        prepare_socket_dir(&dir).unwrap();
        let meta = dir.symlink_metadata().unwrap();
        assert!(meta.is_dir());
        assert_eq!(meta.mode() & 0o7777, 0o700);
        assert_eq!(meta.uid(), me());
        // Binding there works, and again after (an existing good folder is kept).
        drop(bind_listener(&dir.join("board.sock")).unwrap());
        drop(bind_listener(&dir.join("board.sock")).unwrap());
    }

    #[test]
    fn group_or_world_writable_folders_are_refused() {
        let tmp = tempfile::tempdir().unwrap();
        let dir = tmp.path().join("open");
        std::fs::create_dir(&dir).unwrap();
        for mode in [0o777, 0o770, 0o702, 0o720] {
            chmod(&dir, mode);
            let message = refusal(prepare_socket_dir(&dir));
            assert!(message.contains("writable by group or others"), "{message}");
            assert!(message.contains(&format!("{mode:04o}")), "{message}");
            let message = refusal(bind_listener(&dir.join("board.sock")).map(drop));
            assert!(message.contains("open"), "{message}");
        }
        chmod(&dir, 0o755);
        check_socket_dir(&dir).unwrap();
    }

    #[test]
    fn symbolic_links_and_files_are_refused() {
        let tmp = tempfile::tempdir().unwrap();
        let real = tmp.path().join("real");
        std::fs::create_dir(&real).unwrap();
        chmod(&real, 0o700);
        let link = tmp.path().join("link");
        std::os::unix::fs::symlink(&real, &link).unwrap();
        let message = refusal(prepare_socket_dir(&link));
        assert!(message.contains("symbolic link"), "{message}");
        let file = tmp.path().join("file");
        std::fs::write(&file, b"").unwrap();
        let message = refusal(check_socket_dir(&file));
        assert!(message.contains("not a directory"), "{message}");
        // A dangling link is refused too, not followed to create its target.
        let dangling = tmp.path().join("dangling");
        std::os::unix::fs::symlink(tmp.path().join("nowhere"), &dangling).unwrap();
        let message = refusal(prepare_socket_dir(&dangling));
        assert!(message.contains("symbolic link"), "{message}");
        assert!(!tmp.path().join("nowhere").exists());
    }

    #[test]
    fn a_folder_owned_by_another_user_is_refused() {
        let tmp = tempfile::tempdir().unwrap();
        let dir = tmp.path().join("theirs");
        std::fs::create_dir(&dir).unwrap();
        chmod(&dir, 0o700);
        // As seen by another user (the owner comparison itself).
        let other = me().wrapping_add(4242);
        let message = refusal(check_socket_dir_for(&dir, other));
        assert!(
            message.contains(&format!("owned by user id {}", me())),
            "{message}"
        );
        // For real, where this test may hand the folder to another user (as root).
        // SAFETY: a valid NUL-terminated path; chown has no other preconditions.
        let path = std::ffi::CString::new(dir.as_os_str().as_encoded_bytes()).unwrap();
        let given = unsafe { libc::chown(path.as_ptr(), other, other) } == 0;
        if given {
            let message = refusal(prepare_socket_dir(&dir));
            assert!(
                message.contains(&format!("owned by user id {other}")),
                "{message}"
            );
        } else {
            eprintln!("not root: the folder could not be given to another user");
        }
    }

    #[test]
    fn shared_sticky_temporary_directories_are_accepted() {
        let tmp = std::env::temp_dir();
        let meta = tmp.symlink_metadata().unwrap();
        if meta.uid() == 0 && meta.mode() & 0o1000 != 0 {
            check_socket_dir(&tmp).unwrap();
        } else {
            eprintln!("{} is not a root-owned sticky directory", tmp.display());
        }
    }
}

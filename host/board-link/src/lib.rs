//! The host's link to the Space Foosball sensor board, real or emulated.
//!
//! "The paper" and its section numbers (§6) refer to Bang, Heo, Kim and Kim, "Space
//! Foosball: Coupling Tangible Interfaces with a Real-time Game Physics Engine"; what the
//! project takes from it, section by section, is in docs/paper.md in the repository.
//!
//! The game talks to a [`Board`]: it polls IN reports ([`foosball_protocol::InReport`],
//! one per millisecond from the board), sends OUT reports (haptics, LED), and reads the
//! link's [`LinkState`] and [`LinkStats`]. Three implementations exist:
//!
//! * [`UsbBoard`]: the real RP2040 board over USB (`rusb`), found by vendor/product id.
//!   It survives unplugging: polls report [`BoardError::Disconnected`] and the board is
//!   reopened on later polls when it comes back.
//! * [`SocketBoard`]: a client of the emulator process (`sim serve`) over a Unix-domain
//!   stream socket framed by [`socket_wire`]. It survives the emulator being restarted.
//! * the in-process emulation, which lives in the `foosball-sim` crate (it depends on this
//!   one and implements [`Board`]).
//!
//! [`ReportReceiver`] turns raw report bytes into reports and counts received, lost
//! (sequence gaps) and malformed reports; every implementation uses it.
//!
//! ```no_run
//! use std::time::Duration;
//! use board_link::{Board, BoardError, SocketBoard, UsbBoard};
//!
//! // The real board if one is plugged in, else the emulator process.
//! let mut board: Box<dyn Board> = match UsbBoard::open() {
//!     Ok(usb) => Box::new(usb),
//!     Err(_) => Box::new(SocketBoard::at_default_path()),
//! };
//! loop {
//!     // Drain what arrived since the last frame, then simulate and draw.
//!     loop {
//!         match board.poll_report(Duration::ZERO) {
//!             Ok(Some(report)) => { /* apply report.paddles */ }
//!             Ok(None) => break,
//!             Err(BoardError::Malformed(_)) => continue, // dropped, play goes on
//!             Err(_) => break, // disconnected etc.: it reconnects on later polls
//!         }
//!     }
//!     # break;
//! }
//! println!("{}: {:?}", board.name(), board.stats());
//! ```
#![deny(missing_docs)]

// In a browser (wasm32) there is neither libusb nor a Unix socket: the page hands the
// reports over itself (WebHID), through `ReportReceiver`.
#[cfg(not(target_arch = "wasm32"))]
mod feature;
pub mod haptics;
#[cfg(not(target_arch = "wasm32"))]
mod link;
mod receiver;
#[cfg(not(target_arch = "wasm32"))]
mod socket;
#[cfg(not(target_arch = "wasm32"))]
pub mod socket_wire;
#[cfg(not(target_arch = "wasm32"))]
mod usb;

use std::time::Duration;

#[cfg(not(target_arch = "wasm32"))]
pub use feature::FeaturePipe;
pub use foosball_protocol::{DecodeError, InReport, OutReport, ReportTiming};
pub use receiver::ReportReceiver;
#[cfg(not(target_arch = "wasm32"))]
pub use socket::SocketBoard;
#[cfg(not(target_arch = "wasm32"))]
pub use socket_wire::WireError;
#[cfg(not(target_arch = "wasm32"))]
pub use usb::UsbBoard;

/// How often a disconnected board is looked for again (USB rescan, socket connect).
pub const DEFAULT_RETRY_INTERVAL: Duration = Duration::from_millis(250);

/// A sensor board the game can poll, real or emulated.
///
/// Implementations never panic on link trouble: a vanished board is reported as
/// [`BoardError::Disconnected`] and looked for again on later calls, so the caller just
/// keeps polling while play degrades.
pub trait Board: Send {
    /// Human-readable name ("USB 1209:0001 bus 1 addr 7", "emulated (in-process)", …).
    fn name(&self) -> String;

    /// Next IN report, waiting at most `timeout` (`Duration::ZERO`: do not wait).
    ///
    /// * `Ok(Some(report))`: a report arrived.
    /// * `Ok(None)`: nothing arrived in time.
    /// * `Err(BoardError::Malformed(_))`: a bad report was dropped — the caller keeps going.
    /// * `Err(BoardError::Disconnected)`: the board is gone; the implementation keeps
    ///   trying to reconnect on later calls, so the caller just keeps polling.
    /// * other errors: this poll failed; keep polling.
    fn poll_report(&mut self, timeout: Duration) -> Result<Option<InReport>, BoardError>;

    /// Sends an OUT report (haptics, LED). A disconnected board gives
    /// `Err(BoardError::Disconnected)`, never a panic.
    fn send(&mut self, report: &OutReport) -> Result<(), BoardError>;

    /// Whether the link is up.
    fn link_state(&self) -> LinkState;

    /// Counters: reports received, lost (from sequence gaps), malformed, reconnects.
    fn stats(&self) -> LinkStats;

    /// Timing of the last report when the board sends version 2 reports: the device
    /// time of its snapshot (µs) and per paddle the age of the newest packet and the
    /// packets dropped. `None` for a version 1 board (and by default).
    fn last_timing(&self) -> Option<ReportTiming> {
        None
    }
}

impl<B: Board + ?Sized> Board for Box<B> {
    fn name(&self) -> String {
        (**self).name()
    }
    fn poll_report(&mut self, timeout: Duration) -> Result<Option<InReport>, BoardError> {
        (**self).poll_report(timeout)
    }
    fn send(&mut self, report: &OutReport) -> Result<(), BoardError> {
        (**self).send(report)
    }
    fn link_state(&self) -> LinkState {
        (**self).link_state()
    }
    fn stats(&self) -> LinkStats {
        (**self).stats()
    }
    fn last_timing(&self) -> Option<ReportTiming> {
        (**self).last_timing()
    }
}

/// State of the link to a board.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum LinkState {
    /// The board is connected: reports flow.
    Connected,
    /// The board is not connected, and no attempt to reach it has failed since the link
    /// went down (or since the board object was made). The next poll looks for it.
    Disconnected,
    /// The board is not connected; attempts to reach it have failed so far and go on
    /// (rate-limited) on later polls.
    Reconnecting,
}

impl LinkState {
    /// Whether the board is connected.
    pub fn is_connected(self) -> bool {
        self == Self::Connected
    }
}

/// Counters of a link, since the board object was made.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Hash)]
pub struct LinkStats {
    /// Reports decoded successfully.
    pub received: u64,
    /// Reports lost: the sum of the gaps in the sequence numbers of received reports.
    /// A reconnect restarts the count from the next report, so the jump across a
    /// reconnect is not counted.
    pub lost: u64,
    /// Reports rejected as malformed (and dropped).
    pub malformed: u64,
    /// Times the link came back after being lost (the first connection is not counted).
    pub reconnects: u64,
}

/// Why a board operation failed.
#[derive(Debug, thiserror::Error)]
pub enum BoardError {
    /// No USB device with the board's vendor/product id is plugged in.
    #[error("no sensor board found (USB id {vid:04x}:{pid:04x}); is it plugged in?")]
    NotFound {
        /// Vendor id looked for.
        vid: u16,
        /// Product id looked for.
        pid: u16,
    },
    /// Sensor boards are plugged in, but none has the USB serial number asked for
    /// (`UsbBoard::open_serial`).
    #[error(
        "no sensor board with serial number {wanted:?} (USB id {vid:04x}:{pid:04x}); \
         boards found: {}",
        .found.join(", ")
    )]
    SerialNotFound {
        /// Vendor id looked for.
        vid: u16,
        /// Product id looked for.
        pid: u16,
        /// The serial number asked for.
        wanted: String,
        /// Each board with those ids that was found: its serial number (quoted), or why
        /// it could not be read.
        found: Vec<String>,
    },
    /// The board is plugged in but this user may not open it.
    #[error(
        "permission denied opening the sensor board (USB id {vid:04x}:{pid:04x}); \
         install the udev rule 70-space-foosball.rules (see the board-link README)"
    )]
    AccessDenied {
        /// Vendor id of the board.
        vid: u16,
        /// Product id of the board.
        pid: u16,
    },
    /// The board is gone (unplugged, emulator stopped). Later polls try to reconnect.
    #[error("board disconnected")]
    Disconnected,
    /// A malformed report was received and dropped; the link is still up.
    #[error("malformed report dropped: {0}")]
    Malformed(#[from] DecodeError),
    /// The emulator socket carried bytes that are not valid [`socket_wire`] framing. The
    /// connection is dropped and re-established on later polls.
    #[cfg(not(target_arch = "wasm32"))]
    #[error("socket framing error: {0}")]
    Wire(#[from] WireError),
    /// The peer speaks another report format version. The connection is dropped (and
    /// retried on later polls).
    #[error("board speaks report format version {peer}, this build speaks {ours}")]
    VersionMismatch {
        /// The peer's [`foosball_protocol::FORMAT_VERSION`].
        peer: u8,
        /// Ours.
        ours: u8,
    },
    /// An operating-system I/O error (socket).
    #[error("I/O error: {0}")]
    Io(#[from] std::io::Error),
    /// A USB (libusb) error other than the board going away.
    #[error("USB error: {0}")]
    Usb(String),
    /// The board refused a Feature report request (STALL): its firmware has no
    /// Feature reports (a version 1 board), or it rejected what was written.
    #[error("the board does not answer this Feature report request (older firmware?)")]
    FeatureUnsupported,
    /// A port number outside `0..8` was asked for.
    #[error("no port {port} on the board (ports are 0 to 7)")]
    PortOutOfRange {
        /// The port asked for.
        port: u8,
    },
}

impl BoardError {
    /// Whether the error means the board is not reachable now (gone, not found, refused),
    /// as opposed to one bad report or one failed transfer.
    pub fn is_link_down(&self) -> bool {
        match self {
            Self::Disconnected
            | Self::NotFound { .. }
            | Self::SerialNotFound { .. }
            | Self::AccessDenied { .. }
            | Self::VersionMismatch { .. } => true,
            #[cfg(not(target_arch = "wasm32"))]
            Self::Wire(_) => true,
            _ => false,
        }
    }
}

//! Which board `space-foosball board` talks to.
//!
//! The live view opens a board as `play` does ([`crate::window::board::open`]). The
//! diagnostics and settings commands need a board that answers Feature reports
//! ([`FeatureBoard`]): the board on USB ([`UsbBoard`], `--serial` picks one by its
//! serial number), or the built-in emulated board — the same one the game plays on
//! ([`crate::window::board::emulated_board`]), stepped in lockstep and powered up
//! for [`EMULATED_POWER_UP_MS`] of emulated time first, so its mice have finished
//! their self-test. The socket link (`sim serve`) carries IN and OUT reports only, so
//! those commands refuse it.

use crate::window::board::{self, BoardChoice};
use anyhow::{anyhow, bail, Result};
use board_link::{Board, BoardError, FeaturePipe, SocketBoard, UsbBoard};
use foosball_sim::Pacing;
use std::time::Duration;

/// Emulated time the built-in emulated board runs before it is asked anything, ms:
/// its mice finish their 500 ms self-test and initialisation well within it.
pub const EMULATED_POWER_UP_MS: u64 = 1_000;

/// A board that answers Feature reports.
pub trait FeatureBoard: Board + FeaturePipe {}

impl<T: Board + FeaturePipe> FeatureBoard for T {}

/// A board opened for the diagnostics and settings commands.
pub struct FeatureTarget {
    /// The board.
    pub board: Box<dyn FeatureBoard>,
    /// Its USB serial number string, where known.
    pub serial_number: Option<String>,
    /// Whether it is the built-in emulated board (it lives as long as the command).
    pub emulated: bool,
}

/// Refuses `--serial` with a board that is not on USB.
pub fn check_serial(choice: &BoardChoice, serial: Option<&str>) -> Result<()> {
    match (choice, serial) {
        (BoardChoice::Emulated | BoardChoice::Socket(_), Some(serial)) => bail!(
            "--serial {serial} picks a board on USB; it does not go with --board {} \
             (or --socket)",
            choice_name(choice)
        ),
        (_, Some("")) => bail!("--serial needs a serial number (it was empty)"),
        _ => Ok(()),
    }
}

fn choice_name(choice: &BoardChoice) -> &'static str {
    match choice {
        BoardChoice::Auto => "auto",
        BoardChoice::Usb => "usb",
        BoardChoice::Emulated => "emulated",
        BoardChoice::Socket(_) => "socket",
    }
}

/// Opens `choice` for the live view; with `serial`, the USB board with that serial
/// number. A socket board is reached at once so that a missing emulator is said
/// plainly.
pub fn open_live(choice: &BoardChoice, serial: Option<&str>) -> Result<Box<dyn Board>> {
    if let Some(serial) = serial {
        return Ok(Box::new(UsbBoard::open_serial(serial)?));
    }
    if let BoardChoice::Socket(path) = choice {
        let path = path
            .clone()
            .unwrap_or_else(board_link::socket_wire::default_socket_path);
        let socket = SocketBoard::connect(path.clone()).map_err(|e| {
            anyhow!(
                "no emulator answers at {} ({e}); start one with `sim serve --socket {}`",
                path.display(),
                path.display()
            )
        })?;
        return Ok(Box::new(socket));
    }
    Ok(board::open(choice)?.board)
}

/// Opens `choice` for a command that goes through Feature reports. `auto` is the
/// board on USB here: a command that changes settings or restarts the board must not
/// quietly reach the emulated board instead.
pub fn open_feature(choice: &BoardChoice, serial: Option<&str>) -> Result<FeatureTarget> {
    match choice {
        BoardChoice::Socket(path) => {
            let path = path
                .clone()
                .unwrap_or_else(board_link::socket_wire::default_socket_path);
            bail!(
                "the socket link carries IN/OUT reports only, so the emulator at {} cannot \
                 be asked for the board's diagnostics or settings; use --board emulated \
                 (the built-in emulated board), or the emulator as a USB device \
                 (`sim usbip`, attached with `usbip attach`) with --board usb",
                path.display()
            )
        }
        BoardChoice::Emulated => open_emulated(),
        BoardChoice::Auto | BoardChoice::Usb => {
            let opened = match serial {
                Some(serial) => UsbBoard::open_serial(serial),
                None => UsbBoard::open(),
            };
            let usb = opened.map_err(|e| match e {
                BoardError::NotFound { .. } => {
                    anyhow!("{e} (--board emulated asks the built-in emulated board instead)")
                }
                other => anyhow!(other),
            })?;
            Ok(FeatureTarget {
                serial_number: usb.serial_number(),
                board: Box::new(usb),
                emulated: false,
            })
        }
    }
}

/// The built-in emulated board, powered up for [`EMULATED_POWER_UP_MS`].
fn open_emulated() -> Result<FeatureTarget> {
    let (mut emulated, _live) = board::emulated_board(Pacing::Lockstep)?;
    for _ in 0..EMULATED_POWER_UP_MS {
        // Lockstep: each poll is one millisecond of the board, answered at once.
        emulated
            .poll_report(Duration::ZERO)
            .map_err(|e| anyhow!("powering up the emulated board: {e}"))?;
    }
    Ok(FeatureTarget {
        board: Box::new(emulated),
        serial_number: Some(foosball_sim::usb_device::SERIAL.to_owned()),
        emulated: true,
    })
}

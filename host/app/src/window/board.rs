//! Which board `play` reads: the real board over USB when one is plugged in, else the
//! built-in emulated board driven by keyboard, mouse and gamepad; or, on request, the
//! emulator process over its Unix socket (`sim serve`).

use anyhow::{Context, Result};
use board_link::{Board, SocketBoard, UsbBoard};
use foosball_sim::motion::live::{LiveHandle, LiveLimits};
use foosball_sim::{BoardConfig, InProcessBoard, Pacing};
use std::path::PathBuf;

/// The board to play with (`play --board`).
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum BoardChoice {
    /// USB if a board is plugged in, else the built-in emulated board.
    Auto,
    /// The real board over USB only (an error without one).
    Usb,
    /// The built-in emulated board (keyboard, mouse, gamepad).
    Emulated,
    /// The emulator process at this socket (`None`: the default path).
    Socket(Option<PathBuf>),
}

impl std::str::FromStr for BoardChoice {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, String> {
        match s {
            "auto" => Ok(Self::Auto),
            "usb" => Ok(Self::Usb),
            "emulated" => Ok(Self::Emulated),
            "socket" => Ok(Self::Socket(None)),
            _ => match s.strip_prefix("socket:") {
                Some(p) if !p.is_empty() => Ok(Self::Socket(Some(PathBuf::from(p)))),
                _ => Err(format!(
                    "unknown board {s:?}: use auto, usb, emulated, socket or socket:PATH"
                )),
            },
        }
    }
}

/// An open board.
pub struct Opened {
    /// The board.
    pub board: Box<dyn Board>,
    /// The emulated rods' targets, when the board is the built-in emulation.
    pub live: Option<LiveHandle>,
    /// What to tell the player about the choice, if anything.
    pub notice: Option<String>,
}

/// The built-in emulated board the game plays on (rods following live targets, the
/// default board configuration), paced by `pacing`, with the setter of its rods'
/// targets.
pub fn emulated_board(pacing: Pacing) -> Result<(InProcessBoard, LiveHandle)> {
    InProcessBoard::live(BoardConfig::default(), LiveLimits::default(), pacing)
        .context("could not start the emulated board")
}

fn emulated() -> Result<(Box<dyn Board>, LiveHandle)> {
    let (board, live) = emulated_board(Pacing::RealTime)?;
    Ok((Box::new(board), live))
}

/// Opens `choice`.
pub fn open(choice: &BoardChoice) -> Result<Opened> {
    Ok(match choice {
        BoardChoice::Auto => match UsbBoard::open() {
            Ok(b) => Opened {
                board: Box::new(b),
                live: None,
                notice: None,
            },
            Err(e) => {
                let (board, live) = emulated()?;
                Opened {
                    board,
                    live: Some(live),
                    notice: Some(format!(
                        "no board on USB ({e}); playing on the built-in emulated board \
                         (keyboard, mouse, gamepad)"
                    )),
                }
            }
        },
        BoardChoice::Usb => Opened {
            board: Box::new(UsbBoard::open().context("no board on USB")?),
            live: None,
            notice: None,
        },
        BoardChoice::Emulated => {
            let (board, live) = emulated()?;
            Opened {
                board,
                live: Some(live),
                notice: None,
            }
        }
        BoardChoice::Socket(path) => Opened {
            board: Box::new(match path {
                Some(p) => SocketBoard::new(p.clone()),
                None => SocketBoard::at_default_path(),
            }),
            live: None,
            notice: None,
        },
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn board_choices_parse() {
        assert_eq!("auto".parse(), Ok(BoardChoice::Auto));
        assert_eq!("emulated".parse(), Ok(BoardChoice::Emulated));
        assert_eq!("socket".parse(), Ok(BoardChoice::Socket(None)));
        assert_eq!(
            "socket:/tmp/b.sock".parse(),
            Ok(BoardChoice::Socket(Some("/tmp/b.sock".into())))
        );
        assert!("socket:".parse::<BoardChoice>().is_err());
        assert!("serial"
            .parse::<BoardChoice>()
            .unwrap_err()
            .contains("emulated"));
    }
}

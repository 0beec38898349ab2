//! Online play on the desktop: the shared session (`space_foosball_front::online`) over UDP
//! to an address, or over WebRTC to the other side of a room on a signalling server.
//!
//! * [`session`] — the desktop's loop around the shared session, the outcome, the
//!   recording and the history.
//! * [`window`] — the online match in the game's window (`--window`): the lobby, the
//!   match, its end, this side's rods from the board or the keyboard.
//! * [`cli`] — `space-foosball host` and `space-foosball join ADDRESS`, or `--room NAME`
//!   (headless, or `--window`).

pub mod cli;
pub mod session;
pub mod window;

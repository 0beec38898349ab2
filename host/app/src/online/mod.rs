//! Online play on the desktop: the shared session (`space_foosball_front::online`) over UDP
//! to an address, or over WebRTC to the other side of a room on a signalling server.
//!
//! * [`session`] — the desktop's loop around the shared session, the outcome, the
//!   recording and the history.
//! * [`cli`] — `space-foosball host` and `space-foosball join ADDRESS`, or `--room NAME`
//!   (headless).

pub mod cli;
pub mod session;

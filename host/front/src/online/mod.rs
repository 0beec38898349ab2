//! Online play: two cabinets, or a cabinet and a page, one match, with rollback (`ggrs`,
//! GGPO-style). The desktop and the page share all of it but the clock and the socket.
//!
//! * [`input`] — what each side sends per 60 Hz frame: its rods' poses, quantised so both
//!   sides step on identical inputs.
//! * [`rollback`] — the match under rollback: GGRS asks to save the match
//!   (`Match::save`), load it (`Match::restore`) or advance a frame (16 or 17 steps at
//!   1 kHz with both sides' inputs).
//! * [`session`] — the frame loop on the caller's clock: connecting, playing, the end
//!   both sides confirmed, the other side gone; desyncs detected from the state's
//!   checksum.
//! * [`screen`] — what an online match shows (lobby, match, end, why it stopped), in
//!   the desktop's window and in the page.
//! * [`rollback_timing`] — what a rollback of eight frames costs (`bench rollback` on
//!   the desktop, the page's own figure in the browser).
//! * [`room`] — a match by room name through a signalling server (`matchbox_server`),
//!   over a WebRTC data channel (`matchbox_socket`).

pub mod input;
pub mod rollback;
pub mod rollback_timing;
pub mod room;
pub mod screen;
pub mod session;

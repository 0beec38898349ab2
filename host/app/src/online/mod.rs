//! Online play: two cabinets, one match, with rollback (`ggrs`, GGPO-style) over UDP.
//!
//! * [`input`] — what each side sends per 60 Hz frame: its rods' poses, quantised so both
//!   sides step on identical inputs.
//! * [`session`] — the frame loop: GGRS asks to save the match (`Match::save`), load it
//!   (`Match::restore`) or advance a frame (16 or 17 steps at 1 kHz with both sides'
//!   inputs); desyncs are detected from the state's checksum.
//! * [`cli`] — `space-foosball host` and `space-foosball join ADDRESS` (headless).

pub mod cli;
pub mod input;
pub mod session;

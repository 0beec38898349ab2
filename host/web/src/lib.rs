//! Space Foosball in a browser: the game compiled to WebAssembly, drawn by the same
//! renderer through wgpu on WebGPU (where the browser gives an adapter) or WebGL2, played from the keyboard, mouse and a gamepad or from
//! the real sensor board over WebHID, with sound through Web Audio.
//!
//! Target-independent (tested natively):
//!
//! * [`session`]: the board, the screens, the match run ahead in fixed 1 ms steps by the
//!   frame's elapsed time ([`stepper`]), what each frame shows, plays and sends.
//! * [`calibration_store`]: where the page keeps the calibration (`localStorage`), read
//!   back as untrusted input.
//! * [`board`]: raw IN report bytes from the page → the protocol crate's decoder; OUT
//!   reports queued for the page.
//! * [`frame_stats`]: frame times in the page (the status line reports them).
//! * [`keyboard`]: the page's emulated board, moved by keys, the mouse and a gamepad.
//! * [`online_page`]: an online match in a room of a signalling server, against a
//!   desktop or another page, with rollback: the lobby, the match, its end.
//! * [`flow`], [`view`], [`script`], [`controls`], [`calibrate`]: the screens' flow,
//!   game → view conversion, scripted keys, keyboard / mouse / gamepad controls and
//!   calibration mode the desktop program has too (`space-foosball-front`).
//!
//! On `wasm32` only, `web`: the winit window on the page's canvas, the animation-frame
//! loop, and the functions the page's JavaScript calls (WebHID reports in, OUT reports
//! out, the status line); and the front end's gamepad reader (gilrs, whose wasm backend
//! reads the Gamepad API).

pub mod board;
pub mod calibration_store;
pub mod frame_stats;
pub mod keyboard;
pub mod online_page;
pub mod session;
pub mod status;
pub mod stepper;
#[cfg(target_arch = "wasm32")]
use space_foosball_front::gamepad;
pub use space_foosball_front::{calibrate, controls, flow, script, view};
#[cfg(target_arch = "wasm32")]
mod web;

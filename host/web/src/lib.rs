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
//! * [`flow`], [`view`], [`script`], [`controls`], [`calibrate`]: the desktop program's
//!   own screens' flow, game → view conversion, scripted keys, keyboard / mouse / gamepad
//!   controls and calibration mode, compiled here from the same source files.
//!
//! On `wasm32` only, `web`: the winit window on the page's canvas, the animation-frame
//! loop, and the functions the page's JavaScript calls (WebHID reports in, OUT reports
//! out, the status line); and `gamepad`, the desktop's gamepad reader (gilrs, whose wasm
//! backend reads the Gamepad API).

pub mod board;
#[path = "../../app/src/window/calibrate.rs"]
pub mod calibrate;
pub mod calibration_store;
#[path = "../../app/src/window/controls.rs"]
pub mod controls;
#[path = "../../app/src/window/flow.rs"]
pub mod flow;
pub mod frame_stats;
#[cfg(target_arch = "wasm32")]
#[path = "../../app/src/window/gamepad.rs"]
mod gamepad;
pub mod keyboard;
#[path = "../../app/src/window/script.rs"]
pub mod script;
pub mod session;
pub mod status;
pub mod stepper;
#[path = "../../app/src/view.rs"]
pub mod view;
#[cfg(target_arch = "wasm32")]
mod web;

//! The front end the desktop window (`host/app`) and the browser page (`host/web`) share,
//! independent of where the frame is shown:
//!
//! * [`flow`]: the screens (attract, character select, play, pause, goal, game over,
//!   calibration), driven by the rods and the keys.
//! * [`view`]: the game's state → the renderer's view model (`foosball_render::view`).
//! * [`frame`]: what a frame shows besides the match: the screen, the table's marks,
//!   the live text, the sounds that play.
//! * [`match_scene`]: the match as the frames draw it: snapshots, interpolation, the
//!   effects and sounds of its events.
//! * [`controls`]: keyboard, mouse and gamepad → the emulated board's rods; the key map.
//! * [`gamepad`]: the gamepad reader (gilrs: evdev on Linux, the Gamepad API on wasm).
//! * [`calibrate`]: calibration mode (guided motions, the fit, its quality).
//! * [`online`]: online play with rollback (GGRS), by address or by room name.
//! * [`script`]: scripted key presses for unattended checks (`--demo-input`, the page's
//!   `?keys=`).

pub mod calibrate;
pub mod controls;
pub mod flow;
pub mod frame;
pub mod gamepad;
pub mod match_scene;
pub mod online;
pub mod script;
pub mod view;

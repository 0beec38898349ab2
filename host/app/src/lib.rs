//! The Space Foosball program's library part: how the game fills in the renderer's
//! view model ([`view`]). The program itself is `src/main.rs`; keeping the conversion
//! here lets the tests picture the real tables exactly as the program does.

pub use space_foosball_front::view;

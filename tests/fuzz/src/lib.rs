//! Fuzz targets for every loader and decoder of Space Foosball, and the runner that
//! replays their committed corpora and mutates them for a bounded time.
//!
//! * [`targets`]: one [`Target`] per input format (USB reports, PS/2 wire and driver,
//!   socket frames, scene JSON, table TOML, calibration, match recordings, motion
//!   scripts and motion recordings). Each takes arbitrary bytes, returns whether the
//!   input was accepted, and panics when a property fails (a loader accepted an input
//!   whose world goes non-finite within 100 steps, a decoder's output does not encode
//!   back to its input, …).
//! * [`mutate`]: a coverage-less mutator: byte edits for binary formats, edits of the
//!   parsed value tree (numbers set to edge values, arrays grown or emptied, keys
//!   dropped) for JSON and TOML.
//! * [`runner`]: one target in one process: corpus replay, then mutation until a
//!   deadline, with the input under test kept in a [`slot::InputSlot`].
//! * [`supervisor`]: one child process per target, under the [`alloc`] cap; a child
//!   that dies has its last input saved to a file.
//! * [`seeds`]: the committed seed corpus, made by the project's own encoders.
#![deny(missing_docs)]

pub mod alloc;
pub mod mutate;
pub mod runner;
pub mod seeds;
pub mod slot;
pub mod supervisor;
pub mod targets;

use std::path::PathBuf;

pub use targets::{Format, Target, Verdict, TARGETS};

/// Largest input a target is given, bytes: larger mutants are truncated. Bounds the
/// runner's memory per input and the input slot's size.
pub const MAX_INPUT_LEN: usize = 128 * 1024;

/// The committed seed corpus of `target`: `tests/fuzz/corpus/<target>/`.
pub fn corpus_dir(target: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("corpus")
        .join(target)
}

/// Inputs found failing and kept for the record (not replayed by the runner):
/// `tests/fuzz/findings/<target>/`.
pub fn findings_dir(target: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("findings")
        .join(target)
}

/// The target named `name`.
pub fn target(name: &str) -> Option<&'static Target> {
    TARGETS.iter().find(|t| t.name == name)
}

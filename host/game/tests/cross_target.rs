//! The reference match ([`space_foosball::play::reference`]) against its committed
//! outcome, `tests/golden/reference-match.json`: with the `enhanced-determinism`
//! feature a desktop build must play it exactly as recorded (goals to the millisecond,
//! the ball's final state to the bit), and the browser test checks the wasm build
//! against the same file, so the two targets play alike.
//!
//! ```sh
//! cargo test -p space-foosball --features enhanced-determinism --test cross_target
//! # after a change that moves the physics on purpose, rewrite the record:
//! SPACE_FOOSBALL_REWRITE_REFERENCE=1 cargo test -p space-foosball \
//!     --features enhanced-determinism --test cross_target
//! ```
//!
//! Without the feature the desktop's own libm may differ from `libm` in the last bit
//! of a sine, and a match is chaotic enough to make that a different goal, so the test
//! is not built.
#![cfg(feature = "enhanced-determinism")]

use space_foosball::play::reference::{
    play_reference, ReferenceOutcome, REFERENCE_GOALS, REFERENCE_SEED,
};
use space_foosball::Table;
use std::path::PathBuf;

fn record() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/golden/reference-match.json")
}

#[test]
fn the_reference_match_plays_as_recorded() {
    let played = play_reference(&Table::standard(), REFERENCE_SEED, REFERENCE_GOALS).unwrap();
    eprintln!("{}", serde_json::to_string(&played).unwrap());
    if std::env::var_os("SPACE_FOOSBALL_REWRITE_REFERENCE").is_some() {
        let text = serde_json::to_string_pretty(&played).unwrap() + "\n";
        space_foosball::atomic_file::write_atomic(&record(), text.as_bytes()).unwrap();
    }
    let text = std::fs::read_to_string(record()).expect("the committed reference outcome");
    let recorded: ReferenceOutcome = serde_json::from_str(&text).unwrap();
    // A match that scores no goal would compare nothing but the ball.
    assert!(!recorded.goals.is_empty(), "the record holds no goal");
    assert_eq!(played, recorded, "the reference match played differently");
}

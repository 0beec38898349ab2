//! How long the hard cases run: a reduced length in the default test run, the full length
//! with `VPHYS_FULL_HARD_CASES=1` (the test command's release step).
#![allow(dead_code)]

/// Whether `VPHYS_FULL_HARD_CASES=1` asks for the full length.
pub fn full() -> bool {
    std::env::var("VPHYS_FULL_HARD_CASES").is_ok_and(|v| v == "1")
}

/// Steps: `reduced` in the default run, `full_len` with `VPHYS_FULL_HARD_CASES=1`.
pub fn length(reduced: usize, full_len: usize) -> usize {
    if full() {
        full_len
    } else {
        reduced
    }
}

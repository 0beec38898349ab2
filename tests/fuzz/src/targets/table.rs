//! Table TOML: the loader (or the arena) rejects the table, or the arena it builds
//! steps 100 times with every body finite.

use super::finite::first_non_finite;
use super::{text, Verdict};
use space_foosball::arena::Arena;
use space_foosball::Table;

pub(super) fn run(input: &[u8]) -> Verdict {
    let Some(text) = text(input) else {
        return Verdict::Rejected;
    };
    let Ok(table) = Table::from_toml(text) else {
        return Verdict::Rejected;
    };
    let Ok(mut arena) = Arena::new(&table) else {
        return Verdict::Rejected;
    };
    if let Some(body) = first_non_finite(arena.world()) {
        panic!("the built arena is not finite: {body}");
    }
    for step in 1..=super::scene::STEPS {
        arena.step();
        if let Some(body) = first_non_finite(arena.world()) {
            panic!("arena step {step} left a non-finite state: {body}");
        }
    }
    Verdict::Accepted
}

//! Measurement support: the operation-counting scalar, the 6×6 matrix-form baseline, the
//! paper's Table 3 measured on this crate's code, and the reference problems of the accuracy
//! report ([`accuracy`]).
//!
//! The counts are *measured*: the same generic functions that run on `f64` are run once on
//! [`Counted`], which tallies every multiplication and addition it performs.

pub mod accuracy;
mod counting;
pub mod hard;
pub mod matrix_form;
pub mod table3;

pub use counting::{count_ops, Counted, OpCounts};

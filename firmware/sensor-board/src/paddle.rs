//! Per-paddle accumulation: which mouse axis is which paddle motion, and saturating
//! sums over one report period.

pub mod accumulator;
pub mod axis_map;

pub use accumulator::PaddleAccumulator;
pub use axis_map::{AxisMap, MappedMotion, MouseAxis};

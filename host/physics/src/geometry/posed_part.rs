//! A primitive of a body posed in the world: what the narrow phase tests and what a
//! refreshed manifold is moved with (`manifold_refresh.rs`).

use super::{Shape, M3, V3};

/// One primitive of a body, posed in the world.
pub(super) struct PosedPart<'a> {
    pub(super) index: u16,
    pub(super) shape: &'a Shape,
    /// World from part rotation.
    pub(super) rot: M3,
    /// Centre (m, world).
    pub(super) pos: V3,
}

//! Finiteness of a physics world's state.

use virtual_physics::pipeline::World;

/// The first body (or articulated tree) of `world` with a non-finite position,
/// rotation, velocity or angular velocity (or joint coordinate), described.
pub(super) fn first_non_finite(world: &World) -> Option<String> {
    for (i, b) in world.bodies().enumerate() {
        let (p, r, v, w) = (
            b.position(),
            b.rotation(),
            b.linear_velocity(),
            b.angular_velocity(),
        );
        let finite = p.iter().chain(r.iter()).chain(v.iter()).chain(w.iter());
        if !finite.into_iter().all(|x| x.is_finite()) {
            return Some(format!(
                "body {i} ({:?}): pos {:?} rot {:?} vel {:?} omega {:?}",
                b.name(),
                p.as_slice(),
                r.as_slice(),
                v.as_slice(),
                w.as_slice()
            ));
        }
    }
    for (k, h) in world.tree_handles().enumerate() {
        let Some(a) = world.tree(h) else { continue };
        if !a.q().iter().chain(a.qd().iter()).all(|v| v.is_finite()) {
            return Some(format!(
                "articulated tree {k}: q {:?} qd {:?}",
                a.q(),
                a.qd()
            ));
        }
    }
    None
}

//! Finiteness of a physics world's state.

use virtual_physics::pipeline::World;

/// The first body (or articulated tree) of `world` with a non-finite position,
/// rotation, velocity or angular velocity (or joint coordinate), described.
pub(super) fn first_non_finite(world: &World) -> Option<String> {
    let b = &world.bodies;
    for i in 0..b.pos.len() {
        let finite = b.pos[i].iter().all(|v| v.is_finite())
            && b.rot[i].iter().all(|v| v.is_finite())
            && b.vel[i].iter().all(|v| v.is_finite())
            && b.omega[i].iter().all(|v| v.is_finite());
        if !finite {
            return Some(format!(
                "body {i} ({:?}): pos {:?} rot {:?} vel {:?} omega {:?}",
                b.name[i],
                b.pos[i].as_slice(),
                b.rot[i].as_slice(),
                b.vel[i].as_slice(),
                b.omega[i].as_slice()
            ));
        }
    }
    for (k, a) in world.articulated.iter().enumerate() {
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

//! A world's clone is a snapshot: stepped on, it gives what the world gives, bit for bit
//! (rollback netcode restores one and steps again). Piles in motion, a tree in contact
//! with stairs and a ball that bounces between walls, cloned mid-run.

use virtual_physics::pipeline::World;
use virtual_physics::scene::hard as scenes;
use virtual_physics::scene::SceneFile;

/// Every body's pose and velocity, every tree's coordinates, and the clock, as bits.
fn state_bits(w: &World) -> Vec<u64> {
    let mut out = vec![w.time().to_bits()];
    for b in w.bodies() {
        let (p, r) = (b.position(), b.rotation());
        let (v, o) = (b.linear_velocity(), b.angular_velocity());
        out.extend(
            p.iter()
                .chain(r.iter())
                .chain(v.iter())
                .chain(o.iter())
                .map(|x| x.to_bits()),
        );
    }
    for t in w.tree_handles() {
        let t = w.tree(t).expect("a tree of the world");
        out.extend(t.q().iter().chain(t.qd()).map(|x| x.to_bits()));
    }
    out
}

fn clone_steps_alike(scene: SceneFile, before: usize, after: usize) {
    let mut world = scene.build().unwrap();
    for _ in 0..before {
        world.step().unwrap();
    }
    // The snapshot, kept while the world moves on, then restored and stepped again.
    let snapshot = world.clone();
    for _ in 0..after {
        world.step().unwrap();
    }
    let mut restored = snapshot.clone();
    for _ in 0..after {
        restored.step().unwrap();
    }
    assert_eq!(state_bits(&world), state_bits(&restored), "{}", scene.name);
    assert_ne!(
        state_bits(&world),
        state_bits(&snapshot),
        "{}: nothing moved",
        scene.name
    );
}

#[test]
fn a_cloned_pile_steps_as_the_original() {
    // A heavy cube wrecking a pyramid: contacts appear, break and warm-start throughout.
    clone_steps_alike(scenes::heavy_on_pyramid(100.0, 6, 1.0), 30, 60);
}

#[test]
fn a_cloned_tree_in_contact_steps_as_the_original() {
    clone_steps_alike(scenes::arm_on_stairs(4, 0.3, 1.0, 0.2, 4), 14, 40);
}

#[test]
fn a_cloned_fast_ball_steps_as_the_original() {
    let d = scenes::spread_directions(1)[0];
    let v = [60.0 * d[0], 60.0 * d[1], 60.0 * d[2]];
    clone_steps_alike(scenes::ball_in_box(v, 0.3, 0.9, 1.0 / 60.0), 5, 30);
}

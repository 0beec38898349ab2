//! Scene JSON: the loader rejects the scene, or the world it builds steps 100 times
//! with every body finite after each step that returns `Ok` (a step may instead return
//! an error; the run then ends there).

use super::finite::first_non_finite;
use super::{text, Verdict};
use virtual_physics::scene::SceneFile;

/// Steps every accepted scene is run for.
pub(super) const STEPS: usize = 100;

pub(super) fn run(input: &[u8]) -> Verdict {
    let Some(text) = text(input) else {
        return Verdict::Rejected;
    };
    let Ok(scene) = SceneFile::from_json(text) else {
        return Verdict::Rejected;
    };
    let Ok(mut world) = scene.build() else {
        return Verdict::Rejected;
    };
    if let Some(body) = first_non_finite(&world) {
        panic!("the built world is not finite: {body}");
    }
    for step in 1..=STEPS {
        if world.step().is_err() {
            break;
        }
        if let Some(body) = first_non_finite(&world) {
            panic!("step {step} returned Ok with a non-finite state: {body}");
        }
    }
    Verdict::Accepted
}

//! A resting world takes fewer substeps only where its contacts hold it as well on them
//! (`pipeline/resting_substeps.rs`).

use virtual_physics::algebra::Vec3;
use virtual_physics::geometry::Shape;
use virtual_physics::pipeline::{BodyBuilder, Effect, World};
use virtual_physics::scene::builtin::{pyramid, towers};
use virtual_physics::scene::SceneFile;

/// The sink (m) a resting world may take on fewer substeps (`SINK_TOLERANCE`).
const SINK_TOLERANCE: f64 = 5e-3;

/// The scene with sleeping off, so that every body stays in the step.
fn awake(mut s: SceneFile) -> World {
    s.effects.retain(|e| *e != Effect::Sleeping);
    s.build().unwrap()
}

/// Steps `n` times; returns the substeps each step took.
fn steps(w: &mut World, n: usize) -> Vec<usize> {
    (0..n)
        .map(|_| {
            w.step().unwrap();
            w.counters().substeps
        })
        .collect()
}

fn largest_move(w: &World, start: &[Vec3]) -> f64 {
    w.bodies()
        .zip(start)
        .map(|(b, p)| (b.position() - p).norm())
        .fold(0.0, f64::max)
}

/// A pyramid (each box on four below it, none standing alone on another) takes the step's 12
/// substeps until it has rested half a second, then a sixth of them (its five layers sink
/// within the tolerance even on 2 substeps), and stays within the
/// sink tolerance of where it started.
#[test]
fn a_resting_pyramid_takes_a_sixth_of_the_substeps() {
    let mut w = awake(pyramid(5));
    let start: Vec<Vec3> = w.bodies().map(|b| b.position()).collect();
    let taken = steps(&mut w, 120);
    // Half a second at 1/60 s is 30 steps of rest.
    assert!(taken[..30].iter().all(|&n| n == 12), "{taken:?}");
    assert!(taken[60..].iter().all(|&n| n == 2), "{taken:?}");
    let moved = largest_move(&w, &start);
    assert!(moved <= SINK_TOLERANCE, "moved {moved} m");
}

/// Boxes standing alone on one another rock on their contacts: a column takes fewer substeps
/// only while its weight stays within half the load its softer contacts hold upright
/// (the rocking ratio, Dunkerley's sum over its contacts, at most ½). A tower of 5 unit cubes
/// (ratio 0.01 on 2 substeps) takes a sixth of the step's 12 substeps; one of 20 (0.31 on 6,
/// 0.69 on 4) a half; one of 40 (2.5 on 6) keeps them all.
#[test]
fn columns_take_fewer_substeps_as_their_height_allows() {
    for (height, fewest) in [(5, 2), (20, 6), (40, 12)] {
        let mut w = awake(towers(1, 1, height));
        let start: Vec<Vec3> = w.bodies().map(|b| b.position()).collect();
        let taken = steps(&mut w, 120);
        assert!(taken[..30].iter().all(|&n| n == 12), "{height}: {taken:?}");
        assert!(
            taken[60..].iter().all(|&n| n == fewest),
            "{height}: {taken:?}"
        );
        // Where it takes fewer, it stays within the sink tolerance of where it started.
        let moved = largest_move(&w, &start);
        assert!(
            fewest == 12 || moved <= SINK_TOLERANCE,
            "{height}: moved {moved} m"
        );
    }
}

/// A resting pyramid's top box thrown upwards moves: that very step takes the full substeps.
#[test]
fn a_moving_body_brings_the_substeps_back_at_once() {
    let mut w = awake(pyramid(5));
    let taken = steps(&mut w, 60);
    assert_eq!(taken.last(), Some(&2), "{taken:?}");
    let top = w.body_handles().last().unwrap();
    w.body_mut(top)
        .unwrap()
        .set_linear_velocity(Vec3::new(0.0, 0.0, 1.0));
    assert_eq!(steps(&mut w, 1), [12]);
}

/// A box added beside the resting pyramid, at rest on the ground: its contact carries no load
/// yet, so the world counts its rest afresh and takes the full substeps meanwhile.
#[test]
fn an_added_body_counts_the_rest_afresh() {
    let mut w = awake(pyramid(5));
    let taken = steps(&mut w, 60);
    assert_eq!(taken.last(), Some(&2), "{taken:?}");
    w.insert_body(
        BodyBuilder::dynamic(Shape::Cuboid {
            half: Vec3::repeat(0.5),
        })
        .mass(1.0)
        .position(Vec3::new(10.0, 0.0, 0.5)),
    );
    let taken = steps(&mut w, 60);
    // Half a second at 1/60 s is 30 steps of rest.
    assert!(taken[..29].iter().all(|&n| n == 12), "{taken:?}");
    assert_eq!(taken.last(), Some(&2), "{taken:?}");
}

/// Switched off, every step takes the settings' substeps.
#[test]
fn switched_off_every_step_takes_the_settings_substeps() {
    let mut w = awake(pyramid(5));
    w.variants_mut().fewer_substeps_at_rest = false;
    let taken = steps(&mut w, 120);
    assert!(taken.iter().all(|&n| n == 12), "{taken:?}");
}

//! How far a tower of five unit boxes wanders sideways at rest on a given number of substeps
//! per 1/60 s step, with every step taking them (no fewer substeps at rest): the largest
//! horizontal move of a box from where it settled after 1 s, every 10 s over 60 s.
//!
//!     cargo run -p virtual-physics --release --example column_wander -- [SUBSTEPS]

use virtual_physics::pipeline::{Effect, World};
use virtual_physics::scene::builtin::towers;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let substeps: usize = match std::env::args().nth(1) {
        Some(a) => a
            .parse()
            .ok()
            .filter(|n| (1..=64).contains(n))
            .ok_or_else(|| format!("SUBSTEPS must be 1 … 64, got '{a}'"))?,
        None => 12,
    };
    let mut s = towers(1, 1, 5);
    s.effects.retain(|e| *e != Effect::Sleeping);
    let mut w = s.build()?;
    w.settings_mut().substeps = substeps;
    w.variants_mut().fewer_substeps_at_rest = false;
    let positions =
        |w: &World| -> Vec<[f64; 3]> { w.bodies().map(|b| b.position().into()).collect() };
    for _ in 0..60 {
        w.step()?;
    }
    let settled = positions(&w);
    print!("{substeps} substeps, largest sideways move every 10 s (m):");
    for k in 60..3600 {
        w.step()?;
        if (k + 1) % 600 == 0 {
            let moved = positions(&w)
                .iter()
                .zip(&settled)
                .map(|(a, b)| (a[0] - b[0]).hypot(a[1] - b[1]))
                .fold(0.0, f64::max);
            print!(" {moved:.2e}");
        }
    }
    println!();
    Ok(())
}

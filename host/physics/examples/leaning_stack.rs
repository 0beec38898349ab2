//! The leaning stack of `tests/hard_stacks.rs` (25 unit boxes, each 3 cm over the one
//! below) at chosen solver settings: the largest tilt of any box (rad) after 0.1 s and 2 s,
//! against the tilt at which the stack above the lowest box-on-box contact tips over its
//! edge, the substeps its island takes per step at 2 s (0: the step's own; see
//! `island_substeps.rs`), and the largest move of any box (m) after 5 s and 20 s at 1/60 s,
//! with the time per step.
//!
//!     cargo run -p virtual-physics --release --example leaning_stack -- [SUBSTEPS [HERTZ [EVEN [FRICTION]]]]
//!
//! `SUBSTEPS` per step (default 12), `contact_hertz` (default 120),
//! `even_mass_stiffening` (default 1.5), and `FRICTION` 0 to leave the friction effect out
//! (default 1: the scene's own effects).

use virtual_physics::pipeline::{Effect, World};
use virtual_physics::scene::builtin::{towers, unit_cube};

/// Boxes in the stack.
const BOXES: usize = 25;
/// Shift of each box over the one below (m).
const LEAN: f64 = 0.03;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args = std::env::args()
        .skip(1)
        .map(|a| a.parse::<f64>().map_err(|e| format!("{a:?}: {e}")))
        .collect::<Result<Vec<f64>, String>>()?;
    let mut s = towers(1, 1, 0);
    for k in 0..BOXES {
        s.bodies
            .push(unit_cube([k as f64 * LEAN, 0.0, 0.5 + k as f64]));
    }
    match args.get(3) {
        None | Some(1.0) => {}
        Some(0.0) => s.effects.retain(|e| *e != Effect::Friction),
        Some(x) => return Err(format!("FRICTION {x}: 0 or 1").into()),
    }
    let mut w = s.build()?;
    let settings = w.settings_mut();
    if let Some(&n) = args.first() {
        if !(1.0..=1000.0).contains(&n) {
            return Err(format!("SUBSTEPS {n}: 1 to 1000").into());
        }
        settings.substeps = n as usize;
    }
    if let Some(&hz) = args.get(1) {
        settings.contact_hertz = hz;
    }
    if let Some(&x) = args.get(2) {
        w.variants_mut().even_mass_stiffening = x;
    }
    // The contact of box 1 on box 0 spans x from the upper box's left face to the lower
    // box's right face (0.5 m); the 24 boxes above it have their centre of mass
    // LEAN (1 + 24) / 2 along and 12 m above that contact. Tilted by more than the
    // lever over the height, that centre passes the edge.
    let above = (BOXES - 1) as f64;
    let lever = 0.5 - LEAN * (1.0 + above) / 2.0;
    let tipping = lever / (above / 2.0);
    let start: Vec<_> = w.bodies().map(|b| b.position()).collect();
    let tilt = |w: &World| {
        w.bodies()
            .map(|b| (b.rotation()[(2, 2)]).clamp(-1.0, 1.0).acos())
            .fold(0.0, f64::max)
    };
    let mut worst: f64 = 0.0;
    let clock = std::time::Instant::now();
    for step in 1..=1200 {
        w.step()?;
        for (b, p0) in w.bodies().zip(&start) {
            worst = worst.max((b.position() - p0).norm());
        }
        if step == 6 || step == 120 {
            print!(
                "largest tilt at {:.1} s {:.4} rad, ",
                step as f64 / 60.0,
                tilt(&w)
            );
        }
        if step == 120 {
            // The stack's island's own substeps per step (0: it takes the step's).
            print!("island substeps {}, ", w.counters().fine_substeps);
        }
        if step == 300 {
            print!("largest move at 5 s {worst:.4} m, ");
        }
    }
    let ms = clock.elapsed().as_secs_f64() * 1e3 / 1200.0;
    println!("at 20 s {worst:.4} m, {ms:.2} ms per step (tips over at {tipping:.4} rad)");
    Ok(())
}

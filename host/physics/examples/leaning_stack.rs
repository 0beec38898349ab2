//! The leaning stack of `tests/hard_stacks.rs` (25 unit boxes, each 3 cm over the one
//! below) at chosen solver settings: the largest move of any box (m) after 5 s and 20 s
//! at 1/60 s, and the time per step.
//!
//!     cargo run -p virtual-physics --release --example leaning_stack -- [SUBSTEPS [HERTZ [EVEN]]]
//!
//! `SUBSTEPS` per step (default 12), `contact_hertz` (default 120) and
//! `even_mass_stiffening` (default 1.5).

use virtual_physics::scene::builtin::{towers, unit_cube};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args = std::env::args()
        .skip(1)
        .map(|a| a.parse::<f64>().map_err(|e| format!("{a:?}: {e}")))
        .collect::<Result<Vec<f64>, String>>()?;
    let mut s = towers(1, 1, 0);
    for k in 0..25 {
        s.bodies
            .push(unit_cube([k as f64 * 0.03, 0.0, 0.5 + k as f64]));
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
        settings.even_mass_stiffening = x;
    }
    let start: Vec<_> = w.bodies().map(|b| b.position()).collect();
    let mut worst: f64 = 0.0;
    let clock = std::time::Instant::now();
    for step in 1..=1200 {
        w.step()?;
        for (b, p0) in w.bodies().zip(&start) {
            worst = worst.max((b.position() - p0).norm());
        }
        if step == 300 {
            print!("largest move at 5 s {worst:.4} m, ");
        }
    }
    let ms = clock.elapsed().as_secs_f64() * 1e3 / 1200.0;
    println!("at 20 s {worst:.4} m, {ms:.2} ms per step");
    Ok(())
}

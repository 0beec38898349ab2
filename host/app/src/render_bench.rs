//! `space-foosball bench render`: frame time of the renderer on the animated demo match
//! offscreen at 1280 × 720 and 1920 × 1080 (or one size given with `--width` and
//! `--height`), printed as one JSON line:
//!
//! ```text
//! {"adapter", "backend", "device_type", "frames", "sizes": [{"width", "height",
//!  "frame_ms_median", "frame_ms_p95", "fps", "cpu_ms_per_frame"}, …]}
//! ```
//!
//! A frame is building the scene, encoding it, submitting and waiting for the GPU to
//! finish (no read back); `fps` is `1000 / frame_ms_median`. `cpu_ms_per_frame` is the
//! CPU time of every thread of the process per timed frame (Linux; on a software
//! adapter that is the whole GPU work, and, unlike the frame time, it hardly moves with
//! what else the machine runs). It runs on the first
//! adapter (a hardware GPU when there is one, else Mesa's software driver).

use anyhow::{bail, Context, Result};
use foosball_render::demo::demo_snapshot;
use foosball_render::{Renderer, Screen, MAX_SIDE};
use space_foosball_app::view;
use std::time::Instant;

/// The sizes measured by default: 1280 × 720 and 1920 × 1080.
const SIZES: [(u32, u32); 2] = [(1280, 720), (1920, 1080)];

/// Arguments of `bench render`.
#[derive(clap::Args, Debug)]
pub struct RenderArgs {
    /// Frames timed per size, after 5 of warm-up.
    #[arg(long, default_value_t = 120, value_parser = clap::value_parser!(u32).range(1..=100_000))]
    pub frames: u32,
    /// Image width, pixels (with `--height`; default: both standard sizes).
    #[arg(long, requires = "height", value_parser = clap::value_parser!(u32).range(1..=i64::from(MAX_SIDE)))]
    pub width: Option<u32>,
    /// Image height, pixels (with `--width`).
    #[arg(long, requires = "width", value_parser = clap::value_parser!(u32).range(1..=i64::from(MAX_SIDE)))]
    pub height: Option<u32>,
    /// Table: `standard`, `paper` or a TOML file.
    #[arg(long, default_value = "standard")]
    pub table: String,
}

/// Runs the benchmark and prints its JSON line.
pub fn run(args: &RenderArgs) -> Result<()> {
    let sizes: Vec<(u32, u32)> = match (args.width, args.height) {
        (Some(w), Some(h)) => vec![(w, h)],
        (None, None) => SIZES.to_vec(),
        _ => bail!("give both --width and --height, or neither"),
    };
    let table = view::table_geometry(&crate::headless::load_table(&args.table)?);
    let frames = args.frames as usize;
    let mut r = Renderer::new().context("opening a graphics adapter")?;
    let mut results = Vec::new();
    for (width, height) in sizes {
        // Warm up (pipeline compilation on first use, target allocation).
        for i in 0..5 {
            let s = demo_snapshot(&table, i as f64 / 60.0, [2, 1]);
            r.render(&s, Screen::Match, width, height)?;
        }
        let mut ms = Vec::with_capacity(frames);
        let cpu_before = process_cpu_s();
        for i in 0..frames {
            let s = demo_snapshot(&table, 1.0 + i as f64 / 60.0, [2, 1]);
            let t0 = Instant::now();
            r.render(&s, Screen::Match, width, height)?;
            ms.push(t0.elapsed().as_secs_f64() * 1e3);
        }
        let cpu_ms = (process_cpu_s() - cpu_before) * 1e3 / frames as f64;
        ms.sort_by(f64::total_cmp);
        let median = ms[ms.len() / 2];
        let p95 = ms[((ms.len() as f64 * 0.95) as usize).min(ms.len() - 1)];
        results.push(serde_json::json!({
            "width": width,
            "height": height,
            "frame_ms_median": (median * 1e3).round() / 1e3,
            "frame_ms_p95": (p95 * 1e3).round() / 1e3,
            "fps": (1e4 / median).round() / 10.0,
            "cpu_ms_per_frame": (cpu_ms * 10.0).round() / 10.0,
        }));
    }
    let a = r.adapter();
    let out = serde_json::json!({
        "adapter": a.name,
        "backend": a.backend,
        "device_type": a.device_type,
        "frames": frames,
        "sizes": results,
    });
    println!("{out}");
    Ok(())
}

/// CPU seconds used so far by all threads of this process (0 where `/proc` is missing).
fn process_cpu_s() -> f64 {
    crate::window::cpu::thread_cpu_seconds().values().sum()
}

//! Frame-time benchmark: renders the animated demo match offscreen at 1280 × 720 and
//! 1920 × 1080 (or one size given with `--width`/`--height`) and prints one JSON line:
//!
//! ```text
//! {"adapter", "backend", "device_type", "frames", "sizes": [{"width", "height",
//!  "frame_ms_median", "frame_ms_p95", "fps"}, …]}
//! ```
//!
//! A frame is building the scene, encoding it, submitting and waiting for the GPU to
//! finish (no read back); `fps` is `1000 / frame_ms_median`. It runs on the first
//! adapter (a hardware GPU when there is one, else Mesa's software driver).
//!
//! ```text
//! cargo run --release -p foosball-render --bin render-bench -- [--frames 120] [--width W --height H]
//! ```

use foosball_render::demo::demo_snapshot;
use foosball_render::{Renderer, Screen};
use space_foosball::table::Table;
use std::process::ExitCode;
use std::time::Instant;

/// The sizes measured by default: the default screenshot size, 1280 × 720, and the 240 fps
/// target's 1920 × 1080.
const SIZES: [(u32, u32); 2] = [(1280, 720), (1920, 1080)];

fn main() -> ExitCode {
    match run() {
        Ok(json) => {
            println!("{json}");
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("render-bench: {e}");
            ExitCode::FAILURE
        }
    }
}

fn parse<T: std::str::FromStr>(name: &str, v: &str) -> Result<T, String>
where
    T::Err: std::fmt::Display,
{
    v.parse().map_err(|e| format!("{name} {v:?}: {e}"))
}

fn run() -> Result<String, String> {
    let (mut width, mut height, mut frames) = (None, None, 120usize);
    let mut args = std::env::args().skip(1);
    while let Some(a) = args.next() {
        let v = args.next().ok_or_else(|| format!("{a} needs a value"))?;
        match a.as_str() {
            "--width" => width = Some(parse::<u32>("--width", &v)?),
            "--height" => height = Some(parse::<u32>("--height", &v)?),
            "--frames" => frames = parse("--frames", &v)?,
            other => return Err(format!("unknown argument {other:?}")),
        }
    }
    let sizes: Vec<(u32, u32)> = match (width, height) {
        (None, None) => SIZES.to_vec(),
        (Some(w), Some(h)) => vec![(w, h)],
        _ => return Err("give both --width and --height, or neither".into()),
    };
    let frames = frames.max(1);
    let table = Table::standard();
    let mut r = Renderer::new().map_err(|e| e.to_string())?;
    let mut results = Vec::new();
    for (width, height) in sizes {
        // Warm up (pipeline compilation on first use, target allocation).
        for i in 0..5 {
            let s = demo_snapshot(&table, i as f64 / 60.0, [2, 1]);
            r.render(&s, Screen::Match, width, height)
                .map_err(|e| e.to_string())?;
        }
        let mut ms = Vec::with_capacity(frames);
        for i in 0..frames {
            let s = demo_snapshot(&table, 1.0 + i as f64 / 60.0, [2, 1]);
            let t0 = Instant::now();
            r.render(&s, Screen::Match, width, height)
                .map_err(|e| e.to_string())?;
            ms.push(t0.elapsed().as_secs_f64() * 1e3);
        }
        ms.sort_by(f64::total_cmp);
        let median = ms[ms.len() / 2];
        let p95 = ms[((ms.len() as f64 * 0.95) as usize).min(ms.len() - 1)];
        results.push(format!(
            "{{\"width\": {width}, \"height\": {height}, \"frame_ms_median\": {median:.3}, \
             \"frame_ms_p95\": {p95:.3}, \"fps\": {:.1}}}",
            1e3 / median
        ));
    }
    let a = r.adapter();
    Ok(format!(
        "{{\"adapter\": {:?}, \"backend\": {:?}, \"device_type\": {:?}, \"frames\": {frames}, \
         \"sizes\": [{}]}}",
        a.name,
        a.backend,
        a.device_type,
        results.join(", ")
    ))
}

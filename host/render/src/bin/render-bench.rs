//! Frame-time benchmark: renders the animated demo match offscreen and prints JSON
//! `{"adapter", "backend", "device_type", "width", "height", "frames",
//! "frame_ms_median", "frame_ms_p95", "fps"}`. A frame is building the scene, encoding
//! it, submitting and waiting for the GPU to finish (no read back).
//!
//! ```text
//! cargo run --release -p foosball-render --bin render-bench -- [--width 1280] [--height 720] [--frames 120]
//! ```

use foosball_render::demo::demo_snapshot;
use foosball_render::{Renderer, Screen};
use space_foosball::table::Table;
use std::process::ExitCode;
use std::time::Instant;

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

fn run() -> Result<String, String> {
    let (mut width, mut height, mut frames) = (1280u32, 720u32, 120usize);
    let mut args = std::env::args().skip(1);
    while let Some(a) = args.next() {
        let v = args.next().ok_or_else(|| format!("{a} needs a value"))?;
        match a.as_str() {
            "--width" => width = v.parse().map_err(|e| format!("--width: {e}"))?,
            "--height" => height = v.parse().map_err(|e| format!("--height: {e}"))?,
            "--frames" => frames = v.parse().map_err(|e| format!("--frames: {e}"))?,
            other => return Err(format!("unknown argument {other:?}")),
        }
    }
    let frames = frames.max(1);
    let table = Table::standard();
    let mut r = Renderer::new().map_err(|e| e.to_string())?;
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
    let a = r.adapter();
    Ok(format!(
        "{{\"adapter\": {:?}, \"backend\": {:?}, \"device_type\": {:?}, \"width\": {width}, \
         \"height\": {height}, \"frames\": {frames}, \"frame_ms_median\": {median:.3}, \
         \"frame_ms_p95\": {p95:.3}, \"fps\": {:.1}}}",
        a.name,
        a.backend,
        a.device_type,
        1e3 / median
    ))
}

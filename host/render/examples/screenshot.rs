//! Renders a screen of the demo scene offscreen to a PNG.
//!
//! ```text
//! cargo run -p foosball-render --example screenshot -- --screen match --out match.png
//!     [--width 1280] [--height 720] [--table standard|paper] [--time 2.6]
//! cargo run -p foosball-render --example screenshot -- --all DIR   # every screen
//! ```

use foosball_render::demo::screen_snapshot;
use foosball_render::{Renderer, Screen};
use space_foosball::table::Table;
use std::path::PathBuf;
use std::process::ExitCode;

fn main() -> ExitCode {
    match run() {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("screenshot: {e}");
            ExitCode::FAILURE
        }
    }
}

fn run() -> Result<(), String> {
    let mut screen = Screen::Match;
    let mut out: Option<PathBuf> = None;
    let mut all: Option<PathBuf> = None;
    let (mut width, mut height) = (1280u32, 720u32);
    let mut table = Table::standard();
    let mut time = 2.6f64;
    let mut args = std::env::args().skip(1);
    while let Some(a) = args.next() {
        let mut value = || args.next().ok_or_else(|| format!("{a} needs a value"));
        match a.as_str() {
            "--screen" => {
                let v = value()?;
                screen = Screen::from_name(&v).ok_or_else(|| {
                    let names: Vec<_> = Screen::ALL.iter().map(|s| s.name()).collect();
                    format!("unknown screen {v:?} (screens: {})", names.join(", "))
                })?;
            }
            "--out" => out = Some(value()?.into()),
            "--all" => all = Some(value()?.into()),
            "--width" => width = value()?.parse().map_err(|e| format!("--width: {e}"))?,
            "--height" => height = value()?.parse().map_err(|e| format!("--height: {e}"))?,
            "--time" => time = value()?.parse().map_err(|e| format!("--time: {e}"))?,
            "--table" => table = Table::preset(&value()?).map_err(|e| e.to_string())?,
            other => return Err(format!("unknown argument {other:?}")),
        }
    }
    let mut renderer = Renderer::new().map_err(|e| e.to_string())?;
    let jobs: Vec<(Screen, PathBuf)> = match (all, out) {
        (Some(dir), _) => {
            std::fs::create_dir_all(&dir).map_err(|e| format!("{}: {e}", dir.display()))?;
            Screen::ALL
                .iter()
                .map(|s| (*s, dir.join(format!("{}.png", s.name()))))
                .collect()
        }
        (None, Some(path)) => vec![(screen, path)],
        (None, None) => return Err("give --out FILE.png or --all DIR".into()),
    };
    for (screen, path) in jobs {
        let snap = screen_snapshot(&table, time, screen);
        let img = renderer
            .render_to_rgba(&snap, screen, width, height)
            .map_err(|e| e.to_string())?;
        img.save_png(&path).map_err(|e| e.to_string())?;
        println!(
            "{} -> {} ({})",
            screen.name(),
            path.display(),
            renderer.adapter().name
        );
    }
    Ok(())
}

//! `space-foosball screenshot`: any screen of the demo scene rendered offscreen to PNG.

use anyhow::{bail, Context, Result};
use foosball_render::demo::screen_snapshot;
use foosball_render::{Renderer, Screen, MAX_SIDE};
use space_foosball::atomic_file::write_atomic;
use space_foosball_app::view;
use std::path::{Path, PathBuf};

/// Which screens to picture.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Which {
    /// One screen, written to the `--out` file.
    One(Screen),
    /// Every screen, written as `<name>.png` into the `--out` directory.
    All,
}

/// The valid `--screen` values, comma-separated.
fn valid_names() -> String {
    let mut names: Vec<&str> = Screen::ALL.iter().map(|s| s.name()).collect();
    names.push("all");
    names.join(", ")
}

/// Parses a `--screen` value: a screen name or `all`.
fn parse_which(name: &str) -> Result<Which, String> {
    if name == "all" {
        return Ok(Which::All);
    }
    Screen::from_name(name)
        .map(Which::One)
        .ok_or_else(|| format!("unknown screen {name:?}; valid screens: {}", valid_names()))
}

/// Arguments of `space-foosball screenshot`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// Screen to render: attract, character-select, match, goal-ceremony, final-result,
    /// board-lost, calibration, or `all`.
    #[arg(long, value_name = "NAME", value_parser = parse_which)]
    pub screen: Which,
    /// Output PNG file; with `--screen all` a directory (created if missing) that gets
    /// one `<screen>.png` per screen.
    #[arg(long, value_name = "PATH")]
    pub out: PathBuf,
    /// Image width, pixels.
    #[arg(long, default_value_t = 1280, value_parser = clap::value_parser!(u32).range(1..=i64::from(MAX_SIDE)))]
    pub width: u32,
    /// Image height, pixels.
    #[arg(long, default_value_t = 720, value_parser = clap::value_parser!(u32).range(1..=i64::from(MAX_SIDE)))]
    pub height: u32,
    /// Table preset (`standard` or `paper`) or a table TOML file.
    #[arg(long, default_value = "standard", value_name = "PRESET")]
    pub table: String,
    /// Time in the demo scene, s (moves the rods, the ball and the stars).
    #[arg(long, default_value_t = 2.6, value_name = "SECONDS")]
    pub time: f64,
}

/// Renders the requested screens and writes the PNGs (each atomically: a temporary
/// file in the same directory, then a rename).
pub fn run(args: &Args) -> Result<()> {
    if !args.time.is_finite() {
        bail!(
            "--time must be a finite number of seconds, not {}",
            args.time
        );
    }
    let table = crate::headless::load_table(&args.table)?;
    let jobs = jobs(args.screen, &args.out)?;
    let mut renderer = Renderer::new().context("opening a graphics adapter")?;
    for (screen, path) in jobs {
        let snap = screen_snapshot(&view::table_geometry(&table), args.time, screen);
        let img = renderer
            .render_to_rgba(&snap, screen, args.width, args.height)
            .with_context(|| format!("rendering screen {}", screen.name()))?;
        let png = img.to_png().context("encoding PNG")?;
        write_atomic(&path, &png).with_context(|| format!("writing {}", path.display()))?;
        println!(
            "{} -> {} ({}x{}, {})",
            screen.name(),
            path.display(),
            args.width,
            args.height,
            renderer.adapter().name
        );
    }
    Ok(())
}

/// The (screen, file) pairs to write, after checking the output location before any
/// (slow) rendering starts.
fn jobs(which: Which, out: &Path) -> Result<Vec<(Screen, PathBuf)>> {
    match which {
        Which::All => {
            if out.exists() && !out.is_dir() {
                bail!(
                    "--screen all writes one PNG per screen into a directory, but {} is a file",
                    out.display()
                );
            }
            std::fs::create_dir_all(out)
                .with_context(|| format!("creating directory {}", out.display()))?;
            Ok(Screen::ALL
                .iter()
                .map(|s| (*s, out.join(format!("{}.png", s.name()))))
                .collect())
        }
        Which::One(screen) => {
            if out.is_dir() {
                bail!(
                    "{} is a directory; give a file name such as {}",
                    out.display(),
                    out.join(format!("{}.png", screen.name())).display()
                );
            }
            let parent = match out.parent() {
                Some(p) if !p.as_os_str().is_empty() => p,
                _ => Path::new("."),
            };
            if !parent.is_dir() {
                bail!(
                    "cannot write {}: directory {} does not exist",
                    out.display(),
                    parent.display()
                );
            }
            Ok(vec![(screen, out.to_path_buf())])
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn screen_names_parse_and_unknown_ones_list_the_valid() {
        assert_eq!(parse_which("all"), Ok(Which::All));
        for s in Screen::ALL {
            assert_eq!(parse_which(s.name()), Ok(Which::One(s)));
        }
        let e = parse_which("lobby").unwrap_err();
        assert!(e.contains("lobby") && e.contains("goal-ceremony") && e.contains("all"));
    }

    #[test]
    fn output_locations_are_checked_before_rendering() {
        let dir = tempfile::tempdir().unwrap();
        let missing = dir.path().join("no/such/dir/x.png");
        assert!(jobs(Which::One(Screen::Match), &missing).is_err());
        assert!(jobs(Which::One(Screen::Match), dir.path()).is_err());
        let file = dir.path().join("f.png");
        std::fs::write(&file, b"x").unwrap();
        assert!(jobs(Which::All, &file).is_err());
        let all = jobs(Which::All, &dir.path().join("shots")).unwrap();
        assert_eq!(all.len(), Screen::ALL.len());
        assert!(dir.path().join("shots").is_dir());
    }
}

//! `vphys peers front`: accuracy against time on the stacking scenes, ours over its substeps
//! and rapier3d over its solver iterations (feature `rapier-peer`), sleeping off.
//!
//! Each setting steps the scene from the same start for the same number of steps; a point is
//! (median ms per step, largest drift of a box from its start, m). Ours and Rapier's runs
//! alternate setting by setting in one process, so both see the same machine load. The
//! *front* compares the two at equal accuracy: for every drift level Rapier reaches, the
//! least time any of our settings takes to hold that drift, as a ratio of Rapier's time.

use std::path::Path;

use anyhow::{anyhow, Result};
use plotters::coord::Shift;
use plotters::prelude::*;
use serde::Serialize;
use virtual_physics::pipeline::World;

use crate::figure::Figure;
use crate::rapier_peer::{max_drift, missing, rapier_run, DynamicBodies, RapierSettings};
use crate::run::{load, stats, time_steps};

/// The stacking scenes compared by default (`peers front`, `peers rapier`, `accuracy --peers`).
pub const SCENES: [&str; 2] = ["towers-1120", "pyramid-1240"];
/// Our accuracy knob: substeps per step (12 is the default).
pub const OUR_SUBSTEPS: [usize; 6] = [2, 4, 8, 12, 16, 24];
/// Rapier's: solver iterations per step (4 is its default).
pub const RAPIER_ITERATIONS: [usize; 6] = [1, 2, 4, 8, 12, 16];

/// One measured setting.
#[derive(Clone, Debug, Serialize)]
pub struct Point {
    scene: String,
    engine: &'static str,
    /// Substeps (ours) or solver iterations (Rapier).
    setting: usize,
    ms_per_step: f64,
    max_drift_m: f64,
}

/// At one of Rapier's drift levels: Rapier's time and our least time that holds the drift.
#[derive(Clone, Debug, Serialize)]
pub struct FrontRow {
    scene: String,
    rapier_iterations: usize,
    rapier_drift_m: f64,
    rapier_ms: f64,
    /// Our cheapest setting with a drift at most Rapier's, if any.
    ours_substeps: Option<usize>,
    ours_ms: Option<f64>,
    ratio: Option<f64>,
}

fn ours(scene: &str, substeps: usize, steps: Option<u64>) -> Result<(f64, f64)> {
    let s = load(scene, Some(false))?;
    let n = steps.or(s.steps).unwrap_or(600);
    let mut w = s.build()?;
    w.settings_mut().substeps = substeps;
    let dynamic = DynamicBodies::of(&w);
    let snap = |w: &World| dynamic.positions(w);
    let start = snap(&w);
    let ms = stats(&time_steps(&mut w, n, false)?).0;
    Ok((ms, max_drift(&start, &snap(&w))))
}

/// The front of one scene's points.
fn front(scene: &str, points: &[Point]) -> Vec<FrontRow> {
    let of = |e: &'static str| {
        points
            .iter()
            .filter(move |p| p.scene == scene && p.engine == e)
    };
    of("rapier")
        .map(|r| {
            let best = of("ours")
                .filter(|o| o.max_drift_m <= r.max_drift_m)
                .min_by(|a, b| a.ms_per_step.total_cmp(&b.ms_per_step));
            FrontRow {
                scene: scene.to_string(),
                rapier_iterations: r.setting,
                rapier_drift_m: r.max_drift_m,
                rapier_ms: r.ms_per_step,
                ours_substeps: best.map(|o| o.setting),
                ours_ms: best.map(|o| o.ms_per_step),
                ratio: best.map(|o| o.ms_per_step / r.ms_per_step),
            }
        })
        .collect()
}

/// Runs the sweep; prints the points and the front (or one JSON object), and draws the
/// chart to `chart` (`.svg` and `.png` beside each other) when given.
pub fn run(scenes: &[String], steps: Option<u64>, json: bool, chart: Option<&Path>) -> Result<()> {
    if cfg!(not(feature = "rapier-peer")) {
        return Err(missing());
    }
    let points = measure(scenes, steps, true)?;
    report(scenes, &points, json, chart)
}

/// Steps every scene at each of our settings and, with `rapier`, at each of Rapier's,
/// alternating setting by setting so that both engines see the same machine load.
pub(crate) fn measure(scenes: &[String], steps: Option<u64>, rapier: bool) -> Result<Vec<Point>> {
    let mut points = Vec::new();
    for scene in scenes {
        let s = load(scene, Some(false))?;
        let n = steps.or(s.steps).unwrap_or(600);
        for (&k, &it) in OUR_SUBSTEPS.iter().zip(&RAPIER_ITERATIONS) {
            let (ms, drift) = ours(scene, k, Some(n))?;
            points.push(Point {
                scene: scene.clone(),
                engine: "ours",
                setting: k,
                ms_per_step: ms,
                max_drift_m: drift,
            });
            if !rapier {
                continue;
            }
            let (ms, drift) = rapier_run(&s, false, n, RapierSettings::Iterations(it))?;
            points.push(Point {
                scene: scene.clone(),
                engine: "rapier",
                setting: it,
                ms_per_step: ms,
                max_drift_m: drift,
            });
        }
    }
    Ok(points)
}

/// Prints `points` and their front (or one JSON object), and draws the chart to `chart`
/// (`.svg` and `.png` beside each other) when given.
pub(crate) fn report(
    scenes: &[String],
    points: &[Point],
    json: bool,
    chart: Option<&Path>,
) -> Result<()> {
    let rows: Vec<FrontRow> = scenes.iter().flat_map(|s| front(s, points)).collect();
    if let Some(path) = chart {
        draw(scenes, points, path)?;
    }
    if json {
        outln!("{}", serde_json::json!({ "points": points, "front": rows }));
        return Ok(());
    }
    outln!("sleeping off; median ms per step, one thread; drift = largest move of a box (m)");
    outln!(
        "{:<14} {:>7} {:>8} {:>10} {:>12}",
        "scene",
        "engine",
        "setting",
        "ms",
        "drift m"
    );
    for p in points {
        outln!(
            "{:<14} {:>7} {:>8} {:>10.3} {:>12.5}",
            p.scene,
            p.engine,
            p.setting,
            p.ms_per_step,
            p.max_drift_m
        );
    }
    outln!();
    if !points.iter().any(|p| p.engine == "rapier") {
        outln!("not measured: rapier3d (--features rapier-peer); no front");
        return Ok(());
    }
    outln!("the front: for each of Rapier's drift levels, our least time that holds it");
    outln!(
        "{:<14} {:>10} {:>12} {:>10} {:>9} {:>10} {:>7}",
        "scene",
        "iterations",
        "drift m",
        "rapier ms",
        "substeps",
        "ours ms",
        "ratio"
    );
    let opt = |x: Option<f64>, p: usize| x.map_or("-".to_string(), |v| format!("{v:.p$}"));
    for r in &rows {
        outln!(
            "{:<14} {:>10} {:>12.5} {:>10.3} {:>9} {:>10} {:>7}",
            r.scene,
            r.rapier_iterations,
            r.rapier_drift_m,
            r.rapier_ms,
            r.ours_substeps.map_or("-".to_string(), |k| k.to_string()),
            opt(r.ours_ms, 3),
            opt(r.ratio, 2)
        );
    }
    Ok(())
}

/// Drift against ms per step, log–log, one panel per scene.
struct FrontChart<'a> {
    scenes: &'a [String],
    points: &'a [Point],
}

fn draw(scenes: &[String], points: &[Point], path: &Path) -> Result<()> {
    let size = (750 * scenes.len().max(1) as u32, 600);
    let chart = FrontChart { scenes, points };
    crate::figure::save(
        &chart,
        size,
        &path.with_extension("svg"),
        &path.with_extension("png"),
    )
}

impl Figure for FrontChart<'_> {
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<()>
    where
        DB::ErrorType: 'static,
    {
        panels(self.scenes, self.points, root)
    }
}

fn panels<DB: DrawingBackend>(
    scenes: &[String],
    points: &[Point],
    root: &DrawingArea<DB, Shift>,
) -> Result<()>
where
    DB::ErrorType: 'static,
{
    root.fill(&WHITE).map_err(|e| anyhow!("{e}"))?;
    for (area, scene) in root
        .split_evenly((1, scenes.len().max(1)))
        .iter()
        .zip(scenes)
    {
        let pts: Vec<&Point> = points
            .iter()
            .filter(|p| &p.scene == scene && p.ms_per_step > 0.0 && p.max_drift_m > 0.0)
            .collect();
        let span = |f: fn(&Point) -> f64| {
            crate::figure::log_span(pts.iter().map(move |p| f(p)), 1.5, 1e-3..1.0)
        };
        let (xr, yr) = (span(|p| p.ms_per_step), span(|p| p.max_drift_m));
        let caption = format!("{scene}: drift against time");
        let mut chart = crate::figure::log_log(area, &caption, xr, yr)?;
        chart
            .configure_mesh()
            .x_desc("ms per step (one thread)")
            .y_desc("largest drift of a box (m)")
            .x_label_formatter(&|x| format!("{x:.2}"))
            .y_label_formatter(&|y| format!("{y:.0e}"))
            .label_style(("sans-serif", 13))
            .draw()
            .map_err(|e| anyhow!("{e}"))?;
        for (engine, label, c) in [
            ("ours", "ours (2–24 substeps)", RGBColor(31, 119, 180)),
            (
                "rapier",
                "rapier3d (1–16 iterations)",
                RGBColor(214, 39, 40),
            ),
        ] {
            let series: Vec<(f64, f64)> = pts
                .iter()
                .filter(|p| p.engine == engine)
                .map(|p| (p.ms_per_step, p.max_drift_m))
                .collect();
            if series.is_empty() {
                continue;
            }
            crate::figure::curve(&mut chart, series, c, 4, label.to_string())?;
        }
        crate::figure::legend(&mut chart, SeriesLabelPosition::UpperRight, 13)?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn point(engine: &'static str, setting: usize, ms: f64, drift: f64) -> Point {
        Point {
            scene: "s".into(),
            engine,
            setting,
            ms_per_step: ms,
            max_drift_m: drift,
        }
    }

    /// At each of Rapier's drifts the front takes our cheapest setting that holds it, and
    /// none where no setting of ours does.
    #[test]
    fn the_front_takes_our_cheapest_setting_that_holds_rapiers_drift() {
        let points = [
            point("ours", 2, 1.0, 0.2),
            point("ours", 4, 2.0, 0.03),
            point("ours", 8, 3.0, 0.009),
            point("rapier", 1, 0.5, 0.01),
            point("rapier", 4, 1.5, 0.1),
            point("rapier", 16, 4.0, 0.001),
        ];
        let rows = front("s", &points);
        let picked: Vec<Option<usize>> = rows.iter().map(|r| r.ours_substeps).collect();
        assert_eq!(picked, [Some(8), Some(4), None]);
        assert_eq!(rows[0].ratio, Some(3.0 / 0.5));
        assert_eq!(rows[1].ratio, Some(2.0 / 1.5));
    }
}

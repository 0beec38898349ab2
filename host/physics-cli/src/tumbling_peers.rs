//! `vphys peers tumbling`: the accuracy report's tumbling box in our engine, in MuJoCo (when
//! the Python package is installed) and in rapier3d (feature `rapier-peer`), measured
//! against the same converged reference.
//!
//! The error is the report's: the largest `|ω_b − ω_ref| / |ω₀|` over the 0.1 s samples of
//! the 10 s run, `ω_b` the body-frame angular velocity, the reference our RKMK4 at 1/64000 s.
//! Cost is CPU seconds per simulated second. MuJoCo runs `host/physics/peers/mujoco_tumbling.py`
//! (its Euler, implicitfast and RK4 integrators; the steps of each sample in one `mj_step`
//! call); Rapier steps one free cuboid with its gyroscopic forces on (its default).

use std::path::Path;
use std::process::Command;

use crate::figure::Figure;
use anyhow::{anyhow, bail, Context, Result};
use plotters::coord::Shift;
use plotters::prelude::*;
use serde::Serialize;
use virtual_physics::measure::accuracy::free_body::{self, Trajectory, OMEGA0};
use virtual_physics::pipeline::IntegratorKind;

/// The steps measured (s).
/// The MuJoCo side of the comparison (run with `python3`, or `--python`).
pub const MUJOCO_SCRIPT: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../physics/peers/mujoco_tumbling.py"
);
pub const STEPS: [f64; 4] = [1.0 / 60.0, 1.0 / 250.0, 1.0 / 1000.0, 1.0 / 4000.0];

/// One engine and integrator at one step.
#[derive(Clone, Debug, Serialize)]
pub struct Point {
    engine: &'static str,
    integrator: String,
    dt: f64,
    error: f64,
    cpu_s_per_sim_s: f64,
}

/// The report's error of body angular velocity samples against the reference's.
fn error(samples: &[[f64; 3]], reference: &Trajectory) -> f64 {
    let w0 = (OMEGA0[0].powi(2) + OMEGA0[1].powi(2) + OMEGA0[2].powi(2)).sqrt();
    if samples.len() != reference.omega.len() {
        return f64::INFINITY;
    }
    samples
        .iter()
        .zip(&reference.omega)
        .map(|(a, b)| {
            let d = [a[0] - b.x, a[1] - b.y, a[2] - b.z];
            (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt() / w0
        })
        .fold(
            0.0,
            |m: f64, e| if e.is_nan() { f64::INFINITY } else { m.max(e) },
        )
}

/// MuJoCo's points, or `None` when `python` has no `mujoco` package.
fn mujoco(python: &str, script: &Path, reference: &Trajectory) -> Result<Option<Vec<Point>>> {
    let installed = Command::new(python)
        .args(["-c", "import mujoco"])
        .output()
        .map(|o| o.status.success())
        .unwrap_or(false);
    if !installed {
        return Ok(None);
    }
    let out = Command::new(python)
        .arg(script)
        .args(STEPS.iter().map(|dt| format!("{dt:e}")))
        .output()
        .with_context(|| format!("running {python} {}", script.display()))?;
    if !out.status.success() {
        bail!(
            "mujoco script failed: {}",
            String::from_utf8_lossy(&out.stderr).trim()
        );
    }
    #[derive(serde::Deserialize)]
    struct Run {
        integrator: String,
        dt: f64,
        cpu_s: f64,
        omega: Vec<[f64; 3]>,
    }
    let mut points = Vec::new();
    for line in String::from_utf8(out.stdout)?.lines() {
        let r: Run = serde_json::from_str(line).context("a line of the mujoco script")?;
        points.push(Point {
            engine: "mujoco",
            integrator: r.integrator,
            dt: r.dt,
            error: error(&r.omega, reference),
            cpu_s_per_sim_s: r.cpu_s / free_body::DURATION,
        });
    }
    Ok(Some(points))
}

/// Rapier's points (one free cuboid, gyroscopic forces on), or `None` without the feature.
#[cfg(feature = "rapier-peer")]
fn rapier(reference: &Trajectory) -> Option<Vec<Point>> {
    use rapier3d::prelude::*;
    let h = free_body::HALF_EXTENTS;
    let volume = 8.0 * h[0] * h[1] * h[2];
    let points = STEPS
        .iter()
        .map(|&dt| {
            let mut w = PhysicsWorld {
                gravity: Vector::new(0.0, 0.0, 0.0),
                ..PhysicsWorld::default()
            };
            w.integration_parameters.dt = dt as Real;
            let rb = RigidBodyBuilder::dynamic()
                .angvel(Vector::new(
                    OMEGA0[0] as Real,
                    OMEGA0[1] as Real,
                    OMEGA0[2] as Real,
                ))
                .can_sleep(false);
            let col = ColliderBuilder::cuboid(h[0] as Real, h[1] as Real, h[2] as Real)
                .density((free_body::MASS / volume) as Real);
            let (b, _) = w.insert(rb, col);
            let per_sample = free_body::SAMPLE / dt;
            let (mut samples, mut cpu) = (Vec::new(), 0.0);
            for _ in 0..(free_body::DURATION / free_body::SAMPLE).round() as usize {
                let t0 = virtual_physics::measure::accuracy::cpu_seconds();
                for _ in 0..per_sample.round() as usize {
                    w.step();
                }
                cpu += virtual_physics::measure::accuracy::cpu_seconds() - t0;
                let body = &w.bodies[b];
                let wb = body.rotation().inverse() * body.angvel();
                samples.push([wb.x as f64, wb.y as f64, wb.z as f64]);
            }
            Point {
                engine: "rapier",
                integrator: "default".into(),
                dt,
                error: error(&samples, reference),
                cpu_s_per_sim_s: cpu / free_body::DURATION,
            }
        })
        .collect();
    Some(points)
}

#[cfg(not(feature = "rapier-peer"))]
fn rapier(_: &Trajectory) -> Option<Vec<Point>> {
    None
}

/// Runs every engine present; prints the points (or `{"points": [...], "missing": [...]}`)
/// and draws the chart to `chart` (`.svg` and `.png`) when given.
pub fn run(python: &str, script: &Path, json: bool, chart: Option<&Path>) -> Result<()> {
    let reference = free_body::reference()?;
    let mut points = Vec::new();
    for kind in IntegratorKind::ALL {
        for &dt in &STEPS {
            let r = free_body::row(kind, dt, &reference)?;
            points.push(Point {
                engine: "ours",
                integrator: kind.name().to_string(),
                dt,
                error: r.error,
                cpu_s_per_sim_s: r.cpu_s_per_sim_s,
            });
        }
    }
    let mut missing = Vec::new();
    match mujoco(python, script, &reference)? {
        Some(p) => points.extend(p),
        None => missing.push("mujoco (pip install mujoco)"),
    }
    match rapier(&reference) {
        Some(p) => points.extend(p),
        None => missing.push("rapier3d (--features rapier-peer)"),
    }
    if let Some(path) = chart {
        draw(&points, path)?;
    }
    if json {
        outln!(
            "{}",
            serde_json::json!({ "points": points, "missing": missing })
        );
        return Ok(());
    }
    outln!("tumbling box, 10 s: error = max |ω_b − ω_ref| / |ω₀|; cost = CPU s per simulated s");
    outln!(
        "{:<8} {:<20} {:>10} {:>12} {:>12}",
        "engine",
        "integrator",
        "dt s",
        "error",
        "cpu s/s"
    );
    for p in &points {
        outln!(
            "{:<8} {:<20} {:>10.6} {:>12.3e} {:>12.3e}",
            p.engine,
            p.integrator,
            p.dt,
            p.error,
            p.cpu_s_per_sim_s
        );
    }
    for m in &missing {
        outln!("not measured: {m}");
    }
    Ok(())
}

fn colour(i: usize) -> RGBColor {
    const C: [RGBColor; 10] = [
        RGBColor(214, 39, 40),
        RGBColor(31, 119, 180),
        RGBColor(44, 160, 44),
        RGBColor(148, 103, 189),
        RGBColor(255, 127, 14),
        RGBColor(140, 86, 75),
        RGBColor(227, 119, 194),
        RGBColor(127, 127, 127),
        RGBColor(188, 189, 34),
        RGBColor(23, 190, 207),
    ];
    C[i % C.len()]
}

/// Error against cost, log–log, one curve per engine and integrator.
struct TumblingChart<'a>(&'a [Point]);

fn draw(points: &[Point], path: &Path) -> Result<()> {
    let (svg, png) = (path.with_extension("svg"), path.with_extension("png"));
    crate::figure::save(&TumblingChart(points), (900, 650), &svg, &png)
}

impl Figure for TumblingChart<'_> {
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<()>
    where
        DB::ErrorType: 'static,
    {
        panel(self.0, root)
    }
}

fn panel<DB: DrawingBackend>(points: &[Point], root: &DrawingArea<DB, Shift>) -> Result<()>
where
    DB::ErrorType: 'static,
{
    root.fill(&WHITE).map_err(|e| anyhow!("{e}"))?;
    let shown: Vec<&Point> = points
        .iter()
        .filter(|p| p.error.is_finite() && p.error > 0.0 && p.cpu_s_per_sim_s > 0.0)
        .collect();
    let span = |f: fn(&Point) -> f64| {
        crate::figure::log_span(shown.iter().map(move |p| f(p)), 2.0, 1e-6..1.0)
    };
    let (xr, yr) = (span(|p| p.cpu_s_per_sim_s), span(|p| p.error));
    let caption = "tumbling box: error against cost, ours and the peers";
    let mut chart = crate::figure::log_log(root, caption, xr, yr)?;
    chart
        .configure_mesh()
        .x_desc("CPU s per simulated s")
        .y_desc("max |w - w_ref| / |w0| (body angular velocity)")
        .x_label_formatter(&|x| format!("{x:.0e}"))
        .y_label_formatter(&|y| format!("{y:.0e}"))
        .label_style(("sans-serif", 13))
        .draw()
        .map_err(|e| anyhow!("{e}"))?;
    let mut curves: Vec<(&'static str, String)> = Vec::new();
    for p in &shown {
        let key = (p.engine, p.integrator.clone());
        if !curves.contains(&key) {
            curves.push(key);
        }
    }
    for (i, (engine, integrator)) in curves.iter().enumerate() {
        let c = colour(i);
        let series: Vec<(f64, f64)> = shown
            .iter()
            .filter(|p| p.engine == *engine && &p.integrator == integrator)
            .map(|p| (p.cpu_s_per_sim_s, p.error))
            .collect();
        crate::figure::curve(&mut chart, series, c, 3, format!("{engine} {integrator}"))?;
    }
    crate::figure::legend(&mut chart, SeriesLabelPosition::LowerLeft, 12)?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The peers' error is the report's: samples equal to the reference give 0, and a
    /// sample off by |ω₀| anywhere gives 1.
    #[test]
    fn a_peer_is_measured_against_the_reference_as_ours_is() {
        let reference = Trajectory {
            omega: vec![virtual_physics::algebra::Vec3::new(0.0, 5.0, 0.05); 3],
            cpu_s: 0.0,
            energy_drift: 0.0,
            momentum_drift: 0.0,
            flips: 0,
        };
        let same = vec![[0.0, 5.0, 0.05]; 3];
        assert_eq!(error(&same, &reference), 0.0);
        let w0 = (25.0f64 + 0.0025).sqrt();
        let mut off = same.clone();
        off[1][0] = w0;
        assert!((error(&off, &reference) - 1.0).abs() < 1e-12);
        assert_eq!(error(&same[..2], &reference), f64::INFINITY);
    }
}

//! The chart: error against CPU seconds per simulated second, log–log, one panel per problem,
//! one curve per integrator (points in order of the step). PNG and SVG from the same code
//! (`crate::figure`), text in the committed Cantarell font through plotters' `ab_glyph` feature.

use std::path::Path;

use anyhow::{anyhow, Result};
use plotters::coord::Shift;
use plotters::prelude::*;
use virtual_physics::measure::accuracy::Problem;
use virtual_physics::pipeline::IntegratorKind;

use super::Report;
use crate::figure::Figure;

const SIZE: (u32, u32) = (1500, 1000);

fn colour(k: IntegratorKind) -> RGBColor {
    match k {
        IntegratorKind::ExplicitEuler => RGBColor(214, 39, 40),
        IntegratorKind::SymplecticEuler => RGBColor(31, 119, 180),
        IntegratorKind::Rkmk4 => RGBColor(44, 160, 44),
        IntegratorKind::EnergyMomentum => RGBColor(148, 103, 189),
        IntegratorKind::ImplicitGyroscopic => RGBColor(255, 127, 14),
    }
}

/// Draws the chart to `png` and `svg` (each through a temporary file and a rename).
pub fn draw(r: &Report, png: &Path, svg: &Path) -> Result<()> {
    crate::figure::save(&Chart(r), SIZE, svg, png)
}

/// The report's chart.
struct Chart<'a>(&'a Report);

impl Figure for Chart<'_> {
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<()>
    where
        DB::ErrorType: 'static,
    {
        panels(self.0, root)
    }
}

fn panels<DB: DrawingBackend>(r: &Report, root: &DrawingArea<DB, Shift>) -> Result<()>
where
    DB::ErrorType: 'static,
{
    root.fill(&WHITE).map_err(|e| anyhow!("{e}"))?;
    let (title, body) = root.split_vertically(40);
    title
        .titled(
            "Error against CPU time per simulated second (log-log; each point one step size)",
            ("sans-serif", 24),
        )
        .map_err(|e| anyhow!("{e}"))?;
    for (area, p) in body.split_evenly((2, 3)).iter().zip(Problem::ALL) {
        panel(r, area, p)?;
    }
    Ok(())
}

fn panel<DB: DrawingBackend>(r: &Report, area: &DrawingArea<DB, Shift>, p: Problem) -> Result<()>
where
    DB::ErrorType: 'static,
{
    let pts: Vec<(f64, f64)> = r
        .rows
        .iter()
        .filter(|row| row.problem == p.name())
        .map(|row| (row.cpu_s_per_sim_s, row.error))
        .filter(|(x, y)| x.is_finite() && *x > 0.0 && y.is_finite() && *y > 0.0)
        .collect();
    let range = |f: fn(&(f64, f64)) -> f64| {
        let lo = pts.iter().map(f).fold(f64::INFINITY, f64::min);
        let hi = pts.iter().map(f).fold(0.0, f64::max);
        if lo.is_finite() && hi > lo {
            (lo / 2.0)..(hi * 2.0)
        } else {
            1e-6..1.0
        }
    };
    let (xr, yr) = (range(|p| p.0), range(|p| p.1));
    let mut chart = crate::figure::log_log(area, p.name(), xr, yr)?;
    chart
        .configure_mesh()
        .x_desc("CPU s per simulated s")
        .y_desc(if p == Problem::Towers {
            "drift (m)"
        } else {
            "error"
        })
        .x_labels(5)
        .y_labels(6)
        .x_label_formatter(&|x| format!("{x:.0e}"))
        .y_label_formatter(&|y| format!("{y:.0e}"))
        .label_style(("sans-serif", 13))
        .draw()
        .map_err(|e| anyhow!("{e}"))?;
    for k in IntegratorKind::ALL {
        let c = colour(k);
        let series: Vec<(f64, f64)> = r
            .rows
            .iter()
            .filter(|row| row.problem == p.name() && row.integrator == k.name())
            .map(|row| (row.cpu_s_per_sim_s, row.error))
            .filter(|(x, y)| x.is_finite() && *x > 0.0 && y.is_finite() && *y > 0.0)
            .collect();
        crate::figure::curve(&mut chart, series, c, 3, k.name().to_string())?;
    }
    crate::figure::legend(&mut chart, SeriesLabelPosition::LowerLeft, 12)?;
    Ok(())
}

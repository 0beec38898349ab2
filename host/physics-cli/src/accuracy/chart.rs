//! The chart: error against CPU seconds per simulated second, log–log, one panel per problem,
//! one curve per integrator (points in order of the step). PNG and SVG from the same code;
//! text drawn with the committed Cantarell font through plotters' `ab_glyph` feature.

use std::path::Path;
use std::sync::Once;

use anyhow::{anyhow, Result};
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::FontStyle;
use virtual_physics::measure::accuracy::Problem;
use virtual_physics::pipeline::IntegratorKind;

use super::Report;

static FONT: &[u8] = include_bytes!("../../assets/fonts/Cantarell-Regular.ttf");
static REGISTER: Once = Once::new();

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

/// Registers the committed font as plotters' "sans-serif" (once per process).
pub(crate) fn register_font() -> Result<()> {
    let mut ok = true;
    REGISTER.call_once(|| {
        ok = plotters::style::register_font("sans-serif", FontStyle::Normal, FONT).is_ok();
    });
    if !ok {
        return Err(anyhow!("the committed chart font does not parse"));
    }
    Ok(())
}

/// Draws the chart to `png` and `svg` (each through a temporary file and a rename).
pub fn draw(r: &Report, png: &Path, svg: &Path) -> Result<()> {
    register_font()?;
    let tmp_png = png.with_extension("tmp.png");
    {
        let root = BitMapBackend::new(&tmp_png, SIZE).into_drawing_area();
        panels(r, &root)?;
        root.present().map_err(|e| anyhow!("{e}"))?;
    }
    std::fs::rename(&tmp_png, png)?;
    let tmp_svg = svg.with_extension("tmp.svg");
    {
        let root = SVGBackend::new(&tmp_svg, SIZE).into_drawing_area();
        panels(r, &root)?;
        root.present().map_err(|e| anyhow!("{e}"))?;
    }
    std::fs::rename(&tmp_svg, svg)?;
    Ok(())
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
    let mut chart = ChartBuilder::on(area)
        .caption(p.name(), ("sans-serif", 20))
        .margin(8)
        .x_label_area_size(40)
        .y_label_area_size(70)
        .build_cartesian_2d(xr.log_scale(), yr.log_scale())
        .map_err(|e| anyhow!("{e}"))?;
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
        chart
            .draw_series(LineSeries::new(series.clone(), c.stroke_width(2)))
            .map_err(|e| anyhow!("{e}"))?
            .label(k.name())
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 18, y)], c.stroke_width(2)));
        chart
            .draw_series(series.into_iter().map(|xy| Circle::new(xy, 3, c.filled())))
            .map_err(|e| anyhow!("{e}"))?;
    }
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::LowerLeft)
        .background_style(WHITE.mix(0.8))
        .border_style(BLACK)
        .label_font(("sans-serif", 12))
        .draw()
        .map_err(|e| anyhow!("{e}"))?;
    Ok(())
}

//! What every chart of `vphys` shares: the committed font, writing one figure as SVG and
//! PNG (each through a temporary file and a rename), and a labelled curve of points.

use std::path::Path;
use std::sync::Once;

use anyhow::{anyhow, Result};
use plotters::coord::{combinators::LogCoord, Shift};
use plotters::prelude::*;
use plotters::style::FontStyle;

static FONT: &[u8] = include_bytes!("../assets/fonts/Cantarell-Regular.ttf");
static REGISTER: Once = Once::new();

/// A chart that draws itself on any plotters backend.
pub trait Figure {
    /// Draws the whole figure on `root`.
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<()>
    where
        DB::ErrorType: 'static;
}

/// Registers the committed font as plotters' "sans-serif" (once per process).
fn register_font() -> Result<()> {
    let mut ok = true;
    REGISTER.call_once(|| {
        ok = plotters::style::register_font("sans-serif", FontStyle::Normal, FONT).is_ok();
    });
    if !ok {
        return Err(anyhow!("the committed chart font does not parse"));
    }
    Ok(())
}

/// Writes `figure` at `size` (px) to `svg` and `png`.
pub fn save(figure: &impl Figure, size: (u32, u32), svg: &Path, png: &Path) -> Result<()> {
    register_font()?;
    let tmp = svg.with_extension("tmp.svg");
    {
        let root = SVGBackend::new(&tmp, size).into_drawing_area();
        figure.draw(&root)?;
        root.present().map_err(|e| anyhow!("{e}"))?;
    }
    std::fs::rename(&tmp, svg)?;
    let tmp = png.with_extension("tmp.png");
    {
        let root = BitMapBackend::new(&tmp, size).into_drawing_area();
        figure.draw(&root)?;
        root.present().map_err(|e| anyhow!("{e}"))?;
    }
    std::fs::rename(&tmp, png)?;
    Ok(())
}

/// A log–log chart's context.
pub type LogLog<'a, DB> = ChartContext<'a, DB, Cartesian2d<LogCoord<f64>, LogCoord<f64>>>;

/// A log axis over `values`, widened by `pad` each way (`lo / pad .. hi · pad`), or
/// `fallback` when the values span nothing.
pub fn log_span(
    values: impl Iterator<Item = f64> + Clone,
    pad: f64,
    fallback: std::ops::Range<f64>,
) -> std::ops::Range<f64> {
    let lo = values.clone().fold(f64::INFINITY, f64::min);
    let hi = values.fold(0.0, f64::max);
    if lo.is_finite() && hi > lo {
        (lo / pad)..(hi * pad)
    } else {
        fallback
    }
}

/// A log–log chart on `area` over the ranges `x` and `y`, with its caption.
pub fn log_log<'a, DB: DrawingBackend + 'a>(
    area: &'a DrawingArea<DB, Shift>,
    caption: &str,
    x: std::ops::Range<f64>,
    y: std::ops::Range<f64>,
) -> Result<LogLog<'a, DB>>
where
    DB::ErrorType: 'static,
{
    ChartBuilder::on(area)
        .caption(caption, ("sans-serif", 20))
        .margin(10)
        .x_label_area_size(40)
        .y_label_area_size(70)
        .build_cartesian_2d(x.log_scale(), y.log_scale())
        .map_err(|e| anyhow!("{e}"))
}

/// Draws `points` as a line with dots of `radius` px in `colour`, labelled `label`.
pub fn curve<'a, DB: DrawingBackend + 'a>(
    chart: &mut LogLog<'a, DB>,
    points: Vec<(f64, f64)>,
    colour: RGBColor,
    radius: u32,
    label: String,
) -> Result<()>
where
    DB::ErrorType: 'static,
{
    chart
        .draw_series(LineSeries::new(points.clone(), colour.stroke_width(2)))
        .map_err(|e| anyhow!("{e}"))?
        .label(label)
        .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 18, y)], colour.stroke_width(2)));
    chart
        .draw_series(
            points
                .into_iter()
                .map(|xy| Circle::new(xy, radius, colour.filled())),
        )
        .map_err(|e| anyhow!("{e}"))?;
    Ok(())
}

/// Draws the legend of `chart` at `position`, in type of `size` px.
pub fn legend<'a, DB: DrawingBackend + 'a>(
    chart: &mut LogLog<'a, DB>,
    position: SeriesLabelPosition,
    size: u32,
) -> Result<()>
where
    DB::ErrorType: 'static,
{
    chart
        .configure_series_labels()
        .position(position)
        .background_style(WHITE.mix(0.8))
        .border_style(BLACK)
        .label_font(("sans-serif", size))
        .draw()
        .map_err(|e| anyhow!("{e}"))?;
    Ok(())
}

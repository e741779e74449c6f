//! The sweep's plot: frame time against relative RMSE, both log axes, one series per
//! method (and, for `lights`, per sampler) in its own colour and marker (circles: lights,
//! squares: transfer, triangles: lightcuts; filled f32, open f64), the Pareto front as a black staircase (the
//! boundary of the region its points dominate), the 1% relative RMSE line
//! ([`super::ERROR_BOUND`]) dashed, the fastest row within it ([`super::fastest_within`])
//! ringed in green and the default configuration ringed in black, both labelled. Drawn with `plotters` into a pixel buffer and written as PNG through
//! [`crate::image_io::write_png_bytes`] (temporary file, then rename). Text uses the
//! embedded `assets/fonts/DejaVuSans-ASCII.ttf` (DejaVu Sans subset to ASCII; licence beside
//! it), so no system font is needed.

use super::{describe, sampler_name, MethodAxis, MethodKind, Row};
use crate::env::schema::SamplerKind;
use crate::error::{Error, Result};
use crate::scene::Precision;
use plotters::prelude::*;
use std::path::Path;

/// The embedded font (printable ASCII only).
static FONT: &[u8] = include_bytes!("../../assets/fonts/DejaVuSans-ASCII.ttf");

/// Plot size in pixels.
pub const SIZE: (u32, u32) = (1200, 800);

fn register_font() {
    static ONCE: std::sync::Once = std::sync::Once::new();
    ONCE.call_once(|| {
        plotters::style::register_font("sans-serif", FontStyle::Normal, FONT)
            .map_err(|_| ())
            .expect("the embedded font parses");
    });
}

fn sampler_color(s: SamplerKind) -> RGBColor {
    match s {
        SamplerKind::Uniform => RGBColor(220, 170, 0),
        SamplerKind::Importance => RGBColor(204, 121, 167),
        SamplerKind::Stratified => RGBColor(0, 158, 115),
        SamplerKind::MedianCut => RGBColor(213, 94, 0),
        SamplerKind::Lloyd => RGBColor(0, 90, 200),
        SamplerKind::Full => RGBColor(120, 120, 120),
    }
}

/// The plot's series: a method, and for `lights` its sampler.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Series {
    Lights(SamplerKind),
    Transfer,
    Lightcuts,
    Reflection,
}

impl Series {
    fn of(r: &Row) -> Series {
        match r.config.method {
            MethodAxis::Lights { sampler, .. } => Series::Lights(sampler),
            MethodAxis::Transfer { .. } => Series::Transfer,
            MethodAxis::Lightcuts { .. } => Series::Lightcuts,
            MethodAxis::Reflection { .. } => Series::Reflection,
        }
    }

    fn color(self) -> RGBColor {
        match self {
            Series::Lights(s) => sampler_color(s),
            Series::Transfer => RGBColor(200, 0, 40),
            Series::Lightcuts => RGBColor(110, 40, 170),
            Series::Reflection => RGBColor(0, 150, 160),
        }
    }

    fn label(self) -> String {
        match self {
            Series::Lights(s) => format!("lights, {}", sampler_name(s)),
            Series::Transfer => format!("{} (squares)", MethodKind::Transfer.name()),
            Series::Lightcuts => format!("{} (triangles)", MethodKind::Lightcuts.name()),
            Series::Reflection => format!("{} (crosses)", MethodKind::Reflection.name()),
        }
    }
}

/// Log-axis bounds with a margin: [lo / 1.3, hi * 1.3] of the positive values.
fn bounds(vals: impl Iterator<Item = f64>) -> (f64, f64) {
    let (lo, hi) = vals
        .filter(|v| v.is_finite() && *v > 0.0)
        .fold((f64::INFINITY, 0.0f64), |(lo, hi), v| {
            (lo.min(v), hi.max(v))
        });
    if lo > hi {
        (0.1, 10.0)
    } else {
        (lo / 1.3, hi * 1.3)
    }
}

/// Log-axis ticks at 1, 2 and 5 times the powers of ten inside `[lo, hi]` (plotters' own
/// log ticks leave a one-decade axis nearly unlabelled).
fn key_points(lo: f64, hi: f64) -> Vec<f64> {
    let mut out = Vec::new();
    let mut decade = 10f64.powi(lo.log10().floor() as i32);
    while decade <= hi {
        for m in [1.0, 2.0, 5.0] {
            let v = m * decade;
            if v >= lo && v <= hi {
                out.push(v);
            }
        }
        decade *= 10.0;
    }
    out
}

/// A log-axis tick: at most 3 significant digits, no trailing zeros.
fn tick(v: f64) -> String {
    if v == 0.0 || !v.is_finite() {
        return format!("{v}");
    }
    let digits = (2 - v.abs().log10().floor() as i32).max(0) as usize;
    let s = format!("{v:.digits$}");
    if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        s
    }
}

fn plot_err<E: std::fmt::Display>(path: &Path) -> impl Fn(E) -> Error + '_ {
    move |e| Error::format(path, format!("cannot draw the plot: {e}"))
}

/// Draws the rows (with their `pareto` and `default` flags set) to a PNG at `path`.
/// `title` heads the plot. Rows with a non-positive time or error are left out (log axes).
pub fn write_plot(path: &Path, rows: &[Row], title: &str) -> Result<()> {
    register_font();
    let (w, h) = SIZE;
    let mut buf = vec![255u8; (w * h * 3) as usize];
    let ok = |r: &&Row| r.frame_ms > 0.0 && r.rel_rmse > 0.0 && r.rel_rmse.is_finite();
    {
        let root = BitMapBackend::with_buffer(&mut buf, (w, h)).into_drawing_area();
        root.fill(&WHITE).map_err(plot_err(path))?;
        let (x0, x1) = bounds(rows.iter().filter(ok).map(|r| r.frame_ms));
        let (y0, y1) = bounds(rows.iter().filter(ok).map(|r| r.rel_rmse));
        // The 1% line is always inside the plot.
        let (y0, y1) = (
            y0.min(super::ERROR_BOUND / 1.3),
            y1.max(super::ERROR_BOUND * 1.3),
        );
        let mut chart = ChartBuilder::on(&root)
            .caption(title, ("sans-serif", 26))
            .margin(20)
            // Room below the axis for the two marked rows' labels.
            .margin_bottom(70)
            .x_label_area_size(55)
            .y_label_area_size(80)
            .build_cartesian_2d(
                (x0..x1).log_scale().with_key_points(key_points(x0, x1)),
                (y0..y1).log_scale().with_key_points(key_points(y0, y1)),
            )
            .map_err(plot_err(path))?;
        chart
            .configure_mesh()
            .x_desc("frame time (ms, median of the row's renders)")
            .y_desc("relative RMSE against the reference (covered pixels)")
            .axis_desc_style(("sans-serif", 20))
            .label_style(("sans-serif", 16))
            .x_label_formatter(&|v| tick(*v))
            .y_label_formatter(&|v| tick(*v))
            .light_line_style(RGBColor(235, 235, 235))
            .bold_line_style(RGBColor(200, 200, 200))
            .draw()
            .map_err(plot_err(path))?;

        // One series per method (and sampler) present, in the grid's order.
        let mut series: Vec<Series> = Vec::new();
        for r in rows {
            if !series.contains(&Series::of(r)) {
                series.push(Series::of(r));
            }
        }
        for se in series {
            let c = se.color();
            let pts = rows.iter().filter(ok).filter(|r| Series::of(r) == se);
            let f32s = pts.clone().filter(|r| r.config.precision == Precision::F32);
            let f64s = pts.filter(|r| r.config.precision == Precision::F64);
            let at = |r: &Row| (r.frame_ms, r.rel_rmse);
            // Circles for lights, squares for transfer, triangles for lightcuts, crosses for
            // reflection (filled or thick: f32, open or thin: f64).
            let annotation = match se {
                Series::Reflection => {
                    let a = chart
                        .draw_series(f32s.map(|r| Cross::new(at(r), 4, c.stroke_width(2))))
                        .map_err(plot_err(path))?;
                    a.label(se.label())
                        .legend(move |(x, y)| Cross::new((x + 10, y), 5, c.stroke_width(2)));
                    chart
                        .draw_series(f64s.map(|r| Cross::new(at(r), 5, c.stroke_width(1))))
                        .map_err(plot_err(path))?;
                    continue;
                }
                Series::Lightcuts => {
                    let a = chart
                        .draw_series(
                            f32s.map(|r| TriangleMarker::new(at(r), 5, c.mix(0.75).filled())),
                        )
                        .map_err(plot_err(path))?;
                    a.label(se.label())
                        .legend(move |(x, y)| TriangleMarker::new((x + 10, y), 6, c.filled()));
                    chart
                        .draw_series(f64s.map(|r| TriangleMarker::new(at(r), 6, c.stroke_width(1))))
                        .map_err(plot_err(path))?;
                    continue;
                }
                Series::Lights(_) => {
                    let a = chart
                        .draw_series(f32s.map(|r| Circle::new(at(r), 3, c.mix(0.75).filled())))
                        .map_err(plot_err(path))?;
                    a.label(se.label())
                        .legend(move |(x, y)| Circle::new((x + 10, y), 5, c.filled()));
                    chart
                        .draw_series(f64s.map(|r| Circle::new(at(r), 4, c.stroke_width(1))))
                        .map_err(plot_err(path))?;
                    continue;
                }
                Series::Transfer => chart
                    .draw_series(f32s.map(|r| {
                        EmptyElement::at(at(r))
                            + Rectangle::new([(-3, -3), (3, 3)], c.mix(0.75).filled())
                    }))
                    .map_err(plot_err(path))?,
            };
            annotation.label(se.label()).legend(move |(x, y)| {
                Rectangle::new([(x + 5, y - 5), (x + 15, y + 5)], c.filled())
            });
            chart
                .draw_series(f64s.map(|r| {
                    EmptyElement::at(at(r)) + Rectangle::new([(-4, -4), (4, 4)], c.stroke_width(1))
                }))
                .map_err(plot_err(path))?;
        }

        // The error bound, dashed across the plot.
        let bound = super::ERROR_BOUND;
        chart
            .draw_series(DashedLineSeries::new(
                [(x0, bound), (x1, bound)],
                8,
                5,
                RGBColor(0, 140, 70).stroke_width(2),
            ))
            .map_err(plot_err(path))?
            .label(format!("{}% relative RMSE", bound * 100.0))
            .legend(|(x, y)| {
                PathElement::new(
                    vec![(x, y), (x + 20, y)],
                    RGBColor(0, 140, 70).stroke_width(2),
                )
            });

        // The Pareto front as a staircase through its points, fastest first.
        let mut front: Vec<(f64, f64)> = rows
            .iter()
            .filter(ok)
            .filter(|r| r.pareto)
            .map(|r| (r.frame_ms, r.rel_rmse))
            .collect();
        front.sort_by(|a, b| a.0.total_cmp(&b.0).then(b.1.total_cmp(&a.1)));
        let mut stairs = Vec::new();
        for (k, &(t, e)) in front.iter().enumerate() {
            if k > 0 {
                stairs.push((t, front[k - 1].1));
            }
            stairs.push((t, e));
        }
        chart
            .draw_series(LineSeries::new(stairs, BLACK.stroke_width(2)))
            .map_err(plot_err(path))?
            .label("Pareto front (time, rel. RMSE)")
            .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], BLACK.stroke_width(2)));

        // The default configuration (black) and the fastest row within the bound (green),
        // ringed; their labels below the plot, one line each, so they never cover each
        // other, the front or a point.
        let fastest = super::fastest_within(rows, bound).map(|r| r.config.index);
        let green = RGBColor(0, 140, 70);
        let mut labels: Vec<(String, RGBColor)> = Vec::new();
        for r in rows.iter().filter(ok) {
            let is_fastest = fastest == Some(r.config.index);
            if !(r.default || is_fastest) {
                continue;
            }
            let on = if r.pareto {
                "on the front"
            } else {
                "dominated"
            };
            let text = format!(
                "{}: {:.2} ms, rel. RMSE {:.3}% ({on})",
                describe(&r.config),
                r.frame_ms,
                r.rel_rmse * 100.0
            );
            let (label, color) = match (r.default, is_fastest) {
                (true, true) => (format!("default, fastest within 1%: {text}"), green),
                (true, false) => (format!("default (black ring): {text}"), BLACK),
                _ => (format!("fastest within 1% (green ring): {text}"), green),
            };
            chart
                .draw_series(std::iter::once(Circle::new(
                    (r.frame_ms, r.rel_rmse),
                    9,
                    color.stroke_width(3),
                )))
                .map_err(plot_err(path))?;
            labels.push((label, color));
        }
        if fastest.is_none() {
            labels.push((
                format!("no configuration within {}% relative RMSE", bound * 100.0),
                green,
            ));
        }
        // Below the x axis, above the footer line.
        for (k, (label, color)) in labels.iter().rev().enumerate() {
            let y = h as i32 - 48 - 22 * k as i32;
            root.draw(&Text::new(
                label.clone(),
                (90, y),
                ("sans-serif", 17).into_font().color(color),
            ))
            .map_err(plot_err(path))?;
        }

        chart
            .configure_series_labels()
            .position(SeriesLabelPosition::UpperRight)
            .label_font(("sans-serif", 17))
            .background_style(WHITE.mix(0.9))
            .border_style(RGBColor(150, 150, 150))
            .draw()
            .map_err(plot_err(path))?;
        root.draw(&Text::new(
            "each mark one configuration (method and its parameters x order x lookup); filled: f32, open: f64",
            (90, (h - 22) as i32),
            ("sans-serif", 14).into_font().color(&RGBColor(90, 90, 90)),
        ))
        .map_err(plot_err(path))?;
        root.present().map_err(plot_err(path))?;
    }
    crate::image_io::write_png_bytes(path, w, h, buf)
}

#[cfg(test)]
mod tests {
    #[test]
    fn ticks() {
        assert_eq!(super::tick(100.0), "100");
        assert_eq!(super::tick(0.01), "0.01");
        assert_eq!(super::tick(0.0123456), "0.0123");
        assert_eq!(super::tick(2000.0), "2000");
        assert_eq!(super::tick(1.5), "1.5");
    }
}

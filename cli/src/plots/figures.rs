//! SVG figures of the identification experiment (plotters, SVG backend).

use plotters::prelude::*;

/// One named series of (x, y) points.
pub struct Series<'a> {
    /// Legend label.
    pub label: &'a str,
    /// Points.
    pub points: Vec<(f64, f64)>,
    /// Colour index.
    pub color: usize,
}

fn color(i: usize) -> RGBColor {
    [
        RGBColor(31, 119, 180),
        RGBColor(255, 127, 14),
        RGBColor(44, 160, 44),
        RGBColor(214, 39, 40),
        RGBColor(148, 103, 189),
        RGBColor(140, 86, 75),
    ][i % 6]
}

/// A tick label as people write it: 100, 1000, 0.5, 0.25 (no trailing
/// ".0", no float noise).
fn tick(v: f64) -> String {
    let r = (v * 1e6).round() / 1e6;
    if r.abs() >= 1e6 || (r != 0.0 && r.abs() < 1e-4) {
        format!("{v:.0e}")
    } else {
        format!("{r}")
    }
}

fn bounds(panels: &[Vec<Series>]) -> Vec<(f64, f64, f64, f64)> {
    panels
        .iter()
        .map(|s| {
            let xs = s.iter().flat_map(|s| s.points.iter().map(|p| p.0));
            let ys = s.iter().flat_map(|s| s.points.iter().map(|p| p.1));
            let (x0, x1) = xs.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), x| {
                (a.min(x), b.max(x))
            });
            let (y0, y1) = ys.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), y| {
                (a.min(y), b.max(y))
            });
            let pad = 0.05 * (y1 - y0).max(1e-9);
            (x0, x1.max(x0 + 1e-9), y0 - pad, y1 + pad)
        })
        .collect()
}

/// Stacked panels sharing the x axis, as SVG text; `log_x` for
/// sample-count axes.
pub fn line_panels(
    title: &str,
    x_label: &str,
    panel_titles: &[String],
    y_label: &str,
    panels: &[Vec<Series>],
    log_x: bool,
) -> Result<String, String> {
    let mut svg = String::new();
    {
        let h = 260 * panels.len() as u32 + 40;
        let root = SVGBackend::with_string(&mut svg, (1000, h)).into_drawing_area();
        root.fill(&WHITE).map_err(|e| e.to_string())?;
        let root = root
            .titled(title, ("sans-serif", 22))
            .map_err(|e| e.to_string())?;
        let areas = root.split_evenly((panels.len(), 1));
        for ((area, series), (b, pt)) in areas
            .iter()
            .zip(panels)
            .zip(bounds(panels).into_iter().zip(panel_titles))
        {
            let mut cb = ChartBuilder::on(area);
            cb.caption(pt, ("sans-serif", 16))
                .margin(8)
                .margin_right(30)
                .x_label_area_size(35)
                .y_label_area_size(60);
            macro_rules! draw {
                ($chart:expr) => {{
                    let mut chart = $chart.map_err(|e| e.to_string())?;
                    chart
                        .configure_mesh()
                        .x_desc(x_label)
                        .y_desc(y_label)
                        .x_label_formatter(&|v| tick(*v))
                        .y_label_formatter(&|v| tick(*v))
                        .draw()
                        .map_err(|e| e.to_string())?;
                    for s in series {
                        let c = color(s.color);
                        chart
                            .draw_series(LineSeries::new(
                                s.points.iter().copied(),
                                c.stroke_width(1),
                            ))
                            .map_err(|e| e.to_string())?
                            .label(s.label)
                            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], c));
                    }
                    chart
                        .configure_series_labels()
                        .position(SeriesLabelPosition::UpperRight)
                        .background_style(WHITE.mix(0.8))
                        .border_style(BLACK)
                        .draw()
                        .map_err(|e| e.to_string())?;
                }};
            }
            if log_x {
                // sample-count studies span decades on both axes
                let ys = series
                    .iter()
                    .flat_map(|s| s.points.iter().map(|p| p.1))
                    .filter(|y| *y > 0.0);
                let (lo, hi) = ys.fold((f64::INFINITY, 0.0f64), |(a, b), y| (a.min(y), b.max(y)));
                // headroom above the data for the legend in the upper right:
                // a third of the data's decades
                let top = hi * 10f64.powf(0.35 * (hi / lo).log10().max(0.1));
                draw!(cb.build_cartesian_2d((b.0..b.1).log_scale(), (0.8 * lo..top).log_scale()));
            } else {
                draw!(cb.build_cartesian_2d(b.0..b.1, b.2..b.3));
            }
        }
        root.present().map_err(|e| e.to_string())?;
    }
    Ok(svg)
}

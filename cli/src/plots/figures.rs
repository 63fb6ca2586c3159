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

/// Tick values for a log axis over `lo..hi` (both > 0): 1, 2, 5 × 10ᵏ
/// inside it; powers of ten alone when those are more than 12; 1 … 9 × 10ᵏ
/// when they are fewer than 3 (plotters' own log key points are the powers
/// of ten, so a range within a decade had one tick label or none).
fn log_ticks(lo: f64, hi: f64) -> Vec<f64> {
    let pick = |mantissas: &[f64]| -> Vec<f64> {
        let (k0, k1) = (lo.log10().floor() as i32, hi.log10().ceil() as i32);
        (k0..=k1)
            .flat_map(|k| mantissas.iter().map(move |m| m * 10f64.powi(k)))
            .filter(|v| (lo..=hi).contains(v))
            .collect()
    };
    let t = pick(&[1.0, 2.0, 5.0]);
    if t.len() > 12 {
        pick(&[1.0])
    } else if t.len() < 3 {
        pick(&[1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0, 9.0])
    } else {
        t
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

/// The y range of log-scaled panels: from under the smallest positive
/// value to a headroom above the largest for the legend in the upper
/// right (a third of the data's decades).
fn log_y_range(series: &[Series]) -> (f64, f64) {
    let ys = (series.iter())
        .flat_map(|s| s.points.iter().map(|p| p.1))
        .filter(|y| *y > 0.0);
    let (lo, hi) = ys.fold((f64::INFINITY, 0.0f64), |(a, b), y| (a.min(y), b.max(y)));
    let top = hi * 10f64.powf(0.35 * (hi / lo).log10().max(0.1));
    (0.8 * lo, top)
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
                let (x, y) = ((b.0, b.1), log_y_range(series));
                draw!(cb.build_cartesian_2d(
                    (x.0..x.1).log_scale().with_key_points(log_ticks(x.0, x.1)),
                    (y.0..y.1).log_scale().with_key_points(log_ticks(y.0, y.1))
                ));
            } else {
                draw!(cb.build_cartesian_2d(b.0..b.1, b.2..b.3));
            }
        }
        root.present().map_err(|e| e.to_string())?;
    }
    Ok(svg)
}

#[cfg(test)]
mod tests {
    use super::log_ticks;

    /// A log axis has at least three ticks whatever its span, and not a
    /// crowd over many decades.
    #[test]
    fn log_axes_have_readable_ticks() {
        for (lo, hi) in [
            (1e5, 3e5),
            (8e4, 1.2e5),
            (0.8, 120.0),
            (1e3, 1e6),
            (1e-3, 1e9),
        ] {
            let t = log_ticks(lo, hi);
            assert!(t.len() >= 3 && t.len() <= 13, "{lo}..{hi}: {t:?}");
            assert!(t.iter().all(|v| (lo..=hi).contains(v)), "{lo}..{hi}: {t:?}");
            assert!(t.windows(2).all(|w| w[0] < w[1]), "{t:?}");
        }
        assert_eq!(log_ticks(1e5, 3e5), vec![1e5, 2e5, 3e5]);
    }

    /// A log panel whose values lie within a decade shows several value
    /// labels (fig7's middle panel once showed only "100000").
    #[test]
    fn a_log_panel_within_a_decade_is_labelled() {
        let series = vec![super::Series {
            label: "entropic",
            points: vec![(100.0, 1.9e5), (300.0, 1.4e5), (1000.0, 1.1e5)],
            color: 0,
        }];
        let svg = super::line_panels("t", "samples", &["p".into()], "y", &[series], true).unwrap();
        for label in ["90000", "100000", "200000", "100", "1000"] {
            assert!(
                svg.contains(&format!("\n{label}\n")),
                "no tick label {label}"
            );
        }
    }
}

//! Bar charts: one bar per value, labelled under its centre.

use plotters::coord::Shift;
use plotters::prelude::*;

/// What a bar chart shows.
pub struct Bars<'a> {
    /// Above the chart.
    pub caption: &'a str,
    /// One label per bar.
    pub labels: &'a [String],
    /// One value per bar (≥ 0 for a visible bar).
    pub values: &'a [f64],
    /// The value axis.
    pub y: std::ops::Range<f64>,
    /// The value axis' name ("" for none).
    pub y_desc: &'a str,
    /// The bars' colour.
    pub color: RGBColor,
}

/// Draws `b` on `area`: `n` bars in `n` slots (an empty chart for no
/// values). The slots are a continuous axis `0..n`, so one bar spans its
/// whole slot whatever `n` (a segmented axis over `0..n − 1` had zero width
/// at `n = 1` and drew no bar).
pub fn draw_bars<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    b: &Bars,
) -> Result<(), DrawingAreaErrorKind<DB::ErrorType>> {
    let n = b.values.len().max(1);
    let mut c = ChartBuilder::on(area)
        .margin(10)
        .x_label_area_size(35)
        .y_label_area_size(60)
        .caption(b.caption, ("sans-serif", 14))
        .build_cartesian_2d(0.0..n as f64, b.y.clone())?;
    // the axis' key points fall on every half slot: a label at each
    // slot's centre (k + 0.5), none elsewhere
    let labels = b.labels;
    c.configure_mesh()
        .disable_x_mesh()
        .x_labels(2 * n + 1)
        .x_label_formatter(&|x| {
            let k = (x - 0.5).round();
            let centre = (x - 0.5 - k).abs() < 1e-6 && k >= 0.0;
            match labels.get(k as usize) {
                Some(l) if centre => l.clone(),
                _ => String::new(),
            }
        })
        .y_desc(b.y_desc)
        .draw()?;
    let width = 0.8;
    c.draw_series(b.values.iter().enumerate().map(|(k, v)| {
        let x0 = k as f64 + (1.0 - width) / 2.0;
        Rectangle::new([(x0, 0.0), (x0 + width, *v)], b.color.filled())
    }))?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The SVG of a chart of `values`, and how many filled bars of its
    /// colour it holds.
    fn chart(values: &[f64]) -> (String, usize) {
        let labels: Vec<String> = (0..values.len()).map(|k| format!("effect{k}")).collect();
        let mut svg = String::new();
        {
            let root = SVGBackend::with_string(&mut svg, (600, 300)).into_drawing_area();
            root.fill(&WHITE).unwrap();
            let b = Bars {
                caption: "test",
                labels: &labels,
                values,
                y: 0.0..10.0,
                y_desc: "[N²·m²]",
                color: RGBColor(31, 119, 180),
            };
            draw_bars(&root, &b).unwrap();
            root.present().unwrap();
        }
        let bars = svg.matches(r##"fill="#1F77B4""##).count();
        (svg, bars)
    }

    /// Every value is a bar with its label, with one value and with
    /// several; no values draw an empty chart.
    #[test]
    fn each_value_is_a_bar_with_its_label() {
        for values in [vec![], vec![7.0], vec![1.0, 5.0, 2.5], vec![0.5; 12]] {
            let (svg, bars) = chart(&values);
            assert_eq!(bars, values.len(), "{values:?}\n{svg}");
            for k in 0..values.len() {
                // (the SVG puts a text's content on a line of its own)
                assert!(
                    svg.contains(&format!("\neffect{k}\n")),
                    "{values:?}: label {k}"
                );
            }
        }
        // a bar spans most of its slot (not a zero-width line): its rect
        // is wider than a tenth of the plot
        let (svg, _) = chart(&[7.0]);
        let rect = svg
            .split("<rect")
            .find(|r| r.contains(r##"fill="#1F77B4""##))
            .unwrap();
        let width: f64 = rect
            .split("width=\"")
            .nth(1)
            .and_then(|w| w.split('"').next())
            .and_then(|w| w.parse().ok())
            .unwrap();
        assert!(width > 50.0, "{rect}");
    }
}

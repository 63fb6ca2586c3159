//! SVG figures of a diagnosis: per joint, the held-out residual against
//! time, velocity and position (before and after the accepted effects) and
//! its frequency bands; and a bar chart of what each accepted effect removed.

use momentlmi::diagnose::Diagnosis;
use plotters::prelude::*;

/// The axis range of the values: from the 0.1 % to the 99.9 % quantile,
/// padded, so that a few extreme samples (a filter's edge, a spike) do not
/// squeeze the rest into a line; the few beyond are clipped.
fn range(v: impl Iterator<Item = f64>) -> (f64, f64) {
    let mut x: Vec<f64> = v.filter(|x| x.is_finite()).collect();
    if x.is_empty() {
        return (-1.0, 1.0);
    }
    x.sort_by(f64::total_cmp);
    let at = |q: f64| x[((x.len() - 1) as f64 * q).round() as usize];
    let (lo, hi) = (at(0.001), at(0.999));
    let pad = 0.08 * (hi - lo).max(1e-9);
    (lo - pad, hi + pad)
}

type Svg = Result<(), DrawingAreaErrorKind<std::io::Error>>;

/// `residual_<joint>.svg` and `effects.svg` as (file name, SVG text).
pub fn render_plots(d: &Diagnosis) -> Result<Vec<(String, String)>, String> {
    let mut files = vec![];
    for (i, joint) in d.joints.iter().enumerate() {
        let mut svg = String::new();
        residual_plot(&mut svg, d, i).map_err(|e| e.to_string())?;
        files.push((format!("residual_{joint}.svg"), svg));
    }
    let mut svg = String::new();
    effects_plot(&mut svg, d).map_err(|e| e.to_string())?;
    files.push(("effects.svg".to_string(), svg));
    Ok(files)
}

/// Joint `i`'s held-out residual against time, velocity and position, and
/// its frequency bands.
fn residual_plot(svg: &mut String, d: &Diagnosis, i: usize) -> Svg {
    let e = |x| x;
    let h = &d.heldout;
    let stride = (h.t.len() / 3000).max(1);
    let before = RGBColor(214, 39, 40).mix(0.5);
    let after = RGBColor(31, 119, 180).mix(0.5);
    let joint = &d.joints[i];
    {
        let root = SVGBackend::with_string(svg, (1100, 800)).into_drawing_area();
        root.fill(&WHITE).map_err(e)?;
        let root = root
            .titled(
                &format!(
                    "{joint}: held-out residual τ − τ̂ (red: nominal, blue: with accepted effects)"
                ),
                ("sans-serif", 18),
            )
            .map_err(e)?;
        let areas = root.split_evenly((2, 2));
        let idx: Vec<usize> = (0..h.t.len()).step_by(stride).collect();
        let ry = range(idx.iter().flat_map(|&k| [h.nominal[i][k], h.after[i][k]]));
        for (panel, (xs, label)) in areas.iter().take(3).zip([
            (&h.t, "time [s]"),
            (&h.qd[i], "velocity [rad/s]"),
            (&h.q[i], "position [rad]"),
        ]) {
            let rx = range(idx.iter().map(|&k| xs[k]));
            let mut c = ChartBuilder::on(panel)
                .margin(10)
                .x_label_area_size(35)
                .y_label_area_size(55)
                .build_cartesian_2d(rx.0..rx.1, ry.0..ry.1)
                .map_err(e)?;
            c.configure_mesh()
                .x_desc(label)
                .y_desc("residual [N·m]")
                .draw()
                .map_err(e)?;
            c.draw_series(
                idx.iter()
                    .map(|&k| Circle::new((xs[k], h.nominal[i][k]), 1, before.filled())),
            )
            .map_err(e)?;
            c.draw_series(
                idx.iter()
                    .map(|&k| Circle::new((xs[k], h.after[i][k]), 1, after.filled())),
            )
            .map_err(e)?;
        }
        let spec = &d.where_[i].spectrum;
        let labels: Vec<String> = spec.iter().map(|s| s.0.clone()).collect();
        let values: Vec<f64> = spec.iter().map(|s| s.1).collect();
        let bars = super::bars::Bars {
            caption: "share of the nominal residual's variance per band",
            labels: &labels,
            values: &values,
            y: 0.0..1.0,
            y_desc: "",
            color: RGBColor(214, 39, 40),
        };
        super::bars::draw_bars(&areas[3], &bars).map_err(e)?;
        root.present().map_err(e)?;
    }
    Ok(())
}

/// Bar chart: held-out MSE removed by each accepted effect (all joints).
fn effects_plot(svg: &mut String, d: &Diagnosis) -> Svg {
    let e = |x| x;
    let acc: Vec<_> = d.ranked_effects.iter().filter(|r| r.accepted).collect();
    let root = SVGBackend::with_string(svg, (900, 400)).into_drawing_area();
    root.fill(&WHITE).map_err(e)?;
    let vals: Vec<f64> = acc
        .iter()
        .map(|r| {
            r.heldout_rms_before.iter().map(|x| x * x).sum::<f64>()
                - r.heldout_rms_after.iter().map(|x| x * x).sum::<f64>()
        })
        .collect();
    let top = vals.iter().fold(1e-9f64, |a, v| a.max(*v)) * 1.15;
    let names: Vec<String> = acc.iter().map(|r| r.effect.clone()).collect();
    let bars = super::bars::Bars {
        caption: "held-out mean-square torque error removed by each accepted effect (sum over joints)",
        labels: &names,
        values: &vals,
        y: 0.0..top,
        y_desc: "[N²·m²]",
        color: RGBColor(31, 119, 180),
    };
    super::bars::draw_bars(&root, &bars).map_err(e)?;
    root.present()
}

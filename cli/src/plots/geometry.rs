//! `check --out DIR`: per link, its shapes' points, its bounding
//! ellipsoid(s), the covariance ellipsoid of its inertia (E_π, semi-axes
//! √(μᵢ/m), Fig. 3 of the paper), its CoM and, when the inertia is realizable
//! in its geometry, four point masses with the same moments inside it, in
//! three orthogonal views (link frame, equal scales).

use momentlmi::moments::urdf_check::LinkReport;
use momentlmi::moments::{
    Ellipsoid, InertialParams, PointMass, four_point_masses_in, point_masses_on_union,
};
use nalgebra::{Matrix2, Matrix3, Vector2, Vector3};
use plotters::prelude::*;

/// What one link's figure shows (link frame, m).
pub struct LinkFigure<'a> {
    /// The checker's report of the link.
    pub report: &'a LinkReport,
    /// Points on the link's shapes (a sample).
    pub points: &'a [Vector3<f64>],
}

const VIEWS: [(usize, usize, &str); 3] = [
    (0, 1, "top (x, y)"),
    (0, 2, "front (x, z)"),
    (1, 2, "side (y, z)"),
];
const BOUND: RGBColor = RGBColor(31, 119, 180);
const COV: RGBColor = RGBColor(255, 127, 14);
const MASS: RGBColor = RGBColor(214, 39, 40);

/// The outline of an ellipsoid `{x : (x − c)ᵀ A⁻¹ (x − c) ≤ 1}` projected
/// onto coordinates (i, j): the ellipse with the 2×2 block of A.
fn outline(c: &Vector3<f64>, a: &Matrix3<f64>, (i, j): (usize, usize)) -> Vec<(f64, f64)> {
    let b = Matrix2::new(a[(i, i)], a[(i, j)], a[(j, i)], a[(j, j)]);
    let e = nalgebra::SymmetricEigen::new(b);
    let l = e.eigenvectors * Matrix2::from_diagonal(&e.eigenvalues.map(|x| x.max(0.0).sqrt()));
    (0..=72)
        .map(|k| {
            let t = std::f64::consts::TAU * k as f64 / 72.0;
            let p = l * Vector2::new(t.cos(), t.sin());
            (c[i] + p.x, c[j] + p.y)
        })
        .collect()
}

/// The covariance ellipsoid as (centre, A), when the inertia has one.
fn covariance(pi: &InertialParams) -> Option<(Vector3<f64>, Matrix3<f64>)> {
    let e = pi.covariance_ellipsoid();
    if pi.mass() <= 0.0 || !e.semi_axes.iter().all(|s| s.is_finite()) {
        return None;
    }
    let d = Matrix3::from_diagonal(&e.semi_axes.map(|s| s * s));
    Some((e.center, e.axes * d * e.axes.transpose()))
}

/// Four point masses inside the geometry, when the inertia is realizable there.
fn point_masses(r: &LinkReport, pi: &InertialParams) -> Vec<PointMass> {
    if r.realizable_in_geometry != Some(true) {
        return vec![];
    }
    match r.bounding_ellipsoids() {
        [e] => four_point_masses_in(pi, e)
            .map(|p| p.to_vec())
            .unwrap_or_default(),
        many => point_masses_on_union(pi, many).unwrap_or_default(),
    }
}

/// Half the side and the centre of a square window holding every item.
fn window(items: &[Vector3<f64>]) -> (Vector3<f64>, f64) {
    let lo = items
        .iter()
        .fold(Vector3::repeat(f64::INFINITY), |a, p| a.inf(p));
    let hi = items
        .iter()
        .fold(Vector3::repeat(f64::NEG_INFINITY), |a, p| a.sup(p));
    if !lo.iter().all(|x| x.is_finite()) {
        return (Vector3::zeros(), 0.1);
    }
    let half = 0.55 * (hi - lo).max();
    ((lo + hi) / 2.0, if half > 0.0 { half } else { 0.1 })
}

/// Points that bound what is drawn: the shape points and each ellipsoid's
/// axis-aligned bounding box corners.
fn extent(f: &LinkFigure, ellipsoids: &[(Vector3<f64>, Matrix3<f64>)]) -> Vec<Vector3<f64>> {
    let mut v: Vec<Vector3<f64>> = f.points.to_vec();
    for (c, a) in ellipsoids {
        let h = Vector3::new(a[(0, 0)], a[(1, 1)], a[(2, 2)]).map(|x| x.max(0.0).sqrt());
        v.push(c + h);
        v.push(c - h);
    }
    v
}

/// The SVG text of one link's figure.
pub fn link_svg(f: &LinkFigure) -> Result<String, String> {
    let r = f.report;
    let pi = InertialParams(r.params);
    let bounds: Vec<(Vector3<f64>, Matrix3<f64>)> = r
        .bounding_ellipsoids()
        .iter()
        .map(|e: &Ellipsoid| (e.center, e.shape()))
        .collect();
    let cov = covariance(&pi);
    let masses = point_masses(r, &pi);
    let all: Vec<_> = bounds.iter().cloned().chain(cov).collect();
    let (mid, half) = window(&extent(f, &all));
    let verdict = match r.realizable_in_geometry {
        Some(true) => "realizable in its geometry",
        Some(false) => "NOT realizable in its geometry",
        None => "no geometry verdict",
    };
    let title = format!("{}: {}, {}", r.name, r.describe(), verdict);
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, (1260, 470)).into_drawing_area();
        root.fill(&WHITE).map_err(|e| e.to_string())?;
        let root = root
            .titled(&title, ("sans-serif", 18))
            .map_err(|e| e.to_string())?;
        for (area, view) in root.split_evenly((1, 3)).iter().zip(VIEWS) {
            draw_view(area, view, f, (&bounds, cov.as_ref(), &masses), (mid, half))
                .map_err(|e| e.to_string())?;
        }
        root.present().map_err(|e| e.to_string())?;
    }
    Ok(svg)
}

type Area<'a> = DrawingArea<SVGBackend<'a>, plotters::coord::Shift>;
type Drawn<'a> = (
    &'a [(Vector3<f64>, Matrix3<f64>)],
    Option<&'a (Vector3<f64>, Matrix3<f64>)>,
    &'a [PointMass],
);

/// One view: coordinates (i, j) of the link frame.
fn draw_view(
    area: &Area,
    (i, j, name): (usize, usize, &str),
    f: &LinkFigure,
    (bounds, cov, masses): Drawn,
    (mid, half): (Vector3<f64>, f64),
) -> Result<(), DrawingAreaErrorKind<std::io::Error>> {
    let axis = ["x [m]", "y [m]", "z [m]"];
    let mut chart = ChartBuilder::on(area)
        .caption(name, ("sans-serif", 15))
        .margin(10)
        .x_label_area_size(35)
        .y_label_area_size(55)
        .build_cartesian_2d(mid[i] - half..mid[i] + half, mid[j] - half..mid[j] + half)?;
    chart
        .configure_mesh()
        .x_desc(axis[i])
        .y_desc(axis[j])
        .draw()?;
    let grey = RGBColor(150, 150, 150).mix(0.5);
    chart.draw_series(
        f.points
            .iter()
            .map(|p| Circle::new((p[i], p[j]), 1, grey.filled())),
    )?;
    for (k, (c, a)) in bounds.iter().enumerate() {
        let s = chart.draw_series(LineSeries::new(
            outline(c, a, (i, j)),
            BOUND.stroke_width(2),
        ))?;
        if k == 0 {
            s.label("bounding ellipsoid")
                .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], BOUND));
        }
    }
    if let Some((c, a)) = cov {
        chart
            .draw_series(LineSeries::new(outline(c, a, (i, j)), COV.stroke_width(2)))?
            .label("covariance ellipsoid")
            .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], COV));
        chart.draw_series(std::iter::once(Cross::new(
            (c[i], c[j]),
            5,
            BLACK.stroke_width(2),
        )))?;
    }
    if !masses.is_empty() {
        chart
            .draw_series(
                masses
                    .iter()
                    .map(|m| Circle::new((m.position[i], m.position[j]), 4, MASS.filled())),
            )?
            .label("four point masses")
            .legend(|(x, y)| Circle::new((x + 10, y), 4, MASS.filled()));
    }
    if !bounds.is_empty() || cov.is_some() {
        chart
            .configure_series_labels()
            .position(SeriesLabelPosition::UpperRight)
            .background_style(WHITE.mix(0.8))
            .border_style(BLACK)
            .label_font(("sans-serif", 11))
            .draw()?;
    }
    Ok(())
}

/// A file name for a link's figure: `link_NAME.svg` with every character
/// outside `[A-Za-z0-9_.-]` replaced by `_` (and `_2`, `_3`, … when two
/// names come out alike).
pub fn file_name(link: &str, taken: &mut std::collections::HashSet<String>) -> String {
    let safe: String = link
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || "_.-".contains(c) {
                c
            } else {
                '_'
            }
        })
        .collect();
    let mut name = format!("link_{safe}.svg");
    let mut k = 2;
    while !taken.insert(name.clone()) {
        name = format!("link_{safe}_{k}.svg");
        k += 1;
    }
    name
}

//! SVG figures (plotters, SVG backend): the experiment's Fig. 4–6, the
//! diagnosis plots and the links' geometry (`check --out`).

pub mod bars;
pub mod diagnosis;
pub mod figures;
pub mod geometry;

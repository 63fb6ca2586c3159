//! SVG figures (plotters, SVG backend): the experiment's Fig. 4–6 and the
//! diagnosis plots.

pub mod diagnosis;
pub mod figures;

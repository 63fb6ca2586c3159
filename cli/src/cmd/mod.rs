//! One module per command; each `run` returns the process exit code (0
//! success, 1 a negative finding or an unsolved problem, 2 bad input).

pub mod check;
pub mod demo;
pub mod diagnose;
pub mod identify;
pub mod predict;
pub mod sdpa;
pub mod simulate;

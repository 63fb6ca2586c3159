//! # `sim`: data sets, signal processing and (to come) the simulated robot
//!
//! - [`dataset`]: the CSV data format with validation;
//! - [`filter`]: zero-phase Butterworth low-pass and differentiation.

pub mod dataset;
pub mod filter;

pub use dataset::{DataError, Dataset, ReadOptions};

//! # `momentlmi-cli`: the `momentlmi` command line
//!
//! The application layer over the [`momentlmi`] library: argument parsing
//! ([`main`]), one module per command ([`cmd`]), the paper's experiment behind
//! `momentlmi demo` ([`experiment`]) and the SVG figures ([`plots`]). The
//! library itself does not depend on clap, indicatif or plotters.

mod cli;
pub mod cmd;
pub mod experiment;
pub mod interrupt;
pub mod plots;
pub mod regularizer_study;

pub use cli::main;

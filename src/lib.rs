#![doc = include_str!("../README.md")]
#![warn(missing_docs)]

#[cfg(all(feature = "faer-lapack", feature = "system-openblas"))]
compile_error!(
    "features `faer-lapack` (the default) and `system-openblas` are mutually exclusive: \
     build with `--no-default-features --features system-openblas` to link OpenBLAS"
);
#[cfg(not(any(feature = "faer-lapack", feature = "system-openblas")))]
compile_error!(
    "enable exactly one BLAS/LAPACK provider: `faer-lapack` (default) or `system-openblas`"
);

// With `system-openblas`, Clarabel's BLAS/LAPACK calls resolve to the system
// `libopenblas` (Debian: `libopenblas-dev`).
#[cfg(feature = "system-openblas")]
#[link(name = "openblas")]
unsafe extern "C" {}

#[cfg(feature = "faer-lapack")]
pub mod faer_lapack;

pub mod conic;
pub mod data;
pub mod diagnose;
pub mod dynamics;
pub mod effects;
pub mod excite;
pub mod export;
pub mod identify;
mod io;
mod linalg;
pub mod moments;
pub mod numfmt;
pub mod sdpa;
pub mod sim;
pub mod tempfiles;
pub mod urdf;
mod warning;

/// The guides' Rust examples, compiled and run as doctests.
#[cfg(doctest)]
mod guides {
    #[doc = include_str!("../docs/identification.md")]
    struct Identification;
    #[doc = include_str!("../docs/robots.md")]
    struct Robots;
    #[doc = include_str!("../docs/architecture.md")]
    struct Architecture;
    #[doc = include_str!("../docs/math.md")]
    struct Math;
    #[doc = include_str!("../docs/diagnosis.md")]
    struct Diagnosis;
    #[doc = include_str!("../docs/inputs.md")]
    struct Inputs;
}

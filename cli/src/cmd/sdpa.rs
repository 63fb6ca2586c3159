//! `momentlmi sdpa FILE [--json] [--max-memory-gib G] [--decomposition verified|unchecked|off] [--qdldl] [--verbose]`.

use momentlmi::conic::{ConicError, Decomposition, KktSolver, Settings, Solution};
use momentlmi::sdpa::{MemoryEstimate, SdpaError, SdpaOptions, SdpaProblem};
use serde_json::json;
use std::path::PathBuf;

/// `momentlmi sdpa`'s options, declared once: clap parses them and the
/// command reads them.
#[derive(clap::Args, Debug, Clone)]
pub struct SdpaArgs {
    /// The .dat-s file.
    pub file: PathBuf,
    /// Print one JSON object instead of text.
    #[arg(long)]
    pub json: bool,
    /// Clarabel's chordal decomposition of sparse PSD blocks: `verified`
    /// checks the decomposed result against the original problem and
    /// solves again without it when the check fails (Clarabel 0.11 can end
    /// "solved" at a wrong optimum, e.g. SDPLIB control1), unless that
    /// undecomposed solve would exceed --max-memory-gib (then an error);
    /// `unchecked` returns the decomposed result as it is; `off` never
    /// decomposes.
    #[arg(long, value_enum, default_value_t = DecompositionArg::Verified)]
    pub decomposition: DecompositionArg,
    /// Use QDLDL instead of faer's supernodal LDLᵀ for the KKT systems.
    #[arg(long)]
    pub qdldl: bool,
    /// Print the solver's iteration log.
    #[arg(long)]
    pub verbose: bool,
    /// Refuse files whose reading or solve would need more than this
    /// many GiB by the reader's estimate (docs/inputs.md); a dense PSD
    /// block of side n needs about 14·n⁴ bytes, a sparse one decomposed
    /// that of its cliques.
    #[arg(long, value_name = "GIB", default_value_t = momentlmi::sdpa::DEFAULT_MAX_MEMORY_GIB, allow_hyphen_values = true)]
    pub max_memory_gib: f64,
}

/// `--decomposition`'s values.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum DecompositionArg {
    /// Decompose, check against the original problem, fall back if wrong.
    Verified,
    /// Decompose without a check.
    Unchecked,
    /// Never decompose.
    Off,
}

impl From<DecompositionArg> for Decomposition {
    fn from(a: DecompositionArg) -> Self {
        match a {
            DecompositionArg::Verified => Decomposition::Verified,
            DecompositionArg::Unchecked => Decomposition::Unchecked,
            DecompositionArg::Off => Decomposition::Off,
        }
    }
}

/// Solves the file; exit code 0 when solved, 1 when the solver ended
/// otherwise, 2 on unreadable or too large input (the error names the
/// line, block or entry, or the memory it would need).
pub fn run(a: &SdpaArgs) -> i32 {
    let fail = |e: &SdpaError| {
        eprintln!("error: {}: {e}", a.file.display());
        let memory = matches!(e, SdpaError::TooLarge { .. })
            || matches!(
                e,
                SdpaError::Conic(ConicError::DecompositionRejected { .. })
            );
        if memory {
            eprintln!("hint: --max-memory-gib raises the limit (max_memory_gib)");
        }
        2
    };
    let opts = SdpaOptions::default()
        .max_memory_gib(a.max_memory_gib)
        .decomposition(a.decomposition.into());
    let prob = match SdpaProblem::read_with(a.file.as_path(), &opts) {
        Ok(p) => p,
        Err(e) => return fail(&e),
    };
    let kkt = if a.qdldl {
        KktSolver::Qdldl
    } else {
        KktSolver::Faer
    };
    let settings = Settings::default()
        .kkt_solver(kkt)
        .verbose(a.verbose && !a.json);
    let (sol, estimate) = match prob.solve_with(&opts, settings) {
        Ok(r) => r,
        Err(e) => return fail(&e),
    };
    print_result(a, &prob, &estimate, &sol);
    if sol.status.is_solved() { 0 } else { 1 }
}

fn print_result(a: &SdpaArgs, prob: &SdpaProblem, est: &MemoryEstimate, sol: &Solution) {
    if a.json {
        let v = json!({
            "file": a.file.display().to_string(),
            "m": prob.m(),
            "blocks": prob.blocks,
            "memory_estimate_gib": est.total_gib(),
            "memory_estimate_decomposed_gib": est.decomposed_total_bytes() / 1024f64.powi(3),
            "decomposition": sol.decomposition.as_str(),
            "decomposition_reason": match &sol.decomposition {
                momentlmi::conic::DecompositionOutcome::FellBack(r) => Some(r.as_str()),
                _ => None,
            },
            "status": sol.status.as_str(),
            "primal_objective": sol.primal_objective,
            "dual_objective": sol.dual_objective,
            "iterations": sol.iterations,
            "solve_time_s": sol.solve_time_s,
            "setup_time_s": sol.setup_time_s,
        });
        println!("{v}");
    } else {
        println!("file              {}", a.file.display());
        println!("variables m       {}", prob.m());
        println!("blocks            {:?}", prob.blocks);
        println!(
            "memory estimate   {:.3} GiB ({:.3} GiB decomposed)",
            est.total_gib(),
            est.decomposed_total_bytes() / 1024f64.powi(3)
        );
        println!("status            {}", sol.status);
        println!("decomposition     {}", sol.decomposition);
        // an infeasible or unbounded end has no finite objective to show
        let show = |v: f64| {
            if v.is_finite() {
                format!("{v:.10e}")
            } else {
                "none (not solved)".to_string()
            }
        };
        println!("primal objective  {}", show(sol.primal_objective));
        println!("dual objective    {}", show(sol.dual_objective));
        println!("iterations        {}", sol.iterations);
        println!(
            "solve time        {:.4} s (setup {:.4} s)",
            sol.solve_time_s, sol.setup_time_s
        );
    }
}

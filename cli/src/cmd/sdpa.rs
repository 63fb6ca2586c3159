//! `momentlmi sdpa FILE [--json]`.

use momentlmi::conic::{KktSolver, Settings};
use momentlmi::sdpa::SdpaProblem;
use serde_json::json;
use std::path::Path;

/// Solves the file; exit code 0 when solved, 1 when the solver ended
/// otherwise, 2 on unreadable input.
pub fn run(file: &Path, as_json: bool, chordal: bool, qdldl: bool, verbose: bool) -> i32 {
    let prob = match SdpaProblem::read(file) {
        Ok(p) => p,
        Err(e) => {
            eprintln!("error: {}: {e}", file.display());
            return 2;
        }
    };
    let kkt = if qdldl {
        KktSolver::Qdldl
    } else {
        KktSolver::Faer
    };
    let settings = Settings::default()
        .chordal_decomposition(chordal)
        .kkt_solver(kkt)
        .verbose(verbose && !as_json);
    let result = prob
        .to_problem()
        .map_err(|e| e.to_string())
        .and_then(|(p, _)| p.solve(&settings).map_err(|e| e.to_string()));
    let sol = match result {
        Ok(s) => s,
        Err(e) => {
            eprintln!("error: {}: {e}", file.display());
            return 2;
        }
    };
    if as_json {
        let v = json!({
            "file": file.display().to_string(),
            "m": prob.m(),
            "blocks": prob.blocks,
            "status": sol.status.as_str(),
            "primal_objective": sol.primal_objective,
            "dual_objective": sol.dual_objective,
            "iterations": sol.iterations,
            "solve_time_s": sol.solve_time_s,
            "setup_time_s": sol.setup_time_s,
        });
        println!("{v}");
    } else {
        println!("file              {}", file.display());
        println!("variables m       {}", prob.m());
        println!("blocks            {:?}", prob.blocks);
        println!("status            {}", sol.status);
        println!("primal objective  {:.10e}", sol.primal_objective);
        println!("dual objective    {:.10e}", sol.dual_objective);
        println!("iterations        {}", sol.iterations);
        println!(
            "solve time        {:.4} s (setup {:.4} s)",
            sol.solve_time_s, sol.setup_time_s
        );
    }
    if sol.status.is_solved() { 0 } else { 1 }
}

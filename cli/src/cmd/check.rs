//! `momentlmi check ROBOT.urdf [--json] [--repair OUT.urdf]`.

use momentlmi::data::same_file;
use momentlmi::moments::urdf_check::{UrdfReport, check_urdf_file, check_urdf_str, repair_urdf};
use std::path::{Path, PathBuf};

fn fmt3(v: [f64; 3], prec: usize) -> String {
    format!("({:.p$}, {:.p$}, {:.p$})", v[0], v[1], v[2], p = prec)
}

fn print_table(file: &Path, r: &UrdfReport) {
    println!(
        "{} — robot '{}', {} links with inertials",
        file.display(),
        r.robot,
        r.links.len()
    );
    println!(
        "{:<28} {:>10} {:>30} {:>36}  {:<11} status",
        "link", "mass [kg]", "CoM [m]", "principal moments [kg·m²]", "in geometry"
    );
    for l in &r.links {
        let geo = match (l.realizable_in_geometry, l.geometry_primitives) {
            (_, 0) => "-".to_string(),
            (Some(true), n) => format!("yes ({n})"),
            (Some(false), n) => format!("NO ({n})"),
            (None, n) => format!("n/a ({n})"),
        };
        println!(
            "{:<28} {:>10.5} {:>30} {:>36}  {:<11} {}",
            l.name,
            l.mass,
            fmt3(l.com, 5),
            fmt3(l.principal_moments, 7),
            geo,
            l.describe()
        );
    }
    if !r.links_without_inertial.is_empty() {
        println!(
            "links without <inertial>: {}",
            r.links_without_inertial.join(", ")
        );
    }
    for l in &r.links {
        // mesh notes are warnings of the report (printed on stderr)
        for n in l.geometry_notes.iter().filter(|n| !n.contains("mesh '")) {
            println!("geometry not used, link '{}': {n}", l.name);
        }
    }
    let bad = r
        .links
        .iter()
        .filter(|l| !matches!(l.status, "ok" | "placeholder"))
        .count();
    let degenerate: Vec<&str> = r
        .links
        .iter()
        .filter(|l| l.degenerate.is_some())
        .map(|l| l.name.as_str())
        .collect();
    if !degenerate.is_empty() {
        println!(
            "{} degenerate link(s), consistent but with a singular pseudo-inertia (a point mass, rod or thin plate; MuJoCo refuses them): {}",
            degenerate.len(),
            degenerate.join(", ")
        );
    }
    if r.nothing_to_check() {
        println!("nothing to check: no link has an <inertial>");
    } else if bad == 0 {
        println!("all inertias are physically consistent");
    } else {
        println!("{bad} link(s) with physically inconsistent inertia");
    }
}

/// Exit codes: 0 some link has an `<inertial>` and every one is consistent
/// (or a zero placeholder); 1 some are not, or no link has an `<inertial>`
/// (nothing to check), or with `--strict` some link is degenerate; 2 an
/// invalid file (unreadable, beyond the reader's
/// limits, duplicate names, not one tree, …), a `--repair`
/// target that is the input itself, or a failed repair or write (nothing is
/// written then). Warnings (unusable geometry) go to stderr and leave the
/// code alone. See docs/inputs.md.
pub fn run(file: &Path, opts: &CheckArgs) -> i32 {
    let (json, repair, package_paths) = (opts.json, opts.repair, opts.package_paths);
    if let Some(out) = repair
        && same_file(file, out)
    {
        eprintln!(
            "error: --repair {}: that is the input file {}; write the repaired URDF to another file",
            out.display(),
            file.display()
        );
        return 2;
    }
    let (text, report) = match check_urdf_file(file, package_paths) {
        Ok(x) => x,
        Err(e) => {
            eprintln!("error: {e}");
            return 2;
        }
    };
    for w in &report.warnings {
        eprintln!("warning: {}: {w}", file.display());
    }
    if json {
        match serde_json::to_string_pretty(&report) {
            Ok(s) => println!("{s}"),
            Err(e) => {
                eprintln!("error: {e}");
                return 2;
            }
        }
    } else {
        print_table(file, &report);
    }
    if let Some(out) = repair
        && let Err(e) = write_repair(file, &text, &report, out, json)
    {
        eprintln!("error: {e}");
        return 2;
    }
    let strict_finding = opts.strict && report.links.iter().any(|l| l.degenerate.is_some());
    if report.consistent && !strict_finding {
        0
    } else {
        1
    }
}

/// The options of `check`.
pub struct CheckArgs<'a> {
    /// One JSON object instead of the table.
    pub json: bool,
    /// Where to write the repaired copy.
    pub repair: Option<&'a Path>,
    /// Folders of `package://` meshes.
    pub package_paths: &'a [PathBuf],
    /// Degenerate links (singular J) are findings (exit 1).
    pub strict: bool,
}

/// Repairs the inconsistent inertials and writes the result to `out` (a
/// staged temporary file beside it, renamed into place) only if it checks
/// clean; on any failure nothing is written.
fn write_repair(
    file: &Path,
    text: &str,
    report: &UrdfReport,
    out: &Path,
    json: bool,
) -> Result<(), String> {
    let (fixed, names) =
        repair_urdf(text, report, &file.display().to_string()).map_err(|e| e.to_string())?;
    // the repaired file must itself check clean before it is written
    match check_urdf_str(&fixed, &out.display().to_string()) {
        Ok(r)
            if r.links
                .iter()
                .all(|l| matches!(l.status, "ok" | "placeholder" | "nonpositive_mass")) => {}
        Ok(_) | Err(_) => {
            return Err("the repaired URDF did not check clean; nothing written".into());
        }
    }
    momentlmi::data::write_whole(out, &fixed).map_err(|e| e.to_string())?;
    let msg = format!(
        "wrote {} ({} inertial(s) repaired{}{})",
        out.display(),
        names.len(),
        if names.is_empty() { "" } else { ": " },
        names.join(", ")
    );
    if json {
        eprintln!("{msg}");
    } else {
        println!("{msg}");
    }
    Ok(())
}

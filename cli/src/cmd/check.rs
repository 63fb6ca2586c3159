//! `momentlmi check ROBOT.urdf [--json] [--repair OUT.urdf [--repair-to geometry]]
//! [--sidecar S.toml] [--out DIR]`.

use momentlmi::data::{Staged, same_file};
use momentlmi::dynamics::sidecar::Sidecar;
use momentlmi::moments::geometry::{Meshes, geometry_points};
use momentlmi::moments::urdf_check::{
    LEFT_AS_IS, RepairOptions, RepairTarget, UrdfReport, check_urdf_file_with, check_urdf_str,
    repair_urdf,
};
use momentlmi::urdf::Robot;
use momentlmi::urdf::mesh::MeshPaths;
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
        for n in l.shape_notes() {
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
/// target that is the input itself, an unusable `--sidecar` or `--out`, or a
/// failed repair or write (nothing is written then). Warnings (unusable
/// geometry) go to stderr and leave the code alone. See docs/inputs.md.
pub fn run(opts: &CheckArgs) -> i32 {
    match checked(&opts.urdf, opts) {
        Ok(code) => code,
        Err(e) => {
            eprintln!("error: {e}");
            2
        }
    }
}

/// The largest `--repair-margin`: the thinnest direction of a repaired body
/// at about √ε of its length scale, a third of it here.
const MAX_REPAIR_MARGIN: f64 = 0.1;

/// [`run`] with every failure an error message (exit 2).
fn checked(file: &Path, opts: &CheckArgs) -> Result<i32, String> {
    if let Some((_, how)) = &opts.repair()
        && !(how.margin.is_finite() && (0.0..MAX_REPAIR_MARGIN).contains(&how.margin))
    {
        return Err(format!(
            "--repair-margin {}: must be a number in [0, {MAX_REPAIR_MARGIN}) (a relative margin; 1e-6 to 1e-3 is usual)",
            how.margin
        ));
    }
    if let Some((out, _)) = &opts.repair()
        && momentlmi::data::Target::of(out).map_err(|e| e.to_string())?
            == momentlmi::data::Target::Stdout
    {
        return Err(format!(
            "--repair {}: the check's report takes standard output; give the repaired URDF a file",
            out.display()
        ));
    }
    let robot_args = super::args::RobotArgs {
        robot: file.display().to_string(),
        sidecar: opts.sidecar.clone(),
        no_sidecar: opts.sidecar.is_none(),
        package_path: opts.package_path.clone(),
    };
    let inputs = robot_args.inputs_with(&[], &[]);
    for out in opts.repair.iter().chain(&opts.out) {
        if let Some(i) = inputs.iter().find(|i| same_file(i, out)) {
            return Err(format!(
                "{}: that is the input file {}; write to another path",
                out.display(),
                i.display()
            ));
        }
    }
    let mut meshes = geometry_source(file, opts)?;
    let (text, robot, report) =
        check_urdf_file_with(file, &mut meshes).map_err(|e| e.to_string())?;
    if let Some(name) = meshes
        .given_links()
        .find(|n| !robot.links.iter().any(|l| l.name == *n))
    {
        let sc = (opts.sidecar.as_deref()).map_or(String::new(), |p| p.display().to_string());
        return Err(format!(
            "{sc}: [[body]] '{name}': {} has no link of that name",
            file.display()
        ));
    }
    for w in &report.warnings {
        eprintln!("warning: {}: {w}", file.display());
    }
    if let Some(reason) = meshes.cache_error() {
        let reason = reason.to_string();
        let w = momentlmi::dynamics::DescriptionWarning::Cache { reason };
        eprintln!("warning: {w}");
    }
    if opts.json {
        println!(
            "{}",
            serde_json::to_string_pretty(&report).map_err(|e| e.to_string())?
        );
    } else {
        print_table(file, &report);
    }
    if let Some((out, how)) = &opts.repair() {
        write_repair(file, &text, &report, (out, how), opts.json)?;
    }
    if let Some(dir) = &opts.out {
        write_plots(&robot, &report, &mut meshes, dir, &inputs)?;
    }
    let strict_finding = opts.strict && report.links.iter().any(|l| l.degenerate.is_some());
    Ok(if report.consistent && !strict_finding {
        0
    } else {
        1
    })
}

/// Where meshes are found, and the sidecar's bounding ellipsoids by link
/// (each must name a link of the file).
fn geometry_source(file: &Path, opts: &CheckArgs) -> Result<Meshes, String> {
    let mut meshes = Meshes::new(MeshPaths::for_urdf(file, &opts.package_path));
    if let Some(cache) = super::solve_cache() {
        meshes = meshes.with_cache(cache);
    }
    let Some(path) = opts.sidecar.as_deref() else {
        return Ok(meshes);
    };
    let sc = Sidecar::read(path).map_err(|e| e.to_string())?;
    for b in sc.bodies.iter().filter(|b| !b.bounding.is_empty()) {
        let es = b
            .ellipsoids()
            .map_err(|e| format!("{}: {e}", path.display()))?;
        meshes = meshes.with_bounding(&b.name, es);
    }
    Ok(meshes)
}

/// One SVG per link with an `<inertial>` into `dir`, all or none.
fn write_plots(
    robot: &Robot,
    report: &UrdfReport,
    meshes: &mut Meshes,
    dir: &Path,
    inputs: &[std::path::PathBuf],
) -> Result<(), String> {
    use crate::plots::geometry::{LinkFigure, file_name, link_svg};
    let folder = super::OutDir::create(dir)?;
    let mut staged = Staged::protecting(inputs);
    let mut taken = std::collections::HashSet::new();
    for r in &report.links {
        let Some(link) = robot.links.iter().find(|l| l.name == r.name) else {
            continue;
        };
        let points = geometry_points(link, meshes, 3000);
        let svg = link_svg(&LinkFigure {
            report: r,
            points: &points,
        })?;
        let path = dir.join(file_name(&r.name, &mut taken));
        staged.add_text(&path, &svg).map_err(|e| e.to_string())?;
    }
    staged.commit().map_err(|e| e.to_string())?;
    folder.keep();
    eprintln!(
        "wrote {} link figure(s) to {}",
        report.links.len(),
        dir.display()
    );
    Ok(())
}

/// `momentlmi check`'s options, declared once: clap parses them and the
/// command reads them.
#[derive(clap::Args, Debug, Clone)]
pub struct CheckArgs {
    /// The URDF file.
    pub urdf: PathBuf,
    /// Print one JSON object with a `links` array.
    #[arg(long)]
    pub json: bool,
    /// Write a copy with every inconsistent inertial replaced by the nearest consistent one
    /// (never the input itself; nothing is written unless the copy checks clean).
    #[arg(long, value_name = "OUT.urdf")]
    pub repair: Option<PathBuf>,
    /// What --repair projects onto: `consistent` (the inconsistent inertials, inside their
    /// geometry where possible) or `geometry` (also every consistent inertial that is not
    /// density realizable in its link's bounding volume).
    #[arg(long, value_enum, default_value = "consistent", requires = "repair")]
    pub repair_to: RepairTarget,
    /// The repair's relative margin ε: 1e-6 lands next to the boundary (often a rod or a thin
    /// plate); 1e-3 keeps the thinnest direction at about 3 % of the link's length scale.
    #[arg(
        long,
        default_value_t = 1e-6,
        requires = "repair",
        value_name = "EPS",
        allow_hyphen_values = true
    )]
    pub repair_margin: f64,
    /// Bounding ellipsoids for links by name, from a sidecar's `[[body]] name, bounding`
    /// (link frame); they replace the ones of the link's shapes.
    #[arg(long, value_name = "SIDECAR.toml")]
    pub sidecar: Option<PathBuf>,
    /// Folder for one SVG per link: its shapes' points, bounding and covariance ellipsoids,
    /// CoM and four point masses, in three views.
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
    /// A folder where `package://NAME/…` meshes are found: a package itself or a folder of
    /// packages (repeatable; searched after the folders above the URDF, before ROS_PACKAGE_PATH);
    /// meshes outside the URDF's folder and these folders are not read.
    #[arg(long = "package-path", value_name = "DIR")]
    pub package_path: Vec<PathBuf>,
    /// Degenerate links (consistent, but J singular: a point mass, rod or thin plate) make
    /// the exit code 1 too.
    #[arg(long)]
    pub strict: bool,
}

impl CheckArgs {
    /// Where to write the repaired copy, and how to repair.
    fn repair(&self) -> Option<(&Path, RepairOptions)> {
        let how = RepairOptions {
            target: self.repair_to,
            margin: self.repair_margin,
        };
        self.repair.as_deref().map(|p| (p, how))
    }
}

/// Repairs the inconsistent inertials and writes the result to `out` (a
/// staged temporary file beside it, renamed into place) only if it checks
/// clean; on any failure nothing is written.
fn write_repair(
    file: &Path,
    text: &str,
    report: &UrdfReport,
    (out, how): (&Path, &RepairOptions),
    json: bool,
) -> Result<(), String> {
    let margin = how.margin;
    let (fixed, names) = repair_urdf(text, report, &file.display().to_string(), how).map_err(|e| {
        format!(
            "{e}\nhint: --repair-margin {margin:e} asks every repaired body to keep its thinnest direction at about {:.1} % of its length scale; a smaller margin (1e-6 to 1e-3) leaves more room",
            100.0 * margin.sqrt()
        )
    })?;
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
    let left = names.iter().filter(|n| n.ends_with(LEFT_AS_IS)).count();
    let msg = format!(
        "wrote {} ({} inertial(s) repaired{}{})",
        out.display(),
        names.len() - left,
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

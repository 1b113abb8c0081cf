//! `linkwright fabricate SCENE DESIGN -o DIR [--settings PRINT.json]`: printable parts, plates,
//! profiles, the assembly sheet and `fabrication.json` for a design (and `design --fabricate`).

use crate::files::{read_design, read_problem, write_atomically};
use crate::Failure;
use clap::Args;
use linkwright_core::design::DesignFile;
use linkwright_core::fab::bundle::bundle;
use linkwright_core::fab::{fabricate_design_or_alternative, PrintSettings};
use linkwright_core::scene::{Problem, Scene};
use std::path::{Path, PathBuf};

#[derive(Args, Debug)]
pub struct FabricateArgs {
    /// The scene file (scene/1).
    scene: PathBuf,
    /// The design file (design/1).
    design: PathBuf,
    /// Output directory (created if needed).
    #[arg(short, long)]
    output: PathBuf,
    /// Print settings (JSON, millimetres; missing fields keep their defaults).
    #[arg(long)]
    settings: Option<PathBuf>,
}

/// Reads print settings, or the defaults.
pub fn read_settings(path: Option<&Path>) -> Result<PrintSettings, Failure> {
    let Some(path) = path else { return Ok(PrintSettings::default()) };
    let text = std::fs::read_to_string(path)
        .map_err(|e| Failure::Input(format!("error: cannot read {}: {e}", path.display())))?;
    let settings = PrintSettings::from_json(&text)
        .map_err(|e| Failure::Input(format!("error: {}: {}: {}", path.display(), e.field, e.message)))?;
    let issues = settings.validate();
    if !issues.is_empty() {
        let lines: Vec<String> = issues.iter().map(|i| format!("error: {}: {i}", path.display())).collect();
        return Err(Failure::Input(lines.join("\n")));
    }
    Ok(settings)
}

pub fn fabricate(args: FabricateArgs) -> Result<(), Failure> {
    let (scene, problem) = read_problem(&args.scene)?;
    let design = read_design(&args.design)?;
    let settings = read_settings(args.settings.as_deref())?;
    let summary = run(&scene, &problem, &design, &settings, &args.output)?;
    println!("{summary}");
    Ok(())
}

/// Fabricates `design` into `out_dir` and returns a one-line summary.
pub fn run(
    scene: &Scene,
    problem: &Problem,
    design: &DesignFile,
    settings: &PrintSettings,
    out_dir: &Path,
) -> Result<String, Failure> {
    if out_dir.exists() && !out_dir.is_dir() {
        return Err(Failure::Input(format!("error: -o {}: exists and is not a directory", out_dir.display())));
    }
    let (which, fab) = fabricate_design_or_alternative(problem, &scene.units, design, settings)
        .map_err(|e| Failure::Input(format!("error: cannot fabricate: {e}")))?;
    let bundle = bundle(&fab).map_err(|e| Failure::Input(format!("error: cannot fabricate: {e}")))?;
    for dir in [out_dir.to_path_buf(), out_dir.join("parts")] {
        std::fs::create_dir_all(&dir)
            .map_err(|e| Failure::Input(format!("error: cannot create {}: {e}", dir.display())))?;
    }
    for (path, bytes) in &bundle.files {
        write_atomically(&out_dir.join(path), bytes)?;
    }
    let r = &bundle.report;
    let mut line = format!(
        "{}: {} parts on {} layer(s) (front {}, back {}), {} plate(s), {:.0} g; ordering {:.3} s, meshing {:.3} s -> {}",
        r.scene,
        r.totals.parts,
        r.layers.count,
        r.layers.front,
        r.layers.back,
        r.plates.len(),
        r.totals.mass_g,
        r.seconds.ordering,
        r.seconds.meshing,
        out_dir.display()
    );
    if which > 0 {
        line.push_str(&format!(
            "\nnote: the design itself cannot be fabricated, or has parts larger than the bed; this is its alternative \
             {which} (alternatives[{}])",
            which - 1
        ));
    }
    if let Some(advice) = r.oversized_advice() {
        line.push_str(&format!("\nwarning: {advice}; they are not on any plate (fabrication.json \"oversized\")"));
    }
    if !r.checks.ok() {
        line.push_str("\nwarning: the fabrication checks found problems (see fabrication.json \"checks\")");
    }
    Ok(line)
}

//! `linkwright fabricate SCENE DESIGN -o DIR [--settings PRINT.json] [--springs]`: printable parts,
//! plates, profiles, the assembly sheet and `fabrication.json` for a design (and `design --fabricate`),
//! with hooks for its counterbalance springs when asked.

use crate::failure::Failure;
use crate::files::{
    check_output_paths, read_problem, read_text, read_valid_design, remove_below, remove_folder_if_empty, write_below,
};
use clap::Args;
use linkwright_core::fab::{
    bundle, fabricate_design_or_alternative, is_safe_relative_path, Chosen, FabError, PrintSettings, FIXED_FILES,
};
use linkwright_core::hooked::{fabricate_with_springs, Hooked, HookedError};
use linkwright_core::workshop::SpringOrder;
use linkwright_core::{Build, DesignFile, Problem, Silent};
use serde_json::Value;
use std::path::{Path, PathBuf};

#[derive(Args, Debug)]
pub(crate) struct FabricateArgs {
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
    /// Give the parts hooks for counterbalance springs: the extension springs that balance the parts
    /// printed with these settings (as `analyze` chooses them, without torsion springs, and only where
    /// hooks fit), hung beyond the links
    #[arg(long)]
    springs: bool,
    /// How the object is built (overrides the scene's `build`): model:auto or model:1:10 print the
    /// parts of a model; full:plywood, full:aluminium or full:steel write the workshop files of the
    /// full-size build (profiles to cut, cut list, bill of materials, assembly sheet).
    #[arg(long, value_name = "BUILD", value_parser = crate::build_choice())]
    build: Option<Build>,
}

/// Reads print settings, or the defaults.
pub(crate) fn read_settings(path: Option<&Path>) -> Result<PrintSettings, Failure> {
    let Some(path) = path else { return Ok(PrintSettings::default()) };
    let text = read_text(path)?;
    let settings =
        PrintSettings::from_json(&text).map_err(|e| crate::files::parse_failure(path, &e.field, &e.message))?;
    let issues = settings.validate();
    if !issues.is_empty() {
        let lines: Vec<String> = issues
            .iter()
            .map(|i| format!("error: {}: {}", path.display(), crate::terminal::escaped(&i.to_string())))
            .collect();
        return Err(Failure::Input(lines.join("\n")));
    }
    Ok(settings)
}

pub(crate) fn fabricate(args: FabricateArgs) -> Result<(), Failure> {
    let (_, mut problem) = read_problem(&args.scene)?;
    if let Some(build) = args.build {
        problem.build = build;
    }
    let design = read_valid_design(&args.design, &problem)?;
    let settings = read_settings(args.settings.as_deref())?;
    let summary = run(&problem, &design, &settings, args.springs, &args.output)?;
    crate::terminal::say(&summary);
    Ok(())
}

/// Fabricates `design` into `out_dir` and returns a one-line summary.
pub(crate) fn run(
    problem: &Problem,
    design: &DesignFile,
    settings: &PrintSettings,
    springs: bool,
    out_dir: &Path,
) -> Result<String, Failure> {
    if out_dir.exists() && !out_dir.is_dir() {
        return Err(Failure::Input(format!("error: -o {}: exists and is not a directory", out_dir.display())));
    }
    if let Build::Full(material) = problem.build {
        // The springs a full-size build needs are bought, not hooked on printed parts: listed.
        let springs = if springs {
            let (_, balance) =
                crate::springs::counterbalanced(("the scene", problem), ("the design", design), settings)?;
            SpringOrder::from_balance(&balance)
        } else {
            Vec::new()
        };
        return crate::workshop::write(problem, design, material, springs, out_dir);
    }
    let cannot = |e: &dyn std::fmt::Display| Failure::Input(format!("error: cannot fabricate: {e}"));
    // Springs are hooked on the design's own parts: no alternative stands in for it.
    let mut words = String::new();
    let chosen = if springs {
        let hooked = fabricate_with_springs(problem, design, settings, &Silent).map_err(|e| {
            let remedy = match e {
                HookedError::NoRoomForSprings | HookedError::Fab(FabError::SpringHook { .. }) => {
                    " (or leave out --springs)"
                }
                _ => "",
            };
            Failure::Input(format!("error: cannot fabricate with springs: {e}{remedy}"))
        })?;
        let Hooked { fabrication, torque, balance } = hooked;
        for (n, spring) in balance.springs.iter().enumerate() {
            words.push_str(&format!("\nspring {}: {}", n + 1, crate::springs::spring_words(spring, &problem.units)));
        }
        if balance.springs.is_empty() {
            words.push_str("\nnote: no extension spring lowers the crank's peak torque, so the parts have no hooks");
        } else {
            let cut = balance.peak_lowered_percent(&torque);
            words.push_str(&format!(
                "\nthe springs lower the crank's peak torque by {cut:.0}% (`linkwright analyze` may find better ones \
                 that cannot be hooked); the assembly sheet says where each hangs"
            ));
        }
        Chosen { used: 0, fabrication, passed_over: None }
    } else {
        fabricate_design_or_alternative(problem, design, settings).map_err(|e| cannot(&e))?
    };
    let bundle = bundle(&chosen.fabrication).map_err(|e| cannot(&e))?;
    check_output_paths(bundle.files.iter().map(|(path, _)| path.as_str()))?;
    remove_previous(out_dir)?;
    for (path, bytes) in &bundle.files {
        write_below(out_dir, path, bytes)?;
    }
    let r = &bundle.report;
    let mut line = format!(
        "{}: a printed model at {}, {:.0} × {:.0} mm: {} parts on {} layer(s) (front {}, back {}), {} plate(s), {:.0} g; \
         ordering {:.3} s, meshing {:.3} s -> {}",
        r.scene,
        r.scale,
        r.model_mm[0],
        r.model_mm[1],
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
    if let (k @ 1.., Some(why)) = (chosen.used, &chosen.passed_over) {
        line.push_str(&format!(
            "\nnote: these are the parts of the design's alternative {k} (alternatives[{}]), not of the design \
             itself: {why}",
            k - 1
        ));
    }
    if let Some(advice) = r.oversized_advice() {
        line.push_str(&format!("\nwarning: {advice}; they are not on any plate (fabrication.json \"oversized\")"));
    }
    if !r.checks.ok() {
        line.push_str("\nwarning: the fabrication checks found problems (see fabrication.json \"checks\")");
    }
    line.push_str(&words);
    Ok(line)
}

/// Removes what an earlier fabrication wrote into `dir`, as its `fabrication.json` lists it (each
/// part's and plate's file, the files every fabrication writes, then `fabrication.json` itself and the
/// `parts` folder if that leaves it empty), so a folder never holds the parts of two fabrications.
/// Only paths of the shapes a fabrication writes are removed; nothing else in the folder is touched.
pub(crate) fn remove_previous(dir: &Path) -> Result<(), Failure> {
    let manifest = dir.join("fabrication.json");
    let Ok(text) = read_text(&manifest) else { return Ok(()) };
    let report: Value = serde_json::from_str(&text).unwrap_or(Value::Null);
    let listed = ["parts", "plates"]
        .iter()
        .filter_map(|key| report.get(key).and_then(Value::as_array))
        .flatten()
        .filter_map(|entry| entry.get("file").and_then(Value::as_str));
    let written_by_a_fabrication = |path: &&str| {
        is_safe_relative_path(path)
            && ((path.starts_with("parts/") && path.ends_with(".stl") && path.matches('/').count() == 1)
                || (path.starts_with("plate_") && path.ends_with(".3mf") && !path.contains('/')))
    };
    for path in listed.filter(written_by_a_fabrication).chain(FIXED_FILES.iter().copied()) {
        remove_below(dir, path)?;
    }
    remove_below(dir, "fabrication.json")?;
    remove_folder_if_empty(dir, "parts")
}

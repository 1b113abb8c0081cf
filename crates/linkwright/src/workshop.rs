//! A full-size build's workshop files (`full:plywood`, `full:aluminium`, `full:steel`): the profiles
//! to cut, the cut list, the bill of materials, the assembly sheet and `workshop.json`, written into
//! a folder.

use crate::failure::Failure;
use crate::files::{check_output_paths, read_text, remove_below, write_below};
use linkwright_core::fab::is_safe_relative_path;
use linkwright_core::workshop::{files, plan, SpringOrder, WorkshopSettings};
use linkwright_core::{DesignFile, Material, Problem};
use serde_json::Value;
use std::path::Path;

/// Plans the full-size build of `design` in `material` with the default workshop settings (and
/// `springs` in its bill of materials) and writes
/// its files into `out_dir` (created if needed), each atomically; what an earlier plan wrote there is
/// removed first. Returns a one-line summary, with a line per note the plan has.
pub(crate) fn write(
    problem: &Problem,
    design: &DesignFile,
    material: Material,
    springs: Vec<SpringOrder>,
    out_dir: &Path,
) -> Result<String, Failure> {
    if out_dir.exists() && !out_dir.is_dir() {
        return Err(Failure::Input(format!("error: -o {}: exists and is not a directory", out_dir.display())));
    }
    let settings = WorkshopSettings { springs, ..WorkshopSettings::default() };
    let workshop = plan(problem, design, material, &settings)
        .map_err(|e| Failure::Input(format!("error: cannot plan the full-size build: {e}")))?;
    let written = files(&workshop);
    check_output_paths(written.iter().map(|(path, _)| path.as_str()))?;
    remove_previous(out_dir)?;
    for (path, bytes) in &written {
        write_below(out_dir, path, bytes)?;
    }
    let bolts: u32 = workshop.bolts.iter().map(|b| b.count).sum();
    let stocks: Vec<String> = {
        let mut t: Vec<f64> = workshop.links.iter().map(|l| l.thickness_mm).collect();
        t.sort_by(f64::total_cmp);
        t.dedup();
        t.iter().map(|t| format!("{t} mm")).collect()
    };
    let mut line = format!(
        "{}: full size in {}: {} parts from {} stock, {} bolts ({} at the joints), on {} layer(s); the crank holds up to \
         {:.1} N·m -> {}",
        workshop.scene,
        material.id(),
        workshop.links.len(),
        stocks.join(", "),
        bolts,
        workshop.bolt.size,
        workshop.layers.len(),
        workshop.peak_torque_nm,
        out_dir.display()
    );
    for note in &workshop.notes {
        line.push_str(&format!("\nnote: {note}"));
    }
    Ok(line)
}

/// Removes what an earlier plan wrote into `dir`, as its `workshop.json` lists it (only names of the
/// shapes a plan writes, directly in the folder), then `workshop.json` itself; nothing else in the
/// folder is touched, so a folder never holds the profiles of two plans.
fn remove_previous(dir: &Path) -> Result<(), Failure> {
    let manifest = dir.join("workshop.json");
    let Ok(text) = read_text(&manifest) else { return Ok(()) };
    let report: Value = serde_json::from_str(&text).unwrap_or(Value::Null);
    let listed = report.get("files").and_then(Value::as_array).into_iter().flatten().filter_map(Value::as_str);
    let written_by_a_plan = |path: &&str| {
        is_safe_relative_path(path)
            && !path.contains('/')
            && (matches!(*path, "workshop_assembly.svg" | "cut_list.csv" | "bill_of_materials.csv")
                || (path.starts_with("profiles_") && (path.ends_with("mm.dxf") || path.ends_with("mm.svg"))))
    };
    for path in listed.filter(written_by_a_plan) {
        remove_below(dir, path)?;
    }
    remove_below(dir, "workshop.json")
}

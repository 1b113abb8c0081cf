//! The counterbalance springs of a design, as `analyze` reports them, and in words a person buys from
//! (`analyze`, `fabricate --springs`).

use crate::Failure;
use linkwright_core::analysis::{Replay, Which};
use linkwright_core::balance::{Balance, Balancing, Spring, SpringSearch};
use linkwright_core::fab::PrintSettings;
use linkwright_core::statics::{driving_torque, Masses, Torque};
use linkwright_core::{DesignFile, Problem, Scene, Silent};
use std::path::Path;

/// Steps of the crank's travel the torque is given at.
pub const ANALYZE_STEPS: usize = 180;

/// The torque the crank needs along the design's motion (masses of the parts printed with
/// `settings`, or the scene's), and the springs of either kind that lower its peak (what `analyze`
/// reports). Paths are for messages.
pub fn counterbalanced(
    (scene_path, scene): (&Path, &Scene),
    problem: &Problem,
    (design_path, design): (&Path, &DesignFile),
    settings: &PrintSettings,
) -> Result<(Torque, Balance), Failure> {
    let masses = Masses::printed(settings, &scene.units).ok_or_else(|| {
        Failure::Input(format!(
            "error: {}: units \"{}\" are not a length; set them to mm, cm, m, in or ft to weigh the parts",
            scene_path.display(),
            scene.units
        ))
    })?;
    if design.mechanism.is_none() {
        return Err(Failure::Input(format!("error: {}: has no mechanism (status no_solution)", design_path.display())));
    }
    let replay = Replay::new(problem, design, Which::Best, ANALYZE_STEPS)
        .map_err(|e| Failure::Input(format!("error: {}: {e}", design_path.display())))?;
    let torque = driving_torque(problem, &replay.mechanism, &replay.plan, &replay.trace, &masses)
        .map_err(|e| Failure::Input(format!("error: {}: {e}", design_path.display())))?;
    let (mechanism, plan, trace) = (&replay.mechanism, &replay.plan, &replay.trace);
    let balance = Balancing { problem, mechanism, plan, trace, masses: &masses, torque: &torque }
        .best(SpringSearch::ANALYSIS, &Silent)
        .expect("a silent search is never cancelled");
    Ok((torque, balance))
}

/// A spring as a person buys and fits it.
pub fn spring_words(spring: &Spring, units: &str) -> String {
    match spring {
        Spring::Extension { anchors, stiffness_n_per_m, free_length, length_range, force_range_n, .. } => {
            let [a, b] = anchors;
            format!(
                "extension spring, {:.3} N/mm, {free_length:.1} {units} free length hook to hook: one end on {} at \
                 ({:.1}, {:.1}), the other on {} at ({:.1}, {:.1}) (first pose); it stretches to {:.1}–{:.1} {units}, \
                 pulling {:.1}–{:.1} N",
                stiffness_n_per_m / 1000.0,
                a.part,
                a.point.x,
                a.point.y,
                b.part,
                b.point.x,
                b.point.y,
                length_range[0],
                length_range[1],
                force_range_n[0],
                force_range_n[1]
            )
        }
        Spring::Torsion {
            part, pivot, stiffness_nm_per_rad, free_angle_deg, twist_range_deg, torque_range_nm, ..
        } => {
            format!(
                "torsion spring, {:.2} N·mm per degree, at the {part}'s ground pivot ({:.1}, {:.1}); free when the \
                 {part} is turned {free_angle_deg:.0}° from the first pose; wound {:.0}–{:.0}°, {:.3}–{:.3} N·m",
                stiffness_nm_per_rad * 1000.0 * std::f64::consts::PI / 180.0,
                pivot.x,
                pivot.y,
                twist_range_deg[0],
                twist_range_deg[1],
                torque_range_nm[0],
                torque_range_nm[1]
            )
        }
    }
}

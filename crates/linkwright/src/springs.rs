//! The counterbalance springs of a design, as `analyze` reports them, and in words a person buys from
//! (`analyze`, `fabricate --springs`).

use crate::failure::Failure;
use linkwright_core::analysis::{Replay, Which};
use linkwright_core::balance::{Balance, Spring, SpringSearch};
use linkwright_core::fab::PrintSettings;
use linkwright_core::statics::{Masses, Torque};
use linkwright_core::{DesignFile, Problem, Silent, Units};

/// Steps of the crank's travel the torque is given at.
pub(crate) const ANALYZE_STEPS: usize = 180;

/// The torque the crank needs along the design's motion (its printed model's parts with `settings`
/// at the design's scale, or a full-size build's real masses), and the springs of either kind that
/// lower its peak (what `analyze` reports). The error says what is wrong, naming `scene` or `design`
/// (how the caller calls them).
pub(crate) fn counterbalanced(
    (scene, problem): (&str, &Problem),
    (design_name, design): (&str, &DesignFile),
    settings: &PrintSettings,
) -> Result<(Torque, Balance), Failure> {
    let fail = |what: &str, e: &dyn std::fmt::Display| Failure::Input(format!("error: {what}: {e}"));
    let masses = Masses::for_design(problem, Some(design), settings).map_err(|e| fail(scene, &e))?;
    if design.mechanism.is_none() {
        return Err(fail(design_name, &"has no mechanism (status no_solution)"));
    }
    let replay = Replay::new(problem, design, Which::Best, ANALYZE_STEPS).map_err(|e| fail(design_name, &e))?;
    let torque = replay.torque(problem, &masses).map_err(|e| fail(design_name, &e))?;
    let balance = replay
        .balancing(problem, &masses, &torque)
        .best(SpringSearch::ANALYSIS, &Silent)
        .expect("a silent search is never cancelled");
    Ok((torque, balance))
}

/// A spring as a person buys and fits it: the stock rate and free length (millimetres of the thing
/// built: a model's for a printed model), and where its ends hang in the drawing.
pub(crate) fn spring_words(spring: &Spring, units: &Units) -> String {
    match spring {
        Spring::Extension { anchors, rate_n_per_mm, free_length_mm, length_range_mm, force_range_n, .. } => {
            let [a, b] = anchors;
            format!(
                "extension spring, {rate_n_per_mm} N/mm, {free_length_mm} mm free length hook to hook: one end on {} \
                 at ({:.1}, {:.1}), the other on {} at ({:.1}, {:.1}) {units} (first pose); it stretches to \
                 {:.1}–{:.1} mm, pulling {:.1}–{:.1} N",
                a.part,
                a.point.x,
                a.point.y,
                b.part,
                b.point.x,
                b.point.y,
                length_range_mm[0],
                length_range_mm[1],
                force_range_n[0],
                force_range_n[1]
            )
        }
        Spring::Torsion {
            part, pivot, rate_n_mm_per_deg, free_angle_deg, twist_range_deg, torque_range_nm, ..
        } => {
            format!(
                "torsion spring, {rate_n_mm_per_deg} N·mm per degree, at the {part}'s ground pivot ({:.1}, {:.1}) \
                 {units}; free when the {part} is turned {free_angle_deg:.0}° from the first pose; wound {:.0}–{:.0}°, \
                 {:.3}–{:.3} N·m",
                pivot.x, pivot.y, twist_range_deg[0], twist_range_deg[1], torque_range_nm[0], torque_range_nm[1]
            )
        }
    }
}

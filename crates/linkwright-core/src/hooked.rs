//! Counterbalance springs on printed parts: the springs [`crate::balance`] chooses for a design, and its
//! fabrication ([`crate::fab`]) with a hook at both ends of each.
//!
//! Only extension springs get hooks, and only where the parts leave them room along the motion: the
//! search's choices are tried best first (the pairs worth a second spring, then the best single spring
//! of each moving part) until one's hooks fit; when none does and some anchor on a link lay beside a
//! joint, the search again with anchors on links kept clear of their joints.

use crate::analysis::{AnalysisOptions, Replay, Which};
use crate::balance::{Balance, Balancing, Spring, SpringSearch};
use crate::design::DesignFile;
use crate::fab::{
    checked_design, fabricate, model_scale, Dims, FabError, Fabrication, HookRefusal, PrintSettings, SpringEnds,
};
use crate::scene::Problem;
use crate::statics::{driving_torque, Masses, Torque};
use crate::{Cancelled, Observer};

/// A fabrication with hooks for the springs that balance it.
#[derive(Clone, Debug)]
pub struct Hooked {
    /// The parts, with a hook at both ends of each spring of `balance`.
    pub fabrication: Fabrication,
    /// The crank's torque without springs (the parts as printed, or the scene's masses).
    pub torque: Torque,
    /// The springs hooked (none when no extension spring lowers the peak) and the torque with them.
    pub balance: Balance,
}

/// Why a design cannot be fabricated with springs.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum HookedError {
    /// The design cannot be simulated or weighed (why).
    #[error("the springs cannot be chosen: {0}")]
    Statics(String),
    /// The design cannot be fabricated, or a spring's anchor has no hook ([`FabError::SpringHook`]).
    #[error(transparent)]
    Fab(#[from] FabError),
    /// The design is fabricated without springs, but no depth ordering leaves room for the hooks of
    /// any choice of springs.
    #[error(
        "no depth ordering leaves room for the springs' hooks: some part passes over a hook along the motion \
         (paper §7.2 with the springs hung beyond the outermost layer); allow both faces with \"faces\": \"both\", \
         or fabricate without the springs"
    )]
    NoRoomForSprings,
    /// The observer asked to stop.
    #[error("the spring search was cancelled")]
    Cancelled,
}

impl From<Cancelled> for HookedError {
    fn from(_: Cancelled) -> HookedError {
        HookedError::Cancelled
    }
}

/// Fabricates `design` (not an alternative) with hooks for the extension springs that balance its
/// parts as printed with `settings` (or the scene's masses): the first of the search's choices whose
/// hooks fit. A design no spring helps is fabricated without hooks.
pub fn fabricate_with_springs(
    problem: &Problem,
    design: &DesignFile,
    settings: &PrintSettings,
    observer: &dyn Observer,
) -> Result<Hooked, HookedError> {
    // The model is printed, weighed and sprung at its scale.
    let scale = model_scale(problem, Some(design), settings);
    let mm = problem.units.model_millimetres(scale);
    let masses = Masses::model(settings, &problem.units, scale).map_err(|e| HookedError::Statics(e.to_string()))?;
    // The design is checked once, and must fabricate without springs: an ordering that fails with
    // them then fails for their hooks.
    let (fab_mechanism, travel) = checked_design(problem, design)?;
    let fabricated = |ends: &[SpringEnds]| fabricate(problem, scale, &fab_mechanism, travel, settings, ends);
    let plain = fabricated(&[])?;
    let replay = Replay::new(problem, design, Which::Best, AnalysisOptions::default().steps)
        .map_err(|e| HookedError::Statics(e.to_string()))?;
    let (mechanism, plan, trace) = (&replay.mechanism, &replay.plan, &replay.trace);
    let torque =
        driving_torque(problem, mechanism, plan, trace, &masses).map_err(|e| HookedError::Statics(e.to_string()))?;
    let balancing = Balancing { problem, mechanism, plan, trace, masses: &masses, torque: &torque };
    // The search anywhere first (a link's anchor beside a joint only fails its own try), then, when
    // that refused some, with anchors on links clear of their joints.
    let clear = SpringSearch::hooked(&Dims::new(settings, mm), 2);
    let anywhere = SpringSearch { clear_of_joints: 0.0, ..clear };
    let mut refused = None;
    for search in [anywhere, clear] {
        let mut beside_joint = false;
        let choices = balancing.choices(search, observer)?;
        for balance in choices {
            // Each try is a fabrication, which cannot stop midway: the search stops between them.
            if observer.cancelled() {
                return Err(HookedError::Cancelled);
            }
            let ends: Vec<_> = balance
                .springs
                .iter()
                .filter_map(|s| match s {
                    Spring::Extension { anchors, .. } => Some(anchors.clone()),
                    Spring::Torsion { .. } => None,
                })
                .collect();
            // The last refusal is told.
            match fabricated(&ends) {
                Ok(fabrication) => return Ok(Hooked { fabrication, torque, balance }),
                Err(FabError::NoOrdering | FabError::OrderingTimedOut) => refused = Some(HookedError::NoRoomForSprings),
                Err(e @ FabError::SpringHook { why, .. }) => {
                    beside_joint |= why == HookRefusal::BesideJoint;
                    refused = Some(e.into());
                }
                Err(e) => return Err(e.into()),
            }
        }
        if !beside_joint {
            break;
        }
    }
    match refused {
        Some(e) => Err(e),
        // No spring lowers the peak: the parts without hooks.
        None => Ok(Hooked { fabrication: plain, balance: Balance::none(&torque), torque }),
    }
}

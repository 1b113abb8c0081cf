//! A design's motion for fabrication: the crank's travel and the joints at every degree of it.

use super::error::FabError;
use crate::kinematics::{Plan, Trace};
use crate::mechanism::Mechanism;

/// The crank's travel of a design, radians.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Travel {
    /// The driver's angle at the first pose.
    pub start: f64,
    /// The driver's angle at the last pose.
    pub end: f64,
}

/// The motion at crank steps of at most 1° (the paper's simulation step). A travel of more than a
/// full turn (one a closed path takes) is refused before anything is allocated for it (the limit
/// [`crate::DesignFile::validate`] applies).
pub fn motion_trace(mechanism: &Mechanism, travel: Travel) -> Result<Trace, FabError> {
    let turn = crate::design::MAX_TRAVEL_DEG.to_radians();
    if !(travel.start.is_finite() && travel.end.is_finite() && (travel.end - travel.start).abs() <= turn + 1e-9) {
        return Err(FabError::Motion(format!(
            "the crank's travel from {:.1}° to {:.1}° must be finite and at most a full turn",
            travel.start.to_degrees(),
            travel.end.to_degrees()
        )));
    }
    let plan = Plan::compile(mechanism).map_err(|e| FabError::Motion(e.to_string()))?;
    let mut trace = Trace::new(plan.joint_count());
    trace.sweep(&plan, travel.start, travel.end, 1f64.to_radians()).map_err(|e| FabError::Motion(e.to_string()))?;
    Ok(trace)
}

//! Kinematics: a plan of dyad steps compiled once per dimensioned mechanism, then evaluated per crank
//! angle without allocating. The branch of every dyad is read off the first pose and kept, so a
//! motion is tracked by continuity as long as no dyad passes through a singular configuration (which
//! the transmission-angle bound of the engine excludes).

mod complete;
mod dyad;
mod plan;
mod trace;

pub use complete::{complete, complete_turning, completion_order, Completion};
pub use dyad::{circle_circle, circle_circle_branch, Branch, DyadError};
pub(crate) use dyad::{circle_line, transmission_sine};
pub use plan::{carried_velocity, CompileError, Plan, Step};
pub use trace::{BodyFrames, SweepError, Trace};

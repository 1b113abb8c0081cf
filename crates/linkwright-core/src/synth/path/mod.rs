//! Path synthesis: a linkage whose tracer point, carried by a moving body, follows a drawn curve.

mod curve;
mod four_bar;
mod search;

pub(crate) use curve::path_error;
pub use curve::PathError;
pub(crate) use four_bar::FourBar;
pub(crate) use search::{fit_four_bars, PathFit, PathGoal};

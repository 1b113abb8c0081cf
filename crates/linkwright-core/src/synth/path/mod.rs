//! Path synthesis: a linkage whose tracer point, carried by a moving body, follows a drawn curve.

mod design;
mod four_bar;
mod linkage;
mod search;
mod slider_crank;
mod stephenson;

pub(crate) use design::{path_designs, Accepts};

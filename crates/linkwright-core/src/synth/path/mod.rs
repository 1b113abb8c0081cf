//! Path synthesis: a linkage whose tracer point, carried by a moving body, follows a drawn curve.

mod design;
mod four_bar;
mod linkage;
mod search;
mod six_bars;
mod slider_crank;

pub(crate) use design::{path_designs, Accepts};

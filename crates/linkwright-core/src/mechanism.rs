//! Linkage topologies as one generic model: named revolute joints, rigid parts that carry them, a
//! driver link turning about a fixed pivot, and optionally a prismatic slider on a fixed line.
//!
//! The chain of paper §4.2 is generated from K (the number of moving bodies), never written per K:
//! the ground carries `q0, r0`; body k carries `p_k, q_k` and, except the last, `r_k`; the crank joins
//! `q0–p1`; ternary link k joins `r_{k−1}, q_k, p_{k+1}` (k = 1..K−1); the last binary link joins
//! `r_{K−1}–q_K`. Loop k is the four-bar `q_{k−1} r_{k−1} q_k p_k`. K = 1 is the 4R four-bar, K = 2 the
//! Watt-I six-bar. The slider-crank (K = 1) has the ground pivot `q0`, the crank `q0–p1`, and the body
//! carries `p1` and the slider joint `q1`, which runs on a fixed line. The Watt-II six-bar
//! ([`Topology::watt_two`]) drives that four-bar through a second one.
//!
//! Each family of linkages ([`Family`]) builds its topology and says how it is named, how many poses
//! it can meet exactly and which loops describe it.

mod dimensioned;
mod family;
mod topology;

pub use crate::scene::MechanismType;
pub use dimensioned::{Mechanism, SliderLine};
pub(crate) use family::CENTRE_SPACING;
pub use family::{Family, Loop};
pub use topology::{Part, PartKind, Topology};

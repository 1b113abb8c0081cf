//! Why a full-size build cannot be planned; every message says what to change.

use super::standards::BoltSize;
use crate::fab::{FabError, SettingsIssue};

/// Why a design cannot be planned for the workshop.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum WorkshopError {
    /// The workshop settings cannot work (every issue, each naming its field).
    #[error("workshop settings: {}", .0.iter().map(|i| i.to_string()).collect::<Vec<_>>().join("; "))]
    Settings(Vec<SettingsIssue>),
    /// The design cannot be read against its scene, or fails its check (the reason in words).
    #[error("{0}")]
    Design(FabError),
    /// No layering of the links keeps them from rubbing along the motion, with the workshop's sizes.
    #[error(
        "no layering of the links and brackets keeps them apart along the motion with {width_mm:.0} mm wide parts \
         and {bolt} bolts ({why}); choose another design (an alternative) or a smaller safety factor"
    )]
    Layers {
        /// The widest part the layering was run with, mm.
        width_mm: f64,
        /// The bolt size.
        bolt: BoltSize,
        /// What the layering said.
        why: String,
    },
    /// Two joints of a link are too close for two bolts with their washers side by side.
    #[error(
        "joints {a} and {b} of {link} are {apart_mm:.0} mm apart, closer than the {need_mm:.0} mm two {bolt} bolts \
         need in parts {width_mm:.0} mm wide: choose a larger design, or a smaller bolt (settings \"bolt\")"
    )]
    JointsTooClose {
        /// The link's name.
        link: String,
        /// One joint.
        a: String,
        /// The other joint.
        b: String,
        /// How far apart they are, mm.
        apart_mm: f64,
        /// How far apart they must be, mm.
        need_mm: f64,
        /// The parts' width, mm.
        width_mm: f64,
        /// The bolt size.
        bolt: BoltSize,
    },
    /// The linkage locks (a dead point) at some crank angle of the travel: no force holds it there.
    #[error("the linkage passes a dead point at crank {crank_deg:.1}°, where its links cannot hold the load")]
    DeadPoint {
        /// The crank angle, degrees.
        crank_deg: f64,
    },
    /// The topology is not one whose forces follow from equilibrium alone (as many constraints as
    /// joint coordinates), which every family of this version is.
    #[error("the linkage's forces cannot be found from equilibrium alone: {0}")]
    Indeterminate(String),
    /// The bolt size the settings ask for is too weak somewhere.
    #[error(
        "{bolt} bolts are too weak at {at}: {why}; use {} (settings \"bolt\"), or leave \"bolt\" out to have it chosen",
        needed.map_or("a larger bolt".to_string(), |b| b.to_string())
    )]
    BoltTooWeak {
        /// The bolt size asked for.
        bolt: BoltSize,
        /// Where: a joint's name.
        at: String,
        /// What is short, with the numbers.
        why: String,
        /// The smallest size that holds, if any.
        needed: Option<BoltSize>,
    },
    /// Even the largest bolt is too weak in shear somewhere.
    #[error(
        "no bolt up to M24 holds {at}: it takes {shear_n:.0} N in shear; the object is too heavy for bolted \
         pivots of this design (lighten the moving parts or choose a design with shorter links)"
    )]
    NoBoltStrongEnough {
        /// Where: a joint's name, or a bracket's fixing.
        at: String,
        /// The peak shear force there, N.
        shear_n: f64,
    },
}

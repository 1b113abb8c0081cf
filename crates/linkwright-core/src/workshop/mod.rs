//! The full-size build (`full:plywood`, `full:aluminium`, `full:steel`): what a workshop needs to make
//! a design at its real size, from the loads the parts' weights put on every link.
//!
//! [`plan`] turns a design into a [`Workshop`]: every link's pivot-to-pivot lengths, its width and
//! stock thickness from a strength rule, the bolt size and its ISO 273 clearance holes, the layer
//! stack (which link lies in which plane, with washers and spacers between), a cut list, a bill of
//! materials and the assembly steps. [`files`] writes it as bytes: `workshop.json`, the profiles of
//! every part per stock thickness (DXF and SVG, full size in millimetres), the assembly sheet and two
//! CSV tables. Nothing here does I/O.
//!
//! The stages, one file each under `src/workshop/`:
//! - `settings.rs`: [`WorkshopSettings`] (bolt size, safety factor, bodies' thickness, springs to
//!   buy), read from JSON and validated field by field;
//! - `standards.rs`: the standard parts ([`BoltSize`], [`BoltSpec`]: ISO 273 holes, ISO 898-1 stress
//!   areas, ISO 4014 heads, ISO 7089 washers, ISO 10511 nuts) and the materials' design values
//!   ([`MaterialValues`]) with their sources;
//! - `forces.rs`: the loads along the motion ([`equilibrium`]): every link's axial force and every
//!   joint's pin forces, by virtual work with the crank held;
//! - `sizing.rs`: the strength rule: a section's width and stock thickness from its loads
//!   ([`Check`] records each inequality with its demand and capacity);
//! - `pipeline.rs`: [`plan`] itself: the masses, sizing until the link weights settle, the layer
//!   ordering of fabrication (`crate::fab`) run with the workshop's sizes, brackets and the stack;
//! - `stack.rs`: each joint's bolt, washers and spacers from the layers; `outline.rs`: exact part
//!   outlines (lines and arcs) and their DXF and SVG; `sheet.rs`: the assembly sheet; `report.rs`:
//!   the [`Workshop`] types and [`files`].
//!
//! Conventions: every length in the outputs is millimetres, forces newtons, moments newton-metres;
//! a compressive axial force is positive. The loads are the drawn moving parts' weights (and the
//! links' own), quasi-static, with the linkage held at its crank, as [`crate::statics`] takes them.

mod error;
mod files;
mod forces;
mod outline;
mod pipeline;
mod report;
mod settings;
mod sheet;
mod sizing;
mod stack;
mod standards;

pub use error::WorkshopError;
pub use files::files;
pub use forces::{equilibrium, EdgeForce, PinForce, RowForces};
pub use outline::{Hole, Outline};
pub use pipeline::plan;
pub use report::{
    BomItem, CutItem, JointPlan, LayerPlan, LinkKind, LinkLoads, LinkPlan, PartMass, PivotLength, StackItem, Workshop,
    WORKSHOP_FORMAT,
};
pub use settings::{SpringOrder, WorkshopSettings};
pub use sizing::Check;
pub use standards::{
    BoltSize, BoltSpec, MaterialValues, BOLT_GRADE_ULTIMATE_MPA, BOLT_GRADE_YIELD_MPA, BOLT_LENGTHS_MM,
    BOLT_SHEAR_FRACTION,
};

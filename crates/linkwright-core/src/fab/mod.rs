//! Fabrication (paper §7): from a design to parts that print, snap together and move without rubbing.
//!
//! [`fabricate_design`] turns a design file into a [`Fabrication`] ([`fabricate_design_or_alternative`]
//! falls back on one of its alternatives when the design itself cannot be made); [`bundle`] turns a
//! fabrication into the files to print and its [`Report`] (`fabrication.json`); [`check`] runs the
//! checks every fabrication must pass. [`FeasibilityCheck`] is the fast printability test the
//! synthesis runs on its candidates when asked for printable designs ([`crate::Options::printable`]).
//!
//! The stages, one file each under `src/fab/`:
//! - `pipeline.rs`: the pipeline, from a design to its [`Fabrication`] (`fabrication.rs`), each stage
//!   below in turn; `error.rs`: why it fails ([`FabError`]); `feasibility.rs`: [`FeasibilityCheck`];
//!   `build.rs`: the model's scale ([`BuildPlan`]);
//! - `settings.rs`: [`PrintSettings`] in millimetres (defaults for a desktop FDM printer) and the sizes
//!   derived from them in scene units ([`Dims`]);
//! - `layout.rs`: joint connectors (§7.1): which [`Member`]s exist (with the frame of a scene without a
//!   fixed body), what carries each ([`Layout`]); `posts.rs`: where their posts stand (inside the body,
//!   on the middle line of a thin one, or on a [`Pad`] fused to the side of one too thin);
//! - `depth.rs`: collisions recorded along the motion ([`Recorded`]) and the depth [`Ordering`] solved by
//!   a constraint solver (§7.2, eq. 16–19), minimising layers;
//! - `solid.rs`, `parts.rs`: closed [`Mesh`]es of every [`Part`] (§7.3, eq. 20);
//! - `export.rs`: binary STL, 3MF, SVG and DXF profiles; `plates.rs`: parts spread on print beds (and
//!   what a part too large for the bed would need, [`Misfit`]); `split.rs`: bodies too large cut by
//!   dovetails; `sheet.rs`: the assembly sheet; `report.rs`: `fabrication.json`; `check.rs`: the checks
//!   every fabrication must pass (closed meshes, posts on their parts, no part crossing another along
//!   the motion, pins seated); `names.rs`: the parts' file names; `bundle.rs`: the files to print.
//!
//! Conventions: the bodies are extruded from `z = -body_thickness` to `z = 0` (the front face); layer
//! k on the front face spans `layer_bottom(k)..layer_top(k)`, and the back face mirrors it. Geometry is
//! built in scene units; exporters write millimetres. Nothing here does I/O: exporters return bytes.

mod build;
mod bundle;
mod check;
mod depth;
mod error;
mod export;
mod fabrication;
mod feasibility;
mod layout;
mod names;
mod parts;
mod pipeline;
mod plates;
mod posts;
mod report;
mod settings;
mod shapes;
mod sheet;
mod solid;
mod split;
mod travel;

pub use build::{model_scale, BuildPlan, SizeNote, AUTO_RETRIES, PIN_SPACINGS_PER_REGION};
pub use bundle::{assembled_meshes, bundle, Bundle, FIXED_FILES};
pub use check::{check, CheckReport};
pub use depth::{violations as ordering_violations, Constraint, Face, Ordering, PillarRef, Recorded};
pub use error::{FabError, HookRefusal};
pub use fabrication::{Fabrication, Timings};
pub use feasibility::FeasibilityCheck;
pub use layout::{Anchor, BodyPin, Carrier, Hook, HookBase, Layout, Member, MemberKind, Slot, SpringEnds};
pub use names::{is_safe_relative_path, sanitize};
pub use parts::{Heights, HoleSeat, Part, PinSeat, Prism, Role, SlotSeat};
pub(crate) use pipeline::checked_design;
pub use pipeline::{
    fabricate, fabricate_design, fabricate_design_or_alternative, fabricate_design_with_springs, Chosen,
};
pub use plates::Misfit;
pub use posts::Pad;
pub use report::{
    ConstraintReport, HookReport, Layers, Oversized, PartReport, PlateReport, Report, SpringReport, Totals,
    FABRICATION_FORMAT,
};
pub use settings::{Bed, Dims, Faces, PrintSettings, SettingsIssue, SnapCap};
pub use sheet::steps as assembly_steps;
pub use solid::Mesh;
pub use travel::{motion_trace, Travel};

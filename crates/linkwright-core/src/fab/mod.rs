//! Fabrication (paper §7): from a design to parts that print, snap together and move without rubbing.
//!
//! The stages, each a module:
//! - [`settings`]: print settings in millimetres (defaults for a desktop FDM printer) and the derived
//!   sizes in scene units;
//! - [`layout`]: joint connectors (§7.1): which members exist, what carries each, where posts stand;
//! - [`depth`]: collisions recorded along the motion and the depth ordering solved by a constraint
//!   solver (§7.2, eq. 16–19), minimising layers; [`ordering_feasible`] is the fast check the
//!   synthesis can run per candidate;
//! - [`solid`], [`parts`]: closed meshes of every part (§7.3, eq. 20);
//! - [`export`]: binary STL, 3MF, SVG and DXF profiles; [`plates`]: parts spread on print beds;
//!   [`sheet`]: the assembly sheet; [`report`]: `fabrication.json`; [`check`]: the checks every
//!   fabrication must pass (closed meshes, no part crossing another along the motion, pins seated).
//!
//! Conventions: the bodies are extruded from `z = -body_thickness` to `z = 0` (the front face); layer
//! k on the front face spans `layer_bottom(k)..layer_top(k)`, and the back face mirrors it. Geometry is
//! built in scene units; exporters write millimetres. Nothing here does I/O: exporters return bytes.

pub mod bundle;
pub mod check;
pub mod depth;
pub mod export;
pub mod layout;
pub mod parts;
pub mod plates;
pub mod report;
pub mod settings;
pub mod shapes;
pub mod sheet;
pub mod solid;
pub mod split;

use crate::geom::Point;
use crate::kinematics::{Plan, Trace};
use crate::mechanism::Mechanism;
use crate::scene::Problem;
pub use depth::{Constraint, Face, Ordering, Recorded};
pub use layout::{Layout, SceneShapes};
pub use parts::{Part, PinSeat, Role};
pub use settings::{millimetres_per_unit, Dims, Faces, PrintSettings};
use std::time::Instant;

/// Why a design cannot be fabricated; every message says what to change.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum FabError {
    #[error("print settings: {0}")]
    Settings(String),
    #[error("the scene's units \"{0}\" are not known; use mm, cm, m, in or ft")]
    Units(String),
    #[error("the design does not match the scene: {0}")]
    Mismatch(String),
    #[error("the scene has no fixed body to hold the ground joints; draw one")]
    NoGround,
    #[error(
        "no room for the connector post of joint {joint} on {body}: the body is too thin for a post with \
         the print settings (make the body larger or connector_post smaller)"
    )]
    NoRoomForPost { joint: String, body: String },
    #[error(
        "no depth ordering of the links and connectors avoids every collision along the motion (paper \
         §7.2); choose another design (an alternative) or allow both faces with \"faces\": \"both\""
    )]
    NoOrdering,
    #[error("the depth-ordering solver ran out of time; try again or allow both faces")]
    OrderingTimedOut,
    #[error(
        "{body} is too thin for a connector post, and a pad fused to it would enter another body at crank {at_deg:.1}°"
    )]
    PadCollides { body: String, at_deg: f64 },
    #[error(
        "joints {a} and {b} of {link} are closer than the {need_mm:.1} mm two pins need with these print settings: \
         the linkage is too small to print (choose a larger design, or narrower links and pins)"
    )]
    JointsTooClose { link: String, a: String, b: String, need_mm: f64 },
    #[error("cannot build a part's solid: {0}")]
    Mesh(String),
    #[error("the design's motion cannot be simulated: {0}")]
    Motion(String),
}

/// Seconds spent in each stage.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize)]
pub struct Timings {
    /// Connectors and recording the constraints along the motion.
    pub recording: f64,
    /// The constraint solver (all its calls).
    pub ordering: f64,
    /// Building every part's mesh.
    pub meshing: f64,
}

/// Everything fabricated for one design.
#[derive(Clone, Debug)]
pub struct Fabrication {
    pub scene_name: String,
    /// The mechanism's joint names, by index.
    pub joint_names: Vec<String>,
    pub settings: PrintSettings,
    pub dims: Dims,
    pub layout: Layout,
    pub recorded: Recorded,
    pub ordering: Ordering,
    pub parts: Vec<Part>,
    pub seats: Vec<PinSeat>,
    /// The motion at crank steps of at most 1°, from the first pose to the last.
    pub trace: Trace,
    pub timings: Timings,
}

/// The crank's travel of a design, radians.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Travel {
    pub start: f64,
    pub end: f64,
}

/// The motion at crank steps of at most 1° (the paper's simulation step).
pub fn motion_trace(mechanism: &Mechanism, travel: Travel) -> Result<Trace, FabError> {
    let plan = Plan::compile(mechanism).map_err(|e| FabError::Motion(e.to_string()))?;
    let mut trace = Trace::new(plan.joint_count());
    trace.sweep(&plan, travel.start, travel.end, 1f64.to_radians()).map_err(|e| FabError::Motion(e.to_string()))?;
    Ok(trace)
}

/// Fabricates `mechanism` moving through `travel` in the scene of `problem`, drawn in units of
/// `mm_per_unit` millimetres.
pub fn fabricate(
    problem: &Problem,
    mm_per_unit: f64,
    mechanism: &Mechanism,
    travel: Travel,
    settings: &PrintSettings,
) -> Result<Fabrication, FabError> {
    let issues = settings.validate();
    if !issues.is_empty() {
        return Err(FabError::Settings(issues.iter().map(|i| i.to_string()).collect::<Vec<_>>().join("; ")));
    }
    if !(mm_per_unit.is_finite() && mm_per_unit > 0.0) {
        return Err(FabError::Units(mm_per_unit.to_string()));
    }
    let dims = Dims::new(settings, mm_per_unit);
    let trace = motion_trace(mechanism, travel)?;
    let shapes = SceneShapes::new(problem, dims);
    let (mut recording, mut ordering_s) = (0.0, 0.0);
    let mut found = None;
    let mut first_error = None;
    for (body_pins, faces) in strategies(settings.faces) {
        let t0 = Instant::now();
        let attempt = Layout::new(&shapes, mechanism, &trace, body_pins).map(|l| {
            let r = depth::record(&l, &trace);
            (l, r)
        });
        recording += t0.elapsed().as_secs_f64();
        let (layout, recorded) = match attempt {
            Ok(x) => x,
            Err(e) => {
                first_error.get_or_insert(e);
                continue;
            }
        };
        let t1 = Instant::now();
        let solved = depth::solve(&layout, &recorded, faces, 20.0);
        ordering_s += t1.elapsed().as_secs_f64();
        match solved {
            Ok(o) => {
                found = Some((layout, recorded, o));
                break;
            }
            Err(e) => {
                first_error.get_or_insert(e.into());
            }
        }
    }
    let Some((layout, recorded, ordering)) = found else {
        return Err(first_error.unwrap_or(FabError::NoOrdering));
    };
    let t2 = Instant::now();
    let body_names = body_names(problem);
    let (parts, seats) = parts::build(&shapes, &layout, &ordering, &body_names, &settings.bed)?;
    let t3 = Instant::now();
    Ok(Fabrication {
        scene_name: problem.name.clone(),
        joint_names: mechanism.topology.joint_names.clone(),
        settings: settings.clone(),
        dims,
        layout,
        recorded,
        ordering,
        parts,
        seats,
        trace,
        timings: Timings { recording, ordering: ordering_s, meshing: (t3 - t2).as_secs_f64() },
    })
}

/// The attempts, in order of preference: (fuse pins to bodies where they fit?, faces allowed). One
/// face before two, and on each, pins fused to the bodies (fewer parts) before connectors everywhere
/// (the paper's way, which leaves the ordering more freedom).
fn strategies(faces: Faces) -> Vec<(bool, Faces)> {
    match faces {
        Faces::One => vec![(true, Faces::One), (false, Faces::One)],
        Faces::Both => vec![(true, Faces::Both), (false, Faces::Both)],
        Faces::Auto => vec![(true, Faces::One), (false, Faces::One), (true, Faces::Both), (false, Faces::Both)],
    }
}

/// Fabricates the mechanism of a design file for its scene (`units` is the scene's `units` field).
pub fn fabricate_design(
    problem: &Problem,
    units: &str,
    design: &crate::design::DesignFile,
    settings: &PrintSettings,
) -> Result<Fabrication, FabError> {
    let mm = millimetres_per_unit(units).ok_or_else(|| FabError::Units(units.to_string()))?;
    let (Some(mj), Some(motion)) = (&design.mechanism, &design.motion) else {
        return Err(FabError::Mismatch("the design has no mechanism (status no_solution)".into()));
    };
    let mechanism = mj.to_mechanism().map_err(|e| FabError::Mismatch(e.to_string()))?;
    let travel = Travel { start: motion.crank_start_deg.to_radians(), end: motion.crank_end_deg.to_radians() };
    fabricate(problem, mm, &mechanism, travel, settings)
}

/// Fabricates the design's mechanism, or when it cannot be fabricated (no ordering, no room for a
/// post, links too short to print), the first of its alternatives that can. Returns which one was
/// used (0 the design itself, k the k-th alternative) and the first design's error when none can.
pub fn fabricate_design_or_alternative(
    problem: &Problem,
    units: &str,
    design: &crate::design::DesignFile,
    settings: &PrintSettings,
) -> Result<(usize, Fabrication), FabError> {
    let first = match fabricate_design(problem, units, design, settings) {
        Ok(f) => return Ok((0, f)),
        Err(e @ (FabError::Settings(_) | FabError::Units(_))) => return Err(e),
        Err(e) => e,
    };
    for (k, alt) in design.alternatives.iter().enumerate() {
        let view = crate::design::DesignFile {
            mechanism: Some(alt.mechanism.clone()),
            motion: Some(alt.motion.clone()),
            metrics: Some(alt.metrics.clone()),
            alternatives: Vec::new(),
            ..design.clone()
        };
        if let Ok(f) = fabricate_design(problem, units, &view, settings) {
            return Ok((k + 1, f));
        }
    }
    Err(first)
}

/// Unique file-name-safe names of the moving bodies.
fn body_names(problem: &Problem) -> Vec<String> {
    let mut out: Vec<String> = Vec::new();
    for (b, body) in problem.bodies.iter().enumerate() {
        let mut name = sanitize(&body.name);
        if name.is_empty() || name.starts_with("ground") {
            name = format!("body{}", b + 1);
        }
        while out.contains(&name) {
            name.push_str(&format!("_{}", b + 1));
        }
        out.push(name);
    }
    out
}

/// Lower-case letters, digits, `_` and `-` only.
pub fn sanitize(name: &str) -> String {
    let s: String = name
        .trim()
        .chars()
        .map(|c| if c.is_ascii_alphanumeric() || c == '-' { c.to_ascii_lowercase() } else { '_' })
        .collect();
    s.trim_matches('_').to_string()
}

/// A reusable depth-ordering feasibility check for one scene (paper §7.2: candidates without an
/// ordering are rejected). Build it once per problem; [`FeasibilityCheck::check`] then places the
/// connectors (testing candidate post places against the links' sweep), records the constraints over
/// the trace's rows (about `rows × members²` distances between cores of at most three points) and asks
/// the solver for any ordering, with pins fused to bodies and then with connectors everywhere. Measured
/// on the bundled examples: 1–3 ms per candidate (placing 0.5–2 ms, recording 0.2–0.5 ms, solving
/// 0.1–0.4 ms), so run it after the collision check (see `docs/fabrication.md`).
#[derive(Clone, Debug)]
pub struct FeasibilityCheck {
    shapes: SceneShapes,
    faces: Faces,
}

impl FeasibilityCheck {
    /// The check with the given settings in a scene of `mm_per_unit` millimetres per unit.
    pub fn new(problem: &Problem, settings: &PrintSettings, mm_per_unit: f64) -> FeasibilityCheck {
        FeasibilityCheck { shapes: SceneShapes::new(problem, Dims::new(settings, mm_per_unit)), faces: settings.faces }
    }
    /// The least distance between two joints of one link, in scene units (pins need room).
    pub fn min_joint_spacing(&self) -> f64 {
        self.shapes.dims.min_joint_spacing()
    }
    /// True when `mechanism`, moving along `trace` (rows of joint positions at crank steps of at most
    /// 1°, as [`crate::synth::Candidate::trace`]), has connectors that fit and a depth ordering.
    pub fn check(&self, mechanism: &Mechanism, trace: &Trace) -> bool {
        // Both faces allowed is a relaxation of one face, so it alone decides feasibility for `auto`.
        let faces = if self.faces == Faces::One { Faces::One } else { Faces::Both };
        [(true, faces), (false, faces)].into_iter().any(|(body_pins, faces)| {
            let Ok(layout) = Layout::new(&self.shapes, mechanism, trace, body_pins) else { return false };
            let recorded = depth::record(&layout, trace);
            depth::feasible(&layout, &recorded, faces, 0.05)
        })
    }
}

/// [`FeasibilityCheck::check`] with the default print settings in a millimetre scene, building the
/// scene's shapes each call (a union of the fixed bodies, tens of microseconds): prefer a
/// [`FeasibilityCheck`] kept for the whole synthesis.
pub fn ordering_feasible(problem: &Problem, mechanism: &Mechanism, trace: &Trace) -> bool {
    FeasibilityCheck::new(problem, &PrintSettings::default(), 1.0).check(mechanism, trace)
}

/// The world position of a point carried by `carrier` in the configuration of trace row `r`.
pub fn carried(layout: &Layout, trace: &Trace, r: usize, carrier: usize, p: Point) -> Point {
    let mut poses = Vec::new();
    layout.carrier_poses(trace.row(r), &mut poses);
    poses[carrier].apply(p)
}

//! Fabrication (paper §7): from a design to parts that print, snap together and move without rubbing.
//!
//! [`fabricate_design`] turns a design file into a [`Fabrication`] ([`fabricate_design_or_alternative`]
//! falls back on one of its alternatives when the design itself cannot be made); [`bundle`] turns a
//! fabrication into the files to print and its [`Report`] (`fabrication.json`); [`check`] runs the
//! checks every fabrication must pass. [`FeasibilityCheck`] is the fast printability test the
//! synthesis runs on its candidates when asked for printable designs ([`crate::Options::printable`]).
//!
//! The stages, one file each under `src/fab/`:
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
//!   the motion, pins seated).
//!
//! Conventions: the bodies are extruded from `z = -body_thickness` to `z = 0` (the front face); layer
//! k on the front face spans `layer_bottom(k)..layer_top(k)`, and the back face mirrors it. Geometry is
//! built in scene units; exporters write millimetres. Nothing here does I/O: exporters return bytes.

mod build;
mod bundle;
mod check;
mod depth;
mod export;
mod layout;
mod names;
mod parts;
mod plates;
mod posts;
mod report;
mod settings;
mod shapes;
mod sheet;
mod solid;
mod split;

use crate::kinematics::{Plan, Trace};
use crate::mechanism::Mechanism;
use crate::scene::Problem;
use posts::SceneShapes;

pub use build::{model_scale, BuildPlan, SizeNote, AUTO_RETRIES, PIN_SPACINGS_PER_REGION};
pub use bundle::{assembled_meshes, bundle, Bundle, FIXED_FILES};
pub use check::{check, CheckReport};
pub use depth::{violations as ordering_violations, Constraint, Face, Ordering, PillarRef, Recorded};
pub use layout::{Anchor, BodyPin, Carrier, Hook, HookBase, HookRefusal, Layout, Member, MemberKind, Slot, SpringEnds};
pub use names::is_safe_relative_path;
pub use parts::{Heights, HoleSeat, Part, PinSeat, Prism, Role, SlotSeat};
pub use plates::Misfit;
pub use posts::Pad;
pub use report::{
    ConstraintReport, HookReport, Layers, Oversized, PartReport, PlateReport, Report, SpringReport, Totals,
    FABRICATION_FORMAT,
};
pub use settings::{millimetres_per_unit, Bed, Dims, Faces, PrintSettings, SettingsIssue, SnapCap};
pub use sheet::steps as assembly_steps;
pub use solid::Mesh;
use std::time::Instant;

/// Why a design cannot be fabricated; every message says what to change.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum FabError {
    /// The print settings cannot work (every issue, in words).
    #[error("print settings: {0}")]
    Settings(String),
    /// The scene's `units` (given) is not a unit with a known length in millimetres.
    #[error("the scene's units \"{0}\" are not known; use mm, cm, m, in or ft")]
    Units(String),
    /// The design moves other bodies than the scene has (how, in words).
    #[error("the design does not match the scene: {0}")]
    Mismatch(String),
    #[error(
        "no room for the connector post of joint {joint} on {body}: the body is too thin for a post with \
         the print settings (make the body larger or connector_post smaller)"
    )]
    /// No place on a body is deep enough for a connector's post.
    NoRoomForPost {
        /// The joint the connector carries.
        joint: String,
        /// The body's name.
        body: String,
    },
    #[error(
        "no depth ordering of the links and connectors avoids every collision along the motion (paper \
         §7.2); choose another design (an alternative) or allow both faces with \"faces\": \"both\""
    )]
    /// No depth ordering satisfies every constraint recorded along the motion.
    NoOrdering,
    /// The depth-ordering solver ran out of its time budget.
    #[error("the depth-ordering solver ran out of time; try again or allow both faces")]
    OrderingTimedOut,
    #[error(
        "{body} is too thin for the connector post of joint {joint}, and every pad fused to its side near the \
         joint would enter another body (first at crank {at_deg:.1}°): draw the body thicker near the joint, \
         or choose another design"
    )]
    /// A body is too thin for a connector's post, and every pad that could carry it would enter
    /// another body along the motion.
    PadCollides {
        /// The joint the connector carries.
        joint: String,
        /// The body's name.
        body: String,
        /// The first crank angle where the pad would enter another body, degrees.
        at_deg: f64,
    },
    #[error(
        "joints {a} and {b} of {link} are closer than the {need_mm:.1} mm two pins need with these print settings: \
         the linkage is too small to print (choose a larger design, or narrower links and pins)"
    )]
    /// Two joints of a link are too close for two pins side by side.
    JointsTooClose {
        /// The link's name.
        link: String,
        /// One joint's name.
        a: String,
        /// The other joint's name.
        b: String,
        /// The least distance the print settings need between them, mm.
        need_mm: f64,
    },
    #[error(
        "{parts} fit the {width:.0} × {depth:.0} mm print area (the bed minus its margins) in no turn: print on a \
         bed of at least {square_bed_mm:.0} mm square (print settings \"bed\"), print a model at most \
         {max_scale:.2} times as large (the scene's build), or choose another design"
    )]
    /// Some links, connectors or the frame fit the print bed in no turn.
    OffBed {
        /// Their names, joined for the message.
        parts: String,
        /// The print area's width (the bed's minus its margins), mm.
        width: f64,
        /// The print area's depth, mm.
        depth: f64,
        /// The smallest square bed on which every one of them fits, mm.
        square_bed_mm: f64,
        /// The largest factor the scene could be scaled by for them to fit this bed.
        max_scale: f64,
    },
    /// A part's mesh could not be built, or a file encoded (why, in words).
    #[error("cannot build a part's solid: {0}")]
    Mesh(String),
    /// The linkage comes apart along the design's travel, or the travel is not usable (why).
    #[error("the design's motion cannot be simulated: {0}")]
    Motion(String),
    /// The design file is not valid against its scene ([`crate::DesignFile::validate`]).
    #[error("the design file is not valid: {}", joined_list(.0))]
    Invalid(crate::IssueList<crate::design::DesignIssue>),
    #[error(
        "the design fails its check against the scene ({}): fabricate a design that passes the check",
        joined(.0.iter().map(|v| format!("{}: {}", v.constraint, v.message)))
    )]
    /// The design fails its check against the scene ([`crate::DesignFile::violations`]).
    FailsCheck(Vec<crate::verify::Violation>),
    #[error("spring {spring}'s anchor on {part}: {}", hook_words(*.why))]
    /// A spring's anchor has no place for its hook.
    SpringHook {
        /// The spring, counted from 1.
        spring: usize,
        /// The part it is anchored on, as given.
        part: String,
        /// Why.
        why: HookRefusal,
    },
}

fn hook_words(why: HookRefusal) -> &'static str {
    match why {
        HookRefusal::NoSuchPart => "the design has no part of that name",
        HookRefusal::NotFinite => "the point is not a finite number",
        HookRefusal::BesideJoint => {
            "the point is on a link, too close to one of its joints for a hook beside the joint's pin \
             (hook it on the joint itself, or farther along the link)"
        }
        HookRefusal::NoRoom => "the body has no room for the post of a bracket reaching the point",
    }
}

/// Items of a message, one after the other.
fn joined<T: std::fmt::Display>(items: impl IntoIterator<Item = T>) -> String {
    items.into_iter().map(|i| i.to_string()).collect::<Vec<_>>().join("; ")
}

/// The listed problems joined, and how many more there are.
fn joined_list<T: std::fmt::Display>(list: &crate::IssueList<T>) -> String {
    match list.more() {
        0 => joined(list.iter()),
        more => format!("{}; and {more} more", joined(list.iter())),
    }
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
    /// The scene's name.
    pub scene_name: String,
    /// The mechanism's joint names, by index.
    pub joint_names: Vec<String>,
    /// The print settings, millimetres.
    pub settings: PrintSettings,
    /// The print settings in scene units.
    pub dims: Dims,
    /// The model's scale: the parts are the drawing at this scale.
    pub scale: crate::scene::Ratio,
    /// The model's extent, width and height in millimetres: everything drawn at the model's scale.
    pub model_mm: [f64; 2],
    /// The counterbalance springs hooked, as asked for (their hooks are in the layout).
    pub springs: Vec<SpringEnds>,
    /// The printed members and what carries each.
    pub layout: Layout,
    /// The ordering constraints recorded along the motion.
    pub recorded: Recorded,
    /// Every member's face and layer.
    pub ordering: Ordering,
    /// Every printed part, with its meshes.
    pub parts: Vec<Part>,
    /// Every pin and the holes it sits in, for checking.
    pub seats: Vec<PinSeat>,
    /// The motion at crank steps of at most 1°, from the first pose to the last.
    pub trace: Trace,
    /// Seconds spent in each stage.
    pub timings: Timings,
}

/// The crank's travel of a design, radians.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Travel {
    /// The driver's angle at the first pose.
    pub start: f64,
    /// The driver's angle at the last pose.
    pub end: f64,
}

/// The motion at crank steps of at most 1° (the paper's simulation step). A travel of a full turn or
/// more is refused before anything is allocated for it (the limit [`crate::DesignFile::validate`]
/// applies).
pub fn motion_trace(mechanism: &Mechanism, travel: Travel) -> Result<Trace, FabError> {
    let turn = crate::design::MAX_TRAVEL_DEG.to_radians();
    if !(travel.start.is_finite() && travel.end.is_finite() && (travel.end - travel.start).abs() < turn) {
        return Err(FabError::Motion(format!(
            "the crank's travel from {:.1}° to {:.1}° must be finite and less than a full turn",
            travel.start.to_degrees(),
            travel.end.to_degrees()
        )));
    }
    let plan = Plan::compile(mechanism).map_err(|e| FabError::Motion(e.to_string()))?;
    let mut trace = Trace::new(plan.joint_count());
    trace.sweep(&plan, travel.start, travel.end, 1f64.to_radians()).map_err(|e| FabError::Motion(e.to_string()))?;
    Ok(trace)
}

/// Fabricates `mechanism` moving through `travel` in the scene of `problem`, drawn in units of
/// `mm_per_unit` millimetres, with a hook at both ends of each of `springs` (the counterbalance
/// springs of [`crate::balance`], for instance).
pub fn fabricate(
    problem: &Problem,
    mm_per_unit: f64,
    mechanism: &Mechanism,
    travel: Travel,
    settings: &PrintSettings,
    springs: &[SpringEnds],
) -> Result<Fabrication, FabError> {
    let issues = settings.validate_any_build();
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
    // The first attempt with an ordering whose members all fit the bed; else the first with an ordering.
    let mut found = None;
    let mut off_bed = None;
    let mut first_error = None;
    // Each layout (with pins fused to the bodies, without) is built and recorded once.
    let mut built: [Option<Result<(Layout, Recorded), FabError>>; 2] = [None, None];
    for (body_pins, faces) in strategies(settings.faces) {
        let k = usize::from(!body_pins);
        // With no pin fused to a body, the layout without them is the same one: nothing new to try.
        if let (false, Some(Ok((with_pins, _)))) = (body_pins, &built[0]) {
            if with_pins.body_pins.iter().all(Option::is_none) {
                continue;
            }
        }
        let attempt = built[k].get_or_insert_with(|| {
            let t0 = Instant::now();
            let attempt = Layout::new(&shapes, mechanism, &trace, body_pins, springs).map(|l| {
                let r = depth::record(&l, &trace);
                (l, r)
            });
            recording += t0.elapsed().as_secs_f64();
            attempt
        });
        let (layout, recorded) = match attempt {
            Ok(x) => x,
            Err(e) => {
                first_error.get_or_insert(e.clone());
                continue;
            }
        };
        let t1 = Instant::now();
        let solved = depth::solve(layout, recorded, faces, 20.0);
        ordering_s += t1.elapsed().as_secs_f64();
        match solved {
            Ok(o) if layout.off_bed(&settings.bed).is_empty() => {
                found = Some((layout.clone(), recorded.clone(), o));
                break;
            }
            Ok(o) => {
                off_bed.get_or_insert((layout.clone(), recorded.clone(), o));
            }
            Err(e) => {
                first_error.get_or_insert(e.into());
            }
        }
    }
    let Some((layout, recorded, ordering)) = found.or(off_bed) else {
        return Err(first_error.unwrap_or(FabError::NoOrdering));
    };
    let t2 = Instant::now();
    let body_names = body_names(problem);
    let (mut parts, seats) = parts::build(&shapes, &layout, &ordering, &body_names, &settings.bed)?;
    // Link and connector names come from the design file, and every part's name becomes a file name.
    let names = names::file_names(parts.iter().map(|p| p.name.as_str()));
    for (part, name) in parts.iter_mut().zip(names) {
        part.name = name;
    }
    let t3 = Instant::now();
    Ok(Fabrication {
        scene_name: problem.name.clone(),
        springs: springs.to_vec(),
        joint_names: mechanism.topology.joint_names.clone(),
        settings: settings.clone(),
        dims,
        scale: crate::scene::Ratio::ONE,
        model_mm: build::drawn_mm(problem, mm_per_unit),
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

/// Fabricates the mechanism of a design file for its scene (`units` is the scene's `units` field). A
/// design file that is not valid ([`crate::design::DesignFile::validate`]) or fails its check against
/// the scene ([`crate::design::DesignFile::violations`]) is refused before anything is built.
///
/// ```
/// use linkwright_core::fab::{bundle, check, fabricate_design, PrintSettings, Role};
/// use linkwright_core::testbed::{known_scene, Known};
/// use linkwright_core::Problem;
///
/// // A known four-bar in a scene drawn in millimetres, with the default print settings.
/// let known = known_scene(Known::chain(1), 3, 7, 100.0)?;
/// let problem = Problem::new(&known.scene).expect("a valid scene");
/// let fabrication = fabricate_design(&problem, &known.scene.units, &known.design(), &PrintSettings::default())?;
///
/// // Its two links are printed, and every part passes the checks along the whole motion.
/// assert_eq!(fabrication.parts.iter().filter(|p| p.role == Role::Link).count(), 2);
/// assert!(check(&fabrication).ok());
/// // The files to print: one STL per part, among others, and the report.
/// let files = bundle(&fabrication)?;
/// assert!(files.files.iter().any(|(path, _)| path == "fabrication.json"));
/// assert_eq!(files.report.parts.len(), fabrication.parts.len());
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn fabricate_design(
    problem: &Problem,
    units: &str,
    design: &crate::design::DesignFile,
    settings: &PrintSettings,
) -> Result<Fabrication, FabError> {
    fabricate_design_with_springs(problem, units, design, settings, &[])
}

/// [`fabricate_design`] with a hook at both ends of each of `springs`, anchored on the design's parts
/// (not on an alternative's).
pub fn fabricate_design_with_springs(
    problem: &Problem,
    units: &str,
    design: &crate::design::DesignFile,
    settings: &PrintSettings,
    springs: &[SpringEnds],
) -> Result<Fabrication, FabError> {
    let mm = millimetres_per_unit(units).ok_or_else(|| FabError::Units(units.to_string()))?;
    let scale = model_scale(problem, mm, Some(design), settings);
    let (mechanism, travel) = checked_design(problem, design)?;
    let mut fabrication = fabricate(problem, mm * scale.factor(), &mechanism, travel, settings, springs)?;
    fabrication.scale = scale;
    Ok(fabrication)
}

/// The mechanism and travel of a design file that is valid ([`crate::design::DesignFile::validate`])
/// and passes its check against the scene ([`crate::design::DesignFile::violations`]).
pub(crate) fn checked_design(
    problem: &Problem,
    design: &crate::design::DesignFile,
) -> Result<(Mechanism, Travel), FabError> {
    let issues = design.validate(problem);
    if !issues.is_empty() {
        return Err(FabError::Invalid(issues));
    }
    let (Some(mj), Some(motion)) = (&design.mechanism, &design.motion) else {
        return Err(FabError::Mismatch("the design has no mechanism (status no_solution)".into()));
    };
    let violations = design.violations(problem);
    if !violations.is_empty() {
        return Err(FabError::FailsCheck(violations));
    }
    let mechanism = mj.to_mechanism().map_err(|e| FabError::Mismatch(e.to_string()))?;
    let travel = Travel { start: motion.crank_start_deg.to_radians(), end: motion.crank_end_deg.to_radians() };
    Ok((mechanism, travel))
}

/// What [`fabricate_design_or_alternative`] made.
#[derive(Clone, Debug)]
pub struct Chosen {
    /// Which design was fabricated: 0 the design itself, k its k-th alternative (`alternatives[k - 1]`).
    pub used: usize,
    /// What was made of it.
    pub fabrication: Fabrication,
    /// Why the design itself was passed over, when an alternative was used.
    pub passed_over: Option<String>,
}

/// Fabricates the design's mechanism, or when it cannot be fabricated (no ordering, no room for a
/// post, links too short to print) or has links or connectors larger than the bed, the first of its
/// alternatives that can with every member on the bed (and passes its check). Says which one was used
/// and why the design itself was not: the design itself when none is better, and its error when none
/// fabricates. A design file that is not valid or fails its check is refused with no fallback.
pub fn fabricate_design_or_alternative(
    problem: &Problem,
    units: &str,
    design: &crate::design::DesignFile,
    settings: &PrintSettings,
) -> Result<Chosen, FabError> {
    let first = match fabricate_design(problem, units, design, settings) {
        Ok(f) if f.off_bed().is_empty() => return Ok(Chosen { used: 0, fabrication: f, passed_over: None }),
        Err(e @ (FabError::Settings(_) | FabError::Units(_) | FabError::Invalid(_) | FabError::FailsCheck(_))) => {
            return Err(e)
        }
        other => other,
    };
    let passed_over = match &first {
        Ok(f) => {
            let misfits = f.off_bed();
            off_bed_error(&f.layout, &misfits, &f.settings.bed).to_string()
        }
        Err(e) => e.to_string(),
    };
    let chosen =
        |used: usize, fabrication: Fabrication| Chosen { used, fabrication, passed_over: Some(passed_over.clone()) };
    let mut fallback = None;
    for (k, alt) in design.alternatives.iter().enumerate() {
        let view = crate::design::DesignFile {
            mechanism: Some(alt.mechanism.clone()),
            motion: Some(alt.motion.clone()),
            metrics: Some(alt.metrics.clone()),
            alternatives: Vec::new(),
            ..design.clone()
        };
        match fabricate_design(problem, units, &view, settings) {
            Ok(f) if f.off_bed().is_empty() => return Ok(chosen(k + 1, f)),
            Ok(f) if first.is_err() && fallback.is_none() => fallback = Some(chosen(k + 1, f)),
            _ => {}
        }
    }
    match first {
        Ok(f) => Ok(Chosen { used: 0, fabrication: f, passed_over: None }),
        Err(e) => fallback.ok_or(e),
    }
}

impl Fabrication {
    /// The members (links, connectors, the guide, the frame) that fit the print bed in no turn, with
    /// what it would take.
    pub fn off_bed(&self) -> Vec<(usize, plates::Misfit)> {
        self.layout.off_bed(&self.settings.bed)
    }

    /// How far spring `n`'s axis lies beyond the face it hangs on, scene units ([`Dims::spring_axis`]).
    pub fn spring_axis(&self, n: usize) -> f64 {
        let (face, level) = (self.ordering.spring_face[n], self.ordering.spring_level[n]);
        self.dims.spring_axis(self.ordering.layers_on(face), level)
    }

    /// The height of spring `n`'s axis in the parts' frame (z = 0 the bodies' front face), scene units.
    pub fn spring_axis_z(&self, n: usize) -> f64 {
        match self.ordering.spring_face[n] {
            Face::Front => self.spring_axis(n),
            Face::Back => -self.dims.body_thickness - self.spring_axis(n),
        }
    }
}

/// [`FabError::OffBed`] for the members of `layout` in `misfits`.
fn off_bed_error(layout: &Layout, misfits: &[(usize, plates::Misfit)], bed: &settings::Bed) -> FabError {
    let parts: Vec<String> = misfits
        .iter()
        .map(|(i, f)| format!("{} ({:.0} × {:.0} mm)", layout.members[*i].name, f.footprint_mm[0], f.footprint_mm[1]))
        .collect();
    FabError::OffBed {
        parts: parts.join(", "),
        width: bed.width - 2.0 * bed.margin,
        depth: bed.depth - 2.0 * bed.margin,
        square_bed_mm: misfits.iter().map(|m| m.1.square_bed_mm).fold(0.0, f64::max),
        max_scale: misfits.iter().map(|m| m.1.max_scale).fold(f64::INFINITY, f64::min),
    }
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

/// A reusable printability check for one scene (paper §7.2: candidates without an ordering are
/// rejected). Build it once per problem; [`FeasibilityCheck::check`] then simulates the motion at the
/// steps fabrication takes, places the connectors (testing candidate post places against the links'
/// sweep, and pads against the other bodies on bodies too thin for a post), checks that every link,
/// connector, guide and frame fits the print bed, records the constraints over the rows (about
/// `rows × members²` distances between cores of at most three points) and asks the solver for any
/// ordering, with pins fused to bodies and then with connectors everywhere. Measured in release builds
/// on the engine's designs: 0.8–0.9 ms per candidate (wall chair, car roof), 2.7 ms on the car K=3, so
/// run it after the collision check (see `docs/fabrication.md`).
#[derive(Clone, Debug)]
pub struct FeasibilityCheck {
    shapes: SceneShapes,
    faces: Faces,
    bed: settings::Bed,
}

impl crate::synth::Acceptance for FeasibilityCheck {
    fn min_joint_spacing(&self) -> f64 {
        FeasibilityCheck::min_joint_spacing(self)
    }
    fn accepts(&self, mechanism: &Mechanism, trace: &Trace) -> bool {
        self.check(mechanism, trace)
    }
}

impl FeasibilityCheck {
    /// The check with the given settings in a scene of `mm_per_unit` millimetres per unit.
    pub fn new(problem: &Problem, settings: &PrintSettings, mm_per_unit: f64) -> FeasibilityCheck {
        FeasibilityCheck {
            shapes: SceneShapes::new(problem, Dims::new(settings, mm_per_unit)),
            faces: settings.faces,
            bed: settings.bed.clone(),
        }
    }
    /// The least distance between two joints of one link, in scene units (pins need room).
    pub fn min_joint_spacing(&self) -> f64 {
        self.shapes.dims.min_joint_spacing()
    }
    /// True when `mechanism`, moving from the first to the last crank angle of `trace` (as
    /// [`crate::synth::Candidate::trace`]), has connectors that fit, members that fit the bed and a
    /// depth ordering; what it accepts, [`fabricate`] over that travel builds with every member on the
    /// bed (it may refuse a design whose ordering the solver does not find within 50 ms).
    pub fn check(&self, mechanism: &Mechanism, trace: &Trace) -> bool {
        self.diagnose(mechanism, trace).is_ok()
    }
    /// [`FeasibilityCheck::check`] with the reason when it fails (the first strategy's reason: pins
    /// fused to the bodies where they fit). The motion is simulated again from the trace's first to its
    /// last crank angle at the steps [`fabricate`] takes ([`motion_trace`]), so the constraints are
    /// recorded at the very rows fabrication records them (a grazing contact between two rows of one
    /// sampling can show in the other's), and what the check accepts fabricates.
    pub fn diagnose(&self, mechanism: &Mechanism, trace: &Trace) -> Result<(), FabError> {
        let (Some(&start), Some(&end)) = (trace.thetas.first(), trace.thetas.last()) else {
            return Err(FabError::Motion("the trace is empty".into()));
        };
        let trace = &motion_trace(mechanism, Travel { start, end })?;
        // Both faces allowed is a relaxation of one face, so it alone decides feasibility for `auto`.
        let faces = if self.faces == Faces::One { Faces::One } else { Faces::Both };
        let mut first = None;
        for body_pins in [true, false] {
            let (error, pinned) = match Layout::new(&self.shapes, mechanism, trace, body_pins, &[]) {
                Err(e) => (e, true),
                Ok(layout) => {
                    let misfits = layout.off_bed(&self.bed);
                    let pinned = layout.body_pins.iter().any(Option::is_some);
                    if !misfits.is_empty() {
                        (off_bed_error(&layout, &misfits, &self.bed), pinned)
                    } else if depth::feasible(&layout, &depth::record(&layout, trace), faces, 0.05) {
                        return Ok(());
                    } else {
                        (FabError::NoOrdering, pinned)
                    }
                }
            };
            first.get_or_insert(error);
            // With no pin fused to a body, the layout without them is the same one.
            if !pinned {
                break;
            }
        }
        Err(first.unwrap_or(FabError::NoOrdering))
    }
}

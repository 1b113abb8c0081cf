//! The fabrication pipeline: a design's layout tried strategy by strategy until the
//! depth ordering is solved, and its parts built ([`fabricate`]); a design file checked against its
//! scene first ([`fabricate_design`]), and one of its alternatives when the design itself cannot be
//! made ([`fabricate_design_or_alternative`]).

use super::build::{self, model_scale};
use super::depth::{self, Ordering, Recorded};
use super::error::FabError;
use super::fabrication::{Fabrication, Timings};
use super::layout::{Layout, SpringEnds};
use super::names;
use super::parts;
use super::posts::SceneShapes;
use super::settings::{Dims, Faces, PrintSettings};
use super::travel::{motion_trace, Travel};
use crate::kinematics::Trace;
use crate::mechanism::Mechanism;
use crate::scene::Problem;
use std::time::Instant;

/// Fabricates `mechanism` moving through `travel` in the scene of `problem`, a model at `scale` of
/// the drawing (in the scene's units), with a hook at both ends of each of `springs` (the
/// counterbalance springs of [`crate::balance`], for instance).
pub fn fabricate(
    problem: &Problem,
    scale: crate::scene::Ratio,
    mechanism: &Mechanism,
    travel: Travel,
    settings: &PrintSettings,
    springs: &[SpringEnds],
) -> Result<Fabrication, FabError> {
    let issues = settings.validate_any_build();
    if !issues.is_empty() {
        return Err(FabError::Settings(issues.iter().map(|i| i.to_string()).collect::<Vec<_>>().join("; ")));
    }
    let mm_per_unit = problem.units.model_millimetres(scale);
    if !(mm_per_unit.is_finite() && mm_per_unit > 0.0) {
        return Err(FabError::Scale(scale));
    }
    let dims = Dims::new(settings, mm_per_unit);
    let trace = motion_trace(mechanism, travel)?;
    let shapes = SceneShapes::new(problem, dims);
    let ((layout, recorded, ordering), timings) = ordered_layout(&shapes, mechanism, &trace, settings, springs)?;
    let t2 = Instant::now();
    let body_names = names::body_names(problem);
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
        scale,
        model_mm: build::drawn_mm(problem, mm_per_unit),
        layout,
        recorded,
        ordering,
        parts,
        seats,
        trace,
        timings: Timings { meshing: (t3 - t2).as_secs_f64(), ..timings },
    })
}

/// A layout with the constraints recorded along its motion and a depth ordering that satisfies them.
type Ordered = (Layout, Recorded, Ordering);

/// The layout of `mechanism` moving through `trace` for the first of the [`strategies`] whose ordering
/// is solved with every member on the bed, else for the first whose ordering is solved; with the
/// seconds spent recording and solving (none yet meshing).
fn ordered_layout(
    shapes: &SceneShapes,
    mechanism: &Mechanism,
    trace: &Trace,
    settings: &PrintSettings,
    springs: &[SpringEnds],
) -> Result<(Ordered, Timings), FabError> {
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
            let attempt = Layout::new(shapes, mechanism, trace, body_pins, springs).map(|l| {
                let r = depth::record(&l, trace);
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
        let solved = depth::solve(layout, recorded, faces, depth::FABRICATION_STEPS);
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
    let Some(ordered) = found.or(off_bed) else {
        return Err(first_error.unwrap_or(FabError::NoOrdering));
    };
    Ok((ordered, Timings { recording, ordering: ordering_s, meshing: 0.0 }))
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

/// Fabricates the mechanism of a design file for its scene, at the scale the design is printed at
/// ([`model_scale`]). A design file that is not valid ([`crate::design::DesignFile::validate`]) or
/// fails its check against the scene ([`crate::design::DesignFile::violations`]) is refused before
/// anything is built.
///
/// ```
/// use linkwright_core::fab::{bundle, check, fabricate_design, PrintSettings, Role};
/// use linkwright_core::testbed::{known_scene, Known};
/// use linkwright_core::Problem;
///
/// // A known four-bar in a scene drawn in millimetres, with the default print settings.
/// let known = known_scene(Known::chain(1), 3, 7, 100.0)?;
/// let problem = Problem::new(&known.scene).expect("a valid scene");
/// let fabrication = fabricate_design(&problem, &known.design(), &PrintSettings::default())?;
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
    design: &crate::design::DesignFile,
    settings: &PrintSettings,
) -> Result<Fabrication, FabError> {
    fabricate_design_with_springs(problem, design, settings, &[])
}

/// [`fabricate_design`] with a hook at both ends of each of `springs`, anchored on the design's parts
/// (not on an alternative's).
pub fn fabricate_design_with_springs(
    problem: &Problem,
    design: &crate::design::DesignFile,
    settings: &PrintSettings,
    springs: &[SpringEnds],
) -> Result<Fabrication, FabError> {
    let scale = model_scale(problem, Some(design), settings);
    let (mechanism, travel) = checked_design(problem, design)?;
    fabricate(problem, scale, &mechanism, travel, settings, springs)
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
    design: &crate::design::DesignFile,
    settings: &PrintSettings,
) -> Result<Chosen, FabError> {
    let first = match fabricate_design(problem, design, settings) {
        Ok(f) if f.off_bed().is_empty() => return Ok(Chosen { used: 0, fabrication: f, passed_over: None }),
        Err(e @ (FabError::Settings(_) | FabError::Scale(_) | FabError::Invalid(_) | FabError::FailsCheck(_))) => {
            return Err(e)
        }
        other => other,
    };
    let passed_over = match &first {
        Ok(f) => {
            let misfits = f.off_bed();
            f.layout.off_bed_error(&misfits, &f.settings.bed).to_string()
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
        match fabricate_design(problem, &view, settings) {
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

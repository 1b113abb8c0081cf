//! Validation of a parsed scene: every problem found, each naming its field and what to change.
//!
//! [`validate`] never stops at the first problem: a person fixing a sketch wants the whole list at once.
//! It never panics either, whatever the numbers (NaN, infinities, huge values, empty lists): checks that
//! need sound geometry (the collision checks) skip the bodies whose outline or pose is already reported.

use super::file::{FixedBody, MechanismChoice, MechanismType, MovingBody, Scene, Settings, Weights, SCENE_FORMAT};
use super::units::Units;
use crate::geom::{curve_length, curve_size, nearest, Aabb, Point, Polygon, PolygonError, Rigid};
use crate::issues::IssueList;
use serde_json::{Map, Value};

/// How bad a finding is: errors stop the run, warnings are reported and the run goes on.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Severity {
    /// The scene cannot be used as it is.
    Error,
    /// The scene can be used, but something in it is probably not what was meant.
    Warning,
}

/// One finding about a scene.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Issue {
    /// Whether the finding stops the run.
    pub severity: Severity,
    /// The field, as a path: `moving_bodies[1].poses`, `settings.samples`.
    pub field: String,
    /// What is wrong and what to change.
    pub message: String,
}

impl std::fmt::Display for Issue {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let tag = match self.severity {
            Severity::Error => "error",
            Severity::Warning => "warning",
        };
        write!(f, "{tag}: {}: {}", self.field, self.message)
    }
}

/// The limits of what a scene may ask for, in one place (documented in `docs/formats.md`, their
/// measured worst case in `docs/security.md`). Each is far beyond what a person draws: the 64 reference
/// scenes (`crates/linkwright-core/tests/fixtures/reference-scenes/`) reach at most 39 vertices in one
/// outline and 128 in all, 6 fixed and 8 moving bodies, 6 poses, 2 avoid regions, coordinates of 355
/// and a drawing 66 times as large as its smallest moving body.
/// Together they bound the time and memory of every stage, whatever a file says.
pub mod limits {
    /// Largest coordinate accepted, in scene units: a kilometre-scale object is surely a unit
    /// mistake, and bounding the numbers keeps every later product (areas, squared lengths) far from
    /// overflow and the printability check's outline sampling (a step of a fraction of a millimetre)
    /// bounded.
    pub const MAX_COORDINATE: f64 = 1e6;
    /// Vertices of one outline: a traced photograph simplified to a few hundred corners still fits, and
    /// the self-intersection test is quadratic in them.
    pub const MAX_OUTLINE_VERTICES: usize = 500;
    /// Vertices of every outline and region together: the collision sweep tests each link against
    /// every edge at every step of the motion.
    pub const MAX_VERTICES: usize = 2000;
    /// Fixed bodies in one scene.
    pub const MAX_FIXED_BODIES: usize = 50;
    /// Moving bodies: the chain grows two links per body, and its sampling works in 4K dimensions.
    pub const MAX_MOVING_BODIES: usize = 8;
    /// Poses per moving body: beyond the nine or ten of the classic motion-generation tasks, more
    /// poses only draw the path, and every sample fits and simulates through each of them.
    pub const MAX_POSES: usize = 20;
    /// Avoid regions in one scene.
    pub const MAX_AVOID_REGIONS: usize = 50;
    /// How many times the whole drawing (every outline at every pose, and the regions) may be larger
    /// than its smallest moving body: the engine resolves contacts and noise in fractions of that
    /// body's size, so a drawing a thousand times as large is mostly unrelated geometry.
    pub const MAX_EXTENT_RATIO: f64 = 1000.0;
    /// Most `settings.samples`. With the bounds on particles and iterations and the geometry's, this
    /// keeps a run on two cores within minutes (the paper's settings are 100,000 samples, 100
    /// particles, 20 iterations).
    pub const MAX_SAMPLES: usize = 1_000_000;
    /// Most `settings.particles`.
    pub const MAX_PARTICLES: usize = 1000;
    /// Most `settings.iterations`.
    pub const MAX_ITERATIONS: usize = 200;
    /// Samples times moving bodies times poses: every sample is fitted through every pose of every
    /// body, and beyond the exact poses a fit iterates to its least-squares optimum, a few
    /// microseconds per body and pose on one core. Ten million keeps the sampling within about a
    /// minute per family searched on two cores (eight bodies through twenty poses at 62,500 samples:
    /// `stats.seconds.sampling` of `linkwright design SCENE --threads 2`), and lets every reference
    /// scene run at the paper's 100,000 samples.
    pub const MAX_SAMPLE_POSES: usize = 10_000_000;
    /// Shortest `gravity` vector. Gravity is a direction (its strength is always standard gravity),
    /// so `[0, -1]`, `[0, -9.81]` (m/s²) and `[0, -9810]` (mm/s²) all mean down; a length outside
    /// 10⁻³ to 10⁴ is a typo or a hostile number, and bounding it keeps its normalisation exact
    /// (unbounded, `[1e-200, -1e-200]` gives NaN torques and `[1e160, -1e160]` none at all).
    pub const MIN_GRAVITY: f64 = 1e-3;
    /// Longest `gravity` vector (see [`MIN_GRAVITY`]).
    pub const MAX_GRAVITY: f64 = 1e4;
    /// Most `pinned_joints`: a pin names a joint of the design, and a design file's linkage has at
    /// most this many joints (`design::MAX_JOINTS`, which holds to it; the engine's largest, for
    /// eight moving bodies, has 25).
    pub const MAX_PINNED_JOINTS: usize = 256;
    /// Longest name (of a scene, a body, a design's joint or part), in characters: a label, not prose.
    pub const MAX_NAME_CHARS: usize = 100;
    /// Points of a drawn path: a freehand stroke smoothed to a few hundred points keeps its shape,
    /// and the path search measures every traced curve against each of them.
    pub const MAX_PATH_POINTS: usize = 1000;
}
use limits::*;
/// Bodies closer than this fraction of the smaller body size d *touch* (a warning), bodies reaching into
/// each other deeper than it *overlap* (an error). Hand-drawn scenes put bodies in contact with some
/// slack: of the 64 reference scenes none overlaps at any pose, and the closest contacts leave gaps of
/// 0.7% to 1.8% of d (0.2 to 2 mm: the touch warnings of `linkwright design SCENE --samples 1` on
/// `crates/linkwright-core/tests/fixtures/reference-scenes/*.json`). 2% of d (0.2 mm for the smallest
/// reference bodies, 1.5 mm for a 75 mm one) forgives sub-millimetre drawing imprecision, while an
/// overlap of 5% of d is refused.
const TOUCH_FRACTION: f64 = 0.02;
const MAX_POSE_TOLERANCE: f64 = 10.0;
const MAX_ANGLE_TOLERANCE_DEG: f64 = 90.0;
const MAX_MIN_TRANSMISSION_DEG: f64 = 80.0;

/// What is wrong with a name a file gives (a scene's, a body's, a design's joint's or part's), each
/// problem as what to change (empty when it is fine). Names become labels on screen and in files: at
/// most [`MAX_NAME_CHARS`] characters, and no control characters, which a terminal would obey rather
/// than show. Scenes and designs share this rule.
pub(crate) fn name_problems(what: &str, name: &str) -> Vec<String> {
    let mut problems = Vec::new();
    if name.chars().count() > MAX_NAME_CHARS {
        problems.push(format!("the {what} name is longer than {MAX_NAME_CHARS} characters; shorten it"));
    }
    if name.chars().any(char::is_control) {
        problems.push(format!("the {what} name {name:?} holds control characters; use printable characters only"));
    }
    problems
}

/// Every problem found in `scene`, errors and warnings, roughly in document order: the first
/// [`MAX_LISTED_ISSUES`](crate::MAX_LISTED_ISSUES) listed (errors before warnings when there are more)
/// and the rest counted.
///
/// ```
/// use linkwright_core::{validate_scene, Scene, Severity};
///
/// // One pose is no motion.
/// let scene = Scene::from_json(
///     r#"{"linkwright": "scene/1",
///         "fixed_bodies": [{"polygon": [[0, 0], [200, 0], [200, 20], [0, 20]]}],
///         "moving_bodies": [{"polygon": [[0, 0], [20, 0], [20, 80], [0, 80]], "poses": [[50, 100, 0]]}]}"#,
/// )?;
/// let issues = validate_scene(&scene);
/// let error = issues.iter().find(|i| i.severity == Severity::Error).expect("an error");
/// assert_eq!(error.field, "moving_bodies[0].poses");
/// assert!(error.message.contains("at least 2"), "{error}");
/// # Ok::<(), linkwright_core::ParseError>(())
/// ```
pub fn validate(scene: &Scene) -> IssueList<Issue> {
    let mut out = Issues::default();
    if scene.linkwright != SCENE_FORMAT {
        out.error(
            "linkwright",
            format!("unknown format \"{}\"; this version reads \"{SCENE_FORMAT}\"", scene.linkwright),
        );
    }
    out.unknown_fields("", &scene.extra);
    out.name("name", "scene", &scene.name);
    if let Err(e) = scene.units.parse::<Units>() {
        out.error("units", e.to_string());
    }
    if !check_counts(scene, &mut out) {
        // Every later check costs in proportion to these counts: a file far beyond them is answered
        // at once with what to cut, not after minutes of checking what will not run anyway.
        return out.0;
    }
    let fixed_ok = check_fixed_bodies(&scene.fixed_bodies, &mut out);
    let moving_ok = check_moving_bodies(&scene.moving_bodies, &mut out);
    if let Some(region) = &scene.linkage_region {
        out.polygon("linkage_region", region);
    }
    for (i, region) in scene.avoid_regions.iter().enumerate() {
        out.polygon(&format!("avoid_regions[{i}]"), region);
    }
    check_mechanism(scene, &mut out);
    check_paths(scene, &moving_ok, &mut out);
    check_must_hit(scene, &mut out);
    check_pinned_joints(scene, &mut out);
    if let Some([x, y]) = scene.gravity {
        let length = x.hypot(y);
        if !(length.is_finite() && (MIN_GRAVITY..=MAX_GRAVITY).contains(&length)) {
            out.error(
                "gravity",
                format!(
                    "is [{x}, {y}], of length {length:e}; give the direction gravity pulls in, such as [0, -1] \
                     (down), of a length from {MIN_GRAVITY:e} to {MAX_GRAVITY:e}"
                ),
            );
        }
    }
    check_weights(&scene.weights, &mut out);
    check_settings(&scene.settings, &mut out);
    check_work(scene, &mut out);
    if fixed_ok.iter().chain(&moving_ok).all(|&ok| ok) {
        check_extent(scene, &mut out);
    }
    check_collisions(scene, &fixed_ok, &moving_ok, &mut out);
    out.0
}

/// Checks the counts against [`limits`]; returns whether every one is within them.
fn check_counts(scene: &Scene, out: &mut Issues) -> bool {
    let before = out.0.total();
    let counts = [
        (
            "fixed_bodies",
            scene.fixed_bodies.len(),
            MAX_FIXED_BODIES,
            "fixed bodies",
            "merge touching parts into one outline",
        ),
        ("moving_bodies", scene.moving_bodies.len(), MAX_MOVING_BODIES, "moving bodies", "design the motion in parts"),
        ("avoid_regions", scene.avoid_regions.len(), MAX_AVOID_REGIONS, "avoid regions", "merge neighbouring regions"),
        (
            "pinned_joints",
            scene.pinned_joints.len(),
            MAX_PINNED_JOINTS,
            "pinned joints",
            "pin only the joints whose place matters (a linkage has at most that many joints)",
        ),
    ];
    for (field, n, max, what, fix) in counts {
        if n > max {
            out.error(field, format!("has {n} {what}; at most {max} are supported: {fix}"));
        }
    }
    for (k, body) in scene.moving_bodies.iter().enumerate() {
        if body.poses.len() > MAX_POSES {
            out.error(
                format!("moving_bodies[{k}].poses"),
                format!(
                    "has {} poses; at most {MAX_POSES} are supported: keep the poses that matter (where the \
                     motion rests and where it must pass) and drop the ones that only draw the path",
                    body.poses.len()
                ),
            );
        }
    }
    for (k, path) in scene.moving_bodies.iter().enumerate().filter_map(|(k, b)| b.path.as_ref().map(|p| (k, p))) {
        if path.points.len() > MAX_PATH_POINTS {
            out.error(
                format!("moving_bodies[{k}].path.points"),
                format!(
                    "has {} points; at most {MAX_PATH_POINTS} are supported: a few dozen to a few hundred \
                     points spaced along the curve keep its shape",
                    path.points.len()
                ),
            );
        }
    }
    let outlines: Vec<(String, usize)> = (scene.fixed_bodies.iter().enumerate())
        .map(|(j, b)| (format!("fixed_bodies[{j}].polygon"), b.polygon.len()))
        .chain(
            scene
                .moving_bodies
                .iter()
                .enumerate()
                .map(|(k, b)| (format!("moving_bodies[{k}].polygon"), b.polygon.len())),
        )
        .chain(scene.linkage_region.iter().map(|r| ("linkage_region".to_string(), r.len())))
        .chain(scene.avoid_regions.iter().enumerate().map(|(i, r)| (format!("avoid_regions[{i}]"), r.len())))
        .collect();
    let vertices = outlines.iter().map(|o| o.1).fold(0usize, usize::saturating_add);
    if let Some((largest, n)) = outlines.iter().rev().max_by_key(|o| o.1).filter(|_| vertices > MAX_VERTICES) {
        out.error(
            largest,
            format!(
                "the outlines and regions have {vertices} vertices in all, this one {n}; at most \
                 {MAX_VERTICES} are supported in all: simplify the outlines (a few dozen corners per body \
                 keep their shape)"
            ),
        );
    }
    out.0.total() == before
}

/// The whole drawing must stay within [`MAX_EXTENT_RATIO`] times the smallest moving body (its outlines
/// and poses already checked finite and bounded).
fn check_extent(scene: &Scene, out: &mut Issues) {
    let Some((k, d)) =
        scene.moving_bodies.iter().map(|b| body_size(&b.polygon)).enumerate().min_by(|a, b| a.1.total_cmp(&b.1))
    else {
        return;
    };
    let mut points: Vec<Point> = Vec::new();
    points.extend(scene.fixed_bodies.iter().flat_map(|b| b.polygon.iter().copied()));
    points.extend(scene.linkage_region.iter().flatten().copied());
    points.extend(scene.avoid_regions.iter().flatten().copied());
    for body in &scene.moving_bodies {
        for pose in body.poses.iter().filter(|p| pose_is_usable(p)) {
            let placed = Rigid::from_pose(*pose);
            points.extend(body.polygon.iter().map(|&p| placed.apply(p)));
        }
        let path = body.path.iter().flat_map(|path| &path.points);
        points.extend(path.filter(|p| p.is_finite() && p.x.abs().max(p.y.abs()) <= MAX_COORDINATE));
    }
    let Some(bb) = Aabb::around(points) else { return };
    let extent = bb.width().max(bb.height());
    if extent > MAX_EXTENT_RATIO * d {
        let body = &scene.moving_bodies[k];
        out.error(
            format!("moving_bodies[{k}].polygon"),
            format!(
                "{} is {d:.3} across, but the drawing spans {extent:.0}: {:.0} times as much, and at most \
                 {MAX_EXTENT_RATIO} is supported (the engine works in fractions of the smallest body); draw \
                 the small body larger, or crop the fixed bodies and regions to the part near the motion",
                label("body", &body.name, &format!("moving_bodies[{k}]")),
                extent / d
            ),
        );
        return;
    }
    // A pin far from a drawing of the right size is the pin's mistake, so it is named.
    for (name, &pin) in &scene.pinned_joints {
        let Some(with_pin) = Aabb::around([bb.min, bb.max, pin]) else { continue };
        let extent = with_pin.width().max(with_pin.height());
        if extent > MAX_EXTENT_RATIO * d {
            out.error(
                format!("pinned_joints.{name}"),
                format!(
                    "is at [{}, {}], so far from the drawing that the two together span {extent:.0}, {:.0} times \
                     the smallest moving body ({d:.3} across), and at most {MAX_EXTENT_RATIO} is supported; \
                     place the joint near the bodies it moves",
                    pin.x,
                    pin.y,
                    extent / d
                ),
            );
        }
    }
}

/// The findings so far, with the helpers every check shares.
#[derive(Default)]
struct Issues(IssueList<Issue>);

impl Issues {
    fn error(&mut self, field: impl Into<String>, message: impl Into<String>) {
        self.error_with(|| (field.into(), message.into()));
    }
    /// An error whose field and message `make` words only when it is listed.
    fn error_with(&mut self, make: impl FnOnce() -> (String, String)) {
        let make = || {
            let (field, message) = make();
            Issue { severity: Severity::Error, field, message }
        };
        self.0.push_over_with(make, |i| i.severity == Severity::Warning);
    }
    fn warning(&mut self, field: impl Into<String>, message: impl Into<String>) {
        self.warning_with(|| (field.into(), message.into()));
    }
    /// A warning whose field and message `make` words only when it is listed.
    fn warning_with(&mut self, make: impl FnOnce() -> (String, String)) {
        self.0.push_with(|| {
            let (field, message) = make();
            Issue { severity: Severity::Warning, field, message }
        });
    }

    /// Warns about each field the format does not know: the format promises to ignore them, but a
    /// misspelt `"setings"` silently ignored would cost the person an afternoon.
    fn unknown_fields(&mut self, prefix: &str, extra: &Map<String, Value>) {
        for key in extra.keys() {
            self.warning(
                format!("{prefix}{key}"),
                format!("unknown field '{key}' is ignored; check its spelling or remove it"),
            );
        }
    }

    /// A name of the scene ([`name_problems`]).
    fn name(&mut self, field: &str, what: &str, name: &str) {
        for message in name_problems(what, name) {
            self.error(field, message);
        }
    }

    /// Checks that `points` form a usable simple polygon; returns whether they do.
    fn polygon(&mut self, field: &str, points: &[Point]) -> bool {
        if points.len() > MAX_OUTLINE_VERTICES {
            self.error(
                field,
                format!(
                    "has {} vertices; at most {MAX_OUTLINE_VERTICES} are supported: simplify the outline \
                     (a few dozen corners keep its shape)",
                    points.len()
                ),
            );
            return false;
        }
        if let Some(i) = points.iter().position(|p| p.is_finite() && (p.x.abs().max(p.y.abs()) > MAX_COORDINATE)) {
            self.error(
                field,
                format!(
                    "vertex {i} is farther than {MAX_COORDINATE:e} mm from the origin; lengths are millimetres, \
                     so scale the drawing down"
                ),
            );
            return false;
        }
        let Err(e) = Polygon::new(points.to_vec()).validate() else { return true };
        let fix = match e {
            PolygonError::TooFewVertices(_) => "add vertices so that it outlines an area",
            PolygonError::NonFinite(_) => "write finite numbers",
            PolygonError::ZeroArea => "spread the vertices so that they outline an area",
            PolygonError::SelfIntersecting(..) => {
                "reorder or move the vertices so that the outline does not cross itself"
            }
            PolygonError::TooThin { .. } => "widen it, or remove it if it is a stray stroke",
        };
        self.error(field, format!("{e}; {fix}"));
        false
    }
}

/// Checks the fixed bodies (there must be a ground); returns which ones have a usable outline.
fn check_fixed_bodies(bodies: &[FixedBody], out: &mut Issues) -> Vec<bool> {
    if bodies.is_empty() {
        // Not an error: the ground pivots still stand still in the world (the linkage region says where),
        // but nothing shows what holds them, and nothing will be printed for it.
        out.warning(
            "fixed_bodies",
            "there is no fixed body, so nothing shows what the ground pivots stand on; \
             add the part of the object that does not move",
        );
    }
    let ok = bodies.iter().enumerate().map(|(i, b)| out.polygon(&format!("fixed_bodies[{i}].polygon"), &b.polygon));
    let ok = ok.collect();
    for (i, b) in bodies.iter().enumerate() {
        out.name(&format!("fixed_bodies[{i}].name"), "body", &b.name);
        out.unknown_fields(&format!("fixed_bodies[{i}]."), &b.extra);
    }
    ok
}

/// Checks the moving bodies, their poses and pose counts; returns which ones have a usable outline.
fn check_moving_bodies(bodies: &[MovingBody], out: &mut Issues) -> Vec<bool> {
    if bodies.is_empty() {
        out.error("moving_bodies", "there is no moving body; add at least one, with its poses");
    }
    let mut ok = Vec::with_capacity(bodies.len());
    for (k, body) in bodies.iter().enumerate() {
        ok.push(out.polygon(&format!("moving_bodies[{k}].polygon"), &body.polygon));
        let field = format!("moving_bodies[{k}].poses");
        let n = body.poses.len();
        if body.path.is_some() {
            if n == 0 {
                out.error(
                    &field,
                    "is empty, but a body that follows a path needs one: where it starts, with the path's \
                     tracer on the path's first point"
                        .to_string(),
                );
            }
        } else if n < 2 {
            out.error(
                &field,
                format!("has {n} pose(s); a motion needs at least 2 (where it starts and where it ends)"),
            );
        } else if k > 0 && n != bodies[0].poses.len() && bodies[0].path.is_none() {
            out.error(
                &field,
                format!(
                    "{} has {n} poses but {} has {}; pose i of every body happens at the same moment, \
                     so give every body the same number of poses",
                    label("body", &body.name, &format!("moving_bodies[{k}]")),
                    label("body", &bodies[0].name, "moving_bodies[0]"),
                    bodies[0].poses.len()
                ),
            );
        }
        if let Some(mass) = body.mass_kg {
            if !(mass.is_finite() && mass > 0.0 && mass <= MAX_MASS_KG) {
                out.error(
                    format!("moving_bodies[{k}].mass_kg"),
                    format!("is {mass}; give the body's mass in kilograms, more than 0 and at most {MAX_MASS_KG:e}"),
                );
            }
        }
        match (body.material, body.thickness) {
            (_, Some(t)) if !(t.is_finite() && t > 0.0 && t <= MAX_COORDINATE) => out.error(
                format!("moving_bodies[{k}].thickness"),
                format!("is {t}; give the body's thickness in the scene's units, more than 0"),
            ),
            (Some(_), None) => out.error(
                format!("moving_bodies[{k}].thickness"),
                "is missing: a body with a material needs its thickness (scene units) for its mass".to_string(),
            ),
            (None, Some(_)) => out.error(
                format!("moving_bodies[{k}].material"),
                "is missing: a body with a thickness needs its material (plywood, aluminium or steel)".to_string(),
            ),
            _ => {}
        }
        for (i, pose) in body.poses.iter().enumerate() {
            if !pose_is_usable(pose) {
                out.error(
                    format!("{field}[{i}]"),
                    format!(
                        "pose {} is {pose:?}; write three finite numbers [x_mm, y_mm, angle_deg] \
                         within ±{MAX_COORDINATE:e}",
                        i + 1
                    ),
                );
            }
        }
        out.name(&format!("moving_bodies[{k}].name"), "body", &body.name);
        out.unknown_fields(&format!("moving_bodies[{k}]."), &body.extra);
    }
    ok
}

/// A pose the geometry can place a body with: finite, and not absurdly far away.
fn pose_is_usable(pose: &[f64; 3]) -> bool {
    pose.iter().all(|v| v.is_finite() && v.abs() <= MAX_COORDINATE)
}

/// A body as messages name it: `body 'bed'` when it has a name, its path `moving_bodies[0]` otherwise.
fn label(kind: &str, name: &str, path: &str) -> String {
    if name.is_empty() {
        path.to_string()
    } else {
        format!("{kind} '{name}'")
    }
}

/// A family that carries a limited number of bodies (the slider-crank of paper §4.3 drives exactly
/// one) cannot be asked for more.
fn check_mechanism(scene: &Scene, out: &mut Issues) {
    let k = scene.moving_bodies.len();
    let MechanismChoice::Only(family) = scene.mechanism else { return };
    let Some(max) = family.max_bodies() else { return };
    if k == 0 || k > max {
        let (carries, keep) = match max {
            1 => ("exactly one body".to_string(), "one moving body".to_string()),
            _ => (format!("at most {max} bodies"), format!("at most {max} moving bodies")),
        };
        let fitting: String = MechanismType::ALL
            .into_iter()
            .filter(|&t| t != family && t.max_bodies().is_none_or(|m| k <= m))
            .map(|t| format!("\"{}\" or ", t.id()))
            .collect();
        let message =
            format!("{} moves {carries} but the scene has {k}; use {fitting}\"auto\", or keep {keep}", family.id());
        out.error("mechanism", message);
    }
}

/// How far (a fraction of the curve's size) the tracer may be from where a path starts, at the body's
/// pose: a click on the curve's first point, not a second start.
const PATH_START_TOLERANCE: f64 = 0.01;

/// A body's path: a curve of usable points with a length, traced by one moving body on its own (the
/// path search designs four-bars), its tracer placed by the body's pose where the curve starts.
fn check_paths(scene: &Scene, moving_ok: &[bool], out: &mut Issues) {
    for (k, body) in scene.moving_bodies.iter().enumerate() {
        let Some(path) = &body.path else { continue };
        let field = format!("moving_bodies[{k}].path");
        out.unknown_fields(&format!("{field}."), &path.extra);
        if scene.moving_bodies.len() > 1 {
            out.error(
                &field,
                format!(
                    "the scene has {} moving bodies, but a path is followed by a linkage of one moving body; \
                     keep the body with the path alone (design the others in a scene of their own)",
                    scene.moving_bodies.len()
                ),
            );
        }
        if !(path.tracer.x.is_finite() && path.tracer.y.is_finite())
            || path.tracer.x.abs().max(path.tracer.y.abs()) > MAX_COORDINATE
        {
            out.error(
                format!("{field}.tracer"),
                format!("is {:?}; give the tracer's place in the body's own frame, finite numbers", path.tracer),
            );
            continue;
        }
        let least = if path.closed { 3 } else { 2 };
        if path.points.len() < least {
            out.error(
                format!("{field}.points"),
                format!(
                    "has {} point(s); {} curve needs at least {least}",
                    path.points.len(),
                    if path.closed { "a closed" } else { "an open" }
                ),
            );
            continue;
        }
        if let Some(i) = path.points.iter().position(|p| !(p.is_finite() && p.x.abs().max(p.y.abs()) <= MAX_COORDINATE))
        {
            out.error(
                format!("{field}.points[{i}]"),
                format!("is {:?}; write two finite numbers [x, y] within ±{MAX_COORDINATE:e}", path.points[i]),
            );
            continue;
        }
        check_exact(&field, path, out);
        let size = curve_size(&path.points);
        let smallest = body_size(&body.polygon);
        if size.is_nan() || size <= 1e-6 * smallest {
            out.error(
                format!("{field}.points"),
                "are all at one place; draw the curve the tracer should follow".to_string(),
            );
            continue;
        }
        let (Some(pose), true) = (body.poses.first().filter(|p| pose_is_usable(p)), moving_ok[k]) else { continue };
        let start = Rigid::from_pose(*pose).apply(path.tracer);
        let (gap, from) = if path.closed {
            (nearest(start, &path.points, true).0, "the curve")
        } else {
            (start.distance(path.points[0]), "the curve's first point")
        };
        if gap > PATH_START_TOLERANCE * size {
            out.error(
                format!("moving_bodies[{k}].poses[0]"),
                format!(
                    "puts the tracer at ({:.3}, {:.3}), {gap:.3} from {from}: place the body where the path \
                     starts (its tracer on {from}), or start the curve at the tracer",
                    start.x, start.y
                ),
            );
        }
        check_path_poses(k, body, size, start, out);
    }
}

/// A path body's later poses, which it must also pass on its way: each puts the tracer on the curve,
/// farther along it than the pose before (a closed curve is measured from where the body starts).
fn check_path_poses(k: usize, body: &MovingBody, size: f64, start: Point, out: &mut Issues) {
    let Some(path) = &body.path else { return };
    // How far along the curve (as drawn, from its first point) the point of it nearest `p` is.
    let along = |p: Point| {
        let (gap, on, edge) = nearest(p, &path.points, path.closed);
        let before: f64 = path.points.windows(2).take(edge).map(|w| w[0].distance(w[1])).sum();
        (gap, before + path.points[edge].distance(on))
    };
    let length = curve_length(&path.points, path.closed);
    let (_, origin) = along(start);
    let mut last = 0.0;
    for (i, pose) in body.poses.iter().enumerate().skip(1) {
        if !pose_is_usable(pose) {
            continue;
        }
        let tracer = Rigid::from_pose(*pose).apply(path.tracer);
        let (gap, at) = along(tracer);
        let field = format!("moving_bodies[{k}].poses[{i}]");
        if gap > PATH_START_TOLERANCE * size {
            out.error(
                field,
                format!(
                    "puts the tracer at ({:.3}, {:.3}), {gap:.3} from the path: a later pose of a body that \
                     follows a path has its tracer on the path, where the body should pass at that angle",
                    tracer.x, tracer.y
                ),
            );
            continue;
        }
        let at = if path.closed { (at - origin).rem_euclid(length) } else { at };
        if at <= last {
            out.error(
                field,
                format!(
                    "puts the tracer {} along the path than the pose before it: the body passes its poses in \
                     order along the path, so move it farther along or reorder the poses",
                    if at < last { "less far" } else { "no farther" },
                ),
            );
        }
        last = last.max(at);
    }
}

/// A path's exact points are points of its curve, each listed once. A list may be as long as the
/// file: a problem past the curve's points is only counted.
fn check_exact(field: &str, path: &crate::scene::DrawnPath, out: &mut Issues) {
    let n = path.points.len();
    let mut listed = vec![false; n];
    for (k, &i) in path.exact.iter().enumerate() {
        if i >= n {
            out.error_with(|| {
                let message =
                    format!("there is no point {i}: the path has {n} points, numbered from 0 to {}", n.max(1) - 1);
                (format!("{field}.exact[{k}]"), message)
            });
        } else if std::mem::replace(&mut listed[i], true) {
            out.warning_with(|| (format!("{field}.exact[{k}]"), format!("point {i} is listed twice; once is enough")));
        }
    }
}

/// The shorter side of an outline's bounding box (0 for no outline).
fn body_size(polygon: &[Point]) -> f64 {
    Aabb::around(polygon.iter().copied()).map_or(0.0, |bb| bb.width().min(bb.height()))
}

/// The largest mass a moving body may be given, kilograms (a car's door is tens; a bridge is beyond
/// what this tool designs).
const MAX_MASS_KG: f64 = 1e5;

/// Each must-hit pose is one the bodies have. A list may be as long as the file: it is read once,
/// and a problem past the listed ones is only counted.
fn check_must_hit(scene: &Scene, out: &mut Issues) {
    let poses = scene.moving_bodies.first().map_or(0, |b| b.poses.len());
    let mut listed = vec![false; poses];
    for (k, &i) in scene.must_hit_poses.iter().enumerate() {
        if i >= poses {
            out.error_with(|| {
                let message = format!(
                    "there is no pose {i}: the moving bodies have {poses} poses, numbered from 0 to {}",
                    poses.max(1) - 1
                );
                (format!("must_hit_poses[{k}]"), message)
            });
        } else if std::mem::replace(&mut listed[i], true) {
            out.warning_with(|| (format!("must_hit_poses[{k}]"), format!("pose {i} is listed twice; once is enough")));
        }
    }
}

/// Pinned joints: a name a design could use, a place within the coordinate bound.
fn check_pinned_joints(scene: &Scene, out: &mut Issues) {
    for (name, p) in &scene.pinned_joints {
        let field = format!("pinned_joints.{name}");
        if name.is_empty() || name.len() > MAX_JOINT_NAME || !name.chars().all(|c| c.is_ascii_alphanumeric()) {
            out.error(
                field,
                "a joint's name is a few letters and digits, as in a design's mechanism.joints (q0, r0, p1)",
            );
        } else if !(p.x.is_finite() && p.y.is_finite() && p.x.abs() <= MAX_COORDINATE && p.y.abs() <= MAX_COORDINATE) {
            out.error(field, format!("the place must be two finite numbers of at most {MAX_COORDINATE:e} in size"));
        }
    }
}

/// The longest joint name a pin may give (the longest any family uses is three characters).
const MAX_JOINT_NAME: usize = 8;

/// The soft-cost weights must be usable factors of a sum, and not all zero (then every design ties).
fn check_weights(w: &Weights, out: &mut Issues) {
    let defaults = Weights::default();
    let all = [
        ("accuracy", w.accuracy, defaults.accuracy),
        ("smoothness", w.smoothness, defaults.smoothness),
        ("location", w.location, defaults.location),
        ("size", w.size, defaults.size),
        ("transmission", w.transmission, defaults.transmission),
    ];
    for (name, v, default) in all {
        if !v.is_finite() || v < 0.0 {
            out.error(
                format!("weights.{name}"),
                format!("is {v}; a weight must be a finite number ≥ 0 (default {default})"),
            );
        }
    }
    if all.iter().all(|&(_, v, _)| v == 0.0) {
        out.error("weights", "all the weights are 0, so every design would cost the same; make at least one positive");
    }
    out.unknown_fields("weights.", &w.extra);
}

/// The search settings must describe a run that can end and whose noise makes sense.
fn check_settings(s: &Settings, out: &mut Issues) {
    if s.samples == 0 || s.samples > MAX_SAMPLES {
        out.error(
            "settings.samples",
            format!("is {}; use between 1 and {MAX_SAMPLES} (the paper uses 100000)", s.samples),
        );
    }
    if s.particles == 0 || s.particles > MAX_PARTICLES {
        out.error(
            "settings.particles",
            format!("is {}; use between 1 and {MAX_PARTICLES} (the paper uses 100)", s.particles),
        );
    }
    if s.iterations > MAX_ITERATIONS {
        out.error(
            "settings.iterations",
            format!("is {}; use at most {MAX_ITERATIONS} (the paper uses 20)", s.iterations),
        );
    }
    let ranges = [
        (
            "pose_tolerance",
            s.pose_tolerance,
            0.0,
            MAX_POSE_TOLERANCE,
            "a fraction of the body size; the paper uses 0.5",
        ),
        ("angle_tolerance_deg", s.angle_tolerance_deg, 0.0, MAX_ANGLE_TOLERANCE_DEG, "degrees; the paper uses 3"),
        ("min_transmission_deg", s.min_transmission_deg, 0.0, MAX_MIN_TRANSMISSION_DEG, "degrees; the paper uses 10"),
        (
            "comfortable_transmission_deg",
            s.comfortable_transmission_deg,
            0.0,
            MAX_MIN_TRANSMISSION_DEG,
            "degrees; the default is 30",
        ),
    ];
    for (name, v, lo, hi, hint) in ranges {
        if !(v.is_finite() && (lo..=hi).contains(&v)) {
            out.error(format!("settings.{name}"), format!("is {v}; use a number between {lo} and {hi} ({hint})"));
        }
    }
    out.unknown_fields("settings.", &s.extra);
}

/// The sampling's work, samples × bodies × poses, within [`MAX_SAMPLE_POSES`].
fn check_work(scene: &Scene, out: &mut Issues) {
    let (k, n) = (scene.moving_bodies.len(), scene.moving_bodies.iter().map(|b| b.poses.len()).max().unwrap_or(0));
    let samples = scene.settings.samples;
    // A count beyond `MAX_SAMPLES` is reported by the settings' own check.
    if k * n > 0 && samples <= MAX_SAMPLES && samples.saturating_mul(k * n) > MAX_SAMPLE_POSES {
        out.error(
            "settings.samples",
            format!(
                "is {samples} for {k} moving bodies through {n} poses: every sample is fitted through each \
                 body's poses, and at most {MAX_SAMPLE_POSES} body-poses are supported in one run; use at \
                 most {} samples, or fewer poses",
                MAX_SAMPLE_POSES / (k * n)
            ),
        );
    }
}

/// A body outline placed in the world, ready for contact tests.
struct Placed {
    /// How messages name it: `body 'bed'`, `fixed body 'wall'`, or its path when it has no name.
    label: String,
    outline: Polygon,
    /// The body size d: the shorter side of the outline's bounding box.
    size: f64,
}

impl Placed {
    /// `outline` (in its own frame) placed by `pose`; d is measured in the body's own frame, as the
    /// engine measures it, so that turning a body does not change its tolerance.
    fn new(label: String, outline: Polygon, pose: &Rigid) -> Placed {
        let bb = outline.aabb();
        Placed { label, size: bb.width().min(bb.height()), outline: outline.transformed(pose) }
    }
}

/// At every pose, a moving body must not overlap a fixed body or another moving body (the poses are
/// what the person asks for, so an overlap there can never be built). Touching is fine and common (a
/// bed resting on its frame), so it only warns.
fn check_collisions(scene: &Scene, fixed_ok: &[bool], moving_ok: &[bool], out: &mut Issues) {
    let fixed: Vec<Placed> = scene
        .fixed_bodies
        .iter()
        .enumerate()
        .filter(|&(j, _)| fixed_ok[j])
        .map(|(j, b)| {
            let name = label("fixed body", &b.name, &format!("fixed_bodies[{j}]"));
            Placed::new(name, Polygon::new(b.polygon.clone()), &Rigid::IDENTITY)
        })
        .collect();
    let pose_count = scene.moving_bodies.iter().map(|b| b.poses.len()).max().unwrap_or(0);
    // The engine's contact tolerance (see `Problem::contact_tolerance`).
    let contact = super::CONTACT_FRACTION
        * scene
            .moving_bodies
            .iter()
            .zip(moving_ok)
            .filter(|(_, ok)| **ok)
            .map(|(b, _)| Placed::new(String::new(), Polygon::new(b.polygon.clone()), &Rigid::IDENTITY).size)
            .fold(f64::INFINITY, f64::min);
    for i in 0..pose_count {
        let placed: Vec<(usize, Placed)> = scene
            .moving_bodies
            .iter()
            .enumerate()
            .filter(|&(k, b)| moving_ok[k] && b.poses.get(i).is_some_and(pose_is_usable))
            .map(|(k, b)| {
                let name = label("body", &b.name, &format!("moving_bodies[{k}]"));
                (k, Placed::new(name, Polygon::new(b.polygon.clone()), &Rigid::from_pose(b.poses[i])))
            })
            .collect();
        for (n, (k, body)) in placed.iter().enumerate() {
            let field = format!("moving_bodies[{k}].poses[{i}]");
            for other in fixed.iter().chain(placed[n + 1..].iter().map(|(_, p)| p)) {
                report_contact(&field, i, body, other, contact, out);
            }
        }
    }
}

/// Reports an overlap (error) or a touch (warning) between `a` and `b` at pose `i`. An overlap is
/// exactly what the engine's collision check refuses ([`Polygon::penetrates`] with the scene's contact
/// tolerance `contact`), so no scene passes validation only to have every linkage rejected at a pose.
fn report_contact(field: &str, i: usize, a: &Placed, b: &Placed, contact: f64, out: &mut Issues) {
    let tol = TOUCH_FRACTION * a.size.min(b.size);
    let Some(separation) = separation(&a.outline, &b.outline, tol) else { return };
    let (what, by) = if separation < 0.0 { ("overlap", -separation) } else { ("gap", separation) };
    let pose = i + 1;
    if a.outline.penetrates(&b.outline, contact) {
        out.error(
            field,
            format!(
                "{} overlaps {} at pose {pose} by about {by:.2} mm; move the pose or reshape the bodies",
                a.label, b.label
            ),
        );
    } else if separation <= tol {
        out.warning(
            field,
            format!(
                "{} touches {} at pose {pose} ({what} of about {by:.2} mm, within the drawing tolerance of \
                 {tol:.2} mm); fine if one rests on the other, otherwise move the pose apart",
                a.label, b.label
            ),
        );
    }
}

/// The signed distance between `a` and `b`: the gap between them when apart, minus how far they reach
/// into each other when they overlap, or `None` when their bounding boxes are farther apart than `tol`.
///
/// The overlap depth is the largest distance from a boundary point of one polygon lying inside the other
/// to that other's boundary, so a sliver of drawing slack along a shared edge measures as thin as it is,
/// while a crossing bar measures as deep as it reaches (for a deep overlap it can be less than the
/// distance a body must move to come free: enough to say "about", exact where it decides). Boundary
/// points are sampled every `tol / 4` along the part of each edge inside the other's bounding box
/// (vertices included); depth along a line changes no faster than the line, so the estimate is at most
/// `tol / 8` low.
fn separation(a: &Polygon, b: &Polygon, tol: f64) -> Option<f64> {
    if !a.aabb().overlaps(&b.aabb(), -tol) {
        return None;
    }
    let depth = reach(a, b, tol / 4.0).max(reach(b, a, tol / 4.0));
    if depth > 0.0 {
        return Some(-depth);
    }
    // Apart or touching: no edges cross, so the closest points include a vertex of one of them.
    let gap =
        |p: &Polygon, q: &Polygon| p.vertices().iter().map(|&v| q.boundary_distance(v)).fold(f64::INFINITY, f64::min);
    Some(gap(a, b).min(gap(b, a)))
}

/// Upper bound of samples per edge, so that no polygon can stall validation.
const MAX_SAMPLES_PER_EDGE: usize = 4096;

/// How far the outline of `a` reaches into `b` (0 when it does not): see [`separation`].
fn reach(a: &Polygon, b: &Polygon, step: f64) -> f64 {
    let bb = b.aabb();
    let mut deepest = 0.0f64;
    for (p, q) in a.edges() {
        let Some((s, e)) = clip_to_box(p, q, &bb) else { continue };
        let n = ((e - s).norm() / step).ceil().clamp(1.0, MAX_SAMPLES_PER_EDGE as f64) as usize;
        for j in 0..=n {
            let x = s.lerp(e, j as f64 / n as f64);
            if b.contains(x) {
                deepest = deepest.max(b.boundary_distance(x));
            }
        }
    }
    deepest
}

/// The part of segment `p`–`q` inside `bb` (Liang–Barsky), or `None` when it misses the box.
fn clip_to_box(p: Point, q: Point, bb: &Aabb) -> Option<(Point, Point)> {
    let d = q - p;
    let (mut t0, mut t1) = (0.0f64, 1.0f64);
    for (delta, lo, hi) in [(d.x, bb.min.x - p.x, bb.max.x - p.x), (d.y, bb.min.y - p.y, bb.max.y - p.y)] {
        if delta == 0.0 {
            if lo > 0.0 || hi < 0.0 {
                return None;
            }
            continue;
        }
        let (a, b) = (lo / delta, hi / delta);
        t0 = t0.max(a.min(b));
        t1 = t1.min(a.max(b));
    }
    (t0 <= t1).then(|| (p.lerp(q, t0), p.lerp(q, t1)))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A small valid scene: a 200 × 20 ground and a 20 × 80 body visiting two poses well clear of it.
    fn scene() -> Scene {
        Scene::from_json(
            r#"{
              "linkwright": "scene/1", "name": "test",
              "fixed_bodies": [{"name": "ground", "polygon": [[0, 0], [200, 0], [200, 20], [0, 20]]}],
              "moving_bodies": [{"name": "lid", "polygon": [[0, 0], [20, 0], [20, 80], [0, 80]],
                                 "poses": [[50, 100, 0], [120, 60, -90]]}]
            }"#,
        )
        .unwrap()
    }

    fn rect(x0: f64, y0: f64, x1: f64, y1: f64) -> Vec<Point> {
        [[x0, y0], [x1, y0], [x1, y1], [x0, y1]].into_iter().map(Point::from).collect()
    }

    /// The issues of `severity` on `field`.
    fn on(issues: &[Issue], severity: Severity, field: &str) -> Vec<String> {
        issues.iter().filter(|i| i.severity == severity && i.field == field).map(|i| i.message.clone()).collect()
    }

    /// Asserts that validation reports exactly one error on `field`, containing `phrase`.
    fn assert_error(s: &Scene, field: &str, phrase: &str) {
        let issues = validate(s);
        let errors = on(&issues, Severity::Error, field);
        assert!(errors.len() == 1 && errors[0].contains(phrase), "no error '{phrase}' on {field}: {issues:#?}");
    }

    fn errors(s: &Scene) -> Vec<Issue> {
        validate(s).into_iter().filter(|i| i.severity == Severity::Error).collect()
    }

    #[test]
    fn a_valid_scene_has_no_issue() {
        assert_eq!(validate(&scene()), vec![]);
    }

    /// A regular polygon of `n` vertices around (`cx`, `cy`).
    fn round(n: usize, cx: f64, cy: f64, r: f64) -> Vec<Point> {
        let at = |i: usize| std::f64::consts::TAU * i as f64 / n as f64;
        (0..n).map(|i| Point::new(cx + r * at(i).cos(), cy + r * at(i).sin())).collect()
    }

    #[test]
    fn outlines_are_bounded_in_vertices() {
        let mut s = scene();
        s.fixed_bodies[0].polygon = round(MAX_OUTLINE_VERTICES, 100.0, -60.0, 50.0);
        assert_eq!(errors(&s), vec![]);
        s.fixed_bodies[0].polygon = round(MAX_OUTLINE_VERTICES + 1, 100.0, -60.0, 50.0);
        assert_error(&s, "fixed_bodies[0].polygon", "has 501 vertices; at most 500");
        // Thirty thousand vertices in all are refused before any quadratic check looks at them.
        s.fixed_bodies[0].polygon = round(400, 100.0, -60.0, 50.0);
        s.avoid_regions = (0..5).map(|i| round(400, 300.0 + 120.0 * i as f64, 300.0, 50.0)).collect();
        assert_error(&s, "fixed_bodies[0].polygon", "have 2404 vertices in all");
        s.avoid_regions = (0..60).map(|i| round(40, 300.0 + 120.0 * i as f64, 300.0, 50.0)).collect();
        let issues = errors(&s);
        assert!(issues.len() == 2 && issues.iter().all(|i| i.message.contains("supported")), "{issues:#?}");
    }

    #[test]
    fn bodies_regions_and_poses_are_bounded_in_number() {
        let mut s = scene();
        s.avoid_regions = (0..=MAX_AVOID_REGIONS)
            .map(|i| rect(300.0 + 30.0 * i as f64, 0.0, 310.0 + 30.0 * i as f64, 10.0))
            .collect();
        assert_error(&s, "avoid_regions", "has 51 avoid regions; at most 50");
        s.avoid_regions.pop();
        assert_eq!(errors(&s), vec![]);
        let lid = s.moving_bodies[0].clone();
        s.moving_bodies = vec![lid.clone(); MAX_MOVING_BODIES + 1];
        assert!(errors(&s).iter().any(|i| i.field == "moving_bodies" && i.message.contains("has 9 moving bodies")));
        s.moving_bodies = vec![lid];
        let (a, b) = (s.moving_bodies[0].poses[0], s.moving_bodies[0].poses[1]);
        s.moving_bodies[0].poses = (0..=MAX_POSES).map(|i| if i % 2 == 0 { a } else { b }).collect();
        assert_error(&s, "moving_bodies[0].poses", "has 21 poses; at most 20");
    }

    #[test]
    fn the_sampling_work_is_bounded() {
        // One body through two poses: a million samples are 2·10⁶ body-poses, within the bound.
        let mut s = scene();
        s.settings.samples = MAX_SAMPLES;
        assert_eq!(errors(&s), vec![]);
        // Through twenty poses they are 2·10⁷: half as many samples fit.
        let (a, b) = (s.moving_bodies[0].poses[0], s.moving_bodies[0].poses[1]);
        s.moving_bodies[0].poses = (0..20).map(|i| if i % 2 == 0 { a } else { b }).collect();
        assert_error(&s, "settings.samples", "use at most 500000 samples");
        s.settings.samples = 500_000;
        assert!(errors(&s).iter().all(|i| i.field != "settings.samples"));
    }

    #[test]
    fn the_drawing_is_bounded_in_size_against_its_smallest_body() {
        // The lid is 20 across: a ground 950 times as wide passes, one 1500 times as wide does not.
        let mut s = scene();
        s.fixed_bodies[0].polygon = rect(0.0, 0.0, 19_000.0, 20.0);
        assert_eq!(errors(&s), vec![]);
        s.fixed_bodies[0].polygon = rect(0.0, 0.0, 30_000.0, 20.0);
        assert_error(&s, "moving_bodies[0].polygon", "spans 30000: 1500 times as much");
        // And nothing is drawn a kilometre away, whatever its size.
        let mut s = scene();
        s.moving_bodies[0].poses[1] = [2e6, 60.0, 0.0];
        assert_error(&s, "moving_bodies[0].poses[1]", "within ±1e6");
    }

    #[test]
    fn names_are_short_and_free_of_control_characters() {
        let mut s = scene();
        s.name = "\u{1b}[2J".into();
        assert_error(&s, "name", "control characters");
        s.name = "x".repeat(MAX_NAME_CHARS + 1);
        assert_error(&s, "name", "longer than 100");
        let mut s = scene();
        s.moving_bodies[0].name = "lid\u{1b}]0;x\u{7}".into();
        s.fixed_bodies[0].name = "ground\n".into();
        assert_error(&s, "moving_bodies[0].name", "control characters");
        assert_error(&s, "fixed_bodies[0].name", "control characters");
    }

    #[test]
    fn unknown_format_is_an_error() {
        let mut s = scene();
        s.linkwright = "scene/2".into();
        assert_error(&s, "linkwright", "unknown format \"scene/2\"");
    }

    #[test]
    fn units_must_be_a_length_this_version_knows() {
        let mut s = scene();
        s.units = "furlongs".into();
        assert_error(
            &s,
            "units",
            "is \"furlongs\", not a unit of length this version knows; use mm, cm, m, in, ft or µm",
        );
        s.units = " Inches".into();
        assert_eq!(errors(&s), vec![]);
        let problem = crate::Problem::new(&s).unwrap();
        assert_eq!((problem.units.as_str(), problem.units.millimetres()), (" Inches", 25.4));
    }

    #[test]
    fn a_scene_needs_a_moving_body() {
        let mut s = scene();
        s.moving_bodies.clear();
        assert_error(&s, "moving_bodies", "add at least one");
    }

    #[test]
    fn a_body_needs_two_poses() {
        let mut s = scene();
        s.moving_bodies[0].poses.truncate(1);
        assert_error(&s, "moving_bodies[0].poses", "has 1 pose(s); a motion needs at least 2");
    }

    #[test]
    fn bodies_need_the_same_number_of_poses() {
        let mut s = scene();
        let mut other = s.moving_bodies[0].clone();
        other.name = "flap".into();
        other.poses = vec![[300.0, 100.0, 0.0], [330.0, 100.0, 0.0], [360.0, 100.0, 0.0]];
        s.moving_bodies.push(other);
        assert_error(&s, "moving_bodies[1].poses", "body 'flap' has 3 poses but body 'lid' has 2");
    }

    #[test]
    fn bad_polygons_are_errors_wherever_they_are() {
        let mut s = scene();
        s.fixed_bodies[0].polygon.truncate(2);
        s.moving_bodies[0].polygon[1].x = f64::NAN;
        s.linkage_region = Some(vec![Point::new(0.0, 0.0), Point::new(1.0, 1.0), Point::new(2.0, 2.0)]);
        s.avoid_regions =
            vec![rect(0.0, 0.0, 1.0, 1.0), [[0., 0.], [2., 2.], [2., 0.], [0., 1.]].map(Point::from).to_vec()];
        assert_error(&s, "fixed_bodies[0].polygon", "has 2 vertices; a polygon needs at least 3");
        assert_error(&s, "moving_bodies[0].polygon", "vertex 1 is not a finite number");
        assert_error(&s, "linkage_region", "zero area");
        assert_error(&s, "avoid_regions[1]", "crosses itself");
        assert_eq!(errors(&s).len(), 4, "{:#?}", errors(&s));
    }

    #[test]
    fn non_finite_or_huge_numbers_are_errors() {
        let mut s = scene();
        s.moving_bodies[0].poses[1][2] = f64::INFINITY;
        s.fixed_bodies[0].polygon[2].y = 1e300;
        assert_error(&s, "moving_bodies[0].poses[1]", "pose 2 is [120.0, 60.0, inf]; write three finite numbers");
        assert_error(&s, "fixed_bodies[0].polygon", "scale the drawing down");
    }

    #[test]
    fn a_scene_without_a_fixed_body_is_warned_about() {
        let mut s = scene();
        s.fixed_bodies.clear();
        let issues = validate(&s);
        assert!(issues.iter().all(|i| i.severity == Severity::Warning), "{issues:?}");
        assert!(issues.iter().any(|i| i.field == "fixed_bodies" && i.message.contains("no fixed body")), "{issues:?}");
    }

    #[test]
    fn gravity_is_a_direction() {
        let mut s = scene();
        s.gravity = Some([0.0, 0.0]);
        assert_error(&s, "gravity", "give the direction gravity pulls in");
        s.gravity = Some([f64::NAN, 1.0]);
        assert_error(&s, "gravity", "give the direction gravity pulls in");
        s.gravity = Some([3.0, 4.0]);
        assert_eq!(errors(&s), vec![]);
        let problem = crate::scene::Problem::new(&s).unwrap();
        assert!((problem.gravity - crate::geom::Vec2::new(0.6, 0.8)).norm() < 1e-15);
    }

    #[test]
    fn pinned_joints_have_names_and_finite_places() {
        let mut s = scene();
        s.pinned_joints.insert("q 0".into(), Point::new(1.0, 2.0));
        assert_error(&s, "pinned_joints.q 0", "letters and digits");
        s.pinned_joints.clear();
        s.pinned_joints.insert("q0".into(), Point::new(f64::NAN, 2.0));
        assert_error(&s, "pinned_joints.q0", "finite");
        s.pinned_joints.insert("q0".into(), Point::new(1.0, 2.0));
        assert_eq!(errors(&s), vec![]);
        let problem = crate::scene::Problem::new(&s).unwrap();
        assert_eq!(problem.pinned, vec![("q0".to_string(), Point::new(1.0, 2.0))]);
    }

    #[test]
    fn must_hit_poses_are_poses_the_bodies_have() {
        let mut s = scene();
        let poses = s.moving_bodies[0].poses.len();
        s.must_hit_poses = vec![1, 1, poses];
        assert_error(&s, "must_hit_poses[2]", &format!("there is no pose {poses}"));
        let issues = validate(&s);
        assert!(issues.iter().any(|i| i.field == "must_hit_poses[1]" && i.severity == Severity::Warning), "{issues:?}");
        s.must_hit_poses = vec![1];
        assert_eq!(errors(&s), vec![]);
        let problem = crate::scene::Problem::new(&s).unwrap();
        assert_eq!(problem.must_hit, (0..poses).map(|i| i == 0 || i == 1 || i == poses - 1).collect::<Vec<_>>());
    }

    #[test]
    fn a_mistake_repeated_throughout_a_large_file_gets_a_short_answer() {
        // A 1 MB scene naming a pose the bodies lack 340,000 times, with a warning at its start.
        let mut s = scene();
        s.must_hit_poses = vec![3; 340_000];
        s.must_hit_poses[..2].copy_from_slice(&[1, 1]);
        let issues = validate(&s);
        assert_eq!(issues.len(), crate::MAX_LISTED_ISSUES);
        assert_eq!((issues.total(), issues.more()), (340_000 - 1, 340_000 - 1 - crate::MAX_LISTED_ISSUES));
        // Errors are not crowded out by the warning found first.
        assert!(issues.iter().all(|i| i.severity == Severity::Error), "{:?}", &issues[..3]);
        assert_eq!(issues[0].field, "must_hit_poses[2]");
        let Err(refused) = crate::scene::Problem::new(&s) else { panic!("the scene is refused") };
        assert_eq!(refused.total(), issues.total());
    }

    #[test]
    fn a_bow_tie_is_refused_as_crossing_and_a_sliver_as_too_thin() {
        let mut s = scene();
        s.moving_bodies[0].polygon = [[0., 0.], [20., 80.], [20., 0.], [0., 80.]].map(Point::from).to_vec();
        assert_error(&s, "moving_bodies[0].polygon", "crosses itself (edge 0 crosses edge 2)");
        let mut s = scene();
        s.fixed_bodies[0].polygon = rect(0.0, 0.0, 1000.0, 1e-6);
        assert_error(&s, "fixed_bodies[0].polygon", "is too thin: about 1.0e-6 wide for 1.0e3 long");
        assert!(!errors(&s).iter().any(|i| i.message.contains("one line")), "{:?}", errors(&s));
    }

    #[test]
    fn a_pinned_joint_far_away_is_named_itself() {
        let mut s = scene();
        s.pinned_joints.insert("q0".into(), Point::new(1e6, 0.0));
        assert_error(&s, "pinned_joints.q0", "is at [1000000, 0], so far from the drawing");
        assert_eq!(errors(&s).len(), 1, "{:?}", errors(&s));
    }

    #[test]
    fn pinned_joints_are_at_most_as_many_as_a_linkage_has_joints() {
        let mut s = scene();
        s.pinned_joints = (0..10_000).map(|i| (format!("q{i}"), Point::new(60.0, 30.0))).collect();
        let issues = validate(&s);
        assert_eq!(issues.total(), 1, "{issues:?}");
        assert_eq!(issues[0].field, "pinned_joints");
        assert!(issues[0].message.starts_with("has 10000 pinned joints; at most 256 are supported"), "{}", issues[0]);
        assert!(issues[0].message.len() < 200);
        s.pinned_joints = (0..256).map(|i| (format!("q{i}"), Point::new(60.0, 30.0))).collect();
        assert_eq!(errors(&s), vec![]);
    }

    #[test]
    fn gravity_of_an_absurd_length_is_refused_and_any_other_normalised_exactly() {
        let mut s = scene();
        for g in [[1e-200, -1e-200], [1e160, -1e160], [1e-4, 0.0], [0.0, -2e4]] {
            s.gravity = Some(g);
            assert_error(&s, "gravity", "of a length from 1e-3 to 1e4");
        }
        for (g, scale) in [([1e-3, -1e-3], 1e-3), ([7e3, -7e3], 7e3), ([0.6, -0.6], 0.6)] {
            s.gravity = Some(g);
            let problem = crate::scene::Problem::new(&s).unwrap();
            let unit = crate::geom::Vec2::new(1.0, -1.0) / 2f64.sqrt();
            assert!((problem.gravity - unit).norm() < 1e-15, "{scale}: {:?}", problem.gravity);
        }
    }

    #[test]
    fn slider_crank_needs_exactly_one_body() {
        let mut s = scene();
        s.mechanism = MechanismChoice::Only(MechanismType::SliderCrank);
        assert_eq!(errors(&s), vec![]);
        s.moving_bodies.clear();
        assert_error(&s, "mechanism", "slider_crank moves exactly one body but the scene has 0");
    }

    #[test]
    fn settings_out_of_range_are_errors() {
        type Change = fn(&mut Settings);
        let cases: [(&str, Change); 12] = [
            ("samples", |s| s.samples = 0),
            ("samples", |s| s.samples = 10_000_001),
            ("particles", |s| s.particles = 0),
            ("iterations", |s| s.iterations = 1001),
            ("pose_tolerance", |s| s.pose_tolerance = -0.1),
            ("pose_tolerance", |s| s.pose_tolerance = f64::NAN),
            ("angle_tolerance_deg", |s| s.angle_tolerance_deg = 91.0),
            ("min_transmission_deg", |s| s.min_transmission_deg = 80.5),
            ("min_transmission_deg", |s| s.min_transmission_deg = -1.0),
            ("min_transmission_deg", |s| s.min_transmission_deg = f64::INFINITY),
            ("comfortable_transmission_deg", |s| s.comfortable_transmission_deg = 90.0),
            ("comfortable_transmission_deg", |s| s.comfortable_transmission_deg = f64::NAN),
        ];
        for (name, change) in cases {
            let mut s = scene();
            change(&mut s.settings);
            assert_error(&s, &format!("settings.{name}"), "; use ");
        }
        let mut s = scene();
        s.settings.pose_tolerance = 0.0;
        s.settings.iterations = 0;
        assert_eq!(errors(&s), vec![], "hitting every pose exactly is allowed");
    }

    #[test]
    fn weights_must_be_finite_non_negative_and_not_all_zero() {
        let mut s = scene();
        s.weights.accuracy = -1.0;
        s.weights.size = f64::NAN;
        assert_error(&s, "weights.accuracy", "must be a finite number ≥ 0 (default 10000)");
        assert_error(&s, "weights.size", "must be a finite number ≥ 0");
        let mut s = scene();
        let w = &mut s.weights;
        (w.accuracy, w.smoothness, w.location, w.size, w.transmission) = (0.0, 0.0, 0.0, 0.0, 0.0);
        assert_error(&s, "weights", "all the weights are 0");
        s.weights.transmission = -0.5;
        assert_error(&s, "weights.transmission", "must be a finite number ≥ 0");
    }

    /// The lid (d = 20) standing on the ground at its second pose, `offset` mm above it (negative: sunk in).
    fn lid_on_ground(offset: f64) -> Scene {
        let mut s = scene();
        s.moving_bodies[0].poses[1] = [100.0, 20.0 + offset, 0.0];
        s
    }

    #[test]
    fn a_body_overlapping_a_fixed_body_at_a_pose_is_an_error() {
        // 5% of d = 1 mm deep.
        assert_error(
            &lid_on_ground(-1.0),
            "moving_bodies[0].poses[1]",
            "body 'lid' overlaps fixed body 'ground' at pose 2 by about 1.00 mm",
        );
        // A corner dipping 1 mm in: d is the lid's own 20 mm, not the side of its turned bounding box.
        let mut s = scene();
        s.moving_bodies[0].poses[1] = [100.0, 19.0, 45.0];
        assert_error(&s, "moving_bodies[0].poses[1]", "overlaps fixed body 'ground' at pose 2 by about 1.00 mm");
        // Entirely inside, no edges crossing.
        let mut s = scene();
        s.fixed_bodies[0].polygon = rect(0.0, 0.0, 400.0, 400.0);
        let issues = on(&validate(&s), Severity::Error, "moving_bodies[0].poses[0]");
        assert!(issues[0].contains("overlaps"), "{issues:?}");
    }

    #[test]
    fn bodies_that_only_touch_give_a_warning() {
        // The engine's contact tolerance for a 20 mm body is 0.02 mm: a 0.01 mm dip only touches.
        for offset in [0.0, -0.01, 0.1] {
            let issues = validate(&lid_on_ground(offset));
            assert!(on(&issues, Severity::Error, "moving_bodies[0].poses[1]").is_empty(), "{offset}: {issues:#?}");
            let w = on(&issues, Severity::Warning, "moving_bodies[0].poses[1]");
            assert!(w.len() == 1 && w[0].contains("touches fixed body 'ground' at pose 2"), "{offset}: {issues:#?}");
        }
        assert_eq!(validate(&lid_on_ground(1.0)), vec![], "1 mm apart is clear of a 20 mm body");
        // 0.1 mm deep is beyond the engine's tolerance, which would refuse every linkage at that pose.
        assert!(!on(&validate(&lid_on_ground(-0.1)), Severity::Error, "moving_bodies[0].poses[1]").is_empty());
    }

    #[test]
    fn moving_bodies_overlapping_each_other_at_a_pose_is_an_error() {
        let mut s = scene();
        // A bar crossing the lid at its first pose: edges cross, no vertex of either lies inside the other.
        let bar = MovingBody {
            name: "bar".into(),
            polygon: rect(-10.0, 0.0, 40.0, 10.0),
            poses: vec![[30.0, 130.0, 0.0], [300.0, 100.0, 0.0]],
            path: None,
            mass_kg: None,
            material: None,
            thickness: None,
            extra: Map::new(),
        };
        s.moving_bodies.push(bar);
        assert_error(&s, "moving_bodies[0].poses[0]", "body 'lid' overlaps body 'bar' at pose 1 by about");
        assert_eq!(errors(&s).len(), 1);
    }

    #[test]
    fn bodies_with_bad_outlines_are_not_collision_checked() {
        let mut s = lid_on_ground(-10.0);
        s.fixed_bodies[0].polygon.push(Point::new(100.0, -50.0)); // now crosses itself
        assert_eq!(errors(&s).iter().map(|i| i.field.as_str()).collect::<Vec<_>>(), ["fixed_bodies[0].polygon"]);
    }

    #[test]
    fn unknown_fields_are_warnings() {
        let s = Scene::from_json(
            r#"{"linkwright": "scene/1", "colour": "red",
                "fixed_bodies": [{"name": "ground", "polygon": [[0, 0], [200, 0], [200, 20], [0, 20]], "mass": 3}],
                "moving_bodies": [{"name": "lid", "polygon": [[0, 0], [20, 0], [20, 80], [0, 80]], "speed": 1,
                                   "poses": [[50, 100, 0], [120, 60, -90]]}],
                "weights": {"beauty": 2}, "setings": {}, "settings": {"threads": 4}}"#,
        )
        .unwrap();
        let issues = validate(&s);
        for field in [
            "colour",
            "setings",
            "fixed_bodies[0].mass",
            "moving_bodies[0].speed",
            "weights.beauty",
            "settings.threads",
        ] {
            let w = on(&issues, Severity::Warning, field);
            let key = field.rsplit(['.']).next().unwrap();
            assert!(
                w.len() == 1 && w[0].contains(&format!("unknown field '{key}' is ignored")),
                "{field}: {issues:#?}"
            );
        }
        assert_eq!(issues.len(), 6);
    }

    #[test]
    fn scenes_from_json_text() {
        // The example of the format description.
        let wall_bed = r#"{
          "linkwright": "scene/1", "name": "wall bed", "units": "mm",
          "fixed_bodies": [{"name": "wall", "polygon": [[0, 0], [200, 0], [200, 20], [0, 20]]}],
          "moving_bodies": [{"name": "bed", "polygon": [[0, 0], [17, 0], [17, 85], [0, 85]],
                             "poses": [[1.0, 123.2, 0.0], [119.5, 52.7, -90.2]]}],
          "linkage_region": [[-50, 0], [40, 0], [40, 200], [-50, 200]],
          "avoid_regions": [[[0, -50], [300, -50], [300, -5], [0, -5]]],
          "mechanism": "auto",
          "weights": {"accuracy": 1, "smoothness": 1, "location": 10, "size": 1},
          "settings": {"seed": 0, "samples": 100000, "particles": 100, "iterations": 20,
                       "pose_tolerance": 0.5, "angle_tolerance_deg": 3, "min_transmission_deg": 10}
        }"#;
        assert_eq!(validate(&Scene::from_json(wall_bed).unwrap()), vec![]);
        // Two bodies of a chain resting on each other, one of them unnamed, plus a few mistakes at once.
        let chain = r#"{
          "linkwright": "scene/1", "mechanism": "slider_crank",
          "fixed_bodies": [{"name": "base", "polygon": [[0, 0], [100, 0], [100, 10], [0, 10]]}],
          "moving_bodies": [
            {"name": "a", "polygon": [[0, 0], [30, 0], [30, 10], [0, 10]], "poses": [[0, 10, 0], [0, 40, 0]]},
            {"polygon": [[0, 0], [30, 0], [30, 10], [0, 10]], "poses": [[30, 10, 0], [30, 40, 0], [30, 80, 0]]}],
          "settings": {"samples": 0}
        }"#;
        let issues = validate(&Scene::from_json(chain).unwrap());
        let fields: Vec<(Severity, &str)> = issues.iter().map(|i| (i.severity, i.field.as_str())).collect();
        use Severity::{Error, Warning};
        assert_eq!(
            fields,
            [
                (Error, "moving_bodies[1].poses"),
                (Error, "mechanism"),
                (Error, "settings.samples"),
                (Warning, "moving_bodies[0].poses[0]"),
                (Warning, "moving_bodies[0].poses[0]"),
                (Warning, "moving_bodies[1].poses[0]"),
                (Warning, "moving_bodies[0].poses[1]"),
            ],
            "{issues:#?}"
        );
        assert!(issues[0].message.starts_with("moving_bodies[1] has 3 poses but body 'a' has 2"));
        assert!(issues[4].message.contains("body 'a' touches moving_bodies[1] at pose 1"));
    }

    #[test]
    fn never_panics_on_wild_numbers() {
        let wild = [f64::NAN, f64::INFINITY, f64::NEG_INFINITY, 1e308, -1e308, 0.0, f64::MIN_POSITIVE];
        for &v in &wild {
            let mut s = scene();
            s.fixed_bodies[0].polygon[1].x = v;
            s.moving_bodies[0].polygon[2] = Point::new(v, v);
            s.moving_bodies[0].poses[0] = [v, v, v];
            s.linkage_region = Some(vec![Point::new(v, 0.0); 3]);
            s.avoid_regions = vec![vec![], vec![Point::new(v, v); 5]];
            s.weights.location = v;
            s.settings.pose_tolerance = v;
            s.settings.samples = usize::MAX;
            let _ = validate(&s);
        }
        let mut s = scene();
        s.fixed_bodies[0].polygon.clear();
        s.moving_bodies[0].polygon.clear();
        s.moving_bodies[0].poses.clear();
        assert!(!errors(&s).is_empty());
    }
}

//! An independent re-simulation of a mechanism's travel against its scene: every hard constraint and
//! the accuracy, recomputed with plain polygon tests at finer steps (none of the engine's
//! sweep code), so the engine's answers can be checked: by the `check` of a design file
//! ([`crate::design::DesignFile::violations`]), and by the synthesis on every design it returns.

use crate::geom::{path_error, PathError, Point, Polygon};
use crate::kinematics::{BodyFrames, Plan, Trace};
use crate::mechanism::Mechanism;
use crate::scene::{PoseMiss, Problem};

/// One violated constraint.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Violation {
    /// Which constraint: `format`, `pinned`, `assembly`, `order`, `transmission`, `collision`,
    /// `avoid_region`, `accuracy`.
    pub constraint: &'static str,
    /// What is wrong, with the numbers (crank angle, distance, ...) that show it.
    pub message: String,
}

/// How far a pinned joint may be from its pin, relative to the drawing's size: the engine keeps
/// pinned joints exactly; this only lets a design file's decimal numbers round.
const PIN_TOLERANCE: f64 = 1e-9;

/// Crank step of the re-simulation, degrees (finer than the engine's 1°).
const STEP_DEG: f64 = 0.5;

/// A travel of the driver, degrees, unwrapped: from `start` to `end`, passing pose i at `poses[i]`.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Travel<'a> {
    pub start: f64,
    pub end: f64,
    pub poses: &'a [f64],
}

/// Every violated hard constraint of `mechanism` moving along `travel` (empty when it is sound), and
/// the accuracy at the pose angles when the linkage assembles there.
pub(crate) fn verify_travel(
    problem: &Problem,
    mechanism: &Mechanism,
    travel: Travel,
) -> (Vec<Violation>, Option<Accuracy>) {
    let mut out = Vec::new();
    let Some(plan) = check_linkage(problem, mechanism, &mut out) else { return (out, None) };
    if !check_order(problem, mechanism, travel, &mut out) {
        return (out, None);
    }
    let trace = match sweep(&plan, travel.start, travel.end) {
        Ok(trace) => trace,
        Err(violation) => {
            out.push(violation);
            return (out, None);
        }
    };
    let min_transmission = trace.min_transmission(&plan).to_degrees();
    if min_transmission < problem.settings.min_transmission_deg - 1e-9 {
        out.push(violation(
            "transmission",
            format!(
                "a transmission angle comes {min_transmission:.2}° from 0°/180° (minimum {})",
                problem.settings.min_transmission_deg
            ),
        ));
    }
    let frames = body_frames(problem, mechanism);
    out.extend(first_contact(problem, mechanism, &trace, &frames));
    match pose_accuracy(problem, mechanism, &plan, &frames, travel.poses) {
        Ok(accuracy) => (out, Some(Accuracy { path: path_error_along(problem, &trace, &frames), ..accuracy })),
        Err(violation) => {
            out.push(violation);
            (out, None)
        }
    }
}

fn violation(constraint: &'static str, message: String) -> Violation {
    Violation { constraint, message }
}

/// The checks of the linkage alone: as many bodies as the scene, every pinned joint on its pin, and
/// a plan to simulate it, which it returns (`None` when nothing more can be checked).
fn check_linkage(problem: &Problem, mechanism: &Mechanism, out: &mut Vec<Violation>) -> Option<Plan> {
    if mechanism.topology.body_count != problem.body_count() {
        out.push(violation(
            "format",
            format!(
                "the design moves {} bodies, the scene has {}",
                mechanism.topology.body_count,
                problem.body_count()
            ),
        ));
        return None;
    }
    for (name, pin) in &problem.pinned {
        match mechanism.joint(name) {
            None => {
                out.push(violation("pinned", format!("the scene pins joint {name}, which this linkage does not have")))
            }
            Some(p) if p.distance(*pin) > PIN_TOLERANCE * problem.scale => out.push(violation(
                "pinned",
                format!("joint {name} is {:.6} from where pinned_joints puts it", p.distance(*pin)),
            )),
            Some(_) => {}
        }
    }
    match Plan::compile(mechanism) {
        Ok(plan) => Some(plan),
        Err(e) => {
            out.push(violation("assembly", e.to_string()));
            None
        }
    }
}

/// The order checks of the travel: one angle per pose, in order, from the crank's angle at the first
/// pose, within less than a turn. Returns whether the travel can be simulated: a travel that is not
/// finite or turns a full circle or more is an order defect and is not (a huge one would take forever
/// at fine steps).
fn check_order(problem: &Problem, mechanism: &Mechanism, travel: Travel, out: &mut Vec<Violation>) -> bool {
    let Travel { start, end, poses } = travel;
    if poses.len() != problem.pose_count {
        out.push(violation("order", format!("{} pose angles for {} poses", poses.len(), problem.pose_count)));
        return false;
    }
    let finite = start.is_finite() && end.is_finite() && poses.iter().all(|p| p.is_finite());
    if !finite || !problem.travel_fits(start, end) {
        let full_turn = problem.path().is_some_and(|p| p.closed);
        let wanted = if full_turn { "exactly one turn (a closed path)" } else { "less than a full turn" };
        out.push(violation("order", format!("the crank's travel {start}° → {end}° must be finite and {wanted}")));
        return false;
    }
    let dir = (end - start).signum();
    if (mechanism.crank_start().to_degrees() - start).abs() > 1e-6 {
        out.push(violation("order", format!("crank_start_deg {start} is not the crank's angle at the first pose")));
    }
    // A path's travel ends where the path does, past its one pose.
    let ends_at_last_pose = problem.path().is_none();
    if (poses[0] - start).abs() > 1e-9 || (ends_at_last_pose && (poses[poses.len() - 1] - end).abs() > 1e-9) {
        out.push(violation("order", "pose_crank_deg must start at crank_start_deg and end at crank_end_deg".into()));
    }
    if poses.windows(2).any(|w| dir * (w[1] - w[0]) <= 0.0) {
        out.push(violation("order", format!("pose_crank_deg {poses:?} is not monotone within one turn")));
    }
    true
}

/// How far the curve the tracer of `problem`'s path traces along `trace` (the travel at the
/// re-simulation's fine steps) is from the drawn curve; `None` for a scene without a path.
fn path_error_along(problem: &Problem, trace: &Trace, frames: &BodyFrames) -> Option<PathError> {
    let (b, path) = problem.bodies.iter().enumerate().find_map(|(b, body)| body.path.as_ref().map(|p| (b, p)))?;
    let mut traced: Vec<Point> = (0..trace.len()).map(|r| frames.pose(b, trace.row(r)).apply(path.tracer)).collect();
    if path.closed {
        // The last row is the first again, a turn later.
        traced.pop();
    }
    Some(path_error(&path.points, &path.exact, &traced, path.closed))
}

/// The whole travel from `start` to `end` (degrees) at fine steps, or where it comes apart.
fn sweep(plan: &Plan, start: f64, end: f64) -> Result<Trace, Violation> {
    let mut trace = Trace::new(plan.joint_count());
    let steps = (((end - start).abs() / STEP_DEG).ceil() as usize).max(1);
    for s in 0..=steps {
        let theta = (start + (end - start) * s as f64 / steps as f64).to_radians();
        trace.push(plan, theta).map_err(|e| violation("assembly", e.to_string()))?;
    }
    Ok(trace)
}

/// The first contact along `trace`, if any: a body entering a fixed body or another moving body, or a
/// link entering an avoid region.
fn first_contact(problem: &Problem, mechanism: &Mechanism, trace: &Trace, frames: &BodyFrames) -> Option<Violation> {
    let tol = problem.contact_tolerance();
    let link_segments: Vec<(usize, usize)> = mechanism.topology.link_pairs();
    for r in 0..trace.len() {
        let row = trace.row(r);
        let crank_deg = trace.thetas[r].to_degrees();
        let placed: Vec<Polygon> =
            (0..problem.body_count()).map(|b| problem.bodies[b].outline.transformed(&frames.pose(b, row))).collect();
        for (b, body) in placed.iter().enumerate() {
            if let Some(f) = problem.fixed.iter().position(|fixed| body.penetrates(fixed, tol)) {
                return Some(violation(
                    "collision",
                    format!("body {b} enters fixed body {f} at crank {crank_deg:.2}°"),
                ));
            }
            if let Some(c) = placed.iter().take(b).position(|other| body.penetrates(other, tol)) {
                return Some(violation("collision", format!("bodies {c} and {b} overlap at crank {crank_deg:.2}°")));
            }
        }
        for &(a, b) in &link_segments {
            let link = Polygon::new(vec![row[a], row[b]]);
            if let Some(k) = problem.avoid.iter().position(|z| link.penetrates(z, tol)) {
                return Some(violation(
                    "avoid_region",
                    format!("a link enters avoid region {k} at crank {crank_deg:.2}°"),
                ));
            }
        }
    }
    None
}

/// Accuracy at the design's pose angles (`poses`, degrees), against the input poses: the joints' part
/// (eq. 10) and the outlines' part, vertex by vertex (the engine has it in closed form); or the pose
/// where the linkage does not assemble.
fn pose_accuracy(
    problem: &Problem,
    mechanism: &Mechanism,
    plan: &Plan,
    frames: &BodyFrames,
    poses: &[f64],
) -> Result<Accuracy, Violation> {
    let mut row = vec![Point::ORIGIN; plan.joint_count()];
    let (mut joints, mut joint_count) = (0.0, 0usize);
    let mut outlines = 0.0;
    for (i, &theta) in poses.iter().enumerate() {
        if plan.solve(theta.to_radians(), &mut row).is_err() {
            return Err(violation("assembly", format!("the linkage does not assemble at pose {}", i + 1)));
        }
        for part in mechanism.topology.parts.iter() {
            if let crate::mechanism::PartKind::Body(b) = part.kind {
                let motion = problem.bodies[b].motion_from_first(i);
                for &j in &part.joints {
                    joints += (row[j] - motion.apply(mechanism.joints[j])).norm_sq();
                    joint_count += 1;
                }
            }
        }
        for (b, body) in problem.bodies.iter().enumerate() {
            let (reached, wanted) = (frames.pose(b, &row), body.poses[i]);
            let vertices = body.outline.vertices();
            outlines += vertices.iter().map(|&v| (reached.apply(v) - wanted.apply(v)).norm_sq()).sum::<f64>()
                / vertices.len().max(1) as f64;
        }
    }
    let joints = joints / joint_count.max(1) as f64;
    let outlines = outlines / (poses.len() * problem.bodies.len()).max(1) as f64;
    Ok(Accuracy { joints, outlines, path: None })
}

/// E_acc of a design, recomputed: the mean squared miss of the body-carried joints over the poses
/// (paper eq. 10) and that of the bodies' outline vertices, and for a path scene how far the traced
/// curve is from the drawn one; the engine's E_acc is their sum, the path's as its mean distance
/// squared plus its farthest exact point's, [`EXACT_POINT_WEIGHT`] times over, squared. The engine
/// measures its path designs with this too, so the two agree to the last digit.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Accuracy {
    pub joints: f64,
    pub outlines: f64,
    pub path: Option<PathError>,
}

impl Accuracy {
    pub(crate) fn total(&self) -> f64 {
        let path = |e: PathError| {
            let exact = e.exact.map_or(0.0, |x| EXACT_POINT_WEIGHT * x.distance);
            e.mean * e.mean + exact * exact
        };
        self.joints + self.outlines + self.path.map_or(0.0, path)
    }
}

/// How much more a path's exact point weighs in its accuracy than the curve's mean distance: passing
/// a tenth as far from it is worth as much.
pub(crate) const EXACT_POINT_WEIGHT: f64 = 10.0;

/// A path design whose tracer passes one of the path's exact points farther than this fraction of
/// the path's size does not pass it ([`missed_exact_point`]): 0.2% is a fifth of a millimetre on a
/// printed model's 10 cm path, a printed joint's own play.
pub const EXACT_POINT_TOLERANCE: f64 = 0.002;

/// The exact point a path design passes farthest from, when it is farther than
/// [`EXACT_POINT_TOLERANCE`]: the design does not do what was asked, however valid.
pub fn missed_exact_point(error: &PathError) -> Option<crate::geom::ExactMiss> {
    error.exact.filter(|x| x.distance_rel > EXACT_POINT_TOLERANCE)
}

/// How far each body is from each input pose (`[pose][body]`) in the configurations of `trace` at
/// `pose_rows`, the rows a design offers for the poses.
pub fn pose_misses(problem: &Problem, mechanism: &Mechanism, trace: &Trace, pose_rows: &[usize]) -> Vec<Vec<PoseMiss>> {
    let frames = body_frames(problem, mechanism);
    pose_rows
        .iter()
        .enumerate()
        .map(|(i, &r)| {
            let row = trace.row(r);
            problem.bodies.iter().enumerate().map(|(b, body)| body.miss(i, &frames.pose(b, row))).collect()
        })
        .collect()
}

/// A design that misses some pose by more than this fraction of its body's size d, or by more than
/// [`FAR_ANGLE_DEG`], is far from the poses drawn: it is not what was asked for, however valid
/// ([`far_from_pose`]). A quarter of d is where a person sees at a glance that the body is elsewhere.
pub const FAR_POSITION_REL_D: f64 = 0.25;
/// See [`FAR_POSITION_REL_D`].
pub const FAR_ANGLE_DEG: f64 = 5.0;

/// The pose a design is farthest from, when it is far from it ([`FAR_POSITION_REL_D`],
/// [`FAR_ANGLE_DEG`]).
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct FarFromPose {
    /// The pose, counted from 1.
    pub pose: usize,
    /// The moving body's name.
    pub body: String,
    /// By how much it misses.
    #[serde(flatten)]
    pub miss: PoseMiss,
}

/// Of `misses` (`[pose][body]`, [`pose_misses`]), the one furthest past either bound of a far pose,
/// when some pose is past one.
pub fn far_from_pose(problem: &Problem, misses: &[Vec<PoseMiss>]) -> Option<FarFromPose> {
    let past = |m: &PoseMiss| (m.position_rel_d / FAR_POSITION_REL_D).max(m.angle_deg / FAR_ANGLE_DEG);
    let indexed = misses.iter().enumerate().flat_map(|(i, m)| m.iter().enumerate().map(move |(b, m)| (i, b, *m)));
    let (i, b, miss) = indexed.max_by(|a, b| past(&a.2).total_cmp(&past(&b.2)))?;
    (past(&miss) > 1.0).then(|| FarFromPose { pose: i + 1, body: problem.bodies[b].name.clone(), miss })
}

/// How to read each moving body's pose off a configuration of `mechanism` in `problem`.
fn body_frames(problem: &Problem, mechanism: &Mechanism) -> BodyFrames {
    let first_poses: Vec<_> = problem.bodies.iter().map(|b| b.poses[0]).collect();
    BodyFrames::new(mechanism, &first_poses)
}

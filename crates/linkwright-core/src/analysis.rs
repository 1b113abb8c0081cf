//! What a person wants to see of a design's motion, recomputed from the design file alone: frames to
//! animate (crank angle, joints, body poses, every dyad's transmission angle), how far the design
//! misses each input pose, and each four-bar loop's Grashof type.
//!
//! [`Replay`] re-simulates one mechanism of a [`DesignFile`] (the best or an alternative) along its
//! crank travel; [`analyze`] turns a replay into a serializable [`MotionAnalysis`]. Angles in the
//! output are degrees, as in the files; positions are world coordinates, y up.

use crate::balance::Balancing;
use crate::design::{DesignError, DesignFile, MechanismJson, Motion};
use crate::fab::PrintSettings;
use crate::geom::{Point, Rigid};
use crate::kinematics::{BodyFrames, CompileError, Plan, Step, SweepError, Trace};
use crate::mechanism::{Loop, Mechanism, PartKind};
use crate::scene::Problem;
use crate::statics::{driving_torque, Masses, StaticsError, Torque};
use serde::Serialize;
use std::f64::consts::PI;

/// Which mechanism of a design file to look at.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Which {
    /// The design itself.
    #[default]
    Best,
    /// `alternatives[i]` (0-based).
    Alternative(usize),
}

/// How finely to sample the motion.
#[derive(Clone, Debug, PartialEq)]
pub struct AnalysisOptions {
    /// Equal crank steps from the first pose to the last; the exact crank angle of every input pose is
    /// added to them. Default 180; at least 1, and at most [`max_steps`] of the linkage's joints.
    pub steps: usize,
}

/// The most crank steps one analysis samples.
pub const MAX_STEPS: usize = 5000;

/// The most joint positions (crank steps × joints) one analysis samples. Its answer carries each
/// one with what is measured there, about 90 bytes as JSON (`POST /api/simulate` with `"steps": 240`
/// on a seven-joint design answers 150 kB), so this bounds an answer at about 5 MB whatever the
/// design, where 256 joints at [`MAX_STEPS`] steps would be over 100 MB. The app asks for 240 steps,
/// which this allows up to 208 joints.
pub const MAX_JOINT_STEPS: usize = 50_000;

/// The most crank steps an analysis of a linkage with `joints` joints may ask for.
pub fn max_steps(joints: usize) -> usize {
    (MAX_JOINT_STEPS / joints.max(1)).clamp(1, MAX_STEPS)
}

impl Default for AnalysisOptions {
    fn default() -> Self {
        AnalysisOptions { steps: 180 }
    }
}

impl AnalysisOptions {
    /// The same options with `steps` crank steps.
    pub fn with_steps(mut self, steps: usize) -> Self {
        self.steps = steps;
        self
    }
}

/// Why a design cannot be replayed against a scene.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum AnalysisError {
    /// The design file has no mechanism (status `no_solution`).
    #[error("the design has status no_solution: there is no mechanism to show")]
    NoMechanism,
    /// [`Which::Alternative`] names an alternative the file does not have.
    #[error("alternative {index} does not exist (the design has {count})")]
    NoSuchAlternative {
        /// The alternative asked for (0-based).
        index: usize,
        /// How many alternatives the file has.
        count: usize,
    },
    /// The file's mechanism cannot be read back into a linkage.
    #[error("{0}")]
    Design(#[from] DesignError),
    /// The mechanism carries another number of moving bodies than the scene has.
    #[error("the design moves {design} bodies, the scene has {scene}")]
    BodyCount {
        /// Moving bodies of the design's mechanism.
        design: usize,
        /// Moving bodies of the scene.
        scene: usize,
    },
    /// The motion gives a crank angle for another number of poses than the scene has.
    #[error("motion.pose_crank_deg has {design} angles for the scene's {scene} poses")]
    PoseCount {
        /// Pose angles in the design's motion.
        design: usize,
        /// Poses of the scene.
        scene: usize,
    },
    /// More crank steps asked for than a linkage of this many joints may have ([`max_steps`]).
    #[error(
        "{steps} crank steps of a linkage with {joints} joints would sample more than {MAX_JOINT_STEPS} joint \
         positions; at most {most} steps"
    )]
    TooManySteps {
        /// The steps asked for.
        steps: usize,
        /// Joints of the linkage.
        joints: usize,
        /// The most steps it may have.
        most: usize,
    },
    /// A crank angle is not finite, or the travel is a full turn or more (other than exactly one, for
    /// a closed path).
    #[error("motion: crank angles must be finite and the travel shorter than a full turn (one, for a closed path)")]
    Travel,
    /// The mechanism is not a chain of dyads the kinematics can solve.
    #[error("the mechanism cannot be simulated: {0}")]
    Compile(#[from] CompileError),
    /// The linkage comes apart somewhere along its travel.
    #[error("{0}")]
    Sweep(#[from] SweepError),
}

/// One mechanism of a design, simulated along its crank travel.
#[derive(Clone, Debug)]
pub struct Replay {
    /// The mechanism read back from the file.
    pub mechanism: Mechanism,
    /// The mechanism compiled for solving along its crank.
    pub plan: Plan,
    /// Body frames recovered from joints (bodies in scene order).
    pub frames: BodyFrames,
    /// From the first pose to the last, in equal steps plus one row at each pose's crank angle.
    pub trace: Trace,
    /// Row of `trace` at each input pose.
    pub pose_rows: Vec<usize>,
}

impl Replay {
    /// The torque the crank needs along this motion to hold `masses` against gravity.
    pub fn torque(&self, problem: &Problem, masses: &Masses) -> Result<Torque, StaticsError> {
        driving_torque(problem, &self.mechanism, &self.plan, &self.trace, masses)
    }

    /// The search for springs that counterbalance this motion, whose torque without them is `torque`.
    pub fn balancing<'a>(&'a self, problem: &'a Problem, masses: &'a Masses, torque: &'a Torque) -> Balancing<'a> {
        Balancing { problem, mechanism: &self.mechanism, plan: &self.plan, trace: &self.trace, masses, torque }
    }

    /// Re-simulates mechanism `which` of `design` against `problem` in `steps` equal crank steps (plus
    /// the pose angles).
    pub fn new(problem: &Problem, design: &DesignFile, which: Which, steps: usize) -> Result<Replay, AnalysisError> {
        let (mj, motion) = pick(design, which)?;
        Replay::of(problem, mj, motion, steps)
    }

    /// Re-simulates one mechanism with its motion.
    pub fn of(problem: &Problem, mj: &MechanismJson, motion: &Motion, steps: usize) -> Result<Replay, AnalysisError> {
        let mechanism = mj.to_mechanism()?;
        let bodies = mechanism.topology.body_count;
        if bodies != problem.body_count() {
            return Err(AnalysisError::BodyCount { design: bodies, scene: problem.body_count() });
        }
        let pose_degs = &motion.pose_crank_deg;
        if pose_degs.len() != problem.pose_count {
            return Err(AnalysisError::PoseCount { design: pose_degs.len(), scene: problem.pose_count });
        }
        let (start, end) = (motion.crank_start_deg, motion.crank_end_deg);
        let finite = start.is_finite() && end.is_finite() && pose_degs.iter().all(|a| a.is_finite());
        if !finite || !problem.travel_fits(start, end) {
            return Err(AnalysisError::Travel);
        }
        let plan = Plan::compile(&mechanism)?;
        let joints = plan.joint_count();
        if steps > max_steps(joints) {
            return Err(AnalysisError::TooManySteps { steps, joints, most: max_steps(joints) });
        }
        let first_poses: Vec<Rigid> = problem.bodies.iter().map(|b| b.poses[0]).collect();
        let frames = BodyFrames::new(&mechanism, &first_poses);

        // Equal steps along the travel, with each pose's angle merged in at its place.
        let steps = steps.max(1);
        let dir = if end >= start { 1.0 } else { -1.0 };
        let grid = (0..=steps).map(|s| start + (end - start) * s as f64 / steps as f64);
        let mut pose_order: Vec<(usize, f64)> = pose_degs.iter().copied().enumerate().collect();
        pose_order.sort_by(|a, b| (dir * a.1).total_cmp(&(dir * b.1)));
        let mut trace = Trace::new(plan.joint_count());
        let mut pose_rows = vec![0; pose_degs.len()];
        let mut pending = pose_order.into_iter().peekable();
        let tiny = 1e-9 * (1.0 + (end - start).abs());
        for deg in grid {
            while let Some(&(i, pose_deg)) = pending.peek() {
                if dir * (pose_deg - deg) > tiny {
                    break;
                }
                if dir * (deg - pose_deg) > tiny {
                    trace.push(&plan, pose_deg.to_radians())?;
                }
                pose_rows[i] = if dir * (deg - pose_deg) > tiny { trace.len() - 1 } else { trace.len() };
                pending.next();
            }
            trace.push(&plan, deg.to_radians())?;
        }
        // Poses outside the travel (a design file that says so) still get their own row.
        for (i, pose_deg) in pending {
            trace.push(&plan, pose_deg.to_radians())?;
            pose_rows[i] = trace.len() - 1;
        }
        Ok(Replay { mechanism, plan, frames, trace, pose_rows })
    }

    /// Body `b`'s `body_to_world` at trace row `r`.
    pub fn body_pose(&self, b: usize, r: usize) -> Rigid {
        self.frames.pose(b, self.trace.row(r))
    }
}

/// The mechanism and motion of `which`.
fn pick(design: &DesignFile, which: Which) -> Result<(&MechanismJson, &Motion), AnalysisError> {
    match which {
        Which::Best => match (&design.mechanism, &design.motion) {
            (Some(m), Some(mo)) => Ok((m, mo)),
            _ => Err(AnalysisError::NoMechanism),
        },
        Which::Alternative(index) => design
            .alternatives
            .get(index)
            .map(|a| (&a.mechanism, &a.motion))
            .ok_or(AnalysisError::NoSuchAlternative { index, count: design.alternatives.len() }),
    }
}

/// A dyad of the mechanism: the joint it places and the two joints it is placed from.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct DyadInfo {
    /// The joint the dyad places (where the transmission angle is measured).
    pub joint: String,
    /// The two joints it is placed from (for a slider dyad: the crank-side joint only).
    pub from: Vec<String>,
    /// `revolute` (circle-circle) or `slider` (circle-line; the angle is between the rod and the
    /// guide's normal).
    pub kind: &'static str,
}

/// The mechanism at one crank angle.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Frame {
    /// The driver's angle, degrees, unwrapped.
    pub crank_deg: f64,
    /// Every joint, in the order of [`MotionAnalysis::joint_names`].
    pub joints: Vec<Point>,
    /// Every moving body's pose `[x, y, angle_deg]` (angles unwrapped along the motion).
    pub bodies: Vec<[f64; 3]>,
    /// Each dyad's transmission angle, degrees in [0, 180] (the margin is its distance from 0 and 180).
    pub transmission_deg: Vec<f64>,
}

/// How far the design's configuration for one input pose is from it.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct PoseError {
    /// 0-based pose index.
    pub pose: usize,
    /// The driver's angle in the configuration the design offers for the pose, degrees.
    pub crank_deg: f64,
    /// Index of the frame at this pose.
    pub frame: usize,
    /// Root mean square distance of the body-carried joints from where the input pose puts them
    /// (the square root of this pose's share of paper eq. 10), a length.
    pub joint_rms: f64,
    /// Per moving body.
    pub bodies: Vec<BodyError>,
}

/// One body's miss at one pose.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct BodyError {
    /// The largest distance of an outline vertex from its input position, a length.
    pub max_vertex: f64,
    /// The rotation still missing, degrees in (−180, 180].
    pub angle_deg: f64,
}

/// A four-bar loop's (or the slider-crank's) mobility class.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum LoopKind {
    /// Grashof, the shortest link beside the frame link: it turns fully, the opposite one rocks.
    CrankRocker,
    /// Grashof, the frame link shortest: both side links turn fully (a drag link).
    DoubleCrank,
    /// Grashof, the coupler shortest: both side links rock, the coupler turns fully relative to them.
    GrashofDoubleRocker,
    /// Non-Grashof: no link turns fully relative to any other.
    TripleRocker,
    /// s + l = p + q: the loop can fold flat (a change point), where its branch is undetermined.
    ChangePoint,
    /// Slider-crank whose crank turns fully (crank + offset ≤ rod).
    SliderCrank,
    /// Slider-crank whose crank can only rock.
    SliderRocker,
}

impl LoopKind {
    /// A short phrase a person understands.
    pub fn describe(self) -> &'static str {
        match self {
            LoopKind::CrankRocker => "crank-rocker (Grashof): one side link turns fully, the other rocks",
            LoopKind::DoubleCrank => "double-crank (Grashof): both side links turn fully",
            LoopKind::GrashofDoubleRocker => "double-rocker (Grashof): the coupler turns fully, both side links rock",
            LoopKind::TripleRocker => "triple-rocker (non-Grashof): no link turns fully",
            LoopKind::ChangePoint => "change point: the loop can fold flat",
            LoopKind::SliderCrank => "slider-crank: the crank turns fully",
            LoopKind::SliderRocker => "slider-rocker: the crank can only rock",
        }
    }
    /// True for the Grashof classes (some link turns fully).
    pub fn grashof(self) -> bool {
        !matches!(self, LoopKind::TripleRocker | LoopKind::SliderRocker)
    }
}

/// One link of a loop with its length at the first pose.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct LoopLink {
    /// Its role in the loop: `frame`, `input`, `coupler`, `output` (for the slider-crank: `crank`,
    /// `rod`, `offset`).
    pub role: &'static str,
    /// The names of the link's two joints.
    pub joints: Vec<String>,
    /// The distance between them at the first pose, a length (scene units).
    pub length: f64,
}

/// A four-bar loop `q(k−1) r(k−1) q(k) p(k)` of the chain (paper §5.2), or the slider-crank.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct LoopInfo {
    /// The loop's number and joints, e.g. `loop 1: q0 r0 q1 p1`.
    pub name: String,
    /// Its four links (the slider-crank: crank, rod and offset).
    pub links: Vec<LoopLink>,
    /// Its mobility class.
    pub kind: LoopKind,
    /// Whether some link turns fully ([`LoopKind::grashof`]).
    pub grashof: bool,
    /// The class in words ([`LoopKind::describe`]).
    pub description: &'static str,
}

/// Everything the web app shows about a design's motion.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct MotionAnalysis {
    /// Every joint's name, in the order of [`Frame::joints`].
    pub joint_names: Vec<String>,
    /// The joints on the ground.
    pub fixed_joints: Vec<String>,
    /// The dyads in solving order, in the order of [`Frame::transmission_deg`].
    pub dyads: Vec<DyadInfo>,
    /// The motion, from the first pose to the last: equal crank steps plus one frame at each pose.
    pub frames: Vec<Frame>,
    /// The error at each input pose, in pose order.
    pub poses: Vec<PoseError>,
    /// Each four-bar loop of the chain (or the slider-crank's loop) and its class.
    pub loops: Vec<LoopInfo>,
    /// The smallest transmission margin over every frame, degrees from 0°/180°.
    pub min_transmission_deg: f64,
    /// The scene's bound on it (`settings.min_transmission_deg`).
    pub min_transmission_bound_deg: f64,
    /// The angle the synthesis pushes it above (`settings.comfortable_transmission_deg`).
    pub comfortable_transmission_deg: f64,
    /// The torque the crank needs at each frame to hold the parts against gravity, their masses as
    /// printed with the default print settings (or the scene's `mass_kg`); `None` when the travel
    /// passes a dead point.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub torque: Option<Torque>,
}

/// The analysis of mechanism `which` of `design`.
pub fn analyze(
    problem: &Problem,
    design: &DesignFile,
    which: Which,
    options: &AnalysisOptions,
) -> Result<MotionAnalysis, AnalysisError> {
    let replay = Replay::new(problem, design, which, options.steps)?;
    Ok(describe(problem, Some(design), &replay))
}

/// The analysis of a replayed mechanism of `design` (whose build record says at which scale a printed
/// model is weighed).
pub fn describe(problem: &Problem, design: Option<&DesignFile>, replay: &Replay) -> MotionAnalysis {
    let topo = &replay.mechanism.topology;
    let name = |j: usize| topo.joint_names[j].clone();
    let dyads: Vec<DyadInfo> = replay
        .plan
        .steps()
        .iter()
        .filter_map(|s| match *s {
            Step::Dyad { joint, a, b, .. } => {
                Some(DyadInfo { joint: name(joint), from: vec![name(a), name(b)], kind: "revolute" })
            }
            Step::Slider { joint, centre, .. } => {
                Some(DyadInfo { joint: name(joint), from: vec![name(centre)], kind: "slider" })
            }
            Step::Attach { .. } => None,
        })
        .collect();

    let trace = &replay.trace;
    let body_count = problem.body_count();
    let mut last_angles: Vec<Option<f64>> = vec![None; body_count];
    let mut min_margin = 90.0f64;
    let frames: Vec<Frame> = (0..trace.len())
        .map(|r| {
            let row = trace.row(r);
            let bodies = (0..body_count)
                .map(|b| {
                    let pose = replay.body_pose(b, r);
                    let angle = match last_angles[b] {
                        Some(prev) => prev + wrap(pose.angle() - prev),
                        None => pose.angle(),
                    };
                    last_angles[b] = Some(angle);
                    let t = pose.translation();
                    [t.x, t.y, angle.to_degrees()]
                })
                .collect();
            let transmission_deg = transmission_angles(&replay.plan, row);
            for &mu in &transmission_deg {
                min_margin = min_margin.min(mu.min(180.0 - mu));
            }
            Frame { crank_deg: trace.thetas[r].to_degrees(), joints: row.to_vec(), bodies, transmission_deg }
        })
        .collect();

    MotionAnalysis {
        joint_names: topo.joint_names.clone(),
        fixed_joints: topo.fixed_joints().iter().map(|&j| name(j)).collect(),
        dyads,
        frames,
        poses: pose_errors(problem, replay),
        loops: loops(&replay.mechanism),
        min_transmission_deg: min_margin,
        min_transmission_bound_deg: problem.settings.min_transmission_deg,
        comfortable_transmission_deg: problem.settings.comfortable_transmission_deg,
        torque: Masses::for_design(problem, design, &PrintSettings::default())
            .ok()
            .and_then(|masses| replay.torque(problem, &masses).ok()),
    }
}

/// Each dyad's transmission angle in a solved configuration, degrees in [0, 180], in step order.
fn transmission_angles(plan: &Plan, row: &[Point]) -> Vec<f64> {
    let angle = |u: crate::geom::Vec2, v: crate::geom::Vec2| u.cross(v).abs().atan2(u.dot(v)).to_degrees();
    plan.steps()
        .iter()
        .filter_map(|s| match *s {
            Step::Dyad { joint, a, b, .. } => Some(angle(row[a] - row[joint], row[b] - row[joint])),
            Step::Slider { joint, centre, direction, .. } => Some(angle(row[centre] - row[joint], direction.perp())),
            Step::Attach { .. } => None,
        })
        .collect()
}

/// The error at every input pose.
fn pose_errors(problem: &Problem, replay: &Replay) -> Vec<PoseError> {
    let topo = &replay.mechanism.topology;
    let first = &replay.mechanism.joints;
    replay
        .pose_rows
        .iter()
        .enumerate()
        .map(|(i, &r)| {
            let row = replay.trace.row(r);
            let mut sum = 0.0;
            let mut count = 0usize;
            for part in &topo.parts {
                if let PartKind::Body(b) = part.kind {
                    let motion = problem.bodies[b].motion_from_first(i);
                    for &j in &part.joints {
                        sum += (row[j] - motion.apply(first[j])).norm_sq();
                        count += 1;
                    }
                }
            }
            let bodies = problem
                .bodies
                .iter()
                .enumerate()
                .map(|(b, body)| {
                    let reached = replay.body_pose(b, r);
                    BodyError {
                        max_vertex: body.miss(i, &reached).position,
                        angle_deg: wrap(reached.angle() - body.poses[i].angle()).to_degrees(),
                    }
                })
                .collect();
            PoseError {
                pose: i,
                crank_deg: replay.trace.thetas[r].to_degrees(),
                frame: r,
                joint_rms: (sum / count.max(1) as f64).sqrt(),
                bodies,
            }
        })
        .collect()
}

/// The linkage's loops ([`Family::loops`]) with their lengths and types.
fn loops(m: &Mechanism) -> Vec<LoopInfo> {
    let topo = &m.topology;
    let name = |j: usize| topo.joint_names[j].clone();
    let link = |role, [a, b]: [usize; 2]| LoopLink {
        role,
        joints: vec![name(a), name(b)],
        length: m.joints[a].distance(m.joints[b]),
    };
    let family = topo.mechanism_type.family();
    family
        .loops(topo)
        .into_iter()
        .enumerate()
        .filter_map(|(i, l)| match l {
            Loop::FourBar { frame, input, coupler, output } => {
                let links =
                    vec![link("frame", frame), link("input", input), link("coupler", coupler), link("output", output)];
                let kind = four_bar_kind(links[0].length, links[1].length, links[2].length, links[3].length);
                let joints = [frame[0], frame[1], output[1], input[1]].map(name).join(" ");
                Some(LoopInfo {
                    name: format!("loop {}: {joints}", i + 1),
                    links,
                    kind,
                    grashof: kind.grashof(),
                    description: kind.describe(),
                })
            }
            Loop::SliderCrank { pivot, tip, slider } => {
                let line = m.slider?;
                let (q0, p1, q1) = (m.joints[pivot], m.joints[tip], m.joints[slider]);
                let offset = (q0 - line.point).cross(line.direction).abs();
                let (crank, rod) = (q0.distance(p1), p1.distance(q1));
                let kind = slider_crank_kind(crank, rod, offset);
                let links = vec![
                    LoopLink { role: "crank", joints: vec![name(pivot), name(tip)], length: crank },
                    LoopLink { role: "rod", joints: vec![name(tip), name(slider)], length: rod },
                    LoopLink { role: "offset", joints: vec![name(pivot)], length: offset },
                ];
                Some(LoopInfo {
                    name: format!("slider-crank: {} {} {}", name(pivot), name(tip), name(slider)),
                    links,
                    kind,
                    grashof: kind.grashof(),
                    description: kind.describe(),
                })
            }
        })
        .collect()
}

/// The Grashof class of a four-bar with the given link lengths (paper eq. 6), relative to its frame.
pub fn four_bar_kind(frame: f64, input: f64, coupler: f64, output: f64) -> LoopKind {
    let lengths = [frame, input, coupler, output];
    let (mut s, mut shortest) = (f64::INFINITY, 0);
    for (i, &x) in lengths.iter().enumerate() {
        if x < s {
            s = x;
            shortest = i;
        }
    }
    let l = lengths.iter().copied().fold(0.0, f64::max);
    let total: f64 = lengths.iter().sum();
    let (sl, pq) = (s + l, total - s - l);
    if (sl - pq).abs() <= 1e-9 * total {
        LoopKind::ChangePoint
    } else if sl > pq {
        LoopKind::TripleRocker
    } else {
        match shortest {
            0 => LoopKind::DoubleCrank,
            2 => LoopKind::GrashofDoubleRocker,
            _ => LoopKind::CrankRocker,
        }
    }
}

/// The class of a slider-crank (paper eq. 7): the crank turns fully when crank + offset ≤ rod.
pub fn slider_crank_kind(crank: f64, rod: f64, offset: f64) -> LoopKind {
    if crank + offset <= rod {
        LoopKind::SliderCrank
    } else {
        LoopKind::SliderRocker
    }
}

/// The angle `a` brought into (−π, π].
fn wrap(a: f64) -> f64 {
    let w = a.rem_euclid(2.0 * PI);
    if w > PI {
        w - 2.0 * PI
    } else {
        w
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::testing::assert_close;
    use crate::scene::Scene;
    use crate::synth::{synthesize, Silent};

    #[test]
    fn grashof_classes_of_textbook_four_bars() {
        // frame, input, coupler, output
        assert_eq!(four_bar_kind(40.0, 10.0, 35.0, 30.0), LoopKind::CrankRocker);
        assert_eq!(four_bar_kind(40.0, 30.0, 35.0, 10.0), LoopKind::CrankRocker);
        assert_eq!(four_bar_kind(10.0, 40.0, 35.0, 30.0), LoopKind::DoubleCrank);
        assert_eq!(four_bar_kind(40.0, 35.0, 10.0, 30.0), LoopKind::GrashofDoubleRocker);
        assert_eq!(four_bar_kind(40.0, 30.0, 35.0, 33.0), LoopKind::TripleRocker);
        assert_eq!(four_bar_kind(20.0, 10.0, 20.0, 10.0), LoopKind::ChangePoint);
        assert!(LoopKind::CrankRocker.grashof() && !LoopKind::TripleRocker.grashof());
        assert_eq!(slider_crank_kind(10.0, 30.0, 5.0), LoopKind::SliderCrank);
        assert_eq!(slider_crank_kind(10.0, 12.0, 5.0), LoopKind::SliderRocker);
    }

    fn designed_garbage_truck() -> (Problem, DesignFile) {
        let mut scene = Scene::from_json(include_str!("../../../examples/k1_garbage_truck.json")).unwrap();
        scene.settings.samples = 3000;
        scene.settings.seed = 5;
        // A four-bar, whose one loop the test below measures.
        scene.mechanism = crate::scene::MechanismChoice::Only(crate::scene::MechanismType::Chain);
        let problem = Problem::new(&scene).unwrap();
        let outcome = synthesize(&problem, &Silent).unwrap();
        let design = DesignFile::from_outcome(&problem, &outcome);
        assert!(design.mechanism.is_some(), "{:?}", design.reason);
        (problem, design)
    }

    #[test]
    fn analysis_agrees_with_the_design_file() {
        let (problem, design) = designed_garbage_truck();
        let a = analyze(&problem, &design, Which::Best, &AnalysisOptions::default().with_steps(90)).unwrap();
        let motion = design.motion.as_ref().unwrap();
        let metrics = design.metrics.as_ref().unwrap();
        // 91 grid angles plus the intermediate pose (the first and last coincide with grid ends).
        assert!(a.frames.len() >= 91 && a.frames.len() <= 91 + problem.pose_count, "{}", a.frames.len());
        assert_close(a.frames[0].crank_deg, motion.crank_start_deg, 1e-9);
        assert_close(a.frames[a.frames.len() - 1].crank_deg, motion.crank_end_deg, 1e-9);
        for (p, &deg) in a.poses.iter().zip(&motion.pose_crank_deg) {
            assert_close(p.crank_deg, deg, 1e-9);
            assert_close(a.frames[p.frame].crank_deg, deg, 1e-9);
        }
        // E_acc is eq. 10, the mean of the joints' per-pose mean squares, plus the mean squared miss
        // of the body's outline vertices where the frames put the body.
        let joints = a.poses.iter().map(|p| p.joint_rms * p.joint_rms).sum::<f64>() / a.poses.len() as f64;
        let body = &problem.bodies[0];
        let outline = a
            .poses
            .iter()
            .enumerate()
            .map(|(i, p)| {
                let reached = crate::geom::Rigid::from_pose(a.frames[p.frame].bodies[0]);
                let vertices = body.outline.vertices();
                vertices.iter().map(|&v| (reached.apply(v) - body.poses[i].apply(v)).norm_sq()).sum::<f64>()
                    / vertices.len() as f64
            })
            .sum::<f64>()
            / a.poses.len() as f64;
        assert_close(joints + outline, metrics.accuracy, 1e-9 * (1.0 + metrics.accuracy));
        // The first pose is where the joints are given: hit exactly.
        assert!(a.poses[0].joint_rms < 1e-9 && a.poses[0].bodies[0].max_vertex < 1e-9);
        // Frames are coarser than the engine's 1° rows but not among them: between two rows the angle
        // can dip under the rows' smallest by a second-order amount of the step (0.002° on this design,
        // whose smallest angle sits at a smooth minimum), never by more.
        let (frames, rows) = (a.min_transmission_deg, metrics.min_transmission_deg);
        assert!(frames >= rows - 0.01, "frames {frames}°, rows {rows}°");
        // The four-bar's one loop, its links measured on the file's joints: frame q0–r0, input q0–p1,
        // coupler p1–q1 and output r0–q1 (a slider-crank's would be its crank, rod and the pivot's
        // offset from the slider's line).
        let mechanism = design.mechanism.as_ref().unwrap();
        let at = |n: &str| mechanism.joints[n];
        assert_eq!(a.loops.len(), 1);
        let (name, expected) = match &mechanism.slider {
            None => (
                "loop 1: q0 r0 q1 p1",
                vec![
                    ("frame", vec!["q0", "r0"], at("q0").distance(at("r0"))),
                    ("input", vec!["q0", "p1"], at("q0").distance(at("p1"))),
                    ("coupler", vec!["p1", "q1"], at("p1").distance(at("q1"))),
                    ("output", vec!["r0", "q1"], at("r0").distance(at("q1"))),
                ],
            ),
            Some(slider) => {
                let direction = crate::geom::Vec2::new(slider.direction[0], slider.direction[1]).normalized();
                (
                    "slider-crank: q0 p1 q1",
                    vec![
                        ("crank", vec!["q0", "p1"], at("q0").distance(at("p1"))),
                        ("rod", vec!["p1", "q1"], at("p1").distance(at("q1"))),
                        ("offset", vec!["q0"], (at("q0") - slider.point).cross(direction).abs()),
                    ],
                )
            }
        };
        assert_eq!(a.loops[0].name, name);
        assert_eq!(a.loops[0].links.len(), expected.len());
        for (link, (role, joints, length)) in a.loops[0].links.iter().zip(expected) {
            assert_eq!((link.role, link.joints.iter().map(String::as_str).collect::<Vec<_>>()), (role, joints));
            assert_close(link.length, length, 1e-9 * (1.0 + length));
        }
        assert_eq!(a.dyads.len(), a.frames[0].transmission_deg.len());
        // Body angles are continuous (unwrapped).
        for w in a.frames.windows(2) {
            assert!((w[1].bodies[0][2] - w[0].bodies[0][2]).abs() < 90.0);
        }
    }

    #[test]
    fn bad_requests_are_errors_not_panics() {
        let (problem, mut design) = designed_garbage_truck();
        let options = AnalysisOptions::default();
        let count = design.alternatives.len();
        assert_eq!(
            analyze(&problem, &design, Which::Alternative(count), &options),
            Err(AnalysisError::NoSuchAlternative { index: count, count })
        );
        let mut motion = design.motion.clone().unwrap();
        motion.pose_crank_deg.pop();
        design.motion = Some(motion.clone());
        assert!(matches!(analyze(&problem, &design, Which::Best, &options), Err(AnalysisError::PoseCount { .. })));
        motion.pose_crank_deg.push(f64::NAN);
        design.motion = Some(motion);
        assert_eq!(analyze(&problem, &design, Which::Best, &options), Err(AnalysisError::Travel));
        design.mechanism = None;
        assert_eq!(analyze(&problem, &design, Which::Best, &options), Err(AnalysisError::NoMechanism));
    }
}

//! Scenes made from known mechanisms: a mechanism of a given family is drawn at random (reproducibly,
//! from a seed, by the family's [`Family::random_linkage`](crate::Family::random_linkage)), simulated
//! along a crank travel on which it assembles, keeps every transmission angle well away from 0° and
//! 180° and collides with nothing, and the poses its moving bodies take along that travel become a
//! `scene/1` scene. A linkage that hits every pose exactly is then known to exist, so the engine's
//! designs can be measured against a known answer rather than only against each other. Every family
//! has its known mechanisms: [`Known`] names the family, the number of bodies and their course.
//!
//! Everything is drawn in a unit frame (body centres about one unit apart) and multiplied by the
//! caller's scale at the end, so the same seed at two scales gives the same scene, scaled. The
//! mechanism and its travel depend on the [`Known`] kind and the seed only; the number of poses only
//! decides where along that travel the poses are taken, so the same seed gives the same mechanism for
//! every N.

mod paths;

pub use paths::{known_path_scene, published_path_scenes, KnownPath, PublishedPath};

use crate::design::{DesignFile, MechanismJson, Metrics, Motion, SliderJson, Stats, Status, DESIGN_FORMAT};
use crate::geom::{outline_distance, Aabb, Point, Polygon, Rigid, Vec2};
use crate::kinematics::{complete, completion_order, BodyFrames, Completion, Plan, Trace};
use crate::mechanism::{Mechanism, SliderLine, CENTRE_SPACING};
use crate::scene::{FixedBody, MechanismChoice, MechanismType, MovingBody, Scene, Settings, Weights, SCENE_FORMAT};
use crate::synth::random::splitmix;
use crate::synth::{transmission_shortfall, CostWeights, SoftTerms, Term};
use rand::{RngExt, SeedableRng};
use rand_xoshiro::Xoshiro256PlusPlus;
use std::f64::consts::{PI, TAU};

/// Every transmission angle stays at least this far from 0° and 180° along the known travel: twice
/// the engine's default bound, so the known linkage is comfortably valid.
pub const MIN_TRANSMISSION_DEG: f64 = 20.0;
/// The most moving bodies a chain may have here, and the most poses: the scene format's limits, so
/// every scene made here is one the engine takes.
pub const MAX_CHAIN_BODIES: usize = crate::scene::limits::MAX_MOVING_BODIES;
/// The most poses a scene made here has.
pub const MAX_POSES: usize = crate::scene::limits::MAX_POSES;
/// Mechanisms drawn before giving up.
pub const MAX_DRAWS: usize = 20_000;

/// The shortest and longest crank travel, degrees (less than a full turn).
const MIN_TRAVEL_DEG: f64 = 40.0;
const MAX_TRAVEL_DEG: f64 = 300.0;
/// Crank step of every check along the travel, degrees: half the independent check's step, so the
/// known linkage is judged at least as finely as its checker judges it.
pub(crate) const STEP_DEG: f64 = 0.25;
/// No two joints of a drawn mechanism are closer than this (so no part is degenerate).
const MIN_JOINT_DISTANCE: f64 = 0.15;
/// A body outline lies this far around its joints, drawn uniformly between the two.
const PADDING: (f64, f64) = (0.15, 0.3);
/// Along the travel no two outlines come closer than this fraction of the smallest body size.
const GAP_FRACTION: f64 = 0.05;
/// Between the first and the last pose every body moves at least this fraction of its size d.
const MIN_MOVE_FRACTION: f64 = 0.5;
/// Crank angles of intermediate poses are spread evenly, each moved by up to this fraction of the
/// spacing (less than a half, so they stay in order).
const POSE_JITTER: f64 = 0.3;

/// Which known mechanisms to draw: a family, its number of moving bodies, and the course its body
/// takes as the crank turns.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Known {
    mechanism_type: MechanismType,
    bodies: usize,
    course: Course,
}

/// The course a known mechanism's bodies take as its crank turns.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Course {
    /// On from pose to pose: the crank stops short of where a joint carried by links alone would leave
    /// the bodies' places (a Watt-II six-bar's, where the body's four-bar turns back).
    OneWay,
    /// Out and back: the crank is driven on past where the body's four-bar turns back, so the body
    /// goes out and comes back along the way it went while the crank turns on (the Watt-II six-bar).
    OutAndBack,
}

/// The random stream of the out-and-back course, apart from every family's one-way streams (whose
/// high word is the family's [`Family::stream`](crate::Family::stream)).
const OUT_AND_BACK_STREAM: u64 = 4 << 32;

impl Known {
    /// The chain of paper §4.2 with this many moving bodies (1: the four-bar, 2: the Watt-I six-bar).
    pub fn chain(bodies: usize) -> Known {
        Known { mechanism_type: MechanismType::Chain, bodies, course: Course::OneWay }
    }
    /// The linkage of this family for one moving body (the slider-crank of paper §4.3, the Watt-II
    /// and Stephenson-III six-bars, or the chain's four-bar).
    pub fn one(mechanism_type: MechanismType) -> Known {
        Known { mechanism_type, bodies: 1, course: Course::OneWay }
    }
    /// The Watt-II six-bar ([`Topology::watt_two`](crate::Topology::watt_two)) driven on past where
    /// the body's four-bar turns back ([`Course::OutAndBack`]).
    pub fn watt_two_out_and_back() -> Known {
        Known { mechanism_type: MechanismType::WattTwo, bodies: 1, course: Course::OutAndBack }
    }
    /// The family, by its word in files.
    pub fn mechanism_type(self) -> MechanismType {
        self.mechanism_type
    }
    /// The number of moving bodies K.
    pub fn bodies(self) -> usize {
        self.bodies
    }
    /// The course the bodies take.
    pub fn course(self) -> Course {
        self.course
    }
    /// The stream of random numbers this kind of mechanism is drawn from, mixed into the seed: the
    /// family's own ([`Family::stream`](crate::Family::stream)) in the high word, with the number of
    /// bodies in the low word for a family of any number of them; the out-and-back course has one of
    /// its own.
    fn stream(self) -> u64 {
        match self.course {
            Course::OutAndBack => OUT_AND_BACK_STREAM,
            Course::OneWay => {
                let bodies = if self.mechanism_type.max_bodies().is_none() { self.bodies as u64 } else { 0 };
                (self.mechanism_type.family().stream() << 32) | bodies
            }
        }
    }
}

/// The family's label (`slider-crank`), or for a family of any number of bodies its word and the
/// count (`chain K=2`), then the course when it is out and back: the names the scenes carry.
impl std::fmt::Display for Known {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self.mechanism_type.max_bodies() {
            None => write!(f, "{} K={}", self.mechanism_type.id(), self.bodies)?,
            Some(_) => f.write_str(self.mechanism_type.label())?,
        }
        match self.course {
            Course::OneWay => Ok(()),
            Course::OutAndBack => f.write_str(", out and back"),
        }
    }
}

/// Why no scene was made.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum TestbedError {
    /// The chain's number of moving bodies (given) is outside 1..=[`MAX_CHAIN_BODIES`].
    #[error("a chain needs between 1 and {MAX_CHAIN_BODIES} moving bodies, not {0}")]
    BodyCount(usize),
    /// The number of poses (given) is outside 2..=[`MAX_POSES`].
    #[error("a scene needs between 2 and {MAX_POSES} poses, not {0}")]
    PoseCount(usize),
    /// The scale (given) is not a positive number of at most 10⁶.
    #[error("the scale must be a positive finite number (1e-3 to 1e3 is sensible), not {0}")]
    Scale(f64),
    /// No mechanism drawn in [`MAX_DRAWS`] draws met every requirement.
    #[error("no {kind} drawn from seed {seed} met every requirement in {MAX_DRAWS} draws")]
    Exhausted {
        /// The kind of mechanism asked for.
        kind: Known,
        /// The seed asked for.
        seed: u64,
    },
}

/// A scene made from a known mechanism, with that mechanism and its motion.
#[derive(Clone, Debug)]
pub struct KnownScene {
    /// The kind of the known mechanism.
    pub kind: Known,
    /// The seed it was drawn from.
    pub seed: u64,
    /// The scene: the bodies' outlines and the poses the mechanism takes them through, with a fixed
    /// body and a linkage region (a `scene/1` scene any front end opens).
    pub scene: Scene,
    /// The known mechanism, joints at the first pose (world coordinates of the scene).
    pub mechanism: Mechanism,
    /// The driver's angle at each pose, radians, unwrapped: the first is the mechanism's crank angle
    /// at the first pose, the last is the end of the travel.
    pub pose_crank: Vec<f64>,
    /// The known design's metrics (paper eq. 10–14 and the worst transmission angle along the travel).
    pub metrics: Metrics,
    /// For the slider-crank: the signed distances along the guide between which its joint travels.
    pub slider_stroke: Option<[f64; 2]>,
}

impl KnownScene {
    /// The known motion in the `design/1` form.
    pub fn motion(&self) -> Motion {
        let degrees: Vec<f64> = self.pose_crank.iter().map(|t| t.to_degrees()).collect();
        Motion { crank_start_deg: degrees[0], crank_end_deg: degrees[degrees.len() - 1], pose_crank_deg: degrees }
    }

    /// The known linkage as a `design/1` file (no run statistics: nothing was searched).
    pub fn design(&self) -> DesignFile {
        let mut mechanism = MechanismJson::from_mechanism(&self.mechanism);
        if let (Some(line), Some(joint), Some(stroke)) =
            (self.mechanism.slider, self.mechanism.topology.slider_joint, self.slider_stroke)
        {
            mechanism.slider = Some(SliderJson {
                joint: self.mechanism.topology.joint_names[joint].clone(),
                point: line.point,
                direction: [line.direction.x, line.direction.y],
                stroke,
            });
        }
        DesignFile {
            linkwright: DESIGN_FORMAT.to_string(),
            scene: self.scene.name.clone(),
            status: Status::Ok,
            reason: None,
            mechanism: Some(mechanism),
            motion: Some(self.motion()),
            metrics: Some(self.metrics.clone()),
            alternatives: Vec::new(),
            stats: Stats { seed: self.seed, ..Stats::default() },
            build: None,
        }
    }
}

/// `scene` drawn `factor` times as large in the same units: every coordinate (outlines, poses,
/// regions, pinned joints) and every body thickness multiplied, angles kept. The same object at
/// another size, for measuring how designs and builds depend on size.
pub fn scaled_scene(scene: &Scene, factor: f64) -> Scene {
    let points = |v: &[Point]| v.iter().map(|p| Point::new(p.x * factor, p.y * factor)).collect::<Vec<_>>();
    let mut out = scene.clone();
    for body in &mut out.fixed_bodies {
        body.polygon = points(&body.polygon);
    }
    for body in &mut out.moving_bodies {
        body.polygon = points(&body.polygon);
        body.poses = body.poses.iter().map(|&[x, y, angle]| [x * factor, y * factor, angle]).collect();
        body.thickness = body.thickness.map(|t| t * factor);
    }
    out.linkage_region = out.linkage_region.as_deref().map(points);
    out.avoid_regions = out.avoid_regions.iter().map(|r| points(r)).collect();
    for p in out.pinned_joints.values_mut() {
        *p = Point::new(p.x * factor, p.y * factor);
    }
    out
}

/// The scene of a known mechanism of this `kind` with `poses` poses drawn from `seed`, every length
/// multiplied by `scale`.
pub fn known_scene(kind: Known, poses: usize, seed: u64, scale: f64) -> Result<KnownScene, TestbedError> {
    let k = kind.bodies;
    if k == 0 || k > MAX_CHAIN_BODIES {
        return Err(TestbedError::BodyCount(k));
    }
    if !(2..=MAX_POSES).contains(&poses) {
        return Err(TestbedError::PoseCount(poses));
    }
    if !(scale.is_finite() && scale > 0.0 && scale <= 1e6) {
        return Err(TestbedError::Scale(scale));
    }
    let mut rng = generator(seed, kind.stream(), 0);
    let drawn = (0..MAX_DRAWS).find_map(|_| draw(kind, &mut rng)).ok_or(TestbedError::Exhausted { kind, seed })?;
    let pose_crank = pose_angles(&drawn, poses, &mut generator(seed, kind.stream(), poses as u64));
    Ok(assemble(kind, seed, drawn, pose_crank, scale))
}

/// A reproducible generator for (seed, the kind's stream, the generator's own stream).
fn generator(seed: u64, kind: u64, stream: u64) -> Xoshiro256PlusPlus {
    let mut h = splitmix(seed ^ 0x6b6e_6f77_6e00_0000);
    for word in [kind, stream] {
        h = splitmix(h ^ word);
    }
    Xoshiro256PlusPlus::seed_from_u64(h)
}

/// A mechanism that met every requirement, in the unit frame.
struct Drawn {
    mechanism: Mechanism,
    plan: Plan,
    /// Each body's outline in its own frame, and its frame at the first pose.
    bodies: Vec<(Polygon, Rigid)>,
    fixed: Polygon,
    region: Polygon,
    /// Crank angles, radians, unwrapped.
    start: f64,
    end: f64,
}

/// One draw of a mechanism and its scene, or `None` when it misses a requirement.
fn draw(kind: Known, rng: &mut Xoshiro256PlusPlus) -> Option<Drawn> {
    let mechanism = kind.mechanism_type.family().random_linkage(kind.bodies, rng);
    let joints = &mechanism.joints;
    for (i, a) in joints.iter().enumerate() {
        if joints[i + 1..].iter().any(|b| a.distance(*b) < MIN_JOINT_DISTANCE) {
            return None;
        }
    }
    let plan = Plan::compile(&mechanism).ok()?;
    let start = mechanism.crank_start();
    let out_and_back = kind.course == Course::OutAndBack;
    let completion = completion_order(&mechanism.topology);
    let completes = |row: &[Point]| link_joints_in_place(&completion, joints, row);
    let mut trace = Trace::new(plan.joint_count());
    let reach = reach(&plan, start, out_and_back, completes, &mut trace);
    let end = start + travel(reach, rng)?;
    trace.sweep(&plan, start, end, STEP_DEG.to_radians()).ok()?;
    if out_and_back && !turns_back_once(&trace, completes) {
        return None;
    }

    let bodies = outlines(&mechanism, rng);
    let first: Vec<Rigid> = bodies.iter().map(|(_, f)| *f).collect();
    let frames = BodyFrames::new(&mechanism, &first);
    let placed_rows: Vec<Vec<Polygon>> = (0..trace.len())
        .map(|r| bodies.iter().enumerate().map(|(b, (o, _))| o.transformed(&frames.pose(b, trace.row(r)))).collect())
        .collect();
    if !every_body_moves(&bodies, &placed_rows, out_and_back) {
        return None;
    }
    let smallest = bodies.iter().map(|(o, _)| size(o)).fold(f64::INFINITY, f64::min);
    let apart = Apart { gap: GAP_FRACTION * smallest };
    let swept = apart.swept(&placed_rows)?;
    let fixed = ground(&mechanism, &placed_rows, &apart, swept, rng);

    // The linkage region: every joint at the first pose, with room around them.
    let joints_box = Aabb::around(mechanism.joints.iter().copied())?;
    let pad = 0.3;
    let region =
        rectangle(joints_box.min.x - pad, joints_box.min.y - pad, joints_box.max.x + pad, joints_box.max.y + pad);
    Some(Drawn { mechanism, plan, bodies, fixed, region, start, end })
}

/// Whether the joints only links carry are where the bodies' places put them in `row`: completed from
/// the first pose's `joints` by `completion`, they land on the row's own.
fn link_joints_in_place(completion: &[Completion], joints: &[Point], row: &[Point]) -> bool {
    let mut completed = row.to_vec();
    complete(completion, joints, &mut completed).is_ok()
        && completed.iter().zip(row).all(|(c, r)| c.distance(*r) <= 1e-9 * CENTRE_SPACING)
}

/// How far the crank can turn each way from `start` (positively, then negatively) with every
/// transmission angle at least the bound and, unless the body is to go out and back, the joints only
/// links carry where the bodies' places put them (a Watt-II six-bar's crank stops short of where the
/// body's four-bar turns back: there the body retraces its motion).
fn reach(
    plan: &Plan,
    start: f64,
    out_and_back: bool,
    completes: impl Fn(&[Point]) -> bool,
    trace: &mut Trace,
) -> [f64; 2] {
    let bound = MIN_TRANSMISSION_DEG.to_radians().sin();
    let mut reach = [0.0f64; 2];
    for (side, dir) in [1.0f64, -1.0].into_iter().enumerate() {
        // A sweep that stops early keeps the rows before the failure, which are all we need.
        let _ = trace.sweep(plan, start, start + dir * MAX_TRAVEL_DEG.to_radians(), STEP_DEG.to_radians());
        let good = (0..trace.len())
            .take_while(|&r| {
                plan.min_transmission_sine(trace.row(r)) >= bound && (out_and_back || completes(trace.row(r)))
            })
            .count();
        reach[side] = if good == 0 { 0.0 } else { (trace.thetas[good - 1] - start).abs() };
    }
    reach
}

/// The crank's travel, radians, signed: a direction it can turn at least [`MIN_TRAVEL_DEG`] (either,
/// at random, when both can), and a random length from half its reach to all of it, at least the
/// shortest travel. `None` when neither direction reaches that far.
fn travel(reach: [f64; 2], rng: &mut Xoshiro256PlusPlus) -> Option<f64> {
    let min_travel = MIN_TRAVEL_DEG.to_radians();
    let dir = match (reach[0] >= min_travel, reach[1] >= min_travel) {
        (false, false) => return None,
        (true, false) => 1.0,
        (false, true) => -1.0,
        (true, true) => {
            if rng.random::<bool>() {
                1.0
            } else {
                -1.0
            }
        }
    };
    let available = reach[if dir > 0.0 { 0 } else { 1 }];
    Some(dir * rng.random_range(min_travel.max(0.5 * available)..=available))
}

/// Out and back: whether the body's four-bar turns back once along `trace` (the joints only links
/// carry leave the bodies' places and never return), between a third and two thirds of the way.
fn turns_back_once(trace: &Trace, completes: impl Fn(&[Point]) -> bool) -> bool {
    let Some(turned) = (0..trace.len()).position(|r| !completes(trace.row(r))) else { return false };
    let back = (turned..trace.len()).all(|r| !completes(trace.row(r)));
    back && (trace.len() / 3..2 * trace.len() / 3).contains(&turned)
}

/// Outlines around each body's joints, each with its frame at the first pose: at the body's centroid
/// along its first two joints.
fn outlines(mechanism: &Mechanism, rng: &mut Xoshiro256PlusPlus) -> Vec<(Polygon, Rigid)> {
    let topo = &mechanism.topology;
    let mut bodies = Vec::with_capacity(topo.body_count);
    for b in 0..topo.body_count {
        let carried: Vec<Point> = topo.body_part(b).joints.iter().map(|&j| mechanism.joints[j]).collect();
        let (p, q) = (carried[0], carried[1]);
        let centroid = Point::new(
            carried.iter().map(|c| c.x).sum::<f64>() / carried.len() as f64,
            carried.iter().map(|c| c.y).sum::<f64>() / carried.len() as f64,
        );
        let frame = Rigid::from_frame(centroid, q - p);
        let padding = rng.random_range(PADDING.0..PADDING.1);
        let local: Vec<Point> = carried.iter().map(|&c| frame.inverse().apply(c)).collect();
        bodies.push((padded_hull(&local, padding), frame));
    }
    bodies
}

/// Whether every body moves at least [`MIN_MOVE_FRACTION`] of its size from its first place
/// (`placed_rows`: each body's outline placed at each row of the travel) to its last or, out and
/// back, to its farthest.
fn every_body_moves(bodies: &[(Polygon, Rigid)], placed_rows: &[Vec<Polygon>], out_and_back: bool) -> bool {
    let farthest = if out_and_back { &placed_rows[1..] } else { &placed_rows[placed_rows.len() - 1..] };
    bodies.iter().enumerate().all(|(b, (outline, _))| {
        let first = placed_rows[0][b].vertices();
        let moved = farthest
            .iter()
            .flat_map(|row| first.iter().zip(row[b].vertices()).map(|(a, z)| a.distance(*z)))
            .fold(0.0, f64::max);
        moved >= MIN_MOVE_FRACTION * size(outline)
    })
}

/// How far apart outlines keep along the travel: no penetration, and at least `gap` between them.
struct Apart {
    gap: f64,
}

impl Apart {
    fn holds(&self, a: &Polygon, b: &Polygon) -> bool {
        !a.penetrates(b, 0.0) && outline_distance(a.vertices(), b.vertices()) >= self.gap
    }

    /// The box the bodies sweep along the travel (each row of `placed_rows` holds the bodies'
    /// outlines there), or `None` when two bodies come close somewhere.
    fn swept(&self, placed_rows: &[Vec<Polygon>]) -> Option<Aabb> {
        let mut swept: Option<Aabb> = None;
        for placed in placed_rows {
            for (i, a) in placed.iter().enumerate() {
                if placed[i + 1..].iter().any(|b| !self.holds(a, b)) {
                    return None;
                }
                let bb = a.aabb();
                swept = Some(swept.map_or(bb, |s| s.union(&bb)));
            }
        }
        swept
    }
}

/// The ground: an outline around the fixed pivots when the bodies keep clear of it all along the
/// travel, otherwise a slab under everything the bodies sweep.
fn ground(
    mechanism: &Mechanism,
    placed_rows: &[Vec<Polygon>],
    apart: &Apart,
    swept: Aabb,
    rng: &mut Xoshiro256PlusPlus,
) -> Polygon {
    let pivots: Vec<Point> = mechanism.topology.fixed_joints().iter().map(|&j| mechanism.joints[j]).collect();
    let around_pivots = padded_hull(&pivots, rng.random_range(PADDING.0..PADDING.1));
    if placed_rows.iter().all(|row| row.iter().all(|b| apart.holds(b, &around_pivots))) {
        around_pivots
    } else {
        let (top, height) = (swept.min.y - 0.3, 0.3);
        rectangle(swept.min.x, top - height, swept.max.x, top)
    }
}

/// The axis-aligned rectangle with these corners, counter-clockwise.
fn rectangle(x0: f64, y0: f64, x1: f64, y1: f64) -> Polygon {
    Polygon::new(vec![Point::new(x0, y0), Point::new(x1, y0), Point::new(x1, y1), Point::new(x0, y1)])
}

/// The body size d: the shorter side of the outline's bounding box.
fn size(outline: &Polygon) -> f64 {
    let bb = outline.aabb();
    bb.width().min(bb.height())
}

/// The convex hull of octagons of circumradius `padding` about `points`: a convex outline at least
/// `padding · cos 22.5°` from every point.
fn padded_hull(points: &[Point], padding: f64) -> Polygon {
    let mut all: Vec<Point> = points
        .iter()
        .flat_map(|&p| (0..8).map(move |i| p + Vec2::from_angle(i as f64 * TAU / 8.0) * padding))
        .collect();
    all.sort_by(|a, b| a.x.total_cmp(&b.x).then(a.y.total_cmp(&b.y)));
    all.dedup();
    // Andrew's monotone chain, counter-clockwise, collinear points dropped.
    let mut hull: Vec<Point> = Vec::with_capacity(all.len() + 1);
    for pass in 0..2 {
        let start = hull.len();
        let order: Box<dyn Iterator<Item = &Point>> =
            if pass == 0 { Box::new(all.iter()) } else { Box::new(all.iter().rev()) };
        for &p in order {
            while hull.len() >= start + 2 && {
                let (a, b) = (hull[hull.len() - 2], hull[hull.len() - 1]);
                (b - a).cross(p - a) <= 0.0
            } {
                hull.pop();
            }
            hull.push(p);
        }
        hull.pop();
    }
    Polygon::new(hull)
}

/// The crank angles of `poses` poses along the drawn travel: the first at its start, the last at its
/// end, the others evenly spread and each moved by a random fraction of the spacing.
fn pose_angles(drawn: &Drawn, poses: usize, rng: &mut Xoshiro256PlusPlus) -> Vec<f64> {
    let spacing = (drawn.end - drawn.start) / (poses - 1) as f64;
    (0..poses)
        .map(|i| {
            if i == 0 {
                drawn.start
            } else if i == poses - 1 {
                drawn.end
            } else {
                drawn.start + spacing * (i as f64 + rng.random_range(-POSE_JITTER..POSE_JITTER))
            }
        })
        .collect()
}

/// The scene, mechanism and metrics of a draw, every length multiplied by `scale`.
fn assemble(kind: Known, seed: u64, drawn: Drawn, pose_crank: Vec<f64>, scale: f64) -> KnownScene {
    let Drawn { mechanism, plan, bodies, fixed, region, start, end } = drawn;
    let first: Vec<Rigid> = bodies.iter().map(|(_, f)| *f).collect();
    let frames = BodyFrames::new(&mechanism, &first);
    let n = plan.joint_count();

    // Every body's pose at each pose angle, angles unwrapped along the motion.
    let mut rows = vec![Point::ORIGIN; pose_crank.len() * n];
    for (i, &theta) in pose_crank.iter().enumerate() {
        // The travel was swept without a failure, so every angle on it assembles; a failure here would
        // leave the joints at the origin and the check of the known design would report it.
        let _ = plan.solve(theta, &mut rows[i * n..(i + 1) * n]);
    }
    let row = |i: usize| &rows[i * n..(i + 1) * n];
    let scaled = |p: Point| Point::new(p.x * scale, p.y * scale);
    let scaled_polygon = |poly: &Polygon| poly.vertices().iter().map(|&p| scaled(p)).collect::<Vec<Point>>();
    let moving_bodies: Vec<MovingBody> = bodies
        .iter()
        .enumerate()
        .map(|(b, (outline, _))| {
            let mut previous: Option<f64> = None;
            let poses = (0..pose_crank.len())
                .map(|i| {
                    let pose = frames.pose(b, row(i));
                    let t = pose.translation();
                    let mut angle = pose.angle();
                    if let Some(prev) = previous {
                        angle = prev + (angle - prev + PI).rem_euclid(TAU) - PI;
                    }
                    previous = Some(angle);
                    [t.x * scale, t.y * scale, angle.to_degrees()]
                })
                .collect();
            MovingBody {
                name: format!("body{}", b + 1),
                polygon: scaled_polygon(outline),
                poses,
                path: None,
                mass_kg: None,
                material: None,
                thickness: None,
                extra: Default::default(),
            }
        })
        .collect();

    let weights = Weights::default();
    let metrics = known_metrics(&mechanism, &plan, &frames, &bodies, &region, &weights, start, end, &pose_crank, scale);
    let slider_stroke = match (mechanism.slider, mechanism.topology.slider_joint) {
        (Some(line), Some(joint)) => {
            let mut trace = Trace::new(n);
            let _ = trace.sweep(&plan, start, end, STEP_DEG.to_radians());
            let along = (0..trace.len()).map(|r| (trace.row(r)[joint] - line.point).dot(line.direction));
            let (lo, hi) = along.fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), s| (lo.min(s), hi.max(s)));
            Some([lo * scale, hi * scale])
        }
        _ => None,
    };

    let at_scale = Mechanism {
        topology: mechanism.topology.clone(),
        joints: mechanism.joints.iter().map(|&p| scaled(p)).collect(),
        slider: mechanism.slider.map(|line| SliderLine { point: scaled(line.point), direction: line.direction }),
    };
    let scene = Scene {
        linkwright: SCENE_FORMAT.to_string(),
        name: format!("known {kind}, {} poses, seed {seed}", pose_crank.len()),
        units: "mm".to_string(),
        fixed_bodies: vec![FixedBody {
            name: "ground".to_string(),
            polygon: scaled_polygon(&fixed),
            extra: Default::default(),
        }],
        moving_bodies,
        linkage_region: Some(scaled_polygon(&region)),
        avoid_regions: Vec::new(),
        gravity: None,
        must_hit_poses: Vec::new(),
        pinned_joints: Default::default(),
        mechanism: MechanismChoice::Only(kind.mechanism_type),
        weights,
        settings: Settings::default(),
        build: Default::default(),
        extra: Default::default(),
    };
    KnownScene { kind, seed, scene, mechanism: at_scale, pose_crank, metrics, slider_stroke }
}

/// The known linkage's soft terms (paper eq. 10–13, with the engine's small length f = d/20 in eq. 11's
/// ratios), their weighted sum (eq. 14) and its worst transmission angle, at the scene's scale.
#[allow(clippy::too_many_arguments)]
fn known_metrics(
    mechanism: &Mechanism,
    plan: &Plan,
    frames: &BodyFrames,
    bodies: &[(Polygon, Rigid)],
    region: &Polygon,
    weights: &Weights,
    start: f64,
    end: f64,
    pose_crank: &[f64],
    scale: f64,
) -> Metrics {
    let topo = &mechanism.topology;
    let n = plan.joint_count();
    let carried = topo.body_joints();
    let step = STEP_DEG.to_radians();

    // Eq. 10 at the pose angles, against where the drawn poses put the body joints (both come from
    // the same configurations, so this is rounding only).
    let mut row = vec![Point::ORIGIN; n];
    let mut accuracy = 0.0;
    for &theta in pose_crank {
        let _ = plan.solve(theta, &mut row);
        for &(j, b) in &carried {
            let motion = bodies[b].1.to(&frames.pose(b, &row));
            accuracy += (row[j] - motion.apply(mechanism.joints[j])).norm_sq();
        }
    }
    accuracy /= (pose_crank.len() * carried.len()) as f64;

    // Eq. 11: each body joint's path between consecutive poses over its chord.
    let d = bodies.iter().map(|(o, _)| size(o)).fold(f64::INFINITY, f64::min);
    let f = 0.05 * d;
    let mut trace = Trace::new(n);
    let mut smoothness = 0.0;
    for w in pose_crank.windows(2) {
        let _ = trace.sweep(plan, w[0], w[1], step);
        for &(j, _) in &carried {
            let path: f64 = (1..trace.len()).map(|r| trace.row(r)[j].distance(trace.row(r - 1)[j])).sum();
            let chord = trace.row(trace.len() - 1)[j].distance(trace.row(0)[j]);
            smoothness += (path + f) / (chord + f);
        }
    }
    smoothness /= ((pose_crank.len() - 1) * carried.len()) as f64;

    // Eq. 12–13.
    let joints = &mechanism.joints;
    let location = joints.iter().map(|&p| region.distance(p)).sum::<f64>() / joints.len() as f64;
    let links = topo.link_pairs();
    let size = links.iter().map(|&(a, b)| joints[a].distance(joints[b])).sum::<f64>() / links.len().max(1) as f64;

    let _ = trace.sweep(plan, start, end, step);
    let (least_row, least_sine) = trace.least_transmission(plan);
    let min_transmission_deg = least_sine.asin().to_degrees();
    let (accuracy, location, size) = (accuracy * scale * scale, location * scale, size * scale);
    let comfortable_sine = Settings::default().comfortable_transmission_deg.to_radians().sin();
    let transmission = transmission_shortfall(least_sine, comfortable_sine);
    let mut soft = SoftTerms::default();
    for (term, value) in [
        (Term::Accuracy, accuracy),
        (Term::Smoothness, smoothness),
        (Term::Location, location),
        (Term::Size, size),
        (Term::Transmission, transmission),
    ] {
        soft[term] = value;
    }
    let cost = CostWeights::new(weights, d * scale).cost(&soft);
    Metrics {
        accuracy,
        smoothness,
        location,
        size,
        transmission,
        cost,
        min_transmission_deg,
        min_transmission_crank_deg: Some(trace.thetas[least_row].to_degrees()),
        pose_errors: Vec::new(),
        worst_pose_error: None,
        far_from_pose: None,
        path_error: None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::{validate, Problem, Severity};

    /// The chains up to six bodies and every one-body family, each with the pose counts the quality
    /// benchmark uses.
    fn grid() -> Vec<(Known, Vec<usize>)> {
        let mut out: Vec<(Known, Vec<usize>)> = (1..=6).map(|k| (Known::chain(k), (2..=10).collect())).collect();
        for t in MechanismType::ALL.into_iter().filter(|t| t.max_bodies() == Some(1)) {
            out.push((Known::one(t), (2..=10).collect()));
        }
        out
    }

    #[test]
    fn testbed_known_linkages_pass_the_independent_check() {
        for (kind, counts) in grid() {
            for seed in 0..4u64 {
                for &poses in &counts {
                    // Every pose count at scale 1, and a spread of scales across pose counts.
                    let scale = [1.0, 1e-3, 1.0, 1e3, 0.37, 1.0, 42.0, 1.0, 1.0][(poses + seed as usize) % 9];
                    let known = known_scene(kind, poses, seed, scale)
                        .unwrap_or_else(|e| panic!("{kind}, {poses} poses, seed {seed}: {e}"));
                    let label = format!("{kind}, {poses} poses, seed {seed}, scale {scale}");
                    let errors: Vec<_> =
                        validate(&known.scene).into_iter().filter(|i| i.severity == Severity::Error).collect();
                    assert!(errors.is_empty(), "{label}: {errors:?}");
                    let problem = Problem::new(&known.scene).expect("valid");
                    assert_eq!(problem.body_count(), kind.bodies(), "{label}");
                    assert_eq!(problem.pose_count, poses, "{label}");
                    let design = known.design();
                    let violations = design.violations(&problem);
                    assert!(violations.is_empty(), "{label}: {violations:?}");
                    let metrics = design.metrics.as_ref().expect("metrics");
                    assert!(metrics.min_transmission_deg >= MIN_TRANSMISSION_DEG - 1e-9, "{label}");
                    assert!(metrics.accuracy <= 1e-20 * scale * scale, "{label}: {}", metrics.accuracy);
                    assert_eq!(metrics.location, 0.0, "{label}");
                    // The design file round-trips and reads back as the same mechanism.
                    let reread = DesignFile::from_json(&design.to_json()).expect("parses");
                    assert!(reread.violations(&problem).is_empty(), "{label}");
                }
            }
        }
    }

    /// The known linkage really moves every body through its poses: replaying the design file with
    /// the analysis (a separate reader of the file) puts every outline vertex on its drawn pose.
    #[test]
    fn testbed_known_linkages_hit_every_pose() {
        for kind in [Known::chain(1), Known::chain(3), Known::one(MechanismType::SliderCrank)] {
            let known = known_scene(kind, 7, 11, 5.0).expect("drawn");
            let problem = Problem::new(&known.scene).expect("valid");
            let analysis = crate::analysis::analyze(
                &problem,
                &known.design(),
                crate::analysis::Which::Best,
                &crate::analysis::AnalysisOptions::default(),
            )
            .expect("replays");
            for pose in &analysis.poses {
                for (b, body) in pose.bodies.iter().enumerate() {
                    assert!(body.max_vertex <= 1e-9 * problem.bodies[b].size, "{kind}: {pose:?}");
                    assert!(body.angle_deg.abs() <= 1e-9, "{kind}: {pose:?}");
                }
            }
            // The poses are distinct: the last is at least half a body size from the first.
            let b = &problem.bodies[0];
            let last = b.motion_from_first(problem.pose_count - 1);
            let moved = b
                .outline
                .transformed(&b.poses[0])
                .vertices()
                .iter()
                .map(|&v| v.distance(last.apply(v)))
                .fold(0.0, f64::max);
            assert!(moved >= MIN_MOVE_FRACTION * b.size * (1.0 - 1e-9), "{kind}: {moved}");
        }
    }

    #[test]
    fn testbed_scene_scales_with_the_scale() {
        for kind in [Known::chain(1), Known::chain(2), Known::chain(4), Known::one(MechanismType::SliderCrank)] {
            for scale in [1e-3, 0.5, 7.0, 1e3] {
                let unit = known_scene(kind, 5, 3, 1.0).expect("drawn");
                let big = known_scene(kind, 5, 3, scale).expect("drawn");
                let close = |a: f64, b: f64| (a - b).abs() <= 1e-12 * (1.0 + a.abs().max(b.abs()));
                let same_points = |a: &[Point], b: &[Point]| {
                    a.len() == b.len()
                        && a.iter().zip(b).all(|(p, q)| close(p.x * scale, q.x) && close(p.y * scale, q.y))
                };
                for (u, s) in unit.scene.moving_bodies.iter().zip(&big.scene.moving_bodies) {
                    assert!(same_points(&u.polygon, &s.polygon), "{kind} at {scale}");
                    for (p, q) in u.poses.iter().zip(&s.poses) {
                        assert!(close(p[0] * scale, q[0]) && close(p[1] * scale, q[1]), "{kind} at {scale}");
                        assert!(close(p[2], q[2]), "{kind} at {scale}");
                    }
                }
                for (u, s) in unit.scene.fixed_bodies.iter().zip(&big.scene.fixed_bodies) {
                    assert!(same_points(&u.polygon, &s.polygon), "{kind} at {scale}");
                }
                let region = |k: &KnownScene| k.scene.linkage_region.clone().expect("a region");
                assert!(same_points(&region(&unit), &region(&big)), "{kind} at {scale}");
                assert!(same_points(&unit.mechanism.joints, &big.mechanism.joints), "{kind} at {scale}");
                assert_eq!(unit.pose_crank, big.pose_crank, "{kind} at {scale}");
                let (mu, ms) = (&unit.metrics, &big.metrics);
                assert!(close(mu.size * scale, ms.size) && close(mu.smoothness, ms.smoothness), "{kind} at {scale}");
            }
        }
    }

    #[test]
    fn testbed_is_reproducible_and_seeds_differ() {
        let a = known_scene(Known::chain(2), 4, 9, 1.0).expect("drawn");
        let b = known_scene(Known::chain(2), 4, 9, 1.0).expect("drawn");
        let c = known_scene(Known::chain(2), 4, 10, 1.0).expect("drawn");
        assert_eq!(a.scene, b.scene);
        assert_ne!(a.scene, c.scene);
        // The pose count picks poses along the same mechanism's travel.
        let d = known_scene(Known::chain(2), 6, 9, 1.0).expect("drawn");
        assert_eq!(a.mechanism, d.mechanism);
        assert_eq!(a.scene.moving_bodies[0].poses[0], d.scene.moving_bodies[0].poses[0]);
        assert_eq!(a.pose_crank[3], d.pose_crank[5]);
    }

    /// Each kind of known mechanism draws its own random numbers, and keeps the stream and the name
    /// its scenes were first drawn with, so a seed keeps giving the same scene.
    #[test]
    fn testbed_kinds_keep_their_streams_and_names() {
        let one = |t| Known::one(t);
        let kinds = [
            (Known::chain(1), 1, "chain K=1"),
            (Known::chain(2), 2, "chain K=2"),
            (one(MechanismType::SliderCrank), 1 << 32, "slider-crank"),
            (one(MechanismType::WattTwo), 2 << 32, "Watt-II six-bar"),
            (one(MechanismType::StephensonThree), 3 << 32, "Stephenson-III six-bar"),
            (Known::watt_two_out_and_back(), 4 << 32, "Watt-II six-bar, out and back"),
        ];
        for (kind, stream, name) in kinds {
            assert_eq!((kind.stream(), kind.to_string().as_str()), (stream, name), "{kind:?}");
        }
        assert_eq!(Known::one(MechanismType::Chain), Known::chain(1));
        let mut all: Vec<Known> = (1..=MAX_CHAIN_BODIES).map(Known::chain).collect();
        all.extend(MechanismType::ALL.into_iter().filter(|t| t.max_bodies() == Some(1)).map(Known::one));
        all.push(Known::watt_two_out_and_back());
        let streams: std::collections::HashSet<u64> = all.iter().map(|k| k.stream()).collect();
        assert_eq!(streams.len(), all.len(), "each kind draws its own numbers");
    }

    #[test]
    fn testbed_refuses_what_it_cannot_make() {
        assert_eq!(known_scene(Known::chain(0), 3, 0, 1.0).unwrap_err(), TestbedError::BodyCount(0));
        assert_eq!(
            known_scene(Known::chain(MAX_CHAIN_BODIES + 1), 3, 0, 1.0).unwrap_err(),
            TestbedError::BodyCount(MAX_CHAIN_BODIES + 1)
        );
        assert_eq!(known_scene(Known::chain(1), 1, 0, 1.0).unwrap_err(), TestbedError::PoseCount(1));
        assert_eq!(
            known_scene(Known::one(MechanismType::SliderCrank), MAX_POSES + 1, 0, 1.0).unwrap_err(),
            TestbedError::PoseCount(MAX_POSES + 1)
        );
        for scale in [0.0, -1.0, f64::NAN, f64::INFINITY] {
            assert!(matches!(known_scene(Known::chain(1), 3, 0, scale), Err(TestbedError::Scale(_))));
        }
    }

    #[test]
    fn testbed_padded_hull_is_convex_and_keeps_its_distance() {
        let points = [Point::new(0.0, 0.0), Point::new(1.0, 0.0), Point::new(0.3, 0.7)];
        let hull = padded_hull(&points, 0.2);
        assert!(hull.validate().is_ok());
        let v = hull.vertices();
        for i in 0..v.len() {
            let (a, b, c) = (v[i], v[(i + 1) % v.len()], v[(i + 2) % v.len()]);
            assert!((b - a).cross(c - b) > 0.0, "convex and counter-clockwise");
        }
        for p in points {
            assert!(hull.contains(p));
            assert!(hull.boundary_distance(p) >= 0.2 * (PI / 8.0).cos() - 1e-12);
        }
        // Two joints on the x axis: the outline's height is twice the padding.
        let two = padded_hull(&[Point::new(0.0, 0.0), Point::new(1.0, 0.0)], 0.2);
        assert!((size(&two) - 0.4).abs() < 1e-12);
    }
}

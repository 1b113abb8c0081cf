//! Path scenes made from known linkages: a crank-rocker, or a six-bar built on one, drawn at random
//! (reproducibly, from a seed) is simulated by the engine's general solver (not the path search's
//! closed form), and the curve a point of its body traces becomes a scene's path. A linkage tracing
//! that curve exactly is then known to exist, so the path search can be measured against it.

use super::{MIN_TRANSMISSION_DEG, STEP_DEG};
use crate::geom::{curve_size, Point, Rigid, Vec2};
use crate::kinematics::{circle_circle, BodyFrames, Branch, Plan, Trace};
use crate::mechanism::{Mechanism, Topology};
use crate::scene::{
    DrawnPath, FixedBody, MechanismChoice, MechanismType, MovingBody, Scene, Settings, Weights, SCENE_FORMAT,
};
use crate::synth::random::splitmix;
use rand::{RngExt, SeedableRng};
use rand_distr::{Distribution, StandardNormal};
use rand_xoshiro::Xoshiro256PlusPlus;
use std::f64::consts::TAU;
use std::sync::Arc;

/// The stream of the path testbed's draws, apart from the pose testbed's.
const PATH_STREAM: u64 = 5 << 32;
/// Draws tried before giving up (a crank-rocker meeting the transmission bound is found in a few).
const MAX_PATH_DRAWS: u64 = 10_000;

/// A path scene and the linkage whose tracer traces it.
#[derive(Clone, Debug)]
pub struct KnownPath {
    /// The scene: one small body whose centre follows the curve, a ground strip well below.
    pub scene: Scene,
    /// The known linkage, its joints where the body starts.
    pub mechanism: Mechanism,
    /// The size of the traced curve (its bounding box's diagonal), scene units.
    pub curve_size: f64,
    /// The body's pose (`[x, y, angle°]`, scene units) where the known linkage puts it at each point
    /// of the curve before the noise: poses a body following the curve can be asked to pass.
    pub poses_along: Vec<[f64; 3]>,
}

/// The path scene of seed `seed`: `points` points of the curve a known linkage of `family` traces
/// (the four-bar's coupler point, or a point of a Stephenson-III or Watt-II six-bar's body: the
/// Watt-II's runs out and back once per turn of its crank), the whole loop
/// (`closed`) or an arc of 90° to 270° of crank travel, each moved by Gaussian noise of `noise_rel`
/// times the curve's size, everything at `scale` (millimetres per unit). `None` for a family the
/// testbed does not draw.
pub fn known_path_scene(
    family: MechanismType,
    closed: bool,
    points: usize,
    noise_rel: f64,
    seed: u64,
    scale: f64,
) -> Option<KnownPath> {
    let topology = Arc::new(Topology::chain(1));
    let stephenson = Arc::new(Topology::stephenson_three());
    let watt = Arc::new(Topology::watt_two());
    for draw in 0..MAX_PATH_DRAWS {
        let mut rng = Xoshiro256PlusPlus::seed_from_u64(splitmix(seed ^ PATH_STREAM).wrapping_add(draw));
        let Some(four_bar) = crank_rocker(&topology, closed, &mut rng) else { continue };
        let drawn = match family {
            MechanismType::Chain => Some(four_bar),
            MechanismType::StephensonThree => stephenson_three(&stephenson, four_bar, &mut rng),
            MechanismType::WattTwo => watt_two(&watt, four_bar, &mut rng),
            _ => return None,
        };
        let Some((mechanism, start, end, tracer)) = drawn else { continue };
        let Ok(plan) = Plan::compile(&mechanism) else { continue };
        let mut trace = Trace::new(plan.joint_count());
        if trace.sweep(&plan, start, end, STEP_DEG.to_radians()).is_err()
            || trace.min_transmission(&plan).to_degrees() < MIN_TRANSMISSION_DEG
        {
            continue;
        }
        // The body's frame sits on the tracer, unturned, where the motion starts.
        let first = Rigid::new(0.0, tracer - Point::ORIGIN);
        let frames = BodyFrames::new(&mechanism, &[first]);
        let samples = if closed { points } else { points - 1 };
        let along: Vec<Rigid> = (0..points)
            .map(|k| {
                let theta = start + (end - start) * k as f64 / samples as f64;
                let mut row = vec![Point::ORIGIN; plan.joint_count()];
                // The sweep passed, so every angle of the travel assembles.
                let _ = plan.solve(theta, &mut row);
                frames.pose(0, &row)
            })
            .collect();
        let mut curve: Vec<Point> = along.iter().map(|pose| pose.apply(Point::ORIGIN)).collect();
        let size = curve_size(&curve);
        for p in &mut curve {
            let (dx, dy): (f64, f64) = (StandardNormal.sample(&mut rng), StandardNormal.sample(&mut rng));
            *p = *p + Vec2::new(dx, dy) * (noise_rel * size);
        }
        let at = |p: Point| Point::new(p.x * scale, p.y * scale);
        let lowest = curve.iter().chain(&mechanism.joints).map(|p| p.y).fold(f64::INFINITY, f64::min);
        let name = format!(
            "known {} {} curve, {points} points, noise {noise_rel}, seed {seed}",
            family.linkage_label(1),
            if closed { "closed" } else { "open" }
        );
        let curve: Vec<Point> = curve.iter().map(|&p| at(p)).collect();
        let scene = path_scene(name, &curve, closed, (lowest - 0.5) * scale, 0.04 * scale);
        let mechanism = Mechanism { joints: mechanism.joints.iter().map(|&p| at(p)).collect(), ..mechanism };
        let poses_along = along
            .iter()
            .map(|pose| {
                let [x, y, angle] = pose.to_pose();
                [x * scale, y * scale, angle]
            })
            .collect();
        return Some(KnownPath { scene, mechanism, curve_size: size * scale, poses_along });
    }
    None
}

/// A scene whose one body, a square of half-side `half`, carries its tracer at its centre along
/// `curve` (scene millimetres), starting on its first point, above a ground strip whose top is at
/// height `ground_top`.
fn path_scene(name: String, curve: &[Point], closed: bool, ground_top: f64, half: f64) -> Scene {
    let (mut left, mut right) =
        curve.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(l, r), p| (l.min(p.x), r.max(p.x)));
    // A curve up and down (a vertical line) still stands over a strip as wide as it is tall.
    let size = curve_size(curve);
    if right - left < 0.5 * size {
        let middle = 0.5 * (left + right);
        (left, right) = (middle - 0.25 * size, middle + 0.25 * size);
    }
    let thickness = 0.2 * (right - left);
    let ground =
        [(left, ground_top - thickness), (right, ground_top - thickness), (right, ground_top), (left, ground_top)];
    let square = [(-half, -half), (half, -half), (half, half), (-half, half)];
    Scene {
        linkwright: SCENE_FORMAT.to_string(),
        name,
        units: "mm".to_string(),
        fixed_bodies: vec![FixedBody {
            name: "ground".to_string(),
            polygon: ground.iter().map(|&(x, y)| Point::new(x, y)).collect(),
            extra: Default::default(),
        }],
        moving_bodies: vec![MovingBody {
            name: "tracer".to_string(),
            polygon: square.iter().map(|&(x, y)| Point::new(x, y)).collect(),
            poses: vec![[curve[0].x, curve[0].y, 0.0]],
            path: Some(DrawnPath {
                tracer: Point::ORIGIN,
                points: curve.to_vec(),
                closed,
                exact: Vec::new(),
                extra: Default::default(),
            }),
            mass_kg: None,
            material: None,
            thickness: None,
            extra: Default::default(),
        }],
        linkage_region: None,
        avoid_regions: Vec::new(),
        mechanism: MechanismChoice::Auto,
        gravity: None,
        must_hit_poses: Vec::new(),
        pinned_joints: Default::default(),
        weights: Weights::default(),
        settings: Settings::default(),
        build: Default::default(),
        extra: Default::default(),
    }
}

/// A published path-synthesis target: its name, where it comes from, and its points.
#[derive(Clone, Debug)]
pub struct PublishedPath {
    /// What the target is.
    pub name: &'static str,
    /// Where it is published.
    pub source: &'static str,
    /// The target as a path scene.
    pub scene: Scene,
}

/// Path-synthesis targets of the literature, as path scenes (millimetres, the published numbers
/// as they are): straight-line generation, an ellipse and a closed free-form curve. The literature
/// asks a linkage to pass the points (precision points, the curve free between them), so each is
/// asked with every point exact; the free-form curve, whose eighteen points no four-bar or six-bar
/// passes, is also asked as a curve drawn through them. The published errors are sums of squared
/// distances, some at prescribed crank angles, which a timing-free design is not compared with.
pub fn published_path_scenes() -> Vec<PublishedPath> {
    let line: Vec<Point> = (0..6).map(|k| Point::new(20.0, 20.0 + 5.0 * k as f64)).collect();
    let ellipse: Vec<Point> = (0..9)
        .map(|k| {
            let t = (40.0 * k as f64).to_radians();
            Point::new(10.0 + 10.0 * t.cos(), 10.0 + 8.0 * t.sin())
        })
        .collect();
    let free_form: Vec<Point> = [
        (0.5, 1.1),
        (0.4, 1.1),
        (0.3, 1.1),
        (0.2, 1.0),
        (0.1, 0.9),
        (0.05, 0.75),
        (0.02, 0.6),
        (0.0, 0.5),
        (0.0, 0.4),
        (0.03, 0.3),
        (0.1, 0.25),
        (0.15, 0.2),
        (0.2, 0.3),
        (0.3, 0.4),
        (0.4, 0.5),
        (0.5, 0.7),
        (0.6, 0.9),
        (0.6, 1.0),
    ]
    .iter()
    .map(|&(x, y)| Point::new(100.0 * x, 100.0 * y))
    .collect();
    let scene = |name: &str, curve: &[Point], closed: bool| {
        let size = curve_size(curve);
        let lowest = curve.iter().map(|p| p.y).fold(f64::INFINITY, f64::min);
        path_scene(name.to_string(), curve, closed, lowest - 2.0 * size, 0.02 * size)
    };
    let four_bar = |mut scene: Scene| {
        scene.mechanism = MechanismChoice::Only(MechanismType::Chain);
        scene
    };
    let exact = |mut scene: Scene| {
        let path = scene.moving_bodies[0].path.as_mut().expect("a path scene");
        path.exact = (0..path.points.len()).collect();
        scene
    };
    vec![
        PublishedPath {
            name: "six points on a vertical line, each exact",
            source: "Kunjur & Krishnamurty 1997; Cabrera, Simon & Prado 2002",
            scene: exact(scene("straight line, six points", &line, false)),
        },
        // A slider's own joint runs on a line, so `auto` answers the straight line with it; the
        // literature asks it of a four-bar.
        PublishedPath {
            name: "six points on a vertical line, each exact, by a four-bar",
            source: "Kunjur & Krishnamurty 1997; Cabrera, Simon & Prado 2002",
            scene: exact(four_bar(scene("straight line, six points, four-bar", &line, false))),
        },
        PublishedPath {
            name: "nine points on an ellipse, 40° apart, each exact",
            source: "Cabrera, Simon & Prado 2002",
            scene: exact(scene("ellipse, nine points", &ellipse, true)),
        },
        PublishedPath {
            name: "eighteen points of a closed curve (×100), each exact",
            source: "Cabrera, Ortiz, Nadal & Castillo 2011",
            scene: exact(scene("closed curve, eighteen points", &free_form, true)),
        },
        PublishedPath {
            name: "the same eighteen points as a curve drawn through them",
            source: "Cabrera, Ortiz, Nadal & Castillo 2011",
            scene: scene("closed curve, eighteen points", &free_form, true),
        },
    ]
}

/// A crank-rocker (ground 1, the crank the shortest link, Grashof) at a random placement, its travel
/// (radians: a whole turn, or an arc) and its coupler point where the travel starts.
fn crank_rocker(
    topology: &Arc<Topology>,
    closed: bool,
    rng: &mut Xoshiro256PlusPlus,
) -> Option<(Mechanism, f64, f64, Point)> {
    let (crank, coupler, rocker): (f64, f64, f64) =
        (rng.random_range(0.15..0.45), rng.random_range(0.6..1.6), rng.random_range(0.6..1.6));
    let longest = coupler.max(rocker).max(1.0);
    if crank + longest >= 1.0 + coupler + rocker - longest {
        return None;
    }
    let turn = Rigid::new(rng.random_range(0.0..TAU), Vec2::ZERO);
    let q0 = Point::ORIGIN;
    let r0 = turn.apply(Point::new(1.0, 0.0));
    let start: f64 = rng.random_range(0.0..TAU);
    let p1 = q0 + Vec2::from_angle(start) * crank;
    let to = r0 - p1;
    let e = to.norm();
    let along = (coupler * coupler - rocker * rocker + e * e) / (2.0 * e);
    let h = (coupler * coupler - along * along).sqrt();
    let side = if rng.random::<bool>() { 1.0 } else { -1.0 };
    let q1 = p1 + to / e * along + (to / e).perp() * (side * h);
    let (u, v) = (coupler * rng.random_range(-0.5..1.5), coupler * rng.random_range(-1.0..1.0));
    let x = (q1 - p1) / coupler;
    let tracer = p1 + x * u + x.perp() * v;
    let joints = topology
        .joint_names
        .iter()
        .map(|n| match n.as_str() {
            "q0" => q0,
            "r0" => r0,
            "p1" => p1,
            _ => q1,
        })
        .collect();
    let direction = if rng.random::<bool>() { 1.0 } else { -1.0 };
    let span = if closed { TAU } else { rng.random_range(90f64..270.0).to_radians() };
    let mechanism = Mechanism { topology: topology.clone(), joints, slider: None };
    Some((mechanism, start, start + direction * span, tracer))
}

/// The Stephenson-III six-bar on `four_bar` (with its travel and coupler point): the crank-rocker's
/// coupler carries the body's joint `p1` at the coupler point, the body's other joint `q1` swings on
/// a ground link from a pivot drawn near the loop, and the tracer is a point of the body.
fn stephenson_three(
    topology: &Arc<Topology>,
    (four_bar, start, end, p1): (Mechanism, f64, f64, Point),
    rng: &mut Xoshiro256PlusPlus,
) -> Option<(Mechanism, f64, f64, Point)> {
    let at = |name: &str| four_bar.joint(name).expect("a four-bar's joint");
    let r0 = at("q0") + Vec2::new(rng.random_range(-1.0..2.0), rng.random_range(-1.5..1.5));
    let (body, link) = (rng.random_range(0.5..1.5), rng.random_range(0.5..1.5));
    let branch = if rng.random::<bool>() { Branch::Positive } else { Branch::Negative };
    let q1 = circle_circle(p1, body, r0, link, branch).ok()?;
    let x = (q1 - p1) / body;
    let tracer = p1 + x * (body * rng.random_range(-0.5..1.5)) + x.perp() * (body * rng.random_range(-1.0..1.0));
    let joints = topology
        .joint_names
        .iter()
        .map(|n| match n.as_str() {
            "q0" => at("q0"),
            "u0" => at("r0"),
            "a1" => at("p1"),
            "b1" => at("q1"),
            "p1" => p1,
            "q1" => q1,
            _ => r0,
        })
        .collect();
    Some((Mechanism { topology: topology.clone(), joints, slider: None }, start, end, tracer))
}

/// The Watt-II six-bar on `four_bar` (with its travel): the crank-rocker drives the ternary link
/// about its rocker's pivot, which carries the body's joint `p1`; the body's four-bar gets a rocker
/// pivot drawn near it, and the tracer is a point of the body.
fn watt_two(
    topology: &Arc<Topology>,
    (four_bar, start, end, _): (Mechanism, f64, f64, Point),
    rng: &mut Xoshiro256PlusPlus,
) -> Option<(Mechanism, f64, f64, Point)> {
    let at = |name: &str| four_bar.joint(name).expect("a four-bar's joint");
    let (q0, t1) = (at("r0"), at("q1"));
    let input = rng.random_range(0.5..1.5);
    let p1 = q0 + Vec2::from_angle((t1 - q0).angle() + rng.random_range(0.0..TAU)) * input;
    let r0 = q0 + Vec2::new(rng.random_range(-1.5..1.5), rng.random_range(-1.5..1.5));
    let (coupler, rocker) = (rng.random_range(0.5..1.5), rng.random_range(0.5..1.5));
    let branch = if rng.random::<bool>() { Branch::Positive } else { Branch::Negative };
    let q1 = circle_circle(p1, coupler, r0, rocker, branch).ok()?;
    let x = (q1 - p1) / coupler;
    let tracer = p1 + x * (coupler * rng.random_range(-0.5..1.5)) + x.perp() * (coupler * rng.random_range(-1.0..1.0));
    let joints = topology
        .joint_names
        .iter()
        .map(|n| match n.as_str() {
            "u0" => at("q0"),
            "u1" => at("p1"),
            "t1" => t1,
            "q0" => q0,
            "p1" => p1,
            "q1" => q1,
            _ => r0,
        })
        .collect();
    Some((Mechanism { topology: topology.clone(), joints, slider: None }, start, end, tracer))
}

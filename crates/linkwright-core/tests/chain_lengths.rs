//! Property: for every K, a compiled K-chain moves as a linkage must. Along the whole crank travel it
//! assembles in, every link keeps its length, every body keeps its shape, [`BodyFrames`] carries each
//! body's joints onto the solved ones, and the first pose is reproduced at the crank's start angle.
//!
//! The chains are random but well conditioned: loop k (the four-bar `q_{k−1} r_{k−1} q_k p_k`) gets an
//! input link of length 0.5–1.5 and a base of 3–6 (so `|p_k r_{k−1}| ≥ 1.5`), and `q_k` is placed so
//! that the transmission angle of its dyad is 60°–120° with side ratio 0.7–1.4. Each K gets its own
//! proptest run, so every K from 1 to 8 is covered.

use linkwright_core::geom::{Point, Rigid, Vec2};
use linkwright_core::kinematics::{circle_circle, BodyFrames, Branch, Plan};
use linkwright_core::{Mechanism, Topology};
use proptest::prelude::*;
use proptest::test_runner::{Config, TestCaseResult, TestRunner};
use std::f64::consts::PI;
use std::sync::Arc;

/// Crank step of the sweep.
const STEP_DEG: f64 = 0.5;
/// The sweep stops after this much travel each way, when the crank turns fully.
const MAX_TRAVEL_DEG: f64 = 360.0;
/// Each direction must move at least this far before the chain fails to assemble, so the test cannot
/// pass on a chain that barely moves.
const MIN_TRAVEL_DEG: f64 = 2.0;
/// Lengths and positions: the chains' coordinates are within ~100 of the origin, so this is ~1e-11
/// relative, far above f64 round-off and far below any real error.
const TOL: f64 = 1e-9;
const CASES_PER_K: u32 = 64;

/// The shape of one loop of the chain.
#[derive(Clone, Debug)]
struct LoopShape {
    /// `|q_{k−1} p_k|` and its direction.
    input_len: f64,
    input_dir: f64,
    /// `|q_{k−1} r_{k−1}|` and its direction.
    base_len: f64,
    base_dir: f64,
    /// The angle at `q_k` between `q_k→p_k` and `q_k→r_{k−1}`, radians.
    transmission: f64,
    /// `|q_k p_k| / |q_k r_{k−1}|`.
    ratio: f64,
    /// Which side of `p_k → r_{k−1}` `q_k` is on.
    left: bool,
}

#[derive(Clone, Debug)]
struct ChainCase {
    origin: Point,
    loops: Vec<LoopShape>,
    /// Each body's `body_to_world` at the first pose (arbitrary: BodyFrames must honour any).
    first_poses: Vec<(f64, f64, f64)>,
}

fn loop_shape() -> impl Strategy<Value = LoopShape> {
    (0.5..1.5f64, -PI..PI, 3.0..6.0f64, -PI..PI, 60.0..120.0f64, 0.7..1.4f64, any::<bool>()).prop_map(
        |(input_len, input_dir, base_len, base_dir, transmission_deg, ratio, left)| LoopShape {
            input_len,
            input_dir,
            base_len,
            base_dir,
            transmission: transmission_deg.to_radians(),
            ratio,
            left,
        },
    )
}

fn chain_case(k: usize) -> impl Strategy<Value = ChainCase> {
    (
        (-20.0..20.0f64, -20.0..20.0f64),
        prop::collection::vec(loop_shape(), k),
        prop::collection::vec((-PI..PI, -50.0..50.0f64, -50.0..50.0f64), k),
    )
        .prop_map(|((x, y), loops, first_poses)| ChainCase { origin: Point::new(x, y), loops, first_poses })
}

/// The chain of `case`, with its joints at the first pose.
fn build(case: &ChainCase) -> Mechanism {
    let k = case.loops.len();
    let topology = Topology::chain(k);
    let id = |name: String| topology.joint(&name).unwrap_or_else(|| panic!("no joint {name}"));
    let mut joints = vec![Point::new(f64::NAN, f64::NAN); topology.joint_count()];
    joints[id("q0".into())] = case.origin;
    for (i, shape) in case.loops.iter().enumerate() {
        let step = i + 1;
        let base = joints[id(format!("q{i}"))];
        let p = base + Vec2::from_angle(shape.input_dir) * shape.input_len;
        let r = base + Vec2::from_angle(shape.base_dir) * shape.base_len;
        // The triangle p q r with angle `transmission` at q and |qp| = ratio·|qr|.
        let d = p.distance(r);
        let rho = shape.ratio;
        let qr = d / (rho * rho + 1.0 - 2.0 * rho * shape.transmission.cos()).sqrt();
        let branch = if shape.left { Branch::Positive } else { Branch::Negative };
        let q = circle_circle(p, rho * qr, r, qr, branch).expect("the triangle closes");
        let angle = (p - q).cross(r - q).abs().atan2((p - q).dot(r - q));
        assert!((angle - shape.transmission).abs() < 1e-9, "construction: {angle} vs {}", shape.transmission);
        joints[id(format!("p{step}"))] = p;
        joints[id(format!("r{i}"))] = r;
        joints[id(format!("q{step}"))] = q;
    }
    assert!(joints.iter().all(|p| p.is_finite()), "every joint is placed");
    Mechanism { topology: Arc::new(topology), joints, slider: None }
}

/// Pairs of joints a part holds rigidly: the links' pairs and every pair within a body.
fn rigid_pairs(m: &Mechanism) -> Vec<(usize, usize, f64)> {
    let mut pairs = m.topology.link_pairs();
    for b in 0..m.topology.body_count {
        let joints = &m.topology.body_part(b).joints;
        for (i, &x) in joints.iter().enumerate() {
            pairs.extend(joints[i + 1..].iter().map(|&y| (x, y)));
        }
    }
    pairs.into_iter().map(|(a, b)| (a, b, m.joints[a].distance(m.joints[b]))).collect()
}

fn check_chain(case: &ChainCase) -> TestCaseResult {
    let m = build(case);
    let topo = &m.topology;
    let plan = Plan::compile(&m).map_err(|e| TestCaseError::fail(format!("compile: {e}")))?;
    let pairs = rigid_pairs(&m);
    let first_poses: Vec<Rigid> =
        case.first_poses.iter().map(|&(angle, x, y)| Rigid::new(angle, Vec2::new(x, y))).collect();
    let frames = BodyFrames::new(&m, &first_poses);
    prop_assert_eq!(frames.body_count(), topo.body_count);
    // Each body joint in its body's coordinates.
    let local: Vec<(usize, usize, Point)> =
        topo.body_joints().into_iter().map(|(j, b)| (j, b, first_poses[b].inverse().apply(m.joints[j]))).collect();

    let start = m.crank_start();
    let mut pos = vec![Point::ORIGIN; plan.joint_count()];
    plan.solve(start, &mut pos).map_err(|e| TestCaseError::fail(format!("first pose: {e:?}")))?;
    for (j, (&ours, &given)) in pos.iter().zip(&m.joints).enumerate() {
        prop_assert!(
            ours.distance(given) <= TOL,
            "first pose: {} at {:?}, given {:?}",
            topo.joint_names[j],
            ours,
            given
        );
    }

    for direction in [1.0, -1.0] {
        let mut travel_deg = 0.0;
        while travel_deg < MAX_TRAVEL_DEG {
            let next = travel_deg + STEP_DEG;
            if plan.solve(start + direction * next.to_radians(), &mut pos).is_err() {
                break;
            }
            travel_deg = next;
            let at = direction * travel_deg;
            for &(a, b, len) in &pairs {
                let now = pos[a].distance(pos[b]);
                prop_assert!(
                    (now - len).abs() <= TOL,
                    "crank {:+}°: |{} {}| = {}, first pose {}",
                    at,
                    topo.joint_names[a],
                    topo.joint_names[b],
                    now,
                    len
                );
            }
            for &(j, b, p) in &local {
                let carried = frames.pose(b, &pos).apply(p);
                prop_assert!(
                    carried.distance(pos[j]) <= TOL,
                    "crank {:+}°: body {} puts {} at {:?}, solved {:?}",
                    at,
                    b,
                    topo.joint_names[j],
                    carried,
                    pos[j]
                );
            }
        }
        prop_assert!(
            travel_deg >= MIN_TRAVEL_DEG,
            "the chain moves only {}° in direction {} before it fails to assemble",
            travel_deg,
            direction
        );
    }
    Ok(())
}

fn run(k: usize) {
    let config = Config { cases: CASES_PER_K, failure_persistence: None, ..Config::default() };
    let mut runner = TestRunner::new(config);
    if let Err(e) = runner.run(&chain_case(k), |case| check_chain(&case)) {
        panic!("K = {k}: {e}");
    }
}

#[test]
fn chain_k1_keeps_its_lengths() {
    run(1);
}
#[test]
fn chain_k2_keeps_its_lengths() {
    run(2);
}
#[test]
fn chain_k3_keeps_its_lengths() {
    run(3);
}
#[test]
fn chain_k4_keeps_its_lengths() {
    run(4);
}
#[test]
fn chain_k5_keeps_its_lengths() {
    run(5);
}
#[test]
fn chain_k6_keeps_its_lengths() {
    run(6);
}
#[test]
fn chain_k7_keeps_its_lengths() {
    run(7);
}
#[test]
fn chain_k8_keeps_its_lengths() {
    run(8);
}

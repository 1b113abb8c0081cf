//! Path scenes end to end: a drawn curve made from the curve a known linkage traces (so a linkage
//! tracing it exactly exists) is designed for, and the design file's own check re-measures it.

use linkwright_core::analysis::{Replay, Which};
use linkwright_core::geom::{Point, Rigid};
use linkwright_core::testbed::{known_path_scene, KnownPath};
use linkwright_core::MechanismType;
use linkwright_core::{
    missed_exact_point, synthesize, validate_scene, DesignFile, Problem, Scene, Severity, Silent, Status,
    EXACT_POINT_TOLERANCE,
};

/// Millimetres per unit of the testbed.
const SCALE: f64 = 100.0;

fn designed(known: &KnownPath) -> (Problem, DesignFile) {
    let problem = Problem::new(&known.scene).expect("testbed path scenes are valid");
    let outcome = synthesize(&problem, &Silent).expect("never cancelled");
    (problem.clone(), DesignFile::from_outcome(&problem, &outcome))
}

/// Where the design's tracer is at each crank angle of its replayed travel.
fn traced(problem: &Problem, design: &DesignFile) -> Vec<Point> {
    let replay = Replay::new(problem, design, Which::Best, 720).expect("a valid design replays");
    let path = problem.path().expect("a path scene");
    (0..replay.trace.len()).map(|r| replay.frames.pose(0, replay.trace.row(r)).apply(path.tracer)).collect()
}

#[test]
fn a_known_closed_coupler_curve_is_traced_within_a_percent_once_per_turn() {
    let known = known_path_scene(MechanismType::Chain, true, 100, 0.0, 0, SCALE).expect("a known crank-rocker");
    let (problem, design) = designed(&known);
    assert_eq!(design.status, Status::Ok, "{:?}", design.reason);
    assert!(design.violations(&problem).is_empty(), "{:?}", design.violations(&problem));
    let error = design.metrics.as_ref().and_then(|m| m.path_error).expect("a path design carries its error");
    assert!(error.max_rel < 0.01, "{error:?}");
    assert!((error.max_rel * known.curve_size - error.max).abs() < 1e-9 * known.curve_size);
    let motion = design.motion.as_ref().unwrap();
    assert!(((motion.crank_end_deg - motion.crank_start_deg).abs() - 360.0).abs() < 1e-9, "{motion:?}");
    // Once round: the tracer ends where it started, and every drawn point is near the traced loop.
    let tracer = traced(&problem, &design);
    assert!(tracer[0].distance(tracer[tracer.len() - 1]) < 1e-6 * known.curve_size);
    let drawn = &problem.path().unwrap().points;
    for p in drawn {
        let near = tracer.iter().map(|q| q.distance(*p)).fold(f64::INFINITY, f64::min);
        assert!(near < 0.01 * known.curve_size, "{p:?} is {near} from the traced loop");
    }
    // The alternatives are sound too, and re-read the file says the same.
    let reread = DesignFile::from_json(&design.to_json()).expect("the file reads back");
    assert!(reread.violations(&problem).is_empty());
}

/// A six-bar's curve, asked of its own family: the Stephenson-III's bent coupler curve, and the
/// Watt-II's out-and-back stroke (the tracer runs out and comes back the same way once per turn,
/// which no four-bar's crank does), each traced within 1% once per turn.
#[test]
fn each_six_bars_own_closed_curve_is_traced_by_a_linkage_of_its_family() {
    for family in [MechanismType::StephensonThree, MechanismType::WattTwo] {
        let mut known = known_path_scene(family, true, 100, 0.0, 0, SCALE).expect("a known six-bar");
        known.scene.mechanism = linkwright_core::MechanismChoice::Only(family);
        let (problem, design) = designed(&known);
        assert!(design.violations(&problem).is_empty(), "{family:?}: {:?}", design.violations(&problem));
        assert_eq!(design.mechanism.as_ref().unwrap().mechanism_type, family);
        let error = design.metrics.as_ref().and_then(|m| m.path_error).unwrap();
        assert!(error.max_rel < 0.01, "{family:?}: {error:?}");
        let tracer = traced(&problem, &design);
        assert!(tracer[0].distance(tracer[tracer.len() - 1]) < 1e-6 * known.curve_size);
    }
}

#[test]
fn an_open_arc_is_run_from_its_first_point_to_its_last() {
    let known = known_path_scene(MechanismType::Chain, false, 50, 0.0, 1, SCALE).expect("a known crank-rocker");
    let (problem, design) = designed(&known);
    assert!(design.violations(&problem).is_empty(), "{:?}", design.violations(&problem));
    let error = design.metrics.as_ref().and_then(|m| m.path_error).unwrap();
    assert!(error.max_rel < 0.01, "{error:?}");
    let motion = design.motion.as_ref().unwrap();
    assert!((motion.crank_end_deg - motion.crank_start_deg).abs() < 360.0);
    let drawn = &problem.path().unwrap().points;
    let tracer = traced(&problem, &design);
    assert!(tracer[0].distance(drawn[0]) < 1e-9 * known.curve_size, "the body starts where it is drawn");
    let end = tracer[tracer.len() - 1].distance(drawn[drawn.len() - 1]);
    assert!(end < 0.01 * known.curve_size, "the tracer ends {end} from the last point");
}

#[test]
fn the_check_re_measures_the_path_and_refuses_a_travel_that_is_not_one_turn() {
    let known = known_path_scene(MechanismType::Chain, true, 60, 0.0, 2, SCALE).expect("a known crank-rocker");
    let (problem, design) = designed(&known);
    assert!(design.violations(&problem).is_empty());
    let mut claimed = design.clone();
    let error = claimed.metrics.as_mut().and_then(|m| m.path_error.as_mut()).unwrap();
    error.max *= 0.5;
    let violations = claimed.violations(&problem);
    assert!(violations.iter().any(|v| v.constraint == "accuracy"), "{violations:?}");

    let mut short = design.clone();
    let motion = short.motion.as_mut().unwrap();
    motion.crank_end_deg = motion.crank_start_deg + 300.0f64.copysign(motion.crank_end_deg - motion.crank_start_deg);
    let issues = short.validate(&problem);
    assert!(issues.iter().any(|i| i.to_string().contains("crank_end_deg")), "{issues:?}");
}

/// The distance of `p` from the polyline `curve`.
fn distance_from(p: Point, curve: &[Point]) -> f64 {
    curve
        .windows(2)
        .map(|w| {
            let (a, ab) = (w[0], w[1] - w[0]);
            let t = if ab.norm_sq() > 0.0 { ((p - a).dot(ab) / ab.norm_sq()).clamp(0.0, 1.0) } else { 0.0 };
            p.distance(a + ab * t)
        })
        .fold(f64::INFINITY, f64::min)
}

/// A known crank-rocker's loop drawn with noise of 1% of its size, so no linkage passes every drawn
/// point: four points marked exact are passed within the tolerance, where the design of the same
/// drawing without them passes farther from some, and the check re-measures them.
#[test]
fn a_paths_exact_points_are_passed_and_the_check_re_measures_them() {
    let known = known_path_scene(MechanismType::Chain, true, 60, 0.01, 4, SCALE).expect("a known crank-rocker");
    let exact = [7, 22, 37, 52];
    let farthest = |problem: &Problem, design: &DesignFile| {
        let tracer = traced(problem, design);
        let points = &problem.path().unwrap().points;
        exact.iter().map(|&i| distance_from(points[i], &tracer)).fold(0.0, f64::max) / known.curve_size
    };
    let (problem, free) = designed(&known);
    let missed = farthest(&problem, &free);
    assert!(missed > EXACT_POINT_TOLERANCE, "the noisy points are off the free design's curve: {missed}");
    assert!(free.metrics.as_ref().unwrap().path_error.unwrap().exact.is_none());

    let mut pinned = known.clone();
    pinned.scene.moving_bodies[0].path.as_mut().unwrap().exact = exact.to_vec();
    let (problem, design) = designed(&pinned);
    assert!(design.violations(&problem).is_empty(), "{:?}", design.violations(&problem));
    let passed = farthest(&problem, &design);
    assert!(passed <= EXACT_POINT_TOLERANCE, "every exact point within the tolerance: {passed}");
    let error = design.metrics.as_ref().unwrap().path_error.unwrap();
    let written = error.exact.expect("the file says how far the exact points are passed");
    assert!(exact.contains(&written.point) && written.distance_rel <= EXACT_POINT_TOLERANCE, "{written:?}");
    assert!(missed_exact_point(&error).is_none());
    assert!((written.distance_rel - passed).abs() < 1e-3 * EXACT_POINT_TOLERANCE, "{written:?} against {passed}");
    // A file that claims the exact points closer than they are fails its check.
    let mut claimed = design.clone();
    let x = claimed.metrics.as_mut().and_then(|m| m.path_error.as_mut()).and_then(|e| e.exact.as_mut()).unwrap();
    x.distance *= 0.5;
    assert!(claimed.violations(&problem).iter().any(|v| v.constraint == "accuracy"));
}

/// How far (degrees) the body of `design` has turned from what `poses` say, since where it starts,
/// where its tracer passes nearest each pose's tracer: the largest, measured on the replayed travel.
fn worst_turn_miss(problem: &Problem, design: &DesignFile, poses: &[[f64; 3]]) -> f64 {
    let replay = Replay::new(problem, design, Which::Best, 1440).expect("a valid design replays");
    let tracer = problem.path().expect("a path scene").tracer;
    let frames: Vec<Rigid> = (0..replay.trace.len()).map(|r| replay.frames.pose(0, replay.trace.row(r))).collect();
    let start = Rigid::from_pose(poses[0]);
    poses[1..]
        .iter()
        .map(|&pose| {
            let want = Rigid::from_pose(pose);
            let at = want.apply(tracer);
            let row =
                frames.iter().min_by(|a, b| a.apply(tracer).distance(at).total_cmp(&b.apply(tracer).distance(at)));
            let turned = row.unwrap().angle() - frames[0].angle();
            let miss = (turned - (want.angle() - start.angle())).to_degrees();
            (miss + 180.0).rem_euclid(360.0) - 180.0
        })
        .fold(0.0, |worst: f64, m| worst.max(m.abs()))
}

/// A known crank-rocker's loop with two more poses of its body on the way, where the known linkage
/// puts it: the design passes both (place and angle, as the file's own pose errors say and the
/// replayed travel shows), besides tracing the loop, where the design of the loop alone turns the
/// body otherwise there.
#[test]
fn a_path_bodys_later_poses_are_passed_at_their_angles() {
    let mut known = known_path_scene(MechanismType::Chain, true, 60, 0.0, 5, SCALE).expect("a known crank-rocker");
    let poses = [known.scene.moving_bodies[0].poses[0], known.poses_along[20], known.poses_along[40]];
    let (problem, free) = designed(&known);
    let loose = worst_turn_miss(&problem, &free, &poses);
    assert!(loose > 1.0, "the loop alone does not fix the body's turn: {loose}°");
    known.scene.moving_bodies[0].poses = poses.to_vec();
    let (problem, design) = designed(&known);
    let held = worst_turn_miss(&problem, &design, &poses);
    assert!(held <= 1.0, "turned as the poses say where it passes them: {held}°");
    assert!(design.violations(&problem).is_empty(), "{:?}", design.violations(&problem));
    let metrics = design.metrics.as_ref().unwrap();
    assert_eq!(metrics.pose_errors.len(), 3, "one row per pose");
    let worst = metrics.worst_pose_error.expect("a worst pose error");
    assert!(worst.position_rel_d <= 0.01 && worst.angle_deg <= 1.0, "every pose reached: {worst:?}");
    assert!(metrics.path_error.unwrap().max_rel < 0.01, "{:?}", metrics.path_error);
    assert_eq!(design.motion.as_ref().unwrap().pose_crank_deg.len(), 3);
}

#[test]
fn the_same_seed_gives_the_same_path_design() {
    let known = known_path_scene(MechanismType::Chain, false, 30, 0.005, 3, SCALE).expect("a known crank-rocker");
    let (_, a) = designed(&known);
    let (_, b) = designed(&known);
    assert_eq!(a.mechanism, b.mechanism);
    assert_eq!(a.motion, b.motion);
}

/// A path scene with one edit, validated: the fields of its errors.
fn errors_of(edit: impl FnOnce(&mut Scene)) -> Vec<String> {
    let mut scene =
        known_path_scene(MechanismType::Chain, false, 20, 0.0, 0, SCALE).expect("a known crank-rocker").scene;
    edit(&mut scene);
    validate_scene(&scene).iter().filter(|i| i.severity == Severity::Error).map(|i| i.field.clone()).collect()
}

#[test]
fn a_path_scene_is_refused_where_it_cannot_be_traced_and_says_which_field() {
    assert!(errors_of(|_| {}).is_empty(), "the testbed's scene is valid");
    assert_eq!(errors_of(|s| s.moving_bodies[0].poses.clear()), ["moving_bodies[0].poses"], "where it starts");
    assert_eq!(
        errors_of(|s| s.moving_bodies[0].poses[0][0] += 50.0),
        ["moving_bodies[0].poses[0]"],
        "the tracer starts on the curve's first point"
    );
    assert_eq!(
        errors_of(|s| s.moving_bodies[0].path.as_mut().unwrap().points[3] = Point::new(1e9, 0.0)),
        ["moving_bodies[0].path.points[3]"]
    );
    assert_eq!(
        errors_of(|s| {
            let path = s.moving_bodies[0].path.as_mut().unwrap();
            let p = path.points[0];
            path.points = vec![p; 1001];
        }),
        ["moving_bodies[0].path.points"]
    );
    assert_eq!(
        errors_of(|s| {
            let path = s.moving_bodies[0].path.as_mut().unwrap();
            path.points.truncate(2);
            path.closed = true;
        }),
        ["moving_bodies[0].path.points"],
        "a loop needs three points"
    );
    let two = errors_of(|s| {
        let mut other = s.moving_bodies[0].clone();
        other.path = None;
        let [x, y, a] = other.poses[0];
        other.poses = vec![[x, y + 500.0, a], [x + 10.0, y + 500.0, a]];
        s.moving_bodies.push(other);
    });
    assert!(two.contains(&"moving_bodies[0].path".to_string()), "{two:?}");
    // The tracer placed by the pose, not the pose's origin, is what must be on the curve.
    let moved = errors_of(|s| {
        let body = &mut s.moving_bodies[0];
        body.path.as_mut().unwrap().tracer = Point::new(1.0, 0.0);
        let start = Rigid::from_pose(body.poses[0]).apply(Point::new(-1.0, 0.0));
        body.poses[0] = [start.x, start.y, 0.0];
    });
    assert!(moved.is_empty(), "{moved:?}");
    // Later poses: each with its tracer on the curve, farther along than the one before.
    let along = known_path_scene(MechanismType::Chain, false, 20, 0.0, 0, SCALE).unwrap().poses_along;
    assert!(errors_of(|s| s.moving_bodies[0].poses.extend([along[8], along[14]])).is_empty());
    assert_eq!(
        errors_of(|s| s.moving_bodies[0].poses.extend([along[14], along[8]])),
        ["moving_bodies[0].poses[2]"],
        "in order along the path"
    );
    assert_eq!(
        errors_of(|s| s.moving_bodies[0].poses.push([along[8][0] + 50.0, along[8][1], along[8][2]])),
        ["moving_bodies[0].poses[1]"],
        "on the path"
    );
    assert_eq!(
        errors_of(|s| s.moving_bodies[0].path.as_mut().unwrap().exact = vec![3, 20]),
        ["moving_bodies[0].path.exact[1]"],
        "an exact point is a point of the curve"
    );
}

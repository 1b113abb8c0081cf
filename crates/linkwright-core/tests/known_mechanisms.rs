//! Designs for motions made by known exact mechanisms (so a valid linkage through every pose exists),
//! including motions with more poses than the linkage type can hit in general: each must give a valid
//! design that the independent check passes, reaching the last pose, with small errors at the others.

use linkwright_core::testbed::{known_scene, Known};
use linkwright_core::{synthesize, DesignFile, MechanismType, Problem, Silent, Status};

/// The design of the known scene, with its worst pose error and last pose error (fractions of d).
fn design(kind: Known, poses: usize, seed: u64) -> (String, DesignFile, f64, f64) {
    let known = known_scene(kind, poses, seed, 100.0).unwrap();
    let mut scene = known.scene.clone();
    // Chains of five and six bodies through three poses need the default samples (a valid one of
    // tens of thousands); so does a Watt-II six-bar, whose body may go out and back.
    let many = (kind.bodies() >= 5 && poses >= 3) || kind == Known::one(MechanismType::WattTwo);
    scene.settings.samples = if many { 100_000 } else { 20_000 };
    scene.settings.iterations = 8;
    let problem = Problem::new(&scene).unwrap();
    let pool = rayon::ThreadPoolBuilder::new().num_threads(2).build().unwrap();
    let outcome = pool.install(|| synthesize(&problem, &Silent)).unwrap();
    let file = DesignFile::from_outcome(&problem, &outcome);
    let label = format!("{} K={} N={poses} seed {seed}", kind.mechanism_type().id(), kind.bodies());
    assert_eq!(file.status, Status::Ok, "{label}: {:?}", file.reason);
    assert_eq!(file.violations(&problem), vec![], "{label}");
    let metrics = file.metrics.as_ref().unwrap();
    let worst = metrics.worst_pose_error.unwrap().position_rel_d;
    let last = metrics.pose_errors[poses - 1].iter().map(|m| m.position_rel_d).fold(0.0, f64::max);
    (label, file, worst, last)
}

/// Over-determined motions and long chains: four-bars through 6–10 poses, six-bars through 4–6, the
/// K = 3 chain through 4, and longer chains through 2 and 3, all made by a known linkage. Before fits
/// that are not exactly rigid became candidates, these found "no linkage could be fitted" or a
/// handful of fits.
#[test]
fn over_determined_motions_of_known_linkages_get_close_designs() {
    let mut cases: Vec<(Known, usize)> = Vec::new();
    cases.extend((6..=10).map(|n| (Known::chain(1), n)));
    cases.extend((4..=6).map(|n| (Known::chain(2), n)));
    cases.push((Known::chain(3), 4));
    // Chains of four to six bodies through three poses: before each ternary link was drawn until
    // its loop kept its branch, and before their pose noise was scaled down, chains of five and six
    // found no design here.
    cases.extend((4..=6).map(|k| (Known::chain(k), 3)));
    cases.extend((4..=6).map(|k| (Known::chain(k), 2)));
    // The Watt-II six-bar's body rides a four-bar, which meets five poses exactly.
    cases.extend([6, 8].map(|n| (Known::one(MechanismType::WattTwo), n)));
    let mut worsts = Vec::new();
    for (kind, poses) in cases {
        let (label, _, worst, last) = design(kind, poses, 0);
        // The end poses are kept: every design comes to rest at the last pose.
        assert!(last <= 0.005, "{label}: last pose missed by {last}·d");
        worsts.push(worst);
    }
    worsts.sort_by(f64::total_cmp);
    let median = worsts[worsts.len() / 2];
    assert!(median <= 0.05, "median worst pose error {median}·d over {worsts:?}");
}

/// Where the linkage type has the freedom to hit every pose (a four-bar or a Watt-II six-bar through up
/// to five, a Stephenson-III six-bar through three as its sampler builds it, any chain through two, a
/// slider-crank through up to four), the design comes close to all of them.
#[test]
fn determined_motions_of_known_linkages_are_reached() {
    for (kind, poses) in [
        (Known::chain(1), 3),
        (Known::chain(1), 5),
        (Known::chain(2), 2),
        (Known::chain(3), 2),
        (Known::one(MechanismType::SliderCrank), 3),
        (Known::one(MechanismType::SliderCrank), 4),
        (Known::one(MechanismType::WattTwo), 3),
        (Known::one(MechanismType::WattTwo), 4),
        (Known::one(MechanismType::StephensonThree), 3),
    ] {
        let (label, _, worst, last) = design(kind, poses, 1);
        assert!(last <= 0.005, "{label}: last pose missed by {last}·d");
        assert!(worst <= 0.05, "{label}: a pose missed by {worst}·d");
    }
}

/// Poses a scene marks must-hit are reached like the last one (within 0.5% of d and 0.5°) by the best
/// design and by every alternative, on a six-pose motion of a known four-bar, which a four-bar cannot
/// pass exactly in general: unmarked, the same run misses one of those poses by more.
#[test]
fn must_hit_poses_are_reached_by_every_design() {
    let known = known_scene(Known::chain(1), 6, 0, 100.0).unwrap();
    let attempt = |marked: &[usize], nudge: f64| {
        let mut scene = known.scene.clone();
        scene.moving_bodies[0].poses[3][0] += nudge;
        scene.settings.samples = 20_000;
        scene.settings.iterations = 8;
        scene.must_hit_poses = marked.to_vec();
        let problem = Problem::new(&scene).unwrap();
        let pool = rayon::ThreadPoolBuilder::new().num_threads(2).build().unwrap();
        let outcome = pool.install(|| synthesize(&problem, &Silent)).unwrap();
        (problem.clone(), DesignFile::from_outcome(&problem, &outcome))
    };
    let run = |marked: &[usize]| {
        let (problem, file) = attempt(marked, 0.0);
        assert_eq!(file.status, Status::Ok, "{marked:?}: {:?}", file.reason);
        assert_eq!(file.violations(&problem), vec![], "{marked:?}");
        file
    };
    let marked = [2, 4];
    let worst_at = |metrics: &linkwright_core::Metrics, i: usize| {
        let misses = &metrics.pose_errors[i];
        let position = misses.iter().map(|m| m.position_rel_d).fold(0.0, f64::max);
        let angle = misses.iter().map(|m| m.angle_deg).fold(0.0, f64::max);
        (position, angle)
    };
    let free = run(&[]);
    let free_worst = marked.iter().map(|&i| worst_at(free.metrics.as_ref().unwrap(), i).0).fold(0.0, f64::max);
    assert!(free_worst > 0.005, "unmarked, the design already hits poses {marked:?} (within {free_worst}·d)");
    let held = run(&marked);
    let held_worst = marked.iter().map(|&i| worst_at(held.metrics.as_ref().unwrap(), i).0).fold(0.0, f64::max);
    eprintln!(
        "must-hit poses {marked:?}: best design misses them by {free_worst:.4}·d unmarked, {held_worst:.4}·d marked"
    );
    let designs = std::iter::once(held.metrics.as_ref().unwrap()).chain(held.alternatives.iter().map(|a| &a.metrics));
    for (k, metrics) in designs.enumerate() {
        for &i in &marked {
            let (position, angle) = worst_at(metrics, i);
            assert!(position <= 0.005 && angle <= 0.5, "design {k}, pose {i}: {position}·d, {angle}°");
        }
    }
    // Six poses to hit exactly are more than a four-bar passes in general (this motion's own four-bar
    // does, until one pose is moved off it by a tenth of the body's width): the run says to mark fewer.
    let d = known.scene.moving_bodies[0].polygon.iter().map(|p| p.x).fold(f64::NEG_INFINITY, f64::max)
        - known.scene.moving_bodies[0].polygon.iter().map(|p| p.x).fold(f64::INFINITY, f64::min);
    let (_, none) = attempt(&[1, 2, 3, 4], 0.1 * d);
    assert_eq!(none.status, Status::NoSolution);
    let reason = none.reason.unwrap_or_default();
    assert!(
        reason.contains("pass at most 5 poses exactly") && reason.contains("mark fewer must_hit_poses"),
        "{reason}"
    );
}

/// Pinned joints stay exactly where they are pinned, in the best design and every alternative. Both
/// ground pivots of a known four-bar pinned where that four-bar has them (its three poses are then
/// met exactly by its own moving joints): the design reaches the poses. A pivot pinned elsewhere is
/// kept there too, and a pin only the six-bars have a joint for leaves `auto` those families.
#[test]
fn pinned_joints_stay_where_they_are_pinned() {
    let known = known_scene(Known::chain(1), 3, 2, 100.0).unwrap();
    let at = |name: &str| known.mechanism.joint(name).unwrap();
    let design = |pins: &[(&str, linkwright_core::geom::Point)]| {
        let mut scene = known.scene.clone();
        scene.mechanism = linkwright_core::MechanismChoice::Auto;
        scene.settings.samples = 20_000;
        scene.settings.iterations = 8;
        scene.pinned_joints = pins.iter().map(|&(name, p)| (name.to_string(), p)).collect();
        let problem = Problem::new(&scene).unwrap();
        let pool = rayon::ThreadPoolBuilder::new().num_threads(2).build().unwrap();
        let outcome = pool.install(|| synthesize(&problem, &Silent)).unwrap();
        let file = DesignFile::from_outcome(&problem, &outcome);
        assert_eq!(file.status, Status::Ok, "{pins:?}: {:?}", file.reason);
        assert_eq!(file.violations(&problem), vec![], "{pins:?}");
        let mechanisms: Vec<_> = std::iter::once(file.mechanism.clone().unwrap())
            .chain(file.alternatives.iter().map(|a| a.mechanism.clone()))
            .collect();
        assert!(mechanisms.len() > 1, "{pins:?}: no alternatives to check");
        for m in &mechanisms {
            for &(name, p) in pins {
                assert_eq!(m.joints[name], p, "{pins:?}: {name} of a {:?}", m.mechanism_type);
            }
        }
        (file, mechanisms)
    };
    let (exact, _) = design(&[("q0", at("q0")), ("r0", at("r0"))]);
    let worst = exact.metrics.unwrap().worst_pose_error.unwrap().position_rel_d;
    assert!(worst <= 0.01, "pinned at the known pivots, a pose is missed by {worst}·d");
    let elsewhere = at("q0") + linkwright_core::geom::Vec2::new(7.0, -3.0);
    design(&[("q0", elsewhere)]);
    let (_, six_bars) = design(&[("u0", at("q0") + linkwright_core::geom::Vec2::new(-30.0, 10.0))]);
    use linkwright_core::MechanismType::{StephensonThree, WattTwo};
    assert!(six_bars.iter().all(|m| [WattTwo, StephensonThree].contains(&m.mechanism_type)));
}

/// A Watt-II six-bar whose body goes out and comes back the way it went (the four-bar it rides turns
/// back while the crank turns on): the known linkage is judged valid as the synthesis judges its
/// samples, and a warm start from it returns a design that reaches every pose within 5% of d, with
/// the independent check passing. Before, the body's places on the way back were matched to the way
/// out, and the known linkage was rejected as out of order.
#[test]
fn a_warm_start_from_a_known_out_and_back_six_bar_is_kept() {
    use linkwright_core::{assess, synthesize_with, Options, Start};
    for (poses, seed) in [(5, 0), (7, 0), (6, 1), (8, 1)] {
        let known = known_scene(Known::watt_two_out_and_back(), poses, seed, 100.0).unwrap();
        let problem = Problem::new(&known.scene).unwrap();
        let label = format!("out and back, {poses} poses, seed {seed}");
        assert!(matches!(assess(&problem, &known.mechanism), Some(Ok(_))), "{label}: the known linkage is rejected");
        let previous = [known.mechanism.clone()];
        let outcome =
            synthesize_with(&problem, &Options { start: Start::Warm(&previous), printable: None }, &Silent).unwrap();
        assert_valid_within(&problem, &DesignFile::from_outcome(&problem, &outcome), 0.05, &label);
    }
}

/// `file` is a design of `problem` that the independent check accepts and that misses no pose by
/// more than `bound`·d.
fn assert_valid_within(problem: &Problem, file: &DesignFile, bound: f64, label: &str) {
    assert_eq!(file.status, Status::Ok, "{label}: {:?}", file.reason);
    assert_eq!(file.violations(problem), vec![], "{label}");
    let worst = file.metrics.as_ref().unwrap().worst_pose_error.unwrap().position_rel_d;
    assert!(worst <= bound, "{label}: a pose missed by {worst}·d");
}

/// A design far from a pose drawn is never presented as reaching it: the out-and-back six-bar through
/// four poses, searched with few samples, gets a Watt-II missing a pose by 31% of d. The
/// search goes on once from other samples, and the design file names the pose it is far from, with
/// the miss its own pose errors show.
#[test]
fn a_design_far_from_a_pose_says_so() {
    use linkwright_core::{FAR_ANGLE_DEG, FAR_POSITION_REL_D};
    let known = known_scene(Known::watt_two_out_and_back(), 4, 0, 100.0).unwrap();
    let mut scene = known.scene.clone();
    scene.settings.samples = 10_000;
    let problem = Problem::new(&scene).unwrap();
    let outcome = synthesize(&problem, &Silent).unwrap();
    assert_eq!(outcome.stats.samples, 2 * 10_000, "a second search from other samples");
    let file = DesignFile::from_outcome(&problem, &outcome);
    let metrics = file.metrics.as_ref().expect("a design");
    let far = metrics.far_from_pose.as_ref().expect("marked far");
    let miss = metrics.pose_errors[far.pose - 1][0];
    assert_eq!((far.body.as_str(), far.miss), ("body1", miss));
    assert!(miss.position_rel_d > FAR_POSITION_REL_D || miss.angle_deg > FAR_ANGLE_DEG, "{miss:?}");
    // Every other pose is nearer than the one named.
    let past = |m: &linkwright_core::PoseMiss| (m.position_rel_d / FAR_POSITION_REL_D).max(m.angle_deg / FAR_ANGLE_DEG);
    assert!(metrics.pose_errors.iter().flatten().all(|m| past(m) <= past(&miss)));
    // The same scene with the default samples finds a design near every pose, unmarked.
    let problem = Problem::new(&known.scene).unwrap();
    let file = DesignFile::from_outcome(&problem, &synthesize(&problem, &Silent).unwrap());
    let metrics = file.metrics.as_ref().expect("a design");
    assert_eq!(metrics.far_from_pose, None, "{:?}", metrics.worst_pose_error);
}

/// The out-and-back six-bar found cold: its crank's tip is placed so that the four-bar the body rides
/// turns back between the right poses. With the tip drawn at random, these scenes (five and six
/// poses, seed 0) got no design at all in the default 200,000 samples.
#[test]
fn a_cold_search_finds_an_out_and_back_six_bar() {
    for poses in [5, 6] {
        let known = known_scene(Known::watt_two_out_and_back(), poses, 0, 100.0).unwrap();
        let problem = Problem::new(&known.scene).unwrap();
        let file = DesignFile::from_outcome(&problem, &synthesize(&problem, &Silent).unwrap());
        assert_valid_within(&problem, &file, 0.05, &format!("{poses} poses"));
    }
}

/// A Stephenson-III through more poses than three: the joints drawn at random are moved so that the
/// rocker's joint, which the coupler carrying the body places, keeps its distance to the rocker's
/// pivot at every pose. Drawn at random with the pivot at the least-squares centre, the rocker
/// stretched between poses and these scenes' designs missed a pose by 7-11% of d.
#[test]
fn a_stephenson_three_through_many_poses_keeps_its_rocker_rigid() {
    for (poses, seed) in [(5, 1), (6, 0)] {
        let known = known_scene(Known::one(MechanismType::StephensonThree), poses, seed, 1.0).unwrap();
        let problem = Problem::new(&known.scene).unwrap();
        let file = DesignFile::from_outcome(&problem, &synthesize(&problem, &Silent).unwrap());
        assert_valid_within(&problem, &file, 0.05, &format!("{poses} poses, seed {seed}"));
    }
}

/// The one-body six-bars through as many poses as the body's four-bar meets exactly, or more, with
/// the default settings: each design comes within 0.05·d of every pose. With the poses perturbed as
/// far as for a four-bar, these missed a pose by 0.05–0.10·d (the Stephenson-III) or found no design
/// (the out-and-back Watt-II).
#[test]
fn six_bars_through_many_poses_come_close() {
    let stephenson = Known::one(MechanismType::StephensonThree);
    for (kind, poses) in [(stephenson, 5), (stephenson, 7), (stephenson, 8), (Known::watt_two_out_and_back(), 8)] {
        let known = known_scene(kind, poses, 0, 100.0).unwrap();
        let problem = Problem::new(&known.scene).unwrap();
        let file = DesignFile::from_outcome(&problem, &synthesize(&problem, &Silent).unwrap());
        assert_valid_within(&problem, &file, 0.05, &format!("{} through {poses} poses", kind.mechanism_type().id()));
    }
}

/// A search that settles off the poses goes on once from other samples: the known three-body chain
/// through three poses (scene seed 1) gets a design missing a pose by 0.09·d and 3° from the default
/// search, which then searches again; the known Stephenson-III through three poses, met by the first
/// search, is searched once.
#[test]
fn a_design_off_the_poses_gets_a_second_search() {
    let searched = |kind: Known, seed: u64| {
        let known = known_scene(kind, 3, seed, 100.0).unwrap();
        let problem = Problem::new(&known.scene).unwrap();
        let outcome = synthesize(&problem, &Silent).unwrap();
        let file = DesignFile::from_outcome(&problem, &outcome);
        let worst = file.metrics.as_ref().expect("a design").worst_pose_error.unwrap().position_rel_d;
        (outcome.stats.samples / known.scene.settings.samples, worst)
    };
    let (rounds, worst) = searched(Known::one(MechanismType::StephensonThree), 0);
    assert_eq!(rounds, 1, "three poses met ({worst}·d): one search");
    assert!(worst <= 0.05, "{worst}");
    let (rounds, worst) = searched(Known::chain(3), 1);
    assert_eq!(rounds, 2, "poses missed by {worst}·d: a second search");
}

/// A design close to a dead point goes on once from other samples, when the transmission has a
/// weight: the known out-and-back Watt-II through four poses (scene seed 0) gets one at 12.5° from
/// its first search, and searches again; with no transmission weight the same motion is searched
/// once.
#[test]
fn a_design_near_a_dead_point_gets_a_second_search() {
    let known = known_scene(Known::watt_two_out_and_back(), 4, 0, 100.0).unwrap();
    let rounds = |transmission: f64| {
        let mut scene = known.scene.clone();
        scene.weights.transmission = transmission;
        let problem = Problem::new(&scene).unwrap();
        let outcome = synthesize(&problem, &Silent).unwrap();
        let file = DesignFile::from_outcome(&problem, &outcome);
        let metrics = file.metrics.expect("a design");
        let worst = metrics.worst_pose_error.unwrap();
        assert!(worst.position_rel_d <= 0.05 && worst.angle_deg <= 2.0, "near every pose: {worst:?}");
        outcome.stats.samples / scene.settings.samples
    };
    assert_eq!(rounds(known.scene.weights.transmission), 2);
    assert_eq!(rounds(0.0), 1);
}

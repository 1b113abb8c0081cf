//! `DesignFile::validate`: a design file is refused, field by field, before anything simulates, draws
//! or fabricates it; and what every reader builds on it (the check, fabrication) refuses it too.

use linkwright_core::fab::{self, FabError, PrintSettings, Travel};
use linkwright_core::testbed::{known_scene, Known};
use linkwright_core::{DesignFile, PartJson, PartKindJson, Problem};
use std::time::{Duration, Instant};

/// A known four-bar with its scene: a design that is sound.
fn four_bar() -> (Problem, DesignFile) {
    let known = known_scene(Known::chain(1), 3, 7, 100.0).unwrap();
    (Problem::new(&known.scene).unwrap(), known.design())
}

fn fields(design: &DesignFile, problem: &Problem) -> Vec<String> {
    design.validate(problem).into_iter().map(|i| i.field).collect()
}

#[test]
fn a_sound_design_has_no_issue() {
    let (problem, design) = four_bar();
    assert_eq!(design.validate(&problem), vec![]);
    assert_eq!(design.violations(&problem), vec![]);
    assert_eq!(design.usable_mechanisms().len(), 1);
}

#[test]
fn another_format_is_refused_and_nothing_else_is_read() {
    let (problem, mut design) = four_bar();
    design.linkwright = "design/2".into();
    design.motion.as_mut().unwrap().crank_end_deg = f64::NAN;
    let issues = design.validate(&problem);
    assert_eq!(issues.len(), 1, "{issues:?}");
    assert_eq!(issues[0].field, "linkwright");
    assert!(issues[0].message.contains("design/1"), "{}", issues[0]);
    assert!(design.violations(&problem).iter().all(|v| v.constraint == "format"));
}

#[test]
fn an_extra_link_that_locks_the_linkage_is_refused() {
    let (problem, mut design) = four_bar();
    let m = design.mechanism.as_mut().unwrap();
    // The ground pivot q0 joined to the body's joint q1: a triangle q0 p1 q1 that cannot move.
    m.parts.push(PartJson {
        name: "brace".into(),
        kind: PartKindJson::Link,
        body: None,
        joints: vec!["q0".into(), "q1".into()],
    });
    let issues = design.validate(&problem);
    assert_eq!(issues.len(), 1, "{issues:?}");
    assert_eq!(issues[0].field, "mechanism.parts");
    assert!(issues[0].message.contains("0 degrees of freedom"), "{}", issues[0]);
    assert!(design.usable_mechanisms().is_empty(), "a locked linkage is no start for a search either");
    assert!(!design.violations(&problem).is_empty(), "and the check does not pass it");
    let refused = fab::fabricate_design(&problem, &design, &PrintSettings::default());
    assert!(matches!(refused, Err(FabError::Invalid(_))), "{refused:?}");
}

#[test]
fn a_link_left_loose_is_refused() {
    let (problem, mut design) = four_bar();
    let m = design.mechanism.as_mut().unwrap();
    m.parts.retain(|p| p.name != "rocker");
    let issues = design.validate(&problem);
    assert!(issues.iter().any(|i| i.message.contains("2 degrees of freedom")), "{issues:?}");
}

#[test]
fn travels_of_a_turn_or_more_are_refused_before_anything_is_simulated() {
    let (problem, design) = four_bar();
    let start = design.motion.as_ref().unwrap().crank_start_deg;
    for end in [start + 360.0, start - 400.0, 1e7, 1e9, 1e18, f64::INFINITY, f64::NAN] {
        let mut d = design.clone();
        d.motion.as_mut().unwrap().crank_end_deg = end;
        let t = Instant::now();
        assert_eq!(fields(&d, &problem), ["motion.crank_end_deg"], "{end}");
        let refused = fab::fabricate_design(&problem, &d, &PrintSettings::default());
        assert!(matches!(refused, Err(FabError::Invalid(_))), "{end}: {refused:?}");
        assert!(t.elapsed() < Duration::from_secs(1), "{end}: {:?}", t.elapsed());
    }
    // Below the file format, the motion itself is bounded too.
    let mechanism = design.mechanism.as_ref().unwrap().to_mechanism().unwrap();
    let travel = Travel { start: 0.0, end: 1e18 };
    assert!(matches!(fab::motion_trace(&mechanism, travel), Err(FabError::Motion(_))));
}

#[test]
fn references_numbers_and_the_scene_are_checked_field_by_field() {
    let (problem, design) = four_bar();
    let mut d = design.clone();
    {
        let m = d.mechanism.as_mut().unwrap();
        m.parts[1].joints[0] = "nowhere".into();
        m.joints.insert("far".into(), linkwright_core::geom::Point::new(1e12, 0.0));
    }
    d.metrics.as_mut().unwrap().accuracy = f64::NAN;
    d.motion.as_mut().unwrap().pose_crank_deg.push(10.0);
    let found = fields(&d, &problem);
    for field in
        ["mechanism.parts[1].joints[0]", "mechanism.joints[\"far\"]", "motion.pose_crank_deg", "metrics.accuracy"]
    {
        assert!(found.iter().any(|f| f == field), "{field} in {found:?}");
    }

    let mut d = design.clone();
    d.mechanism.as_mut().unwrap().parts.iter_mut().find(|p| p.kind == PartKindJson::Body).unwrap().body = Some(3);
    let issues = d.validate(&problem);
    assert!(issues.iter().any(|i| i.message.contains("another scene")), "{issues:?}");

    let mut d = design.clone();
    d.alternatives = vec![
        linkwright_core::Alternative {
            mechanism: design.mechanism.clone().unwrap(),
            motion: design.motion.clone().unwrap(),
            metrics: design.metrics.clone().unwrap(),
        };
        2
    ];
    d.alternatives[1].motion.crank_start_deg = 1e9;
    assert_eq!(fields(&d, &problem), ["alternatives[1].motion.crank_start_deg"]);
}

#[test]
fn names_with_control_characters_are_refused() {
    let (problem, mut design) = four_bar();
    design.mechanism.as_mut().unwrap().parts[0].name = "gro\0und".into();
    assert_eq!(fields(&design, &problem), ["mechanism.parts[0].name"]);
}

#[test]
fn a_no_solution_design_carries_no_mechanism() {
    let (problem, mut design) = four_bar();
    design.status = linkwright_core::Status::NoSolution;
    assert_eq!(fields(&design, &problem), ["mechanism", "motion", "metrics"]);
}

/// Moving a joint of a design gives the design of the moved linkage: its own motion found again and
/// its metrics recomputed, which the independent check agrees with. The known four-bar passes its
/// poses exactly; with its rocker's pivot moved by a tenth of the body's size it still moves through
/// them, farther off. Moved no joint, it is the known design again. A pivot moved far breaks it,
/// and the check that fails comes back as data.
#[test]
fn moving_a_joint_gives_the_moved_linkages_design() {
    use linkwright_core::geom::Point;
    use linkwright_core::{EditError, Status};
    use std::collections::BTreeMap;
    let (problem, design) = four_bar();
    let d = problem.bodies[0].size;
    let worst = |file: &DesignFile| file.metrics.as_ref().unwrap().worst_pose_error.unwrap().position_rel_d;

    let same = design.with_joints_moved(&problem, None, &BTreeMap::new()).unwrap();
    assert_eq!(same.status, Status::Ok);
    assert_eq!(same.violations(&problem), vec![]);
    assert!(worst(&same) < 1e-6, "the known four-bar misses by {}·d", worst(&same));
    let (a, b) = (&same.motion.as_ref().unwrap().pose_crank_deg, &design.motion.as_ref().unwrap().pose_crank_deg);
    assert!(a.iter().zip(b).all(|(x, y)| (x - y).abs() < 1e-4), "{a:?} against {b:?}");

    let r0 = design.mechanism.as_ref().unwrap().joints["r0"];
    let moved_to = Point::new(r0.x + 0.1 * d, r0.y);
    let moves = BTreeMap::from([("r0".to_string(), moved_to)]);
    let moved = design.with_joints_moved(&problem, None, &moves).unwrap();
    assert_eq!(moved.mechanism.as_ref().unwrap().joints["r0"], moved_to);
    assert!(moved.alternatives.is_empty());
    assert!(worst(&moved) > 0.005, "moved, the linkage still passes the poses within {}·d", worst(&moved));
    assert!(moved.violations(&problem).iter().all(|v| v.constraint != "accuracy" && v.constraint != "format"));

    let far = BTreeMap::from([("r0".to_string(), Point::new(r0.x + 50.0 * d, r0.y))]);
    assert!(matches!(design.with_joints_moved(&problem, None, &far), Err(EditError::Rejected(_))));
    let unknown = BTreeMap::from([("x9".to_string(), r0)]);
    assert_eq!(design.with_joints_moved(&problem, None, &unknown), Err(EditError::UnknownJoint("x9".into())));
    assert_eq!(design.with_joints_moved(&problem, Some(0), &moves), Err(EditError::NoAlternative(0, 0)));
    let nan = BTreeMap::from([("r0".to_string(), Point::new(f64::NAN, 0.0))]);
    assert_eq!(design.with_joints_moved(&problem, None, &nan), Err(EditError::BadPlace("r0".into())));
}

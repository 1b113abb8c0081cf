//! The nine-pose four-bar task (tests/fixtures/nine_pose_four_bar.json) is a usable scene, and its poses
//! are the published task's: points and unit direction vectors (see tests/fixtures/README.md).

use linkwright_core::{Problem, Scene};

#[test]
fn nine_pose_task_is_a_valid_scene_with_the_published_poses() {
    let path = format!("{}/tests/fixtures/nine_pose_four_bar.json", env!("CARGO_MANIFEST_DIR"));
    let scene = Scene::from_json(&std::fs::read_to_string(path).expect("the fixture exists")).expect("parses");
    let problem = Problem::new(&scene).expect("validates");
    assert!(problem.warnings.is_empty(), "{:?}", problem.warnings);
    assert_eq!(problem.pose_count, 9);
    // The task's points and direction vectors, as published (x, y, cos, sin).
    let task = [
        (18.8, 12.1, 0.6216099682706644, -0.7833269096274834),
        (13.3, 18.1, 1.0, 0.0),
        (6.3, 19.8, 0.7648421872844885, 0.644217687237691),
        (-0.4, 17.1, 0.0707372016677029, 0.9974949866040544),
        (-2.7, 10.3, -0.9422223406686581, 0.3349881501559051),
        (-1.1, 6.0, -0.6662760212798241, -0.7457052121767203),
        (0.2, 1.7, -0.4161468365471424, -0.9092974268256817),
        (3.4, -2.2, -0.32328956686350335, -0.9463000876874145),
        (7.8, -4.9, -0.5048461045998576, -0.8632093666488737),
    ];
    for (pose, (x, y, c, s)) in problem.bodies[0].poses.iter().zip(task) {
        let t = pose.translation();
        assert_eq!((t.x, t.y), (x, y));
        // The pose angle is the direction's, to the four decimals the file keeps.
        let a = pose.angle();
        assert!((a.cos() - c).abs() < 1e-5 && (a.sin() - s).abs() < 1e-5, "{pose:?} against ({c}, {s})");
    }
    // The fixed body stays clear of every pose's outline, with room to spare.
    let ground = &problem.fixed[0];
    for pose in &problem.bodies[0].poses {
        let outline = problem.bodies[0].outline.transformed(pose);
        let gap = linkwright_core::geom::outline_distance(outline.vertices(), ground.vertices());
        assert!(gap > 5.0, "{gap}");
    }
}

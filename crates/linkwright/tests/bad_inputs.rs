//! `linkwright design` on bad inputs: every validation rule ends the run with exit code 2, names the
//! offending field on stderr, and writes nothing.

use serde_json::{json, Value};
use std::path::{Path, PathBuf};
use std::process::Command;

/// A valid scene: a 200 × 20 ground and a 20 × 80 lid visiting two poses well clear of it.
fn scene() -> Value {
    json!({
        "linkwright": "scene/1",
        "name": "bad input test",
        "fixed_bodies": [{"name": "ground", "polygon": [[0, 0], [200, 0], [200, 20], [0, 20]]}],
        "moving_bodies": [{"name": "lid", "polygon": [[0, 0], [20, 0], [20, 80], [0, 80]],
                           "poses": [[50, 100, 0], [120, 60, -90]]}],
        "settings": {"samples": 1000, "particles": 10, "iterations": 2}
    })
}

/// What one run left behind.
struct Run {
    code: Option<i32>,
    stderr: String,
    wrote_output: bool,
}

/// A fresh directory of its own for test `name`.
fn workdir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("linkwright-bad-inputs-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// Runs `linkwright design SCENE -o OUT` on `text` written to a file (or on a missing file for `None`).
fn design(name: &str, text: Option<&str>) -> Run {
    let dir = workdir(name);
    let scene_path = dir.join("bad.json");
    if let Some(text) = text {
        std::fs::write(&scene_path, text).unwrap();
    }
    let out = dir.join("out");
    let output = Command::new(env!("CARGO_BIN_EXE_linkwright"))
        .arg("design")
        .arg(&scene_path)
        .arg("-o")
        .arg(&out)
        .output()
        .expect("the binary runs");
    let run = Run {
        code: output.status.code(),
        stderr: String::from_utf8_lossy(&output.stderr).into_owned(),
        wrote_output: Path::new(&out).exists(),
    };
    let _ = std::fs::remove_dir_all(&dir);
    run
}

/// Runs `design` on `scene` and asserts a bad-input failure whose stderr holds every one of `expected`.
fn assert_rejected(name: &str, scene: &Value, expected: &[&str]) {
    let run = design(name, Some(&scene.to_string()));
    assert_eq!(run.code, Some(2), "{name}: exit code; stderr:\n{}", run.stderr);
    for e in expected {
        assert!(run.stderr.contains(e), "{name}: stderr lacks {e:?}:\n{}", run.stderr);
    }
    assert!(!run.wrote_output, "{name}: the output directory was created");
}

#[test]
fn unreadable_file() {
    let run = design("unreadable", None);
    assert_eq!(run.code, Some(2), "{}", run.stderr);
    assert!(run.stderr.contains("bad.json"), "{}", run.stderr);
    assert!(!run.wrote_output);
}

#[test]
fn invalid_json() {
    let run = design("invalid_json", Some("{\"linkwright\": \"scene/1\", "));
    assert_eq!(run.code, Some(2), "{}", run.stderr);
    assert!(run.stderr.contains("not valid JSON"), "{}", run.stderr);
    assert!(!run.wrote_output);
}

#[test]
fn wrong_type_names_its_json_path() {
    let mut s = scene();
    s["moving_bodies"][0]["poses"][1] = json!("left");
    assert_rejected("wrong_type", &s, &["moving_bodies[0].poses[1]"]);
}

#[test]
fn unknown_format() {
    let mut s = scene();
    s["linkwright"] = json!("scene/9");
    assert_rejected("unknown_format", &s, &["error: linkwright: unknown format"]);
}

/// A unit with no known length in millimetres is refused with the units accepted: no later command
/// (fabricating, weighing) could use the scene.
#[test]
fn unknown_units() {
    let mut s = scene();
    s["units"] = json!("furlongs");
    assert_rejected(
        "unknown_units",
        &s,
        &["error: units: is \"furlongs\", not a unit of length this version knows; use mm, cm, m, in, ft or µm"],
    );
}

#[test]
fn no_moving_body() {
    let mut s = scene();
    s["moving_bodies"] = json!([]);
    assert_rejected("no_moving_body", &s, &["error: moving_bodies: "]);
}

#[test]
fn one_pose_only() {
    let mut s = scene();
    s["moving_bodies"][0]["poses"] = json!([[50, 100, 0]]);
    assert_rejected("one_pose", &s, &["error: moving_bodies[0].poses: "]);
}

#[test]
fn different_pose_counts() {
    let mut s = scene();
    let flap = json!({"name": "flap", "polygon": [[0, 0], [20, 0], [20, 20], [0, 20]],
                      "poses": [[300, 100, 0], [330, 100, 0], [360, 100, 0]]});
    s["moving_bodies"].as_array_mut().unwrap().push(flap);
    assert_rejected("pose_counts", &s, &["error: moving_bodies[1].poses: body 'flap' has 3 poses"]);
}

#[test]
fn bad_polygons() {
    let mut s = scene();
    s["fixed_bodies"][0]["polygon"] = json!([[0, 0], [200, 0]]);
    s["linkage_region"] = json!([[0, 0], [10, 10], [20, 20]]);
    s["avoid_regions"] = json!([[[0, 0], [2, 2], [2, 0], [0, 1]]]);
    assert_rejected(
        "bad_polygons",
        &s,
        &["error: fixed_bodies[0].polygon: ", "error: linkage_region: ", "error: avoid_regions[0]: "],
    );
}

#[test]
fn huge_pose_number() {
    let mut s = scene();
    s["moving_bodies"][0]["poses"][1] = json!([1e300, 0, 0]);
    assert_rejected("huge_pose", &s, &["error: moving_bodies[0].poses[1]: "]);
}

/// Not an error: the ground pivots stand still anyway; the person is warned and gets a design.
#[test]
fn no_fixed_body_is_a_warning() {
    let mut s = scene();
    s["fixed_bodies"] = json!([]);
    s["settings"] = json!({"samples": 500, "iterations": 2, "particles": 10});
    let run = design("no_fixed_body", Some(&s.to_string()));
    assert_eq!(run.code, Some(0), "stderr:\n{}", run.stderr);
    assert!(run.stderr.contains("warning: fixed_bodies: "), "{}", run.stderr);
    assert!(run.wrote_output);
}

#[test]
fn slider_crank_with_two_bodies() {
    let mut s = scene();
    let flap = json!({"name": "flap", "polygon": [[0, 0], [20, 0], [20, 20], [0, 20]],
                      "poses": [[300, 100, 0], [330, 100, 0]]});
    s["moving_bodies"].as_array_mut().unwrap().push(flap);
    s["mechanism"] = json!("slider_crank");
    assert_rejected("slider_crank", &s, &["error: mechanism: "]);
}

#[test]
fn settings_out_of_range() {
    let mut s = scene();
    s["settings"] = json!({"samples": 0, "particles": 0, "iterations": 5000, "pose_tolerance": -1,
                           "angle_tolerance_deg": 100, "min_transmission_deg": 85});
    let fields =
        ["samples", "particles", "iterations", "pose_tolerance", "angle_tolerance_deg", "min_transmission_deg"];
    let expected: Vec<String> = fields.iter().map(|f| format!("error: settings.{f}: ")).collect();
    assert_rejected("settings", &s, &expected.iter().map(String::as_str).collect::<Vec<_>>());
}

#[test]
fn bad_weights() {
    let mut s = scene();
    s["weights"] = json!({"accuracy": -1, "smoothness": 0, "location": 0, "size": 0, "transmission": 0});
    assert_rejected("weights_negative", &s, &["error: weights.accuracy: "]);
    s["weights"]["accuracy"] = json!(0);
    assert_rejected("weights_zero", &s, &["error: weights: "]);
}

#[test]
fn overlap_at_a_pose() {
    let mut s = scene();
    s["moving_bodies"][0]["poses"][1] = json!([100, 15, 0]);
    assert_rejected("overlap", &s, &["error: moving_bodies[0].poses[1]: body 'lid' overlaps fixed body 'ground'"]);
}

#[test]
fn unknown_fields_warn_alongside_errors() {
    let mut s = scene();
    s["colour"] = json!("red");
    s["settings"]["threads"] = json!(4);
    s["settings"]["samples"] = json!(0);
    assert_rejected(
        "unknown_fields",
        &s,
        &["warning: colour: unknown field 'colour'", "warning: settings.threads: ", "error: settings.samples: "],
    );
}

#[test]
fn a_mistake_repeated_340000_times_gets_a_short_answer() {
    let mut s = scene();
    s["must_hit_poses"] = json!(vec![3; 340_000]);
    let run = design("repeated_mistake", Some(&s.to_string()));
    assert_eq!(run.code, Some(2), "{}", &run.stderr[..run.stderr.len().min(2000)]);
    assert!(run.stderr.len() < 10_000, "{} bytes of stderr", run.stderr.len());
    let listed = run.stderr.lines().filter(|l| l.contains("there is no pose 3")).count();
    assert_eq!(listed, linkwright_core::MAX_LISTED_ISSUES, "{}", run.stderr);
    assert!(run.stderr.contains("50 error(s) listed and 339950 more problems"), "{}", run.stderr);
}

//! The limits of what a run may ask for (`scene::limits`, `--threads`, `--samples`): each input that once
//! made a run take minutes, gigabytes or a thousand threads is now refused at once with exit code 2 and
//! a message that names the field and the bound, and writes nothing.

mod common;

use common::{example_text, linkwright, text, workdir};
use serde_json::{json, Value};

/// The garbage truck example as JSON, to be edited.
fn truck() -> Value {
    serde_json::from_str(&example_text("k1_garbage_truck")).unwrap()
}

/// Runs `linkwright design` on `scene` with `extra` arguments; returns the exit code, stderr and whether
/// the output folder was written.
fn design(name: &str, scene: &Value, extra: &[&str]) -> (Option<i32>, String, bool) {
    let dir = workdir(name);
    let path = dir.join("scene.json");
    std::fs::write(&path, scene.to_string()).unwrap();
    let out = dir.join("out");
    let mut args = vec!["design", path.to_str().unwrap(), "-o", out.to_str().unwrap()];
    args.extend_from_slice(extra);
    let run = linkwright(&args);
    (run.status.code(), text(&run.stderr), out.exists())
}

/// Asserts that `scene` is refused with exit code 2, naming `field` and saying `phrase`, writing nothing.
fn assert_refused(name: &str, scene: &Value, extra: &[&str], field: &str, phrase: &str) {
    let (code, stderr, wrote) = design(name, scene, extra);
    assert_eq!(code, Some(2), "{name}: {stderr}");
    assert!(stderr.contains(field) && stderr.contains(phrase), "{name}: no '{field}' / '{phrase}' in {stderr}");
    assert!(!wrote, "{name}: a refused run wrote its output folder");
}

/// Every coordinate of the scene times `factor`.
fn scaled(mut scene: Value, factor: f64) -> Value {
    fn scale_points(points: &mut Value, factor: f64) {
        for p in points.as_array_mut().unwrap() {
            for v in p.as_array_mut().unwrap() {
                *v = json!(v.as_f64().unwrap() * factor);
            }
        }
    }
    for body in scene["fixed_bodies"].as_array_mut().unwrap() {
        scale_points(&mut body["polygon"], factor);
    }
    for body in scene["moving_bodies"].as_array_mut().unwrap() {
        scale_points(&mut body["polygon"], factor);
        for pose in body["poses"].as_array_mut().unwrap() {
            pose[0] = json!(pose[0].as_f64().unwrap() * factor);
            pose[1] = json!(pose[1].as_f64().unwrap() * factor);
        }
    }
    if let Some(region) = scene.get_mut("linkage_region") {
        scale_points(region, factor);
    }
    scene
}

#[test]
fn a_drawing_a_hundred_kilometres_across_is_refused() {
    // Scaled 100,000 times the truck is 50 km long: its printability check once took a minute and then
    // aborted on a 2 GB allocation.
    assert_refused("huge", &scaled(truck(), 1e5), &[], "fixed_bodies[0].polygon", "farther than 1e6");
}

#[test]
fn outlines_with_thousands_of_vertices_are_refused() {
    // A fixed body of 10,000 vertices once took 42 s, and one of 30,000 over two minutes.
    let mut scene = truck();
    let circle: Vec<Value> = (0..10_000)
        .map(|i| {
            let a = std::f64::consts::TAU * f64::from(i) / 10_000.0;
            json!([300.0 + 100.0 * a.cos(), -200.0 + 100.0 * a.sin()])
        })
        .collect();
    scene["fixed_bodies"][0]["polygon"] = Value::Array(circle);
    assert_refused("vertices", &scene, &[], "fixed_bodies[0].polygon", "have 10132 vertices in all, this one 10000");
}

#[test]
fn ten_thousand_avoid_regions_are_refused() {
    let mut scene = truck();
    let square = |i: usize| {
        let x = 1000.0 + 20.0 * i as f64;
        json!([[x, 0], [x + 10.0, 0], [x + 10.0, 10], [x, 10]])
    };
    scene["avoid_regions"] = Value::Array((0..10_000).map(square).collect());
    assert_refused("regions", &scene, &[], "avoid_regions", "has 10000 avoid regions; at most 50");
}

#[test]
fn a_run_is_bounded_in_samples_particles_and_threads() {
    let mut scene = truck();
    scene["settings"] = json!({"particles": 1_000_000});
    assert_refused("particles", &scene, &[], "settings.particles", "between 1 and 1000");
    let scene = truck();
    // A hundred thousand threads once started over a thousand before failing.
    assert_refused("threads", &scene, &["--threads", "100000"], "--threads", "1..=256");
    assert_refused("samples", &scene, &["--samples", "20000000"], "--samples", "1..=1000000");
}

#[test]
fn the_sampling_work_is_bounded_whoever_sets_the_samples() {
    // Eight bodies through twenty poses at a million samples once took nine minutes: samples × bodies
    // × poses is bounded, whether the scene or the command line asks for the samples.
    let body = |k: usize| {
        let poses: Vec<Value> = (0..20)
            .map(|i| json!([35.0 * k as f64 + 0.4 * f64::from(i), 0.3 * f64::from(i), 2.0 * f64::from(i)]))
            .collect();
        json!({"name": format!("b{k}"), "polygon": [[0, 0], [10, 0], [10, 10], [0, 10]], "poses": poses})
    };
    let scene = json!({
        "linkwright": "scene/1",
        "fixed_bodies": [{"name": "ground", "polygon": [[-20, -40], [300, -40], [300, -30], [-20, -30]]}],
        "moving_bodies": (0..8).map(body).collect::<Vec<_>>(),
        "settings": {"samples": 1000}
    });
    let phrase = "use at most 62500 samples";
    assert_refused("work", &scene, &["--samples", "100000"], "settings.samples", phrase);
    let mut scene = scene;
    scene["settings"]["samples"] = json!(1_000_000);
    assert_refused("work in the scene", &scene, &[], "settings.samples", phrase);
}

//! The CLI as a person or a script uses it: design, check, simulate, exit codes and outputs.

mod common;
use common::{design_truck, example, linkwright, text, workdir};
use serde_json::Value;
use std::path::{Path, PathBuf};

/// Designs the garbage truck with a small budget into `dir`, returning the design file's path.
fn design_garbage_truck(dir: &Path, threads: &str) -> PathBuf {
    let out = dir.join(format!("threads{threads}"));
    let run = design_truck(&out, &["--seed", "5", "--threads", threads]);
    assert!(run.status.success(), "stderr: {}", text(&run.stderr));
    let summary = text(&run.stdout);
    assert!(summary.starts_with("garbage truck: "), "{summary}");
    assert!(summary.contains("seed 5"), "{summary}");
    out.join("design.json")
}

#[test]
fn design_writes_the_design_its_pictures_and_passes_check() {
    let dir = workdir("design");
    let design = design_garbage_truck(&dir, "2");
    let out = design.parent().unwrap();
    for file in ["design.json", "design.svg", "animation.svg"] {
        assert!(out.join(file).is_file(), "{file} missing");
    }
    let parsed: Value = serde_json::from_str(&std::fs::read_to_string(&design).unwrap()).unwrap();
    assert_eq!(parsed["linkwright"], "design/1");
    assert_eq!(parsed["status"], "ok");
    assert_eq!(parsed["stats"]["seed"], 5);

    let check = linkwright(&["check", &example("k1_garbage_truck"), design.to_str().unwrap()]);
    assert_eq!(check.status.code(), Some(0), "{}", text(&check.stdout));
    // It says how small the transmission gets and where along the motion, as the design file does
    // (re-simulated in its own steps: to a few tenths of a degree and a per cent of the travel).
    let said = text(&check.stdout);
    let number_after = |words: &str| -> f64 {
        let rest = &said[said.find(words).unwrap_or_else(|| panic!("{said} lacks {words}")) + words.len()..];
        rest.chars().take_while(|c| c.is_ascii_digit() || *c == '.').collect::<String>().parse().unwrap()
    };
    let metrics = &parsed["metrics"];
    let motion = &parsed["motion"];
    let (start, end) = (motion["crank_start_deg"].as_f64().unwrap(), motion["crank_end_deg"].as_f64().unwrap());
    let share = (metrics["min_transmission_crank_deg"].as_f64().unwrap() - start) / (end - start);
    assert!(
        (number_after("min transmission ") - metrics["min_transmission_deg"].as_f64().unwrap()).abs() < 0.5,
        "{said}"
    );
    assert!((number_after("° at ") - 100.0 * share).abs() <= 2.0, "{said}");

    // A project the app saved (the scene with its design) reads as its scene; a fault in it is named
    // under `scene`.
    let scene: Value = serde_json::from_str(&std::fs::read_to_string(example("k1_garbage_truck")).unwrap()).unwrap();
    let mut project = serde_json::json!({"linkwright": "project/1", "scene": scene, "design": parsed, "which": null});
    let saved = out.join("project.json");
    std::fs::write(&saved, project.to_string()).unwrap();
    let check = linkwright(&["check", saved.to_str().unwrap(), design.to_str().unwrap()]);
    assert_eq!(check.status.code(), Some(0), "{}{}", text(&check.stdout), text(&check.stderr));
    project["scene"]["moving_bodies"] = Value::from("none");
    std::fs::write(&saved, project.to_string()).unwrap();
    let check = linkwright(&["check", saved.to_str().unwrap(), design.to_str().unwrap()]);
    assert_eq!(check.status.code(), Some(2), "{}", text(&check.stderr));
    assert!(text(&check.stderr).contains("scene.moving_bodies"), "{}", text(&check.stderr));

    // A design whose reported accuracy is wrong, and whose crank starts elsewhere, fails the check.
    let mut tampered = parsed.clone();
    tampered["metrics"]["accuracy"] = Value::from(123.0);
    tampered["motion"]["crank_start_deg"] = Value::from(parsed["motion"]["crank_start_deg"].as_f64().unwrap() + 5.0);
    let bad = out.join("tampered.json");
    std::fs::write(&bad, tampered.to_string()).unwrap();
    let check = linkwright(&["check", &example("k1_garbage_truck"), bad.to_str().unwrap()]);
    assert_eq!(check.status.code(), Some(1));
    let report = text(&check.stdout);
    assert!(report.contains("accuracy:") && report.contains("order:"), "{report}");

    let sim = linkwright(&["simulate", &example("k1_garbage_truck"), design.to_str().unwrap(), "--steps", "10"]);
    assert!(sim.status.success(), "{}", text(&sim.stderr));
    let csv = text(&sim.stdout);
    let lines: Vec<&str> = csv.lines().collect();
    assert_eq!(lines.len(), 12, "header and 11 rows");
    // A column pair per joint, in the order of their names, starting where the design's joints are.
    let joints = parsed["mechanism"]["joints"].as_object().unwrap();
    let columns: Vec<String> = joints.keys().map(|n| format!("{n}_x,{n}_y")).collect();
    assert_eq!(lines[0], format!("step,crank_deg,{}", columns.join(",")));
    let first: Vec<f64> = lines[1].split(',').map(|v| v.parse().unwrap()).collect();
    for (k, at) in joints.values().enumerate() {
        let (x, y) = (first[2 + 2 * k], first[3 + 2 * k]);
        assert!((x - at[0].as_f64().unwrap()).abs() < 1e-9 && (y - at[1].as_f64().unwrap()).abs() < 1e-9);
    }
}

#[test]
fn one_and_two_threads_write_the_same_design() {
    let dir = workdir("threads");
    let strip = |path: PathBuf| {
        let mut v: Value = serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap();
        v["stats"]["seconds"] = Value::Null;
        v.to_string()
    };
    let one = strip(design_garbage_truck(&dir, "1"));
    let two = strip(design_garbage_truck(&dir, "2"));
    assert_eq!(one, two);
}

#[test]
fn json_flag_prints_the_design() {
    let dir = workdir("json");
    let run = linkwright(&[
        "design",
        &example("k2_wall_chair"),
        "-o",
        dir.join("out").to_str().unwrap(),
        "--samples",
        "3000",
        "--json",
    ]);
    assert!(run.status.success(), "{}", text(&run.stderr));
    let v: Value = serde_json::from_str(&text(&run.stdout)).expect("stdout is the design JSON");
    assert_eq!(v["linkwright"], "design/1");
    assert_eq!(v["mechanism"]["type"], "chain");
}

#[test]
fn an_impossible_scene_is_a_no_solution_with_a_reason() {
    // The body must cross a wall that reaches far beyond any linkage: every motion collides.
    let scene = serde_json::json!({
        "linkwright": "scene/1", "name": "through the wall",
        "fixed_bodies": [{"name": "wall", "polygon": [[-5, -1000], [5, -1000], [5, 1000], [-5, 1000]]}],
        "moving_bodies": [{"name": "box", "polygon": [[0, 0], [20, 0], [20, 20], [0, 20]],
                           "poses": [[-60, 0, 0], [40, 0, 0]]}],
        "linkage_region": [[-100, -60], [100, -60], [100, 60], [-100, 60]],
        "settings": {"samples": 2000, "iterations": 3}
    });
    let dir = workdir("impossible");
    let path = dir.join("scene.json");
    std::fs::write(&path, scene.to_string()).unwrap();
    let out = dir.join("out");
    let run = linkwright(&["design", path.to_str().unwrap(), "-o", out.to_str().unwrap()]);
    assert_eq!(run.status.code(), Some(0), "{}", text(&run.stderr));
    let v: Value = serde_json::from_str(&std::fs::read_to_string(out.join("design.json")).unwrap()).unwrap();
    assert_eq!(v["status"], "no_solution");
    let reason = v["reason"].as_str().unwrap();
    assert!(reason.contains("collision") || reason.contains("hit a fixed body"), "{reason}");
    assert!(text(&run.stdout).contains("no solution"));
    let check = linkwright(&["check", path.to_str().unwrap(), out.join("design.json").to_str().unwrap()]);
    assert_eq!(check.status.code(), Some(0));
}

#[test]
fn help_lists_the_commands() {
    let run = linkwright(&["--help"]);
    let help = text(&run.stdout);
    for command in ["design", "check", "simulate", "analyze"] {
        assert!(help.contains(command), "{help}");
    }
}

#[test]
fn check_refuses_an_endless_travel_at_once() {
    let dir = workdir("endless");
    let design = design_garbage_truck(&dir, "2");
    let mut v: Value = serde_json::from_str(&std::fs::read_to_string(&design).unwrap()).unwrap();
    v["motion"]["crank_end_deg"] = Value::from(1e15);
    let bad = dir.join("endless.json");
    std::fs::write(&bad, v.to_string()).unwrap();
    let check = linkwright(&["check", &example("k1_garbage_truck"), bad.to_str().unwrap()]);
    assert_eq!(check.status.code(), Some(2), "an unusable design file is bad input");
    let stderr = text(&check.stderr);
    assert!(stderr.contains("motion.crank_end_deg") && stderr.contains("720"), "{stderr}");
}

/// A design whose links fit the bed but whose other parts do not (the reference scene `k1_limitation`:
/// a slider-crank whose guide and a connector are hundreds of millimetres long at 1:1) is said to be
/// unbuildable for those parts and a scale at which the bed they need shrinks onto the default 220 mm
/// bed, not for links that fit.
#[test]
fn an_unbuildable_model_names_the_parts_that_do_not_fit() {
    let dir = workdir("limitation");
    let scene = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../linkwright-core/tests/fixtures/reference-scenes/k1_limitation.json");
    let out = dir.join("out");
    let run = linkwright(&["design", scene.to_str().unwrap(), "-o", out.to_str().unwrap(), "--samples", "5000"]);
    assert!(run.status.success(), "{}", text(&run.stderr));
    let file: Value = serde_json::from_str(&std::fs::read_to_string(out.join("design.json")).unwrap()).unwrap();
    let reason = file["build"]["reason"].as_str().unwrap();
    assert_eq!(file["build"]["buildable"], false);
    assert!(reason.contains("slider_guide") && reason.contains("fit the print bed in no turn at 1:1"), "{reason}");
    assert!(!reason.contains("a link can span"), "{reason}");
    let number_after = |word: &str| -> f64 {
        let rest = &reason[reason.find(word).unwrap_or_else(|| panic!("{word}: {reason}")) + word.len()..];
        rest.split(|c: char| !c.is_ascii_digit() && c != '.').next().unwrap().parse().unwrap()
    };
    let (bed_needed_mm, scale) = (number_after("need a bed "), number_after("print at 1:"));
    assert!(bed_needed_mm > 220.0 && bed_needed_mm / scale <= 220.0, "{reason}");
    assert!(reason.contains("or smaller"), "{reason}");
}

/// A real object drawn at its real size designs as a printed model at a scale that fits; printed at
/// 1:1 it is still designed, marked as not buildable that way with the reason in numbers, and the
/// command offers its own flags (the library names only the build).
#[test]
fn a_real_size_object_designs_as_a_scaled_model_and_says_when_a_scale_cannot_print_it() {
    // The truck drawn in metres: every linkage is tens of metres long.
    let dir = workdir("unprintable");
    let mut scene: Value =
        serde_json::from_str(&std::fs::read_to_string(example("k1_garbage_truck")).unwrap()).unwrap();
    scene["units"] = "m".into();
    let path = dir.join("truck_in_metres.json");
    std::fs::write(&path, scene.to_string()).unwrap();
    let out = dir.join("out");
    let design = |extra: &[&str]| {
        let mut args = vec!["design", path.to_str().unwrap(), "-o", out.to_str().unwrap(), "--samples", "3000"];
        args.extend_from_slice(extra);
        let run = linkwright(&args);
        assert!(run.status.success(), "{}", text(&run.stderr));
        let file: Value = serde_json::from_str(&std::fs::read_to_string(out.join("design.json")).unwrap()).unwrap();
        (text(&run.stdout), text(&run.stderr), file)
    };
    let (stdout, _, file) = design(&[]);
    assert!(stdout.contains("; a printed model at 1:"), "{stdout}");
    assert_eq!((file["status"].as_str(), file["build"]["buildable"].as_bool()), (Some("ok"), Some(true)));
    assert_eq!(file["build"]["asked"], "model:auto");

    let (stdout, stderr, file) = design(&["--build", "model:1:1"]);
    assert!(stdout.contains("NOT buildable as a printed model at 1:1"), "{stdout}");
    assert!(stdout.contains("print at 1:") && stdout.contains("full size") && !stdout.contains("--"), "{stdout}");
    assert!(stderr.contains("more than the 287 mm a link can span") && stderr.contains("hint: --build"), "{stderr}");
    assert_eq!((file["status"].as_str(), file["build"]["buildable"].as_bool()), (Some("ok"), Some(false)));

    let bad = linkwright(&["design", path.to_str().unwrap(), "--build", "model:1:0"]);
    assert_eq!(bad.status.code(), Some(2));
    assert!(text(&bad.stderr).contains("model:auto"), "{}", text(&bad.stderr));
}

/// `analyze --json`: the torque at every crank angle of the design's travel (which it spans), each
/// moving part's mass and share, and the peak, which is the largest |torque|; a scene mass doubled
/// doubles the body's share. The table form names its unit.
#[test]
fn analyze_gives_the_torque_along_the_motion() {
    let dir = workdir("analyze");
    let design = design_garbage_truck(&dir, "2");
    let scene = example("k1_garbage_truck");
    let run = linkwright(&["analyze", &scene, design.to_str().unwrap(), "--json"]);
    assert!(run.status.success(), "stderr: {}", text(&run.stderr));
    let torque: Value = serde_json::from_str(&text(&run.stdout)).unwrap();
    let file: Value = serde_json::from_str(&std::fs::read_to_string(&design).unwrap()).unwrap();
    let numbers = |v: &Value| v.as_array().unwrap().iter().map(|x| x.as_f64().unwrap()).collect::<Vec<f64>>();
    let (crank, tau) = (numbers(&torque["crank_deg"]), numbers(&torque["torque_nm"]));
    assert_eq!(crank.len(), tau.len());
    let motion = &file["motion"];
    let (start, end) = (motion["crank_start_deg"].as_f64().unwrap(), motion["crank_end_deg"].as_f64().unwrap());
    assert!((crank[0] - start).abs() < 1e-9 && (crank[crank.len() - 1] - end).abs() < 1e-9);
    let peak = tau.iter().fold(0.0f64, |m, t| m.max(t.abs()));
    assert_eq!(torque["peak_nm"].as_f64(), Some(peak));
    let parts = torque["parts"].as_array().unwrap();
    let names: Vec<&str> = file["mechanism"]["parts"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|p| p["kind"] != "fixed")
        .map(|p| p["name"].as_str().unwrap())
        .collect();
    assert_eq!(parts.iter().map(|p| p["name"].as_str().unwrap()).collect::<Vec<_>>(), names);
    for (k, t) in tau.iter().enumerate() {
        let sum: f64 = parts.iter().map(|p| p["torque_nm"][k].as_f64().unwrap()).sum();
        assert!((sum - t).abs() <= 1e-12 * (1.0 + peak), "row {k}: the parts sum to {sum}, not {t}");
    }

    // The springs that balance it: the torque with them, its peak, and each spring as the format
    // says (anchors on parts the design has, at the first pose).
    let balanced = numbers(&torque["torque_with_springs_nm"]);
    assert_eq!(balanced.len(), tau.len());
    let balanced_peak = balanced.iter().fold(0.0f64, |m, t| m.max(t.abs()));
    assert_eq!(torque["peak_with_springs_nm"].as_f64(), Some(balanced_peak));
    assert!(balanced_peak < peak, "{balanced_peak} against {peak}");
    let springs = torque["springs"].as_array().unwrap();
    assert!((1..=2).contains(&springs.len()), "{springs:?}");
    let all_parts: Vec<&str> =
        file["mechanism"]["parts"].as_array().unwrap().iter().map(|p| p["name"].as_str().unwrap()).collect();
    for spring in springs {
        match spring["kind"].as_str() {
            Some("extension") => {
                assert!(
                    spring["stiffness_n_per_m"].as_f64().unwrap() > 0.0
                        && spring["free_length"].as_f64().unwrap() > 0.0
                );
                for (end, anchor) in spring["anchors"].as_array().unwrap().iter().enumerate() {
                    assert!(all_parts.contains(&anchor["part"].as_str().unwrap()), "{anchor}");
                    assert_eq!(anchor["point"], spring["ends"][0][end], "the first row's ends are the anchors");
                }
                assert_eq!(spring["anchors"][0]["part"], "ground");
            }
            Some("torsion") => {
                assert!(all_parts.contains(&spring["part"].as_str().unwrap()), "{spring}");
                assert!(spring["stiffness_nm_per_rad"].as_f64().unwrap() > 0.0 && spring["free_angle_deg"].is_number());
            }
            other => panic!("a spring of kind {other:?}"),
        }
    }

    // Built full size, the body weighs the scene's mass_kg: twice the mass, twice its share.
    let with_mass = |kg: f64| {
        let mut heavier: Value = serde_json::from_str(&std::fs::read_to_string(&scene).unwrap()).unwrap();
        heavier["moving_bodies"][0]["mass_kg"] = Value::from(kg);
        let path = dir.join(format!("body_of_{kg}_kg.json"));
        std::fs::write(&path, heavier.to_string()).unwrap();
        let run = linkwright(&[
            "analyze",
            path.to_str().unwrap(),
            design.to_str().unwrap(),
            "--json",
            "--build",
            "full:plywood",
        ]);
        assert!(run.status.success(), "stderr: {}", text(&run.stderr));
        serde_json::from_str::<Value>(&text(&run.stdout)).unwrap()
    };
    let (one, two) = (with_mass(1.0), with_mass(2.0));
    let share = |t: &Value, k: usize| {
        t["parts"].as_array().unwrap().iter().find(|p| p["name"] == "body1").unwrap()["torque_nm"][k].as_f64().unwrap()
    };
    let peak = one["peak_nm"].as_f64().unwrap();
    for k in 0..tau.len() {
        assert!((share(&two, k) - 2.0 * share(&one, k)).abs() <= 1e-12 * (1.0 + peak));
    }
    assert!(share(&one, tau.len() / 2) != share(&torque, tau.len() / 2), "the model is weighed as printed");

    // The springs are searched in parallel, and found the same on one thread.
    let one_thread = std::process::Command::new(env!("CARGO_BIN_EXE_linkwright"))
        .args(["analyze", &scene, design.to_str().unwrap(), "--json"])
        .env("RAYON_NUM_THREADS", "1")
        .output()
        .unwrap();
    assert!(one_thread.status.success(), "stderr: {}", text(&one_thread.stderr));
    assert_eq!(serde_json::from_slice::<Value>(&one_thread.stdout).unwrap(), torque);

    let table = linkwright(&["analyze", &scene, design.to_str().unwrap()]);
    assert!(table.status.success());
    let table = text(&table.stdout);
    assert!(table.contains("torque (N·mm)") && table.contains("peak "), "{table}");
    assert!(table.contains("counterbalance:") && table.contains("with springs"), "{table}");
}

#[test]
fn a_path_scene_designs_a_linkage_that_traces_it_and_check_says_how_closely() {
    let dir = workdir("path");
    let out = dir.join("walking_foot");
    let run = linkwright(&[
        "design",
        &example("walking_foot"),
        "-o",
        out.to_str().unwrap(),
        "--samples",
        "50000",
        "--threads",
        "2",
    ]);
    assert!(run.status.success(), "stderr: {}", text(&run.stderr));
    let summary = text(&run.stdout);
    assert!(summary.contains("traces the drawn path within"), "{summary}");
    let design: Value = serde_json::from_str(&std::fs::read_to_string(out.join("design.json")).unwrap()).unwrap();
    let error = &design["metrics"]["path_error"];
    let max_rel = error["max_rel"].as_f64().expect("a path design writes its distance from the path");
    assert!(max_rel < 0.01, "{error}");
    // The summary's millimetres are the file's.
    assert!(summary.contains(&format!("within {:.3} mm", error["max"].as_f64().unwrap())), "{summary}");
    let motion = &design["motion"];
    let span = motion["crank_end_deg"].as_f64().unwrap() - motion["crank_start_deg"].as_f64().unwrap();
    assert!((span.abs() - 360.0).abs() < 1e-9, "a closed path turns the crank once: {motion}");
    let design_path = out.join("design.json");
    let check = linkwright(&["check", &example("walking_foot"), design_path.to_str().unwrap()]);
    assert_eq!(check.status.code(), Some(0), "{}", text(&check.stdout));
    assert!(text(&check.stdout).contains("traces the drawn path within"), "{}", text(&check.stdout));
    let svg = std::fs::read_to_string(out.join("design.svg")).unwrap();
    assert!(svg.contains("class=\"drawn-path\"") && svg.contains("class=\"traced-path\""));
}

/// The walking foot with three of its points marked exact: the summary and `check` say how closely
/// they are passed, as the file writes it; a point the path does not have is refused as bad input,
/// naming the field.
#[test]
fn a_paths_exact_points_are_designed_for_and_a_missing_one_is_refused() {
    let dir = workdir("path-exact");
    let mut scene: Value = serde_json::from_str(&std::fs::read_to_string(example("walking_foot")).unwrap()).unwrap();
    scene["moving_bodies"][0]["path"]["exact"] = serde_json::json!([0, 20, 39]);
    let path = dir.join("foot.json");
    std::fs::write(&path, scene.to_string()).unwrap();
    let out = dir.join("foot");
    let args = ["design", path.to_str().unwrap(), "-o", out.to_str().unwrap(), "--samples", "20000"];
    let run = linkwright(&args);
    assert_eq!(run.status.code(), Some(0), "{}", text(&run.stderr));
    let design: Value = serde_json::from_str(&std::fs::read_to_string(out.join("design.json")).unwrap()).unwrap();
    let exact = &design["metrics"]["path_error"]["exact"];
    let distance = exact["distance"].as_f64().expect("the file says how far the exact points are passed");
    assert!(exact["distance_rel"].as_f64().unwrap() <= linkwright_core::EXACT_POINT_TOLERANCE, "{exact}");
    let summary = text(&run.stdout);
    assert!(summary.contains(&format!("passing its exact points within {distance:.3} mm")), "{summary}");
    let check = linkwright(&["check", path.to_str().unwrap(), out.join("design.json").to_str().unwrap()]);
    assert_eq!(check.status.code(), Some(0), "{}", text(&check.stdout));
    assert!(text(&check.stdout).contains("passing its exact points within"), "{}", text(&check.stdout));

    scene["moving_bodies"][0]["path"]["exact"] = serde_json::json!([48]);
    std::fs::write(&path, scene.to_string()).unwrap();
    let bad = linkwright(&["design", path.to_str().unwrap(), "-o", out.to_str().unwrap()]);
    assert_eq!(bad.status.code(), Some(2), "{}", text(&bad.stderr));
    let words = text(&bad.stderr);
    assert!(words.contains("moving_bodies[0].path.exact[0]") && words.contains("there is no point 48"), "{words}");
}

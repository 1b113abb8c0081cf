//! Design files as untrusted input: `check`, `simulate` and `fabricate` refuse what they cannot use
//! with exit code 2 and the field to change, quickly and in little memory; whatever names a design
//! holds, every file lands inside the output folder and no part overwrites another; a run never
//! leaves an earlier run's files beside its own.

mod common;
use common::{design_truck, example, linkwright, text, workdir};
use serde_json::{json, Value};
use std::path::{Path, PathBuf};
use std::process::Output;
use std::time::{Duration, Instant};

/// The regression corpus: designs of `examples/k1_garbage_truck.json` that once got through.
fn corpus() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/hostile")
}

/// A corpus design, parsed.
fn corpus_design(name: &str) -> Value {
    serde_json::from_str(&std::fs::read_to_string(corpus().join(format!("{name}.json"))).unwrap()).unwrap()
}

/// Writes `design` into `dir` and returns its path.
fn write_design(dir: &Path, name: &str, design: &Value) -> String {
    let path = dir.join(name);
    std::fs::write(&path, design.to_string()).unwrap();
    path.to_str().unwrap().to_string()
}

fn truck() -> String {
    example("k1_garbage_truck")
}

/// Every file under `dir`, relative to it, sorted.
fn files_under(dir: &Path) -> Vec<String> {
    let mut out = Vec::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        for entry in std::fs::read_dir(&d).unwrap() {
            let path = entry.unwrap().path();
            if path.is_dir() {
                stack.push(path);
            } else {
                out.push(path.strip_prefix(dir).unwrap().to_string_lossy().into_owned());
            }
        }
    }
    out.sort();
    out
}

/// Fabricates `design` into `out`, which must succeed, and reads its fabrication.json.
fn fabricated_report(design: &str, out: &Path) -> Value {
    let run = fabricate(design, out);
    assert_eq!(run.status.code(), Some(0), "{}", text(&run.stderr));
    serde_json::from_str(&std::fs::read_to_string(out.join("fabrication.json")).unwrap()).unwrap()
}

/// `linkwright fabricate` of the truck with `design` into `out`.
fn fabricate(design: &str, out: &Path) -> Output {
    linkwright(&["fabricate", &truck(), design, "-o", out.to_str().unwrap()])
}

/// Runs `linkwright` with `args` under a 300 MB address-space limit where the shell can set one, so a
/// command that allocated in proportion to a hostile number would fail instead of passing slowly.
fn linkwright_in_little_memory(args: &[&str]) -> Output {
    if !Path::new("/bin/sh").exists() || !cfg!(target_os = "linux") {
        return linkwright(args);
    }
    std::process::Command::new("/bin/sh")
        .arg("-c")
        .arg("ulimit -v 300000 && exec \"$0\" \"$@\"")
        .arg(env!("CARGO_BIN_EXE_linkwright"))
        .args(args)
        .output()
        .expect("the shell runs")
}

#[test]
fn every_design_of_the_corpus_is_refused_or_stays_in_its_folder() {
    let dir = workdir("corpus");
    let mut names: Vec<PathBuf> = std::fs::read_dir(corpus()).unwrap().map(|e| e.unwrap().path()).collect();
    names.sort();
    assert!(names.len() >= 15, "the corpus is there");
    for path in names {
        let name = path.file_stem().unwrap().to_str().unwrap().to_string();
        let design = path.to_str().unwrap();
        let sandbox = dir.join(&name);
        let out = sandbox.join("a/b/out");
        std::fs::create_dir_all(&out).unwrap();
        let started = Instant::now();
        let check = linkwright_in_little_memory(&["check", &truck(), design]);
        let simulate = linkwright_in_little_memory(&["simulate", &truck(), design, "--steps", "20"]);
        let fab = linkwright_in_little_memory(&["fabricate", &truck(), design, "-o", out.to_str().unwrap()]);
        assert!(started.elapsed() < Duration::from_secs(60), "{name}: took {:?}", started.elapsed());
        let codes = (check.status.code(), simulate.status.code(), fab.status.code());
        let stderr = format!("{}{}{}", text(&check.stderr), text(&simulate.stderr), text(&fab.stderr));
        if name.starts_with("refused_") {
            assert_eq!(codes, (Some(2), Some(2), Some(2)), "{name}: {stderr}");
            assert!(stderr.lines().all(|l| !l.contains("panicked")), "{name}: {stderr}");
            assert!(files_under(&out).is_empty(), "{name}: wrote {:?}", files_under(&out));
        } else if name.starts_with("fails_check_") {
            assert_eq!((codes.0, codes.2), (Some(1), Some(2)), "{name}: {stderr}");
            assert!(text(&fab.stderr).contains("fails its check"), "{name}: {stderr}");
        } else {
            assert_eq!(codes, (Some(0), Some(0), Some(0)), "{name}: {stderr}");
            let written = files_under(&out);
            assert!(written.contains(&"fabrication.json".to_string()), "{name}: {written:?}");
        }
        // Nothing anywhere but in the output folder.
        let outside: Vec<String> = files_under(&sandbox).into_iter().filter(|f| !f.starts_with("a/b/out/")).collect();
        assert!(outside.is_empty(), "{name}: wrote outside the output folder: {outside:?}");
        assert!(!dir.parent().unwrap().join("ESCAPED.stl").exists() && !Path::new("/tmp/ABSOLUTE.stl").exists());
    }
}

#[test]
fn a_part_named_to_escape_stays_inside_the_output_folder() {
    let dir = workdir("escape");
    let out = dir.join("a/b/out");
    let design = write_design(&dir, "escape.json", &corpus_design("escaped_part_name"));
    let report = fabricated_report(&design, &out);
    assert!(out.join("parts/ESCAPED.stl").is_file(), "{:?}", files_under(&out));
    let everything = files_under(&dir);
    assert!(everything.iter().all(|f| f == "escape.json" || f.starts_with("a/b/out/")), "{everything:?}");
    assert!(!dir.join("a/ESCAPED.stl").exists() && !dir.join("ESCAPED.stl").exists());
    for part in report["parts"].as_array().unwrap() {
        let file = part["file"].as_str().unwrap();
        assert!(file.starts_with("parts/") && !file.contains(".."), "{file}");
    }
}

#[test]
fn parts_with_the_same_name_do_not_overwrite_each_other() {
    let dir = workdir("duplicates");
    let out = dir.join("out");
    // The crank renamed after the body part: two parts called `body1`.
    let design = write_design(&dir, "dup.json", &corpus_design("duplicate_part_name"));
    let report = fabricated_report(&design, &out);
    let files: Vec<&str> = report["parts"].as_array().unwrap().iter().map(|p| p["file"].as_str().unwrap()).collect();
    let mut unique = files.clone();
    unique.sort();
    unique.dedup_by(|a, b| a.eq_ignore_ascii_case(b));
    assert_eq!(unique.len(), files.len(), "{files:?}");
    assert!(files.contains(&"parts/body1.stl") && files.contains(&"parts/body1-2.stl"), "{files:?}");
    let stl = files_under(&out.join("parts"));
    assert_eq!(stl.len(), files.len(), "one file per part: {stl:?}");
}

#[test]
fn endless_travels_are_refused_at_once_in_little_memory() {
    let dir = workdir("travel");
    for end in [1e7, 1e9, 1e18] {
        let mut design = corpus_design("escaped_part_name");
        design["motion"]["crank_end_deg"] = json!(end);
        let path = write_design(&dir, "travel.json", &design);
        for command in ["check", "simulate", "fabricate"] {
            let (scene, out) = (truck(), dir.join("out"));
            let mut args = vec![command, scene.as_str(), path.as_str()];
            if command == "fabricate" {
                args.extend(["-o", out.to_str().unwrap()]);
            }
            let started = Instant::now();
            let run = linkwright_in_little_memory(&args);
            assert!(started.elapsed() < Duration::from_secs(10), "{command} {end}: {:?}", started.elapsed());
            assert_eq!(run.status.code(), Some(2), "{command} {end}: {}", text(&run.stderr));
            assert!(text(&run.stderr).contains("motion.crank_end_deg"), "{command}: {}", text(&run.stderr));
            assert!(!out.exists());
        }
    }
}

#[test]
fn a_later_format_is_refused() {
    let dir = workdir("format");
    let path = write_design(&dir, "v2.json", &corpus_design("refused_design_2"));
    for command in ["check", "simulate"] {
        let run = linkwright(&[command, &truck(), &path]);
        assert_eq!(run.status.code(), Some(2));
        assert!(text(&run.stderr).contains("linkwright: unknown format \"design/2\""), "{}", text(&run.stderr));
    }
    let run = fabricate(&path, &dir.join("out"));
    assert_eq!(run.status.code(), Some(2));
    assert!(text(&run.stderr).contains("design/2"));
}

#[test]
fn fabricate_refuses_a_design_that_check_rejects() {
    let dir = workdir("order");
    let path = write_design(&dir, "order.json", &corpus_design("fails_check_poses_out_of_order"));
    let check = linkwright(&["check", &truck(), &path]);
    assert_eq!(check.status.code(), Some(1));
    let run = fabricate(&path, &dir.join("out"));
    assert_eq!(run.status.code(), Some(2), "{}", text(&run.stdout));
    let stderr = text(&run.stderr);
    assert!(stderr.contains("fails its check") && stderr.contains("order:"), "{stderr}");
    assert!(!dir.join("out").exists());
}

#[test]
fn check_refuses_a_locked_linkage() {
    let dir = workdir("locked");
    let path = write_design(&dir, "locked.json", &corpus_design("refused_locked_by_an_extra_link"));
    let check = linkwright(&["check", &truck(), &path]);
    assert_eq!(check.status.code(), Some(2), "{}", text(&check.stdout));
    let stderr = text(&check.stderr);
    assert!(stderr.contains("mechanism.parts") && stderr.contains("0 degrees of freedom"), "{stderr}");
    assert!(!text(&check.stdout).contains("holds"));
}

#[test]
fn simulate_refuses_a_scene_the_design_does_not_belong_to() {
    let dir = workdir("mismatch");
    let path = write_design(&dir, "truck.json", &corpus_design("escaped_part_name"));
    // The wall chair has two moving bodies (the truck one) and its own poses.
    let run = linkwright(&["simulate", &example("k2_wall_chair"), &path]);
    assert_eq!(run.status.code(), Some(2), "{}", text(&run.stdout));
    assert!(text(&run.stdout).is_empty());
    let stderr = text(&run.stderr);
    assert!(stderr.contains("another scene") && stderr.contains("moving bod"), "{stderr}");
}

/// The scene of `cli.rs`'s impossible design: every motion goes through a wall.
fn impossible_scene(dir: &Path) -> String {
    let scene = json!({
        "linkwright": "scene/1", "name": "garbage truck",
        "fixed_bodies": [{"name": "wall", "polygon": [[-5, -1000], [5, -1000], [5, 1000], [-5, 1000]]}],
        "moving_bodies": [{"name": "box", "polygon": [[0, 0], [20, 0], [20, 20], [0, 20]],
                           "poses": [[-60, 0, 0], [40, 0, 0]]}],
        "linkage_region": [[-100, -60], [100, -60], [100, 60], [-100, 60]],
        "settings": {"samples": 2000, "iterations": 3}
    });
    write_design(dir, "impossible.json", &scene)
}

#[test]
fn a_rerun_without_a_design_leaves_none_of_the_earlier_files() {
    let dir = workdir("rerun");
    let out = dir.join("out");
    let run = design_truck(&out, &["--seed", "5", "--fabricate"]);
    assert!(run.status.success(), "{}", text(&run.stderr));
    assert!(out.join("design.svg").is_file() && out.join("fabrication/fabrication.json").is_file());
    // Something of the person's own in the output folder stays.
    std::fs::write(out.join("notes.txt"), "mine").unwrap();

    let scene = impossible_scene(&dir);
    let run = linkwright(&["design", &scene, "-o", out.to_str().unwrap()]);
    assert_eq!(run.status.code(), Some(0), "{}", text(&run.stderr));
    let design: Value = serde_json::from_str(&std::fs::read_to_string(out.join("design.json")).unwrap()).unwrap();
    assert_eq!(design["status"], "no_solution");
    assert_eq!(files_under(&out), ["design.json", "notes.txt"]);
}

#[test]
fn a_rerun_without_fabricate_removes_the_earlier_fabrication() {
    let dir = workdir("refab");
    let out = dir.join("out");
    let run = design_truck(&out, &["--seed", "5", "--fabricate"]);
    assert!(run.status.success(), "{}", text(&run.stderr));
    let run = design_truck(&out, &["--seed", "6"]);
    assert!(run.status.success(), "{}", text(&run.stderr));
    assert_eq!(files_under(&out), ["animation.svg", "design.json", "design.svg"]);
}

#[test]
fn fabricating_again_into_a_folder_replaces_the_earlier_parts() {
    let dir = workdir("replace");
    let out = dir.join("out");
    let mut renamed = corpus_design("escaped_part_name");
    renamed["mechanism"]["parts"][2]["name"] = json!("old crank");
    let first = write_design(&dir, "first.json", &renamed);
    assert_eq!(fabricate(&first, &out).status.code(), Some(0));
    assert!(out.join("parts/old crank.stl").is_file());
    std::fs::write(out.join("parts/mine.txt"), "mine").unwrap();
    let second = write_design(&dir, "second.json", &corpus_design("escaped_part_name"));
    assert_eq!(fabricate(&second, &out).status.code(), Some(0));
    let parts = files_under(&out.join("parts"));
    assert!(!parts.contains(&"old crank.stl".to_string()) && parts.contains(&"ESCAPED.stl".to_string()), "{parts:?}");
    assert!(parts.contains(&"mine.txt".to_string()), "files the fabrication did not write stay: {parts:?}");
}

#[cfg(unix)]
#[test]
fn a_symbolic_link_at_an_output_name_is_replaced_not_followed() {
    let dir = workdir("symlink");
    let out = dir.join("out");
    std::fs::create_dir_all(&out).unwrap();
    let victim = dir.join("victim.txt");
    std::fs::write(&victim, "untouched").unwrap();
    std::os::unix::fs::symlink(&victim, out.join("design.json")).unwrap();
    std::os::unix::fs::symlink(&victim, out.join("design.svg")).unwrap();
    let run = design_truck(&out, &["--seed", "5"]);
    assert!(run.status.success(), "{}", text(&run.stderr));
    assert_eq!(std::fs::read_to_string(&victim).unwrap(), "untouched");
    assert!(!std::fs::symlink_metadata(out.join("design.json")).unwrap().file_type().is_symlink());
    assert!(std::fs::read_to_string(out.join("design.json")).unwrap().contains("design/1"));
}

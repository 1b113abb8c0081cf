//! Input files as untrusted text: names and keys reach the terminal escaped, never as control
//! sequences; every input is read through a size cap; `--from` takes only a design it can start from.

mod common;
use common::{example, linkwright, text, workdir};
use serde_json::{json, Value};
use std::path::Path;
use std::process::Output;

/// A small valid scene: a ground and a lid visiting two poses well clear of it.
fn scene() -> Value {
    json!({
        "linkwright": "scene/1",
        "name": "lid",
        "fixed_bodies": [{"name": "ground", "polygon": [[0, 0], [200, 0], [200, 20], [0, 20]]}],
        "moving_bodies": [{"name": "lid", "polygon": [[0, 0], [20, 0], [20, 80], [0, 80]],
                           "poses": [[50, 100, 0], [120, 60, -90]]}],
        "settings": {"samples": 1000, "particles": 10, "iterations": 2}
    })
}

fn write(dir: &Path, name: &str, value: &Value) -> String {
    let path = dir.join(name);
    std::fs::write(&path, value.to_string()).unwrap();
    path.to_str().unwrap().to_string()
}

/// Asserts that neither stream of `run` holds an escape character.
fn assert_no_escape(run: &Output) {
    for (stream, bytes) in [("stdout", &run.stdout), ("stderr", &run.stderr)] {
        assert!(!bytes.contains(&0x1b), "{stream} holds ESC: {:?}", text(bytes));
    }
}

#[test]
fn a_scene_named_with_an_escape_sequence_is_refused() {
    let dir = workdir("scene-name");
    let mut s = scene();
    s["name"] = json!("\u{1b}[2J");
    let path = write(&dir, "scene.json", &s);
    let out = dir.join("out");
    let run = linkwright(&["design", &path, "-o", out.to_str().unwrap()]);
    assert_eq!(run.status.code(), Some(2), "{}", text(&run.stdout));
    let stderr = text(&run.stderr);
    assert!(stderr.contains("error: name: ") && stderr.contains("control characters"), "{stderr}");
    assert_no_escape(&run);
    assert!(!out.exists());
}

#[test]
fn unknown_keys_with_control_characters_are_printed_escaped() {
    let dir = workdir("unknown-key");
    let mut s = scene();
    s["\u{1b}[2J\u{1b}[Hevery hard constraint holds"] = json!(1);
    s["settings"]["x\rerror"] = json!(1);
    // An error too, so the run stops after the warnings.
    s["settings"]["samples"] = json!(0);
    let path = write(&dir, "scene.json", &s);
    let run = linkwright(&["design", &path, "-o", dir.join("out").to_str().unwrap()]);
    assert_eq!(run.status.code(), Some(2));
    let stderr = text(&run.stderr);
    assert!(stderr.contains(r"warning: \u{1b}[2J\u{1b}[Hevery hard constraint holds: unknown field"), "{stderr}");
    assert!(stderr.contains(r"warning: settings.x\rerror: unknown field"), "{stderr}");
    assert!(!stderr.contains('\r'), "{stderr}");
    assert_no_escape(&run);
}

#[test]
fn a_value_quoted_in_an_error_is_printed_escaped() {
    let dir = workdir("format-value");
    let mut s = scene();
    s["linkwright"] = json!("scene/\u{1b}[2J");
    let path = write(&dir, "scene.json", &s);
    let run = linkwright(&["design", &path, "-o", dir.join("out").to_str().unwrap()]);
    assert_eq!(run.status.code(), Some(2));
    assert!(text(&run.stderr).contains(r"scene/\u{1b}[2J"), "{}", text(&run.stderr));
    assert_no_escape(&run);
}

/// `/dev/zero` as each input file a command reads: refused at the cap, naming the file and the cap.
#[cfg(target_os = "linux")]
#[test]
fn every_input_file_is_read_through_a_size_cap() {
    let dir = workdir("cap");
    let out = dir.join("out");
    let (truck, out) = (example("k1_garbage_truck"), out.to_str().unwrap());
    let design = format!("{}/tests/fixtures/hostile/escaped_part_name.json", env!("CARGO_MANIFEST_DIR"));
    let runs: [&[&str]; 6] = [
        &["design", "/dev/zero", "-o", out],
        &["design", &truck, "-o", out, "--print-settings", "/dev/zero"],
        &["design", &truck, "-o", out, "--from", "/dev/zero"],
        &["check", &truck, "/dev/zero"],
        &["fabricate", &truck, &design, "-o", out, "--settings", "/dev/zero"],
        &["analyze", &truck, &design, "--print-settings", "/dev/zero"],
    ];
    for args in runs {
        let run = linkwright(args);
        assert_eq!(run.status.code(), Some(2), "{args:?}: {}", text(&run.stderr));
        let stderr = text(&run.stderr);
        assert!(stderr.contains("error: /dev/zero: is larger than 64 MiB"), "{args:?}: {stderr}");
        assert!(!Path::new(out).exists(), "{args:?}");
    }
}

#[test]
fn from_refuses_a_later_format_and_a_design_without_a_solution() {
    let dir = workdir("from");
    let hostile = format!("{}/tests/fixtures/hostile", env!("CARGO_MANIFEST_DIR"));
    let later = format!("{hostile}/refused_design_2.json");
    let mut none: Value = serde_json::from_str(
        &std::fs::read_to_string(format!("{hostile}/refused_no_solution_with_a_mechanism.json")).unwrap(),
    )
    .unwrap();
    for field in ["mechanism", "motion", "metrics"] {
        none[field] = Value::Null;
    }
    none["alternatives"] = json!([]);
    let none = write(&dir, "none.json", &none);
    let out = dir.join("out");
    for (from, what) in [(later.as_str(), "\"design/2\" file"), (none.as_str(), "status \"no_solution\"")] {
        let run = linkwright(&["design", &example("k1_garbage_truck"), "-o", out.to_str().unwrap(), "--from", from]);
        assert_eq!(run.status.code(), Some(2), "{from}: {}", text(&run.stderr));
        let stderr = text(&run.stderr);
        assert!(stderr.contains(&format!("error: --from {from}: ")) && stderr.contains(what), "{stderr}");
        assert!(stderr.contains("--from needs a design of this scene with a solution"), "{stderr}");
        assert!(!out.exists());
    }
}

//! Symbolic links planted inside an output folder: whatever folder a link at `parts`, `fabrication`
//! or `fabrication/parts` points to, `design` and `fabricate` neither write into it nor delete from
//! it; the link itself is replaced by a real folder. (`-o DIR` itself may be a link: the person
//! chose it.)
#![cfg(unix)]

mod common;
use common::{design_truck, example, linkwright, text, workdir, Workdir};
use serde_json::json;
use std::collections::BTreeMap;
use std::os::unix::fs::symlink;
use std::path::{Path, PathBuf};

/// Every file under `dir` (links not followed) with its size and start, by relative path.
fn contents(dir: &Path) -> BTreeMap<String, String> {
    let mut out = BTreeMap::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        for entry in std::fs::read_dir(&d).unwrap() {
            let path = entry.unwrap().path();
            if std::fs::symlink_metadata(&path).unwrap().is_dir() {
                stack.push(path);
            } else {
                let name = path.strip_prefix(dir).unwrap().to_string_lossy().into_owned();
                let bytes = std::fs::read(&path).unwrap_or_default();
                let start = String::from_utf8_lossy(&bytes[..bytes.len().min(40)]).into_owned();
                out.insert(name, format!("{} bytes: {start}", bytes.len()));
            }
        }
    }
    out
}

/// A folder somebody else owns, holding files of the names a fabrication writes and deletes (a
/// `fabrication.json` listing them, a part, a plate, the assembly), and a file of its own.
fn victim(dir: &Path) -> std::path::PathBuf {
    let victim = dir.join("victim");
    std::fs::create_dir_all(victim.join("parts")).unwrap();
    std::fs::write(victim.join("fabrication.json"), listing().to_string()).unwrap();
    for name in ["parts/crank.stl", "crank.stl", "plate_1.3mf", "assembly.3mf", "own.txt"] {
        std::fs::write(victim.join(name), format!("{name} of someone else")).unwrap();
    }
    victim
}

/// A `fabrication.json` listing files the victim folder holds, as an earlier fabrication's would.
fn listing() -> serde_json::Value {
    json!({"parts": [{"file": "parts/crank.stl"}], "plates": [{"file": "plate_1.3mf"}]})
}

fn is_link(path: &Path) -> bool {
    std::fs::symlink_metadata(path).is_ok_and(|m| m.file_type().is_symlink())
}

fn is_real_folder(path: &Path) -> bool {
    std::fs::symlink_metadata(path).is_ok_and(|m| m.is_dir())
}

/// A design of the garbage truck `fabricate` accepts.
fn truck_design() -> String {
    format!("{}/tests/fixtures/hostile/escaped_part_name.json", env!("CARGO_MANIFEST_DIR"))
}

/// A work folder `name` holding a [`victim`] folder and an output folder `out` in which `link` (a
/// relative path, its parent folders made) is a symbolic link to the victim's `target` subfolder (""
/// for the victim itself): the work folder, the victim, the victim's contents and the output folder.
fn planted(name: &str, link: &str, target: &str) -> (Workdir, PathBuf, BTreeMap<String, String>, PathBuf) {
    let dir = workdir(name);
    let victim = victim(&dir);
    let before = contents(&victim);
    let out = dir.join("out");
    let link = out.join(link);
    std::fs::create_dir_all(link.parent().unwrap()).unwrap();
    symlink(victim.join(target), link).unwrap();
    (dir, victim, before, out)
}

#[test]
fn fabricate_replaces_a_planted_parts_link() {
    let (_dir, victim, before, out) = planted("parts", "parts", "parts");
    // A planted manifest lists `parts/crank.stl`, which the link would make the victim's.
    std::fs::write(out.join("fabrication.json"), listing().to_string()).unwrap();

    let run = linkwright(&["fabricate", &example("k1_garbage_truck"), &truck_design(), "-o", out.to_str().unwrap()]);
    assert_eq!(run.status.code(), Some(0), "{}", text(&run.stderr));
    assert_eq!(contents(&victim), before, "the linked folder is untouched");
    assert!(is_real_folder(&out.join("parts")), "the link is replaced by a folder");
    assert!(out.join("parts/ESCAPED.stl").is_file());
}

#[test]
fn fabricate_into_a_linked_output_folder_writes_there() {
    let dir = workdir("chosen");
    let chosen = dir.join("chosen");
    std::fs::create_dir_all(&chosen).unwrap();
    let out = dir.join("out");
    symlink(&chosen, &out).unwrap();
    let run = linkwright(&["fabricate", &example("k1_garbage_truck"), &truck_design(), "-o", out.to_str().unwrap()]);
    assert_eq!(run.status.code(), Some(0), "{}", text(&run.stderr));
    assert!(chosen.join("parts/ESCAPED.stl").is_file() && chosen.join("fabrication.json").is_file());
}

#[test]
fn design_fabricate_replaces_a_planted_fabrication_link() {
    let (_dir, victim, before, out) = planted("fabrication", "fabrication", "");

    let run = design_truck(&out, &["--seed", "5", "--fabricate"]);
    assert!(run.status.success(), "{}", text(&run.stderr));
    assert_eq!(contents(&victim), before, "the linked folder is untouched");
    assert!(is_real_folder(&out.join("fabrication")));
    assert!(out.join("fabrication/fabrication.json").is_file());
}

#[test]
fn a_design_run_drops_a_planted_fabrication_link_without_following_it() {
    let (_dir, victim, before, out) = planted("stale", "fabrication", "");

    let run = design_truck(&out, &["--seed", "5"]);
    assert!(run.status.success(), "{}", text(&run.stderr));
    assert_eq!(contents(&victim), before, "the linked folder is untouched");
    assert!(!is_link(&out.join("fabrication")), "the earlier run's fabrication is removed, not followed");
}

#[test]
fn design_fabricate_replaces_a_planted_parts_link_inside_fabrication() {
    let (_dir, victim, before, out) = planted("deeper", "fabrication/parts", "parts");
    std::fs::write(out.join("fabrication/fabrication.json"), listing().to_string()).unwrap();

    let run = design_truck(&out, &["--seed", "5", "--fabricate"]);
    assert!(run.status.success(), "{}", text(&run.stderr));
    assert_eq!(contents(&victim), before, "the linked folder is untouched");
    assert!(is_real_folder(&out.join("fabrication/parts")));
}

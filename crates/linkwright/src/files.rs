//! Reading inputs with messages a person can act on, and writing outputs without ever leaving a
//! half-written file in place of one the person had.

use crate::Failure;
use linkwright_core::{DesignFile, Problem, Scene, Severity};
use std::collections::hash_map::RandomState;
use std::fs::{File, OpenOptions};
use std::hash::BuildHasher;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};
use std::time::{SystemTime, UNIX_EPOCH};

fn read_text(path: &Path) -> Result<String, Failure> {
    std::fs::read_to_string(path).map_err(|e| Failure::Input(format!("error: cannot read {}: {e}", path.display())))
}

/// Reads and validates a scene; warnings go to stderr, errors become one message listing them all.
pub fn read_problem(path: &Path) -> Result<(Scene, Problem), Failure> {
    read_problem_with(path, |_| {})
}

/// [`read_problem`] with `edit` applied to the scene before it is validated.
pub fn read_problem_with(path: &Path, edit: impl FnOnce(&mut Scene)) -> Result<(Scene, Problem), Failure> {
    let text = read_text(path)?;
    let mut scene =
        scene_of(&text).map_err(|e| Failure::Input(format!("error: {}: {}: {}", path.display(), e.path, e.message)))?;
    edit(&mut scene);
    match Problem::new(&scene) {
        Ok(problem) => {
            for w in &problem.warnings {
                eprintln!("{w}");
            }
            if problem.warnings.more() > 0 {
                eprintln!("warning: ... and {} more warnings", problem.warnings.more());
            }
            Ok((scene, problem))
        }
        Err(issues) => {
            let mut lines: Vec<String> = issues.iter().map(|i| i.to_string()).collect();
            let errors = issues.iter().filter(|i| i.severity == Severity::Error).count();
            let summary = match issues.more() {
                0 => format!("{errors} error(s)"),
                more => format!("{errors} error(s) listed and {more} more problems"),
            };
            lines.push(format!("{}: {summary}; fix them and run again", path.display()));
            Err(Failure::Input(lines.join("\n")))
        }
    }
}

/// The scene of a scene file, or of a project file the app saved (`project/1`: the scene with its
/// design; docs/formats.md), whose errors then name their place under `scene`.
fn scene_of(text: &str) -> Result<Scene, linkwright_core::ParseError> {
    #[derive(serde::Deserialize)]
    struct Project {
        linkwright: String,
        scene: serde_json::Value,
    }
    match serde_json::from_str::<Project>(text) {
        Ok(project) if project.linkwright == "project/1" => Scene::from_json(&project.scene.to_string()).map_err(|e| {
            let path = if e.path == "." { "scene".to_string() } else { format!("scene.{}", e.path) };
            linkwright_core::ParseError { path, ..e }
        }),
        _ => Scene::from_json(text),
    }
}

/// Reads a design file, without checking it against a scene (for a warm start, which keeps only its
/// usable mechanisms).
pub fn read_design(path: &Path) -> Result<DesignFile, Failure> {
    let text = read_text(path)?;
    DesignFile::from_json(&text)
        .map_err(|e| Failure::Input(format!("error: {}: {}: {}", path.display(), e.path, e.message)))
}

/// Reads a design file and validates it against the scene's problem; every problem becomes one line
/// of the message.
pub fn read_valid_design(path: &Path, problem: &Problem) -> Result<DesignFile, Failure> {
    let design = read_design(path)?;
    let issues = design.validate(problem);
    if issues.is_empty() {
        return Ok(design);
    }
    let mut lines: Vec<String> = issues.iter().map(|i| format!("error: {}: {i}", path.display())).collect();
    if issues.more() > 0 {
        lines.push(format!("error: {}: ... and {} more", path.display(), issues.more()));
    }
    lines.push(format!("{}: {} error(s); fix them (or design again) and run again", path.display(), issues.total()));
    Err(Failure::Input(lines.join("\n")))
}

/// Writes `contents` to `path` through a temporary file in the same directory and a rename, so an
/// interrupted run never leaves a truncated file where a good one was. The temporary file has a name
/// nobody can predict and is created only if nothing is at that name (no file, no symbolic link), so
/// nothing planted in the folder can redirect the write; the rename replaces whatever is at `path`
/// (a symbolic link there is replaced, not followed).
pub fn write_atomically(path: &Path, contents: &[u8]) -> Result<(), Failure> {
    let fail = |e: std::io::Error| Failure::Input(format!("error: cannot write {}: {e}", path.display()));
    let dir = path.parent().filter(|p| !p.as_os_str().is_empty()).unwrap_or(Path::new("."));
    let name = path.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
    let (tmp, mut file) = create_temporary(dir, &name).map_err(fail)?;
    let written = file.write_all(contents).and_then(|()| file.sync_all());
    drop(file);
    written.and_then(|()| std::fs::rename(&tmp, path)).map_err(|e| {
        let _ = std::fs::remove_file(&tmp);
        fail(e)
    })
}

/// A new file `DIR/.NAME.RANDOM.tmp`, created exclusively (`O_EXCL`: it fails on anything already at
/// that path, a symbolic link included, rather than opening it).
fn create_temporary(dir: &Path, name: &str) -> std::io::Result<(PathBuf, File)> {
    let mut last = None;
    for attempt in 0..16u32 {
        let tmp = dir.join(format!(".{name}.{:016x}.tmp", unpredictable(attempt)));
        match create_exclusive(&tmp) {
            Ok(file) => return Ok((tmp, file)),
            Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => last = Some(e),
            Err(e) => return Err(e),
        }
    }
    Err(last.unwrap_or_else(|| std::io::Error::other("no free temporary name")))
}

/// Creates a new file at `path`, failing (`AlreadyExists`) on anything already there, a symbolic link
/// included, which is never followed.
fn create_exclusive(path: &Path) -> std::io::Result<File> {
    OpenOptions::new().write(true).create_new(true).open(path)
}

/// 64 bits nobody outside this process can predict: std's randomly keyed hasher (seeded from the
/// operating system's random source) over the clock, the process id and a counter.
fn unpredictable(attempt: u32) -> u64 {
    static COUNTER: AtomicU64 = AtomicU64::new(0);
    let now = SystemTime::now().duration_since(UNIX_EPOCH).map_or(0, |d| d.as_nanos());
    RandomState::new().hash_one((now, std::process::id(), COUNTER.fetch_add(1, Ordering::Relaxed), attempt))
}

/// Removes the file at `path` if there is one (a symbolic link is removed, not followed).
pub fn remove_if_present(path: &Path) -> Result<(), Failure> {
    match std::fs::remove_file(path) {
        Err(e) if e.kind() != std::io::ErrorKind::NotFound => {
            Err(Failure::Input(format!("error: cannot remove {} (left from an earlier run): {e}", path.display())))
        }
        _ => Ok(()),
    }
}

#[cfg(all(test, unix))]
mod tests {
    use super::*;

    fn scratch(name: &str) -> PathBuf {
        let dir = std::env::temp_dir().join(format!("linkwright-files-{}-{name}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        dir
    }

    #[test]
    fn a_symbolic_link_planted_at_a_temporary_name_is_not_followed() {
        let dir = scratch("planted");
        let victim = dir.join("victim.txt");
        std::fs::write(&victim, "untouched").unwrap();
        let out = dir.join("out");
        std::fs::create_dir_all(&out).unwrap();
        // Where the temporary file used to be (`.NAME.tmpPID`), and a link at a name the exclusive
        // creation meets.
        std::os::unix::fs::symlink(&victim, out.join(format!(".design.json.tmp{}", std::process::id()))).unwrap();
        let planted = out.join("planted.tmp");
        std::os::unix::fs::symlink(&victim, &planted).unwrap();
        let refused = create_exclusive(&planted).map(|_| ()).unwrap_err();
        assert_eq!(refused.kind(), std::io::ErrorKind::AlreadyExists);

        assert!(write_atomically(&out.join("design.json"), b"{}").is_ok());
        assert_eq!(std::fs::read_to_string(&victim).unwrap(), "untouched");
        assert_eq!(std::fs::read_to_string(out.join("design.json")).unwrap(), "{}");
        // No temporary file is left behind, and the planted links are still links.
        let names: Vec<String> =
            std::fs::read_dir(&out).unwrap().map(|e| e.unwrap().file_name().to_string_lossy().into_owned()).collect();
        assert_eq!(names.len(), 3, "{names:?}");
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[test]
    fn temporary_names_differ_from_call_to_call() {
        let names: std::collections::HashSet<u64> = (0..100).map(|_| unpredictable(0)).collect();
        assert_eq!(names.len(), 100);
    }
}

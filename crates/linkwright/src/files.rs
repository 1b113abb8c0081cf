//! Reading inputs with messages a person can act on, and writing outputs without ever leaving a
//! half-written file in place of one the person had.

use crate::failure::Failure;
use crate::terminal::{escaped, warn};
use linkwright_core::fab::is_safe_relative_path;
use linkwright_core::{DesignFile, Problem, Scene, Severity};
use std::collections::hash_map::RandomState;
use std::fs::{File, OpenOptions};
use std::hash::BuildHasher;
use std::io::{Read, Write};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};
use std::time::{SystemTime, UNIX_EPOCH};

/// Largest input file read, bytes. The largest legitimate files are a few megabytes: a design at the
/// limits (256 joints and parts, 100 alternatives) and a scene at its (2,000 vertices, 20 poses per
/// body) written with generous indentation; the server takes 2 MiB. 64 MiB leaves room for files
/// another program pads or annotates, and still parses in a second or two (the garbage truck with
/// 60 MiB of annotations: `/usr/bin/time linkwright design SCENE --samples 1`).
pub(crate) const MAX_INPUT_BYTES: u64 = 64 << 20;

/// The text of an input file (a scene, a design, print settings, a manifest), read through a cap of
/// [`MAX_INPUT_BYTES`] whatever its size says: a device such as `/dev/zero` or a pipe has none.
pub(crate) fn read_text(path: &Path) -> Result<String, Failure> {
    let cannot = |e: std::io::Error| Failure::Input(format!("error: cannot read {}: {e}", path.display()));
    let mut bytes = Vec::new();
    File::open(path).and_then(|file| file.take(MAX_INPUT_BYTES + 1).read_to_end(&mut bytes)).map_err(cannot)?;
    if bytes.len() as u64 > MAX_INPUT_BYTES {
        return Err(Failure::Input(format!(
            "error: {}: is larger than {} MiB, more than any scene, design or settings file holds; check that \
             it is the file you meant",
            path.display(),
            MAX_INPUT_BYTES >> 20
        )));
    }
    String::from_utf8(bytes).map_err(|e| {
        Failure::Input(format!(
            "error: {}: is not UTF-8 text (byte {}); save it as UTF-8",
            path.display(),
            e.utf8_error().valid_up_to()
        ))
    })
}

/// A file that does not parse: where and why, the field path and message escaped (they quote the
/// file's keys and values).
pub(crate) fn parse_failure(path: &Path, field: &str, message: &str) -> Failure {
    Failure::Input(format!("error: {}: {}: {}", path.display(), escaped(field), escaped(message)))
}

/// Reads and validates a scene; warnings go to stderr, errors become one message listing them all.
pub(crate) fn read_problem(path: &Path) -> Result<(Scene, Problem), Failure> {
    read_problem_with(path, |_| {})
}

/// [`read_problem`] with `edit` applied to the scene before it is validated.
pub(crate) fn read_problem_with(path: &Path, edit: impl FnOnce(&mut Scene)) -> Result<(Scene, Problem), Failure> {
    let text = read_text(path)?;
    let mut scene = scene_of(&text).map_err(|e| parse_failure(path, &e.path, &e.message))?;
    edit(&mut scene);
    match Problem::new(&scene) {
        Ok(problem) => {
            for w in &problem.warnings {
                warn(&escaped(&w.to_string()));
            }
            if problem.warnings.more() > 0 {
                eprintln!("warning: ... and {} more warnings", problem.warnings.more());
            }
            Ok((scene, problem))
        }
        Err(issues) => {
            let mut lines: Vec<String> = issues.iter().map(|i| escaped(&i.to_string())).collect();
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
pub(crate) fn read_design(path: &Path) -> Result<DesignFile, Failure> {
    let text = read_text(path)?;
    DesignFile::from_json(&text).map_err(|e| parse_failure(path, &e.path, &e.message))
}

/// Reads a design file and validates it against the scene's problem; every problem becomes one line
/// of the message.
pub(crate) fn read_valid_design(path: &Path, problem: &Problem) -> Result<DesignFile, Failure> {
    let design = read_design(path)?;
    let issues = design.validate(problem);
    if issues.is_empty() {
        return Ok(design);
    }
    let mut lines: Vec<String> =
        issues.iter().map(|i| format!("error: {}: {}", path.display(), escaped(&i.to_string()))).collect();
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
pub(crate) fn write_atomically(path: &Path, contents: &[u8]) -> Result<(), Failure> {
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
pub(crate) fn remove_if_present(path: &Path) -> Result<(), Failure> {
    match std::fs::remove_file(path) {
        Err(e) if e.kind() != std::io::ErrorKind::NotFound => {
            Err(Failure::Input(format!("error: cannot remove {} (left from an earlier run): {e}", path.display())))
        }
        _ => Ok(()),
    }
}

/// What is at a path below the output folder, links not followed.
enum Found {
    Nothing,
    Folder,
    /// A symbolic link, which is removed: Linkwright writes folders there, not links.
    Link,
    File,
}

fn found(path: &Path) -> Result<Found, Failure> {
    match std::fs::symlink_metadata(path) {
        Ok(m) if m.file_type().is_symlink() => Ok(Found::Link),
        Ok(m) if m.is_dir() => Ok(Found::Folder),
        Ok(_) => Ok(Found::File),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => Ok(Found::Nothing),
        Err(e) => Err(Failure::Input(format!("error: cannot read {}: {e}", path.display()))),
    }
}

/// `root/relative` as a real folder, each folder from `root` to it included: every output path below
/// the output folder goes through here. `root`, the folder the person named, may be a symbolic link;
/// below it, a symbolic link where a folder goes is removed (the link, never what it points to), so
/// nothing is ever written into or deleted from a folder a link planted in the output folder points
/// to. With `create`, missing folders (and removed links) become folders and the path is returned;
/// without, the path is returned only when the folder is there.
fn subfolder(root: &Path, relative: &str, create: bool) -> Result<Option<PathBuf>, Failure> {
    let cannot = |what: &str, path: &Path, e: std::io::Error| {
        Failure::Input(format!("error: cannot {what} {}: {e}", path.display()))
    };
    if create {
        std::fs::create_dir_all(root).map_err(|e| cannot("create", root, e))?;
    }
    let mut dir = root.to_path_buf();
    for name in relative.split('/').filter(|name| !name.is_empty()) {
        dir.push(name);
        match found(&dir)? {
            Found::Folder => continue,
            Found::File if create => {
                return Err(Failure::Input(format!(
                    "error: {} is a file where Linkwright writes a folder; move it away or write to another folder",
                    dir.display()
                )))
            }
            Found::File => return Ok(None),
            Found::Link => std::fs::remove_file(&dir).map_err(|e| cannot("remove the link", &dir, e))?,
            Found::Nothing => {}
        }
        if !create {
            return Ok(None);
        }
        // Fails on anything created there meanwhile (a link included) rather than following it.
        std::fs::create_dir(&dir).map_err(|e| cannot("create", &dir, e))?;
    }
    Ok(Some(dir))
}

/// Makes `root/relative` a real folder (see [`subfolder`]) and returns its path.
pub(crate) fn make_subfolder(root: &Path, relative: &str) -> Result<PathBuf, Failure> {
    Ok(subfolder(root, relative, true)?.unwrap_or_else(|| root.join(relative)))
}

/// `root/relative` if it is a real folder (see [`subfolder`]; a link there is removed).
pub(crate) fn existing_subfolder(root: &Path, relative: &str) -> Result<Option<PathBuf>, Failure> {
    subfolder(root, relative, false)
}

/// Refuses, as the bug it would be, any of `paths` (relative to the output folder) that would leave
/// it: the library names its files safely. Checked before a run removes or writes anything.
pub(crate) fn check_output_paths<'a>(mut paths: impl Iterator<Item = &'a str>) -> Result<(), Failure> {
    match paths.find(|path| !is_safe_relative_path(path)) {
        Some(path) => {
            Err(Failure::Input(format!("error: internal error: unsafe output path {path:?}; please report it")))
        }
        None => Ok(()),
    }
}

/// The folder part and the file name of a path relative to the output folder ([`check_output_paths`]).
fn split(relative: &str) -> Result<(&str, &str), Failure> {
    check_output_paths(std::iter::once(relative))?;
    Ok(relative.rsplit_once('/').unwrap_or(("", relative)))
}

/// Writes `contents` to `root/relative` atomically ([`write_atomically`]), its folders made real
/// ([`make_subfolder`]).
pub(crate) fn write_below(root: &Path, relative: &str, contents: &[u8]) -> Result<(), Failure> {
    let (folder, name) = split(relative)?;
    write_atomically(&make_subfolder(root, folder)?.join(name), contents)
}

/// Removes the file at `root/relative` if there is one in a real folder ([`existing_subfolder`]): a
/// file seen through a planted link is someone else's.
pub(crate) fn remove_below(root: &Path, relative: &str) -> Result<(), Failure> {
    let (folder, name) = split(relative)?;
    match existing_subfolder(root, folder)? {
        Some(dir) => remove_if_present(&dir.join(name)),
        None => Ok(()),
    }
}

/// Removes the real folder `root/relative` if it is empty; left in place when it holds anything.
pub(crate) fn remove_folder_if_empty(root: &Path, relative: &str) -> Result<(), Failure> {
    if let Some(dir) = existing_subfolder(root, relative)? {
        let _ = std::fs::remove_dir(dir);
    }
    Ok(())
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
    fn links_below_the_output_folder_become_folders_and_files_there_are_refused() {
        let dir = scratch("subfolders");
        let elsewhere = dir.join("elsewhere");
        std::fs::create_dir_all(&elsewhere).unwrap();
        std::fs::write(elsewhere.join("theirs.stl"), "theirs").unwrap();
        let out = dir.join("out");
        std::fs::create_dir_all(&out).unwrap();
        std::os::unix::fs::symlink(&elsewhere, out.join("parts")).unwrap();
        // Removing through the link finds nothing of ours, and drops the link.
        assert!(remove_below(&out, "parts/theirs.stl").is_ok());
        assert!(elsewhere.join("theirs.stl").is_file());
        assert!(!out.join("parts").exists());
        std::os::unix::fs::symlink(&elsewhere, out.join("parts")).unwrap();
        assert!(write_below(&out, "parts/ours.stl", b"ours").is_ok());
        assert!(std::fs::symlink_metadata(out.join("parts")).unwrap().is_dir());
        assert_eq!(std::fs::read_dir(&elsewhere).unwrap().count(), 1);

        std::fs::write(out.join("plates"), "a file").unwrap();
        let Err(Failure::Input(message)) = write_below(&out, "plates/x", b"") else { panic!("a file is refused") };
        assert!(message.contains("plates") && message.contains("is a file"), "{message}");
        assert!(matches!(write_below(&out, "../x", b""), Err(Failure::Input(_))));
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[test]
    fn temporary_names_differ_from_call_to_call() {
        let names: std::collections::HashSet<u64> = (0..100).map(|_| unpredictable(0)).collect();
        assert_eq!(names.len(), 100);
    }
}

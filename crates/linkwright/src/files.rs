//! Reading inputs with messages a person can act on, and writing outputs without ever leaving a
//! half-written file in place of one the person had.

use crate::Failure;
use linkwright_core::design::DesignFile;
use linkwright_core::scene::{Problem, Scene, Severity};
use std::io::Write;
use std::path::Path;

fn read_text(path: &Path) -> Result<String, Failure> {
    std::fs::read_to_string(path).map_err(|e| Failure::Input(format!("error: cannot read {}: {e}", path.display())))
}

/// Reads and validates a scene; warnings go to stderr, errors become one message listing them all.
pub fn read_problem(path: &Path) -> Result<(Scene, Problem), Failure> {
    let text = read_text(path)?;
    let scene = Scene::from_json(&text)
        .map_err(|e| Failure::Input(format!("error: {}: {}: {}", path.display(), e.path, e.message)))?;
    match Problem::new(&scene) {
        Ok(problem) => {
            for w in &problem.warnings {
                eprintln!("{w}");
            }
            Ok((scene, problem))
        }
        Err(issues) => {
            let mut lines: Vec<String> = issues.iter().map(|i| i.to_string()).collect();
            let errors = issues.iter().filter(|i| i.severity == Severity::Error).count();
            lines.push(format!("{}: {errors} error(s); fix them and run again", path.display()));
            Err(Failure::Input(lines.join("\n")))
        }
    }
}

pub fn read_design(path: &Path) -> Result<DesignFile, Failure> {
    let text = read_text(path)?;
    DesignFile::from_json(&text)
        .map_err(|e| Failure::Input(format!("error: {}: {}: {}", path.display(), e.path, e.message)))
}

/// Writes `contents` to `path` through a temporary file in the same directory and a rename, so an
/// interrupted run never leaves a truncated file where a good one was.
pub fn write_atomically(path: &Path, contents: &[u8]) -> Result<(), Failure> {
    let fail = |e: std::io::Error| Failure::Input(format!("error: cannot write {}: {e}", path.display()));
    let dir = path.parent().filter(|p| !p.as_os_str().is_empty()).unwrap_or(Path::new("."));
    let name = path.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
    let tmp = dir.join(format!(".{name}.tmp{}", std::process::id()));
    let mut file = std::fs::File::create(&tmp).map_err(fail)?;
    file.write_all(contents).and_then(|()| file.sync_all()).map_err(fail)?;
    std::fs::rename(&tmp, path).map_err(|e| {
        let _ = std::fs::remove_file(&tmp);
        fail(e)
    })
}

//! File names for parts. A part's name comes from the design file (links) or the scene (bodies), and
//! becomes `parts/NAME.stl` on disk and in a zip: whatever the name says, the file must land in that
//! folder, under a name every file system takes, and no two parts may share one.

/// Longest file name stem, in characters (leaving room for a suffix and the extension in the 255
/// bytes file systems allow).
pub(crate) const MAX_FILE_STEM: usize = 64;

/// A name every file system takes, inside the folder it is joined to: ASCII letters, digits, `.`, `_`,
/// `-` and space are kept, every other character becomes `_`; no run of dots (so never `..`), no dot,
/// space or `_` at either end (no hidden files, nothing Windows trims), at most [`MAX_FILE_STEM`]
/// characters, and `part` when nothing is left.
pub(crate) fn safe_file_name(name: &str) -> String {
    let mut out = String::with_capacity(name.len().min(MAX_FILE_STEM));
    for c in name.chars() {
        let c = if c.is_ascii_alphanumeric() || matches!(c, '.' | '_' | '-' | ' ') { c } else { '_' };
        if c == '.' && out.ends_with('.') {
            out.pop();
            out.push('_');
            continue;
        }
        out.push(c);
    }
    let trimmed = out.trim_matches(|c| matches!(c, '.' | ' ' | '_'));
    let mut stem: String = trimmed.chars().take(MAX_FILE_STEM).collect();
    while stem.ends_with(['.', ' ', '_']) {
        stem.pop();
    }
    if stem.is_empty() || is_reserved_on_windows(&stem) {
        stem.insert_str(0, "part");
    }
    stem
}

/// Device names Windows refuses as file names, whatever the extension.
fn is_reserved_on_windows(stem: &str) -> bool {
    let base = stem.split('.').next().unwrap_or(stem).to_ascii_uppercase();
    matches!(base.as_str(), "CON" | "PRN" | "AUX" | "NUL")
        || (base.len() == 4
            && (base.starts_with("COM") || base.starts_with("LPT"))
            && base.as_bytes()[3].is_ascii_digit())
}

/// [`safe_file_name`] of each name, made unique ignoring case (as macOS and Windows compare file
/// names): a name already taken gets `-2`, `-3`, … A name that is already safe and unique is kept.
pub(crate) fn file_names<'a>(names: impl IntoIterator<Item = &'a str>) -> Vec<String> {
    let mut taken = std::collections::HashSet::new();
    let mut out = Vec::new();
    for name in names {
        let stem = safe_file_name(name);
        let mut candidate = stem.clone();
        let mut k = 2;
        while !taken.insert(candidate.to_ascii_lowercase()) {
            candidate = format!("{stem}-{k}");
            k += 1;
        }
        out.push(candidate);
    }
    out
}

/// Whether `path` is a relative path of plain names separated by `/` (no `..`, `.`, empty or absolute
/// part, no backslash or drive): what a bundle's paths must be before they are joined to a folder or
/// written into a zip.
pub fn is_safe_relative_path(path: &str) -> bool {
    !path.is_empty()
        && !path.contains(['\\', ':', '\0'])
        && path.split('/').all(|c| !c.is_empty() && c != "." && c != ".." && !c.starts_with('.'))
}

/// Unique file-name-safe names of the moving bodies.
pub(super) fn body_names(problem: &crate::scene::Problem) -> Vec<String> {
    let mut out: Vec<String> = Vec::new();
    for (b, body) in problem.bodies.iter().enumerate() {
        let mut name = sanitize(&body.name);
        if name.is_empty() || name.starts_with("ground") {
            name = format!("body{}", b + 1);
        }
        while out.contains(&name) {
            name.push_str(&format!("_{}", b + 1));
        }
        out.push(name);
    }
    out
}

/// Lower-case letters, digits, `_` and `-` only.
pub fn sanitize(name: &str) -> String {
    let s: String = name
        .trim()
        .chars()
        .map(|c| if c.is_ascii_alphanumeric() || c == '-' { c.to_ascii_lowercase() } else { '_' })
        .collect();
    s.trim_matches('_').to_string()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_stay_in_their_folder() {
        assert_eq!(safe_file_name("crank"), "crank");
        assert_eq!(safe_file_name("body 1_front"), "body 1_front");
        assert_eq!(safe_file_name("../../ESCAPED"), "ESCAPED");
        assert_eq!(safe_file_name("a/../b"), "a___b");
        assert_eq!(safe_file_name("..."), "part");
        assert_eq!(safe_file_name(".hidden"), "hidden");
        assert_eq!(safe_file_name("C:\\x\0y"), "C__x_y");
        assert_eq!(safe_file_name("bédé"), "b_d");
        assert_eq!(safe_file_name(""), "part");
        assert_eq!(safe_file_name("con"), "partcon");
        assert_eq!(safe_file_name("COM1.txt"), "partCOM1.txt");
        assert_eq!(safe_file_name(&"x".repeat(500)).len(), MAX_FILE_STEM);
        for hostile in ["../../ESCAPED", "/etc/passwd", "..\\..\\x", "a..b", " . ", "\u{202e}gpj.exe"] {
            let name = safe_file_name(hostile);
            assert!(is_safe_relative_path(&format!("parts/{name}.stl")), "{hostile:?} -> {name:?}");
            assert!(!name.contains(".."), "{hostile:?} -> {name:?}");
        }
    }

    #[test]
    fn names_are_unique_ignoring_case() {
        let names = file_names(["crank", "Crank", "crank", "crank-2", "../crank"]);
        assert_eq!(names, ["crank", "Crank-2", "crank-3", "crank-2-2", "crank-4"]);
    }

    #[test]
    fn relative_paths() {
        assert!(is_safe_relative_path("parts/crank.stl") && is_safe_relative_path("fabrication.json"));
        for bad in ["", "/abs", "parts/../../x.stl", "parts//x", "./x", "parts/.x", "a\\b", "C:x", "parts/"] {
            assert!(!is_safe_relative_path(bad), "{bad:?}");
        }
    }
}

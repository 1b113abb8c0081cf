//! The web app's JavaScript type-checks. The app has no build step (the browser loads `web/js/*.js` as
//! they are), but every module starts with `// @ts-check` and carries JSDoc types, and the TypeScript
//! compiler reads them all with the repository's `tsconfig.json` (`checkJs`, `strict`) and must find
//! no error. `tsc` is the one `package-lock.json` pins, installed by `npm ci` at the repository's root.
//!
//! Without `node_modules/.bin/tsc` the compiler's tests are skipped with a message, except under
//! `CI=true`, where a missing compiler is a failure (CI runs `npm ci` first: see .ci/run).

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// The repository's root, where `package.json`, `tsconfig.json` and `node_modules` are.
fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// The installed compiler; `None` (the test is skipped, with a message) when it is missing outside CI.
fn tsc(test: &str) -> Option<PathBuf> {
    let tsc = root().join("node_modules/.bin/tsc");
    if tsc.is_file() {
        return Some(tsc);
    }
    if std::env::var("CI").is_ok_and(|v| v == "true") {
        panic!("the TypeScript compiler is not installed ({}): CI must run `npm ci` (see .ci/run)", tsc.display());
    }
    eprintln!("SKIPPED {test}: {} not found; run `npm ci` at the repository's root to run it", tsc.display());
    None
}

/// Runs `tsc` on the project `config` (no output written), from the repository's root.
fn check(tsc: &Path, config: &Path) -> Output {
    Command::new(tsc)
        .args(["--noEmit", "--pretty", "false", "--project"])
        .arg(config)
        .current_dir(root())
        .output()
        .expect("tsc runs (it needs node on the PATH)")
}

fn printed(out: &Output) -> String {
    format!("{}{}", String::from_utf8_lossy(&out.stdout), String::from_utf8_lossy(&out.stderr))
}

#[test]
fn the_web_app_type_checks() {
    let Some(tsc) = tsc("the_web_app_type_checks") else { return };
    let out = check(&tsc, &root().join("tsconfig.json"));
    assert!(
        out.status.success(),
        "tsc finds type errors in the web app (crates/linkwright/web/js):\n{}",
        printed(&out)
    );
}

/// The same settings refuse a module with a type error, so a clean check above means the modules
/// were read and checked (not left out by `include`, or read without `checkJs` or `strict`).
#[test]
fn the_type_check_refuses_a_planted_error() {
    let Some(tsc) = tsc("the_type_check_refuses_a_planted_error") else { return };
    let dir = std::env::temp_dir().join(format!("linkwright-web-types-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let settings = root().join("tsconfig.json").canonicalize().unwrap();
    let config = serde_json::json!({ "extends": settings, "include": ["planted.js"] });
    std::fs::write(dir.join("tsconfig.json"), config.to_string()).unwrap();
    // A parameter without a type (strict's noImplicitAny) and a string where a number goes (checkJs).
    let planted =
        "/** @param {number} x */\nexport const twice = (x) => 2 * x;\nexport const loose = (y) => y;\ntwice('2');\n";
    std::fs::write(dir.join("planted.js"), planted).unwrap();
    let out = check(&tsc, &dir.join("tsconfig.json"));
    let text = printed(&out);
    let _ = std::fs::remove_dir_all(&dir);
    assert!(!out.status.success(), "tsc accepts a module with type errors:\n{text}");
    assert!(
        text.contains("planted.js(3,") && text.contains("planted.js(4,"),
        "tsc does not name both planted errors:\n{text}"
    );
}

#[test]
fn every_module_of_the_web_app_asks_to_be_checked() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("web/js");
    let mut modules = 0;
    for entry in std::fs::read_dir(&dir).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_some_and(|e| e == "js") {
            modules += 1;
            let text = std::fs::read_to_string(&path).unwrap();
            assert!(text.starts_with("// @ts-check\n"), "{} does not start with `// @ts-check`", path.display());
        }
    }
    assert!(modules > 20, "only {modules} modules in {}", dir.display());
}

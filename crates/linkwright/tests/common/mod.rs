//! What the binary's tests share: running the binary, scratch folders, the bundled examples, and the
//! server started on a free port.
#![allow(dead_code, reason = "each test file uses a different part of this module")]

use std::io::{BufRead, BufReader};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Output, Stdio};

/// Runs `linkwright` with `args` and waits for it.
pub(crate) fn linkwright(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_linkwright")).args(args).output().expect("the binary runs")
}

/// A scratch folder of one test, removed when dropped, unless the test is failing: its files are
/// then left to look at.
pub(crate) struct Workdir(PathBuf);

impl std::ops::Deref for Workdir {
    type Target = Path;
    fn deref(&self) -> &Path {
        &self.0
    }
}

impl Drop for Workdir {
    fn drop(&mut self) {
        if !std::thread::panicking() {
            let _ = std::fs::remove_dir_all(&self.0);
        }
    }
}

/// An empty scratch folder of this test file's own (named after the test binary and `name`).
pub(crate) fn workdir(name: &str) -> Workdir {
    let dir =
        std::env::temp_dir().join(format!("linkwright-{}-{}-{name}", env!("CARGO_CRATE_NAME"), std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    Workdir(dir)
}

/// The path of a bundled example.
pub(crate) fn example(name: &str) -> String {
    format!("{}/../../examples/{name}.json", env!("CARGO_MANIFEST_DIR"))
}

/// Output bytes as text.
pub(crate) fn text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}

/// `linkwright serve` on a free port of 127.0.0.1, stopped (by its own pid) when dropped.
pub(crate) struct Server {
    child: Child,
    /// The base URL, ending in `/`.
    pub url: String,
}

impl Server {
    pub(crate) fn start(extra: &[&str]) -> Server {
        let child = Command::new(env!("CARGO_BIN_EXE_linkwright"))
            .args(["serve", "--port", "0", "--threads", "2"])
            .args(extra)
            .stdout(Stdio::piped())
            .stderr(Stdio::inherit())
            .spawn()
            .expect("the binary starts");
        Server::from_child(child)
    }

    /// The server `child` runs, its standard output piped.
    pub(crate) fn from_child(mut child: Child) -> Server {
        let stdout = child.stdout.take().expect("piped stdout");
        let mut lines = BufReader::new(stdout).lines();
        let first = lines.next().and_then(Result::ok).unwrap_or_default();
        let url = first
            .split_whitespace()
            .find(|w| w.starts_with("http://"))
            .unwrap_or_else(|| panic!("the server prints its URL first, printed {first:?}"))
            .to_string();
        // Keep draining stdout so later lines never block the server.
        std::thread::spawn(move || for _ in lines.by_ref() {});
        Server { child, url }
    }

    pub(crate) fn at(&self, path: &str) -> String {
        format!("{}{}", self.url, path.trim_start_matches('/'))
    }

    /// A field of the server process's `/proc/PID/status` in KiB (`VmRSS`, `VmHWM`); `None` where
    /// there is no /proc.
    pub(crate) fn memory_kib(&self, field: &str) -> Option<u64> {
        let status = std::fs::read_to_string(format!("/proc/{}/status", self.child.id())).ok()?;
        let line = status.lines().find(|l| l.starts_with(field))?;
        line.split_whitespace().nth(1)?.parse().ok()
    }
}

impl Drop for Server {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

/// A bundled example's text.
pub(crate) fn example_text(name: &str) -> String {
    std::fs::read_to_string(format!("{}/../../examples/{name}.json", env!("CARGO_MANIFEST_DIR"))).expect("the example")
}

/// The garbage truck with a small, seeded search (a design in a second or two).
pub(crate) fn quick_garbage_truck(samples: u64, seed: u64) -> serde_json::Value {
    let mut scene: serde_json::Value = serde_json::from_str(&example_text("k1_garbage_truck")).unwrap();
    scene["settings"] = serde_json::json!({"samples": samples, "seed": seed});
    scene
}

/// Runs `linkwright design` on the bundled garbage truck with a small budget (3,000 samples) into
/// `out`, with `extra` arguments.
pub(crate) fn design_truck(out: &std::path::Path, extra: &[&str]) -> Output {
    let (scene, out) = (example("k1_garbage_truck"), out.to_str().expect("a UTF-8 path").to_string());
    let mut args = vec!["design", scene.as_str(), "-o", out.as_str(), "--samples", "3000"];
    args.extend_from_slice(extra);
    linkwright(&args)
}

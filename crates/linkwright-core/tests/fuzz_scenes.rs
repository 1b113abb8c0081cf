//! Fuzzing of scene files: mutated copies of every bundled example and reference scene go through
//! everything a scene file reaches before the engine answers (parsing, validation, the problem, the
//! printability pre-check, a small synthesis). No case may panic, abort or run past its bound.
//!
//! CI runs it for a short budget; by hand, run it long:
//! `LINKWRIGHT_FUZZ_SECONDS=3600 LINKWRIGHT_FUZZ_SEED=7 cargo test --release -p linkwright-core --test fuzz_scenes`.
//! A failing case is written to `target/tmp/fuzz-failures/`; once fixed, add it to
//! `tests/fixtures/fuzz-corpus/scenes/`, which every run replays first.

mod mutate;

use linkwright_core::fab::{FeasibilityCheck, PrintSettings};
use linkwright_core::scene::{validate, Problem, Scene, Severity};
use linkwright_core::synth::{synthesize_with, Options, Silent};
use mutate::{mutate, Rng};
use std::path::{Path, PathBuf};
use std::sync::mpsc;
use std::time::{Duration, Instant};

/// The most one case may take: the scene limits bound the work of everything a valid file reaches,
/// with a small search (see `run_case`) it takes well under a second in release builds.
const CASE_BOUND: Duration = Duration::from_secs(60);

fn fixtures() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures")
}

/// The texts of the bundled examples and the reference scenes: real inputs to mutate.
fn seeds() -> Vec<String> {
    let examples = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples");
    let mut files: Vec<PathBuf> = [examples, fixtures().join("reference-scenes")]
        .iter()
        .flat_map(|dir| std::fs::read_dir(dir).unwrap().map(|e| e.unwrap().path()))
        .filter(|p| p.extension().is_some_and(|e| e == "json"))
        .collect();
    files.sort();
    files.iter().map(|p| std::fs::read_to_string(p).unwrap()).collect()
}

/// Everything a scene file reaches before the engine answers, with a small search budget so that many
/// cases run (the full budgets are bounded by the limits and measured in `docs/security.md`).
/// Returns whether the case reached the engine (parsed and validated).
fn run_case(text: &str) -> bool {
    let Ok(mut scene) = Scene::from_json(text) else { return false };
    if validate(&scene).iter().any(|i| i.severity == Severity::Error) {
        return false;
    }
    let settings = &mut scene.settings;
    settings.samples = settings.samples.min(1500);
    settings.particles = settings.particles.min(8);
    settings.iterations = settings.iterations.min(2);
    let problem = Problem::new(&scene).expect("a scene without validation errors makes a problem");
    let printable = FeasibilityCheck::new(&problem, &PrintSettings::default(), 1.0);
    let options = Options { printable: Some(&printable), ..Options::default() };
    let _ = synthesize_with(&problem, &options, &Silent);
    true
}

/// Runs `text` on a thread of its own: whether it reached the engine, or its failure (a panic or
/// running past the bound).
fn outcome(text: &str) -> Result<bool, String> {
    let (done, finished) = mpsc::channel();
    let owned = text.to_string();
    let started = Instant::now();
    let worker = std::thread::spawn(move || {
        let caught = std::panic::catch_unwind(|| run_case(&owned));
        let _ = done.send(caught.ok());
    });
    match finished.recv_timeout(CASE_BOUND) {
        Ok(Some(reached)) => {
            let _ = worker.join();
            Ok(reached)
        }
        Ok(None) | Err(mpsc::RecvTimeoutError::Disconnected) => Err("panicked".into()),
        // The worker is left running: the test fails and its process ends with it.
        Err(mpsc::RecvTimeoutError::Timeout) => Err(format!("ran past {CASE_BOUND:?} ({:?})", started.elapsed())),
    }
}

fn keep(name: &str, text: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("fuzz-failures");
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    path
}

#[test]
fn the_corpus_of_inputs_that_once_failed_still_passes() {
    let dir = fixtures().join("fuzz-corpus/scenes");
    let mut cases: Vec<PathBuf> = std::fs::read_dir(&dir).unwrap().map(|e| e.unwrap().path()).collect();
    cases.sort();
    assert!(!cases.is_empty(), "the corpus at {} is empty", dir.display());
    for case in cases {
        let text = String::from_utf8_lossy(&std::fs::read(&case).unwrap()).into_owned();
        assert!(outcome(&text).is_ok(), "{}: {:?}", case.display(), outcome(&text));
    }
}

#[test]
fn mutated_scenes_never_panic_nor_run_unbounded() {
    let seconds: u64 = std::env::var("LINKWRIGHT_FUZZ_SECONDS").ok().and_then(|s| s.parse().ok()).unwrap_or(15);
    let seed: u64 = std::env::var("LINKWRIGHT_FUZZ_SEED").ok().and_then(|s| s.parse().ok()).unwrap_or(0);
    let seeds = seeds();
    let mut rng = Rng::new(seed);
    let started = Instant::now();
    let (mut cases, mut reached) = (0usize, 0usize);
    while cases < 20 || started.elapsed() < Duration::from_secs(seconds) {
        let text = mutate(&seeds[rng.below(seeds.len())], &mut rng);
        match outcome(&text) {
            Ok(engine) => reached += usize::from(engine),
            Err(what) => {
                let path = keep(&format!("scene-seed{seed}-case{cases}.json"), &text);
                panic!("case {cases} of seed {seed} {what}; the input is in {}", path.display());
            }
        }
        cases += 1;
    }
    let seconds = started.elapsed().as_secs_f64();
    eprintln!("{cases} mutated scenes ({reached} valid, run by the engine) in {seconds:.1} s, seed {seed}: no panic, none past {CASE_BOUND:?}");
}

//! Fuzzing of scene files: mutated copies of every bundled example and reference scene go through
//! everything a scene file reaches before the engine answers (parsing, validation, the problem, the
//! printability pre-check, a small synthesis). No case may panic, abort or run past its bound.
//!
//! CI runs it for a short budget; by hand, run it long:
//! `LINKWRIGHT_FUZZ_SECONDS=3600 LINKWRIGHT_FUZZ_SEED=7 cargo test --release -p linkwright-core --test fuzz_scenes`.
//! A failing case is written to `target/tmp/fuzz-failures/`; once fixed, add it to
//! `tests/fixtures/fuzz-corpus/scenes/`, which every run replays first.

mod fuzz;

use fuzz::{bounded, budget, keep_failure, mutate, Rng, CASE_BOUND};
use linkwright_core::fab::{FeasibilityCheck, PrintSettings};
use linkwright_core::{synthesize_with, validate_scene, Options, Problem, Ratio, Scene, Severity, Silent};
use std::path::{Path, PathBuf};
use std::time::Instant;

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
    if validate_scene(&scene).iter().any(|i| i.severity == Severity::Error) {
        return false;
    }
    let settings = &mut scene.settings;
    settings.samples = settings.samples.min(1500);
    settings.particles = settings.particles.min(8);
    settings.iterations = settings.iterations.min(2);
    let problem = Problem::new(&scene).expect("a scene without validation errors makes a problem");
    let printable = FeasibilityCheck::new(&problem, &PrintSettings::default(), Ratio::ONE);
    let options = Options { printable: Some(&printable), ..Options::default() };
    let _ = synthesize_with(&problem, &options, &Silent);
    true
}

/// [`run_case`] within its bound: whether it reached the engine, or its failure.
fn outcome(text: &str) -> Result<bool, String> {
    let owned = text.to_string();
    bounded(move || run_case(&owned))
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
    let (duration, seed) = budget();
    let seeds = seeds();
    let mut rng = Rng::new(seed);
    let started = Instant::now();
    let (mut cases, mut reached) = (0usize, 0usize);
    while cases < 20 || started.elapsed() < duration {
        let text = mutate(&seeds[rng.below(seeds.len())], &mut rng);
        match outcome(&text) {
            Ok(engine) => reached += usize::from(engine),
            Err(what) => {
                let path = keep_failure(&format!("scene-seed{seed}-case{cases}.json"), &text);
                panic!("case {cases} of seed {seed} {what}; the input is in {}", path.display());
            }
        }
        cases += 1;
    }
    let seconds = started.elapsed().as_secs_f64();
    eprintln!("{cases} mutated scenes ({reached} valid, run by the engine) in {seconds:.1} s, seed {seed}: no panic, none past {CASE_BOUND:?}");
}

//! Fuzzing of design files: mutated copies of the engine's own designs for three bundled examples go
//! through everything a design file reaches (parsing, validation against its scene, the check, the
//! motion analysis and, for some, fabrication). No case may panic, abort or run past its bound, and a
//! design that validation lets through must be one the check can judge.
//!
//! CI runs it for a short budget; by hand, run it long:
//! `LINKWRIGHT_FUZZ_SECONDS=3600 LINKWRIGHT_FUZZ_SEED=7 cargo test --release -p linkwright-core --test fuzz_designs`.
//! A failing case is written to `target/tmp/fuzz-failures/` (its scene is the example named in the
//! file); once fixed, add it to `tests/fixtures/fuzz-corpus/designs/`, which every run replays first.

mod fuzz;

use fuzz::{bounded, budget, keep_failure, mutate, non_finite, Rng, CASE_BOUND};
use linkwright_core::analysis::{analyze, AnalysisOptions, Which};
use linkwright_core::fab::{fabricate_design, PrintSettings};
use linkwright_core::{synthesize, DesignFile, Problem, Scene, Silent};
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::Instant;

/// The examples whose designs are mutated: one body, two bodies, and the slider-crank family.
const EXAMPLES: [&str; 3] = ["k1_garbage_truck", "k2_wall_chair", "k1_sofa_bed"];

fn example(name: &str) -> Arc<Problem> {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join(format!("../../examples/{name}.json"));
    let mut scene = Scene::from_json(&std::fs::read_to_string(path).unwrap()).unwrap();
    scene.settings.samples = 5000;
    Arc::new(Problem::new(&scene).unwrap())
}

/// Per example: its problem and the engine's design of it as text.
fn seeds() -> Vec<(Arc<Problem>, String)> {
    EXAMPLES
        .iter()
        .map(|name| {
            let problem = example(name);
            let outcome = synthesize(&problem, &Silent).unwrap();
            let design = DesignFile::from_outcome(&problem, &outcome);
            let text = serde_json::to_string(&design).unwrap();
            (problem, text)
        })
        .collect()
}

/// Everything a design file reaches; `fabricate` also builds its parts.
fn run_case(problem: &Problem, text: &str, fabricate: bool) -> bool {
    let Ok(design) = DesignFile::from_json(text) else { return false };
    if !design.validate(problem).is_empty() {
        // Every reader refuses it with the same issues.
        assert!(!design.violations(problem).is_empty(), "validation refused what the check accepts");
        return false;
    }
    let _ = design.violations(problem);
    for which in [Which::Best, Which::Alternative(0)] {
        if let Ok(analysis) = analyze(problem, &design, which, &AnalysisOptions::default()) {
            let answer = serde_json::to_value(&analysis).expect("an analysis serialises");
            assert_eq!(non_finite(&answer), None, "the analysis of a valid design has a number that is not finite");
        }
    }
    if fabricate {
        let _ = fabricate_design(problem, &design, &PrintSettings::default());
    }
    true
}

/// [`run_case`] within its bound: whether the design passed validation, or its failure.
fn outcome(problem: &Arc<Problem>, text: &str, fabricate: bool) -> Result<bool, String> {
    let (problem, owned) = (problem.clone(), text.to_string());
    bounded(move || run_case(&problem, &owned, fabricate))
}

#[test]
fn the_corpus_of_designs_that_once_failed_still_passes() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/fuzz-corpus/designs");
    let mut cases: Vec<PathBuf> = std::fs::read_dir(&dir).unwrap().map(|e| e.unwrap().path()).collect();
    cases.sort();
    assert!(!cases.is_empty(), "the corpus at {} is empty", dir.display());
    for case in cases {
        // Files are named `<example>--<what>.json`: the example is the design's scene.
        let stem = case.file_stem().unwrap().to_string_lossy().into_owned();
        let problem = example(stem.split("--").next().unwrap());
        let text = String::from_utf8_lossy(&std::fs::read(&case).unwrap()).into_owned();
        let result = outcome(&problem, &text, true);
        assert!(result.is_ok(), "{}: {result:?}", case.display());
    }
}

#[test]
fn mutated_designs_never_panic_nor_run_unbounded() {
    let (duration, seed) = budget();
    let seeds = seeds();
    let mut rng = Rng::new(seed);
    let started = Instant::now();
    let (mut cases, mut valid) = (0usize, 0usize);
    while cases < 20 || started.elapsed() < duration {
        let k = rng.below(seeds.len());
        let (problem, text) = &seeds[k];
        let mutated = mutate(text, &mut rng);
        // Fabrication is the slowest reader: one case in eight.
        let fabricate = rng.below(8) == 0;
        match outcome(problem, &mutated, fabricate) {
            Ok(passed) => valid += usize::from(passed),
            Err(what) => {
                let path = keep_failure(&format!("{}--seed{seed}-case{cases}.json", EXAMPLES[k]), &mutated);
                panic!("case {cases} of seed {seed} {what}; the input is in {}", path.display());
            }
        }
        cases += 1;
    }
    let seconds = started.elapsed().as_secs_f64();
    eprintln!("{cases} mutated designs ({valid} valid, read through) in {seconds:.1} s, seed {seed}: no panic, none past {CASE_BOUND:?}");
}

//! Micro-benchmarks of the hot kernels, so a regression shows up as a number: `cargo bench`.
//!
//! Each kernel runs on a real bundled scene: the rigidity fit (K = 1, 2, 3), the kinematic checks
//! with their simulation (the defect check), the collision sweep, one kinematic step, and
//! fabrication's printability check.

use linkwright_core::geom::Point;
use linkwright_core::kernels::Kernels;
use linkwright_core::kinematics::Plan;
use linkwright_core::{synthesize, Candidate, MechanismChoice, MechanismType, Problem, Scene, Silent};
use std::sync::OnceLock;

fn main() {
    divan::main();
}

fn problem(name: &str) -> Problem {
    let path = format!("{}/../../examples/{name}.json", env!("CARGO_MANIFEST_DIR"));
    let scene = Scene::from_json(&std::fs::read_to_string(path).expect("bundled example")).expect("parses");
    let mut problem = Problem::new(&scene).expect("valid");
    problem.settings.samples = 20000;
    problem.settings.iterations = 2;
    problem
}

/// A scene per K, and the best design the engine finds on it (computed once).
fn fixture(k: usize) -> &'static (Problem, Candidate) {
    static FIXTURES: OnceLock<Vec<(Problem, Candidate)>> = OnceLock::new();
    &FIXTURES.get_or_init(|| {
        ["k1_garbage_truck", "k2_wall_bed", "k3_power_shovel"]
            .iter()
            .map(|name| {
                let mut p = problem(name);
                p.mechanism = MechanismChoice::Only(MechanismType::Chain);
                let best = synthesize(&p, &Silent).expect("not cancelled").best.expect("a design");
                (p, best)
            })
            .collect()
    })[k - 1]
}

/// One E_rigid fit from the design's joints moved off by 10% of d, against the input poses.
#[divan::bench(args = [1, 2, 3])]
fn rigidity_fit(bencher: divan::Bencher, k: usize) {
    let (problem, best) = fixture(k);
    let mut kernels = Kernels::new(problem, MechanismType::Chain);
    let mut start = Vec::new();
    for (i, p) in best.mechanism.joints.iter().enumerate() {
        let shift = if i % 2 == 0 { 0.1 } else { -0.1 } * kernels.body_size();
        start.extend([p.x + shift, p.y - shift]);
    }
    let mut x = start.clone();
    bencher.bench_local(|| {
        x.copy_from_slice(&start);
        kernels.rigidity_fit(divan::black_box(&mut x))
    });
}

/// The defect checks of a candidate: spacing, branch, order, the 1° simulation, transmission, costs.
#[divan::bench(args = [1, 2, 3])]
fn defect_check(bencher: divan::Bencher, k: usize) {
    let (problem, best) = fixture(k);
    let mut kernels = Kernels::new(problem, MechanismType::Chain);
    bencher.bench_local(|| kernels.defect_check(divan::black_box(best.mechanism.clone())));
}

/// The collision sweep of a valid design's whole travel (no early exit: it is collision-free).
#[divan::bench(args = [1, 2, 3])]
fn collision_sweep(bencher: divan::Bencher, k: usize) {
    let (problem, best) = fixture(k);
    let mut kernels = Kernels::new(problem, MechanismType::Chain);
    bencher.bench_local(|| kernels.collision_sweep(divan::black_box(best)));
}

/// One kinematic step: every joint placed at one crank angle.
#[divan::bench(args = [1, 2, 3])]
fn kinematic_step(bencher: divan::Bencher, k: usize) {
    let (_, best) = fixture(k);
    let plan = Plan::compile(&best.mechanism).expect("compiles");
    let mut row = vec![Point::ORIGIN; plan.joint_count()];
    let theta = best.trace.thetas[best.trace.len() / 2];
    bencher.bench_local(|| plan.solve(divan::black_box(theta), &mut row));
}

/// Fabrication's feasibility check (connectors placed, constraints recorded along the motion, the
/// ordering solved) on the engine's design: the synthesis runs it on each kept design when it is asked
/// for printable designs.
#[divan::bench(args = [1, 2, 3])]
fn printability_check(bencher: divan::Bencher, k: usize) {
    let (problem, best) = fixture(k);
    let check = linkwright_core::fab::FeasibilityCheck::new(problem, &Default::default(), linkwright_core::Ratio::ONE);
    bencher.bench_local(|| check.check(divan::black_box(&best.mechanism), &best.trace));
}

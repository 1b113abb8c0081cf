//! `linkwright bench`: the paper's Table 1, measured side by side on this machine; with `--known`,
//! the quality of the designs on scenes whose exact answer is known (see [`known`]); with `--sizes`,
//! how the scenes given design and print at a hundredth and a hundred times their size ([`sizes`]);
//! with `--live`, how a live redesign follows a dragged pose ([`live`]); with `--auto`, what the
//! automatic choice of family costs against the family it returns ([`auto`]); with `--paths`, how
//! closely designs trace known coupler curves ([`paths`]).

mod auto;
mod known;
mod live;
mod paths;
mod sizes;

/// A scene file's name without its directory and `.json`: how the benchmarks' rows name it.
fn scene_label(path: &std::path::Path) -> String {
    // Printed to the terminal: a file name's control characters are shown, not obeyed.
    path.file_stem().map_or(String::new(), |s| crate::terminal::escaped(&s.to_string_lossy()))
}

/// `problem` designed as `linkwright design` designs it by default: an auto printed model with the
/// default print settings.
fn design_printed(problem: &Problem, start: linkwright_core::Start, pool: &rayon::ThreadPool) -> DesignFile {
    let settings = linkwright_core::fab::PrintSettings::default();
    let plan = linkwright_core::fab::BuildPlan::new(problem, &settings);
    let options = linkwright_core::Options { start, printable: None };
    let (plan, outcome) =
        pool.install(|| plan.synthesize(problem, &settings, &options, &Silent)).expect("never cancelled");
    plan.design_file(problem, &outcome)
}

/// The `q` quantile of `values` (sorted in place), NaN when there are none.
fn quantile(values: &mut [f64], q: f64) -> f64 {
    values.sort_by(f64::total_cmp);
    values.get(((values.len() as f64 - 1.0) * q).round() as usize).copied().unwrap_or(f64::NAN)
}

use crate::failure::Failure;
use crate::files::read_problem;
use clap::Args;
use linkwright_core::{synthesize, DesignFile, MechanismChoice, MechanismType, Problem, Scene, Silent};
use serde::Serialize;
use std::path::PathBuf;

#[derive(Args, Debug)]
pub(crate) struct BenchArgs {
    /// Scene files to time (default: the paper's Table-1 objects, bundled).
    scenes: Vec<PathBuf>,
    /// Runs per scene; the table shows medians.
    #[arg(long, default_value_t = 3)]
    repeat: usize,
    /// Worker threads (default: all cores).
    #[arg(long, value_parser = crate::thread_count())]
    threads: Option<usize>,
    /// Print the table as JSON.
    #[arg(long)]
    json: bool,
    /// Measure how close the designs come to the drawn poses, on scenes made from known exact
    /// mechanisms and on the nine-pose four-bar task, instead of timing Table 1.
    #[arg(long, conflicts_with_all = ["scenes", "repeat"])]
    known: bool,
    /// With --known or --paths: a smaller grid of scenes.
    #[arg(long)]
    quick: bool,
    /// With --known or --paths: the synthesis seed of every run.
    #[arg(long, default_value_t = 0)]
    seed: u64,
    /// With --known or --paths: write each scene and the engine's design into this directory, to
    /// rerun or inspect one (`<family>_k<K>_n<N>_seed<S>.json` and `.design.json`; with --paths
    /// `<closed|open>_<points>_noise<noise>_seed<S>`).
    #[arg(long, value_name = "DIR")]
    save: Option<PathBuf>,
    /// Design each scene given at 0.01x, 1x and 100x its size with default settings (an auto printed
    /// model): the model's scale, the worst pose error at each size, and whether its parts fit the plates.
    #[arg(long, conflicts_with_all = ["known", "repeat"])]
    sizes: bool,
    /// Drag the middle pose of each scene given by a tenth of its body's size in ten steps, each
    /// redesigned live (as the app does) from the design before: family changes, how far the joints
    /// jump per step, and the seconds per step.
    #[arg(long, conflicts_with_all = ["known", "repeat", "sizes"])]
    live: bool,
    /// Design each scene given with `mechanism: auto`, then with the family it returned alone, back
    /// to back (`--repeat` pairs): the seconds of each, their ratio and both designs' quality.
    #[arg(long, conflicts_with_all = ["known", "sizes", "live"])]
    auto: bool,
    /// Measure how closely the designs trace drawn paths made from known four-bars' coupler curves
    /// (closed and open, 20 to 200 points, exact and with noise), instead of timing Table 1.
    #[arg(long, conflicts_with_all = ["scenes", "repeat", "known", "sizes", "live", "auto"])]
    paths: bool,
}

/// A Table-1 object: the bundled example, the mechanism the paper used, and the paper's seconds
/// (sampling + collision check + PFO, i7 with 8 threads).
struct PaperObject {
    label: &'static str,
    scene: &'static str,
    mechanism: MechanismChoice,
    paper_seconds: f64,
}

const TABLE_1: [PaperObject; 9] = [
    PaperObject {
        label: "Car (K=2)",
        scene: include_str!("../../../examples/k2_folding_roof2.json"),
        mechanism: MechanismChoice::Only(MechanismType::Chain),
        paper_seconds: 2.80,
    },
    PaperObject {
        label: "Wall bed (K=2)",
        scene: include_str!("../../../examples/k2_wall_bed.json"),
        mechanism: MechanismChoice::Only(MechanismType::Chain),
        paper_seconds: 2.38,
    },
    PaperObject {
        label: "Wall chair (K=2)",
        scene: include_str!("../../../examples/k2_wall_chair.json"),
        mechanism: MechanismChoice::Only(MechanismType::Chain),
        paper_seconds: 2.34,
    },
    PaperObject {
        label: "Car (K=3)",
        scene: include_str!("../../../examples/k3_folding_roof.json"),
        mechanism: MechanismChoice::Only(MechanismType::Chain),
        paper_seconds: 4.36,
    },
    PaperObject {
        label: "Power shovel (K=3)",
        scene: include_str!("../../../examples/k3_power_shovel.json"),
        mechanism: MechanismChoice::Only(MechanismType::Chain),
        paper_seconds: 5.01,
    },
    PaperObject {
        label: "Sofa bed (slider-crank)",
        scene: include_str!("../../../examples/k1_sofa_bed.json"),
        mechanism: MechanismChoice::Only(MechanismType::SliderCrank),
        paper_seconds: 0.51,
    },
    PaperObject {
        label: "Bulldozer (slider-crank)",
        scene: include_str!("../../../examples/k1_bulldozer.json"),
        mechanism: MechanismChoice::Only(MechanismType::SliderCrank),
        paper_seconds: 0.69,
    },
    PaperObject {
        label: "Garbage truck (K=1)",
        scene: include_str!("../../../examples/k1_garbage_truck.json"),
        mechanism: MechanismChoice::Only(MechanismType::Chain),
        paper_seconds: 1.26,
    },
    PaperObject {
        label: "Folding table (K=1)",
        scene: include_str!("../../../examples/k1_table.json"),
        mechanism: MechanismChoice::Only(MechanismType::Chain),
        paper_seconds: 0.41,
    },
];

/// One row of the table.
#[derive(Serialize, Debug)]
struct Row {
    object: String,
    samples: usize,
    candidates: usize,
    valid: usize,
    seconds_sampling: f64,
    seconds_collision: f64,
    seconds_pfo: f64,
    seconds_total: f64,
    paper_seconds: Option<f64>,
    ratio: Option<f64>,
    cost: Option<f64>,
}

pub(crate) fn bench(args: BenchArgs) -> Result<(), Failure> {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(args.threads.unwrap_or(0))
        .build()
        .map_err(|e| Failure::Input(format!("error: --threads: {e}")))?;
    if args.paths {
        return paths::bench_paths(args.quick, args.seed, args.save.as_deref(), &pool, args.json);
    }
    if args.known {
        return known::bench_known(args.quick, args.seed, args.save.as_deref(), &pool, args.json);
    }
    if args.live {
        return live::bench_live(&args.scenes, &pool, args.json);
    }
    if args.auto {
        return auto::bench_auto(&args.scenes, args.repeat, &pool, args.json);
    }
    if args.sizes {
        return sizes::bench_sizes(&args.scenes, &pool, args.json);
    }
    let mut jobs: Vec<(String, Problem, Option<f64>)> = Vec::new();
    if args.scenes.is_empty() {
        for object in &TABLE_1 {
            let scene = Scene::from_json(object.scene).expect("bundled examples parse");
            let mut problem = Problem::new(&scene).expect("bundled examples are valid");
            problem.mechanism = object.mechanism;
            jobs.push((object.label.to_string(), problem, Some(object.paper_seconds)));
        }
    } else {
        for path in &args.scenes {
            let (_, problem) = read_problem(path)?;
            jobs.push((path.display().to_string(), problem, None));
        }
    }
    let repeat = args.repeat.max(1);
    let mut rows = Vec::new();
    for (label, problem, paper) in &jobs {
        let runs: Vec<DesignFile> = (0..repeat)
            .map(|_| {
                let outcome = pool.install(|| synthesize(problem, &Silent)).expect("never cancelled");
                DesignFile::from_outcome(problem, &outcome)
            })
            .collect();
        let median = |f: &dyn Fn(&DesignFile) -> f64| {
            let mut v: Vec<f64> = runs.iter().map(f).collect();
            v.sort_by(f64::total_cmp);
            v[v.len() / 2]
        };
        let last = &runs[runs.len() - 1];
        let total = median(&|d| d.stats.seconds.total);
        rows.push(Row {
            object: label.clone(),
            samples: last.stats.samples,
            candidates: last.stats.candidates,
            valid: last.stats.valid,
            seconds_sampling: median(&|d| d.stats.seconds.sampling),
            seconds_collision: median(&|d| d.stats.seconds.collision),
            seconds_pfo: median(&|d| d.stats.seconds.pfo),
            seconds_total: total,
            paper_seconds: *paper,
            ratio: paper.map(|p| total / p),
            cost: last.metrics.as_ref().map(|m| m.cost),
        });
        if !args.json {
            crate::terminal::warn(&format!("{label}: {total:.3} s"));
        }
    }
    if args.json {
        println!("{}", serde_json::to_string_pretty(&rows).expect("rows serialize"));
    } else {
        print!("{}", crate::terminal::lines(&table(&rows, repeat, pool.current_num_threads())));
    }
    Ok(())
}

fn table(rows: &[Row], repeat: usize, threads: usize) -> String {
    let mut out = format!(
        "median of {repeat} run(s), {threads} thread(s); seconds are wall-clock\n\
         {:<26} {:>8} {:>10} {:>6} {:>9} {:>9} {:>7} {:>7} {:>7} {:>6} {:>9}\n",
        "object", "samples", "before col", "valid", "sampling", "collision", "pfo", "total", "paper", "ratio", "cost"
    );
    for r in rows {
        let opt = |v: Option<f64>, digits: usize| v.map_or("-".to_string(), |x| format!("{x:.digits$}"));
        out.push_str(&format!(
            "{:<26} {:>8} {:>10} {:>6} {:>9.3} {:>9.3} {:>7.3} {:>7.3} {:>7} {:>6} {:>9}\n",
            r.object,
            r.samples,
            r.candidates,
            r.valid,
            r.seconds_sampling,
            r.seconds_collision,
            r.seconds_pfo,
            r.seconds_total,
            opt(r.paper_seconds, 2),
            opt(r.ratio, 2),
            opt(r.cost, 3)
        ));
    }
    out
}

//! `linkwright bench --sizes SCENES...`: each scene designed at a hundredth, once and a hundred times
//! its drawn size, with default settings (an `auto` printed model): whether it designs, at which
//! model scale, how close it comes to its poses at each size, and whether its printed model's parts
//! all lie on plates.

use crate::failure::Failure;
use crate::files::read_problem;
use linkwright_core::fab::{bundle, fabricate_design, BuildPlan, PrintSettings};
use linkwright_core::testbed::scaled_scene;
use linkwright_core::{Options, Problem, Silent, Status};
use serde::Serialize;
use std::path::PathBuf;
use std::time::Instant;

/// The sizes each scene is drawn at, as factors of its own.
const FACTORS: [f64; 3] = [0.01, 1.0, 100.0];

/// One scene at one size.
#[derive(Serialize, Debug)]
struct Row {
    scene: String,
    factor: f64,
    /// The model's scale the build chose (`1:5`), or why there is none.
    scale: String,
    designed: bool,
    buildable: bool,
    /// The worst pose error as a fraction of the body size d.
    worst_rel_d: Option<f64>,
    /// Parts of the printed model, the plates they lie on, and those on none.
    parts: Option<usize>,
    plates: Option<usize>,
    off_plates: Option<usize>,
    /// Seconds to decide the build (its scale and print check) and to design.
    seconds_build: f64,
    seconds_design: f64,
}

pub(super) fn bench_sizes(scenes: &[PathBuf], pool: &rayon::ThreadPool, json: bool) -> Result<(), Failure> {
    if scenes.is_empty() {
        return Err(Failure::Input("error: --sizes: name the scene files to measure (examples/*.json)".into()));
    }
    let settings = PrintSettings::default();
    let mut rows = Vec::new();
    for path in scenes {
        let (scene, _) = read_problem(path)?;
        for factor in FACTORS {
            let scaled = scaled_scene(&scene, factor);
            let label = super::scene_label(path);
            let Ok(problem) = Problem::new(&scaled) else {
                eprintln!("{label} ×{factor}: not a valid scene at this size");
                continue;
            };
            let t = Instant::now();
            let plan = BuildPlan::new(&problem, &settings);
            let seconds_build = t.elapsed().as_secs_f64();
            let t = Instant::now();
            let (plan, outcome) = pool
                .install(|| plan.synthesize(&problem, &settings, &Options::default(), &Silent))
                .expect("never cancelled");
            let seconds_design = t.elapsed().as_secs_f64();
            let file = plan.design_file(&problem, &outcome);
            let designed = file.status == Status::Ok;
            let fabricated = designed
                .then(|| fabricate_design(&problem, &file, &settings).ok())
                .flatten()
                .and_then(|f| bundle(&f).ok());
            let report = fabricated.as_ref().map(|b| &b.report);
            let row = Row {
                scene: label,
                factor,
                scale: plan.model_scale().map_or("-".into(), |s| s.to_string()),
                designed,
                buildable: file.build.as_ref().is_some_and(|b| b.buildable),
                worst_rel_d: file.metrics.as_ref().and_then(|m| m.worst_pose_error).map(|w| w.position_rel_d),
                parts: report.map(|r| r.parts.len()),
                plates: report.map(|r| r.plates.len()),
                off_plates: report.map(|r| r.oversized.len()),
                seconds_build,
                seconds_design,
            };
            if !json {
                eprintln!(
                    "{} ×{}: {} at {}, {:.3} s",
                    row.scene,
                    row.factor,
                    if designed { "designed" } else { "no design" },
                    row.scale,
                    seconds_design
                );
            }
            rows.push(row);
        }
    }
    if json {
        println!("{}", serde_json::to_string_pretty(&rows).expect("rows serialize"));
    } else {
        print!("{}", table(&rows));
    }
    Ok(())
}

fn table(rows: &[Row]) -> String {
    let mut out = format!(
        "{:<40} {:>7} {:>9} {:>6} {:>9} {:>10} {:>6} {:>6} {:>8} {:>9} {:>8}\n",
        "scene",
        "size",
        "scale",
        "design",
        "buildable",
        "worst (d)",
        "parts",
        "plates",
        "off bed",
        "build (s)",
        "run (s)"
    );
    let opt = |v: Option<usize>| v.map_or("-".to_string(), |x| x.to_string());
    for r in rows {
        out.push_str(&format!(
            "{:<40} {:>7} {:>9} {:>6} {:>9} {:>10} {:>6} {:>6} {:>8} {:>9.5} {:>8.3}\n",
            r.scene,
            format!("{}x", r.factor),
            r.scale,
            if r.designed { "yes" } else { "no" },
            if r.buildable { "yes" } else { "no" },
            r.worst_rel_d.map_or("-".to_string(), |w| format!("{w:.4}")),
            opt(r.parts),
            opt(r.plates),
            opt(r.off_plates),
            r.seconds_build,
            r.seconds_design
        ));
    }
    // Per scene: designed at every size, and the spread of the worst pose error between sizes.
    let mut spreads: Vec<f64> = Vec::new();
    let mut everywhere = 0;
    let scenes: Vec<&str> =
        rows.iter().map(|r| r.scene.as_str()).collect::<std::collections::BTreeSet<_>>().into_iter().collect();
    for scene in &scenes {
        let errors: Vec<f64> = rows.iter().filter(|r| r.scene == *scene).filter_map(|r| r.worst_rel_d).collect();
        if errors.len() == FACTORS.len() {
            everywhere += 1;
            let (lo, hi) = errors.iter().fold((f64::INFINITY, 0.0f64), |(lo, hi), &e| (lo.min(e), hi.max(e)));
            spreads.push(hi - lo);
        }
    }
    spreads.sort_by(f64::total_cmp);
    let median = spreads.get(spreads.len() / 2).copied().unwrap_or(0.0);
    let worst = spreads.last().copied().unwrap_or(0.0);
    let on_plates = rows.iter().filter(|r| r.off_plates == Some(0)).count();
    let designed = rows.iter().filter(|r| r.designed).count();
    let build: f64 = rows.iter().map(|r| r.seconds_build).sum();
    let run: f64 = rows.iter().map(|r| r.seconds_design).sum();
    out.push_str(&format!(
        "{everywhere} of {} scenes designed at every size; worst pose error's spread between sizes (fraction of d): \
         median {median:.4}, worst {worst:.4}\n{designed} designs, {on_plates} with every part on a plate; deciding \
         the build took {:.2}% of the design time\n",
        scenes.len(),
        100.0 * build / run.max(1e-12)
    ));
    out
}

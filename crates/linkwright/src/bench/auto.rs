//! `linkwright bench --auto SCENES`: what the automatic choice of family costs. Each scene is
//! designed as given (default settings, an auto printed model, `mechanism: auto` unless the scene
//! names a family), then at once again with the family that run returned as the scene's only
//! choice: paired runs, back to back, `--repeat` times. Reported per scene: the family, the median
//! of the paired ratios of seconds (auto over the family alone), and both runs' cost and worst pose
//! error (the design auto returns should be as good as the family's own run).

use crate::failure::Failure;
use crate::files::read_problem;
use linkwright_core::{DesignFile, MechanismChoice, Problem, Start};
use serde::Serialize;
use std::path::PathBuf;
use std::time::Instant;

/// One scene's paired runs (medians over the repeats).
#[derive(Serialize, Debug)]
struct Row {
    scene: String,
    /// The family auto returned (of the first run).
    family: &'static str,
    /// Seconds of the auto run and of the family's own.
    seconds_auto: f64,
    seconds_family: f64,
    /// The median of the paired ratios, auto over the family alone.
    ratio: f64,
    /// The best design's cost, auto and the family alone.
    cost_auto: Option<f64>,
    cost_family: Option<f64>,
    /// The worst pose error, fraction of d, auto and the family alone.
    worst_auto_rel_d: Option<f64>,
    worst_family_rel_d: Option<f64>,
}

pub(super) fn bench_auto(
    scenes: &[PathBuf],
    repeat: usize,
    pool: &rayon::ThreadPool,
    json: bool,
) -> Result<(), Failure> {
    if scenes.is_empty() {
        return Err(Failure::Input("error: --auto: name the scene files to time (examples/*.json)".into()));
    }
    let mut rows = Vec::new();
    for path in scenes {
        let (scene, problem) = read_problem(path)?;
        let design = |problem: &Problem| -> (f64, DesignFile) {
            let t = Instant::now();
            let file = super::design_printed(problem, Start::Cold, pool);
            (t.elapsed().as_secs_f64(), file)
        };
        let quality = |file: &DesignFile| {
            let metrics = file.metrics.as_ref();
            (metrics.map(|m| m.cost), metrics.and_then(|m| m.worst_pose_error).map(|w| w.position_rel_d))
        };
        let (mut auto_seconds, mut family_seconds, mut ratios) = (Vec::new(), Vec::new(), Vec::new());
        let mut first = None;
        for _ in 0..repeat.max(1) {
            let (seconds_auto, auto) = design(&problem);
            let Some(family) = auto.mechanism.as_ref().map(|m| m.mechanism_type) else { break };
            let mut alone = scene.clone();
            alone.mechanism = MechanismChoice::Only(family);
            let alone_problem = Problem::new(&alone).expect("the scene was valid with auto");
            let (seconds_family, own) = design(&alone_problem);
            auto_seconds.push(seconds_auto);
            family_seconds.push(seconds_family);
            ratios.push(seconds_auto / seconds_family);
            first.get_or_insert((family, quality(&auto), quality(&own)));
        }
        let label = super::scene_label(path);
        let Some((family, (cost_auto, worst_auto_rel_d), (cost_family, worst_family_rel_d))) = first else {
            eprintln!("{label}: no design");
            continue;
        };
        let row = Row {
            scene: label,
            family: family.id(),
            seconds_auto: super::quantile(&mut auto_seconds, 0.5),
            seconds_family: super::quantile(&mut family_seconds, 0.5),
            ratio: super::quantile(&mut ratios, 0.5),
            cost_auto,
            cost_family,
            worst_auto_rel_d,
            worst_family_rel_d,
        };
        // Progress while the next scene runs; the table comes at the end (labels are escaped).
        eprintln!("{}: auto {:.2} s, {} alone {:.2} s", row.scene, row.seconds_auto, row.family, row.seconds_family);
        rows.push(row);
    }
    if json {
        println!("{}", serde_json::to_string_pretty(&rows).expect("rows serialize"));
        return Ok(());
    }
    let opt = |x: Option<f64>| x.map_or("-".to_string(), |x| format!("{x:.4}"));
    println!(
        "{:<28} {:<15} {:>8} {:>8} {:>6} {:>9} {:>9} {:>9} {:>9}",
        "scene", "family", "auto (s)", "alone (s)", "ratio", "cost", "alone", "worst (d)", "alone"
    );
    for r in &rows {
        println!(
            "{:<28} {:<15} {:>8.2} {:>8.2} {:>6.2} {:>9} {:>9} {:>9} {:>9}",
            r.scene,
            r.family,
            r.seconds_auto,
            r.seconds_family,
            r.ratio,
            opt(r.cost_auto),
            opt(r.cost_family),
            opt(r.worst_auto_rel_d),
            opt(r.worst_family_rel_d)
        );
    }
    let mut ratios: Vec<f64> = rows.iter().map(|r| r.ratio).collect();
    println!("median ratio {:.2}", super::quantile(&mut ratios, 0.5));
    Ok(())
}

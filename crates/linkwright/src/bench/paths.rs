//! `linkwright bench --paths`: how closely the designs' tracers follow drawn paths made from the
//! curves known linkages trace (four-bars' coupler curves and the curves of six-bars' bodies, so a
//! linkage tracing each exactly exists), closed and open, drawn with few and many points, exactly and
//! with noise. Distances come from each design file's independent
//! check (`DesignFile::violations` re-measures `metrics.path_error`).

use super::quantile;
use crate::failure::Failure;
use crate::files::{make_subfolder, write_below};
use linkwright_core::analysis::{Replay, Which};
use linkwright_core::geom::{nearest, Point};
use linkwright_core::testbed::{known_path_scene, published_path_scenes};
use linkwright_core::{synthesize, DesignFile, MechanismType, Problem, Silent, Status};
use serde::Serialize;
use std::path::Path;

/// The families whose curves are drawn.
const FAMILIES: [MechanismType; 3] = [MechanismType::Chain, MechanismType::StephensonThree, MechanismType::WattTwo];
/// Points of the drawn curves: from a few clicks to a smoothed freehand stroke.
const POINTS: [usize; 4] = [20, 50, 100, 200];
/// Noise on every point, as a fraction of the curve's size: none, and a careful hand's.
const NOISE: [f64; 2] = [0.0, 0.005];
/// Millimetres per unit of the testbed (its ground link).
const SCENE_SCALE: f64 = 100.0;

/// One known scene's result.
#[derive(Serialize, Debug)]
struct Row {
    /// The family of the known linkage that traced the curve.
    family: String,
    closed: bool,
    points: usize,
    noise: f64,
    scene_seed: u64,
    #[serde(flatten)]
    measured: Measured,
}

/// One published target's result.
#[derive(Serialize, Debug)]
struct PublishedRow {
    name: &'static str,
    source: &'static str,
    /// The family the scene allows (`auto`, or one family).
    mechanism: String,
    closed: bool,
    points: usize,
    /// The largest distance of a published point from the traced curve, as a fraction of the curve's
    /// size: the literature's measure without its prescribed timing (the measured `max_rel` also
    /// counts the traced curve's distance from the chords between the points).
    point_miss_rel: Option<f64>,
    #[serde(flatten)]
    measured: Measured,
}

/// A scene designed and its design checked.
#[derive(Serialize, Debug)]
struct Measured {
    /// The family of the design.
    designed_by: Option<String>,
    /// The engine returned a design and the independent check finds no violation.
    valid: bool,
    violations: Vec<String>,
    /// The traced curve's largest and mean distance from the drawn one, fractions of its size.
    max_rel: Option<f64>,
    mean_rel: Option<f64>,
    min_transmission_deg: Option<f64>,
    seconds: f64,
}

/// Statistics over one group of rows.
#[derive(Serialize, Debug)]
struct Summary {
    label: String,
    scenes: usize,
    valid: usize,
    median_max_rel: f64,
    worst_max_rel: f64,
    median_mean_rel: f64,
    median_seconds: f64,
    worst_seconds: f64,
}

#[derive(Serialize, Debug)]
struct Report {
    synthesis_seed: u64,
    threads: usize,
    rows: Vec<Row>,
    summaries: Vec<Summary>,
    published: Vec<PublishedRow>,
}

/// Designs `scene` under `seed` and checks the design, writing both below `save` as `stem` when
/// given; with the largest distance of a drawn point from the traced curve (a fraction of the
/// curve's size).
fn measure(
    scene: &linkwright_core::Scene,
    seed: u64,
    pool: &rayon::ThreadPool,
    save: Option<(&Path, &str)>,
) -> Result<(Measured, Option<f64>), Failure> {
    let mut problem = Problem::new(scene)
        .map_err(|issues| Failure::Input(format!("error: a testbed path scene does not validate: {issues:?}")))?;
    problem.settings.seed = seed;
    let outcome = pool.install(|| synthesize(&problem, &Silent)).expect("never cancelled");
    let design = DesignFile::from_outcome(&problem, &outcome);
    if let Some((dir, stem)) = save {
        write_below(dir, &format!("{stem}.json"), scene.to_json().as_bytes())?;
        write_below(dir, &format!("{stem}.design.json"), design.to_json().as_bytes())?;
    }
    let violations: Vec<String> =
        design.violations(&problem).into_iter().map(|v| format!("{}: {}", v.constraint, v.message)).collect();
    let metrics = design.metrics.as_ref();
    let error = metrics.and_then(|m| m.path_error);
    let point_miss =
        problem.path().zip(Replay::new(&problem, &design, Which::Best, 1440).ok()).map(|(path, replay)| {
            let traced: Vec<Point> = (0..replay.trace.len())
                .map(|r| replay.frames.pose(0, replay.trace.row(r)).apply(path.tracer))
                .collect();
            let miss = path.points.iter().map(|&p| nearest(p, &traced, false).0).fold(0.0, f64::max);
            miss / path.size
        });
    let measured = Measured {
        designed_by: design.mechanism.as_ref().map(|m| m.mechanism_type.linkage_label(1)),
        valid: design.status == Status::Ok && violations.is_empty(),
        violations,
        max_rel: error.map(|e| e.max_rel),
        mean_rel: error.map(|e| e.mean_rel),
        min_transmission_deg: metrics.map(|m| m.min_transmission_deg),
        seconds: design.stats.seconds.total,
    };
    Ok((measured, point_miss))
}

pub(super) fn bench_paths(
    quick: bool,
    seed: u64,
    save: Option<&Path>,
    pool: &rayon::ThreadPool,
    json: bool,
) -> Result<(), Failure> {
    if let Some(dir) = save {
        make_subfolder(dir, "")?;
    }
    let mut published = Vec::new();
    for (k, target) in published_path_scenes().into_iter().enumerate() {
        let path = target.scene.moving_bodies[0].path.as_ref().expect("a path scene");
        let stem = format!("published_{k}");
        let (measured, point_miss_rel) = measure(&target.scene, seed, pool, save.map(|dir| (dir, stem.as_str())))?;
        let row = PublishedRow {
            name: target.name,
            source: target.source,
            mechanism: match target.scene.mechanism {
                linkwright_core::MechanismChoice::Auto => "auto".to_string(),
                linkwright_core::MechanismChoice::Only(family) => family.id().to_string(),
            },
            closed: path.closed,
            points: path.points.len(),
            point_miss_rel,
            measured,
        };
        if !json {
            eprintln!("{}", published_line(&row));
        }
        published.push(row);
    }
    let scene_seeds: &[u64] = if quick { &[0] } else { &[0, 1, 2] };
    let mut rows = Vec::new();
    for family in FAMILIES {
        for closed in [true, false] {
            for points in POINTS {
                for noise in NOISE {
                    for &scene_seed in scene_seeds {
                        let known = known_path_scene(family, closed, points, noise, scene_seed, SCENE_SCALE)
                            .ok_or_else(|| {
                                Failure::Input(format!(
                                    "error: no known {} drawn from seed {scene_seed}",
                                    family.label()
                                ))
                            })?;
                        let stem = format!(
                            "{}_{}_{points}_noise{noise}_seed{scene_seed}",
                            family.id(),
                            if closed { "closed" } else { "open" }
                        );
                        let row = Row {
                            family: family.linkage_label(1),
                            closed,
                            points,
                            noise,
                            scene_seed,
                            measured: measure(&known.scene, seed, pool, save.map(|dir| (dir, stem.as_str())))?.0,
                        };
                        if !json {
                            eprintln!("{}", row_line(&row));
                        }
                        rows.push(row);
                    }
                }
            }
        }
    }
    let mut summaries = Vec::new();
    for family in FAMILIES {
        for (label, closed, noisy) in [
            ("closed, exact", true, false),
            ("closed, noisy", true, true),
            ("open, exact", false, false),
            ("open, noisy", false, true),
        ] {
            summaries.push(summarize(
                &format!("{}, {label}", family.linkage_label(1)),
                rows.iter()
                    .filter(|r| r.family == family.linkage_label(1) && r.closed == closed && (r.noise > 0.0) == noisy),
            ));
        }
    }
    summaries.push(summarize("exact", rows.iter().filter(|r| r.noise == 0.0)));
    summaries.push(summarize("all", rows.iter()));
    let report = Report { synthesis_seed: seed, threads: pool.current_num_threads(), rows, summaries, published };
    if json {
        println!("{}", serde_json::to_string_pretty(&report).expect("the report serializes"));
    } else {
        println!(
            "{:<38} {:>6} {:>6} {:>12} {:>11} {:>13} {:>10} {:>9}",
            "targets", "scenes", "valid", "median max", "worst max", "median mean", "median s", "worst s"
        );
        for s in &report.summaries {
            println!(
                "{:<38} {:>6} {:>6} {:>11.3}% {:>10.3}% {:>12.3}% {:>10.2} {:>9.2}",
                s.label,
                s.scenes,
                s.valid,
                100.0 * s.median_max_rel,
                100.0 * s.worst_max_rel,
                100.0 * s.median_mean_rel,
                s.median_seconds,
                s.worst_seconds
            );
        }
        println!("(distances as a percentage of the curve's size; seconds per design, {} threads)", report.threads);
        println!("\npublished targets:");
        for r in &report.published {
            println!("  {}", published_line(r));
        }
    }
    Ok(())
}

fn row_line(r: &Row) -> String {
    format!(
        "{} {:<6} {:>3} points, noise {:<5} seed {}: {}",
        r.family,
        if r.closed { "closed" } else { "open" },
        r.points,
        r.noise,
        r.scene_seed,
        measured_line(&r.measured)
    )
}

fn published_line(r: &PublishedRow) -> String {
    format!(
        "{} ({}; mechanism {}, {} points): every point within {} of the traced curve; {}",
        r.name,
        r.source,
        r.mechanism,
        r.points,
        r.point_miss_rel.map_or("-".to_string(), |x| format!("{:.3}%", 100.0 * x)),
        measured_line(&r.measured)
    )
}

fn measured_line(m: &Measured) -> String {
    let pct = |v: Option<f64>| v.map_or("-".to_string(), |x| format!("{:.3}%", 100.0 * x));
    format!(
        "{} {} max {} mean {} in {:.2} s{}",
        if m.valid { "valid" } else { "NO DESIGN" },
        m.designed_by.as_deref().unwrap_or("-"),
        pct(m.max_rel),
        pct(m.mean_rel),
        m.seconds,
        if m.violations.is_empty() { String::new() } else { format!(" ({})", m.violations.join("; ")) }
    )
}

fn summarize<'a>(label: &str, rows: impl Iterator<Item = &'a Row> + Clone) -> Summary {
    let mut max: Vec<f64> = rows.clone().filter_map(|r| r.measured.max_rel).collect();
    let mut mean: Vec<f64> = rows.clone().filter_map(|r| r.measured.mean_rel).collect();
    let mut seconds: Vec<f64> = rows.clone().map(|r| r.measured.seconds).collect();
    Summary {
        label: label.to_string(),
        scenes: rows.clone().count(),
        valid: rows.filter(|r| r.measured.valid).count(),
        median_max_rel: quantile(&mut max, 0.5),
        worst_max_rel: quantile(&mut max, 1.0),
        median_mean_rel: quantile(&mut mean, 0.5),
        median_seconds: quantile(&mut seconds, 0.5),
        worst_seconds: quantile(&mut seconds, 1.0),
    }
}

//! `linkwright bench --known`: how close the engine's designs come to the drawn poses, on scenes made
//! from known exact mechanisms (so a linkage hitting every pose exactly exists) and on the nine-pose
//! four-bar motion task of the literature. Errors come from replaying each design file against its
//! scene ([`analyze`]), independently of the engine's own cost terms.

use crate::failure::Failure;
use crate::files::{make_subfolder, write_below};
use linkwright_core::analysis::{analyze, AnalysisOptions, MotionAnalysis, Which};
use linkwright_core::testbed::{known_scene, Course, Known};
use linkwright_core::{synthesize, DesignFile, MechanismType, Problem, Scene, Silent, Status};

use serde::Serialize;
use std::path::Path;

/// The nine-pose four-bar task (see the fixture's README for its source).
const NINE_POSE: &str = include_str!("../../../linkwright-core/tests/fixtures/nine_pose_four_bar.json");
/// four-bar-rs's result on it with its default settings: largest position error (scene units) and
/// largest angle error (degrees).
const FOUR_BAR_RS: (f64, f64) = (0.47, 7.4);
/// Testbed scenes are drawn with body centres 1.2 units apart; at this scale (millimetres) that is
/// 120 mm, the size of the bundled example objects.
const SCENE_SCALE: f64 = 100.0;

/// Families and pose counts: every pose count up to where a chain of that many bodies still has few
/// enough poses to be matched in reasonable time.
fn grid(quick: bool) -> (Vec<(Known, Vec<usize>)>, Vec<u64>) {
    if quick {
        let grid = vec![
            (Known::chain(1), vec![2, 5, 9]),
            (Known::chain(2), vec![2, 4]),
            (Known::chain(3), vec![3]),
            (Known::chain(4), vec![2]),
            (Known::chain(6), vec![2]),
            (Known::one(MechanismType::SliderCrank), vec![2, 4]),
            (Known::one(MechanismType::WattTwo), vec![3, 7]),
            (Known::watt_two_out_and_back(), vec![4, 7]),
            (Known::one(MechanismType::StephensonThree), vec![3, 7]),
        ];
        return (grid, vec![0]);
    }
    let grid = vec![
        (Known::chain(1), (2..=10).collect()),
        (Known::chain(2), (2..=6).collect()),
        (Known::chain(3), (2..=4).collect()),
        (Known::chain(4), (2..=3).collect()),
        (Known::chain(5), (2..=3).collect()),
        (Known::chain(6), (2..=3).collect()),
        (Known::one(MechanismType::SliderCrank), (2..=5).collect()),
        (Known::one(MechanismType::WattTwo), (2..=10).collect()),
        (Known::watt_two_out_and_back(), (3..=10).collect()),
        (Known::one(MechanismType::StephensonThree), (2..=10).collect()),
    ];
    (grid, vec![0, 1, 2])
}

/// One scene's result.
#[derive(Serialize, Debug)]
struct Row {
    family: &'static str,
    label: String,
    bodies: usize,
    poses: usize,
    /// The seed the scene was drawn from (the synthesis seed is the run's).
    scene_seed: u64,
    /// The engine returned a design and the independent check finds no violation.
    valid: bool,
    status: Status,
    violations: Vec<String>,
    /// Largest outline-vertex distance over every pose and body, as a fraction of that body's d.
    worst_position: Option<f64>,
    /// Largest angle error over every pose and body, degrees.
    worst_angle_deg: Option<f64>,
    /// The same at the last pose only.
    last_position: Option<f64>,
    last_angle_deg: Option<f64>,
    cost: Option<f64>,
    /// The known linkage's cost under the same weights (paper eq. 14).
    known_cost: f64,
    /// Mean link length over the smallest body size d.
    mean_link_over_d: Option<f64>,
    /// The design's smallest transmission angle along its travel, and the known linkage's, degrees.
    min_transmission_deg: Option<f64>,
    known_min_transmission_deg: f64,
    seconds: f64,
}

/// Per family, and over everything: statistics over the designs returned.
#[derive(Serialize, Debug)]
struct Summary {
    label: String,
    scenes: usize,
    valid: usize,
    designs: usize,
    median_worst_position: Option<f64>,
    max_worst_position: Option<f64>,
    median_worst_angle_deg: Option<f64>,
    max_worst_angle_deg: Option<f64>,
    max_last_position: Option<f64>,
    max_last_angle_deg: Option<f64>,
    /// The median of the designs' smallest transmission angles, degrees.
    median_min_transmission_deg: Option<f64>,
    seconds: f64,
}

/// The nine-pose task's result.
#[derive(Serialize, Debug)]
struct NinePose {
    valid: bool,
    status: Status,
    /// Largest distance of the coupler point (the pose position) from its target, scene units.
    max_position_error: Option<f64>,
    /// Largest angle error, degrees.
    max_angle_error_deg: Option<f64>,
    /// Largest outline-vertex distance as a fraction of the body size d.
    worst_position: Option<f64>,
    cost: Option<f64>,
    seconds: f64,
    four_bar_rs_position_error: f64,
    four_bar_rs_angle_error_deg: f64,
}

#[derive(Serialize, Debug)]
struct Report {
    synthesis_seed: u64,
    threads: usize,
    rows: Vec<Row>,
    families: Vec<Summary>,
    overall: Summary,
    nine_pose: NinePose,
}

/// Largest (position / d, |angle|) over the given poses and every body.
fn pose_errors(problem: &Problem, analysis: &MotionAnalysis, poses: std::ops::Range<usize>) -> (f64, f64) {
    let mut worst = (0.0f64, 0.0f64);
    for pose in &analysis.poses[poses] {
        for (b, e) in pose.bodies.iter().enumerate() {
            worst.0 = worst.0.max(e.max_vertex / problem.bodies[b].size);
            worst.1 = worst.1.max(e.angle_deg.abs());
        }
    }
    worst
}

/// Synthesises `problem` with `seed`; the design and whether it passes the independent check.
fn run(problem: &Problem, pool: &rayon::ThreadPool) -> (DesignFile, Vec<String>) {
    let outcome = pool.install(|| synthesize(problem, &Silent)).expect("never cancelled");
    let design = DesignFile::from_outcome(problem, &outcome);
    let violations =
        design.violations(problem).into_iter().map(|v| format!("{}: {}", v.constraint, v.message)).collect();
    (design, violations)
}

pub(super) fn bench_known(
    quick: bool,
    seed: u64,
    save: Option<&Path>,
    pool: &rayon::ThreadPool,
    json: bool,
) -> Result<(), Failure> {
    if let Some(dir) = save {
        make_subfolder(dir, "")?;
    }
    let (grid, scene_seeds) = grid(quick);
    let mut rows = Vec::new();
    for &(kind, ref counts) in &grid {
        for &scene_seed in &scene_seeds {
            for &poses in counts {
                let known = known_scene(kind, poses, scene_seed, SCENE_SCALE)
                    .map_err(|e| Failure::Input(format!("error: {kind}, {poses} poses, seed {scene_seed}: {e}")))?;
                let mut problem = Problem::new(&known.scene).map_err(|issues| {
                    Failure::Input(format!("error: a testbed scene does not validate: {issues:?}"))
                })?;
                problem.settings.seed = seed;
                let (design, violations) = run(&problem, pool);
                if let Some(dir) = save {
                    let name = match kind.course() {
                        Course::OneWay => kind.mechanism_type().id(),
                        Course::OutAndBack => "watt_two_out_and_back",
                    };
                    let stem = format!("{name}_k{}_n{poses}_seed{scene_seed}", kind.bodies());
                    write_below(dir, &format!("{stem}.json"), known.scene.to_json().as_bytes())?;
                    write_below(dir, &format!("{stem}.design.json"), design.to_json().as_bytes())?;
                }
                let analysis = analyze(&problem, &design, Which::Best, &AnalysisOptions::default()).ok();
                let n = problem.pose_count;
                let worst = analysis.as_ref().map(|a| pose_errors(&problem, a, 0..n));
                let last = analysis.as_ref().map(|a| pose_errors(&problem, a, n - 1..n));
                let d = problem.bodies.iter().map(|b| b.size).fold(f64::INFINITY, f64::min);
                let row = Row {
                    family: kind.mechanism_type().id(),
                    label: kind.to_string(),
                    bodies: kind.bodies(),
                    poses,
                    scene_seed,
                    valid: design.status == Status::Ok && violations.is_empty(),
                    status: design.status,
                    violations,
                    worst_position: worst.map(|w| w.0),
                    worst_angle_deg: worst.map(|w| w.1),
                    last_position: last.map(|w| w.0),
                    last_angle_deg: last.map(|w| w.1),
                    cost: design.metrics.as_ref().map(|m| m.cost),
                    known_cost: known.metrics.cost,
                    mean_link_over_d: design.metrics.as_ref().map(|m| m.size / d),
                    min_transmission_deg: design.metrics.as_ref().map(|m| m.min_transmission_deg),
                    known_min_transmission_deg: known.metrics.min_transmission_deg,
                    seconds: design.stats.seconds.total,
                };
                if !json {
                    eprintln!("{}", row_line(&row));
                }
                rows.push(row);
            }
        }
    }
    let families: Vec<Summary> = grid
        .iter()
        .map(|(kind, _)| summarize(kind.to_string(), rows.iter().filter(|r| r.label == kind.to_string())))
        .collect();
    let overall = summarize("all".to_string(), rows.iter());
    let nine_pose = nine_pose(seed, pool)?;
    let report =
        Report { synthesis_seed: seed, threads: pool.current_num_threads(), rows, families, overall, nine_pose };
    if json {
        println!("{}", serde_json::to_string_pretty(&report).expect("the report serializes"));
    } else {
        print!("{}", table(&report));
    }
    Ok(())
}

fn nine_pose(seed: u64, pool: &rayon::ThreadPool) -> Result<NinePose, Failure> {
    let scene = Scene::from_json(NINE_POSE).map_err(|e| Failure::Input(format!("error: nine-pose task: {e}")))?;
    let mut problem = Problem::new(&scene)
        .map_err(|issues| Failure::Input(format!("error: the nine-pose task does not validate: {issues:?}")))?;
    problem.settings.seed = seed;
    let (design, violations) = run(&problem, pool);
    let analysis = analyze(&problem, &design, Which::Best, &AnalysisOptions::default()).ok();
    // The coupler point is the body frame's origin: where the design puts it at each pose's frame.
    let position = analysis.as_ref().map(|a| {
        a.poses
            .iter()
            .map(|p| {
                let [x, y, _] = a.frames[p.frame].bodies[0];
                let target = problem.bodies[0].poses[p.pose].translation();
                (x - target.x).hypot(y - target.y)
            })
            .fold(0.0, f64::max)
    });
    let worst = analysis.as_ref().map(|a| pose_errors(&problem, a, 0..problem.pose_count));
    Ok(NinePose {
        valid: design.status == Status::Ok && violations.is_empty(),
        status: design.status,
        max_position_error: position,
        max_angle_error_deg: worst.map(|w| w.1),
        worst_position: worst.map(|w| w.0),
        cost: design.metrics.as_ref().map(|m| m.cost),
        seconds: design.stats.seconds.total,
        four_bar_rs_position_error: FOUR_BAR_RS.0,
        four_bar_rs_angle_error_deg: FOUR_BAR_RS.1,
    })
}

fn median(mut v: Vec<f64>) -> Option<f64> {
    if v.is_empty() {
        return None;
    }
    v.sort_by(f64::total_cmp);
    let m = v.len() / 2;
    Some(if v.len() % 2 == 1 { v[m] } else { 0.5 * (v[m - 1] + v[m]) })
}

fn max(v: impl Iterator<Item = f64>) -> Option<f64> {
    v.reduce(f64::max)
}

fn summarize<'a>(label: String, rows: impl Iterator<Item = &'a Row> + Clone) -> Summary {
    let worst_position: Vec<f64> = rows.clone().filter_map(|r| r.worst_position).collect();
    let worst_angle: Vec<f64> = rows.clone().filter_map(|r| r.worst_angle_deg).collect();
    Summary {
        label,
        scenes: rows.clone().count(),
        valid: rows.clone().filter(|r| r.valid).count(),
        designs: worst_position.len(),
        median_worst_position: median(worst_position.clone()),
        max_worst_position: max(worst_position.into_iter()),
        median_worst_angle_deg: median(worst_angle.clone()),
        max_worst_angle_deg: max(worst_angle.into_iter()),
        max_last_position: max(rows.clone().filter_map(|r| r.last_position)),
        max_last_angle_deg: max(rows.clone().filter_map(|r| r.last_angle_deg)),
        median_min_transmission_deg: median(rows.clone().filter_map(|r| r.min_transmission_deg).collect()),
        seconds: rows.map(|r| r.seconds).sum(),
    }
}

fn opt(v: Option<f64>, digits: usize) -> String {
    v.map_or("-".to_string(), |x| format!("{x:.digits$}"))
}

const ROW_HEADER: &str =
    "family          K  N seed valid  worst/d worst°   last/d  last°      cost  known  link/d   μ°  known μ°  seconds";

fn row_line(r: &Row) -> String {
    format!(
        "{:<14} {:>2} {:>2} {:>4} {:>5} {:>8} {:>6} {:>8} {:>6} {:>9} {:>6.2} {:>7} {:>4} {:>9.0} {:>8.3}",
        r.family,
        r.bodies,
        r.poses,
        r.scene_seed,
        if r.valid { "yes" } else { "no" },
        opt(r.worst_position, 3),
        opt(r.worst_angle_deg, 1),
        opt(r.last_position, 3),
        opt(r.last_angle_deg, 1),
        opt(r.cost, 2),
        r.known_cost,
        opt(r.mean_link_over_d, 2),
        opt(r.min_transmission_deg, 0),
        r.known_min_transmission_deg,
        r.seconds
    )
}

fn table(report: &Report) -> String {
    let mut out = format!(
        "known mechanisms, synthesis seed {}, {} thread(s). Errors per pose and body: position = largest \
         outline-vertex distance / the body's d, angle in degrees; worst = over all poses, last = the last pose; \
         known = the exact linkage's cost, μ° = the smallest transmission angle\n{ROW_HEADER}\n",
        report.synthesis_seed, report.threads
    );
    for r in &report.rows {
        out.push_str(&row_line(r));
        out.push('\n');
    }
    out.push_str(&format!(
        "\n{:<14} {:>7} {:>10} {:>10} {:>10} {:>10} {:>10} {:>10} {:>6} {:>8}\n",
        "family",
        "valid",
        "med worst/d",
        "max worst/d",
        "med worst°",
        "max worst°",
        "max last/d",
        "max last°",
        "med μ°",
        "seconds"
    ));
    for s in report.families.iter().chain(std::iter::once(&report.overall)) {
        out.push_str(&format!(
            "{:<14} {:>7} {:>10} {:>10} {:>10} {:>10} {:>10} {:>10} {:>6} {:>8.2}\n",
            s.label,
            format!("{}/{}", s.valid, s.scenes),
            opt(s.median_worst_position, 3),
            opt(s.max_worst_position, 3),
            opt(s.median_worst_angle_deg, 1),
            opt(s.max_worst_angle_deg, 1),
            opt(s.max_last_position, 3),
            opt(s.max_last_angle_deg, 1),
            opt(s.median_min_transmission_deg, 1),
            s.seconds
        ));
    }
    let n = &report.nine_pose;
    out.push_str(&format!(
        "\nnine-pose four-bar task (Hsieh 2017): valid {}, largest position error {} (four-bar-rs {}), \
         largest angle error {}° (four-bar-rs {}°), worst/d {}, cost {}, {:.3} s\n",
        if n.valid { "yes" } else { "no" },
        opt(n.max_position_error, 3),
        n.four_bar_rs_position_error,
        opt(n.max_angle_error_deg, 1),
        n.four_bar_rs_angle_error_deg,
        opt(n.worst_position, 3),
        opt(n.cost, 2),
        n.seconds
    ));
    out
}

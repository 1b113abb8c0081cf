//! The subcommands.

use crate::failure::Failure;
use crate::files::{
    existing_subfolder, make_subfolder, read_design, read_problem, read_problem_with, read_valid_design, remove_below,
    remove_folder_if_empty, write_below,
};
use crate::terminal::{escaped, say, warn};
use clap::Args;
use indicatif::{ProgressBar, ProgressStyle};
use linkwright_core::analysis::{AnalysisOptions, Replay, Which};
use linkwright_core::balance::{Balanced, SpringNeed};
use linkwright_core::fab::BuildPlan;
use linkwright_core::kinematics::{Plan, Trace};
use linkwright_core::{
    animation_svg, design_svg, missed_exact_point, pose_misses, synthesize_with, Build, DesignFile, Observer, Options,
    Outcome, PathError, PoseMiss, Problem, Progress, RenderInput, Stage, Start, Status, DESIGN_FORMAT,
};
use std::path::{Path, PathBuf};

#[derive(Args, Debug)]
pub(crate) struct DesignArgs {
    /// The scene file (scene/1).
    scene: PathBuf,
    /// Output directory (created if needed). Default: the scene file's name without .json, under out/ (out/k1_table for k1_table.json).
    #[arg(short, long)]
    output: Option<PathBuf>,
    /// Seed of the random search (overrides the scene's settings.seed).
    #[arg(long)]
    seed: Option<u64>,
    /// Number of candidate samples (overrides the scene's settings.samples).
    #[arg(long, value_parser = crate::sample_count())]
    samples: Option<usize>,
    /// Worker threads (default: all cores). The result does not depend on it.
    #[arg(long, value_parser = crate::thread_count())]
    threads: Option<usize>,
    /// Print the design JSON on stdout instead of the summary line.
    #[arg(long)]
    json: bool,
    /// Warm start from a previous design of this scene with a solution (after small edits, e.g. a moved pose): its
    /// design and alternatives seed the search, which then takes a fraction of the time.
    #[arg(long, value_name = "PREVIOUS.json")]
    from: Option<PathBuf>,
    /// After a successful design, also fabricate it into the output directory's fabrication/ (as `fabricate` does).
    #[arg(long)]
    fabricate: bool,
    /// Print settings the design must be printable with, and --fabricate uses (JSON, millimetres;
    /// missing fields keep their defaults).
    #[arg(long, value_name = "PRINT.json", conflicts_with = "no_print_check")]
    print_settings: Option<PathBuf>,
    /// Accept designs that cannot be printed (joints too close for pins, no depth ordering of the
    /// links): the paper's synthesis alone, for designs built some other way.
    #[arg(long, conflicts_with_all = ["fabricate", "build"])]
    no_print_check: bool,
    /// How the object is built (overrides the scene's `build`): model:auto (a printed model, at 1:1
    /// when it fits the bed, else at the largest scale that does: the default), model:1:10 (a printed model at that scale:
    /// the design must print at it), or full:plywood, full:aluminium, full:steel (full size, cut in a
    /// workshop: no print check).
    #[arg(long, value_name = "BUILD", value_parser = crate::build_choice())]
    build: Option<Build>,
}

/// Shows progress as a bar on stderr (hidden when stderr is not a terminal), naming the linkage
/// searched for the scene's number of moving bodies.
struct Bar {
    bar: ProgressBar,
    bodies: usize,
}

impl Observer for Bar {
    fn progress(&self, p: &Progress) {
        let stage = match p.stage {
            Stage::Sampling => "sampling",
            Stage::Collision => "collision check",
            Stage::Refining => "refining",
        };
        let best = p.best_cost.map_or(String::new(), |c| format!(", best cost {c:.3}"));
        self.bar.set_position((p.fraction * 1000.0) as u64);
        self.bar.set_message(format!("{}: {stage}{best}", p.mechanism.linkage_label(self.bodies)));
    }
}

pub(crate) fn design(args: DesignArgs) -> Result<(), Failure> {
    // The command line's settings are part of the scene that is validated (its limits bound the work).
    let (_, problem) = read_problem_with(&args.scene, |scene| {
        if let Some(seed) = args.seed {
            scene.settings.seed = seed;
        }
        if let Some(samples) = args.samples {
            scene.settings.samples = samples;
        }
        if let Some(build) = args.build {
            scene.build = build;
        }
    })?;
    let print_settings = crate::fabricate::read_settings(args.print_settings.as_deref())?;
    let plan = if args.no_print_check {
        None
    } else {
        let plan = BuildPlan::new(&problem, &print_settings);
        for note in &plan.notes {
            warn(&format!("warning: {} (--build {} now)", escaped(&note.to_string()), plan.asked));
        }
        Some(plan)
    };
    let out_dir = args.output.clone().unwrap_or_else(|| {
        Path::new("out").join(args.scene.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default())
    });
    if out_dir.exists() && !out_dir.is_dir() {
        return Err(Failure::Input(format!("error: -o {}: exists and is not a directory", out_dir.display())));
    }
    let threads = args.threads.unwrap_or(0);
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .map_err(|e| Failure::Input(format!("error: --threads: {e}")))?;

    let bar = ProgressBar::new(1000);
    bar.set_style(
        ProgressStyle::with_template("{spinner} [{elapsed_precise}] {bar:30} {percent:>3}% {msg}")
            .expect("a valid template"),
    );
    let observer = Bar { bar, bodies: problem.body_count() };
    let previous = match &args.from {
        Some(path) => previous_mechanisms(path)?,
        None => Vec::new(),
    };
    let start = if previous.is_empty() { Start::Cold } else { Start::Warm(&previous) };
    let options = Options { start, printable: None };
    let (plan, outcome) = pool
        .install(|| match plan {
            Some(plan) => plan.synthesize(&problem, &print_settings, &options, &observer).map(|(p, o)| (Some(p), o)),
            None => synthesize_with(&problem, &options, &observer).map(|o| (None, o)),
        })
        .expect("the CLI never cancels");
    observer.bar.finish_and_clear();

    make_subfolder(&out_dir, "")?;
    remove_earlier_outputs(&out_dir, outcome.best.is_none())?;
    let (file, json) = write_outputs(&problem, &outcome, plan.as_ref(), &out_dir)?;
    if args.json {
        println!("{json}");
    } else {
        say(&summary(&file, &problem, &out_dir));
    }
    // The library says what would help; the remedy only this command has is its own.
    if let Some(far) = file.metrics.as_ref().and_then(|m| m.far_from_pose.as_ref()) {
        warn(&format!(
            "hint: pose {} of {} is far from where the linkage takes the body: draw a pose between it and its \
             neighbours, move it closer to the way the others go, or try another --seed or mechanism",
            far.pose, far.body
        ));
    }
    if let Some(missed) = file.metrics.as_ref().and_then(|m| m.path_error.as_ref()).and_then(missed_exact_point) {
        warn(&format!(
            "hint: no linkage found passes exact point {} of the path: mark fewer points exact (a four-bar passes \
             at most nine), move it nearer the curve, or try another --seed or mechanism",
            missed.point
        ));
    }
    if outcome.unbuildable {
        eprintln!(
            "hint: --build model:1:N prints the model at another scale, --build full:plywood builds it full size"
        );
    } else if outcome.best.is_none() && plan.as_ref().is_some_and(|p| !p.notes.is_empty()) {
        eprintln!("hint: --build model:auto picks a scale that suits the drawing");
    }
    if args.fabricate {
        if outcome.best.is_some() {
            let fabrication = make_subfolder(&out_dir, "fabrication")?;
            let line = crate::fabricate::run(&problem, &file, &print_settings, false, &fabrication)?;
            // Keep stdout the design JSON alone with --json.
            if args.json {
                warn(&line);
            } else {
                say(&line);
            }
        } else {
            eprintln!("no design to fabricate");
        }
    }
    Ok(())
}

/// Removes what an earlier run derived from its design, so the folder never mixes two runs: its
/// fabrication (rebuilt only if asked, after the new design is written), and its pictures when the
/// new run has none to replace them with.
fn remove_earlier_outputs(out_dir: &Path, no_design: bool) -> Result<(), Failure> {
    if let Some(fabrication) = existing_subfolder(out_dir, "fabrication")? {
        crate::fabricate::remove_previous(&fabrication)?;
        remove_folder_if_empty(out_dir, "fabrication")?;
    }
    if no_design {
        for picture in ["design.svg", "animation.svg"] {
            remove_below(out_dir, picture)?;
        }
    }
    Ok(())
}

/// Builds and writes design.json, and with a design design.svg and animation.svg. The three files
/// are independent, so each is built and written (its flush to disk included) on its own thread: the
/// run waits for the slowest file rather than for all three in turn, and the disk's flushes overlap.
/// On failure, the message is the first file's in that order.
fn write_outputs(
    problem: &Problem,
    outcome: &Outcome,
    plan: Option<&BuildPlan>,
    out_dir: &Path,
) -> Result<(DesignFile, String), Failure> {
    std::thread::scope(|s| {
        let pictures = outcome.best.as_ref().map(|best| {
            let input =
                RenderInput { problem, mechanism: &best.mechanism, trace: &best.trace, pose_steps: &best.pose_rows };
            let animation =
                s.spawn(move || write_below(out_dir, "animation.svg", animation_svg(&input, 3.0).as_bytes()));
            let design = s.spawn(move || write_below(out_dir, "design.svg", design_svg(&input).as_bytes()));
            (design, animation)
        });
        let file = match plan {
            Some(plan) => plan.design_file(problem, outcome),
            None => DesignFile::from_outcome(problem, outcome),
        };
        let json = file.to_json();
        let written = write_below(out_dir, "design.json", json.as_bytes());
        let pictures = pictures.map(|(design, animation)| (joined(design), joined(animation)));
        written?;
        if let Some((design, animation)) = pictures {
            design?;
            animation?;
        }
        Ok((file, json))
    })
}

/// A writer thread's result; a panic in it carries on in this thread.
fn joined(handle: std::thread::ScopedJoinHandle<'_, Result<(), Failure>>) -> Result<(), Failure> {
    handle.join().unwrap_or_else(|panic| std::panic::resume_unwind(panic))
}

/// The mechanisms of a previous design file (its design and alternatives), for a warm start.
fn previous_mechanisms(path: &Path) -> Result<Vec<linkwright_core::Mechanism>, Failure> {
    let file = read_design(path)?;
    let needs = format!(
        "--from needs a design of this scene with a solution (format \"{DESIGN_FORMAT}\", status \"ok\"), such as \
         the design.json of an earlier run; leave out --from to start from scratch"
    );
    if file.linkwright != DESIGN_FORMAT {
        return Err(Failure::Input(format!(
            "error: --from {}: is a \"{}\" file, which this version does not read; {needs}",
            path.display(),
            file.linkwright
        )));
    }
    if file.status != Status::Ok {
        return Err(Failure::Input(format!(
            "error: --from {}: holds no design (status \"no_solution\"); {needs}",
            path.display()
        )));
    }
    let mechanisms = file.usable_mechanisms();
    if mechanisms.is_empty() {
        warn(&format!("warning: --from {}: has no usable mechanism; starting from scratch", path.display()));
    }
    Ok(mechanisms)
}

fn summary(file: &DesignFile, problem: &Problem, out_dir: &Path) -> String {
    let (s, units) = (&file.stats, &problem.units);
    let counts = format!("{} valid of {} samples, {:.2} s, seed {}", s.valid, s.samples, s.seconds.total, s.seed);
    match (&file.status, &file.mechanism, &file.metrics) {
        (Status::Ok, Some(m), Some(x)) => format!(
            "{}: {} with {} joints{}{}; cost {:.3} (accuracy {:.4}, smoothness {:.3}, location {:.3}, size {:.2}, \
             transmission {:.3}), {}; {counts} -> {}",
            file.scene,
            kind_name(m),
            m.joints.len(),
            match &x.far_from_pose {
                Some(far) => format!(
                    ", FAR FROM POSE {} of {}: misses it by {:.3} {units} ({:.0}% of its size) and {:.1}°, and no \
                     linkage closer was found",
                    far.pose,
                    far.body,
                    far.miss.position,
                    100.0 * far.miss.position_rel_d,
                    far.miss.angle_deg
                ),
                None => match &x.path_error {
                    Some(error) => path_reach(problem, error, &x.pose_errors),
                    None => pose_reach(problem, &x.pose_errors),
                },
            },
            file.build.as_ref().map_or(String::new(), build_words),
            x.cost,
            x.accuracy,
            x.smoothness,
            x.location,
            x.size,
            x.transmission,
            transmission_words(x.min_transmission_deg, travel_share(file, x.min_transmission_crank_deg), problem),
            out_dir.display()
        ),
        _ => format!(
            "{}: no solution. {} ({counts}) -> {}",
            file.scene,
            file.reason.as_deref().unwrap_or(""),
            out_dir.join("design.json").display()
        ),
    }
}

/// How the design is built, for the summary: "; a printed model at 1:5, 430 × 470 mm".
fn build_words(record: &linkwright_core::BuildRecord) -> String {
    let how = match record.checked {
        Build::Full(material) => format!("full size, {}", material.id()),
        _ => {
            let size = record.model_mm.map_or(String::new(), |[w, h]| format!(", {w:.0} × {h:.0} mm"));
            format!("a printed model at {}{size}", record.checked.to_string().trim_start_matches("model:"))
        }
    };
    match &record.reason {
        Some(reason) if !record.buildable => format!("; NOT buildable as {how}: {reason}"),
        _ => format!("; {how}"),
    }
}

/// The smallest transmission angle in words: where along the travel (a share of it, 0 at the first
/// pose), and whether it is under the scene's comfortable angle.
fn transmission_words(min_deg: f64, at: Option<f64>, problem: &Problem) -> String {
    let comfortable = problem.settings.comfortable_transmission_deg;
    let at = at.map_or(String::new(), |share| format!(" at {:.0}% of the travel", 100.0 * share));
    if min_deg < comfortable {
        format!("min transmission {min_deg:.1}°{at}, under the comfortable {comfortable}°")
    } else {
        format!("min transmission {min_deg:.1}°{at}")
    }
}

/// How far along the design's travel (0 at its first pose, 1 at its last) the crank angle `crank_deg` is.
fn travel_share(file: &DesignFile, crank_deg: Option<f64>) -> Option<f64> {
    let (motion, crank) = (file.motion.as_ref()?, crank_deg?);
    let span = motion.crank_end_deg - motion.crank_start_deg;
    (span.abs() > 0.0).then(|| ((crank - motion.crank_start_deg) / span).clamp(0.0, 1.0))
}

fn kind_name(m: &linkwright_core::MechanismJson) -> String {
    let bodies = m.parts.iter().filter(|p| p.body.is_some()).count();
    m.mechanism_type.linkage_label(bodies)
}

pub(crate) fn check(scene: &Path, design: &Path, json: bool) -> Result<(), Failure> {
    let (_, problem) = read_problem(scene)?;
    let file = read_valid_design(design, &problem)?;
    let violations = file.violations(&problem);
    if json {
        println!("{}", serde_json::to_string_pretty(&violations).expect("violations serialize"));
    } else if violations.is_empty() {
        let reach = match Replay::new(&problem, &file, Which::Best, AnalysisOptions::default().steps) {
            Ok(r) => {
                let misses = pose_misses(&problem, &r.mechanism, &r.trace, &r.pose_rows);
                let (row, sine) = r.trace.least_transmission(&r.plan);
                let at = travel_share(&file, Some(r.trace.thetas[row].to_degrees()));
                let words = transmission_words(sine.asin().to_degrees(), at, &problem);
                let reach = match file.metrics.as_ref().and_then(|m| m.path_error) {
                    Some(error) => path_reach(&problem, &error, &misses),
                    None => pose_reach(&problem, &misses),
                };
                format!("{reach}; {words}")
            }
            Err(_) => String::new(),
        };
        say(&format!("{}: every hard constraint holds{reach}", design.display()));
    } else {
        for v in &violations {
            say(&escaped(&format!("{}: {}", v.constraint, v.message)));
        }
    }
    if violations.is_empty() {
        Ok(())
    } else {
        Err(Failure::Violations)
    }
}

/// Most crank steps `simulate` prints: a row per 0.02° of the longest travel a design may have, a few
/// megabytes of text for the usual linkages.
const MAX_SIMULATE_STEPS: usize = 20_000;

pub(crate) fn simulate(scene: &Path, design: &Path, steps: usize) -> Result<(), Failure> {
    if steps > MAX_SIMULATE_STEPS {
        return Err(Failure::Input(format!(
            "error: --steps: {steps} is more than {MAX_SIMULATE_STEPS}; ask for fewer"
        )));
    }
    let (_, problem) = read_problem(scene)?;
    let file = read_valid_design(design, &problem)?;
    let (Some(mj), Some(motion)) = (&file.mechanism, &file.motion) else {
        return Err(Failure::Input(format!("error: {}: has no mechanism (status no_solution)", design.display())));
    };
    let mechanism = mj.to_mechanism().map_err(|e| Failure::Input(format!("error: {}: {e}", design.display())))?;
    let plan = Plan::compile(&mechanism).map_err(|e| Failure::Input(format!("error: {}: {e}", design.display())))?;
    let steps = steps.max(1);
    let mut trace = Trace::new(plan.joint_count());
    let mut out = String::from("step,crank_deg");
    for name in &mechanism.topology.joint_names {
        out.push_str(&format!(",{},{}", csv_field(&format!("{name}_x")), csv_field(&format!("{name}_y"))));
    }
    out.push('\n');
    for s in 0..=steps {
        let deg = motion.crank_start_deg + (motion.crank_end_deg - motion.crank_start_deg) * s as f64 / steps as f64;
        trace.push(&plan, deg.to_radians()).map_err(|e| Failure::Input(format!("error: {}: {e}", design.display())))?;
        out.push_str(&format!("{s},{deg}"));
        for p in trace.row(trace.len() - 1) {
            out.push_str(&format!(",{},{}", p.x, p.y));
        }
        out.push('\n');
    }
    print!("{}", crate::terminal::lines(&out));
    Ok(())
}

/// `analyze`: the torque the crank needs along the design's motion, and the springs that balance it,
/// as a table or JSON.
pub(crate) fn analyze(
    scene: &Path,
    design: &Path,
    json: bool,
    print_settings: Option<&Path>,
    build: Option<Build>,
) -> Result<(), Failure> {
    let (_, mut problem) = read_problem(scene)?;
    if let Some(build) = build {
        problem.build = build;
    }
    let file = read_valid_design(design, &problem)?;
    let settings = crate::fabricate::read_settings(print_settings)?;
    let (torque, balance) = crate::springs::counterbalanced(
        (&scene.display().to_string(), &problem),
        (&design.display().to_string(), &file),
        &settings,
    )?;
    if json {
        let balanced = Balanced { torque: &torque, balance: &balance };
        println!("{}", serde_json::to_string_pretty(&balanced).expect("the torque serializes"));
        return Ok(());
    }
    // A printed model needs thousandths of a newton-metre: its torque reads better in N·mm.
    let (unit, factor) = if torque.peak_nm < 1.0 { ("N·mm", 1000.0) } else { ("N·m", 1.0) };
    let springs = !balance.springs.is_empty();
    let mut out = format!("{:>10}  {:>16}", "crank (°)", format!("torque ({unit})"));
    if springs {
        out.push_str(&format!("  {:>16}", "with springs"));
    }
    out.push('\n');
    let rows = torque.crank_deg.len();
    // About twenty rows of the table, always with the first and the last.
    let every = rows.div_ceil(20).max(1);
    for k in (0..rows).filter(|k| k % every == 0 || k + 1 == rows) {
        out.push_str(&format!("{:>10.1}  {:>16.3}", torque.crank_deg[k], torque.torque_nm[k] * factor));
        if springs {
            out.push_str(&format!("  {:>16.3}", balance.torque_with_springs_nm[k] * factor));
        }
        out.push('\n');
    }
    out.push_str(&format!(
        "peak {:.3} {unit} at crank {:.1}° (positive: the crank lifts the parts as it advances)\nparts:\n",
        torque.peak_nm * factor,
        torque.peak_crank_deg
    ));
    for part in &torque.parts {
        out.push_str(&format!("  {:<10} {:>9.4} kg\n", part.name, part.mass_kg));
    }
    if springs {
        out.push_str("counterbalance:\n");
        for spring in &balance.springs {
            out.push_str(&format!("  {}\n", crate::springs::spring_words(spring, &problem.units)));
        }
        let cut = balance.peak_lowered_percent(&torque);
        out.push_str(&format!(
            "peak with the springs {:.3} {unit} at crank {:.1}° ({cut:.0}% lower)\n",
            balance.peak_with_springs_nm * factor,
            balance.peak_with_springs_crank_deg
        ));
    } else if balance.need == SpringNeed::NotNeeded {
        out.push_str(&format!(
            "counterbalance: no spring needed: the peak is under {} {unit}, less than a joint's friction\n",
            balance.no_spring_below_nm * factor
        ));
    } else {
        out.push_str("counterbalance: no spring hooked on the fixed bodies, in the linkage region or on the moving parts lowers the peak\n");
    }
    print!("{}", crate::terminal::lines(&out));
    Ok(())
}

/// A CSV field: quoted when it holds a comma, a quote or a line break (joint names come from the file).
fn csv_field(text: &str) -> String {
    if text.contains([',', '"', '\n', '\r']) {
        format!("\"{}\"", text.replace('"', "\"\""))
    } else {
        text.to_string()
    }
}

/// A pose counts as reached within this fraction of the body's size and this angle (the web app's
/// badge uses the same bounds).
const REACHED_REL_D: f64 = 0.01;
const REACHED_DEG: f64 = 1.0;

/// A path is traced closely within this fraction of its size; past it the summary says how far it
/// strays, and where.
const TRACED_REL: f64 = 0.02;

/// How closely a path design follows the drawn path, its exact points and, when the body has later
/// poses, those (`misses`).
fn path_reach(problem: &Problem, error: &PathError, misses: &[Vec<PoseMiss>]) -> String {
    let units = &problem.units;
    let at = if error.max_rel > TRACED_REL {
        format!(", farthest near ({:.1}, {:.1})", error.at.x, error.at.y)
    } else {
        String::new()
    };
    let exact = match (error.exact, missed_exact_point(error)) {
        (_, Some(x)) => format!(
            "; MISSES EXACT POINT {} by {:.3} {units} ({:.2}% of the path's size), and no linkage closer was found",
            x.point,
            x.distance,
            100.0 * x.distance_rel
        ),
        (Some(x), None) => format!(", passing its exact points within {:.3} {units}", x.distance),
        (None, None) => String::new(),
    };
    let poses = if misses.len() > 1 { pose_reach(problem, misses) } else { String::new() };
    format!(
        ", traces the drawn path within {:.3} {units} ({:.2}% of its size; {:.3} {units} on average){at}{exact}{poses}",
        error.max,
        100.0 * error.max_rel,
        error.mean
    )
}

/// What a person wants to know after the hard constraints: whether the design reaches the drawn poses,
/// and if not, which one it misses most (the one furthest past either bound).
fn pose_reach(problem: &Problem, misses: &[Vec<PoseMiss>]) -> String {
    let units = &problem.units;
    let past = |m: &PoseMiss| (m.position_rel_d / REACHED_REL_D).max(m.angle_deg / REACHED_DEG);
    let indexed = misses.iter().enumerate().flat_map(|(i, m)| m.iter().enumerate().map(move |(b, m)| (i, b, m)));
    match indexed.max_by(|a, b| past(a.2).total_cmp(&past(b.2))) {
        Some((i, b, m)) if past(m) > 1.0 => format!(
            ", misses pose {} of {} by {:.3} {units} ({:.1}% of its size) and {:.2}°",
            i + 1,
            problem.bodies[b].name,
            m.position,
            100.0 * m.position_rel_d,
            m.angle_deg
        ),
        Some(_) => {
            let worst = PoseMiss::worst(misses.iter().flatten());
            format!(", reaches every pose within {:.3} {units} and {:.2}°", worst.position, worst.angle_deg)
        }
        None => String::new(),
    }
}

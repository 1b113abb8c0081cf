//! The whole synthesis (paper fig. 2): sample → kinematic checks → collision checks → particle filter
//! → a local refinement of the designs kept, each verified again as `check` does,
//! for every mechanism family that fits the scene, with progress reports and cancellation.

use super::collision::check_collisions;
use super::context::Context;
use super::evaluate::{cost_floor, evaluate, Candidate, Reject};
use super::path::{path_designs, Accepts};
use super::pfo::{refine, FilterOptions};
use super::random::splitmix;
use super::refine::{refine_design, Leash, RefineOptions};
use super::sample::{x_from_mechanism, Near, SampleScratch, Sampler, WARM_JITTER};
use super::workspace::Workspace;
use crate::geom::Point;
use crate::kinematics::Trace;
use crate::mechanism::{Mechanism, MechanismType, Topology};
use crate::scene::{MechanismChoice, Problem};
use crate::verify::{far_from_pose, pose_misses, verify_travel, Travel};
use rayon::prelude::*;
use std::sync::{Arc, Mutex, PoisonError};
use std::time::Instant;

/// The factor on the pose noise of a second search, when the first found no design: poses
/// perturbed as far as the scene allows can leave every fitted linkage locking up between them or
/// hitting something, where linkages fitted closer to the drawn poses pass (reference scenes: the
/// three-pose power shovel and the peg in its hole get a design this way).
const RETRY_NOISE: f64 = 0.1;
/// Mixed into the seed of the second search a cold run makes when its first found no design or a
/// poor one ([`worth_another_search`]).
const SECOND_SEARCH_STREAM: u64 = 0x6661_7200;
/// A design that misses some pose by more than this fraction of its body's size d, or by more than
/// [`LOOSE_ANGLE_DEG`], is worth a second search from other samples: one seed's search can settle on
/// a linkage well off the poses where another finds one closer (a known three-body chain through
/// three poses: the test `a_design_off_the_poses_gets_a_second_search`).
const LOOSE_POSITION_REL_D: f64 = 0.05;
/// See [`LOOSE_POSITION_REL_D`].
const LOOSE_ANGLE_DEG: f64 = 2.0;
/// A design whose smallest transmission angle is under this (or under the scene's comfortable angle,
/// when that is lower) runs close to a dead point, and is worth a second search when the
/// transmission has a weight. The comfortable angle is what the cost aims at; this is where a design
/// is poor enough to be worth the time.
const POOR_TRANSMISSION_DEG: f64 = 15.0;
/// The factor on the transmission's weight in the second search of a design near a dead point
/// ([`POOR_TRANSMISSION_DEG`]): the reseeded search alone left reference `k3_power_shovel_3poses`
/// (seed 0) at 14°, where ten times the weight finds 21° (`linkwright design` on that scene with
/// `weights.transmission` 100).
const DEAD_POINT_REWEIGHT: f64 = 10.0;
/// Samples drawn between two progress reports (and cancellation checks).
const CHUNK: usize = 2048;
/// Samples simulated between two updates of the bar a sample's cost floor must pass.
const SIMULATION_CHUNK: usize = 256;
/// Screened samples put in simulation order at a time ([`sort_ahead`]).
const SORT_BLOCK: usize = 4096;
/// The share of the sampling stage's progress that screening takes (the rest is simulation).
const SCREENING_SHARE: f64 = 0.7;
/// Defect-free candidates kept for the collision check, lowest cost first: a bound on memory (each
/// holds its simulated travel) and on the samples simulated (only those whose cost floor is under the
/// costliest kept one are). Where few candidates are collision-free (the folding table, 1 in 8) it
/// also bounds how many valid designs the particle filter starts from, and fewer, cheaper ones served
/// it as well: over seeds 0–9 every Table-1 object's best cost at 1,500 was that at 2,200 or lower on
/// average (the two-body car 4.04 → 3.98, the three-body car 6.73 → 6.66), for runs up to 14% shorter
/// (docs/performance.md, "The candidate cap").
const CANDIDATE_CAP: usize = 1500;
/// The collision check stops once this many particles' worth of valid designs are found: the particle
/// filter resamples its particles from them by weight, and the lowest costs come first.
const VALID_PER_PARTICLE: usize = 10;
/// Candidates checked for collisions between two checks of the stopping rule (fewer when fewer
/// valid ones are wanted, see [`collision_chunk`]).
const COLLISION_CHUNK: usize = 128;
/// At most this many chunks are swept in one parallel batch.
const COLLISION_BATCH_CHUNKS: usize = 8;
/// At most this many alternatives are reported.
pub(crate) const MAX_ALTERNATIVES: usize = 10;
/// Two designs of one family are distinct when some joint differs by more than this fraction of d.
const DISTINCT: f64 = 0.25;

/// Draws sample `i` of a run into the scratch ([`SampleScratch::mechanism`]), the same sample every
/// time; false when it did not fit.
type Draw<'a> = dyn Fn(usize, &mut SampleScratch) -> bool + Sync + 'a;

/// The stage a run is in.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Stage {
    /// Drawing samples, fitting them to the poses and checking them for defects (paper §4–5.4).
    Sampling,
    /// Checking the candidates for collisions along their travel (§5.5).
    Collision,
    /// The particle filter (§6), then refining and checking the designs kept.
    Refining,
}

/// A progress report.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct Progress {
    /// What the run is doing.
    pub stage: Stage,
    /// The family being searched.
    pub mechanism: MechanismType,
    /// Fraction of the whole run done, 0 to 1.
    pub fraction: f64,
    /// The lowest cost of a valid design so far.
    pub best_cost: Option<f64>,
}

/// Receives progress and tells the run whether to stop. Called from worker threads' coordinator only
/// (never concurrently), between chunks of work.
pub trait Observer: Sync {
    /// Called with each progress report; does nothing by default.
    fn progress(&self, _progress: &Progress) {}
    /// Whether the run should stop now (it then returns [`Cancelled`]); never, by default.
    fn cancelled(&self) -> bool {
        false
    }
}

/// An observer that ignores progress and never cancels.
#[derive(Clone, Copy, Debug, Default)]
pub struct Silent;
impl Observer for Silent {}

/// The run was cancelled by its observer.
#[derive(Clone, Copy, Debug, PartialEq, Eq, thiserror::Error)]
#[error("the synthesis was cancelled")]
pub struct Cancelled;

/// Counts and seconds of a run. Families screened side by side each count their own seconds, so the
/// stages' seconds may add up to more than the whole run's.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct RunStats {
    /// Samples drawn.
    pub samples: usize,
    /// Samples that became a rigid linkage (passed the E_rigid fit).
    pub fitted: usize,
    /// Linkages without defects, before the collision check.
    pub candidates: usize,
    /// Candidates without collisions.
    pub valid: usize,
    /// How many candidates each hard constraint rejected.
    pub rejected: Vec<(Reject, usize)>,
    /// Seconds spent drawing, fitting and checking samples.
    pub seconds_sampling: f64,
    /// Seconds spent checking candidates for collisions.
    pub seconds_collision: f64,
    /// Seconds spent in the particle filter.
    pub seconds_pfo: f64,
    /// Checking the screened and the kept designs for printability (when asked).
    pub seconds_printability: f64,
    /// Refining the kept designs and verifying them again.
    pub seconds_refinement: f64,
    /// Designs dropped because the independent re-simulation rejected them.
    pub failed_verification: usize,
    /// Seconds of the whole run.
    pub seconds_total: f64,
}

/// What a run found.
#[derive(Debug)]
pub struct Outcome {
    /// The design of lowest cost, or `None` when no linkage passed every hard constraint.
    pub best: Option<Candidate>,
    /// Other valid designs, best first, each distinct from the best and from each other.
    pub alternatives: Vec<Candidate>,
    /// What the run did and how long it took.
    pub stats: RunStats,
    /// Why there is no design and what to change, when there is none.
    pub reason: Option<String>,
    /// True when the run had a check ([`Options::printable`]) that no valid linkage passed: `best`
    /// is then the valid linkage of lowest cost, which the check refuses (a design is never lost to
    /// that check alone), and there are no alternatives.
    pub unbuildable: bool,
}

/// The families a scene asks for: those its mechanism choice allows for its number of moving bodies
/// that have a joint of every pinned joint's name.
pub(crate) fn families(problem: &Problem) -> Vec<MechanismType> {
    chosen_families(problem).into_iter().filter(|&family| pinned_joints_missing(problem, family).is_empty()).collect()
}

/// The families the scene's mechanism choice allows for its number of bodies, pins aside.
fn chosen_families(problem: &Problem) -> Vec<MechanismType> {
    match problem.mechanism {
        MechanismChoice::Only(family) => vec![family],
        MechanismChoice::Auto => MechanismType::ALL
            .into_iter()
            .filter(|family| family.max_bodies().is_none_or(|max| problem.body_count() <= max))
            .collect(),
    }
}

/// The scene's pinned joints that `family`'s linkage for the scene has no joint for.
fn pinned_joints_missing(problem: &Problem, family: MechanismType) -> Vec<&str> {
    let topology = family.family().topology(problem.body_count());
    problem.pinned.iter().map(|(name, _)| name.as_str()).filter(|name| topology.joint(name).is_none()).collect()
}

/// Where the search starts.
#[derive(Clone, Copy, Debug, Default)]
pub enum Start<'a> {
    /// From scratch: `settings.samples` samples drawn uniformly in the linkage region. With several
    /// families to choose from, each is screened first on a [`SCREENING_DIVISOR`]th of its samples;
    /// the family of the cheapest screened design then draws the rest of its samples and is searched
    /// in full, from all of them; the next cheapest families are too, one by one, while the cheapest
    /// design found misses a pose by more than 2% of d or 1°. The screened designs of every family
    /// stay among the answers.
    #[default]
    Cold,
    /// From earlier designs of a similar scene (a previous design and its alternatives, after the
    /// person moved a pose, say): [`WARM_SAMPLES`] samples are fitted from those designs' joints to the
    /// new poses, and the particle filter runs a quarter of its iterations. The family of the first
    /// (the design refined) is searched from those of its family: the person refines the linkage
    /// they have. If it finds nothing valid, that family falls back to a cold start. Every other
    /// family is screened cold on a [`SCREENING_DIVISOR`]th of the samples, and takes over only with
    /// a design costing less than [`SWITCH_COST_FACTOR`] of the warm family's best.
    Warm(&'a [Mechanism]),
    /// A live redesign after a small edit (a pose dragged a little): searched as [`Start::Warm`] from
    /// the design shown (the first) and its alternatives, its family only (a live redesign must keep
    /// up: the garbage truck's live steps took a median 137 ms when each of its three families was
    /// searched, `CI=true cargo test --release -p linkwright --test web_e2e -- --nocapture | grep
    /// latency`), and the answer is the design whose joints
    /// moved least from the design shown, of those costing at most [`FOLLOW_COST_SLACK`] more than
    /// the cheapest: a small edit moves the linkage a little (same family, same branch, joints near
    /// where they were) rather than jumping to another linkage that is a little cheaper.
    Follow(&'a [Mechanism]),
}

/// How much more than the cheapest design (a fraction of its cost) the design that follows the one
/// shown may cost ([`Start::Follow`]). Dragging a pose of each bundled example by a tenth of the
/// body's size in ten steps, a redesign that took the cheapest moved a joint by a median of up to
/// 0.54 d per step (the folding roof; over 0.15 d on six of the thirteen); following, by at most
/// 0.055 d (`linkwright bench --live examples/*.json`).
pub const FOLLOW_COST_SLACK: f64 = 0.25;

/// How far (fraction of d) the refinement may move the design that follows the one shown: the
/// optimum itself can move several times as far as the pose dragged, and a design refined freely
/// drifts from the one shown until it jumps (`linkwright bench --live examples/*.json`).
const FOLLOW_REACH: f64 = 0.03;

/// A family is screened ([`Start`]) on this share of the samples, and a quarter of the filter's
/// iterations: the bundled one-body examples' cold runs with `mechanism: auto` cost a median 1.37–1.40
/// times the family they return (`linkwright bench --auto --repeat 5 --threads 2
/// examples/k1_*.json`), where searching each family in full costs about 5 times. A twelfth or a
/// sixteenth ranks the families worse (the monitor's design then costs 41% more).
pub const SCREENING_DIVISOR: usize = 8;
/// A screening simulates the samples of this many times its candidates' lowest cost floors, not all
/// those under its costliest candidate's cost. A six-bar's floors lie far under its costs, so it
/// simulated nearly every sample (the full wall bed's Stephenson-III 1,545 of 1,567), where its
/// filter starts from the ten cheapest valid ones. On the one-body reference scenes and examples
/// (seeds 0 and 1), twice as many gave 62 of 64 designs the same as simulating all, one 0.3% cheaper
/// and one 0.01% costlier; the full wall bed's run fell from 1.69–1.73 times its family alone (with
/// three times as many) to 1.54–1.59 (`linkwright bench --auto --repeat 5 --threads 2
/// examples/k1_*.json`). As many did not do (the tractable monitor's design cost 61% more).
const SCREENING_SIMULATED: usize = 2;
/// The share of a cold run's progress bar its screening of every family takes.
const SCREENING_PROGRESS: f64 = 0.25;
/// The cheapest design found so far misses some pose by more than this fraction of d, or by more
/// than [`SCREENED_CLOSE_ANGLE_DEG`]: the motion is hard for a screening, and the next family is
/// searched in full too. (Of the reference scenes, example 5's cheapest screened design, a four-bar,
/// missed a pose by 0.12 d; a Stephenson-III's whole search there costs 5.6, its screening 93.)
/// Searching one family after the other, rather than all once the screening falls short, gives the
/// same designs on the one-body reference scenes and examples, at a fraction of the time where the
/// first family searched comes close (the tractable monitor).
const SCREENED_CLOSE_REL_D: f64 = 0.02;
/// See [`SCREENED_CLOSE_REL_D`].
const SCREENED_CLOSE_ANGLE_DEG: f64 = 1.0;
/// A family screened in a warm start takes over when its design costs less than this share of the
/// warm family's best: clearly better, not the noise between two searches (on known four-bar and
/// slider-crank motions a Stephenson-III asked for cost 1.15 times the cold best, and must stay; one
/// cost 2.25 times, and is left).
pub const SWITCH_COST_FACTOR: f64 = 0.75;

/// At most this many of a screened family's cheapest designs are print-checked to find the cheapest
/// printable one ([`printable_first`]), in parallel batches of [`SCREENED_PRINT_BATCH`].
const SCREENED_PRINT_CHECKS: usize = 16;
/// See [`SCREENED_PRINT_CHECKS`]. The cheapest design checked passes for most families (27 of the 32
/// of the bundled one-body examples), so a batch larger than the cores mostly costs a round of checks
/// for nothing: on two cores, batches of four took a run's print checks a median 12.7–13.2 ms, two
/// take 9.3–9.9 ms (`stats.seconds.printability` of `linkwright design examples/k1_*.json --threads 2
/// --json`, three runs each).
const SCREENED_PRINT_BATCH: usize = 2;

/// Samples of a warm start.
pub const WARM_SAMPLES: usize = 500;

/// A test every design must also pass, beyond the synthesis' own hard constraints: fabrication's print
/// check (paper §7.2) implements it, so the synthesis needs nothing of fabrication. What it refuses is
/// counted as [`Reject::Unprintable`].
pub trait Acceptance: Sync + std::fmt::Debug {
    /// The least distance between two joints of one part the test needs (a length): samples whose
    /// joints are closer are never drawn.
    fn min_joint_spacing(&self) -> f64;
    /// Whether `mechanism`, moving through `trace` (a candidate's own travel), passes.
    fn accepts(&self, mechanism: &Mechanism, trace: &Trace) -> bool;
}

/// How a run starts and what its designs must also satisfy.
#[derive(Clone, Copy, Debug, Default)]
pub struct Options<'a> {
    /// From scratch, or from earlier designs.
    pub start: Start<'a>,
    /// When given, every design must pass it (printable with given print settings, say). Checked on
    /// the kept designs, cheapest first, so the paper's stages run unchanged.
    pub printable: Option<&'a dyn Acceptance>,
}

/// Runs the paper's synthesis from scratch (no fabrication check) on the current rayon pool.
///
/// The result depends on the scene (its `settings.seed` included) and never on the number of
/// threads. `observer` hears of the progress and may stop the run:
///
/// ```
/// use linkwright_core::{synthesize, Observer, Problem, Progress, Scene};
/// use std::sync::atomic::{AtomicUsize, Ordering};
///
/// /// Counts the progress reports.
/// struct Count(AtomicUsize);
/// impl Observer for Count {
///     fn progress(&self, _: &Progress) {
///         self.0.fetch_add(1, Ordering::Relaxed);
///     }
/// }
///
/// // The wall bed: two moving bodies (the bed and its leg), so a Watt-I six-bar.
/// let mut scene = Scene::from_json(include_str!("../../../../examples/k2_wall_bed.json"))?;
/// scene.settings.samples = 20_000; // a fifth of the default, for a quick example
/// scene.settings.iterations = 5;
/// let problem = Problem::new(&scene).expect("the example is a valid scene");
/// let reports = Count(AtomicUsize::new(0));
/// let outcome = synthesize(&problem, &reports)?;
///
/// let best = outcome.best.as_ref().expect("a linkage through every pose");
/// assert_eq!(best.mechanism.topology.joint_count(), 7, "p1, p2, q0, q1, q2, r0, r1");
/// assert!(outcome.alternatives.iter().all(|a| a.cost >= best.cost), "the best comes first");
/// assert!(outcome.stats.valid > 0 && reports.0.into_inner() > 0);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn synthesize(problem: &Problem, observer: &dyn Observer) -> Result<Outcome, Cancelled> {
    synthesize_with(problem, &Options::default(), observer)
}

/// A given linkage judged as the synthesis judges its samples, for a person who moved its joints:
/// its motion through the poses and its costs, or the defect that leaves it without one. A
/// transmission angle under the scene's bound, a collision and a missed pin are left in the motion
/// for the re-simulation ([`crate::DesignFile::violations`]) to find and place, and a must-hit pose
/// missed for the metrics' pose errors to show: the person needs to see where the linkage fails.
/// `None` when `mechanism` is not its family's linkage for the scene's bodies (another number of
/// bodies, or parts the family does not build).
pub fn assess(problem: &Problem, mechanism: &Mechanism) -> Option<Result<Candidate, Reject>> {
    let family = mechanism.topology.mechanism_type;
    let bodies = problem.body_count();
    if mechanism.topology.body_count != bodies || family.max_bodies().is_some_and(|max| bodies > max) {
        return None;
    }
    let mut lenient = problem.clone();
    lenient.must_hit.fill(false);
    let ctx = Context { min_transmission_sine: 0.0, ..Context::new(&lenient, family) };
    let mechanism = on_topology(mechanism, &ctx.topology)?;
    Some(evaluate(&ctx, mechanism, None, f64::INFINITY, &mut Default::default()))
}

/// `mechanism` on `topology` (its joints found by name), when it is that linkage: the same family,
/// the same parts by name and by the joints they carry. A design file's mechanism lists its joints
/// in name order, a family's topology in its own.
fn on_topology(mechanism: &Mechanism, topology: &Arc<Topology>) -> Option<Mechanism> {
    fn parts(t: &Topology) -> Vec<(&str, crate::mechanism::PartKind, Vec<&str>)> {
        let mut parts: Vec<_> = t
            .parts
            .iter()
            .map(|p| {
                let mut joints: Vec<&str> = p.joints.iter().map(|&j| t.joint_names[j].as_str()).collect();
                joints.sort_unstable();
                (p.name.as_str(), p.kind, joints)
            })
            .collect();
        parts.sort_by(|a, b| a.0.cmp(b.0));
        parts
    }
    let given = &mechanism.topology;
    let same = given.mechanism_type == topology.mechanism_type
        && given.body_count == topology.body_count
        && parts(given) == parts(topology)
        && topology.slider_joint.is_some() == mechanism.slider.is_some();
    if !same {
        return None;
    }
    let joints = topology.joint_names.iter().map(|n| mechanism.joint(n)).collect::<Option<Vec<_>>>()?;
    Some(Mechanism { topology: topology.clone(), joints, slider: mechanism.slider })
}

/// One context per family of the run ([`family_context`]).
fn family_contexts<'p>(problem: &'p Problem, families: &[MechanismType], options: &Options) -> Vec<Context<'p>> {
    families.iter().map(|&family| family_context(problem, family, options)).collect()
}

/// A family's context, spaced for the print check when there is one.
fn family_context<'p>(problem: &'p Problem, family: MechanismType, options: &Options) -> Context<'p> {
    let ctx = Context::new(problem, family);
    match options.printable {
        Some(check) => ctx.spaced_at_least(check.min_joint_spacing()),
        None => ctx,
    }
}

/// Runs the synthesis with `options` on the current rayon pool.
pub fn synthesize_with(problem: &Problem, options: &Options, observer: &dyn Observer) -> Result<Outcome, Cancelled> {
    let started = Instant::now();
    if problem.path().is_some() {
        return Ok(synthesize_path(problem, options, observer, started));
    }
    let families = families(problem);
    let mut run = Run {
        printable: options.printable,
        observer,
        stats: RunStats::default(),
        rejected: [0; Reject::ALL.len()],
        refused: None,
    };
    let mut contexts = family_contexts(problem, &families, options);
    // One per family: a sample's buffers hold a mechanism of its family's topology.
    let workspaces: Vec<Workspace> = families.iter().map(|_| Workspace::default()).collect();
    let mut picked = design_round(problem, options, &contexts, &workspaces, &mut run)?;
    if picked.is_empty() && contexts.iter().any(|ctx| !ctx.unperturbed) {
        contexts = contexts.into_iter().map(|ctx| ctx.perturbed_less(RETRY_NOISE)).collect();
        picked = design_round(problem, options, &contexts, &workspaces, &mut run)?;
    }
    // No design, one off the poses or one near a dead point: a cold run searches once more, from
    // other samples (a warm start is the person's own design, and is kept), and keeps what is
    // closest, then cheapest.
    let far = |c: &Candidate| far_from_pose(problem, &pose_misses(problem, &c.mechanism, &c.trace, &c.pose_rows));
    if matches!(options.start, Start::Cold) && worth_another_search(problem, picked.first()) {
        let mut reseeded = problem.clone();
        reseeded.settings.seed = splitmix(problem.settings.seed ^ SECOND_SEARCH_STREAM);
        // Near a dead point, the second search weighs the transmission more, and its designs are
        // then costed as the scene weighs them.
        let reweighted = picked.first().is_some_and(|c| near_dead_point(problem, c));
        if reweighted {
            reseeded.weights.transmission *= DEAD_POINT_REWEIGHT;
        }
        let again = family_contexts(&reseeded, &families, options);
        let mut found = design_round(&reseeded, options, &again, &workspaces, &mut run)?;
        if reweighted {
            // The poses come first: a design clear of the dead point is taken only if it misses
            // the poses by no more than the first search's best, or than a loose miss.
            let bound = looseness(problem, &picked[0]).max(1.0);
            found.retain(|c| looseness(problem, c) <= bound);
            // This run's contexts judge at the scene's weights (their pose noise only draws samples).
            found = found.into_iter().filter_map(|c| recosted(&contexts, c)).collect();
        }
        picked.extend(found);
        // Designs near every pose first, then (after a reweighted search) those clear of a dead
        // point, then by cost: each key found once (both simulate), the sorts stable.
        picked.sort_by(|a, b| a.cost.total_cmp(&b.cost));
        picked.sort_by_cached_key(|c| (far(c).is_some(), reweighted && near_dead_point(problem, c)));
        picked = distinct_designs(problem, picked);
        picked.truncate(MAX_ALTERNATIVES + 1);
    }
    let Run { mut stats, rejected, .. } = run;
    if let Some(best) = picked.first() {
        // The refinement lowers the best cost, and a design that fails verification may be dropped.
        observer.progress(&Progress {
            stage: Stage::Refining,
            mechanism: best.mechanism.topology.mechanism_type,
            fraction: 1.0,
            best_cost: Some(best.cost),
        });
    }
    stats.rejected = Reject::ALL.iter().copied().zip(rejected).filter(|&(_, n)| n > 0).collect();
    stats.seconds_total = started.elapsed().as_secs_f64();
    let unbuildable = options.printable.is_some() && picked.first().is_some_and(|c| !c.printable);
    let mut picked = picked.into_iter();
    let best = picked.next();
    let reason = best.is_none().then(|| no_solution_reason(problem, &stats));
    Ok(Outcome { best, alternatives: picked.collect(), stats, reason, unbuildable })
}

/// Atlas samples of a path search's family, per sample of the scene's settings: the default 100,000
/// gives 20,000 curves (half as many each when `auto` tries several families), which find a known
/// four-bar's curve within 0.1% of its size.
const PATH_SAMPLE_DIVISOR: usize = 5;

/// A path scene's run ([`path_designs`]); a warm start designs anew (the search takes a few seconds).
fn synthesize_path(problem: &Problem, options: &Options, observer: &dyn Observer, started: Instant) -> Outcome {
    let family = match problem.mechanism {
        MechanismChoice::Only(family) => family,
        MechanismChoice::Auto => MechanismType::Chain,
    };
    observer.progress(&Progress { stage: Stage::Sampling, mechanism: family, fraction: 0.0, best_cost: None });
    let samples = (problem.settings.samples / PATH_SAMPLE_DIVISOR).max(1);
    let accepts = options.printable.map(|check| move |m: &Mechanism, t: &Trace| check.accepts(m, t));
    let accepts: Option<&Accepts<'_>> = accepts.as_ref().map(|f| f as _);
    let found = path_designs(problem, samples, MAX_ALTERNATIVES + 1, accepts);
    let mut stats = RunStats {
        samples,
        fitted: found.fitted,
        candidates: found.fitted,
        valid: found.designs.len() + usize::from(found.refused.is_some()),
        ..RunStats::default()
    };
    stats.seconds_total = started.elapsed().as_secs_f64();
    stats.seconds_sampling = stats.seconds_total;
    let unbuildable = found.designs.is_empty() && found.refused.is_some();
    let mut designs = found.designs.into_iter().chain(found.refused);
    let best = designs.next();
    if let Some(b) = &best {
        observer.progress(&Progress {
            stage: Stage::Refining,
            mechanism: b.mechanism.topology.mechanism_type,
            fraction: 1.0,
            best_cost: Some(b.cost),
        });
    }
    let reason = best.is_none().then(|| match &found.closest_violation {
        Some(v) => format!(
            "no linkage found whose tracer follows the path: the closest ones break a hard constraint ({}: {}); \
             move or reshape the path away from the fixed bodies, or make it smoother",
            v.constraint, v.message
        ),
        None => "no linkage found whose tracer follows the path; draw a smoother curve".to_string(),
    });
    Outcome { best, alternatives: designs.collect(), stats, reason, unbuildable }
}

/// Whether a cold run's best design (`None`: no design) is worth a second search from other samples:
/// none was found, or it misses a pose by more than [`LOOSE_POSITION_REL_D`] or
/// [`LOOSE_ANGLE_DEG`], or it passes within [`POOR_TRANSMISSION_DEG`] of a dead point.
fn worth_another_search(problem: &Problem, best: Option<&Candidate>) -> bool {
    best.is_none_or(|c| looseness(problem, c) > 1.0 || near_dead_point(problem, c))
}

/// How far design `c` misses its worst pose, in units of a loose miss ([`LOOSE_POSITION_REL_D`],
/// [`LOOSE_ANGLE_DEG`]): over 1 is loose.
fn looseness(problem: &Problem, c: &Candidate) -> f64 {
    pose_misses(problem, &c.mechanism, &c.trace, &c.pose_rows)
        .iter()
        .flatten()
        .map(|m| (m.position_rel_d / LOOSE_POSITION_REL_D).max(m.angle_deg / LOOSE_ANGLE_DEG))
        .fold(0.0, f64::max)
}

/// Whether design `c` passes within [`POOR_TRANSMISSION_DEG`] of a dead point (or within the
/// scene's comfortable angle, when that is lower), when the scene gives the transmission a weight.
fn near_dead_point(problem: &Problem, c: &Candidate) -> bool {
    let poor_deg = POOR_TRANSMISSION_DEG.min(problem.settings.comfortable_transmission_deg);
    problem.weights.transmission > 0.0 && c.trace.least_transmission(&c.plan).1 < poor_deg.to_radians().sin()
}

/// Design `c` of another search costed by the contexts of this run's scene (`judges`, one per
/// family): its checks are the same, its cost is what this scene's weights make it. `None` if its
/// family has no context here or the checks now fail.
fn recosted(judges: &[Context], c: Candidate) -> Option<Candidate> {
    let ctx = judges.iter().find(|ctx| ctx.topology.mechanism_type == c.mechanism.topology.mechanism_type)?;
    let printable = c.printable;
    let mut judged = evaluate(ctx, c.mechanism, None, f64::INFINITY, &mut Default::default()).ok()?;
    judged.printable = printable;
    Some(judged)
}

/// Puts first, of `designs` (cheapest first) costing at most [`FOLLOW_COST_SLACK`] more than the
/// cheapest, the one whose joints moved least from `shown` ([`Mechanism::farthest_move_from`]) and
/// that the independent re-simulation accepts ([`verifies`]: a linkage at the edge of a check may pass
/// the search's and fail it; `verified` when every one of `designs` has passed it already); linkages
/// of another family never follow it. Run on the valid linkages before the designs are picked (so
/// that it is picked, and the others distinct from it), and again on the finished designs
/// ([`finish_designs`]).
fn follow(problem: &Problem, shown: &Mechanism, designs: &mut [Candidate], verified: bool) {
    let Some(cheapest) = designs.first().map(|c| c.cost) else { return };
    let limit = cheapest + FOLLOW_COST_SLACK * cheapest.abs();
    let mut near: Vec<(usize, f64)> = designs
        .iter()
        .enumerate()
        .take_while(|(_, c)| c.cost <= limit)
        .filter_map(|(i, c)| c.mechanism.farthest_move_from(shown).map(|d| (i, d)))
        .collect();
    near.sort_by(|a, b| a.1.total_cmp(&b.1));
    if let Some(&(i, _)) = near.iter().find(|&&(i, _)| verified || verifies(problem, &designs[i])) {
        designs[..=i].rotate_right(1);
    }
}

/// The order in which a cold run searches its screened families (indices into `screened`, each
/// family's designs from its screening) in full: the family of the cheapest screened design first,
/// families without one last. The run stops after the first family whose search leaves the cheapest
/// design found so far close to every pose ([`cheapest_is_close`]).
fn by_screened_cost(screened: &[Vec<Candidate>]) -> Vec<usize> {
    let cheapest = |f: usize| screened[f].iter().map(|c| c.cost).reduce(f64::min).unwrap_or(f64::INFINITY);
    let mut order: Vec<usize> = (0..screened.len()).collect();
    // Stable: equal costs (and families without a design) keep the families' order.
    order.sort_by(|&a, &b| cheapest(a).total_cmp(&cheapest(b)));
    order
}

/// A screened family's designs made ready to rank: its screening checks collisions only (the print
/// checks of the filter's seeds were most of a six-bar's screening), so with a print check the
/// cheapest are checked, in order, until one passes. Those refused leave (counted), so the cheapest
/// design left, which ranks the family and decides whether the run goes on ([`by_screened_cost`],
/// [`cheapest_is_close`]), is printable. A cheaper design within [`DISTINCT`]·d of one refused
/// leaves unchecked: the filter's designs gather around a few, one unprintable design's neighbours
/// mostly are too, and the designs are picked from the pool in cost order, print-checking each (with a
/// Watt-II's such designs in the pool, the full wall bed's pick took 18 ms, 2 ms without: its
/// `stats.seconds.printability`, `linkwright design examples/k1_wall_bed_full_size.json --json`).
/// When none of the first [`SCREENED_PRINT_CHECKS`] passes, none is left and the family ranks last.
///
/// The checks run in parallel batches of [`SCREENED_PRINT_BATCH`], each of the cheapest designs left
/// that lie apart from one another: were the cheaper of two neighbours refused, the other would be
/// passed over; were it printable, the other would not count. So the batches find what checking one
/// design after the other finds, and never check two neighbours.
fn printable_first(problem: &Problem, run: &mut Run, mut found: Vec<Candidate>) -> Result<Vec<Candidate>, Cancelled> {
    let Some(check) = run.printable else { return Ok(found) };
    let min_shift = min_shift(problem);
    // Stable: equal costs keep their production order.
    found.sort_by(|a, b| a.cost.total_cmp(&b.cost));
    // Each design, until refused.
    let mut found: Vec<Option<Candidate>> = found.into_iter().map(Some).collect();
    // The joints of each design refused.
    let mut refused: Vec<Vec<Point>> = Vec::new();
    // Every design checked so far was refused: the loop ends at the first that passes.
    while refused.len() < SCREENED_PRINT_CHECKS {
        run.go_on()?;
        // A batch of fixed size: what is checked (and counted) never depends on the threads.
        let room = SCREENED_PRINT_BATCH.min(SCREENED_PRINT_CHECKS - refused.len());
        let mut batch: Vec<usize> = Vec::new();
        for (i, c) in found.iter().enumerate() {
            let Some(c) = c else { continue };
            let apart = |joints: &Vec<Point>| moved(&c.mechanism.joints, joints, min_shift);
            if refused.iter().all(apart)
                && batch.iter().all(|&b| found[b].as_ref().is_some_and(|b| apart(&b.mechanism.joints)))
            {
                batch.push(i);
                if batch.len() == room {
                    break;
                }
            }
        }
        if batch.is_empty() {
            break;
        }
        let taken: Vec<(usize, Candidate)> =
            batch.iter().map(|&i| (i, found[i].take().expect("batched designs are left"))).collect();
        let checked: Vec<(usize, Result<Candidate, Refused>)> =
            taken.into_par_iter().map(|(i, c)| (i, mark_printable(check, c))).collect();
        let mut first = None;
        for (i, r) in checked {
            match r {
                Ok(c) => {
                    first = first.or(Some(i));
                    found[i] = Some(c);
                }
                Err((reject, c)) => {
                    refused.push(c.mechanism.joints.clone());
                    run.refuse(reject, c);
                }
            }
        }
        // The first printable design and every costlier one left; those cheaper were refused or lie
        // near one refused.
        if let Some(first) = first {
            return Ok(found.into_iter().skip(first).flatten().collect());
        }
    }
    Ok(Vec::new())
}

/// Whether the cheapest of `designs` misses no pose by more than [`SCREENED_CLOSE_REL_D`] of d or
/// [`SCREENED_CLOSE_ANGLE_DEG`].
fn cheapest_is_close<'c>(problem: &Problem, designs: impl Iterator<Item = &'c Candidate>) -> bool {
    designs.min_by(|a, b| a.cost.total_cmp(&b.cost)).is_some_and(|c| {
        pose_misses(problem, &c.mechanism, &c.trace, &c.pose_rows)
            .iter()
            .flatten()
            .all(|m| m.position_rel_d <= SCREENED_CLOSE_REL_D && m.angle_deg <= SCREENED_CLOSE_ANGLE_DEG)
    })
}

/// Whether the independent re-simulation ([`verify_travel`], what a design file's check runs) finds
/// `c` sound along its travel.
fn verifies(problem: &Problem, c: &Candidate) -> bool {
    let poses: Vec<f64> = c.pose_thetas().map(f64::to_degrees).collect();
    let travel = Travel { start: poses[0], end: poses[poses.len() - 1], poses: &poses };
    verify_travel(problem, &c.mechanism, travel).0.is_empty()
}

/// One search over every family (`contexts`, with their `workspaces`): sampling, checks and the
/// particle filter per family, then the designs picked from all of them and finished, best first.
fn design_round(
    problem: &Problem,
    options: &Options,
    contexts: &[Context],
    workspaces: &[Workspace],
    run: &mut Run,
) -> Result<Vec<Candidate>, Cancelled> {
    let mut valid: Vec<Candidate> = Vec::new();
    let observer = run.observer;
    // Each family's warm-start seeds: the earlier designs of its topology, as parameter vectors, for
    // the family of the design refined only.
    let seeds: Vec<Vec<Vec<f64>>> = contexts
        .iter()
        .map(|ctx| match options.start {
            Start::Cold => Vec::new(),
            Start::Warm(previous) | Start::Follow(previous)
                if previous.first().is_some_and(|m| m.topology.mechanism_type == ctx.topology.mechanism_type) =>
            {
                previous
                    .iter()
                    .filter_map(|m| on_topology(m, &ctx.topology))
                    .map(|m| {
                        let mut x = Vec::new();
                        x_from_mechanism(&m, &mut x);
                        x
                    })
                    .collect()
            }
            Start::Warm(_) | Start::Follow(_) => Vec::new(),
        })
        .collect();
    let warm = seeds.iter().any(|s| !s.is_empty());
    let following = matches!(options.start, Start::Follow(_));
    // A cold run of several families screens each of them first, then searches them in full, cheapest
    // first, until a design comes close to every pose ([`by_screened_cost`]); a warm start (not a
    // live one) screens the families it does not start from, and one of them takes over with a
    // clearly cheaper design ([`SWITCH_COST_FACTOR`]).
    let screens = if warm { !following } else { contexts.len() > 1 };
    let screen: Vec<usize> = (0..contexts.len()).filter(|&f| screens && seeds[f].is_empty()).collect();
    let mut drawn: Vec<Drawn> = contexts.iter().map(|_| Drawn::default()).collect();
    let mut screened: Vec<Vec<Candidate>> = contexts.iter().map(|_| Vec::new()).collect();
    let family_stage = |f: usize| FamilyStage { ctx: &contexts[f], workspace: &workspaces[f] };
    // The progress bar: the screening's share first, then each family searched in full.
    let screen_share = if screen.is_empty() { 0.0 } else { SCREENING_PROGRESS };
    let mut best_cost: Option<f64> = None;
    // The families are screened side by side, each on a run of its own: a screening's stages are
    // short, and while one waits on its slowest task or checks designs one batch at a time, the other
    // cores work on another family. Each family's screening is what it would be alone, and the runs
    // are added up in family order, so nothing depends on the threads.
    let screening = Mutex::new(ScreeningProgress {
        done: vec![0.0; screen.len()],
        stages: vec![Stage::Sampling; screen.len()],
        finished: vec![false; screen.len()],
        best: None,
    });
    let lock_screening = || screening.lock().unwrap_or_else(PoisonError::into_inner);
    let screenings: Vec<(Vec<Candidate>, Drawn, Run)> = screen
        .par_iter()
        .enumerate()
        .map(|(k, &f)| {
            let mut own = run.beside();
            let family = contexts[f].topology.mechanism_type;
            let report = |stage, x, b| {
                let mut progress = lock_screening();
                // Once cancelled, the run stops at each family's next check: a family side by side
                // with the one that saw it reports nothing more meanwhile.
                if observer.cancelled() {
                    return;
                }
                (progress.done[k], progress.stages[k]) = (x, stage);
                // A warm start's best is its own family's: a screened family shows its best only
                // while it reports, as when screened one after the other.
                let best_cost = min_opt(progress.best, b);
                if !warm {
                    progress.best = best_cost;
                }
                let fraction = screen_share * progress.done.iter().sum::<f64>() / screen.len() as f64;
                // The first family still screening is named, so that the label changes only when one
                // finishes, not with every report of the families side by side.
                let named = progress.finished.iter().position(|&finished| !finished).unwrap_or(k);
                let (stage, mechanism) = (progress.stages[named], contexts[screen[named]].topology.mechanism_type);
                observer.progress(&Progress { stage, mechanism, fraction, best_cost })
            };
            let mut drawn = Drawn::default();
            let found = run_family(
                &mut own,
                family_stage(f),
                family,
                &[],
                false,
                Budget::screening(problem),
                &mut drawn,
                &report,
            )?;
            let t = Instant::now();
            let found = printable_first(problem, &mut own, found)?;
            own.stats.seconds_printability += t.elapsed().as_secs_f64();
            lock_screening().finished[k] = true;
            Ok((found, drawn, own))
        })
        .collect::<Result<_, Cancelled>>()?;
    for (&f, (found, family_drawn, own)) in screen.iter().zip(screenings) {
        run.absorb(own);
        if !warm {
            best_cost = min_opt(best_cost, found.iter().map(|c| c.cost).reduce(f64::min));
        }
        drawn[f] = family_drawn;
        screened[f] = found;
    }
    let searched: Vec<usize> = match (warm, screen.is_empty()) {
        (true, _) => (0..contexts.len()).filter(|&f| !seeds[f].is_empty()).collect(),
        (false, true) => (0..contexts.len()).collect(),
        (false, false) => by_screened_cost(&screened),
    };
    let stops_when_close = !warm && !screen.is_empty();
    for (k, &f) in searched.iter().enumerate() {
        let family = contexts[f].topology.mechanism_type;
        let report = |stage, x, b| {
            let fraction = screen_share + (1.0 - screen_share) * (k as f64 + x) / searched.len() as f64;
            observer.progress(&Progress { stage, mechanism: family, fraction, best_cost: min_opt(best_cost, b) })
        };
        let mut found = Vec::new();
        if !seeds[f].is_empty() {
            let budget = Budget::warm(problem);
            found =
                run_family(run, family_stage(f), family, &seeds[f], following, budget, &mut Drawn::default(), &report)?;
        }
        if found.is_empty() {
            let budget = Budget::cold(problem, run.printable.is_some());
            found = run_family(run, family_stage(f), family, &[], false, budget, &mut drawn[f], &report)?;
        }
        best_cost = min_opt(best_cost, found.iter().map(|c| c.cost).reduce(f64::min));
        valid.extend(found);
        if stops_when_close && cheapest_is_close(problem, valid.iter().chain(screened.iter().flatten())) {
            break;
        }
    }
    let others = screened.into_iter().flatten();
    if warm {
        let others: Vec<Candidate> = others.collect();
        let cheapest = |designs: &[Candidate]| designs.iter().map(|c| c.cost).reduce(f64::min);
        if cheapest(&others).is_some_and(|other| cheapest(&valid).is_none_or(|warm| other < SWITCH_COST_FACTOR * warm))
        {
            valid.extend(others);
        }
    } else {
        // The screened designs stay in the pool: the whole search of a family starts from the same
        // samples, and the filter's screening designs may be good ones.
        valid.extend(others);
    }
    // Stable sort: equal costs keep their deterministic production order.
    valid.sort_by(|a, b| a.cost.total_cmp(&b.cost));
    if let Start::Follow([shown, ..]) = options.start {
        follow(problem, shown, &mut valid, false);
    }
    let t = Instant::now();
    let mut picked = pick_designs(problem, valid, run)?;
    run.stats.seconds_printability += t.elapsed().as_secs_f64();
    // Valid linkages the print check alone refused: the best of them is the answer, marked.
    if picked.is_empty() {
        picked.extend(run.refused.take());
    }
    let t = Instant::now();
    let shown = match options.start {
        Start::Follow([shown, ..]) => Some(shown),
        _ => None,
    };
    let picked = finish_designs(problem, (contexts, workspaces), picked, shown, run)?;
    run.stats.seconds_refinement += t.elapsed().as_secs_f64();
    Ok(picked)
}

/// The best design and up to [`MAX_ALTERNATIVES`] alternatives from `valid` (sorted by cost): each
/// distinct from those picked before it and, with a `printable` check, printable. Printability is
/// checked in parallel batches in order of cost (a few milliseconds each), so only as many designs
/// are checked as the picking needs.
fn pick_designs(problem: &Problem, valid: Vec<Candidate>, run: &mut Run) -> Result<Vec<Candidate>, Cancelled> {
    let min_shift = min_shift(problem);
    let wanted = MAX_ALTERNATIVES + 1;
    let mut picked: Vec<Candidate> = Vec::new();
    let mut queue = valid.into_iter().peekable();
    while picked.len() < wanted && queue.peek().is_some() {
        run.go_on()?;
        // Only designs distinct from every one picked so far need the (costly) printability check. The
        // batch's size changes how many are checked, never which are picked.
        let mut batch: Vec<Candidate> = Vec::new();
        while batch.len() < 2 * rayon::current_num_threads() {
            let Some(c) = queue.next() else { break };
            if picked.iter().all(|p| distinct(p, &c, min_shift)) {
                batch.push(c);
            }
        }
        let checked: Vec<Result<Candidate, Refused>> = match run.printable {
            Some(check) => batch.into_par_iter().map(|c| mark_printable(check, c)).collect(),
            None => batch.into_iter().map(Ok).collect(),
        };
        for r in checked {
            match r {
                Err((reject, c)) => run.refuse(reject, c),
                Ok(c) if picked.len() < wanted && picked.iter().all(|p| distinct(p, &c, min_shift)) => picked.push(c),
                Ok(_) => {}
            }
        }
    }
    Ok(picked)
}

/// The picked designs refined to local optima of the cost ([`refine_design`]), each checked again:
/// a refined design that cannot be printed, or that the independent re-simulation ([`verify_travel`],
/// what a design file's check runs) rejects, gives way to its unrefined self; a design neither of
/// which passes is dropped and counted. Returned best first, each distinct from those before it.
///
/// Following the design `shown`, the first picked (the one that follows it) is also refined on a
/// [`FOLLOW_REACH`] leash, and the design that moved least from `shown` goes first ([`follow`]).
fn finish_designs(
    problem: &Problem,
    (contexts, workspaces): (&[Context], &[Workspace]),
    picked: Vec<Candidate>,
    shown: Option<&Mechanism>,
    run: &mut Run,
) -> Result<Vec<Candidate>, Cancelled> {
    run.go_on()?;
    let printable = run.printable;
    let family_of = |c: &Candidate| {
        contexts.iter().position(|ctx| ctx.topology.mechanism_type == c.mechanism.topology.mechanism_type)
    };
    let verified = |c: Candidate| verifies(problem, &c).then_some(c);
    let options = RefineOptions::default();
    let finished: Vec<[Option<Candidate>; 3]> = picked
        .into_par_iter()
        .enumerate()
        .map(|(i, c)| {
            let f = family_of(&c).expect("every design comes from one of the run's families");
            let ctx = &contexts[f];
            let refined = |leash| {
                let mut refined = refine_design(ctx, &c, &options, leash, &mut workspaces[f].judging.take());
                if let Some(check) = printable {
                    refined.printable = refined.printable || check.accepts(&refined.mechanism, &refined.trace);
                    if !refined.printable && c.printable {
                        return None;
                    }
                }
                verified(refined)
            };
            let leash = shown.filter(|_| i == 0).map(|shown| Leash { shown, reach: FOLLOW_REACH * ctx.body_size });
            let leashed = leash.and_then(|leash| refined(Some(leash)));
            let free = refined(None);
            let unrefined =
                (free.is_none() || (leash.is_some() && leashed.is_none())).then(|| verified(c.clone())).flatten();
            [free, leashed, unrefined]
        })
        .collect();
    run.stats.failed_verification = finished.iter().filter(|c| c.iter().all(Option::is_none)).count();
    let mut finished: Vec<Candidate> = finished.into_iter().flatten().flatten().collect();
    finished.sort_by(|a, b| a.cost.total_cmp(&b.cost));
    if let Some(shown) = shown {
        follow(problem, shown, &mut finished, true);
    }
    Ok(distinct_designs(problem, finished))
}

/// Of `designs`, in their order, each distinct from every one kept before it ([`distinct`]).
fn distinct_designs(problem: &Problem, designs: Vec<Candidate>) -> Vec<Candidate> {
    let min_shift = min_shift(problem);
    let mut out: Vec<Candidate> = Vec::new();
    for c in designs {
        if out.iter().all(|p| distinct(p, &c, min_shift)) {
            out.push(c);
        }
    }
    out
}

/// `c` marked printable, or why not with `c` (a candidate already found printable is not checked
/// again).
fn mark_printable(check: &dyn Acceptance, mut c: Candidate) -> Result<Candidate, Refused> {
    c.printable = c.printable || check.accepts(&c.mechanism, &c.trace);
    if c.printable {
        Ok(c)
    } else {
        Err((Reject::Unprintable, Box::new(c)))
    }
}

/// A candidate a check refused, with why (boxed: it is the rare path of a large value).
type Refused = (Reject, Box<Candidate>);

fn min_opt(a: Option<f64>, b: Option<f64>) -> Option<f64> {
    match (a, b) {
        (Some(x), Some(y)) => Some(x.min(y)),
        (x, None) => x,
        (None, y) => y,
    }
}

/// What a run carries from stage to stage: the check its designs must also pass, who follows it,
/// and what it counts.
struct Run<'a> {
    printable: Option<&'a dyn Acceptance>,
    observer: &'a dyn Observer,
    stats: RunStats,
    /// Candidates rejected, per [`Reject`].
    rejected: [usize; Reject::ALL.len()],
    /// The valid candidate of lowest cost that the print check refused (the first found of equal cost).
    refused: Option<Candidate>,
}

impl<'a> Run<'a> {
    /// A run beside this one, for one family screened alongside others: the same check and
    /// observer, counts of its own ([`Run::absorb`]).
    fn beside(&self) -> Run<'a> {
        Run {
            printable: self.printable,
            observer: self.observer,
            stats: RunStats::default(),
            rejected: [0; Reject::ALL.len()],
            refused: None,
        }
    }

    /// Adds the counts of `other`, a run [`Run::beside`] this one: as if its work had been done on
    /// this run after everything so far.
    fn absorb(&mut self, other: Run) {
        // Every field named, so that a new count cannot be left out. The rejects and the whole run's
        // seconds are filled in when the run ends.
        let RunStats {
            samples,
            fitted,
            candidates,
            valid,
            rejected: _,
            seconds_sampling,
            seconds_collision,
            seconds_pfo,
            seconds_printability,
            seconds_refinement,
            failed_verification,
            seconds_total: _,
        } = other.stats;
        let s = &mut self.stats;
        s.samples += samples;
        s.fitted += fitted;
        s.candidates += candidates;
        s.valid += valid;
        s.seconds_sampling += seconds_sampling;
        s.seconds_collision += seconds_collision;
        s.seconds_pfo += seconds_pfo;
        s.seconds_printability += seconds_printability;
        s.seconds_refinement += seconds_refinement;
        s.failed_verification += failed_verification;
        for (count, more) in self.rejected.iter_mut().zip(other.rejected) {
            *count += more;
        }
        if let Some(c) = other.refused {
            self.keep_if_cheapest_refused(c);
        }
    }

    fn reject(&mut self, reject: Reject) {
        self.rejected[reject as usize] += 1;
    }

    /// Counts `reject`; when the print check refused `c`, keeps it if it is the cheapest so far.
    fn refuse(&mut self, reject: Reject, c: Box<Candidate>) {
        self.reject(reject);
        if reject == Reject::Unprintable {
            self.keep_if_cheapest_refused(*c);
        }
    }

    /// Keeps `c`, a design the print check refused, if it is cheaper than the one kept (the first
    /// found of equal cost stays).
    fn keep_if_cheapest_refused(&mut self, c: Candidate) {
        if self.refused.as_ref().is_none_or(|r| c.cost < r.cost) {
            self.refused = Some(c);
        }
    }

    /// `Err` once the person has cancelled the run.
    fn go_on(&self) -> Result<(), Cancelled> {
        if self.observer.cancelled() {
            Err(Cancelled)
        } else {
            Ok(())
        }
    }
}

/// How far the families screened side by side have come, and the cheapest design a cold run's
/// screenings have found.
struct ScreeningProgress {
    /// Each family's fraction of its screening done.
    done: Vec<f64>,
    /// Each family's stage (sampling until it reports another).
    stages: Vec<Stage>,
    /// Whether each family's screening has finished.
    finished: Vec<bool>,
    /// The cheapest design a cold run's screenings have found so far.
    best: Option<f64>,
}

/// One family's context and the buffers its stages share.
#[derive(Clone, Copy)]
struct FamilyStage<'r, 'p> {
    ctx: &'r Context<'p>,
    workspace: &'r Workspace,
}

/// How much of one family's search a run spends.
#[derive(Clone, Copy, Debug)]
struct Budget {
    /// Samples drawn, counted from the first (those a screening drew already are not drawn again).
    samples: usize,
    /// Iterations of the particle filter.
    iterations: usize,
    /// Defect-free candidates kept for the collision check ([`CANDIDATE_CAP`]).
    cap: usize,
    /// Samples simulated at most, those of the lowest cost floors.
    simulated: usize,
    /// Valid designs the collision check looks for before it stops.
    enough: usize,
    /// Whether those must also pass the run's print check (when it has one) before the filter.
    printed: bool,
}

impl Budget {
    /// A cold search's whole budget. It needs one particle set of printable designs (that check
    /// costs milliseconds, and the particle filter stays near them), or several sets of valid ones.
    fn cold(problem: &Problem, printable: bool) -> Budget {
        let settings = &problem.settings;
        let particles = settings.particles.max(1);
        Budget {
            samples: settings.samples,
            iterations: settings.iterations,
            cap: CANDIDATE_CAP,
            simulated: usize::MAX,
            enough: if printable { particles } else { VALID_PER_PARTICLE * particles },
            printed: true,
        }
    }

    /// A warm start's: [`WARM_SAMPLES`] and a quarter of the filter's iterations, from near good
    /// designs, where a quarter of a particle set of valid ones is enough (with the print check, a
    /// slider-crank's live step took a median 173 ms checking a whole set, `CI=true cargo test
    /// --release -p linkwright --test web_e2e -- --nocapture | grep latency`).
    fn warm(problem: &Problem) -> Budget {
        let settings = &problem.settings;
        Budget {
            samples: WARM_SAMPLES.min(settings.samples),
            iterations: (settings.iterations / 4).max(1).min(settings.iterations),
            cap: CANDIDATE_CAP,
            simulated: usize::MAX,
            enough: (settings.particles / 4).max(1),
            printed: true,
        }
    }

    /// A screening's: a [`SCREENING_DIVISOR`]th of the samples and of the candidates, a quarter of
    /// the filter's iterations from a tenth of a particle set of valid designs, checked for collisions
    /// only ([`printable_first`] finds a printable one after the filter): enough to tell a family
    /// that meets the poses at a low cost from one that does not. (The filter keeps its whole
    /// particle set: a quarter of it left the excavator's slider-crank at 6.4 where a whole set
    /// reached 1.7, and another family was chosen.) Of the samples, only [`SCREENING_SIMULATED`]
    /// times the candidates are simulated.
    fn screening(problem: &Problem) -> Budget {
        let settings = &problem.settings;
        Budget {
            samples: (settings.samples / SCREENING_DIVISOR).max(1),
            iterations: (settings.iterations / 4).max(1).min(settings.iterations),
            cap: CANDIDATE_CAP / SCREENING_DIVISOR,
            simulated: SCREENING_SIMULATED * CANDIDATE_CAP / SCREENING_DIVISOR,
            enough: (settings.particles / 10).max(1),
            printed: false,
        }
    }
}

/// The samples of one family a run has drawn so far, and the cost floors of those that passed the
/// screening (in no particular order): a family screened first and then searched in full draws
/// only the samples after them, and picks its candidates from all of them, one pool.
#[derive(Default)]
struct Drawn {
    count: usize,
    floors: Vec<(f64, usize)>,
}

/// Sampling, checks and the particle filter for one family, on `budget`, drawing the samples after
/// those `drawn` already (and noting them there); returns every valid candidate. With `seeds` (a
/// warm start), the samples are fitted from those earlier designs.
#[allow(clippy::too_many_arguments)]
fn run_family(
    run: &mut Run,
    stage: FamilyStage,
    family: MechanismType,
    seeds: &[Vec<f64>],
    following: bool,
    budget: Budget,
    drawn: &mut Drawn,
    report: &dyn Fn(Stage, f64, Option<f64>),
) -> Result<Vec<Candidate>, Cancelled> {
    let FamilyStage { ctx, workspace } = stage;
    let settings = &ctx.problem.settings;
    let seed = settings.seed;
    let family = family.family().stream();
    let warm = !seeds.is_empty();
    let Budget { samples: total, iterations, cap, simulated, enough, printed } = budget;
    let sampler = Sampler::new(ctx, family);
    // Weights of the stages in the progress fraction.
    let (w_sample, w_collide) = (0.6, 0.1);

    let t = Instant::now();
    let draw = |i: usize, scratch: &mut SampleScratch| {
        // Following the design shown, the samples are drawn around it alone.
        let around = if following { 1 } else { seeds.len() };
        let near = (!seeds.is_empty()).then(|| {
            let start = seeds[i % around].as_slice();
            // Following, every other sample stays close, through the poses as drawn: half of those at a
            // fifth of the jitter, half at a twenty-fifth (a design on a check's bound, whose refit
            // crosses it, is followed from just inside: the monitor's drag, 0.24 d to 0.045 d).
            if following && i % 4 == 0 {
                Near { start, jitter: WARM_JITTER / 25.0, perturbed: false }
            } else if following && i % 2 == 0 {
                Near { start, jitter: WARM_JITTER / 5.0, perturbed: false }
            } else {
                Near::warm(start)
            }
        });
        sampler.draw(seed, i as u64, near, scratch)
    };
    // A warm start keeps each earlier design, changed as little as the poses now need, when it is
    // still valid: the filter starts from it too, and a live redesign can follow it. That change moves
    // even a design of the same poses when it was fitted to perturbed ones (through more poses than
    // the family meets exactly, it costs more), so unless a live redesign follows the poses, each is
    // also judged as it is.
    let mut kept = Vec::new();
    if warm {
        let exact = |i: usize, scratch: &mut SampleScratch| {
            sampler.draw(seed, i as u64, Some(Near::exact(seeds[i].as_slice())), scratch)
        };
        let as_is = |i: usize, scratch: &mut SampleScratch| sampler.draw_as_is(seeds[i].as_slice(), scratch);
        let starts: &[&Draw] = if following { &[&exact] } else { &[&exact, &as_is] };
        let mut candidates = Vec::new();
        for &start in starts {
            let mut floors = screen_samples(run, stage, 0..seeds.len(), start, &|_| {})?;
            candidates.extend(simulate_cheapest(run, stage, &mut floors, seeds.len(), start, &|_| {})?);
        }
        candidates.sort_by(|a, b| a.cost.total_cmp(&b.cost));
        kept = check_in_order(run, stage, candidates, seeds.len(), run.printable, COLLISION_BATCH_CHUNKS)?;
    }
    let first = drawn.count.min(total);
    let mut floors = std::mem::take(&mut drawn.floors);
    floors.extend(screen_samples(run, stage, first..total, &draw, &|x| {
        report(Stage::Sampling, w_sample * SCREENING_SHARE * x, None)
    })?);
    let simulated = simulated.min(floors.len());
    if simulated < floors.len() {
        floors.select_nth_unstable_by(simulated, by_floor);
        run.rejected[Reject::Outclassed as usize] += floors.len() - simulated;
    }
    let candidates = simulate_cheapest(run, stage, &mut floors[..simulated], cap, &draw, &|x| {
        report(Stage::Sampling, w_sample * (SCREENING_SHARE + (1.0 - SCREENING_SHARE) * x), None)
    })?;
    *drawn = Drawn { count: total.max(first), floors };
    run.stats.samples += total - first;
    run.stats.seconds_sampling += t.elapsed().as_secs_f64();

    let t = Instant::now();
    let printable = if printed { run.printable } else { None };
    let mut valid = check_in_order(run, stage, candidates, enough, printable, COLLISION_BATCH_CHUNKS)?;
    valid.splice(0..0, kept);
    run.stats.valid += valid.len();
    run.stats.seconds_collision += t.elapsed().as_secs_f64();
    let best = valid.iter().map(|c| c.cost).reduce(f64::min);
    report(Stage::Collision, w_sample + w_collide, best);

    let t = Instant::now();
    if !valid.is_empty() && iterations > 0 && settings.particles > 0 {
        let options = FilterOptions { particles: settings.particles, iterations, ..FilterOptions::default() };
        let mut cancelled = false;
        // No more than the collision check passes on: the candidates found valid are what the designs
        // are picked from, and each carries its travel (memory grows with particles × iterations).
        let keep = (VALID_PER_PARTICLE * settings.particles).min(CANDIDATE_CAP);
        let produced = refine(ctx, workspace, &valid, &options, (seed, family), keep, |done, best| {
            let x = w_sample + w_collide + (1.0 - w_sample - w_collide) * done as f64 / options.iterations as f64;
            report(Stage::Refining, x, Some(best));
            cancelled = run.observer.cancelled();
            !cancelled
        });
        if cancelled {
            return Err(Cancelled);
        }
        valid.extend(produced);
    }
    run.stats.seconds_pfo += t.elapsed().as_secs_f64();
    Ok(valid)
}

/// Draws the samples of `range` and runs the checks that need no simulation: returns each passing
/// sample's floor under its cost with its index, in no particular order (a NaN floor bounds nothing
/// and is returned as −∞). Counts fitted samples and rejects.
fn screen_samples(
    run: &mut Run,
    stage: FamilyStage,
    range: std::ops::Range<usize>,
    draw: &Draw,
    report: &dyn Fn(f64),
) -> Result<Vec<(f64, usize)>, Cancelled> {
    let FamilyStage { ctx, workspace } = stage;
    let mut floors = Vec::new();
    let (first, total) = (range.start, range.end);
    for start in range.step_by(CHUNK) {
        run.go_on()?;
        let end = (start + CHUNK).min(total);
        let results: Vec<Option<Result<f64, Reject>>> = (start..end)
            .into_par_iter()
            .map_init(
                || (workspace.sampling.take(), workspace.judging.take()),
                |(sample_scratch, buffers), i| {
                    if !draw(i, sample_scratch) {
                        return None;
                    }
                    Some(cost_floor(
                        ctx,
                        sample_scratch.mechanism(),
                        Some(sample_scratch.motions()),
                        &mut buffers.evaluation,
                    ))
                },
            )
            .collect();
        for (i, r) in (start..end).zip(results) {
            let Some(r) = r else { continue };
            run.stats.fitted += 1;
            match r {
                Ok(floor) => floors.push((if floor.is_nan() { f64::NEG_INFINITY } else { floor }, i)),
                Err(reject) => run.reject(reject),
            }
        }
        report((end - first) as f64 / (total - first) as f64);
    }
    Ok(floors)
}

/// The order samples are simulated in: lowest floor first, then lowest index (a total order: no two
/// samples tie).
fn by_floor(a: &(f64, usize), b: &(f64, usize)) -> std::cmp::Ordering {
    a.0.total_cmp(&b.0).then(a.1.cmp(&b.1))
}

/// Puts the first `upto` of `floors` in their places in [`by_floor`] order, the first `sorted` being
/// there already: the smallest [`SORT_BLOCK`] of the rest are selected and sorted at a time. The
/// simulation stops long before the last floor (the sofa bed: after about 3,000 of 56,000), and
/// sorting them all would cost about 2% of its instructions (`valgrind --tool=callgrind linkwright
/// design examples/k1_sofa_bed.json --threads 1 --no-print-check`).
fn sort_ahead(floors: &mut [(f64, usize)], sorted: &mut usize, upto: usize) {
    while *sorted < upto.min(floors.len()) {
        let rest = &mut floors[*sorted..];
        let take = SORT_BLOCK.min(rest.len());
        if take < rest.len() {
            rest.select_nth_unstable_by(take - 1, by_floor);
        }
        rest[..take].sort_unstable_by(by_floor);
        *sorted += take;
    }
}

/// The `cap` cheapest defect-free candidates among the screened samples (`floors`, as
/// [`screen_samples`] gives them; reordered), cheapest first, ties in sample order.
///
/// Samples are simulated lowest floor first ([`by_floor`]), and the simulation stops at the first
/// floor above the costliest kept candidate once the cap is reached: every later sample's cost is at
/// least its floor, so none could enter. The result is the set a simulation of every sample would
/// keep, but only the samples with a floor under the final bar are simulated (on the sofa bed about a
/// quarter of what a pass in sample order would). Chunks change only how far past that
/// bar the simulation runs, never the result, so threads never change it.
///
/// Each sample is drawn again rather than kept from the screening: keeping every screened mechanism
/// costs more memory, and so time, than redrawing the few simulated (docs/performance.md, "Memory is
/// time here").
fn simulate_cheapest(
    run: &mut Run,
    stage: FamilyStage,
    floors: &mut [(f64, usize)],
    cap: usize,
    draw: &Draw,
    report: &dyn Fn(f64),
) -> Result<Vec<Candidate>, Cancelled> {
    let FamilyStage { ctx, workspace } = stage;
    // Boxed, so that sorting after each chunk moves pointers, not whole candidates.
    let mut candidates: Vec<(f64, usize, Box<Candidate>)> = Vec::new();
    let (mut done, mut sorted) = (0, 0);
    while done < floors.len() {
        run.go_on()?;
        let bar = if candidates.len() >= cap { candidates[cap - 1].0 } else { f64::INFINITY };
        // The floors ascend: everything from the first one above the bar on is outclassed.
        sort_ahead(floors, &mut sorted, done + SIMULATION_CHUNK);
        let end = done + floors[done..sorted].partition_point(|&(floor, _)| floor <= bar).min(SIMULATION_CHUNK);
        if end == done {
            break;
        }
        // Draws are deterministic: each sample here was fitted at the screening, and is again.
        let results: Vec<Option<(Result<Candidate, Reject>, usize)>> = floors[done..end]
            .par_iter()
            .map_init(
                || (workspace.sampling.take(), workspace.judging.take()),
                |(sample_scratch, buffers), &(_, i)| {
                    if !draw(i, sample_scratch) {
                        return None;
                    }
                    let mechanism = sample_scratch.mechanism().clone();
                    Some((evaluate(ctx, mechanism, Some(sample_scratch.motions()), bar, &mut buffers.evaluation), i))
                },
            )
            .collect();
        for (r, i) in results.into_iter().flatten() {
            match r {
                Ok(c) => {
                    run.stats.candidates += 1;
                    candidates.push((c.cost, i, Box::new(c)));
                }
                Err(reject) => run.reject(reject),
            }
        }
        candidates.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
        candidates.truncate(cap);
        done = end;
        report(done as f64 / floors.len() as f64);
    }
    run.rejected[Reject::Outclassed as usize] += floors.len() - done;
    Ok(candidates.into_iter().map(|(_, _, c)| *c).collect())
}

/// The collision-free (and, with a `printable` check, printable) candidates among `candidates`, checked
/// in order chunk by chunk until `enough` are valid.
///
/// Up to `batch_chunks` chunks are swept in one parallel batch, as many as the valid rate so far says
/// are still needed (fewer waits for a batch's last sweep); only the chunks the rule asks for are
/// taken, so the batch's size changes no result.
fn check_in_order(
    run: &mut Run,
    stage: FamilyStage,
    candidates: Vec<Candidate>,
    enough: usize,
    printable: Option<&dyn Acceptance>,
    batch_chunks: usize,
) -> Result<Vec<Candidate>, Cancelled> {
    let FamilyStage { ctx, workspace } = stage;
    let chunk = collision_chunk(enough);
    let mut valid = Vec::new();
    let mut queue = candidates.into_iter().peekable();
    let mut swept = 0;
    while queue.peek().is_some() && valid.len() < enough {
        run.go_on()?;
        let chunks = if swept == 0 {
            1
        } else {
            let rate = (valid.len() as f64 / swept as f64).max(1.0 / chunk as f64);
            (((enough - valid.len()) as f64 / (rate * chunk as f64)).ceil() as usize).clamp(1, batch_chunks)
        };
        let batch: Vec<Candidate> = queue.by_ref().take(chunks * chunk).collect();
        let mut checked = batch
            .into_par_iter()
            .map_init(
                || workspace.judging.take(),
                |buffers, c| {
                    check_collisions(ctx, &c, &mut buffers.sweep).map_err(Err)?;
                    match printable {
                        Some(check) => mark_printable(check, c).map_err(Ok),
                        None => Ok(c),
                    }
                },
            )
            .collect::<Vec<Result<Candidate, Result<Refused, Reject>>>>()
            .into_iter()
            .peekable();
        while checked.peek().is_some() && valid.len() < enough {
            for r in checked.by_ref().take(chunk) {
                swept += 1;
                match r {
                    Ok(c) => valid.push(c),
                    Err(Ok((reject, c))) => run.refuse(reject, c),
                    Err(Err(reject)) => run.reject(reject),
                }
            }
        }
    }
    Ok(valid)
}

/// Candidates checked between two checks of the stopping rule when `enough` valid ones are wanted: a
/// warm start wants a quarter of a particle set, and a whole chunk of print checks (a few
/// milliseconds each for a slider-crank's guide) would be most of a live step's time (chunks of 16
/// halve the sofa bed's collision stage against 128, `stats.seconds.collision` of `linkwright design
/// --from`).
fn collision_chunk(enough: usize) -> usize {
    enough.clamp(16, COLLISION_CHUNK).next_power_of_two()
}

/// How far some joint must move for two designs of one family to be distinct ([`DISTINCT`]·d).
fn min_shift(problem: &Problem) -> f64 {
    DISTINCT * problem.bodies.iter().map(|b| b.size).fold(f64::INFINITY, f64::min)
}

/// True when two designs differ: another family, or some joint moved by more than `min_shift`.
fn distinct(a: &Candidate, b: &Candidate, min_shift: f64) -> bool {
    let (ma, mb) = (&a.mechanism, &b.mechanism);
    ma.topology.mechanism_type != mb.topology.mechanism_type || moved(&ma.joints, &mb.joints, min_shift)
}

/// True when some joint of one family's design moved by more than `min_shift` between `a` and `b`.
fn moved(a: &[Point], b: &[Point], min_shift: f64) -> bool {
    a.iter().zip(b).any(|(p, q)| p.distance(*q) > min_shift)
}

/// How many missing pinned joints a reason names.
const MISSING_PINS_NAMED: usize = 10;

/// What to tell the person when nothing valid was found: the checks that rejected most, each with
/// what to change.
fn no_solution_reason(problem: &Problem, stats: &RunStats) -> String {
    if families(problem).is_empty() {
        let joints = |family: MechanismType| {
            let topology = family.family().topology(problem.body_count());
            format!("the {} has {}", family.linkage_label(problem.body_count()), topology.joint_names.join(", "))
        };
        let chosen = chosen_families(problem);
        let missing = chosen.first().map(|&f| pinned_joints_missing(problem, f)).unwrap_or_default();
        // The first few names say what is wrong; every one of up to 256 would fill a screen.
        let missing = match missing.len() {
            n if n > MISSING_PINS_NAMED => {
                format!("{} and {} more", missing[..MISSING_PINS_NAMED].join(", "), n - MISSING_PINS_NAMED)
            }
            _ => missing.join(", "),
        };
        return format!(
            "No linkage type tried has every pinned joint ({missing} missing): pinned_joints names joints as a \
             design's mechanism.joints does; {}.",
            chosen.into_iter().map(joints).collect::<Vec<_>>().join("; ")
        );
    }
    let must_hit = problem.must_hit.iter().filter(|&&hit| hit).count();
    let most_exact = families(problem)
        .into_iter()
        .map(|family| family.family().max_exact_poses(problem.body_count()))
        .max()
        .unwrap_or(0);
    if must_hit > most_exact {
        return format!(
            "{must_hit} poses must be hit (the first, the last and must_hit_poses), but these linkages pass at \
             most {most_exact} poses exactly: mark fewer must_hit_poses."
        );
    }
    // A pose drawn on another explains a search with no design better than what the samples met.
    let repeated = problem.bodies.iter().find_map(|b| b.repeated_poses().first().map(|&(i, j)| (b, i, j)));
    if let Some((body, i, j)) = repeated {
        let words = crate::scene::repeated_pose_words(body, i, j);
        return format!("No linkage found: {words}.");
    }
    if stats.fitted == 0 {
        return format!(
            "No linkage could be fitted through the poses ({} samples): the poses may ask for a motion no \
             linkage of this type makes. Raise settings.pose_tolerance (now {}), move the intermediate poses \
             closer to a smooth path, or widen the linkage_region.",
            stats.samples, problem.settings.pose_tolerance
        );
    }
    let mut counts: Vec<(Reject, usize)> =
        stats.rejected.iter().copied().filter(|&(r, _)| r != Reject::Outclassed).collect();
    // Designs refused only because they cannot be printed came closest: say so first.
    counts.sort_by_key(|&(r, n)| (r != Reject::Unprintable, std::cmp::Reverse(n)));
    let advice = |r: Reject| match r {
        Reject::JointsTooClose => "joints fell too close together to build (two pins need room): widen the \
                                   linkage_region, draw the object larger, or print with narrower links and pins"
            .to_string(),
        Reject::Order => "linkages visited the poses out of order: check the order of the poses, or add an \
                          intermediate pose that shows the way"
            .to_string(),
        Reject::Branch => "linkages would have to be taken apart between poses (branch or circuit defect): \
                           add an intermediate pose where the body turns most, or raise settings.pose_tolerance"
            .to_string(),
        Reject::Assembly => "linkages locked up between poses: add an intermediate pose or raise \
                             settings.pose_tolerance"
            .to_string(),
        Reject::Transmission => format!(
            "linkages came too close to a dead point (transmission angle under {}°): widen the linkage_region, \
             or lower settings.min_transmission_deg",
            problem.settings.min_transmission_deg
        ),
        Reject::MissedPose => {
            let marked = problem.must_hit.iter().filter(|&&hit| hit).count() > 2;
            format!(
                "linkages passed a pose they must hit away from it (a link turned over on the way): add an \
                 intermediate pose where the body turns most, or move the linkage_region{}",
                if marked { ", or mark fewer must_hit_poses" } else { "" }
            )
        }
        Reject::AvoidRegion => "links crossed an avoid region: shrink the avoid_regions or move the \
                                linkage_region away from them"
            .to_string(),
        Reject::Collision => "moving bodies hit a fixed body or each other on the way: give them more \
                              clearance, or add intermediate poses that steer around the obstacle"
            .to_string(),
        Reject::Unprintable => "valid linkages could not be printed with these print settings (no room for \
                                the connectors, links larger than the print bed, or no order of the links in \
                                depth avoids every collision): move the linkage_region closer to the bodies, use \
                                a larger bed or narrower links in the print settings, or allow links on both \
                                faces"
            .to_string(),
        Reject::Outclassed => unreachable!("filtered out above"),
    };
    let parts: Vec<String> = counts.iter().take(2).map(|&(r, n)| format!("{n} {}", advice(r))).collect();
    format!(
        "No valid linkage among {} samples ({} fitted): {}. More samples (settings.samples) may also help.",
        stats.samples,
        stats.fitted,
        parts.join("; ")
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::synth::collision::SweepBuffers;
    use crate::synth::testing::{defect_free, example};

    impl Run<'static> {
        /// A run with no printability check, that nobody follows.
        fn quiet() -> Self {
            Run {
                printable: None,
                observer: &Silent,
                stats: RunStats::default(),
                rejected: [0; Reject::ALL.len()],
                refused: None,
            }
        }
    }

    /// A stand-in print check whose verdict a test knows beforehand: it refuses the designs whose
    /// joints it lists (every design when `everything`), and notes the joints of each design checked.
    #[derive(Debug, Default)]
    struct Refusing {
        joints: Vec<Vec<Point>>,
        everything: bool,
        checked: std::sync::Mutex<Vec<Vec<Point>>>,
    }

    impl Refusing {
        fn calls(&self) -> usize {
            self.checked.lock().unwrap().len()
        }
    }

    impl Acceptance for Refusing {
        fn min_joint_spacing(&self) -> f64 {
            0.0
        }
        fn accepts(&self, mechanism: &Mechanism, _: &Trace) -> bool {
            self.checked.lock().unwrap().push(mechanism.joints.clone());
            !self.everything && !self.joints.contains(&mechanism.joints)
        }
    }

    /// A screened family ranks by its cheapest printable design, the one checking the designs one
    /// after the other in cost order finds when it passes over those near a design refused: the
    /// batches check no two neighbours, every cheaper design leaves, every costlier one stays unless
    /// it was refused, and no more than [`SCREENED_PRINT_CHECKS`] are checked, even when none passes.
    #[test]
    fn a_screened_family_ranks_by_its_cheapest_printable_design() {
        let mut problem = example("k1_sofa_bed");
        problem.settings.samples = 3_000;
        let ctx = Context::new(&problem, MechanismType::SliderCrank);
        let sampler = Sampler::new(&ctx, MechanismType::SliderCrank.family().stream());
        let mut designs: Vec<Candidate> = defect_free(&ctx, &sampler, problem.settings.seed, 0..3_000).collect();
        assert!(designs.len() > 2 * SCREENED_PRINT_CHECKS, "{} designs", designs.len());
        designs.sort_by(|a, b| a.cost.total_cmp(&b.cost));
        // The four cheapest designs fail; second comes one that would pass, a hair from the cheapest.
        let check = Refusing {
            joints: designs[..4].iter().map(|c| c.mechanism.joints.clone()).collect(),
            ..Default::default()
        };
        let mut beside = designs[0].clone();
        beside.mechanism.joints[0].x += 0.01 * min_shift(&problem);
        beside.cost = 0.5 * (designs[0].cost + designs[1].cost);
        designs.insert(1, beside.clone());
        let passes = |c: &Candidate| !check.joints.contains(&c.mechanism.joints);
        assert!(passes(&beside));
        let near = |a: &[Point], b: &[Point]| !moved(a, b, min_shift(&problem));
        // One design after the other.
        let mut refused: Vec<&Candidate> = Vec::new();
        let mut one_by_one = None;
        for c in &designs {
            if refused.iter().any(|r| near(&r.mechanism.joints, &c.mechanism.joints)) {
                continue;
            }
            if passes(c) {
                one_by_one = Some(c);
                break;
            }
            refused.push(c);
        }
        let one_by_one = one_by_one.expect("a design passes");

        let mut run = Run::quiet();
        run.printable = Some(&check);
        let ranked = printable_first(&problem, &mut run, designs.clone()).unwrap();
        let first = &ranked[0];
        assert!(first.printable && first.mechanism.joints == one_by_one.mechanism.joints);
        assert!(ranked.iter().all(|c| c.mechanism.joints != beside.mechanism.joints));
        assert!(ranked[1..].iter().all(|c| c.cost >= first.cost));
        let checked = check.checked.lock().unwrap().clone();
        for c in designs.iter().filter(|c| c.cost > first.cost) {
            let stays = ranked.iter().any(|r| r.mechanism.joints == c.mechanism.joints);
            assert!(stays || (!passes(c) && checked.contains(&c.mechanism.joints)), "a costlier design left");
        }
        for (i, a) in checked.iter().enumerate() {
            assert!(checked[..i].iter().all(|b| !near(a, b)), "a neighbour of a design checked was checked");
        }
        assert!(
            checked.len() > SCREENED_PRINT_BATCH && checked.len() <= SCREENED_PRINT_CHECKS,
            "{} checks",
            checked.len()
        );
        let refusals = checked.iter().filter(|j| check.joints.contains(j)).count();
        assert_eq!(run.rejected[Reject::Unprintable as usize], refusals);

        // A check nothing passes: no design is left, after a bounded number of checks.
        let nothing = Refusing { everything: true, ..Default::default() };
        let mut run = Run::quiet();
        run.printable = Some(&nothing);
        assert!(printable_first(&problem, &mut run, designs.clone()).unwrap().is_empty());
        let refused = run.rejected[Reject::Unprintable as usize];
        assert_eq!(nothing.calls(), refused);
        assert!(refused > 0 && refused <= SCREENED_PRINT_CHECKS);
    }

    /// Checking collisions in batches of several chunks keeps exactly the candidates, and counts
    /// exactly the rejects, of checking one chunk at a time: where a first chunk poor in valid
    /// candidates makes the batch reach far past where the stopping rule ends, and where every
    /// candidate is checked.
    #[test]
    fn batched_collision_checks_keep_what_chunk_by_chunk_checks_keep() {
        let mut problem = example("k1_sofa_bed");
        problem.settings.samples = 6_000;
        let ctx = Context::new(&problem, MechanismType::SliderCrank);
        let sampler = Sampler::new(&ctx, MechanismType::SliderCrank.family().stream());
        let (mut valid, mut colliding): (Vec<Candidate>, Vec<Candidate>) =
            defect_free(&ctx, &sampler, problem.settings.seed, 0..problem.settings.samples as u64)
                .partition(|c| check_collisions(&ctx, c, &mut SweepBuffers::default()).is_ok());
        assert!(valid.len() > 100 && colliding.len() > 2 * COLLISION_CHUNK, "{} valid", valid.len());
        // A first chunk with one valid candidate, then the rest mixed.
        let mut candidates: Vec<Candidate> = colliding.drain(..COLLISION_CHUNK - 1).collect();
        candidates.push(valid.pop().unwrap());
        candidates.extend(valid.into_iter().zip(colliding).flat_map(|(v, c)| [v, c]));
        let key = |c: &Candidate| (c.cost.to_bits(), c.mechanism.joints.clone());
        for enough in [40, 100, usize::MAX] {
            let run = |batch_chunks| {
                let mut run = Run::quiet();
                let workspace = Workspace::default();
                let stage = FamilyStage { ctx: &ctx, workspace: &workspace };
                let valid = check_in_order(&mut run, stage, candidates.clone(), enough, None, batch_chunks).unwrap();
                (valid.iter().map(key).collect::<Vec<_>>(), run.rejected)
            };
            let (one, many) = (run(1), run(8));
            assert!(one.0.len() >= enough.min(100), "{} valid", one.0.len());
            assert_eq!(one, many, "enough = {enough}");
        }
    }

    /// Sorting ahead block by block puts every prefix asked for in the order of a full sort: equal
    /// floors (many here) by index, infinite floors first, across several blocks and uneven steps.
    #[test]
    fn floors_sorted_ahead_are_a_full_sorts_prefix() {
        use rand::{RngExt, SeedableRng};
        let mut rng = rand_xoshiro::Xoshiro256PlusPlus::seed_from_u64(5);
        let count = 3 * SORT_BLOCK + 123;
        let mut floors: Vec<(f64, usize)> = (0..count)
            .map(|i| {
                let floor = match i % 50 {
                    0 => f64::NEG_INFINITY,
                    1..=20 => rng.random_range(0..40) as f64,
                    _ => rng.random_range(0.0..40.0),
                };
                (floor, i)
            })
            .collect();
        // Shuffled, so that indices do not ascend with position.
        for i in (1..count).rev() {
            floors.swap(i, rng.random_range(0..=i));
        }
        let mut full = floors.clone();
        full.sort_by(by_floor);
        let mut sorted = 0;
        let mut upto = 0;
        while upto < count {
            upto += rng.random_range(1..SORT_BLOCK / 3);
            sort_ahead(&mut floors, &mut sorted, upto);
            assert!(sorted >= upto.min(count));
            assert_eq!(floors[..sorted], full[..sorted]);
        }
        assert_eq!(floors, full);
    }

    /// Simulating lowest floor first and stopping at the bar keeps exactly the candidates a simulation
    /// of every sample keeps, while simulating fewer. The cap is large enough that the stopping rule
    /// runs for several chunks after the cap fills (stopping at 0.95 of the bar fails this test).
    #[test]
    fn cheapest_candidates_are_those_of_a_full_simulation() {
        let mut problem = example("k1_sofa_bed");
        problem.settings.samples = 12_000;
        let ctx = Context::new(&problem, MechanismType::SliderCrank);
        let sampler = Sampler::new(&ctx, MechanismType::SliderCrank.family().stream());
        let seed = problem.settings.seed;
        let draw = |i: usize, scratch: &mut SampleScratch| sampler.draw(seed, i as u64, None, scratch);
        let cap = 1000;

        // Every sample simulated, the cheapest `cap` kept (ties in sample order).
        let mut all: Vec<Candidate> = defect_free(&ctx, &sampler, seed, 0..problem.settings.samples as u64).collect();
        all.sort_by(|a, b| a.cost.total_cmp(&b.cost));
        all.truncate(cap);

        let mut run = Run::quiet();
        let workspace = Workspace::default();
        let stage = FamilyStage { ctx: &ctx, workspace: &workspace };
        let mut floors = screen_samples(&mut run, stage, 0..problem.settings.samples, &draw, &|_| {}).unwrap();
        let kept = simulate_cheapest(&mut run, stage, &mut floors, cap, &draw, &|_| {}).unwrap();
        let rejected = run.rejected;
        assert_eq!(kept.len(), cap);
        for (k, c) in kept.iter().zip(&all) {
            assert_eq!(k.cost, c.cost);
            assert_eq!(k.mechanism.joints, c.mechanism.joints);
        }
        // Most screened samples were never simulated, but every one whose floor is under the final
        // bar was (the floors can be far below the costs, so a stop too early may keep the same set
        // here and lose candidates elsewhere).
        let outclassed = rejected[Reject::Outclassed as usize];
        assert!(outclassed > floors.len() / 2, "{outclassed} of {} screened outclassed", floors.len());
        let under_bar = floors.iter().filter(|&&(floor, _)| floor <= kept[cap - 1].cost).count();
        assert!(floors.len() - outclassed >= under_bar, "{under_bar} under the bar, {outclassed} outclassed");
    }

    /// A family screened beside a run adds its counts to the run's, and of the designs the print
    /// check refused, the run keeps the cheapest, its own on a tie (the first found, as when the
    /// families are screened one after the other).
    #[test]
    fn a_run_beside_another_adds_its_counts_and_keeps_the_cheapest_refused() {
        let problem = example("k1_sofa_bed");
        let ctx = Context::new(&problem, MechanismType::SliderCrank);
        let sampler = Sampler::new(&ctx, MechanismType::SliderCrank.family().stream());
        let designs: Vec<Candidate> = defect_free(&ctx, &sampler, problem.settings.seed, 0..3_000).take(3).collect();
        assert_eq!(designs.len(), 3);
        let mut run = Run::quiet();
        run.stats.samples = 100;
        run.stats.valid = 7;
        run.stats.seconds_pfo = 0.5;
        run.rejected[Reject::Collision as usize] = 3;
        let mut tied = designs[1].clone();
        tied.cost = designs[0].cost;
        run.refuse(Reject::Unprintable, Box::new(designs[0].clone()));
        let mut beside = run.beside();
        assert_eq!(
            (beside.stats.clone(), beside.rejected, beside.refused.is_none()),
            (RunStats::default(), [0; Reject::ALL.len()], true)
        );
        beside.stats.samples = 12;
        beside.stats.valid = 2;
        beside.stats.seconds_pfo = 0.25;
        beside.rejected[Reject::Collision as usize] = 4;
        beside.refuse(Reject::Unprintable, Box::new(tied.clone()));
        run.absorb(beside);
        assert_eq!((run.stats.samples, run.stats.valid, run.stats.seconds_pfo), (112, 9, 0.75));
        assert_eq!(run.rejected[Reject::Collision as usize], 7);
        assert_eq!(run.rejected[Reject::Unprintable as usize], 2);
        assert_eq!(run.refused.as_ref().map(|c| &c.mechanism.joints), Some(&designs[0].mechanism.joints));
        // A cheaper refused design beside the run replaces the run's.
        let mut cheaper = designs[2].clone();
        cheaper.cost = 0.5 * designs[0].cost;
        let mut beside = run.beside();
        beside.refuse(Reject::Unprintable, Box::new(cheaper.clone()));
        run.absorb(beside);
        assert_eq!(run.refused.map(|c| c.mechanism.joints), Some(cheaper.mechanism.joints));
    }
}

//! From linkages fitted to a drawn curve to designs: each placed so its tracer starts where the body
//! is drawn, judged by the same re-simulation a design file's check runs, and costed like a pose
//! design, its accuracy the distance between the curves.

use super::four_bar::FourBar;
use super::linkage::{PathLinkage, Similarity, TracerAt};
use super::search::{fit, reversals, PathFit, PathGoal, PathPose};
use super::six_bars::{StephensonThree, WattTwo};
use super::slider_crank::SliderCrank;
use crate::geom::{nearest, Point};
use crate::kinematics::{Plan, Trace};
use crate::mechanism::Mechanism;
use crate::scene::{MechanismChoice, MechanismType, PathTarget, Problem};
use crate::synth::context::Context;
use crate::synth::evaluate::{exact_terms, Candidate};
use crate::synth::terms::{transmission_shortfall, CostWeights, Term};
use crate::verify::{verify_travel, Travel, Violation};
use rayon::prelude::*;
use std::f64::consts::{PI, TAU};

/// How much more the path's accuracy weighs than the scene's accuracy weight says of poses: with the
/// default weights a mean distance of 1% of the curve's size costs 100, as much as every joint ten
/// curve sizes outside the linkage region, so the path comes first and compactness decides between
/// designs that trace it alike.
const PATH_ACCURACY_EMPHASIS: f64 = 100.0;
/// Linkages of each family the atlas's best matches are refined into, and then judged.
const REFINED: usize = 24;
/// The families `auto` tries for a path, in order. A Watt-II's tracer runs along an arc of its
/// body's four-bar's coupler curve, and a four-bar traces such an arc alone: it adds a curve of its
/// own only where the tracer comes back the way it went, so it is tried where the drawn curve
/// `turns_back`.
fn path_families(turns_back: bool) -> &'static [MechanismType] {
    if turns_back {
        &[MechanismType::Chain, MechanismType::StephensonThree, MechanismType::SliderCrank, MechanismType::WattTwo]
    } else {
        &[MechanismType::Chain, MechanismType::StephensonThree, MechanismType::SliderCrank]
    }
}
/// The share of the scene's atlas samples each family gets when `auto` tries several: half as many
/// as one family alone, which traces `bench --paths --quick` as closely in two thirds of the time.
const AUTO_SAMPLE_SHARE: usize = 2;
/// A design differs from another when some joint is farther than this fraction of the path's size
/// from its place in the other.
const DISTINCT: f64 = 0.02;

/// A test every design must pass besides the hard constraints (the print check).
pub(crate) type Accepts<'a> = dyn Fn(&Mechanism, &Trace) -> bool + Sync + 'a;

/// What a path search found.
#[derive(Debug, Default)]
pub(crate) struct PathDesigns {
    /// Valid designs, cheapest first, each distinct from those before it.
    pub designs: Vec<Candidate>,
    /// The cheapest valid design the acceptance test refused, when it refused every one.
    pub refused: Option<Candidate>,
    /// Linkages fitted to the curve (each then judged).
    pub fitted: usize,
    /// What the closest fitted linkage that failed a hard constraint broke first.
    pub closest_violation: Option<Violation>,
}

/// Designs whose tracer follows `problem`'s path: `samples` atlas linkages of each family the scene
/// allows under its seed, at most `wanted` designs, each passing `accepts` (the print check) when
/// given.
pub(crate) fn path_designs(problem: &Problem, samples: usize, wanted: usize, accepts: Option<&Accepts>) -> PathDesigns {
    let Some(path) = problem.path() else { return PathDesigns::default() };
    let start = problem.bodies[0].poses[0].apply(path.tracer);
    let drawn = starting_at(path, start);
    // Found once: they choose the families, and every family's refinement measures from them.
    let turns_back = reversals(&drawn, path.closed);
    // The body's drawn place is where the design's tracer starts, so the whole linkage moves by how
    // far its curve passes from there. With later poses, every pose is held (the first, where the
    // body starts, with no turn); with exact points only, that place is held like them.
    let body = &problem.bodies[0];
    let poses: Vec<PathPose> = match body.poses.len() {
        1 => Vec::new(),
        _ => body
            .poses
            .iter()
            .map(|pose| PathPose { tracer: pose.apply(path.tracer), turn: pose.angle() - body.poses[0].angle() })
            .collect(),
    };
    let mut exact: Vec<Point> = path.exact.iter().map(|&i| path.points[i]).collect();
    if !exact.is_empty() && poses.is_empty() {
        exact.push(start);
    }
    let goal = PathGoal {
        drawn: &drawn,
        closed: path.closed,
        min_transmission_sine: problem.settings.min_transmission_deg.to_radians().sin(),
        reversals: &turns_back,
        exact: &exact,
        poses: &poses,
        body_size: body.size,
    };
    let (families, samples) = match problem.mechanism {
        MechanismChoice::Auto => (path_families(!turns_back.is_empty()).to_vec(), samples / AUTO_SAMPLE_SHARE),
        MechanismChoice::Only(family) => (vec![family], samples),
    };
    let mut out = PathDesigns::default();
    let mut judgements = Vec::new();
    for family in families {
        let judge = match family {
            MechanismType::Chain => judge_family::<FourBar>,
            MechanismType::StephensonThree => judge_family::<StephensonThree>,
            MechanismType::SliderCrank => judge_family::<SliderCrank>,
            MechanismType::WattTwo => judge_family::<WattTwo>,
        };
        judgements.extend(judge(problem, &goal, samples, (start, &poses)));
    }
    out.fitted = judgements.len();
    let mut valid: Vec<Candidate> = Vec::new();
    for judgement in judgements {
        match judgement {
            Ok(c) => valid.push(c),
            Err(v) => {
                out.closest_violation.get_or_insert(v);
            }
        }
    }
    // Stable: equal costs keep the fits' order.
    valid.sort_by(|a, b| a.cost.total_cmp(&b.cost));
    let min_shift = DISTINCT * path.size;
    for mut c in valid {
        if out.designs.len() >= wanted {
            break;
        }
        let apart = |p: &Candidate| {
            p.mechanism.topology.mechanism_type != c.mechanism.topology.mechanism_type
                || p.mechanism.joints.iter().zip(&c.mechanism.joints).any(|(a, b)| a.distance(*b) > min_shift)
        };
        if !out.designs.iter().all(apart) {
            continue;
        }
        if let Some(accepts) = accepts {
            if !accepts(&c.mechanism, &c.trace) {
                out.refused.get_or_insert(c);
                continue;
            }
            c.printable = true;
        }
        out.designs.push(c);
    }
    if !out.designs.is_empty() {
        out.refused = None;
    }
    out
}

/// The drawn curve as the tracer runs it from `start`: an open curve as drawn, a closed one begun at
/// its point nearest `start`.
fn starting_at(path: &PathTarget, start: Point) -> Vec<Point> {
    if !path.closed {
        return path.points.clone();
    }
    let n = path.points.len();
    let (_, on, edge) = nearest(start, &path.points, true);
    let mut out = Vec::with_capacity(n + 1);
    out.push(on);
    out.extend((1..=n).map(|k| path.points[(edge + k) % n]).filter(|p| p.distance(on) > 0.0));
    out
}

/// The crank angle, within half a turn of `theta`, where `linkage`'s tracer passes nearest `point`
/// ([`nearest_along`]), or `theta` itself if no nearer.
fn nearest_angle<L: PathLinkage>(linkage: &L, point: Point, theta: f64) -> f64 {
    let at = |t: f64| linkage.tracer_at(t);
    let distance = |t: f64| at(t).map_or(f64::INFINITY, |c| c.point.distance(point));
    let best = nearest_along(&at, point, (theta - PI, theta + PI));
    if distance(best) <= distance(theta) {
        best
    } else {
        theta
    }
}

/// Where `distance` is least between crank angles `a` and `b` (either order), to a thousandth of a
/// degree, by golden sections: near its least a tracer's distance from a point is smooth.
fn golden(distance: &dyn Fn(f64) -> f64, a: f64, b: f64) -> f64 {
    const GOLDEN: f64 = 0.618_033_988_749_894_9;
    let (mut lo, mut hi) = (a.min(b), a.max(b));
    while hi - lo > 1e-3 * 1f64.to_radians() {
        let (a, b) = (hi - GOLDEN * (hi - lo), lo + GOLDEN * (hi - lo));
        if distance(a) <= distance(b) {
            hi = b;
        } else {
            lo = a;
        }
    }
    0.5 * (lo + hi)
}

/// Members of family `L` fitted to `goal` and judged as designs, closest fit first.
fn judge_family<L: PathLinkage>(
    problem: &Problem,
    goal: &PathGoal,
    samples: usize,
    places: (Point, &[PathPose]),
) -> Vec<Result<Candidate, Violation>> {
    let ctx = Context::new(problem, L::FAMILY);
    let fits = fit::<L>(goal, problem.settings.seed, samples, REFINED);
    // Judged in parallel, kept in the fits' order: the same designs whatever the thread count.
    fits.par_iter().map(|fit| judged(problem, &ctx, fit, places)).collect()
}

/// `fit` placed with its tracer exactly at `start` at the start of its travel, passing `poses` where
/// its tracer comes nearest theirs, as a design of the scene, or the first hard constraint it breaks.
fn judged<L: PathLinkage>(
    problem: &Problem,
    ctx: &Context,
    fit: &PathFit<L>,
    (start, poses): (Point, &[PathPose]),
) -> Result<Candidate, Violation> {
    let apart =
        || Violation { constraint: "assembly", message: "the linkage does not close where the path starts".into() };
    // A closed curve's travel starts where its curve passes nearest the body's place, so the shift
    // that puts the tracer there moves the curve as little as it can.
    let fit_start = if problem.path().is_some_and(|p| p.closed) {
        nearest_angle(&fit.linkage, start, fit.theta_start)
    } else {
        fit.theta_start
    };
    let begin = fit.linkage.tracer_at(fit_start).ok_or_else(apart)?;
    let placed = fit.linkage.mapped(&Similarity::shift(start - begin.point));
    let mechanism = placed.mechanism(fit_start).ok_or_else(apart)?;
    // The travel as a design file writes it: from the crank's direction, in (−180°, 180°].
    let theta_start = mechanism.crank_start();
    let theta_start = if theta_start <= -PI { theta_start + TAU } else { theta_start };
    let theta_end = theta_start + (fit.theta_end - fit.theta_start);
    // Each later pose where the tracer passes nearest its place, along the travel (crank angles of
    // the placed linkage, which turned as the design's frame did: the same offset for all).
    let offset = theta_start - fit_start;
    let mut thetas = vec![theta_start];
    for pose in poses.iter().skip(1) {
        let placed_at = |t: f64| placed.tracer_at(t - offset);
        thetas.push(nearest_along(&placed_at, pose.tracer, (theta_start, theta_end)));
    }
    let (start_deg, end_deg) = (theta_start.to_degrees(), theta_end.to_degrees());
    let pose_degs: Vec<f64> = thetas.iter().map(|t| t.to_degrees()).collect();
    let (violations, accuracy) =
        verify_travel(problem, &mechanism, Travel { start: start_deg, end: end_deg, poses: &pose_degs });
    if let Some(v) = violations.into_iter().next() {
        return Err(v);
    }
    // A sound travel is measured: its poses' misses and its path's distance.
    let (Some(accuracy), Some(error)) = (accuracy, accuracy.and_then(|a| a.path)) else {
        return Err(Violation { constraint: "assembly", message: "the travel comes apart".into() });
    };
    let plan = Plan::compile(&mechanism).map_err(|e| Violation { constraint: "assembly", message: e.to_string() })?;
    let (trace, pose_rows) = trace_through(&plan, (theta_start, theta_end), &thetas)
        .map_err(|e| Violation { constraint: "assembly", message: e.to_string() })?;
    let mut soft = exact_terms(ctx, &mechanism);
    // The accuracy the check recomputes: the poses' misses (the first, where the body starts, met
    // exactly), the curves' mean distance and the exact points', squared like E_acc's misses.
    // Smoothness is the drawn curve's own, 1.
    soft[Term::Accuracy] = accuracy.total();
    soft[Term::Smoothness] = 1.0;
    soft[Term::Transmission] =
        transmission_shortfall(trace.min_transmission_sine(&plan), ctx.comfortable_transmission_sine);
    // Scale-free in the path, not in the body: the tracer's body may be a small foot on a stride
    // many times its size, and how far the curves are apart matters relative to the curve.
    let path_size = problem.path().map_or(ctx.body_size, |p| p.size);
    let mut weights = CostWeights::new(&problem.weights, path_size);
    weights[Term::Accuracy] *= PATH_ACCURACY_EMPHASIS;
    let cost = weights.cost(&soft);
    Ok(Candidate { mechanism, plan, trace, pose_rows, soft, cost, printable: false, path: Some(error) })
}

/// The travel from `start` to `end` at 1° steps with a row at each of the poses' angles `thetas`
/// (in order along it, the first `start`), and those rows.
fn trace_through(
    plan: &Plan,
    (start, end): (f64, f64),
    thetas: &[f64],
) -> Result<(Trace, Vec<usize>), crate::kinematics::SweepError> {
    let step = 1f64.to_radians();
    let dir = (end - start).signum();
    let steps = ((end - start).abs() / step).ceil().max(1.0) as usize;
    let mut trace = Trace::new(plan.joint_count());
    let mut rows = Vec::with_capacity(thetas.len());
    let mut next = 0;
    for k in 0..=steps {
        // The last row is `end` itself: the design file writes the travel from the rows, and its
        // check must measure the travel measured here (a path's distance depends on the sampling).
        let theta = if k == steps { end } else { start + (end - start) * k as f64 / steps as f64 };
        // The poses the grid passes (or meets) here, each a row of its own.
        while next < thetas.len() && dir * (thetas[next] - theta) <= 0.0 {
            rows.push(trace.len());
            trace.push(plan, thetas[next])?;
            next += 1;
        }
        if rows.last().is_none_or(|&r| trace.thetas[r] != theta) {
            trace.push(plan, theta)?;
        }
    }
    Ok((trace, rows))
}

/// The crank angle within `range` (from its start towards its end) where the tracer `at` passes
/// nearest `point`: the nearest of whole degrees, then to a thousandth of a degree between them.
fn nearest_along(at: &dyn Fn(f64) -> Option<TracerAt>, point: Point, (start, end): (f64, f64)) -> f64 {
    let distance = |t: f64| at(t).map_or(f64::INFINITY, |c| c.point.distance(point));
    let steps = ((end - start).abs().to_degrees().ceil() as usize).max(1);
    let angle = |k: usize| start + (end - start) * k as f64 / steps as f64;
    let best = (0..=steps).min_by(|&a, &b| distance(angle(a)).total_cmp(&distance(angle(b)))).unwrap_or(0);
    golden(&distance, angle(best.saturating_sub(1)), angle((best + 1).min(steps)))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A design file's travel is read off its trace's rows, and its check must measure what the
    /// search measured: the trace ends on the travel's end itself, and has a row at each pose's
    /// angle, in order.
    #[test]
    fn the_trace_ends_on_the_travel_and_has_a_row_at_each_pose() {
        let linkage = FourBar::known();
        let (start, end) = (0.1f64.to_radians() + 0.3, 0.3 + 178f64.to_radians());
        let mechanism = linkage.mechanism(start).expect("the crank-rocker assembles");
        let plan = Plan::compile(&mechanism).expect("a four-bar compiles");
        let poses = [start, 1.234_567, 2.0];
        for (from, to) in [(start, end), (end, start)] {
            let poses: Vec<f64> = if from < to { poses.to_vec() } else { vec![end, 2.0, 1.234_567] };
            let (trace, rows) = trace_through(&plan, (from, to), &poses).expect("it turns fully");
            assert_eq!(trace.thetas[0], from);
            assert_eq!(trace.thetas[trace.len() - 1], to, "the last row is the end itself");
            let at: Vec<f64> = rows.iter().map(|&r| trace.thetas[r]).collect();
            assert_eq!(at, poses, "a row at each pose's angle");
            let dir = (to - from).signum();
            assert!(trace.thetas.windows(2).all(|w| dir * (w[1] - w[0]) > 0.0), "in order, no row twice");
            assert!(trace.thetas.windows(2).all(|w| (w[1] - w[0]).abs() <= 1f64.to_radians() + 1e-12));
        }
    }
}

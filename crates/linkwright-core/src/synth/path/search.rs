//! Linkages whose tracer follows a drawn curve: an atlas of random members of a family whose crank
//! turns fully, each tracer's curve matched to the drawn one up to a similarity (the timing along the
//! curve free), then the best few refined on the distance between the curves itself.
//!
//! The match is the classic one of path synthesis: both curves are resampled evenly by arc length, so
//! the shape, not the crank's speed along it, is compared; a closed curve may start anywhere on the
//! other (every cyclic shift is tried), an open one is matched against arcs of the coupler curve
//! (several starts and spans). Each pair is aligned by the similarity that best maps one onto the
//! other (least squares, in closed form with complex numbers), so one normalised linkage stands for
//! every placement, size and turn of itself.

use super::linkage::{PathLinkage, Similarity};
use crate::geom::{curve_size as size, nearest, resample, resample_into, smoothed, Point, Vec2};
use crate::synth::random::{rng, Stream};
use nalgebra::{DMatrix, DVector};
use rayon::prelude::*;
use std::f64::consts::{PI, TAU};

/// Crank steps of a coupler curve in the atlas (5°).
const ATLAS_STEPS: usize = 72;
/// Points both curves are resampled to for the atlas's match.
const MATCH_POINTS: usize = 32;
/// Spans of the coupler curve, in atlas steps, an open curve is matched against (45° to 315°).
const OPEN_SPANS: [usize; 7] = [9, 18, 27, 36, 45, 54, 63];
/// Every how many atlas steps an arc matched against an open curve starts.
const OPEN_START_STEP: usize = 3;
/// Crank steps of a traced curve during the refinement, over a whole turn (2°).
const REFINE_STEPS: usize = 180;
/// Points of the drawn curve the refinement measures from.
const REFINE_POINTS: usize = 64;
/// Levenberg–Marquardt iterations of the refinement.
const REFINE_ITERATIONS: usize = 40;
/// A drawn point where the curve turns by more than this is a reversal ([`reversals`]).
const REVERSAL_DEG: f64 = 120.0;
/// How much more an exact point's distance (and a pose's miss) weighs in the refinement than a point
/// of the curve's, in turn: the linkage is first bent towards them with the curve still in view,
/// then held to them, each weight pulling a hundred times as hard as the last (the squares sum).
const EXACT_EMPHASES: [f64; 3] = [10.0, 100.0, 1000.0];
/// The most reversals the refinement measures from.
const MAX_REVERSALS: usize = 4;
/// The smoothing's half-window: this share of the drawn curve's points (see [`fit`]).
const SMOOTHING_SHARE: usize = 64;
/// Draws of an atlas sample before it is skipped (a family's draw is refused now and then: a loop
/// that would not turn fully).
const SAMPLE_DRAWS: usize = 1000;

/// What a path search is asked: the drawn curve and how the tracer runs along it.
#[derive(Clone, Copy, Debug)]
pub(crate) struct PathGoal<'a> {
    /// The curve, world coordinates, in the order the tracer should run along it.
    pub drawn: &'a [Point],
    /// Closed: the crank turns fully and the tracer goes round once per turn.
    pub closed: bool,
    /// The least sine of a transmission angle along the travel.
    pub min_transmission_sine: f64,
    /// Where the curve turns back on itself ([`reversals`]).
    pub reversals: &'a [Point],
    /// The points of the curve the tracer must pass exactly.
    pub exact: &'a [Point],
    /// Where the body starts and the poses it must pass on its way (none, or at least two).
    pub poses: &'a [PathPose],
    /// The body's size d, which a pose's miss is a fraction of.
    pub body_size: f64,
}

/// A pose a body that follows a path must also pass: where its tracer is then (on the curve), and
/// how far the body has turned since it started (radians).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct PathPose {
    pub tracer: Point,
    pub turn: f64,
}

/// A linkage fitted to a drawn curve, with the crank's travel: from `theta_start` to `theta_end`
/// (radians; a whole turn, either way, for a closed curve).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct PathFit<L> {
    pub linkage: L,
    pub theta_start: f64,
    pub theta_end: f64,
    /// The refinement's objective at the end: the mean squared distance between the curves, as a
    /// fraction of the drawn curve's size.
    pub objective: f64,
}

/// The tracer's curve of `m` from crank angle `start` to `end`, at `steps` + 1 angles; `None` where
/// the loop does not close, or transmits worse than `min_sine`.
fn traced<L: PathLinkage>(m: &L, start: f64, end: f64, steps: usize, min_sine: f64) -> Option<Vec<Point>> {
    (0..=steps)
        .map(|k| {
            let c = m.tracer_at(start + (end - start) * k as f64 / steps as f64)?;
            (c.transmission_sine >= min_sine).then_some(c.point)
        })
        .collect()
}

/// A point as a complex number (x + iy), for the similarity fit.
#[derive(Clone, Copy, Debug, Default)]
struct C(f64, f64);

impl C {
    fn of(v: Vec2) -> C {
        C(v.x, v.y)
    }
    /// conj(self)·o
    fn conj_mul(self, o: C) -> C {
        C(self.0 * o.0 + self.1 * o.1, self.0 * o.1 - self.1 * o.0)
    }
    fn norm_sq(self) -> f64 {
        self.0 * self.0 + self.1 * self.1
    }
}

/// Points less their centroid, and the centroid.
fn centred(points: &[Point], out: &mut Vec<C>) -> Point {
    let n = points.len() as f64;
    let (sx, sy) = points.iter().fold((0.0, 0.0), |(x, y), p| (x + p.x, y + p.y));
    let c = Point::new(sx / n, sy / n);
    out.clear();
    out.extend(points.iter().map(|&p| C::of(p - c)));
    c
}

/// The drawn curve, resampled and centred, as the atlas compares with it.
struct Target {
    closed: bool,
    /// Centred points in drawn order, and reversed.
    forward: Vec<C>,
    backward: Vec<C>,
    centroid: Point,
    norm_sq: f64,
}

impl Target {
    fn new(goal: &PathGoal) -> Target {
        let points = resample(goal.drawn, goal.closed, MATCH_POINTS);
        let mut forward = Vec::new();
        let centroid = centred(&points, &mut forward);
        let mut backward = forward.clone();
        backward.reverse();
        if goal.closed {
            // Reversed, a closed curve still starts at its first point.
            backward.rotate_right(1);
        }
        let norm_sq = forward.iter().map(|z| z.norm_sq()).sum();
        Target { closed: goal.closed, forward, backward, centroid, norm_sq }
    }
}

/// The best alignment found of one atlas curve onto the target.
#[derive(Clone, Copy, Debug)]
struct Match {
    /// 1 − the squared correlation of the two shapes: 0 for the same shape.
    residual: f64,
    /// The similarity, as `z = alpha·(w − w_centroid) + target centroid`.
    alpha: C,
    w_centroid: Point,
    /// The crank angle (normalised frame) where the tracer starts, the travel's signed span.
    theta_start: f64,
    span: f64,
}

/// Aligns the centred `w` with the target's `z` (either direction), `w[(k + shift) % n]` with `z[k]`.
fn align(w: &[C], z: &[C], shift: usize) -> (f64, C) {
    let n = w.len();
    let mut c = C::default();
    let mut w_sq = 0.0;
    for (k, zk) in z.iter().enumerate() {
        let wk = w[(k + shift) % n];
        let p = wk.conj_mul(*zk);
        c.0 += p.0;
        c.1 += p.1;
        w_sq += wk.norm_sq();
    }
    (w_sq, c)
}

/// Atlas sample `index` of family `L` under `seed`, normalised; `None` when the family's draws
/// keep failing.
fn atlas_sample<L: PathLinkage>(seed: u64, index: u64) -> Option<L> {
    let mut r = rng(seed, Stream::Sample { family: L::STREAM }, index);
    (0..SAMPLE_DRAWS).find_map(|_| L::sample(&mut r))
}

/// Scratch for matching one atlas curve.
#[derive(Default)]
struct MatchScratch {
    curve: Vec<Point>,
    arc: Vec<Point>,
    resampled: Vec<Point>,
    w: Vec<C>,
}

/// The best match of `m`'s tracer curve onto the target.
fn best_match<L: PathLinkage>(m: &L, target: &Target, s: &mut MatchScratch) -> Option<Match> {
    s.curve.clear();
    for k in 0..ATLAS_STEPS {
        s.curve.push(m.tracer_at(TAU * k as f64 / ATLAS_STEPS as f64)?.point);
    }
    let step = TAU / ATLAS_STEPS as f64;
    let mut best: Option<Match> = None;
    let mut consider = |w_sq: f64, c: C, w_centroid: Point, theta_start: f64, span: f64| {
        if w_sq.is_nan() || w_sq <= 0.0 {
            return;
        }
        let residual = 1.0 - c.norm_sq() / (w_sq * target.norm_sq);
        if best.is_none_or(|b| residual < b.residual) {
            let alpha = C(c.0 / w_sq, c.1 / w_sq);
            best = Some(Match { residual, alpha, w_centroid, theta_start, span });
        }
    };
    if target.closed {
        resample_into(&s.curve, true, MATCH_POINTS, &mut s.resampled);
        // The resampled curve starts at the crank's 0; the shift finds where the drawn start is.
        let w_centroid = centred(&s.resampled, &mut s.w);
        let length_to: Vec<f64> = arc_lengths(&s.curve);
        for (z, span) in [(&target.forward, TAU), (&target.backward, -TAU)] {
            for shift in 0..MATCH_POINTS {
                let (w_sq, c) = align(&s.w, z, shift);
                // The crank angle at resampled point `shift`: where that arc length falls.
                let theta = theta_at_fraction(&length_to, shift as f64 / MATCH_POINTS as f64);
                consider(w_sq, c, w_centroid, theta, span);
            }
        }
    } else {
        for start in (0..ATLAS_STEPS).step_by(OPEN_START_STEP) {
            for &len in &OPEN_SPANS {
                for dir in [1isize, -1] {
                    s.arc.clear();
                    for k in 0..=len {
                        let i = (start as isize + dir * k as isize).rem_euclid(ATLAS_STEPS as isize) as usize;
                        s.arc.push(s.curve[i]);
                    }
                    resample_into(&s.arc, false, MATCH_POINTS, &mut s.resampled);
                    let w_centroid = centred(&s.resampled, &mut s.w);
                    let (w_sq, c) = align(&s.w, &target.forward, 0);
                    consider(w_sq, c, w_centroid, start as f64 * step, dir as f64 * len as f64 * step);
                }
            }
        }
    }
    best
}

/// The cumulative arc length at each vertex of the closed polyline `curve` (its first 0, one more
/// entry for the closing edge).
fn arc_lengths(curve: &[Point]) -> Vec<f64> {
    let mut out = Vec::with_capacity(curve.len() + 1);
    let mut walked = 0.0;
    out.push(0.0);
    for i in 0..curve.len() {
        walked += curve[i].distance(curve[(i + 1) % curve.len()]);
        out.push(walked);
    }
    out
}

/// The crank angle (of a curve traced at even steps over a whole turn) where `fraction` of its length
/// is walked.
fn theta_at_fraction(length_to: &[f64], fraction: f64) -> f64 {
    let total = length_to[length_to.len() - 1];
    let want = fraction * total;
    let i = length_to.partition_point(|&l| l <= want).clamp(1, length_to.len() - 1);
    let (a, b) = (length_to[i - 1], length_to[i]);
    let t = if b > a { (want - a) / (b - a) } else { 0.0 };
    TAU * ((i - 1) as f64 + t) / (length_to.len() - 1) as f64
}

/// The atlas sample `m` placed by `matched` onto the drawn curve, with its travel.
fn placed<L: PathLinkage>(m: &L, matched: &Match, target: &Target) -> PathFit<L> {
    let C(ar, ai) = matched.alpha;
    let map = Similarity {
        from: matched.w_centroid,
        to: target.centroid,
        scale: (ar * ar + ai * ai).sqrt(),
        turn: ai.atan2(ar),
    };
    // Turning the whole linkage turns its crank as much.
    let theta_start = matched.theta_start + map.turn;
    PathFit { linkage: m.mapped(&map), theta_start, theta_end: theta_start + matched.span, objective: matched.residual }
}

/// The residuals the refinement's least squares sums: the distance of each drawn point from the
/// traced curve and of each traced point from the drawn one, as fractions of the drawn curve's size;
/// the distance of each reversal from the traced curve, and for an open curve the tracer's miss at
/// either end, count thrice (the tracer must reach the tip of a stroke, and run from the first point
/// to the last), and that of each exact point `exact_emphasis` times, as much as the tracer's miss of
/// each pose the body must pass, as a fraction of the body's size d, and the body's turn there
/// (radians). `None` where the loop does not close along the travel or transmits worse than allowed.
fn residuals<L: PathLinkage>(
    x: &[f64],
    template: &L,
    (closed, min_sine): (bool, f64),
    drawn: &Drawn,
    exact_emphasis: f64,
) -> Option<Vec<f64>> {
    let n = x.len() - 2;
    let m = template.with_params(&x[..n]);
    let (start, end) = travel(&x[n..], closed);
    let steps =
        if closed { REFINE_STEPS } else { ((REFINE_STEPS as f64 * (end - start).abs() / TAU).ceil() as usize).max(8) };
    let curve = traced(&m, start, end, steps, min_sine)?;
    let mut out = Vec::with_capacity(4 * REFINE_POINTS + 4);
    let emphasis = 3.0;
    let weighed = drawn.points.iter().map(|p| (p, 1.0));
    let weighed = weighed.chain(drawn.goal.reversals.iter().map(|p| (p, emphasis)));
    let weighed = weighed.chain(drawn.goal.exact.iter().map(|p| (p, exact_emphasis)));
    for (&p, weight) in weighed {
        let (_, q, _) = nearest(p, &curve, closed);
        out.extend([weight * (q.x - p.x) / drawn.size, weight * (q.y - p.y) / drawn.size]);
    }
    let stride = (curve.len() / REFINE_POINTS).max(1);
    for &q in curve.iter().step_by(stride) {
        let (_, p, _) = nearest(q, drawn.goal.drawn, closed);
        out.extend([(q.x - p.x) / drawn.size, (q.y - p.y) / drawn.size]);
    }
    if !closed {
        for (q, p) in [(curve[0], drawn.points[0]), (curve[curve.len() - 1], drawn.points[drawn.points.len() - 1])] {
            out.extend([emphasis * (q.x - p.x) / drawn.size, emphasis * (q.y - p.y) / drawn.size]);
        }
    }
    // The poses, where the tracer passes nearest each, the first (where the body starts) the
    // reference of the turns. The body's heading is asked only at the ends of those traced edges.
    let heading_at = |k: usize| m.tracer_at(start + (end - start) * k as f64 / steps as f64).map(|c| c.heading);
    let mut first: Option<Vec2> = None;
    for pose in drawn.goal.poses {
        let (_, q, edge) = nearest(pose.tracer, &curve, closed);
        let next = (edge + 1) % curve.len();
        let span = curve[edge].distance(curve[next]);
        let t = if span > 0.0 { q.distance(curve[edge]) / span } else { 0.0 };
        let heading = heading_at(edge)? * (1.0 - t) + heading_at(next)? * t;
        let from = *first.get_or_insert(heading);
        let miss = (from.cross(heading).atan2(from.dot(heading)) - pose.turn + PI).rem_euclid(TAU) - PI;
        // Relative to the body, as a pose's miss is judged: a hundredth of d weighs as much as 0.6°.
        let p = pose.tracer;
        out.extend([
            exact_emphasis * (q.x - p.x) / drawn.goal.body_size,
            exact_emphasis * (q.y - p.y) / drawn.goal.body_size,
        ]);
        out.push(exact_emphasis * miss);
    }
    Some(out)
}

/// The drawn curve as the refinement measures from it: points spaced evenly along it (whose
/// distances from the traced curve are measured), and the goal, whose curve as drawn the traced
/// points' distances are measured to (a coarser polyline's chords would cut its bends).
struct Drawn<'a> {
    points: Vec<Point>,
    goal: &'a PathGoal<'a>,
    size: f64,
}

/// The travel from its two refined parameters: start and end, or for a closed curve start and a
/// whole turn the way the second's sign says.
fn travel(x: &[f64], closed: bool) -> (f64, f64) {
    if closed {
        (x[0], x[0] + x[1].signum() * TAU)
    } else {
        (x[0], x[1])
    }
}

/// Levenberg–Marquardt from `fit` on [`residuals`] (the exact points weighed `exact_emphasis` times),
/// forward differences for the Jacobian; never returns a worse fit than it is given.
fn refine<L: PathLinkage>(fit: PathFit<L>, goal: &PathGoal, drawn: &Drawn, exact_emphasis: f64) -> PathFit<L> {
    let template = fit.linkage;
    let mut x: Vec<f64> = template.params();
    let n = x.len();
    if goal.closed {
        x.extend([fit.theta_start, fit.theta_end - fit.theta_start]);
    } else {
        x.extend([fit.theta_start, fit.theta_end]);
    }
    let f = |x: &[f64]| residuals(x, &template, (goal.closed, goal.min_transmission_sine), drawn, exact_emphasis);
    let Some(mut r) = f(&x) else { return fit };
    let mut cost: f64 = r.iter().map(|v| v * v).sum();
    // Angles move in radians, lengths relative to the curve: a step of 1e-7 of each.
    let step = |k: usize| if k >= n || L::is_angle(k) { 1e-7 } else { 1e-7 * drawn.size };
    // A closed travel's span is a whole turn whatever its parameter: it is not refined.
    let free = if goal.closed { x.len() - 1 } else { x.len() };
    let mut lambda = 1e-3;
    for _ in 0..REFINE_ITERATIONS {
        let mut jac = DMatrix::<f64>::zeros(r.len(), free);
        for k in 0..free {
            let mut xk = x.clone();
            xk[k] += step(k);
            let Some(rk) = f(&xk).filter(|rk| rk.len() == r.len()) else { continue };
            for (i, (a, b)) in rk.iter().zip(&r).enumerate() {
                jac[(i, k)] = (a - b) / step(k);
            }
        }
        let rv = DVector::from_column_slice(&r);
        let jtj = jac.transpose() * &jac;
        let jtr = jac.transpose() * rv;
        let mut improved = false;
        for _ in 0..6 {
            let mut damped = jtj.clone();
            for k in 0..free {
                damped[(k, k)] += lambda * jtj[(k, k)].max(1e-12);
            }
            let Some(delta) = damped.lu().solve(&(-&jtr)) else {
                lambda *= 4.0;
                continue;
            };
            let mut trial = x.clone();
            for k in 0..free {
                trial[k] += delta[k];
            }
            match f(&trial) {
                Some(rt) if rt.len() == r.len() && rt.iter().map(|v| v * v).sum::<f64>() < cost => {
                    cost = rt.iter().map(|v| v * v).sum();
                    (x, r) = (trial, rt);
                    lambda = (lambda / 3.0).max(1e-9);
                    improved = true;
                    break;
                }
                _ => lambda *= 4.0,
            }
        }
        if !improved {
            break;
        }
    }
    let (theta_start, theta_end) = travel(&x[n..], goal.closed);
    PathFit { linkage: template.with_params(&x[..n]), theta_start, theta_end, objective: cost / r.len() as f64 }
}

/// Where the drawn curve turns back on itself (by more than [`REVERSAL_DEG`] between the points
/// the smoothing's half-window before and after, at least 1, so a hand's jitter is not one), the
/// sharpest [`MAX_REVERSALS`] of them: the tip of an out-and-back stroke, which the even resampling
/// and the smoothing would both cut short, so the refinement measures the traced curve from them too.
pub(crate) fn reversals(curve: &[Point], closed: bool) -> Vec<Point> {
    let n = curve.len();
    let reach = (n / SMOOTHING_SHARE).max(1);
    if n <= 2 * reach {
        return Vec::new();
    }
    let mut turns: Vec<(f64, usize)> = (0..n)
        .filter(|&i| closed || (i >= reach && i + reach < n))
        .filter_map(|i| {
            let (before, after) = (curve[i] - curve[(i + n - reach) % n], curve[(i + reach) % n] - curve[i]);
            let turn = before.cross(after).atan2(before.dot(after)).abs();
            (turn > REVERSAL_DEG.to_radians()).then_some((turn, i))
        })
        .collect();
    turns.sort_by(|a, b| b.0.total_cmp(&a.0).then(a.1.cmp(&b.1)));
    turns.into_iter().take(MAX_REVERSALS).map(|(_, i)| curve[i]).collect()
}

/// Members of family `L` whose tracer follows `goal`'s curve: `samples` atlas curves under `seed`,
/// the `refined` best matches refined; returned best first (the least mean squared distance), at
/// most `refined` of them. Deterministic whatever the thread count.
pub(crate) fn fit<L: PathLinkage>(goal: &PathGoal, seed: u64, samples: usize, refined: usize) -> Vec<PathFit<L>> {
    // A hand's jitter along many points lengthens the curve unevenly, which would space the points
    // the match compares unevenly: the match and the refinement see the curve smoothed over a
    // 64th of its points either side (none under 64 points).
    let window = goal.drawn.len() / SMOOTHING_SHARE;
    let curve = smoothed(goal.drawn, goal.closed, window);
    let goal = &PathGoal { drawn: &curve, ..*goal };
    let target = Target::new(goal);
    let mut matches: Vec<(f64, usize, PathFit<L>)> = (0..samples)
        .into_par_iter()
        .map_init(MatchScratch::default, |scratch, i| {
            let m = atlas_sample::<L>(seed, i as u64)?;
            best_match(&m, &target, scratch).map(|matched| (matched.residual, i, placed(&m, &matched, &target)))
        })
        .flatten()
        .collect();
    matches.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
    matches.truncate(refined);

    let drawn = Drawn { points: resample(goal.drawn, goal.closed, REFINE_POINTS), goal, size: size(goal.drawn) };
    let mut fits: Vec<(f64, usize, PathFit<L>)> = matches
        .into_par_iter()
        .map(|(_, i, fit)| {
            let mut fit = refine(fit, goal, &drawn, EXACT_EMPHASES[0]);
            if !goal.exact.is_empty() || !goal.poses.is_empty() {
                for &emphasis in &EXACT_EMPHASES[1..] {
                    fit = refine(fit, goal, &drawn, emphasis);
                }
            }
            (fit.objective, i, fit)
        })
        .collect();
    fits.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
    fits.into_iter().map(|(_, _, fit)| fit).collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::{path_error, PathError};
    use crate::synth::path::four_bar::FourBar;

    fn check(closed: bool, start: f64, end: f64, points: usize) -> (PathError, PathFit<FourBar>) {
        let m = FourBar::known();
        assert!(m.crank_turns_fully());
        let drawn = traced(&m, start, end, points - usize::from(closed), 0.0).unwrap();
        let drawn = if closed { drawn[..points].to_vec() } else { drawn };
        let goal = PathGoal {
            drawn: &drawn,
            closed,
            min_transmission_sine: 10f64.to_radians().sin(),
            reversals: &reversals(&drawn, closed),
            exact: &[],
            poses: &[],
            body_size: 0.0,
        };
        let t = std::time::Instant::now();
        let fits = fit::<FourBar>(&goal, 0, 20_000, 16);
        let best = fits[0];
        let curve = traced(&best.linkage, best.theta_start, best.theta_end, 720, 0.0).unwrap();
        let e = path_error(&drawn, &[], &curve, closed);
        eprintln!("closed {closed}: {e:?} in {:.2} s, {best:?}", t.elapsed().as_secs_f64());
        (e, best)
    }

    /// A stroke out along x and back, and a circle: the stroke's tip is its one reversal (the ends of
    /// an open stroke are not), a circle has none.
    #[test]
    fn only_a_curve_that_turns_back_has_reversals() {
        let mut stroke: Vec<Point> = (0..=10).map(|k| Point::new(k as f64, 0.1 * k as f64)).collect();
        stroke.extend((5..10).rev().map(|k| Point::new(k as f64, 0.1 * k as f64 + 0.5)));
        assert_eq!(reversals(&stroke, false), [Point::new(10.0, 1.0)]);
        let circle: Vec<Point> = (0..40).map(|k| Point::ORIGIN + Vec2::from_angle(TAU * k as f64 / 40.0)).collect();
        assert!(reversals(&circle, true).is_empty());
        // Closed, the stroke turns back at its tip and where it closes on its start.
        assert_eq!(reversals(&stroke, true).len(), 2);
    }

    #[test]
    fn a_known_crank_rockers_whole_coupler_curve_is_traced_within_a_percent() {
        let (e, _) = check(true, 0.0, TAU, 100);
        assert!(e.max_rel < 0.01, "{e:?}");
    }

    #[test]
    fn an_arc_of_a_known_coupler_curve_is_traced_from_its_first_point_to_its_last() {
        let (e, fit) = check(false, 0.5, 2.6, 50);
        assert!(e.max_rel < 0.01, "{e:?}");
        let m = FourBar::known();
        let (first, last) = (m.at(0.5).unwrap().tracer, m.at(2.6).unwrap().tracer);
        let size = size(&traced(&m, 0.5, 2.6, 49, 0.0).unwrap());
        assert!(fit.linkage.at(fit.theta_start).unwrap().tracer.distance(first) < 0.01 * size);
        assert!(fit.linkage.at(fit.theta_end).unwrap().tracer.distance(last) < 0.01 * size);
    }
}

//! Judging one mechanism: hard constraints (paper §5) from the cheapest to the most expensive, and the
//! soft terms (eq. 10–13) from the same single simulation.
//!
//! The configuration a design offers for pose i is the one along the crank's travel closest to the
//! input pose (least squares over the body-carried joints); the travel runs from the first pose to the
//! configuration closest to the last pose. Order, branch and circuit defects, poor transmission and
//! failures to assemble are all judged on that travel.

use super::context::{Context, CRANK_STEP, END_SEARCH, MUST_HIT_ANGLE_DEG, MUST_HIT_POSITION};
use super::terms::{transmission_shortfall, Floor, SoftTerms, Term};
use crate::geom::Point;
use crate::kinematics::{BodyFrames, Branch, Plan, Trace};
use crate::mechanism::{Mechanism, Topology};
use std::f64::consts::TAU;
use std::sync::Arc;

/// Why a candidate is rejected, cheapest check first.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Reject {
    /// Two joints of one part (or the two ends of a link) are too close to build.
    JointsTooClose,
    /// The crank cannot pass the poses in order without a full turn or turning back (§5.1).
    Order,
    /// A four-bar loop is on another branch or circuit at some pose than at the first (§5.2–5.3).
    Branch,
    /// The linkage comes apart between the poses.
    Assembly,
    /// A transmission angle comes closer to 0° or 180° than allowed (§5.4).
    Transmission,
    /// A body passes a pose it must hit (its last, where it comes to rest, or one the scene marks)
    /// away from it (a link that turns over on the way, say), though the linkage is rigid through
    /// those poses: the object would not be where it was drawn.
    MissedPose,
    /// A link enters an avoid region.
    AvoidRegion,
    /// A moving body penetrates a fixed body or another moving body (§5.5).
    Collision,
    /// Valid, but it cannot be printed: no room for its connectors, or no depth ordering (§7.2).
    Unprintable,
    /// Not a defect: its cost, bounded from below before any simulation, could not beat the designs
    /// already kept.
    Outclassed,
}

impl Reject {
    /// Every reason, cheapest check first.
    pub const ALL: [Reject; 10] = [
        Reject::JointsTooClose,
        Reject::Order,
        Reject::Branch,
        Reject::Assembly,
        Reject::Transmission,
        Reject::MissedPose,
        Reject::AvoidRegion,
        Reject::Collision,
        Reject::Unprintable,
        Reject::Outclassed,
    ];
}

/// A mechanism that passed the kinematic checks, with its motion.
#[derive(Clone, Debug)]
pub struct Candidate {
    /// The linkage, its joints at the first pose.
    pub mechanism: Mechanism,
    /// The linkage compiled for solving along its crank.
    pub plan: Plan,
    /// The travel from the first to the last pose: crank steps of at most 1°, plus one row exactly at
    /// each pose's crank angle.
    pub trace: Trace,
    /// Row of `trace` at each pose.
    pub pose_rows: Vec<usize>,
    /// The soft terms of paper eq. 10–13.
    pub soft: SoftTerms,
    /// Weighted sum of the soft terms (eq. 14).
    pub cost: f64,
    /// Fabrication's feasibility check passed (false: failed or not run).
    pub printable: bool,
    /// For a path scene: how far the tracer's curve is from the drawn one.
    pub path: Option<crate::geom::PathError>,
}

impl Candidate {
    /// The crank angle at each pose, radians (unwrapped).
    pub fn pose_thetas(&self) -> impl Iterator<Item = f64> + '_ {
        self.pose_rows.iter().map(|&r| self.trace.thetas[r])
    }
}

/// Reusable buffers, one per worker thread.
#[derive(Debug, Default)]
pub(crate) struct Scratch {
    coarse: Trace,
    /// The configuration at each pose, and the sweep's rows between consecutive poses.
    pose_positions: Vec<Point>,
    between_poses: Vec<std::ops::Range<usize>>,
    targets: Vec<Point>,
    fitted_targets: Vec<Point>,
    row: Vec<Point>,
    branches: Vec<Branch>,
    pub(crate) fit: super::rigidity::FitWorkspace,
    /// The last plan compiled, and its topology: later mechanisms of that topology only redimension it.
    template: Option<(Arc<Topology>, Plan)>,
    /// The plan of the mechanism being screened.
    plan: Option<Plan>,
    /// The crank's direction at each pose (NaN where only the turned tip assembles), and with the
    /// turning tip turned ([`Context::turning_tip`]; NaN where it does not assemble).
    nominal: Vec<f64>,
    nominal_turned: Vec<f64>,
    /// The screened travels (see [`Screening`]), reused from mechanism to mechanism, and for each of
    /// their angles whether the turning tip is turned there.
    travels: Vec<f64>,
    turned: Vec<bool>,
}

/// The kinematic checks and the soft costs of one mechanism; [`Reject::Outclassed`] when its cost is
/// bounded from below by more than `cost_bound` before any simulation.
///
/// `fitted` holds the (perturbed) motions a sample was fitted to: the cheap branch and order checks
/// read the sample's own configurations there, as the paper does, because a near-singular dyad may
/// flip at the unperturbed poses while the simulated motion still passes them closely. Without it
/// (particle filter proposals) the input poses are used. Accuracy and the pose search always use the
/// input poses.
pub(crate) fn evaluate(
    ctx: &Context,
    mechanism: Mechanism,
    fitted: Option<&[Vec<crate::geom::Rigid>]>,
    cost_bound: f64,
    scratch: &mut Scratch,
) -> Result<Candidate, Reject> {
    let screening = screen(ctx, &mechanism, fitted, scratch)?;
    if screening.floor > cost_bound {
        return Err(Reject::Outclassed);
    }
    let plan = scratch.plan.clone().expect("screening dimensions the plan");
    simulate(ctx, mechanism, plan, screening, scratch)
}

/// What the checks before any simulation found of a mechanism that passed them, with the travels
/// left in `Scratch::travels`: the crank's nominal angle at each pose, for each direction it may turn
/// that the closed form does not rule out (shortest travel first), one pose count after another.
struct Screening {
    /// The reject of the first direction the closed form ruled out, if any.
    first_failure: Option<Reject>,
    /// The terms known before any simulation ([`Floor::Exact`]); the others are zero.
    exact: SoftTerms,
    /// A floor under the cost [`evaluate`] would give.
    floor: f64,
}

/// A floor under the cost [`evaluate`] would give `mechanism`, from the checks that need no
/// simulation, or the reject one of those checks gives (`evaluate` gives the same reject).
pub(crate) fn cost_floor(
    ctx: &Context,
    mechanism: &Mechanism,
    fitted: Option<&[Vec<crate::geom::Rigid>]>,
    scratch: &mut Scratch,
) -> Result<f64, Reject> {
    screen(ctx, mechanism, fitted, scratch).map(|screening| screening.floor)
}

/// Puts the mechanism's kinematic plan in `scratch.plan`: the last one compiled for its topology,
/// redimensioned.
fn dimension_plan(mechanism: &Mechanism, scratch: &mut Scratch) -> Result<(), Reject> {
    let dimensioned = match (&scratch.template, &mut scratch.plan) {
        (Some((topology, template)), Some(plan)) if Arc::ptr_eq(topology, &mechanism.topology) => {
            template.redimension_into(mechanism, plan)
        }
        _ => Plan::compile(mechanism).map(|plan| {
            scratch.template = Some((mechanism.topology.clone(), plan.clone()));
            scratch.plan = Some(plan);
        }),
    };
    dimensioned.map_err(|_| Reject::JointsTooClose)
}

/// Spacing, branch, order, and closed-form assembly and transmission checks, then the terms that need
/// no simulation and a floor under the cost. Leaves the plan in `scratch.plan`, the travels in
/// `scratch.travels` and the input-pose targets in `scratch.targets`.
fn screen(
    ctx: &Context,
    mechanism: &Mechanism,
    fitted: Option<&[Vec<crate::geom::Rigid>]>,
    scratch: &mut Scratch,
) -> Result<Screening, Reject> {
    let n = ctx.topology.joint_count();
    let poses = ctx.problem.pose_count;
    let joints = &mechanism.joints;
    if ctx.part_pairs.iter().any(|&(a, b)| joints[a].distance(joints[b]) < ctx.min_spacing) {
        return Err(Reject::JointsTooClose);
    }
    dimension_plan(mechanism, scratch)?;
    let Scratch { plan, targets, fitted_targets, branches, nominal, nominal_turned, travels, turned, row, .. } =
        scratch;
    let plan = plan.as_ref().expect("just dimensioned");

    // Where every joint is at every pose in the sample's own fit, pose after pose, and branch and
    // circuit (§5.2–5.3): every dyad must be on its first-pose branch at every pose. Most samples fail
    // this at some pose; the input poses' targets wait until every check below passes. The crank's
    // direction at each pose comes from there: for a turning tip, on either side (the tip passes from
    // one to the other where the link it drives turns back, while the crank turns on).
    fitted_targets.clear();
    nominal.clear();
    nominal_turned.clear();
    for i in 0..poses {
        fitted_targets.extend((0..n).map(|j| match (fitted, ctx.carriers[j]) {
            (Some(motions), Some(b)) => motions[b][i].apply(joints[j]),
            _ => ctx.target(j, joints[j], i),
        }));
        let at = &mut fitted_targets[i * n..];
        let (own, turned_tip) =
            if i == 0 { (crank_angle(ctx, at), f64::NAN) } else { pose_cranks(ctx, joints, plan, at, row, branches)? };
        nominal.push(own);
        nominal_turned.push(turned_tip);
    }

    let count = order(ctx, nominal, nominal_turned, travels, turned)?;
    let first_failure = keep_closed_form_passes(ctx, plan, poses, count, travels, turned)?;

    // Where every joint should be at every pose, at the input poses.
    targets.clear();
    for i in 0..poses {
        targets.extend((0..n).map(|j| ctx.target(j, joints[j], i)));
    }

    // The terms that need no simulation, and a floor under the two that do, bound the cost from below.
    let exact = exact_terms(ctx, mechanism);
    let floor = ctx.weights.cost_of(&exact, Floor::Exact) + simulated_floor(ctx, mechanism, targets);
    Ok(Screening { first_failure, exact, floor })
}

/// The crank's direction in the configuration `row`.
#[inline]
fn crank_angle(ctx: &Context, row: &[Point]) -> f64 {
    (row[ctx.topology.driver_tip] - row[ctx.topology.driver_pivot]).angle()
}

/// The crank's direction at a pose after the first, from the joints the body motions put at `at`:
/// with the tip on its own side, and with the turning tip turned (`row` holds that configuration);
/// NaN where that side does not assemble. The branch reject when neither side passes.
#[inline]
fn pose_cranks(
    ctx: &Context,
    joints: &[Point],
    plan: &Plan,
    at: &mut [Point],
    row: &mut Vec<Point>,
    branches: &mut Vec<Branch>,
) -> Result<(f64, f64), Reject> {
    let n = ctx.topology.joint_count();
    row.clear();
    if ctx.turning_tip.is_some() {
        row.extend_from_slice(&at[..n]);
    }
    let own = on_own_branches(ctx, joints, plan, branches, at, false);
    let turned_tip = on_own_branches(ctx, joints, plan, branches, row, true);
    match (own, turned_tip) {
        (Err(reject), Err(_) | Ok(None)) => Err(reject),
        (own, turned_tip) => {
            Ok((own.ok().flatten().unwrap_or(f64::NAN), turned_tip.ok().flatten().unwrap_or(f64::NAN)))
        }
    }
}

/// Completes `row` (the turning tip turned, if `turn`) and checks every dyad is on its first-pose
/// branch there: the crank's direction if so, `None` when that side does not apply, or the reject.
#[inline]
fn on_own_branches(
    ctx: &Context,
    joints: &[Point],
    plan: &Plan,
    branches: &mut Vec<Branch>,
    row: &mut [Point],
    turn: bool,
) -> Result<Option<f64>, Reject> {
    let placed = if turn { ctx.complete_turned(joints, row) } else { ctx.complete(joints, row).map(|()| true) };
    if !placed.map_err(|_| Reject::Assembly)? {
        return Ok(None);
    }
    plan.branches_of(row, branches);
    if branches.iter().copied().eq(plan.own_branches()) {
        Ok(Some(crank_angle(ctx, row)))
    } else {
        Err(Reject::Branch)
    }
}

/// Order (§5.1), nominally: the crank's direction at each pose (`nominal`, and `nominal_turned` with
/// the turning tip turned) must advance one way by less than a turn. Leaves the crank's angle at each
/// pose in `travels` for each direction it may turn, the shorter travel first (on a tie, turning
/// positively), and returns how many directions there are.
#[inline]
fn order(
    ctx: &Context,
    nominal: &[f64],
    nominal_turned: &[f64],
    travels: &mut Vec<f64>,
    turned: &mut Vec<bool>,
) -> Result<usize, Reject> {
    let poses = nominal.len();
    let (mut totals, mut count) = travels_in_order(nominal, nominal_turned, false, travels, turned);
    if count == 0 && ctx.turning_tip.is_some() {
        (totals, count) = travels_in_order(nominal, nominal_turned, true, travels, turned);
    }
    if count == 0 {
        return Err(Reject::Order);
    }
    if count == 2 && totals[1] < totals[0] {
        travels.rotate_left(poses);
        turned.rotate_left(poses);
    }
    Ok(count)
}

/// For each direction the crank may turn, its angle at each pose, one direction after the other, in
/// `travels` (and in `turned` whether the tip is turned there): with the tip on its own side
/// throughout, or else, if `may_turn`, on the side the crank reaches first (the body goes out and
/// back). Returns each direction's total turn and how many directions pass.
#[inline]
fn travels_in_order(
    nominal: &[f64],
    nominal_turned: &[f64],
    may_turn: bool,
    travels: &mut Vec<f64>,
    turned: &mut Vec<bool>,
) -> ([f64; 2], usize) {
    let poses = nominal.len();
    travels.clear();
    turned.clear();
    let mut totals = [0.0; 2];
    let mut count = 0;
    for dir in [1.0, -1.0] {
        let start = travels.len();
        travels.push(nominal[0]);
        turned.push(false);
        let mut from = nominal[0];
        for i in 1..poses {
            let step = |to: f64| (dir * (to - from)).rem_euclid(TAU);
            let turning = if may_turn { nominal_turned[i] } else { f64::NAN };
            let nearest = [(nominal[i], false), (turning, true)]
                .into_iter()
                .filter(|&(to, _)| to.is_finite() && step(to) > 0.0)
                .min_by(|a, b| step(a.0).total_cmp(&step(b.0)));
            let Some((to, side)) = nearest else { break };
            travels.push(travels[travels.len() - 1] + dir * step(to));
            turned.push(side);
            from = to;
        }
        let total = (travels[travels.len() - 1] - travels[start]).abs();
        if travels.len() - start == poses && total < TAU {
            totals[count] = total;
            count += 1;
        } else {
            travels.truncate(start);
            turned.truncate(start);
        }
    }
    (totals, count)
}

/// A four-bar or slider-crank is judged on assembly and transmission in closed form, so travels that
/// lock up or transmit poorly are never simulated: keeps the `count` travels that pass (in order) and
/// returns the reject of the first that does not, or that reject when none passes.
#[inline]
fn keep_closed_form_passes(
    ctx: &Context,
    plan: &Plan,
    poses: usize,
    count: usize,
    travels: &mut Vec<f64>,
    turned: &mut Vec<bool>,
) -> Result<Option<Reject>, Reject> {
    let mut first_failure = None;
    let mut kept = 0;
    for k in 0..count {
        let angles = k * poses..(k + 1) * poses;
        match plan.closed_form_travel(travels[angles.start], travels[angles.end - 1]) {
            Some(Err(_)) => {
                first_failure.get_or_insert(Reject::Assembly);
            }
            Some(Ok(sine)) if sine < ctx.min_transmission_sine => {
                first_failure.get_or_insert(Reject::Transmission);
            }
            _ => {
                travels.copy_within(angles.clone(), kept * poses);
                turned.copy_within(angles, kept * poses);
                kept += 1;
            }
        }
    }
    if kept == 0 {
        return Err(first_failure.unwrap_or(Reject::Assembly));
    }
    travels.truncate(kept * poses);
    turned.truncate(kept * poses);
    Ok(first_failure)
}

/// Simulates a screened mechanism's travels, shortest first, and returns the first that passes every
/// kinematic check, with its costs.
fn simulate(
    ctx: &Context,
    mechanism: Mechanism,
    plan: Plan,
    screening: Screening,
    scratch: &mut Scratch,
) -> Result<Candidate, Reject> {
    let Screening { mut first_failure, exact, .. } = screening;
    let poses = ctx.problem.pose_count;
    // A copy: the simulation uses the scratch (one allocation against a whole simulation).
    let (travels, turned) = (scratch.travels.clone(), scratch.turned.clone());
    let frames = BodyFrames::new(&mechanism, &ctx.first_poses);
    for (angles, turned) in travels.chunks_exact(poses).zip(turned.chunks_exact(poses)) {
        match travel(ctx, &plan, (angles, turned), scratch) {
            Ok((trace, pose_rows, _)) if misses_must_hit_pose(ctx, &frames, &trace, &pose_rows) => {
                first_failure.get_or_insert(Reject::MissedPose);
            }
            Ok((trace, pose_rows, least_sine)) => {
                let mut soft = exact;
                simulated_terms(ctx, &frames, (&trace, &pose_rows, least_sine), &scratch.targets, &mut soft);
                let cost = ctx.weights.cost(&soft);
                return Ok(Candidate { mechanism, plan, trace, pose_rows, soft, cost, printable: false, path: None });
            }
            Err(r) => {
                first_failure.get_or_insert(r);
            }
        }
    }
    Err(first_failure.unwrap_or(Reject::Assembly))
}

/// True when some body, in the configuration `trace` offers for a must-hit pose after the first (where
/// the joints are given), is farther from that pose than [`MUST_HIT_POSITION`] of its size d or
/// [`MUST_HIT_ANGLE_DEG`].
fn misses_must_hit_pose(ctx: &Context, frames: &BodyFrames, trace: &Trace, pose_rows: &[usize]) -> bool {
    let must_hit = &ctx.problem.must_hit;
    (1..pose_rows.len()).filter(|&i| must_hit[i]).any(|i| {
        let row = trace.row(pose_rows[i]);
        ctx.problem.bodies.iter().enumerate().any(|(b, body)| {
            let miss = body.miss(i, &frames.pose(b, row));
            miss.position_rel_d > MUST_HIT_POSITION || miss.angle_deg > MUST_HIT_ANGLE_DEG
        })
    })
}

/// The first row of `positions` (rows of `n` joints) whose `moving` joints are nearest `targets` (a
/// row's worth): least sum of squared misses, each row's computed once.
///
/// The simulation's hottest loop, written out for the common one and two moving joints, comparing by
/// `<`, which orders finite errors as `total_cmp` does (the rows and targets are finite): the folding
/// table's whole run takes 5% fewer instructions so than with a scan summing over `moving` for each
/// row (`valgrind --tool=callgrind linkwright design examples/k1_table.json --threads 1
/// --no-print-check`, the scene's `"mechanism"` set to `"chain"`).
fn nearest_row(positions: &[Point], n: usize, moving: &[usize], targets: &[Point]) -> usize {
    let miss = |p: Point, t: Point| (p - t).norm_sq();
    let rows = positions.chunks_exact(n);
    match *moving {
        [a] => {
            let ta = targets[a];
            first_least(rows.map(|row| miss(row[a], ta)))
        }
        [a, b] => {
            let (ta, tb) = (targets[a], targets[b]);
            first_least(rows.map(|row| miss(row[a], ta) + miss(row[b], tb)))
        }
        _ => first_least(rows.map(|row| moving.iter().map(|&j| miss(row[j], targets[j])).sum())),
    }
}

/// The index of the first least of `errors` (0 when there is none).
fn first_least(mut errors: impl Iterator<Item = f64>) -> usize {
    let Some(first) = errors.next() else { return 0 };
    let mut best = (0, first);
    for (r, e) in errors.enumerate() {
        if e < best.1 {
            best = (r + 1, e);
        }
    }
    best.0
}

/// Simulates the travel through nominal crank `angles`, finds the configuration closest to each pose,
/// and returns the travel's trace with the row of each pose. With a turning tip, a pose's
/// configuration is looked for on the side of the turn the screening found (`turned`): the body
/// passes its places on the way out again on the way back.
fn travel(
    ctx: &Context,
    plan: &Plan,
    (angles, turned): (&[f64], &[bool]),
    scratch: &mut Scratch,
) -> Result<(Trace, Vec<usize>, f64), Reject> {
    let n = plan.joint_count();
    let poses = angles.len();
    let (start, end) = (angles[0], angles[poses - 1]);
    let dir = (end - start).signum();
    let extension = (END_SEARCH / CRANK_STEP).round() as usize;
    let Scratch { coarse, targets, row, pose_positions, between_poses, .. } = scratch;
    // The sweep becomes the candidate's trace (see below): room for the rows past the last pose and
    // the pose rows, so neither reallocates it.
    coarse.clear(n);
    coarse.reserve_rows(Trace::sweep_rows(start, end, CRANK_STEP) + extension + poses);
    coarse.sweep(plan, start, end, CRANK_STEP).map_err(|_| Reject::Assembly)?;
    let last_grid_step = (end - start).abs() / (coarse.len() - 1) as f64;
    for k in 1..=extension {
        if coarse.push(plan, end + dir * k as f64 * last_grid_step).is_err() {
            break;
        }
    }

    // The configuration closest to each pose, refined between grid neighbours.
    let moving = &ctx.moving_joints;
    let error = |row: &[Point], i: usize| -> f64 {
        let t = &targets[i * n..(i + 1) * n];
        moving.iter().map(|&j| (row[j] - t[j]).norm_sq()).sum()
    };
    row.resize(n, Point::ORIGIN);
    let mut thetas = vec![start];
    for i in 1..poses {
        let target = &targets[i * n..(i + 1) * n];
        let best = if ctx.turning_tip.is_some() {
            let first = &coarse.positions[..n];
            let on_side = |row: &[Point]| ctx.tip_turned(first, row) == turned[i];
            let miss = |row: &[Point]| moving.iter().map(|&j| (row[j] - target[j]).norm_sq()).sum::<f64>();
            let rows = coarse.positions.chunks_exact(n);
            first_least(rows.map(|row| if on_side(row) { miss(row) } else { f64::INFINITY }))
        } else {
            nearest_row(&coarse.positions, n, moving, target)
        };
        let lo = coarse.thetas[best.saturating_sub(1)];
        let hi = coarse.thetas[(best + 1).min(coarse.len() - 1)];
        let theta = minimise(lo, hi, |theta| match plan.solve(theta, row) {
            Ok(()) => error(row, i),
            Err(_) => f64::INFINITY,
        });
        if dir * (theta - thetas[i - 1]) <= 0.0 {
            return Err(Reject::Order);
        }
        thetas.push(theta);
    }

    // The travel: one exact row per pose, and every grid row strictly between consecutive poses,
    // rearranged in the sweep's own buffer, which the candidate then takes.
    pose_positions.clear();
    pose_positions.resize(poses * n, Point::ORIGIN);
    for (&theta, row) in thetas.iter().zip(pose_positions.chunks_exact_mut(n)) {
        plan.solve(theta, row).map_err(|_| Reject::Assembly)?;
    }
    between_poses.clear();
    let mut grid = 0;
    for w in thetas.windows(2) {
        while grid < coarse.len() && dir * (coarse.thetas[grid] - w[0]) <= 1e-12 {
            grid += 1;
        }
        let first = grid;
        while grid < coarse.len() && dir * (w[1] - coarse.thetas[grid]) > 1e-12 {
            grid += 1;
        }
        between_poses.push(first..grid);
    }
    coarse.splice_rows(between_poses, &thetas, pose_positions);
    // A four-bar or slider-crank has its transmission in closed form, over exactly this travel.
    let least_sine = match plan.closed_form_travel(thetas[0], thetas[poses - 1]) {
        Some(Ok(sine)) => sine,
        Some(Err(_)) => return Err(Reject::Assembly),
        None => coarse.min_transmission_sine(plan),
    };
    if least_sine < ctx.min_transmission_sine {
        return Err(Reject::Transmission);
    }
    let mut pose_rows = Vec::with_capacity(poses);
    pose_rows.push(0);
    for range in between_poses.iter() {
        pose_rows.push(pose_rows[pose_rows.len() - 1] + range.len() + 1);
    }
    Ok((std::mem::replace(coarse, Trace::new(n)), pose_rows, least_sine))
}

/// The minimiser of a function on `[a, b]` (either order) by Brent's method: parabolic steps through
/// the three best points while they shrink the bracket fast enough, golden-section steps otherwise,
/// to about 1e-8 of the interval: about as close as values can place a minimum (√ε of the interval;
/// nearer, the error's differences are rounding). Asking 1e-10 costs 1.2–1.5% more of a synthesis'
/// instructions and changes one design in 216 (the nine Table-1 objects, seeds 0–23: `linkwright
/// design SCENE --seed S`, instructions by the callgrind command of docs/performance.md). The error
/// near a pose is smooth and unimodal between grid neighbours, so the parabolic steps converge in
/// about a dozen evaluations where golden sections alone take fifty. Points where `f` is infinite
/// (the linkage does not assemble) force golden steps.
fn minimise(a: f64, b: f64, mut f: impl FnMut(f64) -> f64) -> f64 {
    // 1 − 1/φ: the golden section of an interval, from its nearer end.
    const GOLDEN: f64 = 0.381_966_011_250_105_1;
    let (mut a, mut b) = (a.min(b), a.max(b));
    let tol = 1e-8 * (b - a);
    // x: the best point so far; w: the second best; v: the previous w.
    let mut x = a + GOLDEN * (b - a);
    let fx0 = f(x);
    let (mut w, mut v, mut fx, mut fw, mut fv) = (x, x, fx0, fx0, fx0);
    // The last step, and the one before it (a parabolic step must shrink faster than that).
    let (mut step, mut previous) = (0.0f64, 0.0f64);
    for _ in 0..100 {
        let mid = 0.5 * (a + b);
        if (x - mid).abs() <= 2.0 * tol - 0.5 * (b - a) {
            break;
        }
        let mut parabolic = false;
        if previous.abs() > tol {
            // The vertex of the parabola through (x, fx), (w, fw), (v, fv), as x + p / q.
            let r = (x - w) * (fx - fv);
            let q = (x - v) * (fx - fw);
            let mut p = (x - v) * q - (x - w) * r;
            let mut q = 2.0 * (q - r);
            if q > 0.0 {
                p = -p;
            } else {
                q = -q;
            }
            let before = previous;
            previous = step;
            // Comparisons with NaN (from infinite values) are false: a golden step follows.
            if p.abs() < (0.5 * q * before).abs() && p > q * (a - x) && p < q * (b - x) {
                step = p / q;
                let u = x + step;
                if u - a < 2.0 * tol || b - u < 2.0 * tol {
                    step = tol.copysign(mid - x);
                }
                parabolic = true;
            }
        }
        if !parabolic {
            previous = if x >= mid { a - x } else { b - x };
            step = GOLDEN * previous;
        }
        let u = if step.abs() >= tol { x + step } else { x + tol.copysign(step) };
        let fu = f(u);
        if fu <= fx {
            if u >= x {
                a = x;
            } else {
                b = x;
            }
            (v, fv, w, fw, x, fx) = (w, fw, x, fx, u, fu);
        } else {
            if u < x {
                a = u;
            } else {
                b = u;
            }
            if fu <= fw || w == x {
                (v, fv, w, fw) = (w, fw, u, fu);
            } else if fu <= fv || v == x || v == w {
                (v, fv) = (u, fu);
            }
        }
    }
    // The bracket's ends are never evaluated inside it. When the least error lies at an end of the
    // interval (the pose is nearest where the travel starts, say), return that end itself: the order
    // check compares crank angles exactly.
    let ends = [(a, f(a)), (x, fx), (b, f(b))];
    ends.into_iter().min_by(|p, q| p.1.total_cmp(&q.1)).map_or(x, |(t, _)| t)
}

/// The terms computed from the joints alone ([`Floor::Exact`]), the others left zero. Paper eq. 12–13:
/// location and size.
pub(crate) fn exact_terms(ctx: &Context, mechanism: &Mechanism) -> SoftTerms {
    let joints = &mechanism.joints;
    let mut soft = SoftTerms::default();
    for term in Term::ALL {
        soft[term] = match term {
            Term::Location => joints.iter().map(|&p| ctx.problem.region.distance(p)).sum::<f64>() / joints.len() as f64,
            Term::Size => {
                ctx.link_pairs.iter().map(|&(a, b)| joints[a].distance(joints[b])).sum::<f64>()
                    / ctx.link_pairs.len() as f64
            }
            // Measured on the travel (`simulated_terms`), bounded by `simulated_floor`.
            Term::Accuracy | Term::Smoothness | Term::Transmission => continue,
        };
        debug_assert_eq!(term.floor(), Floor::Exact);
    }
    soft
}

/// A lower bound on `w_acc·accuracy + w_smooth·smoothness` (eq. 10–11) before any simulation, from
/// the input targets and the loci the joints are bound to.
///
/// Let e(i, j) be joint j's distance from its target at pose i on the travel. A joint that a link ties
/// to a fixed joint stays on a circle around it, and the slider joint on its line, in every
/// configuration, so e(i, j) is at least the target's distance from that locus. Its path from pose i to
/// i + 1 is at least the chord between its targets less e(i, j) and e(i + 1, j) (triangle inequality),
/// so each smoothness ratio is at least 1 − (e(i, j) + e(i + 1, j)) / (chord + f). The weighted sum is
/// then at least w_smooth plus one term β·e² − α·e per (pose, joint) (β from accuracy, α from the
/// intervals next to the pose), each minimised over e at or beyond its locus distance.
///
/// The outlines' part of E_acc adds a floor of its own. A body's miss is a rigid displacement u
/// with u(p) = u(c) + (R − I)(p − c) about the outline's mean point c, whose vertices miss by
/// |u(c)|² + s²·J on average (s = |R − I|, J their spread): a joint r from c misses by at most
/// |u(c)| + s·r, so by Cauchy–Schwarz that mean is at least e²·J / (J + r²) for each of its joints.
fn simulated_floor(ctx: &Context, mechanism: &Mechanism, targets: &[Point]) -> f64 {
    let w = &ctx.weights;
    let n = ctx.topology.joint_count();
    let poses = ctx.problem.pose_count;
    let moving = &ctx.moving_joints;
    let (w_accuracy, w_smoothness) = (w[Term::Accuracy], w[Term::Smoothness]);
    if w_accuracy <= 0.0 || w_smoothness < 0.0 || poses < 2 || moving.is_empty() {
        return 0.0;
    }
    let joints = &mechanism.joints;
    let target = |i: usize, j: usize| targets[i * n + j];
    let f = 0.05 * ctx.body_size;
    let beta = w_accuracy / (poses * moving.len()) as f64;
    let per_ratio = w_smoothness / ((poses - 1) * moving.len()) as f64;
    let inverse_chord = |i: usize, j: usize| 1.0 / (target(i + 1, j).distance(target(i, j)) + f);
    let locus_distance = |i: usize, j: usize| {
        let t = target(i, j);
        let circles = ctx
            .tethers
            .iter()
            .filter(|&&(m, _)| m == j)
            .map(|&(_, g)| (t.distance(joints[g]) - joints[j].distance(joints[g])).abs());
        let line = mechanism
            .slider
            .filter(|_| ctx.topology.slider_joint == Some(j))
            .map(|line| line.direction.cross(t - line.point).abs());
        circles.chain(line).fold(0.0, f64::max)
    };
    let mut floor = w_smoothness;
    for &j in moving {
        for i in 0..poses {
            let before = if i > 0 { inverse_chord(i - 1, j) } else { 0.0 };
            let after = if i + 1 < poses { inverse_chord(i, j) } else { 0.0 };
            let alpha = per_ratio * (before + after);
            let e = (alpha / (2.0 * beta)).max(locus_distance(i, j));
            floor += beta * e * e - alpha * e;
        }
    }
    let outline_beta = w_accuracy / (poses * ctx.outlines.len().max(1)) as f64;
    for outline in &ctx.outlines {
        let share = |j: usize| outline.spread / (outline.spread + (joints[j] - outline.first_mean).norm_sq());
        for i in 0..poses {
            let bound = outline.joints.iter().map(|&j| share(j) * locus_distance(i, j).powi(2)).fold(0.0, f64::max);
            floor += outline_beta * bound;
        }
    }
    // Rounding in the simulated terms must never push a candidate under its own floor.
    (floor * (1.0 - 1e-9)).max(0.0)
}

/// Paper eq. 10–11 and E_trans: accuracy, smoothness and transmission, on a simulated travel (its
/// trace, the row of each pose, and the sine of its smallest transmission angle, in closed form where
/// the linkage has one). E_acc is the paper's mean squared miss of the body-carried joints plus the
/// mean squared miss of the bodies' outline vertices ([`Context::outline_miss`]): joints close
/// together on a large body can all be near their targets while the body is turned well away from
/// its pose, and the outline is what the person drew.
fn simulated_terms(
    ctx: &Context,
    frames: &BodyFrames,
    (trace, pose_rows, least_sine): (&Trace, &[usize], f64),
    targets: &[Point],
    soft: &mut SoftTerms,
) {
    let n = trace.joint_count;
    let poses = pose_rows.len();
    let moving = &ctx.moving_joints;
    let target = |i: usize, j: usize| targets[i * n + j];
    let count = moving.len() as f64;

    let mut joints_miss = 0.0;
    let mut outlines_miss = 0.0;
    for (i, &r) in pose_rows.iter().enumerate() {
        let row = trace.row(r);
        joints_miss += moving.iter().map(|&j| (row[j] - target(i, j)).norm_sq()).sum::<f64>();
        outlines_miss += (0..frames.body_count())
            .map(|b| ctx.outline_miss(b, i, &frames.isometry(b, row)).iter().map(|m| m * m).sum::<f64>())
            .sum::<f64>();
    }
    let accuracy = joints_miss / (poses as f64 * count) + outlines_miss / (poses * frames.body_count().max(1)) as f64;

    // Eq. 11's ratio path / chord, with a small length f added to both: the same for joints that move
    // (f is a twentieth of the body size), still at least 1, and bounded for a joint that hardly moves
    // between two poses, whose bare ratio would divide by almost nothing.
    let f = 0.05 * ctx.body_size;
    let mut smoothness = 0.0;
    for i in 0..poses - 1 {
        for &j in moving {
            let path: f64 =
                (pose_rows[i]..pose_rows[i + 1]).map(|r| trace.row(r + 1)[j].distance(trace.row(r)[j])).sum();
            smoothness += (path + f) / (target(i + 1, j).distance(target(i, j)) + f);
        }
    }
    smoothness /= (poses - 1) as f64 * count;

    soft[Term::Accuracy] = accuracy;
    soft[Term::Smoothness] = smoothness;
    soft[Term::Transmission] = transmission_shortfall(least_sine, ctx.comfortable_transmission_sine);
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::testing::assert_close;
    use crate::mechanism::MechanismType;
    use crate::synth::sample::{SampleScratch, Sampler};
    use crate::synth::testing::example;
    use proptest::prelude::*;

    proptest! {
        /// The unrolled row scan finds the row the plain scan finds: the first of least summed squared
        /// miss, compared by `total_cmp`, for one, two and more moving joints, ties included (rows
        /// are drawn from a few points, so equal errors are common).
        #[test]
        fn nearest_row_is_the_plain_scans(
            n in 1usize..6,
            rows in 1usize..40,
            coords in proptest::collection::vec(-3i32..3, 2 * 6 * 40),
            moving_mask in 1u8..64,
            target_coords in proptest::collection::vec(-3i32..3, 12),
        ) {
            let point = |c: &[i32]| Point::new(c[0] as f64 * 0.5, c[1] as f64 * 0.5);
            let positions: Vec<Point> = coords.chunks_exact(2).take(rows * n).map(point).collect();
            let targets: Vec<Point> = target_coords.chunks_exact(2).take(n).map(point).collect();
            let moving: Vec<usize> = (0..n).filter(|&j| moving_mask & (1 << j) != 0).collect();
            prop_assume!(!moving.is_empty());
            let error = |row: &[Point]| -> f64 { moving.iter().map(|&j| (row[j] - targets[j]).norm_sq()).sum() };
            let mut expected = (0, error(&positions[..n]));
            for (r, row) in positions.chunks_exact(n).enumerate().skip(1) {
                let e = error(row);
                if e.total_cmp(&expected.1).is_lt() {
                    expected = (r, e);
                }
            }
            prop_assert_eq!(nearest_row(&positions, n, &moving, &targets), expected.0);
        }
    }

    /// The bound that lets the sampler skip simulations is a true lower bound: no simulated candidate
    /// costs less than its static terms plus the floor under its simulated ones, and the floor is not
    /// vacuous (it reaches most of the way to the cost on some candidates).
    #[test]
    fn cost_floor_never_exceeds_the_simulated_cost() {
        for (name, ty) in [
            ("k1_sofa_bed", MechanismType::SliderCrank),
            ("k1_table", MechanismType::Chain),
            ("k2_wall_chair", MechanismType::Chain),
        ] {
            let problem = example(name);
            let ctx = Context::new(&problem, ty);
            let sampler = Sampler::new(&ctx, 0);
            let (mut sample_scratch, mut scratch) = (SampleScratch::default(), Scratch::default());
            let (mut checked, mut tight) = (0, 0);
            for i in 0..6000 {
                let Some(m) = sampler.sample(7, i, None, &mut sample_scratch) else { continue };
                let Ok(c) = evaluate(&ctx, m, Some(sample_scratch.motions()), f64::INFINITY, &mut scratch) else {
                    continue;
                };
                let floor = simulated_floor(&ctx, &c.mechanism, &scratch.targets);
                let simulated = ctx.weights.cost_of(&c.soft, Floor::Simulated);
                assert!(floor <= simulated, "{name} sample {i}: floor {floor} above {simulated}");
                // The whole floor, every term's bound, under the whole cost.
                let whole = cost_floor(&ctx, &c.mechanism, Some(sample_scratch.motions()), &mut scratch).unwrap();
                assert!(whole <= c.cost, "{name} sample {i}: floor {whole} above the cost {}", c.cost);
                checked += 1;
                tight += usize::from(floor > 0.5 * simulated);
            }
            assert!(checked > 20, "{name}: only {checked} candidates");
            assert!(tight > 0, "{name}: the floor never came near the cost");
        }
    }

    /// The minimiser against known minima: a parabola, a smooth non-polynomial function, a minimum at
    /// an end of the interval, and a function infinite on part of it; with the number of evaluations.
    #[test]
    fn minimise_finds_known_minima_in_either_order() {
        let mut calls = 0;
        let parabola = minimise(-1.0, 3.0, |x| {
            calls += 1;
            (x - 0.7) * (x - 0.7)
        });
        assert_close(parabola, 0.7, 1e-8);
        assert!(calls < 20, "{calls} evaluations for a parabola, where golden sections take fifty");
        assert_close(minimise(3.0, -1.0, |x| (x - 0.7) * (x - 0.7)), 0.7, 1e-8);
        // cos x + 0.1 (x − 3)^4 is not a parabola near its minimum.
        let exact = {
            // The minimiser of cos x + 0.1 (x − 3)^4: its derivative −sin x + 0.4 (x − 3)^3, by bisection.
            let (mut lo, mut hi) = (3.0f64, 3.3f64);
            for _ in 0..200 {
                let m = 0.5 * (lo + hi);
                if -m.sin() + 0.4 * (m - 3.0).powi(3) < 0.0 {
                    lo = m;
                } else {
                    hi = m;
                }
            }
            lo
        };
        // Function values locate a minimum to about the square root of their precision.
        assert_close(minimise(2.9, 3.5, |x| x.cos() + 0.1 * (x - 3.0).powi(4)), exact, 1e-7);
        // Monotone throughout: the end itself, exactly.
        assert_eq!(minimise(0.0, 1.0, |x| -x), 1.0);
        assert_eq!(minimise(1.0, 0.0, |x| x), 0.0);
        // Infinite left of 0.2 (the linkage does not assemble there).
        assert_close(minimise(0.0, 1.0, |x| if x < 0.2 { f64::INFINITY } else { (x - 0.5).abs() }), 0.5, 1e-8);
    }
}

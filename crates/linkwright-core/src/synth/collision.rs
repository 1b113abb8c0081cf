//! Collisions along a travel (paper §5.5): moving bodies against fixed bodies and each other, links
//! against avoid regions.
//!
//! Every row of the trace (1° crank steps) is tested exactly, and every interval between two rows is
//! checked by conservative advancement: a mover (a body outline or a link segment) cannot reach deeper
//! than the contact tolerance into an obstacle in between when its clearance at either end, plus that
//! tolerance, exceeds how far any of its points moves relative to the obstacle over the interval (the
//! farthest-moving point of a rigid motion is a vertex; a margin covers the arc), or when its
//! clearances at both ends together do, less twice the tolerance (a point that dips in must come back
//! out). Otherwise the interval is bisected, at most down to 1/16° (sixteen times finer than the
//! engine's crank step, eight times finer than `verify`'s re-simulation), so a body sliding along
//! another costs a bounded number of tests. Bounding boxes first, exact polygon
//! tests only where boxes come near; the sweep stops at the first collision, and four rows spread
//! over the travel are tested before it, where most colliding linkages are caught first.

use super::context::{Context, Pair};
use super::evaluate::{Candidate, Reject};
use crate::geom::{outline_distance, penetrates_unchecked, Aabb, Isometry, Obstacle, Point, Vec2};
use crate::kinematics::{BodyFrames, Plan, Trace};

/// Margin on a motion bound: a point's path over a short interval bulges past its chord a little.
const ARC_MARGIN: f64 = 1.5;
/// The rows tested before the sweep, in eighths of the travel: a colliding linkage usually collides
/// over a span, and rows spread evenly over the travel find most spans early (docs/performance.md,
/// "Collision sweep"); fewer or other rows catch fewer collisions, more do no better.
const PROBES: [usize; 4] = [1, 3, 5, 7];
/// Deepest bisection of one 1° interval (a sixteenth of a degree). At a quarter, a sharp corner of a
/// fixed body can poke through an edge sliding past it between two tests (the reference scene
/// `k1_handle`).
const MAX_DEPTH: u32 = 4;

/// Checks the whole travel of `candidate`: first the rows at `PROBES`, then the sweep
/// (`sweep_travel`).
///
/// A linkage that collides usually does so over a span of rows, and a few exact tests spread over the
/// travel find most such spans without proving the rows before them free first. A probe only finds a
/// penetration the sweep finds too (the sweep skips a row only where no point can have moved far
/// enough to penetrate), so the probes change no verdict; for a linkage that collides in more than
/// one way, they may change which reject is reported.
pub(crate) fn check_collisions(ctx: &Context, candidate: &Candidate, buffers: &mut SweepBuffers) -> Result<(), Reject> {
    let frames = BodyFrames::new(&candidate.mechanism, &ctx.first_poses);
    let sweep = Sweep { ctx, frames: &frames, plan: &candidate.plan };
    probe(&sweep, &candidate.trace, buffers)?;
    sweep_travel(&sweep, &candidate.trace, buffers)
}

/// Exact tests of every pair at the rows at [`PROBES`] of `trace`.
fn probe(sweep: &Sweep, trace: &Trace, buffers: &mut SweepBuffers) -> Result<(), Reject> {
    let last = trace.len().saturating_sub(1);
    for eighths in PROBES {
        sweep.place_into(trace.row(eighths * last / 8), &mut buffers.current);
        for &pair in &sweep.ctx.collision_pairs {
            sweep.test(pair, &buffers.current)?;
        }
    }
    Ok(())
}

/// Sweeps the whole travel `trace`.
///
/// Each pair keeps a slack: its boundary distance at the last exact test plus the contact tolerance,
/// minus how far the mover has moved relative to the obstacle since (a bound on every point's path).
/// While the slack is positive the pair cannot have met, so its rows and intervals need no test; when
/// it runs out, the slack restarts from the distance at the new row, and only when that distance is
/// smaller than the last step's motion are the interval proven or bisected as above and the row
/// tested exactly. Far from obstacles this skips most of the work; in sliding contact
/// it tests every row and interval. Where no two moving bodies are paired, a body's motion over a step
/// is bounded from its two frame joints ([`BodyReach`]), and rows are placed only where a slack runs
/// out: about two rows in three are not (folding table, sofa bed).
fn sweep_travel(sweep: &Sweep, trace: &Trace, buffers: &mut SweepBuffers) -> Result<(), Reject> {
    let ctx = sweep.ctx;
    let pairs = &ctx.collision_pairs;
    let SweepBuffers { reaches, frames_at, previous, current, slack, distance_before, body_motion, midpoints } =
        buffers;
    // A pair of moving bodies needs both placed at every row for their relative motion.
    let placing_every_row = pairs.iter().any(|p| matches!(p, Pair::BodyBody { .. }));
    reaches.clear();
    reaches.extend(
        ctx.problem.bodies.iter().enumerate().map(|(b, body)| BodyReach::new(sweep.frames, b, body.outline.vertices())),
    );
    frames_at.clear();
    frames_at.extend(reaches.iter().map(|reach| reach.frame(trace.row(0))));
    sweep.place_into(trace.row(0), previous);
    // The row `previous` holds.
    let mut previous_row = 0;
    slack.clear();
    // Each pair's boundary distance at the previous row, when it was computed there.
    distance_before.clear();
    for &pair in pairs.iter() {
        sweep.test(pair, previous)?;
        let distance = sweep.distance(pair, previous);
        slack.push(distance + ctx.contact_tolerance);
        distance_before.push(Some(distance));
    }
    midpoints.resize_with(MAX_DEPTH as usize, Midpoint::default);
    for mid in midpoints.iter_mut() {
        mid.row.resize(trace.joint_count, Point::ORIGIN);
    }
    for r in 1..trace.len() {
        let (row_before, row) = (trace.row(r - 1), trace.row(r));
        let mut placed = placing_every_row;
        body_motion.clear();
        if placing_every_row {
            sweep.place_into(row, current);
            body_motion.extend(previous.bodies.iter().zip(&current.bodies).map(|(p, q)| largest_motion(p, q)));
        } else {
            for (reach, at) in reaches.iter().zip(frames_at.iter_mut()) {
                let next = reach.frame(row);
                body_motion.push(reach.motion(*at, next));
                *at = next;
            }
        }
        for (k, &pair) in pairs.iter().enumerate() {
            let moved = match pair {
                Pair::LinkAvoid { link, .. } => {
                    let (a, b) = ctx.link_pairs[link];
                    largest_motion(&[row_before[a], row_before[b]], &[row[a], row[b]])
                }
                Pair::BodyFixed { body, .. } => body_motion[body],
                Pair::BodyBody { body, other } => sweep.relative_motion(body, other, previous, current),
            };
            let reach = ARC_MARGIN * moved;
            slack[k] -= reach;
            if slack[k] > 0.0 {
                distance_before[k] = None;
                continue;
            }
            if !placed {
                sweep.place_into(row, current);
                placed = true;
            }
            // The gap between the two boxes is a lower bound on the distance: when it alone covers the
            // step, the pair is proven apart over it as the distance would prove, and the slack
            // restarts from the gap (no distance needed).
            let gap = sweep.box_gap(pair, current) + ctx.contact_tolerance;
            if gap > reach {
                slack[k] = gap;
                distance_before[k] = None;
                continue;
            }
            let distance = sweep.distance(pair, current);
            let clearance = distance + ctx.contact_tolerance;
            // Free at the previous row and no closer to it here than its motion: free in between and here.
            if clearance <= reach {
                if previous_row != r - 1 {
                    sweep.place_into(row_before, previous);
                    previous_row = r - 1;
                }
                let before = distance_before[k].unwrap_or_else(|| sweep.distance(pair, previous));
                let a = End { theta: trace.thetas[r - 1], at: previous, distance: before };
                let b = End { theta: trace.thetas[r], at: current, distance };
                sweep.interval(pair, a, b, midpoints)?;
                sweep.test(pair, current)?;
            }
            slack[k] = clearance;
            distance_before[k] = Some(distance);
        }
        if placed {
            std::mem::swap(previous, current);
            previous_row = r;
        }
    }
    Ok(())
}

/// A body's frame in one configuration: where its outline's bounding circle's centre is, and the unit
/// direction of the frame's x axis; `None` when the frame joints coincide.
type Frame = (Point, Vec2);

/// How far a body's outline moves between two configurations, bounded from its two frame joints
/// without placing it: a point at `e` from the centre of the outline's bounding circle (in the
/// frame) moves by the centre's displacement plus `(R(û′) − R(û))e`, whose length is `|û′ − û|·|e|`
/// exactly. The bound is exact for a pure translation and for a turn about the centre.
#[derive(Debug)]
struct BodyReach {
    /// The frame joints: the origin, and the joint the x axis points to.
    joints: (usize, usize),
    /// The bounding circle's centre in frame coordinates, and its radius.
    center: Point,
    radius: f64,
}

impl BodyReach {
    fn new(frames: &BodyFrames, b: usize, outline: &[Point]) -> BodyReach {
        let (a, c, body_to_frame) = frames.frame(b);
        let bounds = Aabb::around(outline.iter().copied()).expect("outlines have vertices");
        let center = bounds.min.lerp(bounds.max, 0.5);
        let radius = outline.iter().map(|p| p.distance(center)).fold(0.0, f64::max);
        BodyReach { joints: (a, c), center: body_to_frame.apply(center), radius }
    }

    fn frame(&self, row: &[Point]) -> Option<Frame> {
        let (origin, toward) = (row[self.joints.0], row[self.joints.1]);
        let axis = toward - origin;
        let length = axis.norm();
        if !(length > 0.0 && length.is_finite()) {
            return None;
        }
        let u = axis / length;
        let c = self.center.to_vec2();
        Some((origin + Vec2::new(u.x * c.x - u.y * c.y, u.y * c.x + u.x * c.y), u))
    }

    /// The bound between two frames (unbounded when either is undefined).
    fn motion(&self, from: Option<Frame>, to: Option<Frame>) -> f64 {
        match (from, to) {
            (Some((c0, u0)), Some((c1, u1))) => c0.distance(c1) + (u1 - u0).norm() * self.radius,
            _ => f64::INFINITY,
        }
    }
}

/// One end of an interval the sweep must prove free: a tested configuration and the pair's boundary
/// distance there.
#[derive(Clone, Copy)]
struct End<'a> {
    theta: f64,
    at: &'a Placed,
    distance: f64,
}

/// Reused buffers for one level of bisection.
#[derive(Debug, Default)]
struct Midpoint {
    row: Vec<Point>,
    placed: Placed,
}

/// The sweep's buffers, reused from candidate to candidate.
#[derive(Debug, Default)]
pub(crate) struct SweepBuffers {
    reaches: Vec<BodyReach>,
    /// Each body's frame at the last row seen.
    frames_at: Vec<Option<Frame>>,
    /// The last row placed, and the row being placed.
    previous: Placed,
    current: Placed,
    /// Per pair: its slack, and its boundary distance at the previous row when it was computed there.
    slack: Vec<f64>,
    distance_before: Vec<Option<f64>>,
    /// Per body: how far it moved over the last step.
    body_motion: Vec<f64>,
    /// One per level of bisection.
    midpoints: Vec<Midpoint>,
}

/// Every mover placed in one configuration: body outlines, then link segments.
#[derive(Debug, Default)]
struct Placed {
    poses: Vec<Isometry>,
    bodies: Vec<Vec<Point>>,
    body_boxes: Vec<Aabb>,
    links: Vec<[Point; 2]>,
}

/// What a mover must not penetrate: a fixed obstacle, prepared once, or another moving body's outline
/// and box in the same configuration.
enum Other<'a> {
    Fixed(&'a Obstacle),
    Moving(&'a [Point], Aabb),
}

impl Other<'_> {
    fn bounds(&self) -> Aabb {
        match self {
            Other::Fixed(obstacle) => obstacle.bounds(),
            Other::Moving(_, bb) => *bb,
        }
    }
    fn penetrated_by(&self, mover: &[Point], tol: f64) -> bool {
        match self {
            Other::Fixed(obstacle) => obstacle.penetrated_by(mover),
            Other::Moving(outline, _) => penetrates_unchecked(mover, outline, tol),
        }
    }
    fn distance(&self, mover: &[Point]) -> f64 {
        match self {
            Other::Fixed(obstacle) => obstacle.boundary_distance(mover),
            Other::Moving(outline, _) => outline_distance(mover, outline),
        }
    }
}

struct Sweep<'s, 'p> {
    ctx: &'s Context<'p>,
    frames: &'s BodyFrames,
    plan: &'s Plan,
}

impl Sweep<'_, '_> {
    #[cfg(test)]
    fn place(&self, row: &[Point]) -> Placed {
        let mut placed = Placed::default();
        self.place_into(row, &mut placed);
        placed
    }

    /// [`Sweep::place`] into reused buffers.
    fn place_into(&self, row: &[Point], out: &mut Placed) {
        let problem = self.ctx.problem;
        out.poses.clear();
        out.poses.extend((0..problem.bodies.len()).map(|b| self.frames.isometry(b, row)));
        out.bodies.resize_with(problem.bodies.len(), Vec::new);
        out.body_boxes.clear();
        for ((body, pose), outline) in problem.bodies.iter().zip(&out.poses).zip(&mut out.bodies) {
            outline.clear();
            outline.extend(body.outline.vertices().iter().map(|&p| pose.apply(p)));
            out.body_boxes.push(Aabb::around(outline.iter().copied()).expect("outlines have vertices"));
        }
        out.links.clear();
        out.links.extend(self.ctx.link_pairs.iter().map(|&(a, b)| [row[a], row[b]]));
    }

    /// The mover's outline and box in configuration `at`, what it must not penetrate, and the verdict
    /// when it does.
    fn shapes<'a>(&'a self, pair: Pair, at: &'a Placed) -> (&'a [Point], Aabb, Other<'a>, Reject) {
        match pair {
            Pair::LinkAvoid { link, avoid } => {
                let segment = &at.links[link];
                let bb = Aabb::around(segment.iter().copied()).expect("two points");
                (segment, bb, Other::Fixed(&self.ctx.avoid_obstacles[avoid]), Reject::AvoidRegion)
            }
            Pair::BodyFixed { body, fixed } => (
                &at.bodies[body],
                at.body_boxes[body],
                Other::Fixed(&self.ctx.fixed_obstacles[fixed]),
                Reject::Collision,
            ),
            Pair::BodyBody { body, other } => (
                &at.bodies[body],
                at.body_boxes[body],
                Other::Moving(&at.bodies[other], at.body_boxes[other]),
                Reject::Collision,
            ),
        }
    }

    /// Exact penetration test of one pair in one configuration.
    fn test(&self, pair: Pair, at: &Placed) -> Result<(), Reject> {
        let tol = self.ctx.contact_tolerance;
        let (mover, mover_box, other, verdict) = self.shapes(pair, at);
        if !mover_box.overlaps(&other.bounds(), tol) {
            return Ok(());
        }
        let penetrates = match (pair, other) {
            (Pair::BodyFixed { body, .. }, Other::Fixed(obstacle)) => {
                obstacle.penetrated_by_shape(mover, &self.ctx.body_shapes[body], &at.poses[body])
            }
            (_, other) => other.penetrated_by(mover, tol),
        };
        if penetrates {
            return Err(verdict);
        }
        Ok(())
    }

    /// The gap between the mover's box and the obstacle's in configuration `at`: at most the distance.
    fn box_gap(&self, pair: Pair, at: &Placed) -> f64 {
        let (_, mover_box, other, _) = self.shapes(pair, at);
        mover_box.gap(&other.bounds())
    }

    /// The distance between the pair's boundaries in a configuration where they do not penetrate
    /// (0 when they touch or overlap within the contact tolerance).
    fn distance(&self, pair: Pair, at: &Placed) -> f64 {
        let (mover, _, other, _) = self.shapes(pair, at);
        other.distance(mover)
    }

    /// Proves the pair apart over the open interval between two tested configurations, bisecting
    /// where it cannot; `midpoints` holds one buffer per level of bisection still allowed.
    fn interval(&self, pair: Pair, a: End, b: End, midpoints: &mut [Midpoint]) -> Result<(), Reject> {
        let Some((mid, deeper)) = midpoints.split_first_mut() else { return Ok(()) };
        if self.proven_free(pair, a, b) {
            return Ok(());
        }
        let theta = 0.5 * (a.theta + b.theta);
        // Between two assembled configurations whose transmission margins are above the bound, no
        // dead point intervenes; failing to assemble here means the linkage locks up.
        self.plan.solve(theta, &mut mid.row).map_err(|_| Reject::Assembly)?;
        self.place_into(&mid.row, &mut mid.placed);
        self.test(pair, &mid.placed)?;
        if deeper.is_empty() {
            return Ok(());
        }
        let m = End { theta, at: &mid.placed, distance: self.distance(pair, &mid.placed) };
        self.interval(pair, a, m, deeper)?;
        self.interval(pair, m, b, deeper)
    }

    /// True when the pair's mover cannot reach deeper than the contact tolerance into its obstacle
    /// between the two ends: a point that dips deeper than the tolerance in between covers its
    /// clearance at one end, twice that depth, and its clearance at the other, so the interval is free
    /// when the two clearances together are at least the reach less twice the tolerance.
    fn proven_free(&self, pair: Pair, a: End, b: End) -> bool {
        let tol = self.ctx.contact_tolerance;
        // How far the mover moves relative to the obstacle, and how far both wander from the boxes
        // around their two placements.
        let (moved, wander) = match pair {
            Pair::LinkAvoid { link, .. } => {
                let moved = largest_motion(&a.at.links[link], &b.at.links[link]);
                (moved, moved)
            }
            Pair::BodyFixed { body, .. } => {
                let moved = largest_motion(&a.at.bodies[body], &b.at.bodies[body]);
                (moved, moved)
            }
            Pair::BodyBody { body, other } => (
                self.relative_motion(body, other, a.at, b.at).max(0.0),
                largest_motion(&a.at.bodies[body], &b.at.bodies[body])
                    + largest_motion(&a.at.bodies[other], &b.at.bodies[other]),
            ),
        };
        if moved <= tol {
            return true;
        }
        let (_, box_a, other_a, _) = self.shapes(pair, a.at);
        let (_, box_b, other_b, _) = self.shapes(pair, b.at);
        if box_a.union(&box_b).gap(&other_a.bounds().union(&other_b.bounds())) > ARC_MARGIN * wander {
            return true;
        }
        a.distance + b.distance >= ARC_MARGIN * moved - 2.0 * tol
    }
}

impl Sweep<'_, '_> {
    /// The farthest any vertex of body `k` moves in body `c`'s frame from configuration `a` to `b`.
    fn relative_motion(&self, k: usize, c: usize, a: &Placed, b: &Placed) -> f64 {
        let in_c_at_a = a.poses[k].then(&a.poses[c].inverse());
        let in_c_at_b = b.poses[k].then(&b.poses[c].inverse());
        self.ctx.problem.bodies[k]
            .outline
            .vertices()
            .iter()
            .map(|&v| in_c_at_a.apply(v).distance(in_c_at_b.apply(v)))
            .fold(0.0, f64::max)
    }
}

/// The farthest any vertex moved between two placements of one outline.
fn largest_motion(a: &[Point], b: &[Point]) -> f64 {
    a.iter().zip(b).map(|(p, q)| p.distance(*q)).fold(0.0, f64::max)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mechanism::MechanismType;
    use crate::synth::sample::Sampler;
    use crate::synth::testing::{defect_free, example, pose_examples};

    /// The probes find a collision only where the sweep finds one too, so the check's verdict is the
    /// sweep's, on the travels of sampled candidates of three scenes (one with two moving bodies);
    /// and the probes do find most of the collisions.
    #[test]
    fn probes_change_no_verdict() {
        let (mut colliding, mut probed, mut free) = (0, 0, 0);
        let scenes = [
            ("k1_sofa_bed", MechanismType::SliderCrank),
            ("k1_table", MechanismType::Chain),
            ("k2_wall_bed", MechanismType::Chain),
        ];
        for (name, family) in scenes {
            let problem = example(name);
            let ctx = Context::new(&problem, family);
            let sampler = Sampler::new(&ctx, 0);
            let mut buffers = SweepBuffers::default();
            let mut candidates = 0;
            for c in defect_free(&ctx, &sampler, 7, 0..200_000).take(300) {
                let frames = BodyFrames::new(&c.mechanism, &ctx.first_poses);
                let sweep = Sweep { ctx: &ctx, frames: &frames, plan: &c.plan };
                let by_probe = probe(&sweep, &c.trace, &mut buffers).is_err();
                let by_sweep = sweep_travel(&sweep, &c.trace, &mut buffers).is_err();
                assert!(!by_probe || by_sweep, "{name}: a probe found a collision the sweep does not");
                assert_eq!(check_collisions(&ctx, &c, &mut buffers).is_err(), by_sweep, "{name}");
                colliding += by_sweep as usize;
                probed += by_probe as usize;
                free += !by_sweep as usize;
                candidates += 1;
            }
            assert_eq!(candidates, 300, "{name}");
        }
        assert!(free >= 30 && colliding >= 300, "{free} free, {colliding} colliding");
        assert!(probed * 2 >= colliding, "the probes found {probed} of {colliding} collisions");
    }

    /// Along the travels of sampled candidates, the bound from the frame joints is at least the
    /// farthest any vertex of the placed outline moves between two rows (consecutive, and farther
    /// apart), and not much more: at most the centre's motion plus the turn's whole sweep.
    #[test]
    fn body_reach_bounds_the_placed_outlines_motion() {
        let (mut compared, mut tight) = (0, 0);
        for (name, family) in [("k1_sofa_bed", MechanismType::SliderCrank), ("k1_table", MechanismType::Chain)] {
            let problem = example(name);
            let ctx = Context::new(&problem, family);
            let sampler = Sampler::new(&ctx, 0);
            let mut candidates = 0;
            for c in defect_free(&ctx, &sampler, 5, 0..20_000).take(20) {
                let frames = BodyFrames::new(&c.mechanism, &ctx.first_poses);
                let sweep = Sweep { ctx: &ctx, frames: &frames, plan: &c.plan };
                let body = &problem.bodies[0];
                let reach = BodyReach::new(&frames, 0, body.outline.vertices());
                let trace = &c.trace;
                for r in 1..trace.len() {
                    for from in [r - 1, r / 2] {
                        let (a, b) = (sweep.place(trace.row(from)), sweep.place(trace.row(r)));
                        let exact = largest_motion(&a.bodies[0], &b.bodies[0]);
                        let bound = reach.motion(reach.frame(trace.row(from)), reach.frame(trace.row(r)));
                        let scale = 1e-9 * (body.size + reach.radius);
                        assert!(bound >= exact - scale, "{name}: bound {bound} under the motion {exact}");
                        compared += 1;
                        tight += (bound <= 2.0 * exact + scale) as usize;
                    }
                }
                candidates += 1;
            }
            assert_eq!(candidates, 20, "{name}");
        }
        assert!(tight * 10 >= compared * 9, "{tight} of {compared} within twice the motion");
    }

    /// The sweep's verdict is that of exact tests of every pair at every 1/64 of every step, on
    /// sampled travels of every bundled scene (all three families): it misses no collision that
    /// such a fine re-simulation finds, though its proofs assume a margin ([`ARC_MARGIN`]) that some
    /// fast-moving linkages exceed (docs/performance.md, on `ARC_MARGIN`). A sweep that bisects no interval,
    /// or takes a third of the margin, misses some.
    #[test]
    fn sweep_agrees_with_exact_tests_at_every_64th_of_a_step() {
        const FINE: usize = 64;
        let (mut compared, mut colliding) = (0, 0);
        for (name, problem) in pose_examples() {
            let families: &[MechanismType] = match problem.bodies.len() {
                1 => &[MechanismType::Chain, MechanismType::SliderCrank],
                _ => &[MechanismType::Chain],
            };
            for &family in families {
                let ctx = Context::new(&problem, family);
                let sampler = Sampler::new(&ctx, 0);
                let mut buffers = SweepBuffers::default();
                for c in defect_free(&ctx, &sampler, 13, 0..60_000).take(60) {
                    let frames = BodyFrames::new(&c.mechanism, &ctx.first_poses);
                    let sweep = Sweep { ctx: &ctx, frames: &frames, plan: &c.plan };
                    let thetas = &c.trace.thetas;
                    let mut fine = std::iter::once(thetas[0]).chain(
                        thetas
                            .windows(2)
                            .flat_map(|w| (1..=FINE).map(move |s| w[0] + (w[1] - w[0]) * s as f64 / FINE as f64)),
                    );
                    let mut row = vec![Point::ORIGIN; c.trace.joint_count];
                    let mut collides = |theta: f64| {
                        c.plan.solve(theta, &mut row).is_ok() && {
                            let placed = sweep.place(&row);
                            ctx.collision_pairs.iter().any(|&pair| sweep.test(pair, &placed).is_err())
                        }
                    };
                    let exact = fine.any(&mut collides);
                    let swept = check_collisions(&ctx, &c, &mut buffers).is_err();
                    assert_eq!(swept, exact, "{name}, {family:?}: the sweep says {swept}, the exact tests {exact}");
                    compared += 1;
                    colliding += exact as usize;
                }
            }
        }
        assert!(compared >= 1000 && colliding * 3 >= compared, "{colliding} colliding of {compared}");
    }
}

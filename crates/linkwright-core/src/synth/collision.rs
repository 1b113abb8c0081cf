//! Collisions along a travel (paper §5.5): moving bodies against fixed bodies and each other, links
//! against avoid regions.
//!
//! Every row of the trace (1° crank steps) is tested exactly, and every interval between two rows is
//! checked by conservative advancement: a mover (a body outline or a link segment) cannot reach deeper
//! than the contact tolerance into an obstacle in between when its clearance at either end, plus that
//! tolerance, exceeds how far any of its points moves relative to the obstacle over the interval (the
//! farthest-moving point of a rigid motion is a vertex; a margin covers the arc). Otherwise the
//! interval is bisected, at most down to 1/4° (four times finer than the engine's crank step and
//! twice as fine as `verify`'s re-simulation), so a body sliding along another costs a bounded number
//! of tests. Bounding boxes first, exact polygon
//! tests only where boxes come near; the sweep stops at the first collision.

use super::context::Context;
use super::evaluate::{Candidate, Reject, Scratch};
use crate::geom::{penetrates_unchecked, point_segment_distance_sq, Aabb, Point, Rigid, Vec2};
use crate::kinematics::{BodyFrames, Plan};

/// Margin on a motion bound: a point's path over a short interval bulges past its chord a little.
const ARC_MARGIN: f64 = 1.5;
/// Deepest bisection of one 1° interval (a quarter of a degree).
const MAX_DEPTH: u32 = 2;

/// Checks the whole travel of `candidate`.
pub fn check_collisions(ctx: &Context, candidate: &Candidate, _scratch: &mut Scratch) -> Result<(), Reject> {
    let frames = BodyFrames::new(&candidate.mechanism, &ctx.first_poses);
    let sweep = Sweep { ctx, frames: &frames, plan: &candidate.plan };
    let trace = &candidate.trace;
    let mut previous = sweep.place(trace.row(0));
    sweep.test(&previous)?;
    for r in 1..trace.len() {
        let current = sweep.place(trace.row(r));
        sweep.test(&current)?;
        sweep.interval(trace.thetas[r - 1], &previous, trace.thetas[r], &current, 0)?;
        previous = current;
    }
    Ok(())
}

/// Every mover placed in one configuration: body outlines, then link segments.
struct Placed {
    poses: Vec<Rigid>,
    bodies: Vec<Vec<Point>>,
    body_boxes: Vec<Aabb>,
    links: Vec<[Point; 2]>,
}

struct Sweep<'s, 'p> {
    ctx: &'s Context<'p>,
    frames: &'s BodyFrames,
    plan: &'s Plan,
}

impl Sweep<'_, '_> {
    fn place(&self, row: &[Point]) -> Placed {
        let problem = self.ctx.problem;
        let poses: Vec<Rigid> = (0..problem.bodies.len()).map(|b| self.frames.pose(b, row)).collect();
        let bodies: Vec<Vec<Point>> = problem
            .bodies
            .iter()
            .zip(&poses)
            .map(|(body, pose)| body.outline.vertices().iter().map(|&p| pose.apply(p)).collect())
            .collect();
        let body_boxes =
            bodies.iter().map(|o| Aabb::around(o.iter().copied()).expect("outlines have vertices")).collect();
        let links = self.ctx.link_segments.iter().map(|&(a, b)| [row[a], row[b]]).collect();
        Placed { poses, bodies, body_boxes, links }
    }

    /// Exact penetration tests of one configuration.
    fn test(&self, at: &Placed) -> Result<(), Reject> {
        let ctx = self.ctx;
        let tol = ctx.contact_tolerance;
        for link in &at.links {
            let bb = Aabb::around(link.iter().copied()).expect("two points");
            for (avoid, avoid_box) in ctx.problem.avoid.iter().zip(&ctx.avoid_boxes) {
                if bb.overlaps(avoid_box, tol) && penetrates_unchecked(link, avoid.vertices(), tol) {
                    return Err(Reject::AvoidRegion);
                }
            }
        }
        for (b, (outline, bb)) in at.bodies.iter().zip(&at.body_boxes).enumerate() {
            for (fixed, fixed_box) in ctx.problem.fixed.iter().zip(&ctx.fixed_boxes) {
                if bb.overlaps(fixed_box, tol) && penetrates_unchecked(outline, fixed.vertices(), tol) {
                    return Err(Reject::Collision);
                }
            }
            for c in 0..b {
                if bb.overlaps(&at.body_boxes[c], tol) && penetrates_unchecked(outline, &at.bodies[c], tol) {
                    return Err(Reject::Collision);
                }
            }
        }
        Ok(())
    }

    /// Proves the open interval between two tested configurations free, bisecting where it cannot.
    fn interval(&self, ta: f64, a: &Placed, tb: f64, b: &Placed, depth: u32) -> Result<(), Reject> {
        if depth >= MAX_DEPTH || self.proven_free(a, b) {
            return Ok(());
        }
        let tm = 0.5 * (ta + tb);
        let mut row = vec![Point::ORIGIN; self.plan.joint_count()];
        // Between two assembled configurations whose transmission margins are above the bound, no
        // dead point intervenes; failing to assemble here means the linkage locks up.
        self.plan.solve(tm, &mut row).map_err(|_| Reject::Assembly)?;
        let m = self.place(&row);
        self.test(&m)?;
        self.interval(ta, a, tm, &m, depth + 1)?;
        self.interval(tm, &m, tb, b, depth + 1)
    }

    /// True when no mover can reach deeper than the contact tolerance into an obstacle between
    /// configurations `a` and `b`.
    fn proven_free(&self, a: &Placed, b: &Placed) -> bool {
        let ctx = self.ctx;
        let tol = ctx.contact_tolerance;
        let fine = tol;
        let body_motion: Vec<f64> = a.bodies.iter().zip(&b.bodies).map(|(p, q)| largest_motion(p, q)).collect();
        for (k, &moved) in body_motion.iter().enumerate() {
            if moved <= fine {
                continue;
            }
            let swept = a.body_boxes[k].union(&b.body_boxes[k]);
            for (fixed, fixed_box) in ctx.problem.fixed.iter().zip(&ctx.fixed_boxes) {
                let reach = ARC_MARGIN * moved;
                if box_gap(&swept, fixed_box) > reach {
                    continue;
                }
                let need = reach - tol;
                if !clear_of(&a.bodies[k], fixed.vertices(), need) && !clear_of(&b.bodies[k], fixed.vertices(), need) {
                    return false;
                }
            }
            for (c, &other_moved) in body_motion.iter().enumerate().take(k) {
                let other = a.body_boxes[c].union(&b.body_boxes[c]);
                if box_gap(&swept, &other) > ARC_MARGIN * (moved + other_moved) {
                    continue;
                }
                // Bodies that move together are judged by how they move relative to each other.
                let reach = ARC_MARGIN * self.relative_motion(k, c, a, b).max(0.0);
                if reach <= fine {
                    continue;
                }
                let need = reach - tol;
                if !clear_of(&a.bodies[k], &a.bodies[c], need) && !clear_of(&b.bodies[k], &b.bodies[c], need) {
                    return false;
                }
            }
        }
        for (la, lb) in a.links.iter().zip(&b.links) {
            let moved = largest_motion(la, lb);
            if moved <= fine {
                continue;
            }
            let reach = ARC_MARGIN * moved;
            let swept = Aabb::around(la.iter().chain(lb).copied()).expect("four points");
            for (avoid, avoid_box) in ctx.problem.avoid.iter().zip(&ctx.avoid_boxes) {
                if box_gap(&swept, avoid_box) > reach {
                    continue;
                }
                let need = reach - tol;
                if !clear_of(la, avoid.vertices(), need) && !clear_of(lb, avoid.vertices(), need) {
                    return false;
                }
            }
        }
        true
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

/// The gap between two boxes (0 when they overlap).
fn box_gap(a: &Aabb, b: &Aabb) -> f64 {
    let dx = (b.min.x - a.max.x).max(a.min.x - b.max.x).max(0.0);
    let dy = (b.min.y - a.max.y).max(a.min.y - b.max.y).max(0.0);
    Vec2::new(dx, dy).norm()
}

/// True when the boundaries of two outlines that do not cross (a two-point outline is a segment) are
/// at least `gap` apart. The nearest pair of boundary points always includes a vertex of one of them;
/// the test stops at the first pair closer than `gap`.
fn clear_of(a: &[Point], b: &[Point], gap: f64) -> bool {
    if gap <= 0.0 {
        return true;
    }
    let gap_sq = gap * gap;
    let one_way = |p: &[Point], q: &[Point]| {
        let n = q.len();
        let edges = if n == 2 { 1 } else { n };
        p.iter().all(|&v| (0..edges).all(|i| point_segment_distance_sq(v, q[i], q[(i + 1) % n]) >= gap_sq))
    };
    one_way(a, b) && one_way(b, a)
}

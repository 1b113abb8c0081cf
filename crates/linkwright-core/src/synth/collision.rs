//! Collisions along a travel (paper §5.5): moving bodies against fixed bodies and each other, links
//! against avoid regions, at every row of the trace (1° crank steps or finer). Bounding boxes first,
//! exact polygon tests only where boxes overlap; the sweep stops at the first collision.

use super::context::Context;
use super::evaluate::{Candidate, Reject, Scratch};
use crate::geom::{penetrates_unchecked, Aabb, Point};
use crate::kinematics::BodyFrames;

/// Checks the whole travel of `candidate`.
pub fn check_collisions(ctx: &Context, candidate: &Candidate, scratch: &mut Scratch) -> Result<(), Reject> {
    let problem = ctx.problem;
    let tol = ctx.contact_tolerance;
    let frames = BodyFrames::new(&candidate.mechanism, &ctx.first_poses);
    let bodies = problem.bodies.len();
    scratch.outlines.resize_with(bodies, Vec::new);
    let mut boxes = vec![Aabb { min: Point::ORIGIN, max: Point::ORIGIN }; bodies];
    let trace = &candidate.trace;
    for r in 0..trace.len() {
        let row = trace.row(r);
        for (seg_a, seg_b) in ctx.link_segments.iter().map(|&(a, b)| (row[a], row[b])) {
            let seg_box = Aabb::around([seg_a, seg_b]).expect("two points");
            for (avoid, avoid_box) in problem.avoid.iter().zip(&ctx.avoid_boxes) {
                if seg_box.overlaps(avoid_box, tol) && penetrates_unchecked(&[seg_a, seg_b], avoid.vertices(), tol) {
                    return Err(Reject::AvoidRegion);
                }
            }
        }
        for b in 0..bodies {
            let pose = frames.pose(b, row);
            let outline = &mut scratch.outlines[b];
            outline.clear();
            outline.extend(problem.bodies[b].outline.vertices().iter().map(|&p| pose.apply(p)));
            boxes[b] = Aabb::around(outline.iter().copied()).expect("outlines have vertices");
            for (fixed, fixed_box) in problem.fixed.iter().zip(&ctx.fixed_boxes) {
                if boxes[b].overlaps(fixed_box, tol) && penetrates_unchecked(outline, fixed.vertices(), tol) {
                    return Err(Reject::Collision);
                }
            }
            for c in 0..b {
                if boxes[b].overlaps(&boxes[c], tol)
                    && penetrates_unchecked(&scratch.outlines[b], &scratch.outlines[c], tol)
                {
                    return Err(Reject::Collision);
                }
            }
        }
    }
    Ok(())
}

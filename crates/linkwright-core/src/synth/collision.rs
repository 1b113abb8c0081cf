//! Collisions along a travel (paper §5.5): moving bodies against fixed bodies and each other, links
//! against avoid regions. Every row of the trace (1° crank steps) is tested, and wherever a body's
//! swept box comes near an obstacle between two rows, the interval is subdivided so that no body
//! point moves more than [`SUBSTEP`]·d between tests: a brief penetration between crank steps is
//! found too. Bounding boxes first, exact polygon tests only where boxes overlap; the sweep stops at
//! the first collision.

use super::context::Context;
use super::evaluate::{Candidate, Reject, Scratch};
use crate::geom::{penetrates_unchecked, Aabb, Point};
use crate::kinematics::{BodyFrames, Plan};

/// Largest motion of any body point between two collision tests near an obstacle, as a fraction of d.
pub const SUBSTEP: f64 = 0.005;

/// Checks the whole travel of `candidate`.
pub fn check_collisions(ctx: &Context, candidate: &Candidate, scratch: &mut Scratch) -> Result<(), Reject> {
    let frames = BodyFrames::new(&candidate.mechanism, &ctx.first_poses);
    let trace = &candidate.trace;
    let bodies = ctx.problem.bodies.len();
    let mut sweep = Sweep {
        ctx,
        frames: &frames,
        plan: &candidate.plan,
        previous: vec![Vec::new(); bodies],
        current: vec![Vec::new(); bodies],
    };
    sweep.test(trace.row(0), false)?;
    std::mem::swap(&mut sweep.previous, &mut sweep.current);
    let step = SUBSTEP * ctx.body_size;
    for r in 1..trace.len() {
        sweep.test(trace.row(r), false)?;
        let moved = sweep.largest_motion();
        if moved > step && sweep.swept_boxes_meet_obstacles(moved) {
            let pieces = (moved / step).ceil() as usize;
            let (from, to) = (trace.thetas[r - 1], trace.thetas[r]);
            scratch.sub_row.resize(trace.joint_count, Point::ORIGIN);
            for k in 1..pieces {
                let theta = from + (to - from) * k as f64 / pieces as f64;
                // Between two rows that assemble, the plan assembles too (no dead point lies between
                // rows whose transmission margins are both above the bound); if it does not, the
                // linkage locks up there.
                candidate.plan.solve(theta, &mut scratch.sub_row).map_err(|_| Reject::Assembly)?;
                sweep.test(&scratch.sub_row, true)?;
            }
        }
        std::mem::swap(&mut sweep.previous, &mut sweep.current);
    }
    Ok(())
}

/// The state of one sweep: the bodies' outlines at the previous and the current row.
struct Sweep<'s, 'p> {
    ctx: &'s Context<'p>,
    frames: &'s BodyFrames,
    #[allow(dead_code, reason = "kept beside the frames it was compiled with, for substeps")]
    plan: &'s Plan,
    previous: Vec<Vec<Point>>,
    current: Vec<Vec<Point>>,
}

impl Sweep<'_, '_> {
    /// Tests one configuration. A substep places its outlines in a scratch slot so `current` keeps the
    /// row's outlines.
    fn test(&mut self, row: &[Point], substep: bool) -> Result<(), Reject> {
        let ctx = self.ctx;
        let problem = ctx.problem;
        let tol = ctx.contact_tolerance;
        for (seg_a, seg_b) in ctx.link_segments.iter().map(|&(a, b)| (row[a], row[b])) {
            let seg_box = Aabb::around([seg_a, seg_b]).expect("two points");
            for (avoid, avoid_box) in problem.avoid.iter().zip(&ctx.avoid_boxes) {
                if seg_box.overlaps(avoid_box, tol) && penetrates_unchecked(&[seg_a, seg_b], avoid.vertices(), tol) {
                    return Err(Reject::AvoidRegion);
                }
            }
        }
        let mut placed: Vec<Vec<Point>> =
            if substep { vec![Vec::new(); problem.bodies.len()] } else { std::mem::take(&mut self.current) };
        let result = (|| {
            for (b, body) in problem.bodies.iter().enumerate() {
                let pose = self.frames.pose(b, row);
                placed[b].clear();
                placed[b].extend(body.outline.vertices().iter().map(|&p| pose.apply(p)));
                let bb = Aabb::around(placed[b].iter().copied()).expect("outlines have vertices");
                for (fixed, fixed_box) in problem.fixed.iter().zip(&ctx.fixed_boxes) {
                    if bb.overlaps(fixed_box, tol) && penetrates_unchecked(&placed[b], fixed.vertices(), tol) {
                        return Err(Reject::Collision);
                    }
                }
                for c in 0..b {
                    let other = Aabb::around(placed[c].iter().copied()).expect("outlines have vertices");
                    if bb.overlaps(&other, tol) && penetrates_unchecked(&placed[b], &placed[c], tol) {
                        return Err(Reject::Collision);
                    }
                }
            }
            Ok(())
        })();
        if !substep {
            self.current = placed;
        }
        result
    }

    /// The largest distance any body vertex moved from the previous row to the current one.
    fn largest_motion(&self) -> f64 {
        self.previous
            .iter()
            .zip(&self.current)
            .flat_map(|(a, b)| a.iter().zip(b).map(|(p, q)| p.distance(*q)))
            .fold(0.0, f64::max)
    }

    /// True when some body's box, swept from the previous row to the current one and grown by
    /// `moved` (rotation can bulge the path), meets a fixed body's box or another body's swept box.
    fn swept_boxes_meet_obstacles(&self, moved: f64) -> bool {
        let grow = |b: Aabb| Aabb {
            min: b.min - crate::geom::Vec2::new(moved, moved),
            max: b.max + crate::geom::Vec2::new(moved, moved),
        };
        let swept: Vec<Aabb> = self
            .previous
            .iter()
            .zip(&self.current)
            .map(|(a, b)| grow(Aabb::around(a.iter().chain(b).copied()).expect("outlines have vertices")))
            .collect();
        swept.iter().enumerate().any(|(b, bb)| {
            self.ctx.fixed_boxes.iter().any(|f| bb.overlaps(f, 0.0)) || swept[..b].iter().any(|o| bb.overlaps(o, 0.0))
        })
    }
}

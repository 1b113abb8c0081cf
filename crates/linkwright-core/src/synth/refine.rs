//! The final refinement: each design the run returns is moved to a local optimum of the full weighted
//! cost (eq. 14) with every hard constraint kept, so what is returned is not merely the best random
//! draw of the particle filter.
//!
//! Levenberg–Marquardt over the joint coordinates (and the slider's angle). The cost is a sum of
//! squares of residuals: one per pose, moving joint and axis for E_acc (the joint's miss, scaled) and three per
//! pose and body for its outline's miss ([`Context::outline_miss`]), and
//! the square roots of the other terms, which are never negative. Their Jacobian is taken by
//! forward differences: each residual comes from a simulation (the pose configurations are searched
//! along the travel), so no closed form exists. Every point the optimiser looks at is first projected
//! back onto linkages that reach the end poses ([`Context::project`]), and a step is taken only when
//! the linkage there passes every kinematic check and the collision sweep and costs less: the result
//! is never worse than the start, and is as valid.

use super::collision::check_collisions;
use super::context::Context;
use super::evaluate::{evaluate, Candidate, Scratch};
use super::sample::{mechanism_from_x, x_from_mechanism};
use super::terms::Term;
use super::workspace::Buffers;
use crate::kinematics::BodyFrames;
use crate::mechanism::Mechanism;
use nalgebra::{DMatrix, DVector};

/// The refinement's constants.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct RefineOptions {
    /// Levenberg–Marquardt iterations (each one Jacobian).
    pub iterations: usize,
    /// Forward-difference step for joint coordinates, as a fraction of d.
    pub step: f64,
    /// Forward-difference step for the slider's angle, radians.
    pub angle_step: f64,
}

impl Default for RefineOptions {
    fn default() -> Self {
        RefineOptions { iterations: 12, step: 1e-5, angle_step: 1e-5 }
    }
}

/// How far a refinement may take a design from the one a person is looking at: no joint farther than
/// `reach` from where it is in `shown` (or than it was at the start, when that is farther).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Leash<'a> {
    pub shown: &'a Mechanism,
    pub reach: f64,
}

/// Damped steps tried per Jacobian before the refinement gives up at this point.
const TRIALS: usize = 6;
/// The refinement stops once an iteration gains less than this fraction of the cost.
const GAIN: f64 = 1e-5;

/// The residuals whose squares sum to the candidate's cost: E_acc's misses, scaled, then the square
/// roots of the weighted smoothness, location, size and transmission.
fn residuals(ctx: &Context, c: &Candidate, out: &mut Vec<f64>) {
    out.clear();
    let w = &ctx.weights;
    let poses = c.pose_rows.len();
    let moving = &ctx.moving_joints;
    let scale = (w[Term::Accuracy] / (poses * moving.len()) as f64).sqrt();
    let frames = BodyFrames::new(&c.mechanism, &ctx.first_poses);
    let outline_scale = (w[Term::Accuracy] / (poses * frames.body_count().max(1)) as f64).sqrt();
    for (i, &r) in c.pose_rows.iter().enumerate() {
        let row = c.trace.row(r);
        for &j in moving {
            let miss = row[j] - ctx.target(j, c.mechanism.joints[j], i);
            out.extend([scale * miss.x, scale * miss.y]);
        }
        for b in 0..frames.body_count() {
            out.extend(ctx.outline_miss(b, i, &frames.isometry(b, row)).map(|m| outline_scale * m));
        }
    }
    for term in Term::ALL {
        match term {
            // Its misses, above.
            Term::Accuracy => {}
            Term::Smoothness | Term::Location | Term::Size | Term::Transmission => {
                out.push((w[term] * c.soft[term]).max(0.0).sqrt())
            }
        }
    }
}

/// The linkage of parameter vector `x`, projected onto the end poses and judged on the kinematic
/// checks (not the collision sweep), with `x` moved to the projection.
fn judge(ctx: &Context, x: &mut [f64], scratch: &mut Scratch) -> Option<Candidate> {
    if !ctx.project(x, &mut scratch.fit) {
        return None;
    }
    evaluate(ctx, mechanism_from_x(ctx, x), None, f64::INFINITY, scratch).ok()
}

/// `start` refined to a nearby local optimum of the cost, every hard constraint kept, and within the
/// `leash` if any; `start` itself when no step improves it. Deterministic: no randomness, and the
/// same arithmetic on any thread.
pub(crate) fn refine_design(
    ctx: &Context,
    start: &Candidate,
    options: &RefineOptions,
    leash: Option<Leash>,
    buffers: &mut Buffers,
) -> Candidate {
    let Buffers { evaluation: scratch, sweep } = buffers;
    // The leash's reach, no shorter than the start's own distance from the design shown.
    let leash = leash.map(|Leash { shown, reach }| {
        (shown, start.mechanism.farthest_move_from(shown).map_or(reach, |d| d.max(reach)))
    });
    let leashed = |c: &Candidate| {
        leash.is_none_or(|(shown, reach)| c.mechanism.farthest_move_from(shown).is_some_and(|d| d <= reach))
    };
    let mut x = Vec::new();
    x_from_mechanism(&start.mechanism, &mut x);
    let joint_vars = 2 * ctx.topology.joint_count();
    let mut best = start.clone();
    let mut r = Vec::new();
    residuals(ctx, &best, &mut r);
    let mut lambda = 1e-3;
    let mut trial_r = Vec::new();
    for _ in 0..options.iterations {
        // The Jacobian by forward differences; a column whose step breaks a check is taken backwards,
        // and left zero when both directions do, or when it is a pinned joint's (which then stays).
        let m = r.len();
        let mut jac = DMatrix::<f64>::zeros(m, x.len());
        let pinned = |k: usize| k < joint_vars && ctx.pins.iter().any(|&(j, _)| j == k / 2);
        for k in (0..x.len()).filter(|&k| !pinned(k)) {
            let h = if k < joint_vars { options.step * ctx.body_size } else { options.angle_step };
            for signed in [h, -h] {
                let mut probe = x.clone();
                probe[k] += signed;
                let Some(c) = judge(ctx, &mut probe, scratch) else { continue };
                residuals(ctx, &c, &mut trial_r);
                if trial_r.len() == m {
                    for (row, (&a, &b)) in trial_r.iter().zip(&r).enumerate() {
                        jac[(row, k)] = (a - b) / signed;
                    }
                    break;
                }
            }
        }
        let residual = DVector::from_column_slice(&r);
        let jtj = jac.transpose() * &jac;
        let gradient = jac.transpose() * residual;
        let mut improved = false;
        for _ in 0..TRIALS {
            // Marquardt's scaling: damping along each unknown in proportion to its curvature.
            let mut damped = jtj.clone();
            for k in 0..x.len() {
                damped[(k, k)] += lambda * jtj[(k, k)].max(1e-12);
            }
            let Some(step) = damped.cholesky().map(|ch| ch.solve(&(-&gradient))) else {
                lambda *= 4.0;
                continue;
            };
            let mut trial_x: Vec<f64> = x.iter().zip(step.iter()).map(|(a, b)| a + b).collect();
            let accepted = judge(ctx, &mut trial_x, scratch)
                .filter(|c| c.cost < best.cost && leashed(c) && check_collisions(ctx, c, sweep).is_ok());
            match accepted {
                Some(c) => {
                    let gain = best.cost - c.cost;
                    improved = gain > GAIN * best.cost;
                    x = trial_x;
                    best = c;
                    residuals(ctx, &best, &mut r);
                    lambda = (lambda / 3.0).max(1e-9);
                    break;
                }
                None => lambda *= 4.0,
            }
        }
        if !improved {
            break;
        }
    }
    best.printable = best.printable && best.mechanism.joints == start.mechanism.joints;
    best
}

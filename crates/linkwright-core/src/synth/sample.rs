//! Candidate sampling (paper §4.1–4.3): perturb the intermediate poses, draw every joint in the
//! linkage region, and pull the joints onto a rigid linkage by minimising E_rigid.

use super::context::Context;
use super::random::{normal, rng, Stream};
use super::rigidity::FitWorkspace;
use crate::geom::{penetrates_unchecked, Aabb, Point, Rigid, Vec2};
use crate::mechanism::{Mechanism, SliderLine};
use rand::RngExt;
use rand_xoshiro::Xoshiro256PlusPlus;

/// σ of the jitter around a previous design's joints in a warm start, as a fraction of d.
pub const WARM_JITTER: f64 = 0.05;
/// How often a perturbed pose that collides is drawn again before the input pose is used unperturbed.
const PERTURB_TRIES: usize = 5;

/// Draws candidate mechanisms for one context.
#[derive(Debug)]
pub struct Sampler<'c, 'p> {
    ctx: &'c Context<'p>,
    region_box: Aabb,
    family: u64,
}

/// Buffers one worker reuses across samples.
#[derive(Debug, Default)]
pub struct SampleScratch {
    motions: Vec<Vec<Rigid>>,
    x: Vec<f64>,
    fit: FitWorkspace,
    outlines: Vec<Vec<Point>>,
}

impl SampleScratch {
    /// The perturbed motions of the last sample: `motions()[b][i]` carries body b from pose 0 to pose i.
    pub fn motions(&self) -> &[Vec<Rigid>] {
        &self.motions
    }
}

impl<'c, 'p> Sampler<'c, 'p> {
    pub fn new(ctx: &'c Context<'p>, family: u64) -> Self {
        Sampler { region_box: ctx.problem.region.aabb(), ctx, family }
    }

    /// Sample `index` under `seed`: a mechanism whose links are rigid over perturbed poses, or `None`
    /// when the fit does not reach a rigid linkage.
    ///
    /// With `near`, the joints start from that parameter vector (a previous design's, see
    /// [`x_from_mechanism`]) jittered by [`WARM_JITTER`]·d instead of uniformly in the region.
    pub fn sample(
        &self,
        seed: u64,
        index: u64,
        near: Option<&[f64]>,
        scratch: &mut SampleScratch,
    ) -> Option<Mechanism> {
        let ctx = self.ctx;
        let mut rng = rng(seed, Stream::Sample { family: self.family }, index);
        self.perturbed_motions(&mut rng, scratch);
        let n = ctx.topology.joint_count();
        scratch.x.clear();
        match near {
            Some(start) => {
                scratch.x.extend_from_slice(start);
                for v in &mut scratch.x[..2 * n] {
                    *v += normal(&mut rng) * WARM_JITTER * ctx.body_size;
                }
            }
            None => {
                for _ in 0..n {
                    let p = self.point_in_region(&mut rng);
                    scratch.x.extend([p.x, p.y]);
                }
                if ctx.rigidity.dim() > 2 * n {
                    scratch.x.push(rng.random_range(0.0..std::f64::consts::PI));
                }
            }
        }
        let fit = ctx.rigidity.fit(&mut scratch.x, &scratch.motions, ctx.body_size, &mut scratch.fit);
        if fit.max_relative_deviation.is_nan() || fit.max_relative_deviation > ctx.accepted_deviation() {
            return None;
        }
        Some(mechanism_from_x(ctx, &scratch.x))
    }

    /// `scratch.motions[b][i]`: the first pose to a perturbed pose i (the first and last are kept).
    fn perturbed_motions(&self, rng: &mut Xoshiro256PlusPlus, scratch: &mut SampleScratch) {
        let problem = self.ctx.problem;
        let settings = &problem.settings;
        let poses = problem.pose_count;
        let bodies = problem.bodies.len();
        let mut placed: Vec<Rigid> = Vec::with_capacity(bodies);
        scratch.motions.resize_with(bodies, Vec::new);
        scratch.outlines.resize_with(bodies, Vec::new);
        for m in &mut scratch.motions {
            m.clear();
        }
        for i in 0..poses {
            placed.clear();
            for (b, body) in problem.bodies.iter().enumerate() {
                let input = body.poses[i];
                let mut pose = input;
                if i > 0 && i + 1 < poses && !self.ctx.exact {
                    for _ in 0..PERTURB_TRIES {
                        let shift = Vec2::new(normal(rng), normal(rng)) * (settings.pose_tolerance * body.size);
                        let turn = normal(rng) * settings.angle_tolerance_deg.to_radians();
                        let trial = Rigid::new(input.angle() + turn, input.translation() + shift);
                        if self.free_at(b, &trial, &placed, scratch) {
                            pose = trial;
                            break;
                        }
                    }
                }
                placed.push(pose);
                scratch.motions[b].push(body.poses[0].to(&pose));
            }
        }
    }

    /// True when body `b` at `pose` penetrates neither a fixed body nor an already placed body.
    fn free_at(&self, b: usize, pose: &Rigid, placed: &[Rigid], scratch: &mut SampleScratch) -> bool {
        let problem = self.ctx.problem;
        let tol = self.ctx.contact_tolerance;
        let place = |k: usize, pose: &Rigid, out: &mut Vec<Point>| {
            out.clear();
            out.extend(problem.bodies[k].outline.vertices().iter().map(|&p| pose.apply(p)));
        };
        let (head, tail) = scratch.outlines.split_at_mut(b);
        let outline = &mut tail[0];
        place(b, pose, outline);
        let bb = Aabb::around(outline.iter().copied()).expect("outline has vertices");
        let hits_fixed = problem
            .fixed
            .iter()
            .zip(&self.ctx.fixed_boxes)
            .any(|(f, fb)| bb.overlaps(fb, tol) && penetrates_unchecked(outline, f.vertices(), tol));
        if hits_fixed {
            return false;
        }
        placed.iter().enumerate().all(|(k, other)| {
            place(k, other, &mut head[k]);
            !penetrates_unchecked(outline, &head[k], tol)
        })
    }

    /// A uniform point of the linkage region (of its bounding box if the region is too thin to hit).
    fn point_in_region(&self, rng: &mut Xoshiro256PlusPlus) -> Point {
        let b = &self.region_box;
        let mut p = b.min;
        for _ in 0..64 {
            p = Point::new(rng.random_range(b.min.x..=b.max.x), rng.random_range(b.min.y..=b.max.y));
            if self.ctx.problem.region.contains(p) {
                break;
            }
        }
        p
    }
}

/// The mechanism of a parameter vector: joint coordinates, then the slider's angle if there is one.
pub fn mechanism_from_x(ctx: &Context, x: &[f64]) -> Mechanism {
    let n = ctx.topology.joint_count();
    let joints: Vec<Point> = (0..n).map(|j| Point::new(x[2 * j], x[2 * j + 1])).collect();
    let slider =
        ctx.topology.slider_joint.map(|j| SliderLine { point: joints[j], direction: Vec2::from_angle(x[2 * n]) });
    Mechanism { topology: ctx.topology.clone(), joints, slider }
}

/// The parameter vector of a mechanism (inverse of [`mechanism_from_x`]).
pub fn x_from_mechanism(m: &Mechanism, out: &mut Vec<f64>) {
    out.clear();
    for p in &m.joints {
        out.extend([p.x, p.y]);
    }
    if let Some(line) = m.slider {
        out.push(line.direction.angle());
    }
}

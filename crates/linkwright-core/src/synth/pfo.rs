//! Particle filter optimisation (paper §6, eq. 15): perturb every particle, keep the perturbations
//! that still satisfy every hard constraint, weight old and new by exp(−λ·cost / max initial cost),
//! and resample.

use super::collision::check_collisions;
use super::context::Context;
use super::evaluate::{evaluate, Candidate, Scratch};
use super::random::{normal, rng, Stream};
use super::sample::{mechanism_from_x, x_from_mechanism};
use rand::RngExt;
use rayon::prelude::*;

/// The particle filter's constants.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FilterOptions {
    /// Particles kept after each resampling (paper: 100).
    pub particles: usize,
    /// Iterations (paper: 20).
    pub iterations: usize,
    /// Decay λ of eq. 15 (paper: 20).
    pub lambda: f64,
    /// σ of the joint perturbation at the first iteration, as a fraction of the body size d.
    pub sigma_start: f64,
    /// σ at the last iteration: the proposal narrows geometrically from start to end, so the filter
    /// explores first and polishes last.
    pub sigma_end: f64,
    /// σ of the slider direction's perturbation at the first iteration, radians (narrows alike).
    pub slider_sigma: f64,
}

impl Default for FilterOptions {
    fn default() -> Self {
        FilterOptions {
            particles: 100,
            iterations: 20,
            lambda: 20.0,
            sigma_start: 0.25,
            sigma_end: 0.01,
            slider_sigma: 0.1,
        }
    }
}

/// Relative weight below which a proposal is never worth checking for collisions (it would be drawn
/// with a probability under one in a million against the best particle).
const NEGLIGIBLE_WEIGHT: f64 = 1e-6;

/// Runs the filter from the valid candidates `initial` (non-empty). Returns every valid candidate it
/// produced (for alternatives) and calls `on_iteration(done, best_cost)` after each iteration; stops
/// early when it returns false.
pub fn refine(
    ctx: &Context,
    initial: &[Candidate],
    options: &FilterOptions,
    seed: u64,
    family: u64,
    mut on_iteration: impl FnMut(usize, f64) -> bool,
) -> Vec<Candidate> {
    let max_cost = initial.iter().map(|c| c.cost).fold(f64::MIN_POSITIVE, f64::max);
    let weight = |c: &Candidate| (-options.lambda * c.cost / max_cost).exp();
    let mut resample_rng = rng(seed, Stream::Resample { family }, 0);
    let mut particles = resample(initial, options.particles, &weight, &mut resample_rng);
    let mut produced = Vec::new();
    for iteration in 0..options.iterations {
        let t = if options.iterations > 1 { iteration as f64 / (options.iterations - 1) as f64 } else { 0.0 };
        let sigma = options.sigma_start * (options.sigma_end / options.sigma_start).powf(t);
        let slider_sigma = options.slider_sigma * (options.sigma_end / options.sigma_start).powf(t);
        // A proposal whose weight would be below NEGLIGIBLE_WEIGHT of the best particle's can never be
        // drawn: it is dropped before the collision sweep, the costliest check.
        let best = particles.iter().map(|c| c.cost).fold(f64::INFINITY, f64::min);
        let hopeless = best - NEGLIGIBLE_WEIGHT.ln() * max_cost / options.lambda;
        let fresh: Vec<Candidate> = particles
            .par_iter()
            .enumerate()
            .map_init(Scratch::default, |scratch, (k, particle)| {
                let mut r = rng(seed, Stream::Perturb { family, iteration: iteration as u64 }, k as u64);
                let mut x = Vec::new();
                x_from_mechanism(&particle.mechanism, &mut x);
                let n = 2 * ctx.topology.joint_count();
                for v in &mut x[..n] {
                    *v += normal(&mut r) * sigma * ctx.body_size;
                }
                for v in &mut x[n..] {
                    *v += normal(&mut r) * slider_sigma;
                }
                if ctx.exact {
                    // Project the proposal back onto linkages that hit the input poses exactly.
                    let fit = ctx.rigidity.fit(&mut x, &ctx.motions, ctx.body_size, &mut scratch.fit);
                    if fit.max_relative_deviation.is_nan() || fit.max_relative_deviation > ctx.accepted_deviation() {
                        return None;
                    }
                }
                let candidate = evaluate(ctx, mechanism_from_x(ctx, &x), None, hopeless, scratch).ok()?;
                if candidate.cost > hopeless {
                    return None;
                }
                check_collisions(ctx, &candidate, scratch).ok()?;
                Some(candidate)
            })
            .flatten()
            .collect();
        let pool: Vec<Candidate> = particles.into_iter().chain(fresh.iter().cloned()).collect();
        produced.extend(fresh);
        particles = resample(&pool, options.particles, &weight, &mut resample_rng);
        let best = pool.iter().map(|c| c.cost).fold(f64::INFINITY, f64::min);
        if !on_iteration(iteration + 1, best) {
            break;
        }
    }
    produced
}

/// Draws `count` candidates with replacement, each with probability proportional to its weight; the
/// best candidate is always kept so the filter never loses ground.
fn resample(
    pool: &[Candidate],
    count: usize,
    weight: &impl Fn(&Candidate) -> f64,
    r: &mut rand_xoshiro::Xoshiro256PlusPlus,
) -> Vec<Candidate> {
    let weights: Vec<f64> = pool.iter().map(weight).collect();
    let total: f64 = weights.iter().sum();
    let best = (0..pool.len()).min_by(|&a, &b| pool[a].cost.total_cmp(&pool[b].cost)).expect("a non-empty pool");
    let mut out = vec![pool[best].clone()];
    while out.len() < count {
        let pick = if total > 0.0 && total.is_finite() {
            let mut u = r.random_range(0.0..total);
            let mut chosen = pool.len() - 1;
            for (i, w) in weights.iter().enumerate() {
                if u < *w {
                    chosen = i;
                    break;
                }
                u -= w;
            }
            chosen
        } else {
            r.random_range(0..pool.len())
        };
        out.push(pool[pick].clone());
    }
    out
}

//! Particle filter optimisation (paper §6, eq. 15): perturb every particle, keep the perturbations
//! that still satisfy every hard constraint, weight old and new by exp(−λ·cost / max initial cost),
//! and resample.

use super::collision::check_collisions;
use super::context::Context;
use super::evaluate::{evaluate, Candidate};
use super::random::{normal, rng, Stream};
use super::sample::{mechanism_from_x, x_from_mechanism};
use super::workspace::Workspace;
use rand::RngExt;
use rayon::prelude::*;
use std::sync::{Arc, Mutex};

/// The particle filter's constants.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct FilterOptions {
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

/// Relative weight below which a proposal is not worth simulating (it would be drawn with a probability
/// under one in a million against the best particle).
const NEGLIGIBLE_WEIGHT: f64 = 1e-6;

/// Runs the filter from the valid candidates `initial` (non-empty). Returns the `keep` cheapest valid
/// candidates it produced (for alternatives), cheapest first, and calls `on_iteration(done, best_cost)`
/// after each iteration; stops early when it returns false.
///
/// Only the cheapest are kept because each candidate carries its whole simulated travel: keeping every
/// one, 1,000 particles through 200 iterations (the scene format's bounds) would hold up to 200,000 of
/// them.
pub(crate) fn refine(
    ctx: &Context,
    workspace: &Workspace,
    initial: &[Candidate],
    options: &FilterOptions,
    (seed, family): (u64, u64),
    keep: usize,
    mut on_iteration: impl FnMut(usize, f64) -> bool,
) -> Vec<Candidate> {
    let cheapest = |produced: &mut Vec<Candidate>| {
        // Stable: candidates of equal cost stay in the order they were produced.
        produced.sort_by(|a, b| a.cost.total_cmp(&b.cost));
        produced.truncate(keep);
    };
    let max_cost = initial.iter().map(|c| c.cost).fold(f64::MIN_POSITIVE, f64::max);
    let weight = |c: &Candidate| (-options.lambda * c.cost / max_cost).exp();
    let mut resample_rng = rng(seed, Stream::Resample { family }, 0);
    let mut particles =
        Pool::new(ctx, workspace, initial, initial.len()).resample(options.particles, &weight, &mut resample_rng);
    let mut produced = Vec::new();
    for iteration in 0..options.iterations {
        let t = if options.iterations > 1 { iteration as f64 / (options.iterations - 1) as f64 } else { 0.0 };
        let sigma = options.sigma_start * (options.sigma_end / options.sigma_start).powf(t);
        let slider_sigma = options.slider_sigma * (options.sigma_end / options.sigma_start).powf(t);
        // A proposal whose weight would be below NEGLIGIBLE_WEIGHT of the best particle's can never be
        // drawn: it is not simulated past that bound.
        let best = particles.iter().map(|c| c.cost).fold(f64::INFINITY, f64::min);
        let hopeless = best - NEGLIGIBLE_WEIGHT.ln() * max_cost / options.lambda;
        let proposals: Vec<Arc<Candidate>> = particles
            .par_iter()
            .enumerate()
            .map_init(
                || workspace.judging.take(),
                |buffers, (k, particle)| {
                    let scratch = &mut buffers.evaluation;
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
                    ctx.pin(&mut x);
                    if !ctx.project(&mut x, &mut scratch.fit) {
                        return None;
                    }
                    let candidate = evaluate(ctx, mechanism_from_x(ctx, &x), None, hopeless, scratch).ok()?;
                    (candidate.cost <= hopeless).then(|| Arc::new(candidate))
                },
            )
            .flatten()
            .collect();
        let kept = particles.len();
        let candidates: Vec<Arc<Candidate>> = particles.into_iter().chain(proposals).collect();
        let mut pool = Pool::new(ctx, workspace, &candidates, kept);
        particles = pool.resample(options.particles, &weight, &mut resample_rng);
        produced.extend(pool.valid_proposals());
        if produced.len() > keep.saturating_add(options.particles) {
            cheapest(&mut produced);
        }
        let best = particles[0].cost;
        if !on_iteration(iteration + 1, best) {
            break;
        }
    }
    cheapest(&mut produced);
    produced
}

/// The particles and the proposals of one iteration. A proposal passed every check but the collision
/// sweep, the costliest, which it meets only when the resampling draws it: a proposal that collides is
/// then removed and the draw repeated. Each draw therefore picks among the valid candidates with
/// probability proportional to weight, as if all had been swept, while most proposals, which are too
/// costly to be drawn, are never swept.
struct Pool<'a, 'p, P> {
    ctx: &'a Context<'p>,
    workspace: &'a Workspace,
    /// The particles (valid), then the proposals.
    candidates: &'a [P],
    /// Per candidate: valid, colliding, or not swept yet.
    valid: Vec<Option<bool>>,
    /// Per candidate: the resampling asked whether it is valid. Unlike `valid`, this does not depend
    /// on how many candidates were swept ahead, so neither does anything read from it.
    asked: Vec<bool>,
    first_proposal: usize,
}

impl<'a, 'p, P: Particle> Pool<'a, 'p, P> {
    /// `candidates`: the first `particles` are valid, the rest proposals not swept yet.
    fn new(ctx: &'a Context<'p>, workspace: &'a Workspace, candidates: &'a [P], particles: usize) -> Self {
        let mut valid = vec![Some(true); particles];
        valid.resize(candidates.len(), None);
        Pool { ctx, workspace, candidates, valid, asked: vec![false; candidates.len()], first_proposal: particles }
    }

    /// Whether candidate `i` is valid, swept now if [`Pool::sweep_predicted`] did not sweep it.
    fn is_valid(&mut self, i: usize) -> bool {
        self.asked[i] = true;
        if self.valid[i].is_none() {
            let valid =
                check_collisions(self.ctx, self.candidates[i].candidate(), &mut self.workspace.judging.take().sweep)
                    .is_ok();
            self.valid[i] = Some(valid);
        }
        self.valid[i] == Some(true)
    }

    /// Draws `count` valid candidates with replacement, each with probability proportional to its
    /// weight; the best valid candidate is always kept so the filter never loses ground.
    fn resample(
        &mut self,
        count: usize,
        weight: &impl Fn(&Candidate) -> f64,
        r: &mut rand_xoshiro::Xoshiro256PlusPlus,
    ) -> Vec<Arc<Candidate>> {
        let cost = |k: usize| self.candidates[k].candidate().cost;
        let mut weights: Vec<f64> = self.candidates.iter().map(|c| weight(c.candidate())).collect();
        let mut by_cost: Vec<usize> = (0..self.candidates.len()).collect();
        by_cost.sort_by(|&a, &b| cost(a).total_cmp(&cost(b)));
        self.sweep_predicted(&by_cost, &weights, count, r);
        // The particles are valid, so the search ends at the latest at the best of them.
        let best = by_cost.into_iter().find(|&i| self.is_valid(i)).expect("the particles are valid");
        let mut out = vec![self.candidates[best].share()];
        // Summed again only when a weight is zeroed (the same total: the same sum in the same order).
        let mut total: f64 = weights.iter().sum();
        while out.len() < count {
            let pick = if total > 0.0 && total.is_finite() {
                draw(&weights, r.random_range(0.0..total))
            } else {
                let drawable: Vec<usize> =
                    (0..weights.len()).filter(|&i| !(self.asked[i] && self.valid[i] == Some(false))).collect();
                drawable[r.random_range(0..drawable.len())]
            };
            if self.is_valid(pick) {
                out.push(self.candidates[pick].share());
            } else {
                weights[pick] = 0.0;
                total = weights.iter().sum();
            }
        }
        out
    }

    /// Sweeps ahead, in parallel, the candidates [`Pool::resample`] will ask about: its search for the
    /// best valid candidate and its draws (with a copy of its generator `r`) are replayed with each
    /// unswept candidate taken as valid, and the candidates that took are swept. Whenever one turns
    /// out to collide, the replay is run again on what is known then, and the candidates it meets anew
    /// are swept too, while the others still are: no thread waits for a batch to end (in batches, the
    /// folding table's filter spent a quarter of its sweeping time waiting). When the last sweep ends,
    /// the replay meets no unswept candidate. Which candidates are swept ahead changes no result.
    fn sweep_predicted(
        &mut self,
        by_cost: &[usize],
        weights: &[f64],
        count: usize,
        r: &rand_xoshiro::Xoshiro256PlusPlus,
    ) {
        let ahead = Mutex::new(Ahead {
            valid: std::mem::take(&mut self.valid),
            queued: vec![false; self.candidates.len()],
            pending: 0,
            stale: false,
        });
        let sweeps = Sweeps {
            ctx: self.ctx,
            workspace: self.workspace,
            candidates: self.candidates,
            replay: Replay { by_cost, weights, count, r },
        };
        rayon::scope(|scope| sweeps.queue_unswept(scope, &ahead));
        self.valid = ahead.into_inner().expect("no sweep panics").valid;
    }

    /// The proposals the resampling found valid.
    fn valid_proposals(&self) -> impl Iterator<Item = Candidate> + '_ {
        let asked = (self.first_proposal..self.candidates.len()).filter(|&i| self.asked[i]);
        asked.filter(|&i| self.valid[i] == Some(true)).map(|i| self.candidates[i].candidate().clone())
    }
}

/// What [`Pool::sweep_predicted`]'s sweeps share: each candidate's verdict (`None` until swept),
/// whether it was queued for a sweep, how many queued sweeps have not ended, whether a candidate
/// was found colliding since the last replay.
struct Ahead {
    valid: Vec<Option<bool>>,
    queued: Vec<bool>,
    pending: usize,
    stale: bool,
}

/// The resampling's search and draws, replayed on what is known of the candidates.
struct Replay<'a> {
    by_cost: &'a [usize],
    weights: &'a [f64],
    count: usize,
    r: &'a rand_xoshiro::Xoshiro256PlusPlus,
}

impl Replay<'_> {
    /// The candidates the resampling would ask about, each unswept one taken as valid, that are neither
    /// swept nor `queued`.
    fn unswept(&self, valid: &[Option<bool>], queued: &[bool]) -> Vec<usize> {
        let mut unswept = Vec::new();
        let mut meet = |k: usize| {
            if valid[k].is_none() && !queued[k] {
                unswept.push(k);
            }
        };
        if let Some(&k) = self.by_cost.iter().find(|&&k| valid[k] != Some(false)) {
            meet(k);
        }
        let (mut r, mut weights) = (self.r.clone(), self.weights.to_vec());
        // As in the resampling, summed again only when a weight is zeroed.
        let mut total: f64 = weights.iter().sum();
        let mut drawn = 1;
        while drawn < self.count {
            if !(total > 0.0 && total.is_finite()) {
                break;
            }
            let pick = draw(&weights, r.random_range(0.0..total));
            if valid[pick] == Some(false) {
                weights[pick] = 0.0;
                total = weights.iter().sum();
            } else {
                meet(pick);
                drawn += 1;
            }
        }
        unswept.sort_unstable();
        unswept.dedup();
        unswept
    }
}

/// The sweeps of [`Pool::sweep_predicted`].
struct Sweeps<'a, 'p, P> {
    ctx: &'a Context<'p>,
    workspace: &'a Workspace,
    candidates: &'a [P],
    replay: Replay<'a>,
}

impl<P: Particle> Sweeps<'_, '_, P> {
    /// Queues a sweep of every candidate the replay meets unswept and not queued yet.
    fn queue_unswept<'s>(&'s self, scope: &rayon::Scope<'s>, ahead: &'s Mutex<Ahead>) {
        let unswept = {
            let mut ahead = ahead.lock().expect("no sweep panics");
            let unswept = self.replay.unswept(&ahead.valid, &ahead.queued);
            unswept.iter().for_each(|&k| ahead.queued[k] = true);
            ahead.pending += unswept.len();
            ahead.stale = false;
            unswept
        };
        for k in unswept {
            scope.spawn(move |scope| {
                let valid = check_collisions(
                    self.ctx,
                    self.candidates[k].candidate(),
                    &mut self.workspace.judging.take().sweep,
                )
                .is_ok();
                let replay = {
                    let mut ahead = ahead.lock().expect("no sweep panics");
                    ahead.valid[k] = Some(valid);
                    ahead.pending -= 1;
                    // A valid candidate is what the replay took it for; a colliding one changes its
                    // draws. The replay is run again when a thread would otherwise wait (with one
                    // thread, when every queued sweep has ended: batch after batch).
                    ahead.stale |= !valid;
                    ahead.stale && ahead.pending < rayon::current_num_threads()
                };
                if replay {
                    self.queue_unswept(scope, ahead);
                }
            });
        }
    }
}

/// A candidate in a [`Pool`]: the filter's candidates are shared, so a particle drawn again is not
/// copied (a candidate holds its whole travel); the first pool draws from the collision stage's.
trait Particle: Sync {
    fn candidate(&self) -> &Candidate;
    /// The candidate as a particle of the next iteration.
    fn share(&self) -> Arc<Candidate>;
}

impl Particle for Candidate {
    fn candidate(&self) -> &Candidate {
        self
    }
    fn share(&self) -> Arc<Candidate> {
        Arc::new(self.clone())
    }
}

impl Particle for Arc<Candidate> {
    fn candidate(&self) -> &Candidate {
        self
    }
    fn share(&self) -> Arc<Candidate> {
        Arc::clone(self)
    }
}

/// The candidate a uniform `u` in `[0, Σ weights)` draws: the first whose cumulative weight exceeds
/// `u` (rounding can carry `u` past the last weight: then the last candidate that can be drawn).
fn draw(weights: &[f64], mut u: f64) -> usize {
    for (i, w) in weights.iter().enumerate() {
        if u < *w {
            return i;
        }
        u -= w;
    }
    weights.iter().rposition(|&w| w > 0.0).unwrap_or(weights.len() - 1)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mechanism::MechanismType;
    use crate::synth::collision::SweepBuffers;
    use crate::synth::evaluate::Scratch;
    use crate::synth::sample::{SampleScratch, Sampler};
    use crate::synth::testing::example;

    /// Defect-free candidates of the sofa bed, the valid ones first: (candidates, how many are valid).
    fn sofa_candidates(ctx: &Context) -> (Vec<Candidate>, usize) {
        let sampler = Sampler::new(ctx, 0);
        let (mut sample_scratch, mut scratch) = (SampleScratch::default(), Scratch::default());
        let (mut valid, mut colliding) = (Vec::new(), Vec::new());
        for i in 0..20_000 {
            let Some(m) = sampler.sample(3, i, None, &mut sample_scratch) else { continue };
            let Ok(c) = evaluate(ctx, m, Some(sample_scratch.motions()), f64::INFINITY, &mut scratch) else { continue };
            match check_collisions(ctx, &c, &mut SweepBuffers::default()) {
                Ok(()) if valid.len() < 12 => valid.push(c),
                Err(_) if colliding.len() < 12 => colliding.push(c),
                _ => {}
            }
            if valid.len() == 12 && colliding.len() == 12 {
                break;
            }
        }
        assert!(valid.len() == 12 && colliding.len() == 12, "{} valid, {} colliding", valid.len(), colliding.len());
        let count = valid.len();
        (valid.into_iter().chain(colliding).collect(), count)
    }

    /// The lazy resampling draws only valid candidates, keeps the cheapest valid one first, draws each
    /// valid candidate as often as its weight says (as if every proposal had been swept), and never
    /// sweeps proposals too light to be drawn.
    #[test]
    fn resampling_draws_valid_candidates_by_weight() {
        let problem = example("k1_sofa_bed");
        let ctx = Context::new(&problem, MechanismType::SliderCrank);
        let (mut candidates, valid) = sofa_candidates(&ctx);
        // Two valid particles; the proposals are the other valid candidates and the colliding ones, so
        // that the cheapest proposals may collide.
        let particles = 2;
        let cheapest_valid = candidates[..valid].iter().map(|c| c.cost).fold(f64::INFINITY, f64::min);
        candidates[particles..].sort_by(|a, b| a.cost.total_cmp(&b.cost));
        let is_valid = |c: &Candidate| check_collisions(&ctx, c, &mut SweepBuffers::default()).is_ok();

        // Weights proportional to cost (any positive weights will do): each valid candidate drawn in
        // proportion to its weight among the valid ones, no colliding one ever.
        let by_cost = |c: &Candidate| c.cost;
        let workspace = Workspace::default();
        let mut pool = Pool::new(&ctx, &workspace, &candidates, particles);
        let mut r = rng(1, Stream::Resample { family: 0 }, 0);
        let draws = 24_000;
        let drawn = pool.resample(draws + 1, &by_cost, &mut r);
        assert_eq!(drawn[0].cost, cheapest_valid);
        assert!(drawn.iter().all(|c| is_valid(c)));
        let valid_weight: f64 = candidates.iter().filter(|c| is_valid(c)).map(by_cost).sum();
        for c in &candidates {
            let times = drawn[1..].iter().filter(|d| d.cost == c.cost).count() as f64;
            let expected = if is_valid(c) { draws as f64 * c.cost / valid_weight } else { 0.0 };
            assert!((times - expected).abs() <= 0.15 * expected, "drawn {times} times, expected {expected:.0}");
        }

        // Steep weights: the heaviest proposals are swept, the lightest never are.
        let lightest = candidates.iter().map(|c| c.cost).fold(0.0, f64::max);
        let steep = |c: &Candidate| (-200.0 * c.cost / lightest).exp();
        let mut pool = Pool::new(&ctx, &workspace, &candidates, particles);
        let drawn = pool.resample(100, &steep, &mut r);
        assert!(drawn.iter().all(|c| is_valid(c)));
        assert!(pool.valid.iter().any(Option::is_none), "every proposal was swept");
        let swept_valid: Vec<Candidate> = pool.valid_proposals().collect();
        assert!(swept_valid.iter().all(is_valid));
    }

    /// However many particles and iterations, the filter hands back at most `keep` candidates (each
    /// carries its travel), and they are the cheapest it produced: the same run keeping more returns
    /// them first, in the same order.
    #[test]
    fn the_filter_keeps_only_its_cheapest_candidates() {
        let problem = example("k1_sofa_bed");
        let ctx = Context::new(&problem, MechanismType::SliderCrank);
        let (candidates, valid) = sofa_candidates(&ctx);
        let workspace = Workspace::default();
        let options = FilterOptions { particles: 40, iterations: 6, ..FilterOptions::default() };
        let run = |keep| refine(&ctx, &workspace, &candidates[..valid], &options, (5, 0), keep, |_, _| true);
        let all = run(usize::MAX);
        let kept = run(10);
        assert!(all.len() > 10 + options.particles, "{} produced", all.len());
        assert_eq!(kept.len(), 10);
        let costs = |cs: &[Candidate]| cs.iter().map(|c| c.cost).collect::<Vec<f64>>();
        assert_eq!(costs(&kept), costs(&all[..10]));
        assert!(costs(&all).is_sorted(), "cheapest first");
    }
}

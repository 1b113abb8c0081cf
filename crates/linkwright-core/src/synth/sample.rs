//! Candidate sampling (paper §4.1–4.3): perturb the intermediate poses, draw joints in the linkage
//! region and solve the others in closed form where the poses allow it ([`super::construct`]), and
//! pull the rest onto a rigid linkage by minimising E_rigid.

use super::construct::{ConstructScratch, Constructor, Region, Tolerances};
use super::context::{Context, END_DEVIATION};
use super::perturb::{PerturbationCells, Verdict};
use super::random::{normal, rng, Stream};
use super::rigidity::{FitWorkspace, RigidityModel, FLIP_TOLERANCE};
use crate::geom::{penetrates_unchecked, Aabb, Obstacle, Point, Rigid, Vec2};
use crate::mechanism::{Mechanism, SliderLine};
use rand::RngExt;
use rand_xoshiro::Xoshiro256PlusPlus;

/// σ of the jitter around a previous design's joints in a warm start, as a fraction of d.
pub(crate) const WARM_JITTER: f64 = 0.05;
/// A construction left unpolished is accepted without measuring its deviation, so its links keep
/// their lengths to this fraction of the deviation a sample may have. Projecting further, to rounding,
/// takes one more step in six, 2.6% of the folding table's instructions (`valgrind --tool=callgrind
/// linkwright design examples/k1_table.json --threads 1 --no-print-check`, the scene's `"mechanism"`
/// set to `"chain"`).
const UNPOLISHED_DEVIATION: f64 = 1e-4;
/// Iterations of a quick fit ([`super::construct::Polish`]), which a ternary link through three poses
/// takes when a joint of it is pinned: a fit that converges takes fewer; one that has not by then
/// rarely ends exact, and drawing it again is cheaper (`linkwright design` on four scenes of
/// `linkwright bench --known --save DIR` through three poses: 100 iterations take 1.3–2.9 times as
/// long and find no more valid designs).
const QUICK_FIT_ITERATIONS: usize = 15;
/// How often a perturbed pose that collides is drawn again before the input pose is used unperturbed.
const PERTURB_TRIES: usize = 5;

/// Draws candidate mechanisms for one context.
#[derive(Debug)]
pub(crate) struct Sampler<'c, 'p> {
    ctx: &'c Context<'p>,
    region_box: Aabb,
    /// The linkage region with no tolerance, whose grid places most drawn points at once.
    region_grid: Obstacle,
    family: u64,
    constructor: Constructor,
    /// The rigidity fit with [`QUICK_FIT_ITERATIONS`], for blocks drawn again when they fail.
    quick_rigidity: RigidityModel,
    /// Each body's first pose, inverted: perturbed motions start from it.
    first_inverse: Vec<Rigid>,
    /// The fixed bodies' verdicts on perturbed poses, by cell of the perturbation.
    cells: PerturbationCells,
}

/// Buffers one worker reuses across samples.
#[derive(Debug, Default)]
pub(crate) struct SampleScratch {
    motions: Vec<Vec<Rigid>>,
    x: Vec<f64>,
    fit: FitWorkspace,
    construct: ConstructScratch,
    /// Each body's outline and its box at the pose being perturbed, once placed.
    outlines: Vec<Vec<Point>>,
    boxes: Vec<Aabb>,
    /// The last sample drawn by [`Sampler::draw`], its buffers reused from sample to sample.
    mechanism: Option<Mechanism>,
}

impl SampleScratch {
    /// The perturbed motions of the last sample: `motions()[b][i]` carries body b from pose 0 to pose i.
    pub(crate) fn motions(&self) -> &[Vec<Rigid>] {
        &self.motions
    }
    /// The last sample [`Sampler::draw`] accepted.
    pub(crate) fn mechanism(&self) -> &Mechanism {
        self.mechanism.as_ref().expect("a sample was drawn")
    }
}

/// Where a warm sample starts ([`Sampler::draw`]): a previous design's parameter vector, how far its
/// joints are jittered, and whether it is fitted to perturbed poses like any sample or to the poses
/// as drawn ([`Near::exact`]: the least change that makes that design rigid through the poses now).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Near<'a> {
    pub start: &'a [f64],
    /// The jitter of each joint, a fraction of d ([`WARM_JITTER`] for a warm start).
    pub jitter: f64,
    /// Whether the poses are perturbed as for any sample (else fitted as drawn).
    pub perturbed: bool,
}

impl<'a> Near<'a> {
    /// Fitted as it is, through the poses as drawn.
    pub(crate) fn exact(start: &'a [f64]) -> Self {
        Near { start, jitter: 0.0, perturbed: false }
    }
    /// Jittered by [`WARM_JITTER`]·d and fitted to perturbed poses, as a warm start's samples are.
    pub(crate) fn warm(start: &'a [f64]) -> Self {
        Near { start, jitter: WARM_JITTER, perturbed: true }
    }
}

impl<'c, 'p> Sampler<'c, 'p> {
    pub(crate) fn new(ctx: &'c Context<'p>, family: u64) -> Self {
        Sampler {
            region_box: ctx.problem.region.aabb(),
            region_grid: Obstacle::new(ctx.problem.region.vertices(), 0.0),
            ctx,
            family,
            constructor: Constructor::new(
                &ctx.topology,
                Tolerances {
                    projection: UNPOLISHED_DEVIATION * ctx.accepted_deviation() * ctx.body_size,
                    deviation: ctx.accepted_deviation(),
                    flip: FLIP_TOLERANCE * ctx.body_size,
                    spacing: ctx.min_spacing,
                    intermediate_turnover: !ctx.overdetermined,
                },
            )
            .with_pins(&ctx.pins),
            quick_rigidity: ctx.rigidity.clone().with_max_iterations(QUICK_FIT_ITERATIONS),
            first_inverse: ctx.problem.bodies.iter().map(|b| b.poses[0].inverse()).collect(),
            cells: PerturbationCells::new(ctx),
        }
    }

    /// Draws sample `index` under `seed` into `scratch` ([`SampleScratch::mechanism`], its buffers
    /// reused): a mechanism whose links are rigid over perturbed poses. False when the fit does not
    /// reach a rigid linkage.
    ///
    /// Without `near`, joints are drawn uniformly in the region and the others solved in closed form
    /// where the poses allow it, the rest fitted from the constructed start. With `near`, every joint
    /// starts from that parameter vector (a previous design's, see [`x_from_mechanism`]) jittered as
    /// `near` says, and the whole linkage is fitted.
    pub(crate) fn draw(&self, seed: u64, index: u64, near: Option<Near>, scratch: &mut SampleScratch) -> bool {
        let ctx = self.ctx;
        let mut rng = rng(seed, Stream::Sample { family: self.family }, index);
        if near.is_some_and(|n| !n.perturbed) {
            scratch.motions.clone_from(&ctx.motions);
        } else {
            self.perturbed_motions(&mut rng, scratch);
        }
        let n = ctx.topology.joint_count();
        let SampleScratch { motions, x, fit, construct, .. } = scratch;
        x.clear();
        // The slider's direction when no fit turns it afterwards, else read from `x`.
        let mut slider_direction = None;
        let deviation = match near {
            Some(Near { start, jitter, .. }) => {
                x.extend_from_slice(start);
                if jitter > 0.0 {
                    for v in &mut x[..2 * n] {
                        *v += normal(&mut rng) * jitter * ctx.body_size;
                    }
                }
                ctx.pin(x);
                ctx.rigidity.fit(x, motions, ctx.body_size, fit).max_relative_deviation
            }
            None => {
                x.resize(ctx.rigidity.dim(), 0.0);
                let mut draw = |rng: &mut Xoshiro256PlusPlus| self.point_in_region(rng);
                let mut region = Region { draw: &mut draw, bounds: self.region_box };
                let mut polish = |x: &mut [f64], joint: usize, quick: bool| {
                    let model = if quick { &self.quick_rigidity } else { &ctx.rigidity };
                    model.fit_block_of(joint, x, motions, ctx.body_size, fit)
                };
                let deviation = self.constructor.construct(x, motions, &mut rng, &mut region, &mut polish, construct);
                // The slider's direction goes to the mechanism as it is: an angle would only be
                // turned back into it (an `atan2` and a `sin_cos` per sample).
                slider_direction = construct.slider_direction();
                if x[..2 * n].iter().all(|v| v.is_finite()) {
                    deviation
                } else {
                    f64::INFINITY
                }
            }
        };
        if deviation.is_nan() || deviation > ctx.accepted_deviation() {
            return false;
        }
        // A fit that balanced its residual over every pose is moved onto one through the end poses
        // (a construction left unpolished already is: `constructions_left_unpolished_are_rigid`); one
        // already rigid through them still needs its ternary links the right way round (`mirrored`),
        // which `through_must_hit_poses` checks too, and the construction did for its own links.
        let through_end_poses = if deviation > END_DEVIATION {
            // The fit reads the slider's angle in `x` and may turn it.
            if let Some(direction) = slider_direction.take() {
                scratch.x[2 * n] = direction.angle();
            }
            ctx.through_must_hit_poses(&mut scratch.x, &mut scratch.fit)
        } else {
            near.is_none() || !ctx.rigidity.mirrored(&scratch.x, &ctx.must_hit_motions, ctx.body_size)
        };
        if !through_end_poses {
            return false;
        }
        let m = scratch.mechanism.get_or_insert_with(|| empty_mechanism(ctx));
        mechanism_into_x(ctx, &scratch.x, slider_direction, m);
        true
    }

    /// The linkage of parameter vector `start` as it is, with the poses as drawn, into `scratch`
    /// ([`SampleScratch::mechanism`]): a previous design judged without a fit. False when its joints
    /// are not all finite.
    pub(crate) fn draw_as_is(&self, start: &[f64], scratch: &mut SampleScratch) -> bool {
        let ctx = self.ctx;
        debug_assert_eq!(start.len(), ctx.rigidity.dim(), "a previous design of this topology");
        if !start.iter().all(|v| v.is_finite()) {
            return false;
        }
        scratch.motions.clone_from(&ctx.motions);
        let m = scratch.mechanism.get_or_insert_with(|| empty_mechanism(ctx));
        mechanism_into_x(ctx, start, None, m);
        true
    }

    /// [`Sampler::draw`], as an owned mechanism (`None` when the fit failed).
    #[cfg(test)]
    pub(crate) fn sample(
        &self,
        seed: u64,
        index: u64,
        near: Option<Near>,
        scratch: &mut SampleScratch,
    ) -> Option<Mechanism> {
        self.draw(seed, index, near, scratch).then(|| scratch.mechanism().clone())
    }

    /// `scratch.motions[b][i]`: the first pose to a perturbed pose i (the first and last are kept).
    fn perturbed_motions(&self, rng: &mut Xoshiro256PlusPlus, scratch: &mut SampleScratch) {
        let problem = self.ctx.problem;
        let settings = &problem.settings;
        let poses = problem.pose_count;
        let bodies = problem.bodies.len();
        scratch.motions.resize_with(bodies, Vec::new);
        scratch.outlines.resize_with(bodies, Vec::new);
        scratch.boxes.resize(bodies, self.region_box);
        for m in &mut scratch.motions {
            m.clear();
        }
        for i in 0..poses {
            let perturbed = !problem.must_hit[i] && !self.ctx.unperturbed;
            for (b, body) in problem.bodies.iter().enumerate() {
                if !perturbed {
                    scratch.motions[b].push(self.ctx.motions[b][i]);
                    continue;
                }
                let input = body.poses[i];
                let mut pose = input;
                let mut free = false;
                for _ in 0..PERTURB_TRIES {
                    let noise = self.ctx.noise_scale;
                    let shift = Vec2::new(normal(rng), normal(rng)) * (noise * settings.pose_tolerance * body.size);
                    let turn = normal(rng) * noise * settings.angle_tolerance_deg.to_radians();
                    let trial = Rigid::new(input.angle() + turn, input.translation() + shift);
                    if self.free_at(b, i, (shift, turn), &trial, scratch) {
                        (pose, free) = (trial, true);
                        break;
                    }
                }
                if !free && b + 1 < bodies {
                    // The bodies after this one are tested against its outline at the input pose.
                    self.place(b, &pose, scratch);
                }
                // `first.to(pose)`, with the inverse computed once.
                scratch.motions[b].push(self.first_inverse[b].then(&pose));
            }
        }
    }

    /// Places body `b`'s outline and box at `pose` in `scratch`.
    fn place(&self, b: usize, pose: &Rigid, scratch: &mut SampleScratch) {
        let outline = &mut scratch.outlines[b];
        outline.clear();
        outline.extend(self.ctx.problem.bodies[b].outline.vertices().iter().map(|&p| pose.apply(p)));
        scratch.boxes[b] = Aabb::around(outline.iter().copied()).expect("outline has vertices");
    }

    /// True when body `b` at `pose`, pose `i` perturbed by `(shift, turn)`, penetrates neither a fixed
    /// body nor a body placed before it at this pose (bodies `0..b`, whose outlines `scratch` holds).
    /// Leaves `b`'s outline in `scratch` when there are other bodies (the last body of a scene with
    /// one is placed only where a fixed body's cell leaves its verdict open).
    fn free_at(
        &self,
        b: usize,
        i: usize,
        (shift, turn): (Vec2, f64),
        pose: &Rigid,
        scratch: &mut SampleScratch,
    ) -> bool {
        let tol = self.ctx.contact_tolerance;
        let bodies = self.ctx.problem.bodies.len();
        let shape = &self.ctx.body_shapes[b];
        let mut placed = false;
        for (k, f) in self.ctx.fixed_obstacles.iter().enumerate() {
            match self.cells.verdict(self.ctx, b, i, shift, turn, k) {
                Verdict::Clear => {}
                Verdict::Penetrated => return false,
                Verdict::Undecided => {
                    if !placed {
                        self.place(b, pose, scratch);
                        placed = true;
                    }
                    let (outline, bb) = (&scratch.outlines[b], &scratch.boxes[b]);
                    if bb.overlaps(&f.bounds(), tol) && f.penetrated_by_shape(outline, shape, &pose.isometry()) {
                        return false;
                    }
                }
            }
        }
        if bodies == 1 {
            return true;
        }
        if !placed {
            self.place(b, pose, scratch);
        }
        let (outline, bb) = (&scratch.outlines[b], &scratch.boxes[b]);
        // Boxes that do not overlap at all cannot hold a crossing or a point deep inside the other.
        (0..b)
            .all(|k| !(bb.overlaps(&scratch.boxes[k], 0.0) && penetrates_unchecked(outline, &scratch.outlines[k], tol)))
    }

    /// A uniform point of the linkage region (of its bounding box if the region is too thin to hit).
    fn point_in_region(&self, rng: &mut Xoshiro256PlusPlus) -> Point {
        let b = &self.region_box;
        let mut p = b.min;
        for _ in 0..64 {
            p = Point::new(rng.random_range(b.min.x..=b.max.x), rng.random_range(b.min.y..=b.max.y));
            if self.region_grid.decided_deep(p).unwrap_or_else(|| self.ctx.problem.region.contains(p)) {
                break;
            }
        }
        p
    }
}

/// The mechanism of a parameter vector: joint coordinates, then the slider's angle if there is one.
pub(crate) fn mechanism_from_x(ctx: &Context, x: &[f64]) -> Mechanism {
    let mut m = empty_mechanism(ctx);
    mechanism_into_x(ctx, x, None, &mut m);
    m
}

/// A mechanism of this context's topology with no joints yet.
fn empty_mechanism(ctx: &Context) -> Mechanism {
    Mechanism { topology: ctx.topology.clone(), joints: Vec::new(), slider: None }
}

/// The mechanism of a parameter vector (see [`mechanism_from_x`]) into `m`, a mechanism of this
/// context's topology, reusing its buffers; the slider along `direction` when given (rather than
/// `x`'s angle).
fn mechanism_into_x(ctx: &Context, x: &[f64], direction: Option<Vec2>, m: &mut Mechanism) {
    let n = ctx.topology.joint_count();
    m.joints.clear();
    m.joints.extend((0..n).map(|j| Point::new(x[2 * j], x[2 * j + 1])));
    m.slider = ctx
        .topology
        .slider_joint
        .map(|j| SliderLine { point: m.joints[j], direction: direction.unwrap_or_else(|| Vec2::from_angle(x[2 * n])) });
}

/// The parameter vector of a mechanism (inverse of [`mechanism_from_x`]).
pub(crate) fn x_from_mechanism(m: &Mechanism, out: &mut Vec<f64>) {
    out.clear();
    for p in &m.joints {
        out.extend([p.x, p.y]);
    }
    if let Some(line) = m.slider {
        out.push(line.direction.angle());
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mechanism::MechanismType;
    use crate::scene::Problem;
    use crate::synth::testing::{example, pose_examples};
    use crate::synth::{check_collisions, evaluate, Scratch, SweepBuffers};

    /// The region's grid changes no drawn point: on every example scene, the draws are those of the
    /// even-odd test alone, bit for bit.
    #[test]
    fn region_grid_draws_the_points_of_the_even_odd_test() {
        use rand::SeedableRng;
        for (name, problem) in pose_examples() {
            let ctx = Context::new(&problem, MechanismType::Chain);
            let sampler = Sampler::new(&ctx, 0);
            let b = problem.region.aabb();
            let (mut rng, mut reference) = (Xoshiro256PlusPlus::seed_from_u64(4), Xoshiro256PlusPlus::seed_from_u64(4));
            for _ in 0..20_000 {
                let mut expected = b.min;
                for _ in 0..64 {
                    expected = Point::new(
                        reference.random_range(b.min.x..=b.max.x),
                        reference.random_range(b.min.y..=b.max.y),
                    );
                    if problem.region.contains(expected) {
                        break;
                    }
                }
                let p = sampler.point_in_region(&mut rng);
                assert_eq!((p.x.to_bits(), p.y.to_bits()), (expected.x.to_bits(), expected.y.to_bits()), "{name}");
            }
        }
    }

    /// What lets [`Sampler::draw`] skip measuring a construction that left nothing to polish: on every
    /// example scene and family, over perturbed poses, its links keep their lengths to far below the
    /// deviation a sample may have.
    #[test]
    fn constructions_left_unpolished_are_rigid() {
        let mut unpolished = 0;
        for (name, problem) in pose_examples() {
            let families: &[MechanismType] = if problem.body_count() == 1 {
                &[MechanismType::Chain, MechanismType::SliderCrank]
            } else {
                &[MechanismType::Chain]
            };
            for &family in families {
                unpolished += rigid_unpolished_constructions(&name, &problem, family, 3000);
            }
        }
        assert!(unpolished > 20_000, "only {unpolished} unpolished constructions");
    }

    /// A chain's ternary links through three poses are solved by Newton's method rather than fitted:
    /// every linkage so built is rigid through the (perturbed) poses it was built for.
    #[test]
    fn long_chains_through_three_poses_are_built_rigid() {
        use crate::testbed::{known_scene, Known};
        let scene = known_scene(Known::chain(5), 3, 0, 100.0).unwrap().scene;
        let problem = Problem::new(&scene).unwrap();
        let unpolished = rigid_unpolished_constructions("chain of five", &problem, MechanismType::Chain, 3000);
        assert!(unpolished >= 10, "only {unpolished} unpolished constructions");
    }

    /// Constructs samples `0..samples` of `family`'s linkage for `problem` and asserts that each one
    /// built without a fit is rigid through its poses; returns how many there were.
    fn rigid_unpolished_constructions(name: &str, problem: &Problem, family: MechanismType, samples: u64) -> usize {
        let ctx = Context::new(problem, family);
        let sampler = Sampler::new(&ctx, 0);
        let mut scratch = SampleScratch::default();
        let mut unpolished = 0;
        // Constructions with a defect end early and are not counted.
        for i in 0..samples {
            let mut rng = rng(2, Stream::Sample { family: 0 }, i);
            sampler.perturbed_motions(&mut rng, &mut scratch);
            let SampleScratch { motions, x, construct, .. } = &mut scratch;
            x.clear();
            x.resize(ctx.rigidity.dim(), 0.0);
            let mut draw = |rng: &mut Xoshiro256PlusPlus| sampler.point_in_region(rng);
            let mut region = Region { draw: &mut draw, bounds: sampler.region_box };
            let mut polished = false;
            let mut polish = |_: &mut [f64], _: usize, _: bool| {
                polished = true;
                f64::INFINITY
            };
            let built = sampler.constructor.construct(x, motions, &mut rng, &mut region, &mut polish, construct);
            if polished || built.is_infinite() {
                continue;
            }
            if let Some(direction) = construct.slider_direction() {
                x[2 * ctx.topology.joint_count()] = direction.angle();
            }
            let deviation = ctx.rigidity.relative_deviation(x, motions, ctx.body_size);
            let bound = UNPOLISHED_DEVIATION * ctx.accepted_deviation();
            assert!(deviation <= bound, "{name}: deviation {deviation} of an unpolished construction");
            unpolished += 1;
        }
        unpolished
    }

    /// Constructive sampling against the fit from uniform starts: fitted, kinematically valid and
    /// collision-free samples, and the best costs. `cargo test --release -p linkwright-core
    /// sampling_statistics -- --ignored --nocapture`.
    #[test]
    #[ignore]
    fn sampling_statistics() {
        let samples = 20000;
        for (name, ty) in [
            ("k1_sofa_bed", MechanismType::SliderCrank),
            ("k1_car_roof", MechanismType::Chain),
            ("k1_bulldozer", MechanismType::SliderCrank),
            ("k1_table", MechanismType::Chain),
            ("k1_garbage_truck", MechanismType::Chain),
            ("k2_wall_bed", MechanismType::Chain),
            ("k2_wall_chair", MechanismType::Chain),
            ("k2_folding_roof2", MechanismType::Chain),
            ("k3_power_shovel", MechanismType::Chain),
            ("k3_folding_roof", MechanismType::Chain),
        ] {
            let problem = example(name);
            let ctx = Context::new(&problem, ty);
            let sampler = Sampler::new(&ctx, 0);
            for constructive in [false, true] {
                let (mut fitted, mut candidates, mut costs, mut inside) = (0, 0, Vec::new(), 0usize);
                let mut scratch = SampleScratch::default();
                let mut eval = Scratch::default();
                for i in 0..samples {
                    let m = if constructive {
                        sampler.sample(1, i, None, &mut scratch)
                    } else {
                        let mut rng = rng(1, Stream::Sample { family: 0 }, i);
                        sampler.perturbed_motions(&mut rng, &mut scratch);
                        let n = ctx.topology.joint_count();
                        scratch.x.clear();
                        for _ in 0..n {
                            let p = sampler.point_in_region(&mut rng);
                            scratch.x.extend([p.x, p.y]);
                        }
                        if ctx.rigidity.dim() > 2 * n {
                            scratch.x.push(rng.random_range(0.0..std::f64::consts::PI));
                        }
                        let fit = ctx.rigidity.fit(&mut scratch.x, &scratch.motions, ctx.body_size, &mut scratch.fit);
                        (fit.max_relative_deviation <= ctx.accepted_deviation())
                            .then(|| mechanism_from_x(&ctx, &scratch.x))
                    };
                    let Some(m) = m else { continue };
                    fitted += 1;
                    inside += m.joints.iter().filter(|&&p| problem.region.contains(p)).count();
                    if let Ok(c) = evaluate(&ctx, m, Some(scratch.motions()), f64::INFINITY, &mut eval) {
                        candidates += 1;
                        if check_collisions(&ctx, &c, &mut SweepBuffers::default()).is_ok() {
                            costs.push(c.cost);
                        }
                    }
                }
                costs.sort_by(f64::total_cmp);
                let best: Vec<String> = costs.iter().take(5).map(|c| format!("{c:.2}")).collect();
                println!(
                    "{name:17} {:12} fitted {fitted:6} joints in region {:5.1}% candidates {candidates:5} valid {:4} best {}",
                    if constructive { "constructive" } else { "uniform+LM" },
                    100.0 * inside as f64 / (fitted.max(1) * ctx.topology.joint_count()) as f64,
                    costs.len(),
                    best.join(" ")
                );
            }
        }
    }
}

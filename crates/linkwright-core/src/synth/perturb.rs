//! The fixed bodies' verdicts on a moving body's perturbed poses, decided once per cell of the
//! perturbation wherever that cell's centre pose decides them for the whole cell.
//!
//! The sampler perturbs each intermediate pose by a shift and a turn drawn from normal laws, and draws
//! again when the body then penetrates a fixed body: 1.5–1.9 penetration tests per sample, which,
//! tested exactly at about 3 k instructions each, would be a fifth of the sofa bed's run (`valgrind
//! --tool=callgrind linkwright design examples/k1_sofa_bed.json --threads 1 --no-print-check`, the
//! scene's `"mechanism"` set to `"slider_crank"`). Most perturbations land clear of the fixed
//! bodies or deep in them. Within a cell of (shift x, shift y, turn) a point p of the body (in its own
//! frame) moves from the cell's centre pose by at most |Δshift| + |Δturn|·|p|, so
//! [`Obstacle::penetration_within`] at the centre pose, with that reach, gives the exact test's answer
//! for every perturbation in the cell, or says it cannot. Cells are decided when a sample first lands
//! in them, by whichever thread gets there: the verdict depends on the cell alone, so the designs do
//! not depend on the threads, and they are those of the exact test everywhere.

use super::context::Context;
use crate::geom::{Point, Rigid, Vec2};
use std::sync::atomic::{AtomicU8, Ordering};

/// Cells per standard deviation of each perturbation axis.
const CELLS_PER_SIGMA: f64 = 4.0;
/// How many standard deviations the cells cover on each side; perturbations beyond are tested exactly.
/// Out there (under 4% of the perturbations) most cells see a single sample, and deciding a cell costs
/// more than the exact test it would save: covering 4σ costs 0.4–1.9% more instructions on the
/// folding table, sofa bed and bulldozer (the callgrind command of docs/performance.md, each scene's
/// `"mechanism"` as in Table 1).
const SPAN_SIGMAS: f64 = 2.5;

/// A cell's verdict against one fixed body, as stored.
const UNKNOWN: u8 = 0;
const CLEAR: u8 = 1;
const PENETRATED: u8 = 2;
const UNDECIDED: u8 = 3;

/// The cells of every perturbed pose of every moving body.
#[derive(Debug)]
pub(crate) struct PerturbationCells {
    /// `grids[b * poses + i]`: body b's cells at pose i, for the perturbed poses.
    grids: Vec<Option<CellGrid>>,
    poses: usize,
}

/// The cells of one body at one pose.
#[derive(Debug)]
struct CellGrid {
    input: Rigid,
    /// Per axis (shift x, shift y, turn): the first cell's lower end, the cells' width, their count.
    axes: [Axis; 3],
    /// How far a point of the body moves between a cell's centre and any perturbation in it.
    reach: f64,
    /// Per cell and fixed body (`cell * fixed + k`), the verdict, `UNKNOWN` until a sample lands there.
    verdicts: Vec<AtomicU8>,
}

#[derive(Clone, Copy, Debug)]
struct Axis {
    low: f64,
    width: f64,
    count: usize,
}

impl Axis {
    /// The axis of a perturbation with standard deviation `sigma` (one cell of width 0 when it is 0).
    fn new(sigma: f64) -> Axis {
        if sigma > 0.0 {
            let count = (2.0 * SPAN_SIGMAS * CELLS_PER_SIGMA) as usize;
            Axis { low: -SPAN_SIGMAS * sigma, width: sigma / CELLS_PER_SIGMA, count }
        } else {
            Axis { low: 0.0, width: 0.0, count: 1 }
        }
    }
    fn index(&self, v: f64) -> Option<usize> {
        if self.width == 0.0 {
            return (v == 0.0).then_some(0);
        }
        let t = (v - self.low) / self.width;
        (t >= 0.0 && t < self.count as f64).then_some(t as usize)
    }
    fn center(&self, k: usize) -> f64 {
        self.low + (k as f64 + 0.5) * self.width
    }
}

/// What a cell says of a perturbation against one fixed body.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Verdict {
    Clear,
    Penetrated,
    /// The exact test must decide.
    Undecided,
}

impl PerturbationCells {
    /// Empty cells for the perturbed poses of `ctx` (none when poses are not perturbed).
    pub(crate) fn new(ctx: &Context) -> Self {
        let problem = ctx.problem;
        let poses = problem.pose_count;
        let settings = &problem.settings;
        let fixed = ctx.fixed_obstacles.len();
        let mut grids = Vec::with_capacity(problem.bodies.len() * poses);
        for body in &problem.bodies {
            let shift = Axis::new(ctx.noise_scale * settings.pose_tolerance * body.size);
            let turn = Axis::new(ctx.noise_scale * settings.angle_tolerance_deg.to_radians());
            let arm = body.outline.vertices().iter().fold(0.0, |r: f64, p| r.max(p.to_vec2().norm()));
            // Half a cell's diagonal in shift, half its width in turn, and a hair more for the
            // rounding of the cell index.
            let reach = (0.5 * shift.width * std::f64::consts::SQRT_2 + 0.5 * turn.width * arm) * (1.0 + 1e-9);
            let cells = shift.count * shift.count * turn.count;
            for i in 0..poses {
                let perturbed = i > 0 && i + 1 < poses && !ctx.unperturbed && fixed > 0;
                grids.push(perturbed.then(|| CellGrid {
                    input: body.poses[i],
                    axes: [shift, shift, turn],
                    reach,
                    verdicts: (0..cells * fixed).map(|_| AtomicU8::new(UNKNOWN)).collect(),
                }));
            }
        }
        PerturbationCells { grids, poses }
    }

    /// The verdict against fixed body `k` of body `b` at pose `i` perturbed by `shift` and `turn`
    /// (the pose `Rigid::new(input.angle() + turn, input.translation() + shift)`).
    pub(crate) fn verdict(&self, ctx: &Context, b: usize, i: usize, shift: Vec2, turn: f64, k: usize) -> Verdict {
        let Some(grid) = &self.grids[b * self.poses + i] else { return Verdict::Undecided };
        let [x, y, t] = grid.axes;
        let (Some(ix), Some(iy), Some(it)) = (x.index(shift.x), y.index(shift.y), t.index(turn)) else {
            return Verdict::Undecided;
        };
        let fixed = ctx.fixed_obstacles.len();
        let slot = &grid.verdicts[((it * y.count + iy) * x.count + ix) * fixed + k];
        let mut verdict = slot.load(Ordering::Relaxed);
        if verdict == UNKNOWN {
            let center = Rigid::new(
                grid.input.angle() + t.center(it),
                grid.input.translation() + Vec2::new(x.center(ix), y.center(iy)),
            );
            let outline: Vec<Point> =
                ctx.problem.bodies[b].outline.vertices().iter().map(|&p| center.apply(p)).collect();
            verdict = match ctx.fixed_obstacles[k].penetration_within(&outline, grid.reach) {
                Some(false) => CLEAR,
                Some(true) => PENETRATED,
                None => UNDECIDED,
            };
            slot.store(verdict, Ordering::Relaxed);
        }
        match verdict {
            CLEAR => Verdict::Clear,
            PENETRATED => Verdict::Penetrated,
            _ => Verdict::Undecided,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geom::penetrates_unchecked;
    use crate::mechanism::MechanismType;
    use crate::synth::random::normal;
    use crate::synth::testing::example;
    use rand::SeedableRng;
    use rand_xoshiro::Xoshiro256PlusPlus;

    /// On every example scene, each decided cell gives the brute force's verdict for the
    /// perturbations the sampler draws (and wider ones, out to the grid's edge and beyond), and most
    /// perturbations are decided by their cell.
    #[test]
    fn decided_cells_agree_with_the_exact_test() {
        let (mut decided, mut asked) = (0usize, 0usize);
        for name in [
            "k1_bulldozer",
            "k1_car_roof",
            "k1_excavator",
            "k1_garbage_truck",
            "k1_monitor",
            "k1_sofa_bed",
            "k1_table",
            "k2_folding_roof2",
            "k2_wall_bed",
            "k2_wall_chair",
            "k3_folding_roof",
            "k3_power_shovel",
        ] {
            let problem = example(name);
            let ctx = Context::new(&problem, MechanismType::Chain);
            let cells = PerturbationCells::new(&ctx);
            let settings = &problem.settings;
            let tol = ctx.contact_tolerance;
            let mut rng = Xoshiro256PlusPlus::seed_from_u64(3);
            for (b, body) in problem.bodies.iter().enumerate() {
                for i in 1..problem.pose_count - 1 {
                    for draw in 0..3000 {
                        let spread = if draw % 4 == 0 { 2.5 } else { 1.0 };
                        let shift = Vec2::new(normal(&mut rng), normal(&mut rng))
                            * (spread * settings.pose_tolerance * body.size);
                        let turn = normal(&mut rng) * spread * settings.angle_tolerance_deg.to_radians();
                        let input = body.poses[i];
                        let pose = Rigid::new(input.angle() + turn, input.translation() + shift);
                        let outline: Vec<Point> = body.outline.vertices().iter().map(|&p| pose.apply(p)).collect();
                        for (k, fixed) in problem.fixed.iter().enumerate() {
                            asked += 1;
                            let exact = penetrates_unchecked(&outline, fixed.vertices(), tol);
                            match cells.verdict(&ctx, b, i, shift, turn, k) {
                                Verdict::Undecided => {}
                                verdict => {
                                    decided += 1;
                                    assert_eq!(verdict == Verdict::Penetrated, exact, "{name}: body {b} pose {i}");
                                }
                            }
                        }
                    }
                }
            }
        }
        assert!(decided * 10 > asked * 6, "{decided} of {asked} decided");
    }
}

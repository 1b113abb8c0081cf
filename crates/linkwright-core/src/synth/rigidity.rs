//! The rigidity energy `E_rigid` of paper §4.2–4.3 (eq. 3–5) and a small, allocation-free
//! Levenberg–Marquardt minimiser for it.
//!
//! The unknowns are the joints' world coordinates at the first pose, `x = [x_0, y_0, x_1, y_1, …]` in
//! the topology's joint order, followed for the slider-crank by the slider direction angle `φ`
//! (radians). A joint carried by moving body `b` is at `motions[b][i].apply(x_j)` in pose `i`; a joint
//! carried by the ground never moves.
//!
//! Residuals, pair-major then slider, each over the poses `i = 1..N`:
//! - for each link pair `(m, n)` of [`Topology::link_pairs`]: `r = |mⁱ − nⁱ|² − |m⁰ − n⁰|²` (eq. 4);
//! - for the slider joint `q`: `r = (qⁱ − q⁰) × u(φ)`, `u(φ) = (cos φ, sin φ)` (eq. 5).
//!
//! `E = Σ r²` in world units (length⁴ for link terms, length² for slider terms), as the paper writes it.
//!
//! ## The minimiser
//! - **Blocks.** Every joint sits on exactly one link (and on the ground or one body, which only move
//!   it by the given motions), so `E` splits into independent terms, one per link: the crank `q0 p1`
//!   (4 unknowns), each ternary link `r_{k−1} q_k p_{k+1}` (6), the last link `r_{K−1} q_K` (4), and the
//!   slider joint with `φ` (3). [`RigidityModel::new`] finds these blocks as the connected components of
//!   the residuals' unknowns, and [`RigidityModel::fit`] minimises each block on its own: a fit costs
//!   O(K) small dense solves instead of one (6K+2)-dimensional one, and each block stops as soon as it
//!   has converged.
//! - **Levenberg–Marquardt** on each block with the analytic Jacobian, damping `λ·I` and Nielsen's
//!   update of `λ`, plus a geodesic-acceleration correction (Transtrum & Sethna): link residuals are
//!   quadratic in the joints, so `r(x + v) − r(x) − Jv` is exactly half the second directional
//!   derivative along the step `v`, which bends the step along narrow curved valleys (poses close
//!   together make such valleys, along which a fit without it crawls for many times the iterations).
//! - **Scale-free.** The solve runs in coordinates normalised by the body size `d` (joints `/ d`, link
//!   residuals `/ d²`, slider residuals `/ d`), so every tolerance is relative, and a block's normalised
//!   objective is its world energy times a constant (`d⁻⁴` for links, `d⁻²` for the slider block): the
//!   energy never increases.
//! - **Underdetermined fits stay near the start.** With N = 2 or 3 poses the exact solutions form a
//!   manifold; the damped steps are short, minimum-norm-like steps that end near the sampled start,
//!   which is what the sampler wants. For three poses a ground pivot ends exactly at the circumcentre
//!   of its moving joint's three positions.
//! - **Not every start converges to zero.** A ternary link for three poses is a square polynomial
//!   system (its ground or body pivot must be the circumcentre of two joints' positions), and beyond
//!   five poses (K = 1) or three (K ≥ 2) there is generally no exact solution: the fit then ends in a
//!   local minimum, reported by [`Fit::max_relative_deviation`]. It also stops when a joint runs away
//!   (an infimum at infinity, a link growing towards a slider-like motion) or progress stalls.
//! - **Degenerate solutions are reported, not excluded.** For a relative motion with a fixed point,
//!   `m = n =` that point makes a link's residuals vanish; [`Fit::min_relative_link_length`] flags it.

use crate::geom::{Point, Rigid, Vec2};
use crate::mechanism::{PartKind, Topology};

/// How far turning a ternary link over may move a joint, as a fraction of the body size, before the
/// link counts as mirrored ([`RigidityModel::mirrored`]): the precision the end poses are reached with.
pub(crate) const FLIP_TOLERANCE: f64 = 0.05;

/// What carries a joint from pose to pose.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Carrier {
    Ground,
    Body(usize),
    /// Links only: the joint is in no residual (its place at a pose follows from the others').
    Links,
}

/// A set of unknowns that shares residuals with no other: minimised on its own.
#[derive(Clone, Debug)]
struct Block {
    /// Global indices of the block's unknowns.
    vars: Vec<usize>,
    /// The link pairs whose residuals the block holds.
    pairs: Vec<(usize, usize)>,
    /// Whether the block holds the slider residuals (and the unknown `φ`).
    slider: bool,
}

/// The rigidity energy of one topology, built once and evaluated for any joints and body motions.
#[derive(Clone, Debug)]
pub(crate) struct RigidityModel {
    carriers: Vec<Carrier>,
    pairs: Vec<(usize, usize)>,
    slider: Option<usize>,
    body_count: usize,
    blocks: Vec<Block>,
    /// The ternary links' joints: their lengths keep a triangle only up to its mirror image.
    triangles: Vec<[usize; 3]>,
    /// For each unknown, its index within its block.
    local: Vec<usize>,
    max_iterations: usize,
}

/// The outcome of one fit of the rigidity energy (paper eq. 3–5): how far the fitted joints are from
/// a rigid linkage.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Fit {
    /// `E_rigid` at the returned joints, in world units (`Σ r²`).
    pub energy: f64,
    /// Max over link pairs and poses of `| |mⁱ−nⁱ| − |m⁰−n⁰| | / scale`, and for the slider the max
    /// distance of `qⁱ` from the line through `q⁰` along `u(φ)`, `/ scale`. 0 means exactly rigid.
    pub max_relative_deviation: f64,
    /// The shortest link at the first pose, `/ scale` (∞ without links). Near 0 flags the degenerate
    /// collapsed-link solution.
    pub min_relative_link_length: f64,
    /// Levenberg–Marquardt iterations of the block that took the most (each iteration factors one
    /// small damped normal matrix).
    pub iterations: usize,
}

/// Reusable buffers for [`RigidityModel::fit`]; after the first fit of a given size, fitting allocates
/// nothing.
#[derive(Clone, Debug, Default)]
pub(crate) struct FitWorkspace {
    /// Normalised residual rows (block-local columns), normal matrix `JᵀJ` (row-major, n × n) and
    /// gradient `Jᵀr` at the current point, and the same at the trial point.
    rows: Vec<Row>,
    a: Vec<f64>,
    g: Vec<f64>,
    rows_trial: Vec<Row>,
    a_trial: Vec<f64>,
    g_trial: Vec<f64>,
    r_trial: Vec<f64>,
    /// Cholesky factor of `A + λI` and the reciprocals of its diagonal.
    chol: Vec<f64>,
    inv_diag: Vec<f64>,
    /// Velocity, second-order right-hand side, acceleration, and the step taken.
    v: Vec<f64>,
    h: Vec<f64>,
    acc: Vec<f64>,
    step: Vec<f64>,
    /// The block's unknowns at the current point and at the start.
    current: Vec<f64>,
    start: Vec<f64>,
}

impl FitWorkspace {
    fn prepare(&mut self, n: usize) {
        for m in [&mut self.a, &mut self.a_trial, &mut self.chol] {
            m.resize(n * n, 0.0);
        }
        for v in [&mut self.inv_diag, &mut self.g, &mut self.g_trial, &mut self.v, &mut self.h, &mut self.acc] {
            v.resize(n, 0.0);
        }
        self.step.resize(n, 0.0);
    }

    /// The decrease of `½|r|²` the linear model predicts for `step`: `−gᵀδ − ½|Jδ|²`.
    #[inline]
    fn predicted_decrease(&self) -> f64 {
        let j_step_sq: f64 = self
            .rows
            .iter()
            .map(|row| (0..row.len).map(|k| row.j[k] * self.step[row.cols[k]]).sum::<f64>().powi(2))
            .sum();
        -dot(&self.g, &self.step) - 0.5 * j_step_sq
    }

    /// Takes the trial point (the block's unknowns `vars` in `x`) as the current one, with its normal
    /// equations.
    #[inline]
    fn take_trial(&mut self, vars: &[usize], x: &[f64]) {
        for (k, &v) in vars.iter().enumerate() {
            self.current[k] = x[v];
        }
        std::mem::swap(&mut self.a, &mut self.a_trial);
        std::mem::swap(&mut self.g, &mut self.g_trial);
        std::mem::swap(&mut self.rows, &mut self.rows_trial);
    }
}

/// Stop when the normalised objective `½|r|²` is below this (normalised residuals ≈ 1e-14).
const F_TINY: f64 = 1e-28;
/// Stop when the infinity norm of the normalised gradient is below this.
const G_TOL: f64 = 1e-15;
/// Stop when the step is this small relative to the normalised unknowns.
const X_TOL: f64 = 1e-13;
/// Stop when an accepted step lowers the objective by less than this fraction.
const F_REL_TOL: f64 = 1e-10;
/// Stop when `STALL_WINDOW` iterations lowered the objective by less than the fraction `STALL_GAIN`.
const STALL_WINDOW: usize = 10;
const STALL_GAIN: f64 = 1e-3;
/// Stop when a joint has moved farther than this many body sizes from the start.
const RUNAWAY: f64 = 1e3;
/// Give up on a point where the damping has grown this large (no descent direction is representable).
const LAMBDA_MAX: f64 = 1e20;
/// Initial damping relative to the largest diagonal entry of `JᵀJ`.
const LAMBDA_START: f64 = 1e-3;
/// Largest `2|a| / |v|` for which the geodesic acceleration is used.
const ACCELERATION_RATIO: f64 = 0.75;

/// How a block's unknowns are normalised: unknown k moves by `unit(k)·δₖ` for a normalised step δ,
/// joints by the body size `s`, the slider angle `φ` by δ itself.
struct Units<'a> {
    /// The block's unknowns (global indices).
    vars: &'a [usize],
    /// The slider angle's global index, when the model has a slider.
    phi: Option<usize>,
    s: f64,
}

impl Units<'_> {
    #[inline]
    fn unit(&self, k: usize) -> f64 {
        if Some(self.vars[k]) == self.phi {
            1.0
        } else {
            self.s
        }
    }

    /// Puts the block's unknowns at `base` moved by the normalised `step`.
    #[inline]
    fn set(&self, x: &mut [f64], base: &[f64], step: &[f64]) {
        for (k, &v) in self.vars.iter().enumerate() {
            x[v] = base[k] + self.unit(k) * step[k];
        }
    }

    /// Whether a joint has moved more than [`RUNAWAY`] body sizes from the start: an infimum at
    /// infinity (a link growing without bound towards a slider-like motion).
    #[inline]
    fn ran_away(&self, ws: &FitWorkspace) -> bool {
        (0..self.vars.len())
            .any(|k| Some(self.vars[k]) != self.phi && (ws.current[k] - ws.start[k]).abs() > RUNAWAY * self.s)
    }
}

/// Levenberg–Marquardt's damping λ and its growth factor ν (Nielsen's update).
struct Damping {
    lambda: f64,
    nu: f64,
}

impl Damping {
    /// After a step that was not taken: damp harder, faster each time.
    #[inline]
    fn refuse(&mut self) {
        self.lambda *= self.nu;
        self.nu *= 2.0;
    }

    /// After a step taken whose gain was `rho` times the predicted one.
    #[inline]
    fn accept(&mut self, rho: f64) {
        self.lambda *= (1.0 - (2.0 * rho - 1.0).powi(3)).max(1.0 / 3.0);
        self.nu = 2.0;
    }
}

/// Away from an exact solution Levenberg–Marquardt converges linearly: the fit stops once
/// [`STALL_WINDOW`] iterations have lowered the objective by less than the fraction [`STALL_GAIN`].
struct Stall {
    /// The objective at the window's start, and the iteration that ends it.
    f_window: f64,
    window_end: usize,
}

impl Stall {
    /// Whether the window ending by `iterations` gained too little to go on (the objective now `f`);
    /// if not and it has ended, the next window starts.
    #[inline]
    fn stalled(&mut self, iterations: usize, f: f64) -> bool {
        if iterations >= self.window_end {
            if f > (1.0 - STALL_GAIN) * self.f_window {
                return true;
            }
            (self.f_window, self.window_end) = (f, iterations + STALL_WINDOW);
        }
        false
    }
}

/// One residual row: its value and its nonzero Jacobian entries.
#[derive(Clone, Copy, Debug)]
struct Row {
    /// A slider row (else a link row); they normalise differently.
    slider: bool,
    r: f64,
    cols: [usize; 4],
    j: [f64; 4],
    len: usize,
}

impl RigidityModel {
    /// The model of `topology`: its link pairs between joints the ground or a moving body carries
    /// (a joint carried by links only has no given place at a pose, [`Topology::link_only_joints`])
    /// and, for the slider-crank, its slider joint.
    ///
    /// # Panics
    /// If a joint is carried by more than one of the ground and the moving bodies.
    pub(crate) fn new(topology: &Topology) -> Self {
        let joint_count = topology.joint_count();
        let mut carriers = vec![None; joint_count];
        for part in &topology.parts {
            let carrier = match part.kind {
                PartKind::Fixed => Carrier::Ground,
                PartKind::Body(b) => Carrier::Body(b),
                PartKind::Link => continue,
            };
            for &j in &part.joints {
                assert!(carriers[j].is_none(), "joint {} is carried by two bodies", topology.joint_names[j]);
                carriers[j] = Some(carrier);
            }
        }
        let carriers: Vec<Carrier> = carriers.iter().map(|c| c.unwrap_or(Carrier::Links)).collect();
        let carried = |j: usize| carriers[j] != Carrier::Links;
        let pairs: Vec<(usize, usize)> =
            topology.link_pairs().into_iter().filter(|&(m, n)| carried(m) && carried(n)).collect();
        let slider = topology.slider_joint;

        // Blocks: connected components of the joints under the link pairs. Node `joint_count` stands
        // for φ, joined to the slider joint.
        let mut parent: Vec<usize> = (0..=joint_count).collect();
        fn root(parent: &mut [usize], mut i: usize) -> usize {
            while parent[i] != i {
                parent[i] = parent[parent[i]];
                i = parent[i];
            }
            i
        }
        let mut join = |a: usize, b: usize| {
            let (ra, rb) = (root(&mut parent, a), root(&mut parent, b));
            parent[ra] = rb;
        };
        for &(m, n) in &pairs {
            join(m, n);
        }
        if let Some(q) = slider {
            join(q, joint_count);
        }
        let mut blocks: Vec<Block> = Vec::new();
        let mut block_of_root = vec![usize::MAX; joint_count + 1];
        let mut block_of = |parent: &mut [usize], joint: usize, blocks: &mut Vec<Block>| {
            let r = root(parent, joint);
            if block_of_root[r] == usize::MAX {
                block_of_root[r] = blocks.len();
                blocks.push(Block { vars: Vec::new(), pairs: Vec::new(), slider: false });
            }
            block_of_root[r]
        };
        for &(m, n) in &pairs {
            let b = block_of(&mut parent, m, &mut blocks);
            blocks[b].pairs.push((m, n));
        }
        if let Some(q) = slider {
            let b = block_of(&mut parent, q, &mut blocks);
            blocks[b].slider = true;
        }
        let dim = 2 * joint_count + usize::from(slider.is_some());
        let mut local = vec![usize::MAX; dim];
        for j in 0..joint_count {
            let in_residuals = pairs.iter().any(|&(m, n)| m == j || n == j) || slider == Some(j);
            if in_residuals {
                let b = block_of(&mut parent, j, &mut blocks);
                for v in [2 * j, 2 * j + 1] {
                    local[v] = blocks[b].vars.len();
                    blocks[b].vars.push(v);
                }
            }
        }
        if slider.is_some() {
            let b = block_of(&mut parent, joint_count, &mut blocks);
            local[dim - 1] = blocks[b].vars.len();
            blocks[b].vars.push(dim - 1);
        }
        let triangles = (topology.parts.iter())
            .filter(|p| p.kind == PartKind::Link && p.joints.len() == 3 && p.joints.iter().all(|&j| carried(j)))
            .map(|p| [p.joints[0], p.joints[1], p.joints[2]])
            .collect();
        RigidityModel {
            carriers,
            pairs,
            slider,
            body_count: topology.body_count,
            blocks,
            triangles,
            local,
            max_iterations: 100,
        }
    }

    /// The same model with the joints `pinned` held where the parameter vector has them: their
    /// coordinates are no unknowns of any fit (their residuals stay, their columns go).
    pub(crate) fn with_pinned(mut self, pinned: &[usize]) -> Self {
        for block in &mut self.blocks {
            block.vars.retain(|&v| v >= 2 * self.carriers.len() || !pinned.contains(&(v / 2)));
        }
        self.local.fill(usize::MAX);
        for block in &self.blocks {
            for (k, &v) in block.vars.iter().enumerate() {
                self.local[v] = k;
            }
        }
        self
    }

    /// The same model with another iteration limit per block for [`RigidityModel::fit`] (default 100).
    pub(crate) fn with_max_iterations(mut self, max_iterations: usize) -> Self {
        self.max_iterations = max_iterations;
        self
    }

    /// Number of unknowns: 2 per joint, plus the slider angle for the slider-crank.
    pub(crate) fn dim(&self) -> usize {
        2 * self.carriers.len() + usize::from(self.slider.is_some())
    }

    /// Number of residuals for `poses` poses.
    #[cfg(test)]
    pub(crate) fn residual_count(&self, poses: usize) -> usize {
        (self.pairs.len() + usize::from(self.slider.is_some())) * poses.saturating_sub(1)
    }

    /// The residuals of eq. 4–5 (world units), pair-major then slider, poses 1..N within each.
    #[cfg(test)]
    pub(crate) fn residuals(&self, x: &[f64], motions: &[Vec<Rigid>], out: &mut Vec<f64>) {
        out.clear();
        self.for_each_row::<false>(&self.pairs, self.slider.is_some(), x, motions, |row| out.push(row.r));
    }

    /// `E_rigid = Σ r²` (world units).
    #[cfg(test)]
    pub(crate) fn energy(&self, x: &[f64], motions: &[Vec<Rigid>]) -> f64 {
        let mut e = 0.0;
        self.for_each_row::<false>(&self.pairs, self.slider.is_some(), x, motions, |row| e += row.r * row.r);
        e
    }

    /// The analytic gradient of [`RigidityModel::energy`], `2 Jᵀ r`.
    #[cfg(test)]
    pub(crate) fn gradient(&self, x: &[f64], motions: &[Vec<Rigid>], out: &mut [f64]) {
        assert_eq!(out.len(), self.dim(), "gradient buffer has the wrong length");
        out.fill(0.0);
        self.for_each_row::<true>(&self.pairs, self.slider.is_some(), x, motions, |row| {
            for k in 0..row.len {
                out[row.cols[k]] += 2.0 * row.r * row.j[k];
            }
        });
    }

    /// Minimises `E_rigid` from `x` (updated in place), block by block, by Levenberg–Marquardt in
    /// coordinates normalised by `scale` (the body size d; a non-positive or non-finite scale is taken
    /// as 1).
    ///
    /// The energy never increases from the start. With non-finite inputs `x` is left unchanged and the
    /// fit reports infinite energy and deviation.
    pub(crate) fn fit(&self, x: &mut [f64], motions: &[Vec<Rigid>], scale: f64, ws: &mut FitWorkspace) -> Fit {
        self.fit_where(x, motions, scale, ws, |_| true)
    }

    /// [`RigidityModel::fit`] on the blocks that hold a joint for which `polish` is true (indexed like
    /// the joints); the other blocks are kept as they are (a constructed exact solution, say) and only
    /// enter the reported energy and deviation.
    pub(crate) fn fit_where(
        &self,
        x: &mut [f64],
        motions: &[Vec<Rigid>],
        scale: f64,
        ws: &mut FitWorkspace,
        polish: impl Fn(usize) -> bool,
    ) -> Fit {
        assert_eq!(x.len(), self.dim(), "x has the wrong length");
        let s = usable_scale(scale);
        let poses = self.poses(motions);
        if !self.finite(x, motions) {
            return Fit {
                energy: f64::INFINITY,
                max_relative_deviation: f64::INFINITY,
                min_relative_link_length: self.min_link_length(x) / s,
                iterations: 0,
            };
        }
        let (mut energy, mut iterations) = (0.0, 0);
        if poses >= 2 {
            for block in &self.blocks {
                if block.vars.iter().any(|&v| v < 2 * self.carriers.len() && polish(v / 2)) {
                    let (e, it) = self.fit_block(block, x, motions, s, ws);
                    energy += e;
                    iterations = iterations.max(it);
                } else {
                    self.for_each_row::<false>(&block.pairs, block.slider, x, motions, |row| energy += row.r * row.r);
                }
            }
        }
        self.report(x, motions, s, energy, iterations)
    }

    /// [`RigidityModel::fit`] on the one block that holds `joint`, the others left as they are: the
    /// block's own [`Fit::max_relative_deviation`] (its other joints and, for the slider, its angle
    /// must be in `x`; the rest of `x` is not read). Infinite for non-finite inputs.
    pub(crate) fn fit_block_of(
        &self,
        joint: usize,
        x: &mut [f64],
        motions: &[Vec<Rigid>],
        scale: f64,
        ws: &mut FitWorkspace,
    ) -> f64 {
        let s = usable_scale(scale);
        let holds = |b: &&Block| {
            b.pairs.iter().any(|&(m, n)| m == joint || n == joint) || (b.slider && self.slider == Some(joint))
        };
        let block = self.blocks.iter().find(holds).expect("every joint a block polishes is in one");
        let finite = block.vars.iter().all(|&v| x[v].is_finite())
            && motions.iter().flatten().all(|m| m.angle().is_finite() && m.translation().is_finite());
        if !finite {
            return f64::INFINITY;
        }
        if self.poses(motions) >= 2 {
            self.fit_block(block, x, motions, s, ws);
        }
        self.deviation_of(&block.pairs, block.slider, x, motions) / s
    }

    /// Levenberg–Marquardt with geodesic acceleration on one block; returns the block's world energy
    /// and the iterations taken.
    fn fit_block(
        &self,
        block: &Block,
        x: &mut [f64],
        motions: &[Vec<Rigid>],
        s: f64,
        ws: &mut FitWorkspace,
    ) -> (f64, usize) {
        let n = block.vars.len();
        ws.prepare(n);
        ws.current.clear();
        ws.current.extend(block.vars.iter().map(|&v| x[v]));
        ws.start.clear();
        ws.start.extend_from_slice(&ws.current);
        let units = Units { vars: &block.vars, phi: self.slider.map(|_| self.dim() - 1), s };

        let (mut f, mut e) = self.normal_equations(block, x, motions, s, &mut ws.rows, &mut ws.a, &mut ws.g);
        let e_start = e;
        let mut iterations = 0;
        let max_diag = (0..n).map(|i| ws.a[i * n + i]).fold(0.0, f64::max);
        let mut damping = Damping { lambda: LAMBDA_START * max_diag, nu: 2.0 };
        let mut stall = Stall { f_window: f, window_end: STALL_WINDOW };
        while iterations < self.max_iterations && f > F_TINY && damping.lambda < LAMBDA_MAX {
            if ws.g.iter().fold(0.0f64, |m, v| m.max(v.abs())) <= G_TOL {
                break;
            }
            iterations += 1;
            damping.lambda = damping.lambda.max(1e-30);
            if !cholesky_factor(n, &ws.a, damping.lambda, &mut ws.chol, &mut ws.inv_diag) {
                damping.refuse();
                continue;
            }
            if !self.geodesic_step(block, &units, x, motions, ws) {
                break;
            }
            units.set(x, &ws.current, &ws.step);
            let (f_trial, e_trial) =
                self.normal_equations(block, x, motions, s, &mut ws.rows_trial, &mut ws.a_trial, &mut ws.g_trial);
            if !(f_trial.is_finite() && f_trial < f) {
                damping.refuse();
                continue;
            }
            let rho = (f - f_trial) / ws.predicted_decrease().max(f64::MIN_POSITIVE);
            let small_gain = f - f_trial <= F_REL_TOL * f;
            ws.take_trial(&block.vars, x);
            f = f_trial;
            e = e_trial;
            damping.accept(rho);
            if small_gain || stall.stalled(iterations, f) || units.ran_away(ws) {
                break;
            }
        }
        if e > e_start {
            // A block mixing link and slider residuals weighs them differently from the world energy;
            // never hand back a worse point than the start.
            for (k, &v) in block.vars.iter().enumerate() {
                x[v] = ws.start[k];
            }
            return (e_start, iterations);
        }
        for (k, &v) in block.vars.iter().enumerate() {
            x[v] = ws.current[k];
        }
        (e, iterations)
    }

    /// The next step from the current point into `ws.step`: the damped Gauss–Newton velocity
    /// `(A + λI) v = −g` (with `A + λI` factored in `ws.chol`), plus half the geodesic acceleration
    /// when that is small beside it. False when the velocity is negligible beside the unknowns, or not
    /// finite: the fit has converged. Leaves `x` at the current point moved by the velocity.
    #[inline]
    fn geodesic_step(
        &self,
        block: &Block,
        units: &Units,
        x: &mut [f64],
        motions: &[Vec<Rigid>],
        ws: &mut FitWorkspace,
    ) -> bool {
        let n = block.vars.len();
        cholesky_solve(n, &ws.chol, &ws.inv_diag, &ws.g, &mut ws.v);
        let v_norm = dot(&ws.v, &ws.v).sqrt();
        let y_norm = (0..n).map(|k| (ws.current[k] / units.unit(k)).powi(2)).sum::<f64>().sqrt();
        if !v_norm.is_finite() || v_norm <= X_TOL * (y_norm + X_TOL) {
            return false;
        }
        ws.step.copy_from_slice(&ws.v);
        // Geodesic acceleration: r(x + v) − r(x) − Jv = ½ r_vv (exactly, for link residuals).
        units.set(x, &ws.current, &ws.v);
        self.normalised_residuals(block, x, motions, units.s, &mut ws.r_trial);
        ws.h.fill(0.0);
        for (row, &r1) in ws.rows.iter().zip(&ws.r_trial) {
            let jv: f64 = (0..row.len).map(|k| row.j[k] * ws.v[row.cols[k]]).sum();
            let r_vv = 2.0 * (r1 - row.r - jv);
            for k in 0..row.len {
                ws.h[row.cols[k]] += row.j[k] * r_vv;
            }
        }
        cholesky_solve(n, &ws.chol, &ws.inv_diag, &ws.h, &mut ws.acc);
        let a_norm = dot(&ws.acc, &ws.acc).sqrt();
        if a_norm.is_finite() && 2.0 * a_norm <= ACCELERATION_RATIO * v_norm {
            for (d, a) in ws.step.iter_mut().zip(&ws.acc) {
                *d += 0.5 * a;
            }
        }
        true
    }

    /// Number of poses in `motions`, checked against the topology.
    fn poses(&self, motions: &[Vec<Rigid>]) -> usize {
        assert!(motions.len() >= self.body_count, "need the motions of {} bodies", self.body_count);
        let poses = motions.first().map_or(0, Vec::len);
        debug_assert!(motions.iter().all(|m| m.len() == poses), "every body needs the same number of poses");
        poses
    }

    fn place(&self, j: usize, x: &[f64], motions: &[Vec<Rigid>], pose: usize) -> (Point, Option<Rigid>) {
        let p0 = Point::new(x[2 * j], x[2 * j + 1]);
        match self.carriers[j] {
            // A joint carried by links only is in no residual.
            Carrier::Ground | Carrier::Links => (p0, None),
            Carrier::Body(b) => {
                let m = motions[b][pose];
                (m.apply(p0), Some(m))
            }
        }
    }

    /// Calls `sink` with every residual row of `pairs` and, if `slider`, of the slider joint, with
    /// the Jacobian entries (global columns, world units) when `JAC`.
    #[inline]
    fn for_each_row<const JAC: bool>(
        &self,
        pairs: &[(usize, usize)],
        slider: bool,
        x: &[f64],
        motions: &[Vec<Rigid>],
        mut sink: impl FnMut(&Row),
    ) {
        assert_eq!(x.len(), self.dim(), "x has the wrong length");
        let poses = self.poses(motions);
        let mut row = Row { slider: false, r: 0.0, cols: [0; 4], j: [0.0; 4], len: 4 };
        for &(m, n) in pairs {
            let d0 = Point::new(x[2 * m], x[2 * m + 1]) - Point::new(x[2 * n], x[2 * n + 1]);
            let l0 = d0.norm_sq();
            row.cols = [2 * m, 2 * m + 1, 2 * n, 2 * n + 1];
            for i in 1..poses {
                let (mi, rm) = self.place(m, x, motions, i);
                let (ni, rn) = self.place(n, x, motions, i);
                let d = mi - ni;
                row.r = d.norm_sq() - l0;
                if JAC {
                    // ∂r/∂m⁰ = 2(Rₘᵀ d − d⁰), ∂r/∂n⁰ = −2(Rₙᵀ d − d⁰).
                    let gm = rm.map_or(d, |t| t.unrotate(d)) - d0;
                    let gn = rn.map_or(d, |t| t.unrotate(d)) - d0;
                    row.j = [2.0 * gm.x, 2.0 * gm.y, -2.0 * gn.x, -2.0 * gn.y];
                }
                sink(&row);
            }
        }
        if let (Some(q), true) = (self.slider, slider) {
            let phi_col = self.dim() - 1;
            let u = Vec2::from_angle(x[phi_col]);
            // ∂(v × u)/∂v = (u_y, −u_x) = w; v = qⁱ − q⁰ = (R − I)q⁰ + t, so ∂r/∂q⁰ = Rᵀw − w.
            let w = Vec2::new(u.y, -u.x);
            let q0 = Point::new(x[2 * q], x[2 * q + 1]);
            row = Row { slider: true, r: 0.0, cols: [2 * q, 2 * q + 1, phi_col, 0], j: [0.0; 4], len: 3 };
            for i in 1..poses {
                let (qi, rq) = self.place(q, x, motions, i);
                let v = qi - q0;
                row.r = v.cross(u);
                if JAC {
                    let gq = rq.map_or(w, |t| t.unrotate(w)) - w;
                    // ∂(v × u)/∂φ = v × u' with u' = (−sin φ, cos φ): v · u.
                    row.j = [gq.x, gq.y, v.dot(u), 0.0];
                }
                sink(&row);
            }
        }
    }

    /// One block's normalised residual rows at `x` (block-local columns) and its normal equations
    /// `A = JₙᵀJₙ`, `g = Jₙᵀrₙ`; returns the normalised objective `½|rₙ|²` and the world energy `Σ r²`.
    #[allow(clippy::too_many_arguments)]
    fn normal_equations(
        &self,
        block: &Block,
        x: &[f64],
        motions: &[Vec<Rigid>],
        s: f64,
        rows: &mut Vec<Row>,
        a: &mut [f64],
        g: &mut [f64],
    ) -> (f64, f64) {
        let n = g.len();
        rows.clear();
        a.fill(0.0);
        g.fill(0.0);
        let (inv_s, inv_s2) = (1.0 / s, 1.0 / (s * s));
        let mut f = 0.0;
        let mut e = 0.0;
        self.for_each_row::<true>(&block.pairs, block.slider, x, motions, |row| {
            e += row.r * row.r;
            // Link rows: r/s², coordinates ×s ⇒ J/s. Slider rows: r/s ⇒ joint columns J, φ column J/s.
            let mut nrow = *row;
            if row.slider {
                nrow.r *= inv_s;
                nrow.j[2] *= inv_s;
            } else {
                nrow.r *= inv_s2;
                nrow.j = row.j.map(|v| v * inv_s);
            }
            // Columns of pinned coordinates are dropped.
            let mut kept = 0;
            for k in 0..nrow.len {
                let local = self.local[nrow.cols[k]];
                if local != usize::MAX {
                    (nrow.cols[kept], nrow.j[kept]) = (local, nrow.j[k]);
                    kept += 1;
                }
            }
            nrow.len = kept;
            f += 0.5 * nrow.r * nrow.r;
            for k in 0..nrow.len {
                let ck = nrow.cols[k];
                g[ck] += nrow.j[k] * nrow.r;
                let a_row = &mut a[ck * n..(ck + 1) * n];
                for l in 0..nrow.len {
                    a_row[nrow.cols[l]] += nrow.j[k] * nrow.j[l];
                }
            }
            rows.push(nrow);
        });
        (f, e)
    }

    /// One block's normalised residuals at `x` (link rows `/ s²`, slider rows `/ s`).
    fn normalised_residuals(&self, block: &Block, x: &[f64], motions: &[Vec<Rigid>], s: f64, out: &mut Vec<f64>) {
        out.clear();
        let (inv_s, inv_s2) = (1.0 / s, 1.0 / (s * s));
        self.for_each_row::<false>(&block.pairs, block.slider, x, motions, |row| {
            out.push(row.r * if row.slider { inv_s } else { inv_s2 })
        });
    }

    /// The shortest link at the first pose.
    fn min_link_length(&self, x: &[f64]) -> f64 {
        self.pairs
            .iter()
            .map(|&(m, n)| (x[2 * m] - x[2 * n]).hypot(x[2 * m + 1] - x[2 * n + 1]))
            .fold(f64::INFINITY, f64::min)
    }

    fn report(&self, x: &[f64], motions: &[Vec<Rigid>], s: f64, energy: f64, iterations: usize) -> Fit {
        Fit {
            energy,
            max_relative_deviation: self.max_deviation(x, motions) / s,
            min_relative_link_length: self.min_link_length(x) / s,
            iterations,
        }
    }

    /// [`Fit::max_relative_deviation`] of `x` as it stands (no fit), the only figure the sampler reads
    /// of a linkage its construction made exact: infinite for non-finite inputs, as a fit reports.
    pub(crate) fn relative_deviation(&self, x: &[f64], motions: &[Vec<Rigid>], scale: f64) -> f64 {
        let s = usable_scale(scale);
        if !self.finite(x, motions) {
            return f64::INFINITY;
        }
        self.max_deviation(x, motions) / s
    }

    /// Whether a ternary link of `x` is, at some pose of `motions`, the mirror image of itself at the
    /// first pose. Its three lengths then all hold, yet no linkage reaches that pose: a rigid triangle
    /// cannot turn over in the plane. A nearly straight link is the exception: turning it over moves a
    /// joint by twice its height, and where that is under [`FLIP_TOLERANCE`] of the body size `scale`
    /// the linkage comes as close to the pose as the person asked for (two jaws closing on a line are
    /// driven by such links). (Checked apart from the energy, whose length residuals cannot see it: a
    /// signed-area residual would be redundant with them at every solution and make the fit's normal
    /// equations singular.)
    pub(crate) fn mirrored(&self, x: &[f64], motions: &[Vec<Rigid>], scale: f64) -> bool {
        let poses = self.poses(motions);
        let tolerance = FLIP_TOLERANCE * usable_scale(scale);
        self.triangles.iter().any(|&t| {
            // `x` holds the first pose; `motions` carry it to the others.
            let first = t.map(|j| Point::new(x[2 * j], x[2 * j + 1]));
            turns_over(first, (1..poses).map(|i| t.map(|j| self.place(j, x, motions, i).0)), tolerance)
        })
    }

    /// Whether `x` and `motions` are finite (a fit leaves anything else unchanged).
    fn finite(&self, x: &[f64], motions: &[Vec<Rigid>]) -> bool {
        x.iter().all(|v| v.is_finite())
            && motions.iter().flatten().all(|m| m.angle().is_finite() && m.translation().is_finite())
    }

    /// The largest change of a link's length, or of the slider joint's distance from its line, over
    /// the poses (world units).
    fn max_deviation(&self, x: &[f64], motions: &[Vec<Rigid>]) -> f64 {
        self.deviation_of(&self.pairs, self.slider.is_some(), x, motions)
    }

    /// [`RigidityModel::max_deviation`] over `pairs` and, if `slider`, the slider joint.
    fn deviation_of(&self, pairs: &[(usize, usize)], slider: bool, x: &[f64], motions: &[Vec<Rigid>]) -> f64 {
        let poses = self.poses(motions);
        let mut dev = 0.0f64;
        for &(m, n) in pairs {
            let l0 = (x[2 * m] - x[2 * n]).hypot(x[2 * m + 1] - x[2 * n + 1]);
            for i in 1..poses {
                let l = self.place(m, x, motions, i).0.distance(self.place(n, x, motions, i).0);
                dev = dev.max((l - l0).abs());
            }
        }
        if let Some(q) = self.slider.filter(|_| slider) {
            let u = Vec2::from_angle(x[2 * self.carriers.len()]);
            let q0 = Point::new(x[2 * q], x[2 * q + 1]);
            for i in 1..poses {
                dev = dev.max((self.place(q, x, motions, i).0 - q0).cross(u).abs());
            }
        }
        dev
    }
}

/// Whether a rigid triangle at `first` is the mirror image of itself at one of the placements
/// `later`, unless it is nearly straight: turning it over moves a vertex by twice its height, and
/// where that is at most `tolerance` it does not count.
pub(crate) fn turns_over(first: [Point; 3], mut later: impl Iterator<Item = [Point; 3]>, tolerance: f64) -> bool {
    // Twice the triangle's height over its longest side, signed by its orientation.
    let flip = |[a, b, c]: [Point; 3]| {
        let longest = a.distance(b).max(b.distance(c)).max(c.distance(a));
        2.0 * (b - a).cross(c - a) / longest.max(f64::MIN_POSITIVE)
    };
    let first = flip(first);
    first.abs() > tolerance && later.any(|t| first * flip(t) < 0.0)
}

/// The length fits are normalised by: `scale`, or 1 when it is not a positive finite number.
fn usable_scale(scale: f64) -> f64 {
    if scale.is_finite() && scale > 0.0 {
        scale
    } else {
        1.0
    }
}

/// Factors `A + λI = LLᵀ` for symmetric positive semi-definite `A` (row-major n × n; only the lower
/// triangle is read) into the lower triangle of `l`, and the reciprocals of L's diagonal into
/// `inv_diag`. Returns false when the damped matrix is not numerically positive definite.
fn cholesky_factor(n: usize, a: &[f64], lambda: f64, l: &mut [f64], inv_diag: &mut [f64]) -> bool {
    for i in 0..n {
        let (done, rest) = l.split_at_mut(i * n);
        let row_i = &mut rest[..n];
        let a_i = &a[i * n..(i + 1) * n];
        for j in 0..i {
            row_i[j] = (a_i[j] - dot(&row_i[..j], &done[j * n..j * n + j])) * inv_diag[j];
        }
        let d = a_i[i] + lambda - dot(&row_i[..i], &row_i[..i]);
        if !(d > 0.0 && d.is_finite()) {
            return false;
        }
        row_i[i] = d.sqrt();
        inv_diag[i] = 1.0 / row_i[i];
    }
    true
}

/// Solves `LLᵀ δ = −g` with the factor of [`cholesky_factor`].
fn cholesky_solve(n: usize, l: &[f64], inv_diag: &[f64], g: &[f64], out: &mut [f64]) {
    // L z = −g, by rows.
    for i in 0..n {
        out[i] = (-g[i] - dot(&l[i * n..i * n + i], &out[..i])) * inv_diag[i];
    }
    // Lᵀ δ = z, by columns of L: once δᵢ is known, remove it from the equations above.
    for i in (0..n).rev() {
        out[i] *= inv_diag[i];
        let xi = out[i];
        let row = &l[i * n..i * n + i];
        for (o, &lik) in out[..i].iter_mut().zip(row) {
            *o -= lik * xi;
        }
    }
}

/// Dot product with four independent partial sums (the compiler may not reassociate floating-point
/// sums itself).
#[inline]
fn dot(a: &[f64], b: &[f64]) -> f64 {
    let (a4, b4) = (a.chunks_exact(4), b.chunks_exact(4));
    let tail: f64 = a4.remainder().iter().zip(b4.remainder()).map(|(x, y)| x * y).sum();
    let mut acc = [0.0; 4];
    for (x, y) in a4.zip(b4) {
        for k in 0..4 {
            acc[k] += x[k] * y[k];
        }
    }
    (acc[0] + acc[1]) + (acc[2] + acc[3]) + tail
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::kinematics::Plan;
    use crate::mechanism::Mechanism;
    use proptest::prelude::*;
    use rand::{RngExt, SeedableRng};
    use rand_xoshiro::Xoshiro256PlusPlus;
    use std::sync::Arc;

    /// A six-bar's ternary link r0 (ground), q1 (body 1), p2 (body 2) with body 1 still and body 2
    /// moved by `shift`: the link's lengths hold exactly when the move reflects p2 across r0–q1.
    #[test]
    fn a_ternary_link_turned_over_is_mirrored_unless_nearly_straight() {
        let topology = Topology::chain(2);
        let model = RigidityModel::new(&topology);
        let joint = |name: &str| topology.joint_names.iter().position(|n| n == name).unwrap();
        let check = |p2: Point, shift: Vec2| {
            let mut x = vec![0.0; model.dim()];
            for (name, p) in [("r0", Point::new(0.0, 0.0)), ("q1", Point::new(10.0, 0.0)), ("p2", p2)] {
                (x[2 * joint(name)], x[2 * joint(name) + 1]) = (p.x, p.y);
            }
            let motions = vec![vec![Rigid::IDENTITY; 2], vec![Rigid::IDENTITY, Rigid::new(0.0, shift)]];
            model.mirrored(&x, &motions, 10.0)
        };
        // Turned over: lengths kept, p2 moved by 10 = the body size.
        assert!(check(Point::new(0.0, 5.0), Vec2::new(0.0, -10.0)));
        // Not moved, or moved without turning over: not mirrored.
        assert!(!check(Point::new(0.0, 5.0), Vec2::ZERO));
        assert!(!check(Point::new(0.0, 5.0), Vec2::new(0.0, 1.0)));
        // Nearly straight (height 0.01): turned over it moves p2 by 0.02 = 0.2% of the body size.
        assert!(!check(Point::new(5.0, 0.01), Vec2::new(0.0, -0.02)));
        // Height 0.5: turned over it moves p2 by 10% of the body size, beyond the tolerance.
        assert!(check(Point::new(5.0, 0.5), Vec2::new(0.0, -1.0)));
    }

    fn topologies() -> Vec<Topology> {
        vec![Topology::chain(1), Topology::chain(2), Topology::chain(3), Topology::slider_crank()]
    }

    /// Random motions: pose 0 the identity, the others within a turn of ±1 rad and a few units.
    fn random_motions(rng: &mut Xoshiro256PlusPlus, bodies: usize, poses: usize, spread: f64) -> Vec<Vec<Rigid>> {
        (0..bodies)
            .map(|_| {
                let mut m = vec![Rigid::IDENTITY];
                for _ in 1..poses {
                    let t = Vec2::new(rng.random_range(-spread..spread), rng.random_range(-spread..spread));
                    m.push(Rigid::new(rng.random_range(-1.0..1.0), t));
                }
                m
            })
            .collect()
    }

    fn random_x(rng: &mut Xoshiro256PlusPlus, dim: usize, half: f64) -> Vec<f64> {
        (0..dim).map(|_| rng.random_range(-half..half)).collect()
    }

    fn joint(t: &Topology, x: &[f64], name: &str) -> Point {
        let j = t.joint(name).unwrap();
        Point::new(x[2 * j], x[2 * j + 1])
    }

    fn circumcentre(a: Point, b: Point, c: Point) -> Point {
        let (ab, ac) = (b - a, c - a);
        let den = 2.0 * ab.cross(ac);
        let (b2, c2) = (ab.norm_sq(), ac.norm_sq());
        a + Vec2::new(ac.y * b2 - ab.y * c2, ab.x * c2 - ac.x * b2) / den
    }

    /// A random dimensioned chain of `k` bodies that the kinematic plan moves through `poses` crank
    /// angles `step` apart, with the body motions it produces (each body's frame taken from its first
    /// two joints). Returns the first-pose joints and the motions.
    fn moving_chain(k: usize, poses: usize, step: f64, seed: u64) -> (Vec<f64>, Vec<Vec<Rigid>>) {
        let topology = Arc::new(Topology::chain(k));
        let mut rng = Xoshiro256PlusPlus::seed_from_u64(seed);
        'sample: loop {
            let joints: Vec<Point> = (0..topology.joint_count())
                .map(|_| Point::new(rng.random_range(-4.0..4.0), rng.random_range(-4.0..4.0)))
                .collect();
            let mech = Mechanism { topology: topology.clone(), joints: joints.clone(), slider: None };
            let Ok(plan) = Plan::compile(&mech) else { continue };
            if plan.min_transmission(&joints) < 0.3 {
                continue;
            }
            let theta0 = mech.crank_start();
            let mut rows = Vec::new();
            // Fine steps so the plan tracks the branch; keep every pose's configuration.
            let sub = 20;
            let mut pos = vec![Point::ORIGIN; topology.joint_count()];
            for s in 0..=(poses - 1) * sub {
                if plan.solve(theta0 + step * s as f64 / sub as f64, &mut pos).is_err()
                    || plan.min_transmission(&pos) < 0.2
                {
                    continue 'sample;
                }
                if s % sub == 0 {
                    rows.push(pos.clone());
                }
            }
            let motions = (0..k)
                .map(|b| {
                    let part = topology.body_part(b);
                    let (a, c) = (part.joints[0], part.joints[1]);
                    let frame = |row: &[Point]| Rigid::from_frame(row[a], row[c] - row[a]);
                    rows.iter().map(|row| frame(&rows[0]).to(&frame(row))).collect()
                })
                .collect();
            let x = joints.iter().flat_map(|p| [p.x, p.y]).collect();
            return (x, motions);
        }
    }

    /// A slider-crank with the slider through (3.5, 0.8) at 0.2 rad, and its body's motion.
    fn moving_slider(poses: usize) -> (Vec<f64>, Vec<Vec<Rigid>>) {
        let q0 = Point::ORIGIN;
        let (crank, a0) = (1.2, 0.5);
        let p1 = q0 + Vec2::from_angle(a0) * crank;
        let q1 = Point::new(3.5, 0.8);
        let u = Vec2::from_angle(0.2);
        let c = p1.distance(q1);
        let mut s_prev = 0.0;
        let motion = (0..poses)
            .map(|i| {
                let pi = q0 + Vec2::from_angle(a0 + 0.3 * i as f64) * crank;
                // |q1 + s u − pi| = c: s² + 2 s u·w + |w|² − c² = 0.
                let w = q1 - pi;
                let (b, cc) = (u.dot(w), w.norm_sq() - c * c);
                let disc = (b * b - cc).sqrt();
                let s =
                    [-b - disc, -b + disc].into_iter().min_by(|x, y| (x - s_prev).abs().total_cmp(&(y - s_prev).abs()));
                s_prev = s.unwrap();
                let qi = q1 + u * s_prev;
                let frame = |a: Point, b: Point| Rigid::from_frame(a, b - a);
                frame(p1, q1).to(&frame(pi, qi))
            })
            .collect();
        (vec![q0.x, q0.y, p1.x, p1.y, q1.x, q1.y, 0.2], vec![motion])
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(64))]

        #[test]
        fn gradient_matches_central_differences(which in 0usize..4, poses in 2usize..=5, seed in any::<u64>()) {
            let t = &topologies()[which];
            let model = RigidityModel::new(t);
            let mut rng = Xoshiro256PlusPlus::seed_from_u64(seed);
            let motions = random_motions(&mut rng, t.body_count, poses, 2.0);
            let x = random_x(&mut rng, model.dim(), 3.0);
            let mut g = vec![0.0; model.dim()];
            model.gradient(&x, &motions, &mut g);
            let scale = g.iter().fold(1.0f64, |m, v| m.max(v.abs()));
            let mut xp = x.clone();
            for i in 0..x.len() {
                let h = 1e-5 * x[i].abs().max(1.0);
                xp[i] = x[i] + h;
                let ep = model.energy(&xp, &motions);
                xp[i] = x[i] - h;
                let em = model.energy(&xp, &motions);
                xp[i] = x[i];
                let fd = (ep - em) / (2.0 * h);
                prop_assert!((fd - g[i]).abs() <= 1e-5 * scale, "∂{i}: analytic {} vs fd {fd}", g[i]);
            }
        }

        #[test]
        fn fit_never_increases_energy(which in 0usize..4, poses in 1usize..=8, seed in any::<u64>(),
                                      scale in 0.1..100.0f64) {
            let t = &topologies()[which];
            let model = RigidityModel::new(t);
            let mut rng = Xoshiro256PlusPlus::seed_from_u64(seed);
            let motions = random_motions(&mut rng, t.body_count, poses, 2.0 * scale);
            let mut x = random_x(&mut rng, model.dim(), 3.0 * scale);
            if t.slider_joint.is_some() {
                x[model.dim() - 1] /= scale;
            }
            let e0 = model.energy(&x, &motions);
            let fit = model.fit(&mut x, &motions, scale, &mut FitWorkspace::default());
            prop_assert!(fit.energy.is_finite() && fit.max_relative_deviation.is_finite());
            prop_assert!(fit.energy <= e0, "{} > {e0}", fit.energy);
            prop_assert!((model.energy(&x, &motions) - fit.energy).abs() <= 1e-12 * e0.max(1e-300));
        }
    }

    #[test]
    fn residual_count_and_layout() {
        let t = Topology::chain(2);
        let model = RigidityModel::new(&t);
        assert_eq!(model.dim(), 14);
        assert_eq!(model.residual_count(4), 5 * 3);
        let s = RigidityModel::new(&Topology::slider_crank());
        assert_eq!(s.dim(), 7);
        assert_eq!(s.residual_count(5), 2 * 4);
        let mut rng = Xoshiro256PlusPlus::seed_from_u64(1);
        let motions = random_motions(&mut rng, 2, 4, 1.0);
        let x = random_x(&mut rng, 14, 2.0);
        let mut r = Vec::new();
        model.residuals(&x, &motions, &mut r);
        assert_eq!(r.len(), 15);
        let e: f64 = r.iter().map(|v| v * v).sum();
        assert!((e - model.energy(&x, &motions)).abs() <= 1e-12 * e);
    }

    #[test]
    fn energy_splits_into_one_block_per_link() {
        for k in 1..=6 {
            let model = RigidityModel::new(&Topology::chain(k));
            let mut sizes: Vec<usize> = model.blocks.iter().map(|b| b.vars.len()).collect();
            sizes.sort_unstable();
            let mut expected = vec![4, 4];
            expected.extend(std::iter::repeat_n(6, k - 1));
            expected.sort_unstable();
            assert_eq!(sizes, expected, "K = {k}");
            // Every unknown in exactly one block, and every pair in exactly one block.
            let mut seen: Vec<usize> = model.blocks.iter().flat_map(|b| b.vars.iter().copied()).collect();
            seen.sort_unstable();
            assert_eq!(seen, (0..model.dim()).collect::<Vec<_>>());
            assert_eq!(model.blocks.iter().map(|b| b.pairs.len()).sum::<usize>(), model.pairs.len());
        }
        let slider = RigidityModel::new(&Topology::slider_crank());
        let sizes: Vec<(usize, bool)> = slider.blocks.iter().map(|b| (b.vars.len(), b.slider)).collect();
        assert_eq!(sizes, vec![(4, false), (3, true)]);
    }

    #[test]
    fn four_bar_from_five_poses_is_recovered_exactly() {
        for seed in 0..20 {
            let (truth, motions) = moving_chain(1, 5, 0.25, seed);
            let model = RigidityModel::new(&Topology::chain(1));
            assert!(model.energy(&truth, &motions) < 1e-20, "the true linkage is rigid");
            let d = 2.0;
            let mut rng = Xoshiro256PlusPlus::seed_from_u64(100 + seed);
            let mut x: Vec<f64> = truth.iter().map(|v| v + 0.05 * d * rng.random_range(-1.0..1.0)).collect();
            let fit = model.fit(&mut x, &motions, d, &mut FitWorkspace::default());
            assert!(fit.energy < 1e-16 * d.powi(4), "seed {seed}: {fit:?}");
            assert!(fit.max_relative_deviation < 1e-8, "seed {seed}: {fit:?}");
            assert!(fit.iterations < 30, "seed {seed}: {fit:?}");
        }
    }

    /// The deviation alone is the one a fit that polishes nothing reports: zero for the true linkage,
    /// the same figure for a perturbed one, infinite for non-finite joints.
    #[test]
    fn relative_deviation_is_the_fits_without_polishing() {
        for k in [1, 2, 3] {
            let (truth, motions) = moving_chain(k, 4, 0.2, k as u64);
            let model = RigidityModel::new(&Topology::chain(k));
            let d = 2.0;
            assert!(model.relative_deviation(&truth, &motions, d) < 1e-12);
            let mut rng = Xoshiro256PlusPlus::seed_from_u64(k as u64);
            let mut x: Vec<f64> = truth.iter().map(|v| v + 0.05 * d * rng.random_range(-1.0..1.0)).collect();
            let deviation = model.relative_deviation(&x, &motions, d);
            let fit = model.fit_where(&mut x, &motions, d, &mut FitWorkspace::default(), |_| false);
            assert!(deviation > 1e-4, "K {k}: the perturbed linkage is not rigid");
            assert_eq!(deviation, fit.max_relative_deviation, "K {k}");
            x[0] = f64::NAN;
            assert_eq!(model.relative_deviation(&x, &motions, d), f64::INFINITY);
        }
    }

    #[test]
    fn six_and_eight_bars_from_five_poses_are_recovered_exactly() {
        for k in [2, 3] {
            for seed in 0..10 {
                let (truth, motions) = moving_chain(k, 5, 0.15, seed);
                let model = RigidityModel::new(&Topology::chain(k));
                let d = 2.0;
                let mut rng = Xoshiro256PlusPlus::seed_from_u64(100 + seed);
                let mut x: Vec<f64> = truth.iter().map(|v| v + 0.05 * d * rng.random_range(-1.0..1.0)).collect();
                let fit = model.fit(&mut x, &motions, d, &mut FitWorkspace::default());
                assert!(fit.energy < 1e-16 * d.powi(4), "K {k} seed {seed}: {fit:?}");
                assert!(fit.max_relative_deviation < 1e-8, "K {k} seed {seed}: {fit:?}");
            }
        }
    }

    #[test]
    fn slider_crank_from_five_poses_is_recovered_exactly() {
        let (truth, motions) = moving_slider(5);
        let model = RigidityModel::new(&Topology::slider_crank());
        assert!(model.energy(&truth, &motions) < 1e-20);
        let d = 1.5;
        for seed in 0..20 {
            let mut rng = Xoshiro256PlusPlus::seed_from_u64(seed);
            let mut x: Vec<f64> = truth.iter().map(|v| v + 0.05 * d * rng.random_range(-1.0..1.0)).collect();
            let fit = model.fit(&mut x, &motions, d, &mut FitWorkspace::default());
            assert!(fit.energy < 1e-16 * d.powi(4), "seed {seed}: {fit:?}");
            assert!(fit.max_relative_deviation < 1e-8, "seed {seed}: {fit:?}");
            // The slider direction is recovered up to a half turn.
            let dphi = (x[6] - 0.2).rem_euclid(std::f64::consts::PI);
            assert!(dphi.min(std::f64::consts::PI - dphi) < 1e-7, "seed {seed}: φ = {}", x[6]);
        }
    }

    #[test]
    fn three_poses_put_ground_pivots_at_circumcentres() {
        let t = Topology::chain(1);
        let model = RigidityModel::new(&t);
        let mut ws = FitWorkspace::default();
        for seed in 0..50 {
            let mut rng = Xoshiro256PlusPlus::seed_from_u64(seed);
            let motions = random_motions(&mut rng, 1, 3, 2.0);
            let mut x = random_x(&mut rng, model.dim(), 3.0);
            let fit = model.fit(&mut x, &motions, 1.0, &mut ws);
            assert!(fit.energy < 1e-20 && fit.max_relative_deviation < 1e-9, "seed {seed}: {fit:?}");
            for (moving, ground) in [("p1", "q0"), ("q1", "r0")] {
                let m = joint(&t, &x, moving);
                let [a, b, c] = [0, 1, 2].map(|i| motions[0][i].apply(m));
                let centre = circumcentre(a, b, c);
                assert!(centre.distance(joint(&t, &x, ground)) < 1e-6 * (1.0 + centre.to_vec2().norm()), "seed {seed}");
            }
        }
    }

    #[test]
    fn three_poses_are_met_exactly_by_longer_chains() {
        // The ternary link r0–q1–p2 of the six-bar is a square system for three poses (r0 is the
        // circumcentre of both q1's and p2's positions, and q1–p2 keeps its length), so from some
        // starts the fit ends in a local minimum that is not rigid.
        for k in [2, 3] {
            let t = Topology::chain(k);
            let model = RigidityModel::new(&t);
            let mut ws = FitWorkspace::default();
            let mut exact = 0;
            for seed in 0..40 {
                let mut rng = Xoshiro256PlusPlus::seed_from_u64(seed);
                let motions = random_motions(&mut rng, k, 3, 2.0);
                let mut x = random_x(&mut rng, model.dim(), 3.0);
                let fit = model.fit(&mut x, &motions, 1.0, &mut ws);
                exact += usize::from(fit.max_relative_deviation < 1e-8);
            }
            assert!(exact >= 30, "K {k}: only {exact} of 40 fits were exact");
        }
    }

    #[test]
    fn the_start_point_is_kept_nearby_when_poses_underdetermine_the_joints() {
        // Two poses: one equation per link, so the exact solutions form a manifold. Holding the moving
        // points and sliding each ground pivot onto the perpendicular bisector of its moving point's
        // two positions is one exact solution; the fit must land at least about as close to the start.
        let t = Topology::chain(1);
        let model = RigidityModel::new(&t);
        let mut rng = Xoshiro256PlusPlus::seed_from_u64(7);
        let mut ratios = Vec::new();
        for _ in 0..200 {
            let motions = random_motions(&mut rng, 1, 2, 0.5);
            let start = random_x(&mut rng, model.dim(), 3.0);
            let mut x = start.clone();
            let fit = model.fit(&mut x, &motions, 1.0, &mut FitWorkspace::default());
            assert!(fit.max_relative_deviation < 1e-8, "{fit:?}");
            let moved = x.iter().zip(&start).map(|(a, b)| (a - b).powi(2)).sum::<f64>().sqrt();
            let bisector_sq: f64 = [("p1", "q0"), ("q1", "r0")]
                .iter()
                .map(|&(m, f)| {
                    let (m0, f0) = (joint(&t, &start, m), joint(&t, &start, f));
                    let m1 = motions[0][1].apply(m0);
                    let n = (m1 - m0).normalized();
                    (f0 - m0.lerp(m1, 0.5)).dot(n).powi(2)
                })
                .sum();
            ratios.push(moved / bisector_sq.sqrt());
        }
        ratios.sort_by(f64::total_cmp);
        assert!(ratios[100] < 1.0, "median {} times the bisector distance", ratios[100]);
        assert!(ratios[199] < 1.5, "up to {} times the bisector distance", ratios[199]);
    }

    #[test]
    fn degenerate_inputs_give_no_nan() {
        let mut ws = FitWorkspace::default();
        for t in topologies() {
            let model = RigidityModel::new(&t);
            let mut rng = Xoshiro256PlusPlus::seed_from_u64(3);
            // All poses identical: already rigid.
            let still = vec![vec![Rigid::IDENTITY; 4]; t.body_count];
            let mut x = random_x(&mut rng, model.dim(), 3.0);
            let fit = model.fit(&mut x, &still, 1.0, &mut ws);
            assert_eq!(fit.energy, 0.0);
            assert_eq!(fit.iterations, 0);
            // Coincident joints, moving bodies.
            let motions = random_motions(&mut rng, t.body_count, 5, 2.0);
            let mut x = vec![0.5; model.dim()];
            let fit = model.fit(&mut x, &motions, 1.0, &mut ws);
            assert!(fit.energy.is_finite() && x.iter().all(|v| v.is_finite()), "{fit:?}");
            // Everything at the origin with rotations about the origin: the collapsed solution.
            let spin: Vec<Vec<Rigid>> =
                (0..t.body_count).map(|_| (0..4).map(|i| Rigid::new(0.3 * i as f64, Vec2::ZERO)).collect()).collect();
            let mut x = vec![0.0; model.dim()];
            let fit = model.fit(&mut x, &spin, 1.0, &mut ws);
            assert_eq!(fit.energy, 0.0);
            assert_eq!(fit.min_relative_link_length, 0.0);
            // A zero or NaN scale, single pose, and non-finite input.
            let mut x = random_x(&mut rng, model.dim(), 3.0);
            assert!(model.fit(&mut x, &motions, 0.0, &mut ws).energy.is_finite());
            assert!(model.fit(&mut x, &motions, f64::NAN, &mut ws).energy.is_finite());
            let one: Vec<Vec<Rigid>> = vec![vec![Rigid::IDENTITY]; t.body_count];
            assert_eq!(model.fit(&mut x, &one, 1.0, &mut ws).energy, 0.0);
            let before = x.clone();
            x[0] = f64::NAN;
            let fit = model.fit(&mut x, &motions, 1.0, &mut ws);
            assert!(fit.energy.is_infinite() && !fit.max_relative_deviation.is_nan());
            assert!(x[1..] == before[1..]);
        }
    }

    #[test]
    fn fit_is_scale_free() {
        let (truth, motions) = moving_chain(1, 5, 0.25, 4);
        let model = RigidityModel::new(&Topology::chain(1));
        let mut rng = Xoshiro256PlusPlus::seed_from_u64(11);
        let start: Vec<f64> = truth.iter().map(|v| v + 0.3 * rng.random_range(-1.0..1.0)).collect();
        let mut reference = None;
        for k in [1e-3, 1.0, 1e3] {
            let scaled: Vec<Vec<Rigid>> = motions
                .iter()
                .map(|m| m.iter().map(|r| Rigid::new(r.angle(), r.translation() * k)).collect())
                .collect();
            let mut x: Vec<f64> = start.iter().map(|v| v * k).collect();
            let fit = model.fit(&mut x, &scaled, 2.0 * k, &mut FitWorkspace::default());
            let y: Vec<f64> = x.iter().map(|v| v / k).collect();
            let (iters, y_ref) = reference.get_or_insert((fit.iterations, y.clone()));
            // Scaling by 1e-3 is not exact in binary: a stopping test that lands near its threshold
            // may take one step more or less.
            assert!(fit.iterations.abs_diff(*iters) <= 1, "{} against {iters} iterations", fit.iterations);
            assert!(y.iter().zip(y_ref.iter()).all(|(a, b)| (a - b).abs() < 1e-9));
        }
    }

    /// Timing of fits; run with `cargo test --release -p linkwright-core rigidity_timing -- --ignored
    /// --nocapture`.
    #[test]
    #[ignore]
    fn rigidity_timing() {
        let d = 2.0;
        for (name, t) in [
            ("K=1", Topology::chain(1)),
            ("K=2", Topology::chain(2)),
            ("K=3", Topology::chain(3)),
            ("K=8", Topology::chain(8)),
            ("slider", Topology::slider_crank()),
        ] {
            for poses in [3, 5, 8] {
                let model = RigidityModel::new(&t);
                let mut rng = Xoshiro256PlusPlus::seed_from_u64(1);
                let cases: Vec<(Vec<f64>, Vec<Vec<Rigid>>)> = (0..2000)
                    .map(|_| {
                        let m = random_motions(&mut rng, t.body_count, poses, d);
                        (random_x(&mut rng, model.dim(), 2.0 * d), m)
                    })
                    .collect();
                let mut ws = FitWorkspace::default();
                // CPU time of this thread (ns on the CPU, from the scheduler), so that other processes
                // sharing the machine do not inflate the figure; wall time where that is unavailable.
                let cpu_ns = || {
                    std::fs::read_to_string("/proc/thread-self/schedstat")
                        .ok()
                        .and_then(|s| s.split_whitespace().next()?.parse::<f64>().ok())
                };
                let mut us = f64::INFINITY;
                for _ in 0..3 {
                    let (wall, cpu) = (std::time::Instant::now(), cpu_ns());
                    for (x0, m) in cases.iter().cycle().take(10 * cases.len()) {
                        let mut x = x0.clone();
                        std::hint::black_box(model.fit(&mut x, m, d, &mut ws));
                    }
                    let ns = match (cpu, cpu_ns()) {
                        (Some(a), Some(b)) => b - a,
                        _ => wall.elapsed().as_secs_f64() * 1e9,
                    };
                    us = us.min(ns * 1e-3 / (10 * cases.len()) as f64);
                }
                let (mut iters, mut exact, mut short, mut capped) = (0, 0, 0, 0);
                for (x0, m) in &cases {
                    let mut x = x0.clone();
                    let fit = model.fit(&mut x, m, d, &mut ws);
                    iters += fit.iterations;
                    capped += usize::from(fit.iterations >= 100);
                    exact += usize::from(fit.max_relative_deviation < 1e-6);
                    short += usize::from(fit.min_relative_link_length < 0.05);
                }
                println!(
                    "{name:7} N={poses}: {us:7.2} µs/fit, {:5.1} iterations, {:5.1}% rigid (dev < 1e-6), {:4.1}% short links, {:4.1}% at the iteration limit",
                    iters as f64 / cases.len() as f64,
                    100.0 * exact as f64 / cases.len() as f64,
                    100.0 * short as f64 / cases.len() as f64,
                    100.0 * capped as f64 / cases.len() as f64
                );
            }
        }
    }
}

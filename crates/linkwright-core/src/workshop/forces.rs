//! The loads along the motion: every link's axial force and every part's force on every bolt, at each
//! crank angle, with the linkage held at its crank against the parts' weights.
//!
//! **By virtual work.** Hold the crank's angle. Every part keeps the distances between its joints
//! (a binary link one, a ternary plate or a body with three joints a triangle's three), the crank also
//! its angle, and the slider joint its line: as many constraints `g` as the moving joints have
//! coordinates, so the held linkage is a structure. Let one constraint's length grow by δ while every
//! other keeps its own: the joints move by `J⁻¹ e δ` (J the constraints' Jacobian), and the weights'
//! potential energy V changes by `∇V · J⁻¹ e δ`. That derivative, `λ = J⁻ᵀ ∇V`, is the force in that
//! constraint: a link's axial force (positive pushing its joints apart, compression), the crank's
//! force across its end (the holding torque divided by its length), the guide's push on the slider.
//! Solving `Jᵀ λ = ∇V` once per row gives every such derivative at once, exactly: it is the finite
//! difference "lengthen one link and solve the kinematics again" in the limit, and the direct
//! equilibrium of every bolt (`Jᵀ λ = ∇V` is the sum of forces at each moving joint).
//!
//! **The weights.** A body's centre of mass is the centroid of its outline, carried rigidly by its
//! first two joints (as [`crate::kinematics::BodyFrames`] carries the body); a link's is the mean of
//! its joints. Both make V a linear function of the joints' positions, so `∇V` is exact: a weight W
//! at `c = a + α (b − a) + β perp(b − a)` puts `W (α u − β perp u)` on b and the rest of `W u` on a
//! (u the up direction): forces statically equivalent to the weight at its centre.

use super::error::WorkshopError;
use crate::geom::{Point, Vec2};
use crate::kinematics::Trace;
use crate::mechanism::{Mechanism, PartKind};
use crate::scene::Problem;
use crate::statics::GRAVITY;
use nalgebra::{DMatrix, DVector};

/// The axial force between two joints a part holds apart: a binary link's, or one side of a ternary
/// plate's (or a body's) triangle.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EdgeForce {
    /// The part, an index into the topology's parts.
    pub part: usize,
    /// The two joints.
    pub joints: [usize; 2],
    /// The force along the pair, N: positive pushes the joints apart (compression), negative pulls
    /// them together (tension).
    pub compression_n: f64,
}

/// The force one part exerts on the bolt of one of its joints.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PinForce {
    /// The part, an index into the topology's parts (the ground's force is the reaction of the fixed
    /// bodies, and at the slider joint the guide's push).
    pub part: usize,
    /// The joint.
    pub joint: usize,
    /// The force, N, world directions.
    pub force_n: Vec2,
}

/// The forces in the linkage at one crank angle.
#[derive(Clone, Debug, PartialEq)]
pub struct RowForces {
    /// The crank's angle, degrees.
    pub crank_deg: f64,
    /// Every pair of joints held apart by a part, with its axial force.
    pub edges: Vec<EdgeForce>,
    /// The force the crank puts across the joint at its moving end, N, counter-clockwise about the
    /// crank's pivot positive: the holding torque divided by the crank's length.
    pub crank_transverse_n: f64,
    /// The torque the crank is held with, N·m, counter-clockwise positive.
    pub torque_nm: f64,
    /// The guide's push on the slider joint across its line, N (the slider-crank only).
    pub guide_n: Option<f64>,
    /// Every part's force on the bolt of each of its joints; at every joint they sum to zero.
    pub pins: Vec<PinForce>,
}

impl RowForces {
    /// The largest shear any interface of the bolt at `joint` can carry: half the sum of the parts'
    /// forces' magnitudes on it. Between two parts it is the force one passes to the other; in a
    /// stack of more, the shear at an interface is the sum of the forces on one side, which (the
    /// forces summing to zero) is at most half the sum of them all.
    pub fn bolt_shear_n(&self, joint: usize) -> f64 {
        0.5 * self.pins.iter().filter(|p| p.joint == joint).map(|p| p.force_n.norm()).sum::<f64>()
    }
    /// The force `part` exerts on the bolt at `joint` (zero when it does not carry it).
    pub fn pin_force(&self, part: usize, joint: usize) -> Vec2 {
        self.pins.iter().filter(|p| p.part == part && p.joint == joint).fold(Vec2::ZERO, |s, p| s + p.force_n)
    }
}

/// What one constraint of the held linkage ties.
#[derive(Clone, Copy, Debug)]
enum Tie {
    /// The distance between two joints.
    Distance(usize, usize),
    /// The crank's angle: its tip stays on the line from its pivot.
    CrankAngle { pivot: usize, tip: usize },
    /// The slider joint stays on its line (unit normal given).
    Line { joint: usize, normal: Vec2 },
}

/// A constraint and the part that holds it.
#[derive(Clone, Copy, Debug)]
struct Constraint {
    part: usize,
    tie: Tie,
}

impl Constraint {
    /// The gradient of the constraint with respect to each joint it involves, at `row`.
    fn gradient(&self, row: &[Point]) -> [(usize, Vec2); 2] {
        match self.tie {
            Tie::Distance(a, b) => {
                let u = (row[a] - row[b]).normalized();
                [(a, u), (b, -u)]
            }
            Tie::CrankAngle { pivot, tip } => {
                let n = (row[tip] - row[pivot]).normalized().perp();
                [(tip, n), (pivot, -n)]
            }
            Tie::Line { joint, normal } => [(joint, normal), (joint, Vec2::ZERO)],
        }
    }
}

/// Where a part's weight sits, in terms of its joints.
#[derive(Clone, Debug)]
enum Centre {
    /// `a + α (b − a) + β perp(b − a)`.
    Carried { a: usize, b: usize, alpha: f64, beta: f64 },
    /// The mean of these joints.
    Mean(Vec<usize>),
}

/// The weight model and the constraints of a mechanism, built once.
struct Model {
    constraints: Vec<Constraint>,
    /// Per part (topology index): weight in N and where it sits (none for the ground).
    weights: Vec<Option<(f64, Centre)>>,
    /// Each moving joint's first coordinate's index among the unknowns (`None` for fixed joints).
    dof: Vec<Option<usize>>,
    unknowns: usize,
    ground: usize,
    /// The crank's pivot and tip.
    pivot: usize,
    tip: usize,
    up: Vec2,
    metres_per_unit: f64,
}

impl Model {
    fn new(
        problem: &Problem,
        mechanism: &Mechanism,
        masses_kg: &[f64],
        metres_per_unit: f64,
    ) -> Result<Model, WorkshopError> {
        let topo = &mechanism.topology;
        if masses_kg.len() != topo.parts.len() {
            return Err(WorkshopError::Indeterminate(format!(
                "masses are given for {} parts, the linkage has {}",
                masses_kg.len(),
                topo.parts.len()
            )));
        }
        let fixed = topo.fixed_joints();
        let mut dof = vec![None; topo.joint_count()];
        let mut unknowns = 0;
        for (j, slot) in dof.iter_mut().enumerate() {
            if !fixed.contains(&j) {
                *slot = Some(unknowns);
                unknowns += 2;
            }
        }
        let (pivot, tip) = (topo.driver_pivot, topo.driver_tip);
        let crank = topo
            .parts
            .iter()
            .position(|p| p.kind == PartKind::Link && p.joints.contains(&pivot) && p.joints.contains(&tip))
            .ok_or_else(|| WorkshopError::Indeterminate("no link joins the driver's pivot and tip".into()))?;
        let ground = topo.parts.iter().position(|p| p.kind == PartKind::Fixed).unwrap_or(usize::MAX);
        let mut constraints = Vec::new();
        let mut weights = Vec::with_capacity(topo.parts.len());
        for (k, part) in topo.parts.iter().enumerate() {
            let js = &part.joints;
            if part.kind != PartKind::Fixed && js.len() >= 2 {
                // A rigid triangulation: the first two joints, then each further joint tied to both.
                constraints.push(Constraint { part: k, tie: Tie::Distance(js[0], js[1]) });
                for &c in &js[2..] {
                    constraints.push(Constraint { part: k, tie: Tie::Distance(js[0], c) });
                    constraints.push(Constraint { part: k, tie: Tie::Distance(js[1], c) });
                }
            }
            let weight = masses_kg[k] * GRAVITY;
            weights.push(match part.kind {
                PartKind::Fixed => None,
                PartKind::Link => Some((weight, Centre::Mean(js.clone()))),
                PartKind::Body(b) => {
                    let body = &problem.bodies[b];
                    let com = body.poses[0].apply(body.outline.centroid());
                    let (a, c) = (js[0], js[1]);
                    let d = mechanism.joints[c] - mechanism.joints[a];
                    let v = com - mechanism.joints[a];
                    let n = d.norm_sq();
                    Some((weight, Centre::Carried { a, b: c, alpha: v.dot(d) / n, beta: d.cross(v) / n }))
                }
            });
        }
        constraints.push(Constraint { part: crank, tie: Tie::CrankAngle { pivot, tip } });
        if let (Some(joint), Some(line)) = (topo.slider_joint, mechanism.slider) {
            constraints.push(Constraint { part: ground, tie: Tie::Line { joint, normal: line.direction.perp() } });
        }
        if constraints.len() != unknowns {
            return Err(WorkshopError::Indeterminate(format!(
                "{} constraints hold {} joint coordinates",
                constraints.len(),
                unknowns
            )));
        }
        Ok(Model { constraints, weights, dof, unknowns, ground, pivot, tip, up: -problem.gravity, metres_per_unit })
    }

    /// Each part's weight on each of its joints, `∇V` split by part: (part, joint, force on the
    /// joint's coordinates).
    fn weight_gradients(&self) -> Vec<(usize, usize, Vec2)> {
        let mut out = Vec::new();
        for (k, w) in self.weights.iter().enumerate() {
            let Some((weight, centre)) = w else { continue };
            let lift = self.up * *weight;
            match centre {
                Centre::Carried { a, b, alpha, beta } => {
                    let on_b = lift * *alpha - lift.perp() * *beta;
                    out.push((k, *b, on_b));
                    out.push((k, *a, lift - on_b));
                }
                Centre::Mean(joints) => {
                    let share = lift / joints.len() as f64;
                    out.extend(joints.iter().map(|&j| (k, j, share)));
                }
            }
        }
        out
    }

    /// The forces at one row (crank at `theta`).
    fn solve(&self, theta: f64, row: &[Point]) -> Result<RowForces, WorkshopError> {
        let crank_deg = theta.to_degrees();
        let n = self.unknowns;
        let gradients: Vec<[(usize, Vec2); 2]> = self.constraints.iter().map(|c| c.gradient(row)).collect();
        // Jᵀ: one row per joint coordinate, one column per constraint.
        let mut jt = DMatrix::<f64>::zeros(n, n);
        for (c, grad) in gradients.iter().enumerate() {
            for &(j, g) in grad {
                if let Some(d) = self.dof[j] {
                    jt[(d, c)] += g.x;
                    jt[(d + 1, c)] += g.y;
                }
            }
        }
        let weights = self.weight_gradients();
        let mut rhs = DVector::<f64>::zeros(n);
        for &(_, j, f) in &weights {
            if let Some(d) = self.dof[j] {
                rhs[d] += f.x;
                rhs[d + 1] += f.y;
            }
        }
        // Near a dead point the held structure turns into a mechanism: Jᵀ loses rank.
        let singular = jt.clone().singular_values();
        let (lo, hi) = singular.iter().fold((f64::INFINITY, 0.0f64), |(lo, hi), &s| (lo.min(s), hi.max(s)));
        if lo.is_nan() || lo <= 1e-9 * hi {
            return Err(WorkshopError::DeadPoint { crank_deg });
        }
        let lambda = jt.lu().solve(&rhs).ok_or(WorkshopError::DeadPoint { crank_deg })?;
        if lambda.iter().any(|x| !x.is_finite()) {
            return Err(WorkshopError::DeadPoint { crank_deg });
        }
        let mut edges = Vec::new();
        let mut pins: Vec<PinForce> = Vec::new();
        let (mut transverse, mut guide) = (0.0, None);
        for ((c, grad), &l) in self.constraints.iter().zip(&gradients).zip(lambda.iter()) {
            match c.tie {
                Tie::Distance(a, b) => edges.push(EdgeForce { part: c.part, joints: [a, b], compression_n: l }),
                Tie::CrankAngle { .. } => transverse = l,
                Tie::Line { .. } => guide = Some(l),
            }
            for &(j, g) in grad {
                if g != Vec2::ZERO {
                    add_pin(&mut pins, c.part, j, g * l);
                }
            }
        }
        for &(k, j, f) in &weights {
            add_pin(&mut pins, k, j, -f);
        }
        // The fixed bodies hold the fixed joints with whatever the moving parts leave there.
        for j in (0..self.dof.len()).filter(|&j| self.dof[j].is_none()) {
            let rest =
                pins.iter().filter(|p| p.joint == j && p.part != self.ground).fold(Vec2::ZERO, |s, p| s + p.force_n);
            if rest != Vec2::ZERO {
                add_pin(&mut pins, self.ground, j, -rest);
            }
        }
        let crank_m = row[self.pivot].distance(row[self.tip]) * self.metres_per_unit;
        Ok(RowForces {
            crank_deg,
            edges,
            crank_transverse_n: transverse,
            torque_nm: transverse * crank_m,
            guide_n: guide,
            pins,
        })
    }
}

/// Adds `force` to what `part` exerts on the bolt at `joint`.
fn add_pin(pins: &mut Vec<PinForce>, part: usize, joint: usize, force: Vec2) {
    match pins.iter_mut().find(|p| p.part == part && p.joint == joint) {
        Some(p) => p.force_n += force,
        None => pins.push(PinForce { part, joint, force_n: force }),
    }
}

/// The forces in `mechanism` at every row of `trace` (its motion), holding the parts of
/// `masses_kg` (one mass per part of the topology, kilograms; the ground's is ignored) against the
/// scene's gravity with the crank. A body's weight acts at its outline's centroid, a link's at the
/// mean of its joints.
///
/// ```
/// use linkwright_core::testbed::{known_scene, Known};
/// use linkwright_core::workshop::equilibrium;
/// use linkwright_core::{kinematics::{Plan, Trace}, Problem};
///
/// let known = known_scene(Known::chain(1), 3, 7, 1000.0)?;
/// let problem = Problem::new(&known.scene).expect("a valid scene");
/// let plan = Plan::compile(&known.mechanism)?;
/// let mut trace = Trace::new(plan.joint_count());
/// let (from, to) = (known.pose_crank[0], known.pose_crank[known.pose_crank.len() - 1]);
/// trace.sweep(&plan, from, to, 2f64.to_radians())?;
/// // A 10 kg body on weightless links.
/// let masses: Vec<f64> = known.mechanism.topology.parts.iter().map(|p| if p.name == "body1" { 10.0 } else { 0.0 }).collect();
/// let rows = equilibrium(&problem, &known.mechanism, &trace, &masses)?;
/// // At every bolt the parts' forces balance.
/// for row in &rows {
///     for j in 0..plan.joint_count() {
///         let sum = row.pins.iter().filter(|p| p.joint == j).fold((0.0, 0.0), |s, p| (s.0 + p.force_n.x, s.1 + p.force_n.y));
///         assert!(sum.0.abs() < 1e-6 && sum.1.abs() < 1e-6);
///     }
/// }
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn equilibrium(
    problem: &Problem,
    mechanism: &Mechanism,
    trace: &Trace,
    masses_kg: &[f64],
) -> Result<Vec<RowForces>, WorkshopError> {
    let model = Model::new(problem, mechanism, masses_kg, problem.units.millimetres() / 1000.0)?;
    (0..trace.len()).map(|r| model.solve(trace.thetas[r], trace.row(r))).collect()
}

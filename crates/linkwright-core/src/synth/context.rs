//! Everything about one (problem, topology) pair that every candidate needs, computed once.

use super::rigidity::RigidityModel;
use super::terms::CostWeights;
use crate::geom::{Isometry, Obstacle, Point, Polygon, Rigid, Vec2};
use crate::kinematics::{
    circle_circle_branch, complete, complete_turning, completion_order, Branch, Completion, DyadError,
};
use crate::mechanism::{MechanismType, PartKind, Topology};
use crate::scene::Problem;
use std::sync::Arc;

/// Fraction of the smallest body size d below which two joints of one part count as too close to
/// build (a pin and its hole need room). Paper §7 fixes link widths in absolute units; we keep every
/// threshold relative to the drawing.
pub(crate) const MIN_JOINT_SPACING: f64 = 0.2;
/// The crank step of every simulation, radians (paper §8.3: 1°).
pub(crate) const CRANK_STEP: f64 = std::f64::consts::PI / 180.0;
/// How far past the last pose's nominal crank angle the search for the configuration closest to it
/// may look, radians.
pub(crate) const END_SEARCH: f64 = 10.0 * std::f64::consts::PI / 180.0;
/// A fit is accepted when no link length (nor the slider's line) deviates across the perturbed poses
/// by more than this fraction of the body size d: scale-free, so any drawing unit works.
pub(crate) const ACCEPT_DEVIATION: f64 = 0.05;
/// The same bound when the motion has more poses than the linkage type can hit exactly
/// ([`crate::mechanism::Topology::max_exact_poses`]): fits then end at a residual, and the linkage
/// built from their first-pose joints is simulated and charged by E_acc (paper §4.2), so the gate only
/// keeps out fits that are far from any linkage.
pub(crate) const OVERDETERMINED_DEVIATION: f64 = 0.5;
/// The first and last poses are where the object rests, and a scene may mark intermediate poses that
/// must be hit as well (`Problem::must_hit`): a linkage is kept rigid through them to this fraction of
/// d (its links' lengths at those poses), which puts the body there to well under 0.5% of d.
pub(crate) const END_DEVIATION: f64 = 1e-5;
/// The same bound when every pose must be hit exactly (`pose_tolerance` 0).
pub(crate) const EXACT_DEVIATION: f64 = 1e-8;
/// A design's bodies pass each must-hit pose (the last, where they come to rest, among them) within
/// this fraction of their size d, and within [`MUST_HIT_ANGLE_DEG`]: the closed lid closes.
pub(crate) const MUST_HIT_POSITION: f64 = 0.005;
/// The angle a design may miss a must-hit pose by, degrees.
pub(crate) const MUST_HIT_ANGLE_DEG: f64 = 0.5;

/// Per-topology precomputation for one problem.
#[derive(Debug)]
pub(crate) struct Context<'a> {
    pub problem: &'a Problem,
    pub topology: Arc<Topology>,
    /// The moving body that carries each joint, `None` for ground joints.
    pub carriers: Vec<Option<usize>>,
    /// The joints carried by moving bodies (J_M of paper eq. 10–11).
    pub moving_joints: Vec<usize>,
    /// `(moving, fixed)`: a body-carried joint and a fixed joint that a link holds at a fixed distance,
    /// so the moving joint stays on a circle around the fixed one in every configuration.
    pub tethers: Vec<(usize, usize)>,
    /// Every pair of joints held at a fixed distance by a link: also the segments links draw, which
    /// the collision sweep checks against avoid regions.
    pub link_pairs: Vec<(usize, usize)>,
    /// Every pair of joints on one part (links, bodies, ground), which must stay apart.
    pub part_pairs: Vec<(usize, usize)>,
    /// `motions[b][i]`: the input motion of body b from the first pose to pose i.
    pub motions: Vec<Vec<Rigid>>,
    pub first_poses: Vec<Rigid>,
    /// The smallest moving body size d.
    pub body_size: f64,
    /// The scene's weights over the scale-free soft terms.
    pub weights: CostWeights,
    pub min_spacing: f64,
    /// The sine of the least transmission angle allowed (margins are compared as sines).
    pub min_transmission_sine: f64,
    /// The sine of the comfortable transmission angle, E_trans's reference ([`super::terms::Term`]).
    pub comfortable_transmission_sine: f64,
    /// Penetration below this depth is contact, not collision (a length).
    pub contact_tolerance: f64,
    /// The fixed bodies and the avoid regions, prepared for the tests of moving outlines against them.
    pub fixed_obstacles: Vec<Obstacle>,
    pub avoid_obstacles: Vec<Obstacle>,
    /// Each moving body's outline in its own frame, prepared the same way: its grid tells most points
    /// deep inside the body or not at once (see [`Obstacle::penetrated_by_shape`]).
    pub body_shapes: Vec<Obstacle>,
    /// Each moving body's outline as E_acc reads it ([`Context::outline_miss`]).
    pub outlines: Vec<OutlineMoments>,
    /// Every mover–obstacle pair the collision sweep watches.
    pub(crate) collision_pairs: Vec<Pair>,
    /// The rigidity energy of this topology (paper eq. 3–5).
    pub rigidity: RigidityModel,
    /// `pose_tolerance` is 0: no pose is perturbed.
    pub unperturbed: bool,
    /// `pose_tolerance` is 0 and the linkage type can hit this many poses: only exact fits are
    /// accepted, and the particle filter's proposals are projected back onto exact linkages.
    pub exact: bool,
    /// The motion has more poses than the linkage type can hit exactly.
    pub overdetermined: bool,
    /// How the joints carried by links only are placed at a pose, in order (empty for a topology
    /// without such joints).
    pub completion: Vec<Completion>,
    /// The driver's tip when it is placed where two parts meet (a Watt-II six-bar's crank tip): its
    /// side of the two joints it is placed from changes where the link it drives turns back, and the
    /// body then retraces its way ([`Context::tip_side`]). With the two joints.
    pub turning_tip: Option<(usize, usize, usize)>,
    /// The scene's pinned joints of this topology, by index, each where it must be at the first pose:
    /// every sample, proposal and refinement keeps them there.
    pub pins: Vec<(usize, Point)>,
    /// The factor on the scene's pose noise (`pose_tolerance`, `angle_tolerance_deg`): 1, or for an
    /// over-determined motion the square of the share of its intermediate poses an exact fit could
    /// pass through. Noise on every one of many intermediate poses does not widen the set of linkages
    /// a fit finds; it pulls the fit away from every linkage, towards collapsed links. The family's own
    /// factor comes on top ([`crate::mechanism::Family::pose_noise`]).
    pub noise_scale: f64,
    /// `must_hit_motions[b]`: body b's motion to each must-hit pose (the first, the last and those the
    /// scene marks), the poses every linkage is kept rigid through (`END_DEVIATION`).
    pub must_hit_motions: Vec<Vec<Rigid>>,
}

impl<'a> Context<'a> {
    pub(crate) fn new(problem: &'a Problem, mechanism_type: MechanismType) -> Context<'a> {
        let family = mechanism_type.family();
        let topology = Arc::new(family.topology(problem.body_count()));
        let mut carriers = vec![None; topology.joint_count()];
        for part in &topology.parts {
            if let PartKind::Body(b) = part.kind {
                for &j in &part.joints {
                    carriers[j] = Some(b);
                }
            }
        }
        let moving_joints = (0..topology.joint_count()).filter(|&j| carriers[j].is_some()).collect();
        let link_pairs = topology.link_pairs();
        let fixed = topology.fixed_joints();
        let tethers = topology
            .parts
            .iter()
            .filter(|part| part.kind == PartKind::Link)
            .flat_map(|part| {
                let anchors = part.joints.iter().copied().filter(|g| fixed.contains(g));
                anchors
                    .flat_map(|g| part.joints.iter().copied().filter(|&j| carriers[j].is_some()).map(move |j| (j, g)))
            })
            .collect();
        let body_size = problem.bodies.iter().map(|b| b.size).fold(f64::INFINITY, f64::min);
        let contact_tolerance = problem.contact_tolerance();
        let obstacle = |p: &Polygon| Obstacle::new(p.vertices(), contact_tolerance);
        let collision_pairs = watched_pairs(problem, link_pairs.len());
        let motions: Vec<Vec<Rigid>> =
            problem.bodies.iter().map(|b| (0..problem.pose_count).map(|i| b.motion_from_first(i)).collect()).collect();
        let must_hit_motions = motions
            .iter()
            .map(|m| m.iter().zip(&problem.must_hit).filter(|(_, &hit)| hit).map(|(&motion, _)| motion).collect())
            .collect();
        let overdetermined = problem.pose_count > topology.max_exact_poses();
        let overdetermined_noise = if overdetermined {
            ((topology.max_exact_poses() - 2) as f64 / (problem.pose_count - 2) as f64).powi(2)
        } else {
            1.0
        };
        let noise_scale = overdetermined_noise * family.pose_noise(topology.body_count, problem.pose_count);
        let unperturbed = problem.settings.pose_tolerance == 0.0;
        // A pin of a joint this topology lacks is left out; `pipeline::families` tries no such family.
        let pins: Vec<(usize, Point)> =
            problem.pinned.iter().filter_map(|(name, p)| Some((topology.joint(name)?, *p))).collect();
        let completion = completion_order(&topology);
        Context {
            problem,
            carriers,
            moving_joints,
            tethers,
            link_pairs,
            part_pairs: topology.part_pairs(),
            motions,
            must_hit_motions,
            first_poses: problem.bodies.iter().map(|b| b.poses[0]).collect(),
            body_size,
            weights: CostWeights::new(&problem.weights, body_size),
            min_spacing: MIN_JOINT_SPACING * body_size,
            min_transmission_sine: problem.settings.min_transmission_deg.to_radians().sin(),
            comfortable_transmission_sine: problem.settings.comfortable_transmission_deg.to_radians().sin(),
            contact_tolerance,
            fixed_obstacles: problem.fixed.iter().map(obstacle).collect(),
            avoid_obstacles: problem.avoid.iter().map(obstacle).collect(),
            body_shapes: problem.bodies.iter().map(|b| obstacle(&b.outline)).collect(),
            outlines: problem
                .bodies
                .iter()
                .enumerate()
                .map(|(b, body)| OutlineMoments::new(body, topology.body_part(b).joints.clone()))
                .collect(),
            collision_pairs,
            rigidity: RigidityModel::new(&topology).with_pinned(&pins.iter().map(|&(j, _)| j).collect::<Vec<_>>()),
            pins,
            unperturbed,
            exact: unperturbed && !overdetermined,
            overdetermined,
            noise_scale,
            turning_tip: completion.iter().find_map(|step| match *step {
                Completion::Dyad { joint, a, b } if joint == topology.driver_tip => Some((joint, a, b)),
                _ => None,
            }),
            completion,
            topology,
        }
    }

    /// Puts the pinned joints at their places in parameter vector `x` (joint coordinates first).
    pub(crate) fn pin(&self, x: &mut [f64]) {
        for &(j, p) in &self.pins {
            (x[2 * j], x[2 * j + 1]) = (p.x, p.y);
        }
    }

    /// Places the joints carried by links only in `row` ([`complete`]), from `first`, the joints at
    /// the first pose.
    pub(crate) fn complete(&self, first: &[Point], row: &mut [Point]) -> Result<(), DyadError> {
        complete(&self.completion, first, row)
    }

    /// [`Context::complete`] with the turning tip on its other side: where it is once the link it
    /// drives has turned back. `Ok(false)` (and `row` untouched) when the topology has no turning tip.
    pub(crate) fn complete_turned(&self, first: &[Point], row: &mut [Point]) -> Result<bool, DyadError> {
        let Some((tip, ..)) = self.turning_tip else { return Ok(false) };
        complete_turning(&self.completion, first, row, Some(tip)).map(|()| true)
    }

    /// Whether the turning tip is in `row` on the other side than in `first` (the joints at the first
    /// pose): the link it drives has turned back. False without a turning tip.
    pub(crate) fn tip_turned(&self, first: &[Point], row: &[Point]) -> bool {
        self.turning_tip.is_some_and(|(tip, a, b)| {
            let side = |r: &[Point]| -> Branch { circle_circle_branch(r[a], r[b], r[tip]) };
            side(first) != side(row)
        })
    }

    /// This context for a run whose joints of one part must also be at least `spacing` apart (a
    /// length): the print check's pins need room, so samples closer than that are never drawn.
    pub(crate) fn spaced_at_least(self, spacing: f64) -> Self {
        Context { min_spacing: self.min_spacing.max(spacing), ..self }
    }

    /// This context with its pose noise scaled by `factor`.
    pub(crate) fn perturbed_less(self, factor: f64) -> Self {
        Context { noise_scale: self.noise_scale * factor, ..self }
    }

    /// The largest accepted rigidity deviation of a fit (relative to d).
    pub(crate) fn accepted_deviation(&self) -> f64 {
        if self.exact {
            EXACT_DEVIATION
        } else if self.overdetermined {
            OVERDETERMINED_DEVIATION
        } else {
            ACCEPT_DEVIATION
        }
    }

    /// Moves parameter vector `x` (a particle filter's proposal, say) to a nearby linkage this run may
    /// keep: one that hits every input pose when the run is exact, else one that reaches the end poses
    /// ([`Context::through_must_hit_poses`]). False when there is none nearby.
    pub(crate) fn project(&self, x: &mut [f64], fit: &mut super::rigidity::FitWorkspace) -> bool {
        if self.exact {
            let deviation = self.rigidity.fit(x, &self.motions, self.body_size, fit).max_relative_deviation;
            deviation <= EXACT_DEVIATION && !self.rigidity.mirrored(x, &self.motions, self.body_size)
        } else {
            self.through_must_hit_poses(x, fit)
        }
    }

    /// Moves parameter vector `x` to a nearby linkage that is rigid through the must-hit poses (the
    /// first, the last and those the scene marks; `END_DEVIATION`) with no ternary link turned over, so
    /// its bodies reach them; false when no such linkage is near. Two poses leave a link one equation
    /// to meet, so from a start close to rigid the fit ends close by.
    pub(crate) fn through_must_hit_poses(&self, x: &mut [f64], fit: &mut super::rigidity::FitWorkspace) -> bool {
        if self.rigidity.relative_deviation(x, &self.must_hit_motions, self.body_size) > END_DEVIATION {
            let deviation = self.rigidity.fit(x, &self.must_hit_motions, self.body_size, fit).max_relative_deviation;
            if deviation > END_DEVIATION {
                return false;
            }
        }
        !self.rigidity.mirrored(x, &self.must_hit_motions, self.body_size)
    }

    /// How far body `b`'s outline is from input pose `i` when the body is at `reached`: the miss of
    /// the outline's mean point, and the part its vertices add by turning (their spread times the
    /// chord of the turn). The squares of the three numbers sum to the mean squared miss of the
    /// outline's vertices, in closed form: a vertex at mean point c plus u misses by the mean point's
    /// miss plus the turn's (R − I)·u, the u average out, and |(R − I)·u| = 2·|sin(Δθ/2)|·|u|.
    pub(crate) fn outline_miss(&self, b: usize, i: usize, reached: &Isometry) -> [f64; 3] {
        let OutlineMoments { mean, spread, .. } = self.outlines[b];
        let wanted = self.problem.bodies[b].poses[i].isometry();
        let shift = reached.apply(mean) - wanted.apply(mean);
        // The turn between the two, as a unit vector: its chord is |(cos − 1, sin)|.
        let turn = wanted.unrotate(reached.rotate(Vec2::new(1.0, 0.0)));
        let chord = ((turn.x - 1.0).powi(2) + turn.y * turn.y).sqrt();
        [shift.x, shift.y, spread.sqrt() * chord]
    }

    /// Where joint `j`, at `p` in the first pose, should be at pose `i` (it rides on its carrier).
    pub(crate) fn target(&self, j: usize, p: Point, i: usize) -> Point {
        match self.carriers[j] {
            Some(b) => self.motions[b][i].apply(p),
            None => p,
        }
    }
}

/// What the accuracy's outline part needs of one moving body, once per scene.
#[derive(Clone, Debug)]
pub(crate) struct OutlineMoments {
    /// The mean of the outline's vertices, in the body's frame.
    pub mean: Point,
    /// The same point at the first pose, in the world.
    pub first_mean: Point,
    /// The vertices' mean squared distance from their mean.
    pub spread: f64,
    /// The joints the body carries.
    pub joints: Vec<usize>,
}

impl OutlineMoments {
    fn new(body: &crate::scene::MovingBodyProblem, joints: Vec<usize>) -> Self {
        let vertices = body.outline.vertices();
        let count = vertices.len().max(1) as f64;
        let sum = vertices.iter().fold(Vec2::new(0.0, 0.0), |s, v| s + v.to_vec2());
        let mean = Point::ORIGIN + sum * (1.0 / count);
        let spread = vertices.iter().map(|v| (*v - mean).norm_sq()).sum::<f64>() / count;
        OutlineMoments { mean, first_mean: body.poses[0].apply(mean), spread, joints }
    }
}

/// One mover against one obstacle.
#[derive(Clone, Copy, Debug)]
pub(crate) enum Pair {
    /// Link segment `link` against avoid region `avoid`.
    LinkAvoid { link: usize, avoid: usize },
    /// Moving body `body` against fixed body `fixed`.
    BodyFixed { body: usize, fixed: usize },
    /// Moving body `body` against moving body `other` (`other < body`).
    BodyBody { body: usize, other: usize },
}

/// Every pair the collision sweep watches, for a scene and `links` link segments (once per scene),
/// links first (their verdict, an avoid region, is reported first).
pub(crate) fn watched_pairs(problem: &Problem, links: usize) -> Vec<Pair> {
    let mut pairs = Vec::new();
    for link in 0..links {
        pairs.extend((0..problem.avoid.len()).map(|avoid| Pair::LinkAvoid { link, avoid }));
    }
    for body in 0..problem.bodies.len() {
        pairs.extend((0..problem.fixed.len()).map(|fixed| Pair::BodyFixed { body, fixed }));
        pairs.extend((0..body).map(|other| Pair::BodyBody { body, other }));
    }
    pairs
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::synth::testing::example;
    use crate::testbed::Known;

    /// The joints only links carry, placed from the body's and the ground's joints, are where the
    /// simulation from the crank puts them (two implementations: the completion goes from the body
    /// back to the crank, the plan from the crank to the body), along known six-bars' travels.
    #[test]
    fn completed_joints_are_where_the_simulation_puts_them() {
        for t in [MechanismType::WattTwo, MechanismType::StephensonThree] {
            completed_like_simulated(t);
        }
    }

    fn completed_like_simulated(t: MechanismType) {
        use crate::kinematics::Plan;
        use crate::testbed::known_scene;
        let known = known_scene(Known::one(t), 4, 3, 100.0).unwrap();
        let problem = Problem::new(&known.scene).unwrap();
        let ctx = Context::new(&problem, t);
        assert_eq!(ctx.completion.len(), 2);
        let first = &known.mechanism.joints;
        let plan = Plan::compile(&known.mechanism).unwrap();
        let (start, end) = (known.pose_crank[0], known.pose_crank[known.pose_crank.len() - 1]);
        let link_only = ctx.topology.link_only_joints();
        for k in 0..=20 {
            let theta = start + (end - start) * k as f64 / 20.0;
            let mut simulated = first.clone();
            plan.solve(theta, &mut simulated).unwrap();
            let mut completed = simulated.clone();
            for &j in &link_only {
                completed[j] = Point::new(f64::NAN, f64::NAN);
            }
            ctx.complete(first, &mut completed).unwrap();
            for j in 0..first.len() {
                assert!(completed[j].distance(simulated[j]) < 1e-9 * 100.0, "joint {j} at step {k}");
            }
        }
        // The first joint a dyad is placed from, pulled far away: no configuration.
        let mut apart = first.clone();
        let far = ctx.completion.iter().find_map(|s| match *s {
            crate::kinematics::Completion::Dyad { a, .. } => Some(a),
            _ => None,
        });
        let far = far.expect("a dyad");
        apart[far] = first[far] + Vec2::new(1e6, 0.0);
        assert!(ctx.complete(first, &mut apart).is_err());
    }

    /// The closed form of an outline's mean squared miss is the mean over its vertices, for any
    /// reached pose: turned either way, by up to a half turn, and shifted.
    #[test]
    fn outline_miss_is_the_mean_squared_miss_of_the_vertices() {
        let problem = example("k2_wall_bed");
        let ctx = Context::new(&problem, MechanismType::Chain);
        for (b, body) in problem.bodies.iter().enumerate() {
            for (i, wanted) in body.poses.iter().enumerate() {
                for (turn, shift) in [(0.0, (0.0, 0.0)), (0.3, (0.0, 0.0)), (-2.9, (5.0, -7.0)), (1.0, (-3.0, 2.0))] {
                    let reached = Rigid::new(wanted.angle() + turn, wanted.translation() + Vec2::new(shift.0, shift.1));
                    let closed: f64 = ctx.outline_miss(b, i, &reached.isometry()).iter().map(|m| m * m).sum();
                    let vertices = body.outline.vertices();
                    let mean = vertices.iter().map(|&v| (reached.apply(v) - wanted.apply(v)).norm_sq()).sum::<f64>()
                        / vertices.len() as f64;
                    assert!((closed - mean).abs() <= 1e-9 * (1.0 + mean), "body {b} pose {i}: {closed} vs {mean}");
                }
            }
        }
    }
}

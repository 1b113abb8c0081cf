//! Compiling a mechanism into an ordered list of dyad steps, and solving it at a crank angle.

use super::dyad::{
    circle_circle, circle_circle_branch, circle_line, circle_line_branch, transmission_sine, Branch, DyadError,
};
use crate::geom::{Point, Vec2};
use crate::mechanism::{Mechanism, PartKind, Topology};

/// One step of a plan: it places one joint from joints already placed.
#[derive(Clone, Debug, PartialEq)]
pub enum Step {
    /// The joint is at distance `ra` from `a` and `rb` from `b` (two parts meet at it).
    Dyad {
        /// The joint placed (an index into the topology's joints, as are `a` and `b`).
        joint: usize,
        /// The first centre.
        a: usize,
        /// The joint's distance from `a`.
        ra: f64,
        /// The second centre.
        b: usize,
        /// The joint's distance from `b`.
        rb: f64,
        /// Which of the two intersections, as at the first pose.
        branch: Branch,
    },
    /// The joint is at distance `r` from `centre` and on the slider line.
    Slider {
        /// The joint placed (an index into the topology's joints, as is `centre`).
        joint: usize,
        /// The joint at the other end of the rod.
        centre: usize,
        /// The rod's length.
        r: f64,
        /// A point of the slider line.
        origin: Point,
        /// The slider line's unit direction.
        direction: Vec2,
        /// Which of the two intersections, as at the first pose.
        branch: Branch,
    },
    /// The joint is carried by a part whose joints `a`, `b` are placed: it sits at `along` on the
    /// direction a→b and `across` to its left, in the part's frame.
    Attach {
        /// The joint placed (an index into the topology's joints, as are `a` and `b`).
        joint: usize,
        /// The origin of the part's frame.
        a: usize,
        /// The joint the frame's x axis points to.
        b: usize,
        /// The joint's distance along the x axis (a length).
        along: f64,
        /// The joint's distance to the left of the x axis (a length).
        across: f64,
    },
}

/// The velocity of point `p` of a rigid part whose points `at[0]`, `at[1]` (apart) move at `velocity`:
/// the part turns at ω = (b − a) × (v_b − v_a) / |b − a|², so p moves at v_a + ω·perp(p − a).
pub fn carried_velocity(at: [Point; 2], velocity: [Vec2; 2], p: Point) -> Vec2 {
    let e = at[1] - at[0];
    let omega = e.cross(velocity[1] - velocity[0]) / e.norm_sq();
    velocity[0] + (p - at[0]).perp() * omega
}

impl Step {
    /// Places this step's joint in `row`, whose earlier joints are placed.
    #[inline]
    fn solve(&self, row: &mut [Point]) -> Result<(), DyadError> {
        match *self {
            Step::Dyad { joint, a, ra, b, rb, branch } => row[joint] = circle_circle(row[a], ra, row[b], rb, branch)?,
            Step::Slider { joint, centre, r, origin, direction, branch } => {
                row[joint] = circle_line(row[centre], r, origin, direction, branch)?
            }
            Step::Attach { joint, a, b, along, across } => {
                let e = (row[b] - row[a]).normalized();
                row[joint] = row[a] + e * along + e.perp() * across;
            }
        }
        Ok(())
    }
}

/// Applies `solve` to each row of `rows` (rows of `n` points) in order, up to the first that fails:
/// that row's index and error.
#[inline]
fn first_failure(
    rows: &mut [Point],
    n: usize,
    mut solve: impl FnMut(&mut [Point]) -> Result<(), DyadError>,
) -> Option<(usize, DyadError)> {
    rows.chunks_exact_mut(n).enumerate().find_map(|(r, row)| solve(row).err().map(|e| (r, e)))
}

/// Why a mechanism cannot be compiled into a plan.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum CompileError {
    /// No solving order places this joint (named) from joints already placed.
    #[error("joint {0} cannot be placed from the others: the mechanism is not a chain of dyads")]
    NotDyadic(String),
    /// Two joints (named) that define a part's frame or a dyad are at the same point.
    #[error("joints {0} and {1} coincide, so the part or dyad through them is undefined")]
    Coincident(String, String),
    /// The crank's two joints are at the same point.
    #[error("the crank has zero length")]
    ZeroCrank,
}

/// A compiled mechanism: fixed joints, the crank, and the dyad steps in solving order.
///
/// # Examples
///
/// A four-bar ([`Topology::chain`]`(1)`) compiled at its first pose and solved at another crank angle,
/// where its coupler joint is where the loop-closure equations put it.
///
/// ```
/// use linkwright_core::geom::Point;
/// use linkwright_core::kinematics::Plan;
/// use linkwright_core::{Mechanism, Topology};
/// use std::sync::Arc;
///
/// // A crank-rocker four-bar at its first pose: ground pivots q0 = (0, 0) and r0 = (d, 0), the crank
/// // q0–p1 (length a) at 90°, the coupler p1–q1 (length b) and the rocker r0–q1 (length c).
/// let (a, b, c, d) = (1.0, 20f64.sqrt(), 3.0, 4.0);
/// let topology = Topology::chain(1);
/// let [q0, r0, p1, q1] = ["q0", "r0", "p1", "q1"].map(|name| topology.joint(name).unwrap());
/// let mut joints = vec![Point::ORIGIN; topology.joint_count()];
/// joints[q0] = Point::new(0.0, 0.0);
/// joints[r0] = Point::new(d, 0.0);
/// joints[p1] = Point::new(0.0, a);
/// joints[q1] = Point::new(d, c);
/// let mechanism = Mechanism { topology: Arc::new(topology), joints, slider: None };
/// let plan = Plan::compile(&mechanism)?;
///
/// let theta = 2.0; // radians
/// let mut row = vec![Point::ORIGIN; plan.joint_count()];
/// plan.solve(theta, &mut row).expect("a crank-rocker assembles at every crank angle");
/// assert!(row[p1].distance(Point::new(a * f64::cos(theta), a * f64::sin(theta))) < 1e-15);
///
/// // Loop closure a·e^(iθ) + b·e^(iβ) = d + c·e^(iφ). Eliminating the coupler's angle β leaves
/// // A·cos φ + B·sin φ + C = 0 for the rocker's angle φ; the + root is the circuit of the first pose.
/// let big_a = 2.0 * c * (d - a * theta.cos());
/// let big_b = -2.0 * a * c * theta.sin();
/// let big_c = a * a - b * b + c * c + d * d - 2.0 * a * d * theta.cos();
/// let phi = big_b.atan2(big_a) + (-big_c / big_a.hypot(big_b)).acos();
/// assert!(row[q1].distance(Point::new(d + c * phi.cos(), c * phi.sin())) < 1e-12);
/// # Ok::<(), linkwright_core::kinematics::CompileError>(())
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct Plan {
    joint_count: usize,
    fixed: Vec<(usize, Point)>,
    pivot: usize,
    tip: usize,
    crank_radius: f64,
    steps: Vec<Step>,
}

impl Plan {
    /// Compiles `mechanism` at its first pose: lengths, part frames and branches are read from there.
    pub fn compile(mechanism: &Mechanism) -> Result<Plan, CompileError> {
        Plan::order(&mechanism.topology)?.redimension(mechanism)
    }

    /// The solving order of `topology`, undimensioned (every length 0, every fixed joint at the
    /// origin): what [`Plan::redimension`] dimensions. Rigid placements first (a part with two placed
    /// joints places the rest), then one dyad at a time: an unplaced joint where two parts, each
    /// with a placed joint, meet, or the slider joint on its line.
    fn order(topo: &Topology) -> Result<Plan, CompileError> {
        let n = topo.joint_count();
        let mut known = vec![false; n];
        let fixed_joints = topo.fixed_joints();
        for &j in fixed_joints {
            known[j] = true;
        }
        let (pivot, tip) = (topo.driver_pivot, topo.driver_tip);
        known[tip] = true;
        let mut steps = Vec::new();
        while known.iter().any(|k| !k) {
            let before = steps.len();
            for part in topo.parts.iter().filter(|p| p.kind != PartKind::Fixed) {
                let placed: Vec<usize> = part.joints.iter().copied().filter(|&j| known[j]).collect();
                if placed.len() < 2 || placed.len() == part.joints.len() {
                    continue;
                }
                let (a, b) = (placed[0], placed[1]);
                for &joint in &part.joints {
                    if !known[joint] {
                        steps.push(Step::Attach { joint, a, b, along: 0.0, across: 0.0 });
                        known[joint] = true;
                    }
                }
            }
            if steps.len() > before {
                continue;
            }
            for joint in (0..n).filter(|&j| !known[j]) {
                let anchors: Vec<usize> = topo
                    .parts
                    .iter()
                    .filter(|p| p.joints.contains(&joint))
                    .filter_map(|p| p.joints.iter().copied().find(|&x| known[x]))
                    .collect();
                let step = match anchors[..] {
                    [a, b, ..] => Step::Dyad { joint, a, ra: 0.0, b, rb: 0.0, branch: Branch::Positive },
                    [centre] if topo.slider_joint == Some(joint) => Step::Slider {
                        joint,
                        centre,
                        r: 0.0,
                        origin: Point::ORIGIN,
                        direction: Vec2::new(1.0, 0.0),
                        branch: Branch::Positive,
                    },
                    _ => continue,
                };
                steps.push(step);
                known[joint] = true;
                break;
            }
            if steps.len() == before {
                let j = (0..n).find(|&j| !known[j]).expect("some joint is unplaced");
                return Err(CompileError::NotDyadic(topo.joint_names[j].clone()));
            }
        }
        let fixed = fixed_joints.iter().map(|&j| (j, Point::ORIGIN)).collect();
        Ok(Plan { joint_count: n, fixed, pivot, tip, crank_radius: 0.0, steps })
    }

    /// The dyads of `topology`'s solving order, each as `[a, b, joint]`: `joint` is placed from `a`
    /// and `b`, and the sign of `(b − a) × (joint − a)` is its branch, which a motion without a
    /// branch or circuit defect keeps. Empty when the topology has no solving order.
    pub fn dyad_triangles(topology: &Topology) -> Vec<[usize; 3]> {
        let steps = Plan::order(topology).map(|plan| plan.steps).unwrap_or_default();
        steps
            .into_iter()
            .filter_map(|s| match s {
                Step::Dyad { joint, a, b, .. } => Some([a, b, joint]),
                _ => None,
            })
            .collect()
    }

    /// This plan's solving order for another mechanism of the same topology: the order depends on the
    /// topology alone, so only lengths, part frames and branches are read again (cheaper than
    /// [`Plan::compile`], which searches for the order first).
    pub fn redimension(&self, mechanism: &Mechanism) -> Result<Plan, CompileError> {
        let mut plan = Plan { fixed: Vec::new(), steps: Vec::new(), ..*self };
        self.redimension_into(mechanism, &mut plan)?;
        Ok(plan)
    }

    /// [`Plan::redimension`] into `out`, reusing its buffers (the sampler redimensions one plan per
    /// sample). On an error `out` is left partly written.
    pub fn redimension_into(&self, mechanism: &Mechanism, out: &mut Plan) -> Result<(), CompileError> {
        let pos = &mechanism.joints;
        let name = |j: usize| mechanism.topology.joint_names[j].clone();
        let apart = |a: usize, b: usize| {
            if pos[a].distance(pos[b]) > 0.0 {
                Ok(())
            } else {
                Err(CompileError::Coincident(name(a), name(b)))
            }
        };
        let crank_radius = pos[self.pivot].distance(pos[self.tip]);
        if crank_radius <= 0.0 {
            return Err(CompileError::ZeroCrank);
        }
        out.steps.clear();
        for step in &self.steps {
            out.steps.push(match *step {
                Step::Dyad { joint, a, b, .. } => {
                    apart(a, b)?;
                    Step::Dyad {
                        joint,
                        a,
                        ra: pos[a].distance(pos[joint]),
                        b,
                        rb: pos[b].distance(pos[joint]),
                        branch: circle_circle_branch(pos[a], pos[b], pos[joint]),
                    }
                }
                Step::Slider { joint, centre, .. } => {
                    let line = mechanism.slider.ok_or_else(|| CompileError::NotDyadic(name(joint)))?;
                    Step::Slider {
                        joint,
                        centre,
                        r: pos[centre].distance(pos[joint]),
                        origin: line.point,
                        direction: line.direction,
                        branch: circle_line_branch(pos[centre], line.point, line.direction, pos[joint]),
                    }
                }
                Step::Attach { joint, a, b, .. } => {
                    apart(a, b)?;
                    let e = (pos[b] - pos[a]).normalized();
                    let v = pos[joint] - pos[a];
                    Step::Attach { joint, a, b, along: v.dot(e), across: e.cross(v) }
                }
            });
        }
        out.fixed.clear();
        out.fixed.extend(self.fixed.iter().map(|&(j, _)| (j, pos[j])));
        (out.joint_count, out.pivot, out.tip, out.crank_radius) =
            (self.joint_count, self.pivot, self.tip, crank_radius);
        Ok(())
    }

    /// Number of joints a configuration of the mechanism has (the length of a row).
    pub fn joint_count(&self) -> usize {
        self.joint_count
    }
    /// The steps that place the moving joints after the crank's tip, in solving order.
    pub fn steps(&self) -> &[Step] {
        &self.steps
    }

    /// Places every joint with the crank at `theta` (radians). `out` must hold `joint_count` points.
    pub fn solve(&self, theta: f64, out: &mut [Point]) -> Result<(), (usize, DyadError)> {
        self.solve_towards(Vec2::from_angle(theta), out)
    }

    /// [`Plan::solve`] with the crank along the unit vector `crank` (its angle's cosine and sine).
    pub fn solve_towards(&self, crank: Vec2, out: &mut [Point]) -> Result<(), (usize, DyadError)> {
        self.place_crank(crank, out);
        for (i, step) in self.steps.iter().enumerate() {
            step.solve(out).map_err(|e| (i, e))?;
        }
        Ok(())
    }

    /// Every joint's velocity per radian of crank, `d(position)/dθ`, at configuration `row` (solved at
    /// crank angle `theta`): the exact derivative of each step's solution, in solving order. A dyad's
    /// joint keeps its distances to both centres, so its velocity solves the 2 × 2 system
    /// `(p − a)·(ṗ − ȧ) = 0`, `(p − b)·(ṗ − ḃ) = 0`; a slider joint moves along its line and keeps its
    /// distance to the rod's other end; an attached joint turns with its part. `None` at a dead point,
    /// where the system is singular (the crank cannot drive the linkage there).
    pub fn velocities(&self, theta: f64, row: &[Point], out: &mut [Vec2]) -> Option<()> {
        for &(j, _) in &self.fixed {
            out[j] = Vec2::ZERO;
        }
        out[self.tip] = Vec2::from_angle(theta).perp() * self.crank_radius;
        for step in &self.steps {
            match *step {
                Step::Dyad { joint, a, b, .. } => {
                    let (u, v) = (row[joint] - row[a], row[joint] - row[b]);
                    let det = u.cross(v);
                    if det.abs() <= 1e-12 * u.norm() * v.norm() {
                        return None;
                    }
                    let (ra, rb) = (u.dot(out[a]), v.dot(out[b]));
                    // Cramer's rule on [uᵀ; vᵀ]·ṗ = (ra, rb).
                    out[joint] = Vec2::new(ra * v.y - rb * u.y, u.x * rb - v.x * ra) / det;
                }
                Step::Slider { joint, centre, direction, .. } => {
                    let w = row[joint] - row[centre];
                    let along = w.dot(direction);
                    if along.abs() <= 1e-12 * w.norm() {
                        return None;
                    }
                    out[joint] = direction * (w.dot(out[centre]) / along);
                }
                Step::Attach { joint, a, b, .. } => {
                    out[joint] = carried_velocity([row[a], row[b]], [out[a], out[b]], row[joint]);
                }
            }
        }
        Some(())
    }

    /// Puts the fixed joints and the crank's tip (the crank along the unit vector `crank`) in `out`, a
    /// row of `joint_count` points: what [`Plan::solve_rows`] starts from.
    pub fn place_crank(&self, crank: Vec2, out: &mut [Point]) {
        for &(j, p) in &self.fixed {
            out[j] = p;
        }
        out[self.tip] = out[self.pivot] + crank * self.crank_radius;
    }

    /// Solves every row of `rows` (rows of `joint_count` points, each with its crank placed by
    /// [`Plan::place_crank`]), step after step across all rows: the arithmetic of
    /// [`Plan::solve_towards`], so the same points, without matching every step anew for every row:
    /// the simulation's sweeps are most of its rows, and solving them so takes 3–5% fewer instructions
    /// than row by row over a whole synthesis of the folding table, sofa bed and bulldozer
    /// (`valgrind --tool=callgrind linkwright design SCENE --threads 1 --no-print-check` on their
    /// examples, each scene's `"mechanism"` as in Table 1 of docs/performance.md). On failure, the
    /// first row that cannot assemble, in row order, with the step and the reason
    /// [`Plan::solve_towards`] gives; the rows before it are solved.
    pub fn solve_rows(&self, rows: &mut [Point]) -> Result<(), (usize, usize, DyadError)> {
        let n = self.joint_count;
        for (i, step) in self.steps.iter().enumerate() {
            // Matched once per step, so that the loop over rows is a straight line: `step.solve` in
            // the loop, matching per row, costs 1.2–1.7% more of a synthesis' instructions (the
            // callgrind runs above).
            let failed = match *step {
                Step::Dyad { joint, a, ra, b, rb, branch } => first_failure(rows, n, |row| {
                    row[joint] = circle_circle(row[a], ra, row[b], rb, branch)?;
                    Ok(())
                }),
                Step::Slider { joint, centre, r, origin, direction, branch } => first_failure(rows, n, |row| {
                    row[joint] = circle_line(row[centre], r, origin, direction, branch)?;
                    Ok(())
                }),
                Step::Attach { .. } => first_failure(rows, n, |row| step.solve(row)),
            };
            if let Some((last, cause)) = failed {
                // A row before this one may fail at a later step: those finish row by row, in order.
                for (r, row) in rows.chunks_exact_mut(n).take(last).enumerate() {
                    for (k, later) in self.steps.iter().enumerate().skip(i + 1) {
                        later.solve(row).map_err(|e| (r, k, e))?;
                    }
                }
                return Err((last, i, cause));
            }
        }
        Ok(())
    }

    /// For a plan with a single dyad after the crank (a four-bar or a slider-crank), in closed form:
    /// whether it assembles at every crank angle from `from` to `to` (radians), and if so the least
    /// [`Plan::min_transmission_sine`] along the way. `None` for other plans.
    ///
    /// The dyad's one varying quantity is a sinusoid of the crank angle: the squared distance between
    /// its two centres for a circle-circle dyad, the distance of its centre from the guide for a
    /// slider. Assembly and transmission only get worse as it moves away from its middle value, so its
    /// extremes over the travel (at the ends or where the sinusoid peaks) decide both exactly, between
    /// the 1° rows a sweep would test too.
    pub fn closed_form_travel(&self, from: f64, to: f64) -> Option<Result<f64, DyadError>> {
        let mut dyads = self.steps.iter().filter(|s| !matches!(s, Step::Attach { .. }));
        let (Some(dyad), None) = (dyads.next(), dyads.next()) else { return None };
        let pivot = self.fixed.iter().find(|&&(j, _)| j == self.pivot)?.1;
        // A joint the dyad reads: the crank tip (pivot + R·(cos θ, sin θ)) or a fixed joint.
        let fixed_at = |j: usize| self.fixed.iter().find(|&&(f, _)| f == j).map(|&(_, p)| p);
        let (lo, hi) = (from.min(to), from.max(to));
        match *dyad {
            Step::Dyad { a, ra, b, rb, .. } => {
                // s(θ) = |a − b|² = |w + R·u(θ)|², with w from the fixed end to the pivot (or constant).
                let (w, radius) = match (a == self.tip, b == self.tip) {
                    (true, false) => (pivot - fixed_at(b)?, self.crank_radius),
                    (false, true) => (pivot - fixed_at(a)?, self.crank_radius),
                    (false, false) => (fixed_at(a)? - fixed_at(b)?, 0.0),
                    (true, true) => return None,
                };
                let mean = w.norm_sq() + radius * radius;
                let (s_min, s_max) = sinusoid_range(mean, 2.0 * radius * w.norm(), w.angle(), lo, hi);
                if s_min <= 1e-300 {
                    return Some(Err(DyadError::CoincidentCentres));
                }
                if s_min < (ra - rb) * (ra - rb) || s_max > (ra + rb) * (ra + rb) {
                    return Some(Err(DyadError::CirclesApart));
                }
                // Law of cosines at the joint: cos μ = (ra² + rb² − s) / (2·ra·rb), monotone in s.
                let sine = |s: f64| {
                    let cos = ((ra * ra + rb * rb - s) / (2.0 * ra * rb)).clamp(-1.0, 1.0);
                    (1.0 - cos * cos).sqrt()
                };
                Some(Ok(sine(s_min).min(sine(s_max))))
            }
            Step::Slider { centre, r, origin, direction, .. } => {
                // h(θ) = direction × (centre − origin): the centre's signed distance from the guide.
                let (offset, radius) = if centre == self.tip {
                    (direction.cross(pivot - origin), self.crank_radius)
                } else {
                    (direction.cross(fixed_at(centre)? - origin), 0.0)
                };
                // direction × u(θ) = sin(θ − ψ) = cos(θ − ψ − π/2).
                let phase = direction.angle() + std::f64::consts::FRAC_PI_2;
                let (h_min, h_max) = sinusoid_range(offset, radius, phase, lo, hi);
                let h = h_min.abs().max(h_max.abs());
                if h > r {
                    return Some(Err(DyadError::LineOutOfReach));
                }
                // The rod's angle from the guide's normal has sine √(r² − h²) / r.
                Some(Ok((r * r - h * h).max(0.0).sqrt() / r))
            }
            Step::Attach { .. } => None,
        }
    }

    /// The smallest transmission-angle margin (radians from 0 and π) over every dyad of a solved
    /// configuration. For a slider dyad the angle is between the rod and the normal of the guide.
    ///
    /// # Examples
    ///
    /// The four-bar of [`Plan`]'s example at its first pose: the transmission angle μ between its
    /// coupler and rocker follows from the law of cosines in the triangle p1 q1 r0, whose side p1–r0
    /// is √17.
    ///
    /// ```
    /// # use linkwright_core::geom::Point;
    /// # use linkwright_core::kinematics::Plan;
    /// # use linkwright_core::{Mechanism, Topology};
    /// # use std::sync::Arc;
    /// #
    /// # let (a, b, c, d) = (1.0, 20f64.sqrt(), 3.0, 4.0);
    /// # let topology = Topology::chain(1);
    /// # let [q0, r0, p1, q1] = ["q0", "r0", "p1", "q1"].map(|name| topology.joint(name).unwrap());
    /// # let mut joints = vec![Point::ORIGIN; topology.joint_count()];
    /// # joints[q0] = Point::new(0.0, 0.0);
    /// # joints[r0] = Point::new(d, 0.0);
    /// # joints[p1] = Point::new(0.0, a);
    /// # joints[q1] = Point::new(d, c);
    /// # let mechanism = Mechanism { topology: Arc::new(topology), joints, slider: None };
    /// # let plan = Plan::compile(&mechanism)?;
    /// let cos_mu = (b * b + c * c - 17.0) / (2.0 * b * c); // 1/√5: μ is about 63.4°, its own margin
    /// assert!((plan.min_transmission(&mechanism.joints) - cos_mu.acos()).abs() < 1e-12);
    /// assert!((plan.min_transmission_sine(&mechanism.joints) - 2.0 / 5f64.sqrt()).abs() < 1e-15);
    /// # Ok::<(), linkwright_core::kinematics::CompileError>(())
    /// ```
    pub fn min_transmission(&self, pos: &[Point]) -> f64 {
        self.min_transmission_sine(pos).asin()
    }

    /// The sine of [`Plan::min_transmission`] (cheaper, and ordered alike).
    pub fn min_transmission_sine(&self, pos: &[Point]) -> f64 {
        let mut m: f64 = 1.0;
        for step in &self.steps {
            match *step {
                Step::Dyad { joint, a, b, .. } => {
                    m = m.min(transmission_sine(pos[a] - pos[joint], pos[b] - pos[joint]))
                }
                Step::Slider { joint, centre, direction, .. } => {
                    m = m.min(transmission_sine(pos[centre] - pos[joint], direction.perp()))
                }
                Step::Attach { .. } => {}
            }
        }
        m
    }

    /// The branch every dyad of a configuration is on, in step order (attach steps are skipped).
    /// A configuration is on the plan's circuit when these equal the plan's own branches.
    pub fn branches_of(&self, pos: &[Point], out: &mut Vec<Branch>) {
        out.clear();
        for step in &self.steps {
            match *step {
                Step::Dyad { joint, a, b, .. } => out.push(circle_circle_branch(pos[a], pos[b], pos[joint])),
                Step::Slider { joint, centre, origin, direction, .. } => {
                    out.push(circle_line_branch(pos[centre], origin, direction, pos[joint]))
                }
                Step::Attach { .. } => {}
            }
        }
    }

    /// The plan's own branches, in the order of [`Plan::branches_of`].
    pub fn branches(&self) -> Vec<Branch> {
        self.own_branches().collect()
    }

    /// [`Plan::branches`] without collecting them.
    pub fn own_branches(&self) -> impl Iterator<Item = Branch> + '_ {
        self.steps.iter().filter_map(|s| match *s {
            Step::Dyad { branch, .. } | Step::Slider { branch, .. } => Some(branch),
            Step::Attach { .. } => None,
        })
    }
}

/// The least and greatest of `mean + amplitude·cos(θ − phase)` for θ in `[lo, hi]`: at the ends, or at a
/// peak or trough inside.
fn sinusoid_range(mean: f64, amplitude: f64, phase: f64, lo: f64, hi: f64) -> (f64, f64) {
    let value = |theta: f64| mean + amplitude * (theta - phase).cos();
    if (hi - lo).is_nan() || hi - lo >= 2.0 * std::f64::consts::TAU {
        // A travel this long (or not a number) passes every value.
        return (mean - amplitude.abs(), mean + amplitude.abs());
    }
    let (a, b) = (value(lo), value(hi));
    let (mut min, mut max) = (a.min(b), a.max(b));
    // Peaks at phase + 2kπ, troughs at phase + (2k + 1)π.
    let mut k = ((lo - phase) / std::f64::consts::PI).ceil();
    loop {
        let theta = phase + k * std::f64::consts::PI;
        if theta >= hi {
            break;
        }
        if theta > lo {
            let extreme = if k.rem_euclid(2.0) == 0.0 { mean + amplitude } else { mean - amplitude };
            min = min.min(extreme);
            max = max.max(extreme);
        }
        k += 1.0;
    }
    (min, max)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mechanism::{SliderLine, Topology};
    use proptest::prelude::*;
    use std::sync::Arc;

    fn mechanism(topology: &Arc<Topology>, coords: &[f64], slider_angle: f64) -> Mechanism {
        let joints: Vec<Point> =
            coords.chunks(2).take(topology.joint_count()).map(|c| Point::new(c[0], c[1])).collect();
        let slider =
            topology.slider_joint.map(|j| SliderLine { point: joints[j], direction: Vec2::from_angle(slider_angle) });
        Mechanism { topology: topology.clone(), joints, slider }
    }

    proptest! {
        /// Redimensioning a plan compiled for one mechanism gives exactly the plan compiled afresh for
        /// another of the same topology.
        #[test]
        fn redimension_equals_compile(k in 0usize..4, first in prop::collection::vec(-5.0..5.0f64, 20),
                                      second in prop::collection::vec(-5.0..5.0f64, 20), angle in -3.2..3.2f64) {
            let topology = Arc::new(if k == 0 { Topology::slider_crank() } else { Topology::chain(k) });
            let template = Plan::compile(&mechanism(&topology, &first, 0.3)).expect("random joints are distinct");
            let other = mechanism(&topology, &second, angle);
            prop_assert_eq!(template.redimension(&other), Plan::compile(&other));
        }

        /// The velocities are the derivative of the solution: they match central differences of
        /// `solve` (step 1e-6 rad) on random linkages of every kind, away from dead points.
        #[test]
        fn velocities_are_the_derivative_of_the_solution(k in 0usize..4, coords in prop::collection::vec(-5.0..5.0f64, 20),
                                                          theta in -3.2..3.2f64) {
            let topology = Arc::new(if k == 0 { Topology::slider_crank() } else { Topology::chain(k) });
            let plan = Plan::compile(&mechanism(&topology, &coords, 0.7)).expect("random joints are distinct");
            let n = plan.joint_count();
            let h = 1e-6;
            let (mut row, mut ahead, mut behind) = (vec![Point::ORIGIN; n], vec![Point::ORIGIN; n], vec![Point::ORIGIN; n]);
            let solved = plan.solve(theta, &mut row).is_ok()
                && plan.solve(theta + h, &mut ahead).is_ok()
                && plan.solve(theta - h, &mut behind).is_ok();
            let mut velocity = vec![Vec2::ZERO; n];
            if solved && plan.velocities(theta, &row, &mut velocity).is_some() {
                let scale = coords.iter().fold(1.0f64, |m, c| m.max(c.abs()));
                for j in 0..n {
                    let difference = (ahead[j] - behind[j]) / (2.0 * h);
                    let speed = velocity[j].norm().max(difference.norm());
                    // Near a dead point the velocity grows without bound and differences lose digits.
                    prop_assume!(speed < 1e3 * scale);
                    prop_assert!((velocity[j] - difference).norm() <= 1e-4 * (scale + speed),
                                 "joint {}: {:?} against {:?}", j, velocity[j], difference);
                }
            }
        }

        /// Solving rows step by step gives the points of solving them one by one, bit for bit, and
        /// the first row (in order) that fails, at the step and for the reason the row gives, with the
        /// rows before it solved. Random linkages fail at many rows and steps.
        #[test]
        fn rows_solve_as_one_by_one(k in 0usize..4, coords in prop::collection::vec(-5.0..5.0f64, 20),
                                    angles in prop::collection::vec(-7.0..7.0f64, 1..40)) {
            let topology = Arc::new(if k == 0 { Topology::slider_crank() } else { Topology::chain(k) });
            let plan = Plan::compile(&mechanism(&topology, &coords, 0.7)).expect("random joints are distinct");
            let n = plan.joint_count();
            let mut rows = vec![Point::ORIGIN; angles.len() * n];
            for (row, &theta) in rows.chunks_exact_mut(n).zip(&angles) {
                plan.place_crank(Vec2::from_angle(theta), row);
            }
            let together = plan.solve_rows(&mut rows);
            let mut one = vec![Point::ORIGIN; n];
            let mut first_failure = None;
            for (r, &theta) in angles.iter().enumerate() {
                match plan.solve(theta, &mut one) {
                    Ok(()) => prop_assert_eq!(&rows[r * n..(r + 1) * n], &one[..]),
                    Err((step, cause)) => {
                        first_failure = Some((r, step, cause));
                        break;
                    }
                }
            }
            prop_assert_eq!(together, first_failure.map_or(Ok(()), Err));
        }
    }
}

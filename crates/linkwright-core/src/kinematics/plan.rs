//! Compiling a mechanism into an ordered list of dyad steps, and solving it at a crank angle.

use super::dyad::{
    circle_circle, circle_circle_branch, circle_line, circle_line_branch, transmission_sine, Branch, DyadError,
};
use crate::geom::{Point, Vec2};
use crate::mechanism::{Mechanism, PartKind};

/// One step of a plan: it places one joint from joints already placed.
#[derive(Clone, Debug, PartialEq)]
pub enum Step {
    /// The joint is at distance `ra` from `a` and `rb` from `b` (two parts meet at it).
    Dyad { joint: usize, a: usize, ra: f64, b: usize, rb: f64, branch: Branch },
    /// The joint is at distance `r` from `centre` and on the slider line.
    Slider { joint: usize, centre: usize, r: f64, origin: Point, direction: Vec2, branch: Branch },
    /// The joint is carried by a part whose joints `a`, `b` are placed: it sits at `along` on the
    /// direction a→b and `across` to its left, in the part's frame.
    Attach { joint: usize, a: usize, b: usize, along: f64, across: f64 },
}

/// Why a mechanism cannot be compiled into a plan.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum CompileError {
    #[error("joint {0} cannot be placed from the others: the mechanism is not a chain of dyads")]
    NotDyadic(String),
    #[error("joints {0} and {1} coincide, so the part or dyad through them is undefined")]
    Coincident(String, String),
    #[error("the crank has zero length")]
    ZeroCrank,
}

/// A compiled mechanism: fixed joints, the crank, and the dyad steps in solving order.
#[derive(Clone, Debug)]
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
        let topo = &mechanism.topology;
        let pos = &mechanism.joints;
        let name = |j: usize| topo.joint_names[j].clone();
        let n = topo.joint_count();
        let mut known = vec![false; n];
        let fixed_joints = topo.fixed_joints();
        let fixed: Vec<(usize, Point)> = fixed_joints.iter().map(|&j| (j, pos[j])).collect();
        for &j in fixed_joints {
            known[j] = true;
        }
        let (pivot, tip) = (topo.driver_pivot, topo.driver_tip);
        let crank_radius = pos[pivot].distance(pos[tip]);
        if crank_radius <= 0.0 {
            return Err(CompileError::ZeroCrank);
        }
        known[tip] = true;
        let mut steps = Vec::new();
        while known.iter().any(|k| !k) {
            let before = steps.len();
            // Rigid placement first: a part with two placed joints places the rest.
            for part in topo.parts.iter().filter(|p| p.kind != PartKind::Fixed) {
                let placed: Vec<usize> = part.joints.iter().copied().filter(|&j| known[j]).collect();
                if placed.len() < 2 || placed.len() == part.joints.len() {
                    continue;
                }
                let (a, b) = (placed[0], placed[1]);
                let ab = pos[b] - pos[a];
                if ab.norm() <= 0.0 {
                    return Err(CompileError::Coincident(name(a), name(b)));
                }
                let e = ab.normalized();
                let unplaced: Vec<usize> = part.joints.iter().copied().filter(|&j| !known[j]).collect();
                for j in unplaced {
                    let v = pos[j] - pos[a];
                    steps.push(Step::Attach { joint: j, a, b, along: v.dot(e), across: e.cross(v) });
                    known[j] = true;
                }
            }
            if steps.len() > before {
                continue;
            }
            // Then one dyad: an unplaced joint where two parts, each with a placed joint, meet.
            for j in (0..n).filter(|&j| !known[j]) {
                let anchors: Vec<usize> = topo
                    .parts
                    .iter()
                    .filter(|p| p.joints.contains(&j))
                    .filter_map(|p| p.joints.iter().copied().find(|&x| known[x]))
                    .collect();
                if anchors.len() >= 2 {
                    let (a, b) = (anchors[0], anchors[1]);
                    if pos[a].distance(pos[b]) <= 0.0 {
                        return Err(CompileError::Coincident(name(a), name(b)));
                    }
                    let branch = circle_circle_branch(pos[a], pos[b], pos[j]);
                    steps.push(Step::Dyad {
                        joint: j,
                        a,
                        ra: pos[a].distance(pos[j]),
                        b,
                        rb: pos[b].distance(pos[j]),
                        branch,
                    });
                    known[j] = true;
                    break;
                }
                if let (Some(line), [centre]) =
                    (mechanism.slider.filter(|_| topo.slider_joint == Some(j)), anchors.as_slice())
                {
                    let branch = circle_line_branch(pos[*centre], line.point, line.direction, pos[j]);
                    steps.push(Step::Slider {
                        joint: j,
                        centre: *centre,
                        r: pos[*centre].distance(pos[j]),
                        origin: line.point,
                        direction: line.direction,
                        branch,
                    });
                    known[j] = true;
                    break;
                }
            }
            if steps.len() == before {
                let j = (0..n).find(|&j| !known[j]).expect("some joint is unplaced");
                return Err(CompileError::NotDyadic(name(j)));
            }
        }
        Ok(Plan { joint_count: n, fixed, pivot, tip, crank_radius, steps })
    }

    pub fn joint_count(&self) -> usize {
        self.joint_count
    }
    pub fn steps(&self) -> &[Step] {
        &self.steps
    }
    /// Number of steps that have a transmission angle (dyads and slider dyads).
    pub fn dyad_count(&self) -> usize {
        self.steps.iter().filter(|s| !matches!(s, Step::Attach { .. })).count()
    }

    /// Places every joint with the crank at `theta` (radians). `out` must hold `joint_count` points.
    pub fn solve(&self, theta: f64, out: &mut [Point]) -> Result<(), (usize, DyadError)> {
        self.solve_towards(Vec2::from_angle(theta), out)
    }

    /// [`Plan::solve`] with the crank along the unit vector `crank` (its angle's cosine and sine).
    pub fn solve_towards(&self, crank: Vec2, out: &mut [Point]) -> Result<(), (usize, DyadError)> {
        for &(j, p) in &self.fixed {
            out[j] = p;
        }
        out[self.tip] = out[self.pivot] + crank * self.crank_radius;
        for (i, step) in self.steps.iter().enumerate() {
            match *step {
                Step::Dyad { joint, a, ra, b, rb, branch } => {
                    out[joint] = circle_circle(out[a], ra, out[b], rb, branch).map_err(|e| (i, e))?;
                }
                Step::Slider { joint, centre, r, origin, direction, branch } => {
                    out[joint] = circle_line(out[centre], r, origin, direction, branch).map_err(|e| (i, e))?;
                }
                Step::Attach { joint, a, b, along, across } => {
                    let e = (out[b] - out[a]).normalized();
                    out[joint] = out[a] + e * along + e.perp() * across;
                }
            }
        }
        Ok(())
    }

    /// The smallest transmission-angle margin (radians from 0 and π) over every dyad of a solved
    /// configuration. For a slider dyad the angle is between the rod and the normal of the guide.
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
        self.steps
            .iter()
            .filter_map(|s| match *s {
                Step::Dyad { branch, .. } | Step::Slider { branch, .. } => Some(branch),
                Step::Attach { .. } => None,
            })
            .collect()
    }
}

//! A motion sampled along the crank's travel, and the moving bodies' poses along it.

use super::plan::Plan;
use super::DyadError;
use crate::geom::{Point, Rigid, Vec2};
use crate::mechanism::Mechanism;

/// Why a sweep stopped.
#[derive(Clone, Copy, Debug, PartialEq, thiserror::Error)]
#[error("the linkage cannot assemble at crank angle {theta_deg:.2}° (step {step}: {cause})")]
pub struct SweepError {
    pub theta_deg: f64,
    pub step: usize,
    pub cause: DyadError,
}

/// Joint positions at a sequence of crank angles along one travel.
#[derive(Clone, Debug, Default)]
pub struct Trace {
    /// Crank angles, radians, unwrapped, in travel order.
    pub thetas: Vec<f64>,
    /// `thetas.len() × joint_count` positions, one row per angle.
    pub positions: Vec<Point>,
    pub joint_count: usize,
}

impl Trace {
    /// An empty trace for mechanisms with `joint_count` joints.
    pub fn new(joint_count: usize) -> Trace {
        Trace { joint_count, ..Trace::default() }
    }

    /// Sweeps the crank from `from` to `to` (radians) in equal steps of at most `max_step`, keeping the
    /// plan's branches. Reuses `self`'s buffers.
    pub fn sweep(&mut self, plan: &Plan, from: f64, to: f64, max_step: f64) -> Result<(), SweepError> {
        let n = plan.joint_count();
        self.clear(n);
        let steps = (((to - from).abs() / max_step).ceil() as usize).max(1);
        self.positions.resize((steps + 1) * n, Point::ORIGIN);
        // The crank's direction turns by one fixed rotation per step; it is recomputed from its angle
        // every few steps so rounding cannot build up.
        let turn = Rigid::new((to - from) / steps as f64, Vec2::ZERO);
        let mut crank = Vec2::ZERO;
        for (s, row) in self.positions.chunks_exact_mut(n).enumerate() {
            let theta = from + (to - from) * (s as f64 / steps as f64);
            crank = if s % 32 == 0 { Vec2::from_angle(theta) } else { turn.rotate(crank) };
            plan.place_crank(crank, row);
            self.thetas.push(theta);
        }
        plan.solve_rows(&mut self.positions).map_err(|(row, step, cause)| {
            let theta_deg = self.thetas[row].to_degrees();
            self.thetas.truncate(row);
            self.positions.truncate(row * n);
            SweepError { theta_deg, step, cause }
        })
    }

    /// Empties the trace, keeping its buffers.
    pub fn clear(&mut self, joint_count: usize) {
        self.joint_count = joint_count;
        self.thetas.clear();
        self.positions.clear();
    }

    /// Solves the plan at `theta` and appends the configuration; on failure the trace is unchanged.
    pub fn push(&mut self, plan: &Plan, theta: f64) -> Result<(), SweepError> {
        let n = self.joint_count;
        let start = self.positions.len();
        self.positions.resize(start + n, Point::ORIGIN);
        if let Err((step, cause)) = plan.solve(theta, &mut self.positions[start..]) {
            self.positions.truncate(start);
            return Err(SweepError { theta_deg: theta.to_degrees(), step, cause });
        }
        self.thetas.push(theta);
        Ok(())
    }

    /// Appends rows `rows` of `other` (same mechanism).
    pub fn extend_rows_of(&mut self, other: &Trace, rows: std::ops::Range<usize>) {
        let n = self.joint_count;
        self.positions.extend_from_slice(&other.positions[rows.start * n..rows.end * n]);
        self.thetas.extend_from_slice(&other.thetas[rows]);
    }

    pub fn len(&self) -> usize {
        self.thetas.len()
    }
    pub fn is_empty(&self) -> bool {
        self.thetas.is_empty()
    }
    /// The joints at sample `s`.
    pub fn row(&self, s: usize) -> &[Point] {
        &self.positions[s * self.joint_count..(s + 1) * self.joint_count]
    }
    /// The smallest transmission margin of `plan` (this trace's mechanism) along the whole trace,
    /// radians. Computed on demand: the engine judges most travels without it (see
    /// [`Plan::closed_form_travel`]).
    pub fn min_transmission(&self, plan: &Plan) -> f64 {
        self.min_transmission_sine(plan).asin()
    }
    /// The sine of [`Trace::min_transmission`] (cheaper, and ordered alike).
    pub fn min_transmission_sine(&self, plan: &Plan) -> f64 {
        (0..self.len()).map(|r| plan.min_transmission_sine(self.row(r))).fold(1.0, f64::min)
    }
}

/// How to recover each moving body's pose from the positions of two joints it carries.
#[derive(Clone, Debug)]
pub struct BodyFrames {
    /// Per body: the two joints that fix its frame, and the map from body coordinates to the frame
    /// those joints span (read at the first pose).
    frames: Vec<(usize, usize, Rigid)>,
}

impl BodyFrames {
    /// `first_poses[b]` is body b's `body_to_world` at the first pose.
    pub fn new(mechanism: &Mechanism, first_poses: &[Rigid]) -> BodyFrames {
        let topo = &mechanism.topology;
        let frames = (0..topo.body_count)
            .map(|b| {
                let part = topo.body_part(b);
                let (a, c) = (part.joints[0], part.joints[1]);
                let joints_frame = Rigid::from_frame(mechanism.joints[a], mechanism.joints[c] - mechanism.joints[a]);
                (a, c, first_poses[b].then(&joints_frame.inverse()))
            })
            .collect();
        BodyFrames { frames }
    }
    /// Body `b`'s `body_to_world` in the configuration `row`.
    pub fn pose(&self, b: usize, row: &[Point]) -> Rigid {
        let (a, c, body_to_frame) = &self.frames[b];
        body_to_frame.then(&Rigid::from_frame(row[*a], row[*c] - row[*a]))
    }
    pub fn body_count(&self) -> usize {
        self.frames.len()
    }
    /// Body `b`'s frame joints (the origin, then the joint its x axis points to) and its map from
    /// body coordinates to that frame: [`BodyFrames::pose`] is that map, then the frame the two
    /// joints span in a configuration.
    pub fn frame(&self, b: usize) -> (usize, usize, &Rigid) {
        let (a, c, body_to_frame) = &self.frames[b];
        (*a, *c, body_to_frame)
    }
}

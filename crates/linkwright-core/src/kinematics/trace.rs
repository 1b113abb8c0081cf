//! A motion sampled along the crank's travel, and the moving bodies' poses along it.

use super::plan::Plan;
use super::DyadError;
use crate::geom::{Point, Rigid};
use crate::mechanism::Mechanism;

/// Why a sweep stopped.
#[derive(Clone, Copy, Debug, PartialEq, thiserror::Error)]
#[error("the linkage cannot assemble at crank angle {theta_deg:.2}° (step {step}: {cause})")]
pub struct SweepError {
    pub theta_deg: f64,
    pub step: usize,
    pub cause: DyadError,
}

/// Joint positions at crank angles spaced evenly from a start to an end angle.
#[derive(Clone, Debug, Default)]
pub struct Trace {
    /// Crank angles, radians, unwrapped, from start to end.
    pub thetas: Vec<f64>,
    /// `thetas.len() × joint_count` positions, one row per angle.
    pub positions: Vec<Point>,
    pub joint_count: usize,
    /// The smallest transmission margin along the trace, radians.
    pub min_transmission: f64,
}

impl Trace {
    /// Sweeps the crank from `from` to `to` (radians) in equal steps of at most `max_step`, keeping the
    /// plan's branches. Reuses `self`'s buffers.
    pub fn sweep(&mut self, plan: &Plan, from: f64, to: f64, max_step: f64) -> Result<(), SweepError> {
        let n = plan.joint_count();
        let steps = (((to - from).abs() / max_step).ceil() as usize).max(1);
        self.joint_count = n;
        self.thetas.clear();
        self.positions.clear();
        self.positions.resize((steps + 1) * n, Point::ORIGIN);
        self.min_transmission = std::f64::consts::FRAC_PI_2;
        for s in 0..=steps {
            let theta = from + (to - from) * (s as f64 / steps as f64);
            let row = &mut self.positions[s * n..(s + 1) * n];
            plan.solve(theta, row).map_err(|(step, cause)| SweepError {
                theta_deg: theta.to_degrees(),
                step,
                cause,
            })?;
            self.min_transmission = self.min_transmission.min(plan.min_transmission(row));
            self.thetas.push(theta);
        }
        Ok(())
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
}

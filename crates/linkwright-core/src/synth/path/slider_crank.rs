//! The slider-crank as a path generator, in closed form: the crank turns, the body's second joint
//! runs on a fixed line, and the tracer rides on the body.

use super::four_bar::log_uniform;
use super::linkage::{on_body, random_branch, PathLinkage, Similarity, TracerAt};
use crate::geom::{Point, Vec2};
use crate::kinematics::{circle_line, transmission_sine, Branch};
use crate::mechanism::{Mechanism, SliderLine, Topology};
use crate::scene::MechanismType;
use rand::RngExt;
use rand_xoshiro::Xoshiro256PlusPlus;
use std::sync::Arc;

/// The slider-crank as a path generator: the crank `q0 p1` turns, the body's joint `q1` runs on a
/// fixed line, and the tracer rides on the body at `(u, v)` in its frame (origin `p1`, x towards
/// `q1`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct SliderCrank {
    pub crank_pivot: Point,
    pub crank: f64,
    /// |p1 q1|.
    pub coupler: f64,
    /// A point of the slider's line, and its direction (radians).
    pub line_point: Point,
    pub line_angle: f64,
    pub u: f64,
    pub v: f64,
    /// Which way along the line from the crank tip's foot `q1` is.
    pub branch: Branch,
}

impl SliderCrank {
    fn joints_at(&self, theta: f64) -> Option<(Point, Point, f64)> {
        let p1 = self.crank_pivot + Vec2::from_angle(theta) * self.crank;
        let direction = Vec2::from_angle(self.line_angle);
        let q1 = circle_line(p1, self.coupler, self.line_point, direction, self.branch).ok()?;
        Some((p1, q1, transmission_sine(p1 - q1, direction.perp())))
    }
}

impl PathLinkage for SliderCrank {
    const FAMILY: MechanismType = MechanismType::SliderCrank;
    const STREAM: u64 = 0x7061_7468_0001;

    fn tracer_at(&self, theta: f64) -> Option<TracerAt> {
        let (p1, q1, transmission_sine) = self.joints_at(theta)?;
        Some(TracerAt { point: on_body(p1, q1, self.coupler, self.u, self.v), heading: q1 - p1, transmission_sine })
    }

    /// A crank of 1 about the origin, a line `offset` from it along x, and a coupler longer than
    /// the offset and the crank together (so the crank turns fully).
    fn sample(r: &mut Xoshiro256PlusPlus) -> Option<SliderCrank> {
        let offset: f64 = r.random_range(-2.0..2.0);
        let coupler = (offset.abs() + 1.0) * log_uniform(r, 1.05, 4.0);
        Some(SliderCrank {
            crank_pivot: Point::ORIGIN,
            crank: 1.0,
            coupler,
            line_point: Point::new(0.0, offset),
            line_angle: 0.0,
            u: coupler * r.random_range(-1.0..2.0),
            v: coupler * r.random_range(-1.5..1.5),
            branch: random_branch(r),
        })
    }

    fn mapped(&self, map: &Similarity) -> SliderCrank {
        let s = map.scale;
        SliderCrank {
            crank_pivot: map.point(self.crank_pivot),
            crank: self.crank * s,
            coupler: self.coupler * s,
            line_point: map.point(self.line_point),
            line_angle: self.line_angle + map.turn,
            u: self.u * s,
            v: self.v * s,
            branch: self.branch,
        }
    }

    fn params(&self) -> Vec<f64> {
        vec![
            self.crank_pivot.x,
            self.crank_pivot.y,
            self.crank,
            self.coupler,
            self.line_point.x,
            self.line_point.y,
            self.line_angle,
            self.u,
            self.v,
        ]
    }

    fn with_params(&self, x: &[f64]) -> SliderCrank {
        SliderCrank {
            crank_pivot: Point::new(x[0], x[1]),
            crank: x[2],
            coupler: x[3],
            line_point: Point::new(x[4], x[5]),
            line_angle: x[6],
            u: x[7],
            v: x[8],
            branch: self.branch,
        }
    }

    fn is_angle(k: usize) -> bool {
        k == 6
    }

    fn mechanism(&self, theta: f64) -> Option<Mechanism> {
        let (p1, q1, _) = self.joints_at(theta)?;
        let topology = Arc::new(Topology::slider_crank());
        let joints = topology
            .joint_names
            .iter()
            .map(|n| match n.as_str() {
                "q0" => self.crank_pivot,
                "p1" => p1,
                _ => q1,
            })
            .collect();
        let slider = SliderLine { point: q1, direction: Vec2::from_angle(self.line_angle) };
        Some(Mechanism { topology, joints, slider: Some(slider) })
    }
}

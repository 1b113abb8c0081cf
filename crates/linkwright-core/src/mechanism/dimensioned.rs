//! A dimensioned linkage: a topology and every joint's position at the first pose.

use super::topology::Topology;
use crate::geom::{Point, Vec2};
use std::sync::Arc;

/// The fixed line a slider joint runs on.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SliderLine {
    /// A point of the line: the slider joint's position at the first pose.
    pub point: Point,
    /// Unit direction of the line.
    pub direction: Vec2,
}

/// A dimensioned mechanism: a topology and every joint's position at the first pose.
#[derive(Clone, Debug, PartialEq)]
pub struct Mechanism {
    /// The structure: joints, parts and driver.
    pub topology: Arc<Topology>,
    /// Position of each joint at the first pose, indexed like `topology.joint_names`.
    pub joints: Vec<Point>,
    /// The line the slider joint runs on (the slider-crank only).
    pub slider: Option<SliderLine>,
}

impl Mechanism {
    /// The position at the first pose of the joint called `name`.
    pub fn joint(&self, name: &str) -> Option<Point> {
        self.topology.joint(name).map(|j| self.joints[j])
    }
    /// The driver's angle at the first pose (radians, atan2 of tip − pivot).
    pub fn crank_start(&self) -> f64 {
        (self.joints[self.topology.driver_tip] - self.joints[self.topology.driver_pivot]).angle()
    }
    /// The largest distance of a joint from where it is in `earlier` (both at the first pose); `None`
    /// when `earlier` is of another family, so that no joint of one corresponds to a joint of the other.
    pub fn farthest_move_from(&self, earlier: &Mechanism) -> Option<f64> {
        if self.topology.mechanism_type != earlier.topology.mechanism_type {
            return None;
        }
        let names = &self.topology.joint_names;
        let mut each = names.iter().zip(&self.joints).map(|(name, p)| earlier.joint(name).map(|q| p.distance(q)));
        each.try_fold(0.0, |far: f64, d| d.map(|d| far.max(d)))
    }
}

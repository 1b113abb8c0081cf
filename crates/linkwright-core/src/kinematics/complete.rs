//! Where the joints that only links carry are at a configuration whose other joints are given (the
//! ground's, and the moving bodies' at a pose): the synthesis knows the bodies' poses, not the crank
//! angle, so it places such joints from the bodies back towards the crank.

use super::dyad::{circle_circle, circle_circle_branch, DyadError};
use crate::geom::{Point, Vec2};
use crate::mechanism::{Part, Topology};

/// How a joint carried by links only is placed at a pose from joints placed before it
/// ([`complete`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Completion {
    /// On a part that also holds the placed joints `a` and `b`: carried with them.
    Attach {
        /// The joint placed.
        joint: usize,
        /// Two placed joints of its part.
        a: usize,
        /// See `a`.
        b: usize,
    },
    /// Where two parts meet, one holding the placed joint `a`, the other `b`.
    Dyad {
        /// The joint placed.
        joint: usize,
        /// A placed joint of one of its parts.
        a: usize,
        /// A placed joint of another of its parts.
        b: usize,
    },
}

/// Places the joints carried by links only in `row`, a configuration whose other joints are
/// placed, in the order `completion` ([`completion_order`]), as the parts carry them from `first`
/// (the joints at the first pose): each keeps its distances to the joints it is placed from, on its
/// first-pose side of them. `Err` when two circles do not meet there: the linkage cannot assemble in
/// that configuration.
pub fn complete(completion: &[Completion], first: &[Point], row: &mut [Point]) -> Result<(), DyadError> {
    complete_turning(completion, first, row, None)
}

/// [`complete`], with the joint `turned` (when placed where two parts meet) on the other side of the
/// joints it is placed from: where a crank's tip is, once the link it drives has turned back.
pub fn complete_turning(
    completion: &[Completion],
    first: &[Point],
    row: &mut [Point],
    turned: Option<usize>,
) -> Result<(), DyadError> {
    for &step in completion {
        match step {
            Completion::Attach { joint, a, b } => {
                let (u, w) = (first[b] - first[a], row[b] - row[a]);
                let scale = u.norm() * w.norm();
                if scale <= 0.0 {
                    return Err(DyadError::CoincidentCentres);
                }
                let (cos, sin) = (u.dot(w) / scale, u.cross(w) / scale);
                let v = first[joint] - first[a];
                row[joint] = row[a] + Vec2::new(cos * v.x - sin * v.y, sin * v.x + cos * v.y);
            }
            Completion::Dyad { joint, a, b } => {
                let mut branch = circle_circle_branch(first[a], first[b], first[joint]);
                if turned == Some(joint) {
                    branch = branch.other();
                }
                let (ra, rb) = (first[joint].distance(first[a]), first[joint].distance(first[b]));
                row[joint] = circle_circle(row[a], ra, row[b], rb, branch)?;
            }
        }
    }
    Ok(())
}

/// The order in which [`complete`] places `topology`'s joints carried by links only: a
/// joint on a part holding two placed joints first, else one where two parts holding placed joints
/// meet. A joint that neither rule reaches is left out (no family builds one).
pub fn completion_order(topology: &Topology) -> Vec<Completion> {
    let link_only = topology.link_only_joints();
    let mut placed: Vec<bool> = (0..topology.joint_count()).map(|j| !link_only.contains(&j)).collect();
    let mut order = Vec::new();
    loop {
        let next = link_only.iter().copied().filter(|&j| !placed[j]).find_map(|joint| {
            let parts = || topology.parts.iter().filter(move |p| p.joints.contains(&joint));
            let placed_on =
                |part: &Part| -> Vec<usize> { part.joints.iter().copied().filter(|&k| placed[k]).collect() };
            if let Some(on) = parts().map(placed_on).find(|on| on.len() >= 2) {
                return Some(Completion::Attach { joint, a: on[0], b: on[1] });
            }
            let anchors: Vec<usize> = parts().filter_map(|p| placed_on(p).first().copied()).collect();
            (anchors.len() >= 2).then(|| Completion::Dyad { joint, a: anchors[0], b: anchors[1] })
        });
        let Some(step) = next else { return order };
        let (Completion::Attach { joint, .. } | Completion::Dyad { joint, .. }) = step;
        placed[joint] = true;
        order.push(step);
    }
}

//! Pictures a person can open: a design as SVG text, static ([`design_svg`]) or animated
//! ([`animation_svg`]). No I/O: callers write the strings where they like.
//!
//! Both pictures are in world coordinates with y up (a `scale(1,-1)` group; text is placed outside
//! it, so it stays upright), fitted to everything drawn with a margin and a title band on top. Every
//! stroke width, radius and font size is a fraction of the problem's `scale`, so a scene drawn in
//! millimetres, metres or inches looks the same. Numbers are written to about 10⁻⁴ of the scale, names
//! are XML-escaped, and the output depends only on the input (no clock, no hash order).
//!
//! Input poses are numbered from 1 in the pictures, as a person counts them (pose 1 is the first pose).

mod animation;
mod design;
mod layers;
mod sheet;
mod style;
mod svg;

#[cfg(test)]
mod tests;

pub use animation::animation_svg;
pub use design::design_svg;

use crate::kinematics::Trace;
use crate::mechanism::Mechanism;
use crate::scene::Problem;

/// What a picture shows: a scene, the linkage designed for it and its motion.
#[derive(Clone, Copy, Debug)]
pub struct RenderInput<'a> {
    /// The scene the linkage was designed for.
    pub problem: &'a Problem,
    /// The linkage, its joints at the first pose.
    pub mechanism: &'a Mechanism,
    /// The motion, from the first pose to the last (an empty trace draws the linkage standing still).
    pub trace: &'a Trace,
    /// For each input pose, the index of the trace row the design offers for it (the row closest to
    /// the pose's crank angle). Indices past the end of the trace are ignored.
    pub pose_steps: &'a [usize],
}

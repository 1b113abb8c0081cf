//! What fabricating one design makes: [`Fabrication`], the parts with everything they were built
//! from (the layout, the recorded constraints, the ordering, the motion), and the seconds each stage
//! took.

use super::depth::{Face, Ordering, Recorded};
use super::layout::{Layout, SpringEnds};
use super::parts::{Part, PinSeat};
use super::plates::Misfit;
use super::settings::{Dims, PrintSettings};
use crate::kinematics::Trace;

/// Seconds spent in each stage.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize)]
pub struct Timings {
    /// Connectors and recording the constraints along the motion.
    pub recording: f64,
    /// The constraint solver (all its calls).
    pub ordering: f64,
    /// Building every part's mesh.
    pub meshing: f64,
}

/// Everything fabricated for one design.
#[derive(Clone, Debug)]
pub struct Fabrication {
    /// The scene's name.
    pub scene_name: String,
    /// The mechanism's joint names, by index.
    pub joint_names: Vec<String>,
    /// The print settings, millimetres.
    pub settings: PrintSettings,
    /// The print settings in scene units.
    pub dims: Dims,
    /// The model's scale: the parts are the drawing at this scale.
    pub scale: crate::scene::Ratio,
    /// The model's extent, width and height in millimetres: everything drawn at the model's scale.
    pub model_mm: [f64; 2],
    /// The counterbalance springs hooked, as asked for (their hooks are in the layout).
    pub springs: Vec<SpringEnds>,
    /// The printed members and what carries each.
    pub layout: Layout,
    /// The ordering constraints recorded along the motion.
    pub recorded: Recorded,
    /// Every member's face and layer.
    pub ordering: Ordering,
    /// Every printed part, with its meshes.
    pub parts: Vec<Part>,
    /// Every pin and the holes it sits in, for checking.
    pub seats: Vec<PinSeat>,
    /// The motion at crank steps of at most 1°, from the first pose to the last.
    pub trace: Trace,
    /// Seconds spent in each stage.
    pub timings: Timings,
}

impl Fabrication {
    /// The members (links, connectors, the guide, the frame) that fit the print bed in no turn, with
    /// what it would take.
    pub fn off_bed(&self) -> Vec<(usize, Misfit)> {
        self.layout.off_bed(&self.settings.bed)
    }

    /// How far spring `n`'s axis lies beyond the face it hangs on, scene units ([`Dims::spring_axis`]).
    pub fn spring_axis(&self, n: usize) -> f64 {
        let (face, level) = (self.ordering.spring_face[n], self.ordering.spring_level[n]);
        self.dims.spring_axis(self.ordering.layers_on(face), level)
    }

    /// The height of spring `n`'s axis in the parts' frame (z = 0 the bodies' front face), scene units.
    pub fn spring_axis_z(&self, n: usize) -> f64 {
        match self.ordering.spring_face[n] {
            Face::Front => self.spring_axis(n),
            Face::Back => -self.dims.body_thickness - self.spring_axis(n),
        }
    }
}

//! The fast printability test the synthesis runs on its candidates ([`FeasibilityCheck`]).

use super::depth;
use super::error::FabError;
use super::layout::Layout;
use super::posts::SceneShapes;
use super::settings::{Bed, Dims, Faces, PrintSettings};
use super::travel::{motion_trace, Travel};
use crate::kinematics::Trace;
use crate::mechanism::Mechanism;
use crate::scene::{Problem, Ratio};

/// A reusable printability check for one scene (paper §7.2: candidates without an ordering are
/// rejected). Build it once per problem and model scale; [`FeasibilityCheck::check`] then simulates
/// the motion at the steps fabrication takes, places the connectors (testing candidate post places
/// against the links' sweep, and pads against the other bodies on bodies too thin for a post), checks
/// that every link, connector, guide and frame fits the print bed, records the constraints over the
/// rows (about `rows × members²` distances between cores of at most three points) and asks the solver
/// for any ordering, with pins fused to bodies and then with connectors everywhere. A candidate costs
/// 0.2–2 ms, ten to a hundred times its collision sweep (`cargo bench -p linkwright-core --bench
/// kernels`, `printability_check` against `collision_sweep`), so run it after the collision check
/// (see `docs/fabrication.md`).
#[derive(Clone, Debug)]
pub struct FeasibilityCheck {
    shapes: SceneShapes,
    faces: Faces,
    bed: Bed,
}

impl crate::synth::Acceptance for FeasibilityCheck {
    fn min_joint_spacing(&self) -> f64 {
        FeasibilityCheck::min_joint_spacing(self)
    }
    fn accepts(&self, mechanism: &Mechanism, trace: &Trace) -> bool {
        self.check(mechanism, trace)
    }
}

impl FeasibilityCheck {
    /// The check with the given settings for a model at `scale` of the drawing (in the scene's units),
    /// as [`fabricate`](super::pipeline::fabricate) makes it.
    pub fn new(problem: &Problem, settings: &PrintSettings, scale: Ratio) -> FeasibilityCheck {
        let mm_per_unit = problem.units.model_millimetres(scale);
        FeasibilityCheck {
            shapes: SceneShapes::new(problem, Dims::new(settings, mm_per_unit)),
            faces: settings.faces,
            bed: settings.bed.clone(),
        }
    }
    /// The least distance between two joints of one link, in scene units (pins need room).
    pub fn min_joint_spacing(&self) -> f64 {
        self.shapes.dims.min_joint_spacing()
    }
    /// True when `mechanism`, moving from the first to the last crank angle of `trace` (as
    /// [`crate::synth::Candidate::trace`]), has connectors that fit, members that fit the bed and a
    /// depth ordering; what it accepts, [`fabricate`](super::pipeline::fabricate) over that travel
    /// builds with every member on the bed (it may refuse a design whose ordering the solver does not
    /// find within its step budget, `depth::FEASIBILITY_STEPS`).
    pub fn check(&self, mechanism: &Mechanism, trace: &Trace) -> bool {
        self.diagnose(mechanism, trace).is_ok()
    }
    /// [`FeasibilityCheck::check`] with the reason when it fails (the first strategy's reason: pins
    /// fused to the bodies where they fit). The motion is simulated again from the trace's first to its
    /// last crank angle at the steps [`fabricate`](super::pipeline::fabricate) takes ([`motion_trace`]),
    /// so the constraints are recorded at the very rows fabrication records them (a grazing contact
    /// between two rows of one sampling can show in the other's), and what the check accepts
    /// fabricates.
    pub fn diagnose(&self, mechanism: &Mechanism, trace: &Trace) -> Result<(), FabError> {
        let (Some(&start), Some(&end)) = (trace.thetas.first(), trace.thetas.last()) else {
            return Err(FabError::Motion("the trace is empty".into()));
        };
        let trace = &motion_trace(mechanism, Travel { start, end })?;
        // Both faces allowed is a relaxation of one face, so it alone decides feasibility for `auto`.
        let faces = if self.faces == Faces::One { Faces::One } else { Faces::Both };
        let mut first = None;
        for body_pins in [true, false] {
            let (error, pinned) = match Layout::new(&self.shapes, mechanism, trace, body_pins, &[]) {
                Err(e) => (e, true),
                Ok(layout) => {
                    let misfits = layout.off_bed(&self.bed);
                    let pinned = layout.body_pins.iter().any(Option::is_some);
                    if !misfits.is_empty() {
                        (layout.off_bed_error(&misfits, &self.bed), pinned)
                    } else if depth::feasible(&layout, &depth::record(&layout, trace), faces, depth::FEASIBILITY_STEPS)
                    {
                        return Ok(());
                    } else {
                        (FabError::NoOrdering, pinned)
                    }
                }
            };
            first.get_or_insert(error);
            // With no pin fused to a body, the layout without them is the same one.
            if !pinned {
                break;
            }
        }
        Err(first.unwrap_or(FabError::NoOrdering))
    }
}

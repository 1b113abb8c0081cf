//! The synthesis's innermost kernels, one call each, so they can be timed on their own
//! (`benches/kernels.rs`) or profiled. Nothing here is needed to use the engine: [`crate::synthesize`]
//! runs every one of them on each candidate it judges.
//!
//! The kernels read the synthesis's per-problem data and reuse its buffers exactly as the synthesis
//! does; [`Kernels`] holds both, so a kernel's cost here is its cost inside a run.

use crate::mechanism::{Mechanism, MechanismType};
use crate::scene::Problem;
use crate::synth::rigidity::FitWorkspace;
use crate::synth::{check_collisions, evaluate, Candidate, Context, Reject, Scratch, SweepBuffers};

pub use crate::synth::rigidity::Fit;

/// The synthesis's data for one problem and one mechanism family, with the buffers its kernels reuse
/// from call to call.
pub struct Kernels<'a> {
    context: Context<'a>,
    fit: FitWorkspace,
    scratch: Scratch,
    sweep: SweepBuffers,
}

impl<'a> Kernels<'a> {
    /// Prepares what the synthesis prepares once per family before sampling: the topology of `family`
    /// for `problem`'s bodies, the bodies' motions between their poses, the rigidity model and the
    /// obstacles.
    pub fn new(problem: &'a Problem, family: MechanismType) -> Kernels<'a> {
        Kernels {
            context: Context::new(problem, family),
            fit: FitWorkspace::default(),
            scratch: Scratch::default(),
            sweep: SweepBuffers::default(),
        }
    }

    /// The body size d: the smallest moving body's size, a length in scene units, the scale of every
    /// tolerance of the synthesis.
    pub fn body_size(&self) -> f64 {
        self.context.body_size
    }

    /// One fit of the rigidity energy (paper eq. 3–5) to the input poses, from `x` (updated in place):
    /// `x` holds `x, y` of every joint at the first pose in the topology's order, then for the
    /// slider-crank the slider line's angle. The sampler runs one per sample.
    pub fn rigidity_fit(&mut self, x: &mut [f64]) -> Fit {
        let ctx = &self.context;
        ctx.rigidity.fit(x, &ctx.motions, ctx.body_size, &mut self.fit)
    }

    /// The kinematic checks of `mechanism` (joint spacing, branch, order, the simulation of its travel
    /// at 1° steps, transmission angles) and its soft costs, against the input poses and with no cost
    /// bound: what every candidate passes through before the collision sweep.
    pub fn defect_check(&mut self, mechanism: Mechanism) -> Result<Candidate, Reject> {
        evaluate(&self.context, mechanism, None, f64::INFINITY, &mut self.scratch)
    }

    /// The collision sweep of `candidate`'s whole travel: moving bodies against the fixed bodies and
    /// each other, links against the avoid regions.
    pub fn collision_sweep(&mut self, candidate: &Candidate) -> Result<(), Reject> {
        check_collisions(&self.context, candidate, &mut self.sweep)
    }
}

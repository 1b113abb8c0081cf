//! Synthesis (paper §4–6): sampling rigid linkages through perturbed poses, rejecting defects and
//! collisions, refining with a particle filter, and the pipeline that ties them together.

mod collision;
mod construct;
mod context;
mod evaluate;
mod path;
mod perturb;
mod pfo;
mod pipeline;
pub(crate) mod random;
mod refine;
pub(crate) mod rigidity;
mod sample;
mod scratch_pool;
mod terms;
mod workspace;

pub(crate) use collision::{check_collisions, SweepBuffers};
pub(crate) use context::Context;
pub(crate) use evaluate::{evaluate, Scratch};
pub use evaluate::{Candidate, Reject};
pub use pipeline::{
    assess, synthesize, synthesize_with, Acceptance, Cancelled, Observer, Options, Outcome, Progress, RunStats, Silent,
    Stage, Start, FOLLOW_COST_SLACK, SCREENING_DIVISOR, SWITCH_COST_FACTOR, WARM_SAMPLES,
};
pub(crate) use terms::CostWeights;
pub use terms::{transmission_shortfall, SoftTerms, Term};

/// Fixtures shared by the synthesis unit tests.
#[cfg(test)]
pub(crate) mod testing {
    use super::evaluate::{evaluate, Candidate, Scratch};
    use super::sample::{SampleScratch, Sampler};
    use super::Context;
    use crate::scene::{Problem, Scene};

    /// A bundled example scene, as a problem.
    pub(crate) fn example(name: &str) -> Problem {
        let path = format!("{}/../../examples/{name}.json", env!("CARGO_MANIFEST_DIR"));
        Problem::new(&Scene::from_json(&std::fs::read_to_string(path).unwrap()).unwrap()).unwrap()
    }

    /// Every bundled example scene that asks for poses (a path scene's one pose is no motion to fit
    /// through), by name, as a problem.
    pub(crate) fn pose_examples() -> impl Iterator<Item = (String, Problem)> {
        let dir = format!("{}/../../examples", env!("CARGO_MANIFEST_DIR"));
        let mut names: Vec<String> = std::fs::read_dir(dir)
            .unwrap()
            .map(|e| e.unwrap().path().file_stem().unwrap().to_string_lossy().into_owned())
            .collect();
        names.sort();
        names.into_iter().map(|name| (name.clone(), example(&name))).filter(|(_, p)| p.path().is_none())
    }

    /// The defect-free candidates among samples `samples` under `seed`, in sample order.
    pub(crate) fn defect_free<'a>(
        ctx: &'a Context,
        sampler: &'a Sampler,
        seed: u64,
        samples: std::ops::Range<u64>,
    ) -> impl Iterator<Item = Candidate> + 'a {
        let (mut sample_scratch, mut scratch) = (SampleScratch::default(), Scratch::default());
        samples.filter_map(move |i| {
            let m = sampler.sample(seed, i, None, &mut sample_scratch)?;
            evaluate(ctx, m, Some(sample_scratch.motions()), f64::INFINITY, &mut scratch).ok()
        })
    }
}

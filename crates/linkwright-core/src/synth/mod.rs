//! Synthesis (paper §4–6): sampling rigid linkages through perturbed poses, rejecting defects and
//! collisions, refining with a particle filter, and the pipeline that ties them together.

mod collision;
mod construct;
mod context;
mod evaluate;
mod perturb;
mod pfo;
mod pipeline;
mod random;
pub mod rigidity;
mod sample;

pub use collision::check_collisions;
pub use context::Context;
pub use evaluate::{evaluate, Candidate, Reject, Scratch, SoftTerms};
pub use pfo::FilterOptions;
pub use pipeline::{
    families, synthesize, synthesize_with, Cancelled, Observer, Options, Outcome, Progress, RunStats, Silent, Stage,
    Start, WARM_SAMPLES,
};

/// Fixtures shared by the synthesis unit tests.
#[cfg(test)]
pub(crate) mod testing {
    use crate::scene::{Problem, Scene};

    /// A bundled example scene, as a problem.
    pub fn example(name: &str) -> Problem {
        let path = format!("{}/../../examples/{name}.json", env!("CARGO_MANIFEST_DIR"));
        Problem::new(&Scene::from_json(&std::fs::read_to_string(path).unwrap()).unwrap()).unwrap()
    }
}

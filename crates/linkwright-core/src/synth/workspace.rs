//! The buffers of a run, kept from task to task in pools ([`ScratchPool`]): what the sampler draws
//! into, and what judging a candidate (its evaluation and its collision sweep) works in. The problem's
//! context holds none of them, so it stays the same for every worker.

use super::collision::SweepBuffers;
use super::evaluate::Scratch;
use super::sample::SampleScratch;
use super::scratch_pool::ScratchPool;

/// One worker's buffers for judging candidates.
#[derive(Debug, Default)]
pub(crate) struct Buffers {
    pub evaluation: Scratch,
    pub sweep: SweepBuffers,
}

/// The buffer pools of one run.
#[derive(Debug, Default)]
pub(crate) struct Workspace {
    pub judging: ScratchPool<Buffers>,
    pub sampling: ScratchPool<SampleScratch>,
}

//! What the engine drops, counted so that no loss is silent: [`Dropped`] for the caller, and
//! the stream's own counts behind it ([`Lost`]).

/// What the engine had to drop since the last [`super::Engine::prepare`], counted so that no
/// loss is silent. Every count but `breaths` and `unanalysed_samples` stays 0 unless an
/// internal bound is wrong (debug builds assert it); `breaths` grows when a caller lets more
/// than 64 finished breaths pile up without [`super::Engine::take_breaths`],
/// `unanalysed_samples` when a stream runs past a replayed analysis
/// ([`super::Engine::replay_analysis`]).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Dropped {
    /// Feature frames completed in one block beyond the block's frame buffer.
    pub frames: u64,
    /// Phrase events beyond three reported at one frame.
    pub phrase_events: u64,
    /// Control frames, breath actions and breathing-cycle actions pushed out of full queues.
    pub scheduled: u64,
    /// Finished breaths pushed out before [`super::Engine::take_breaths`] collected them.
    pub breaths: u64,
    /// Breaths heard in the input pushed out before [`super::Engine::take_existing_breaths`]
    /// collected them.
    pub existing_breaths: u64,
    /// Blocks the analysis refused (it is prepared for every block `process` hands it).
    pub analysis_blocks: u64,
    /// Samples fed past the end of a replayed analysis ([`super::Engine::replay_analysis`]): they
    /// were not analysed (the input was longer than the learning pass heard).
    pub unanalysed_samples: u64,
}

impl Dropped {
    /// True when nothing was dropped.
    pub fn is_none(&self) -> bool {
        *self == Self::default()
    }
}

/// Losses [`Dropped`] reports besides the queues' own counts (kept from `prepare` on, through
/// `reset`).
#[derive(Debug, Clone, Copy, Default)]
pub(super) struct Lost {
    pub(super) frames: u64,
    pub(super) phrase_events: u64,
    pub(super) analysis_blocks: u64,
    pub(super) unanalysed_samples: u64,
}

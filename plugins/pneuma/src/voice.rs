//! The breath voice on the audio thread: the freeze switch (`freeze_breath_voice`) and the saved
//! voice (`breath_voice`, [`SavedVoice`]) applied to the running engine, and what the editor
//! shows ([`VoiceShown`]).
//!
//! At the start of every block ([`VoiceFreeze::follow`], after a new engine was swapped in):
//! - freeze on, nothing saved: the engine's voice is frozen
//!   ([`Engine::freeze_voice`]: the voice learned so far, or the built-in one when nothing was
//!   learned) and written to the saved voice;
//! - freeze on, a voice saved (frozen earlier, or restored with a project or preset): the engine
//!   draws its breaths from it ([`BreathVoiceMode::Fixed`], or the built-in voice);
//! - freeze off: the engine goes back to the voice it was built with (learning as the audio
//!   goes, or the breath-like file's voice), learning afresh, and the saved voice is cleared.
//!
//! The switch is read every block (an atomic load); the saved voice is read only after a
//! restore (counted lock-free by [`SavedVoice::restores`]) and written with a try-lock: a busy
//! lock is tried again at the next block, so the audio thread never waits, and never allocates.

use std::sync::atomic::{AtomicU64, Ordering};

use pneuma_core::engine::{BreathVoiceMode, Engine, VoiceStatus};
use pneuma_core::settings::placement::BREATH_LEVEL_DB;

use crate::params::breath_voice::{FrozenVoice, SavedVoice, Stored};
use crate::params::PneumaParams;

/// The audio thread's side of the freeze (see the module docs).
#[derive(Debug, Default)]
pub struct VoiceFreeze {
    /// Restores of the saved voice already taken in.
    seen_restores: u64,
    /// The saved voice as this side knows it (read after a restore, or written by it).
    saved: Option<FrozenVoice>,
    /// A value the saved voice still has to take (its lock was busy).
    unwritten: Option<Option<FrozenVoice>>,
    /// The engine may not follow the switch and the saved voice yet (a new engine, a restore).
    stale: bool,
    /// The switch as last applied.
    frozen: bool,
}

impl VoiceFreeze {
    /// A new engine runs: its voice is set at the next [`VoiceFreeze::follow`].
    pub fn engine_changed(&mut self) {
        self.stale = true;
    }

    /// Audio thread, start of a block: applies the switch and the saved voice to `engine`
    /// (built with the voice mode `built`) and writes a voice it froze. Never allocates, locks
    /// or waits.
    pub fn follow(
        &mut self,
        engine: Option<&mut Engine>,
        built: &BreathVoiceMode,
        saved: &SavedVoice,
        freeze: bool,
    ) {
        let restores = saved.restores();
        if restores != self.seen_restores {
            // A state was restored: take its voice (when the lock is free).
            match saved.try_get() {
                Ok(v) => {
                    self.seen_restores = restores;
                    self.saved = v;
                    self.unwritten = None;
                    self.stale = true;
                }
                Err(_) => return,
            }
        }
        if freeze != self.frozen {
            self.stale = true;
        }
        if self.stale {
            if let Some(engine) = engine {
                self.apply(engine, built, freeze);
                self.stale = false;
                self.frozen = freeze;
            } else if !freeze && self.saved.is_some() {
                self.set_saved(None);
                self.frozen = freeze;
            }
        }
        if let Some(value) = self.unwritten {
            match saved.try_store(value, self.seen_restores) {
                Stored::Written | Stored::Restored => self.unwritten = None,
                Stored::Busy => {}
            }
        }
    }

    fn apply(&mut self, engine: &mut Engine, built: &BreathVoiceMode, freeze: bool) {
        match (freeze, self.saved) {
            (true, Some(frozen)) => {
                let mode = frozen.mode();
                if *engine.voice_mode() != mode {
                    engine.set_voice_mode(mode);
                }
            }
            (true, None) => {
                let frozen = FrozenVoice::from_engine(engine.freeze_voice());
                self.set_saved(Some(frozen));
            }
            (false, saved) => {
                if engine.voice_mode() != built {
                    engine.set_voice_mode(*built);
                }
                if saved.is_some() {
                    self.set_saved(None);
                }
            }
        }
    }

    fn set_saved(&mut self, value: Option<FrozenVoice>) {
        self.saved = value;
        self.unwritten = Some(value);
    }

    /// What the editor shows for `engine`'s voice: frozen is the user's freeze; a fixed voice
    /// without it is the breath-like file's.
    pub fn shown(&self, engine: &Engine) -> VoiceShown {
        let level_db = engine
            .learned_voice()
            .map(|v| v.level_re_speech_db)
            .filter(|db| db.is_finite())
            .map(|db| db.round().clamp(-LEVEL_SPAN_DB, 0.0) as i16);
        match engine.voice_status() {
            VoiceStatus::BuiltIn if self.frozen => VoiceShown::FrozenBuiltIn,
            VoiceStatus::BuiltIn => VoiceShown::BuiltIn,
            VoiceStatus::Learning { breaths } => VoiceShown::Learning { breaths, level_db },
            VoiceStatus::Fixed { breaths } if self.frozen => {
                VoiceShown::Frozen { breaths, level_db }
            }
            VoiceStatus::Fixed { breaths } => VoiceShown::BreathLike { breaths, level_db },
        }
    }
}

/// The breath voice as the editor shows it. `level_db`: the learned level of the speaker's
/// breaths under the speech, whole dB (`None` before anything is learned), what the Breath
/// level parameter's default plays.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum VoiceShown {
    /// No engine runs.
    #[default]
    NoEngine,
    /// The built-in voice.
    BuiltIn,
    /// Frozen before anything was learned: the built-in voice.
    FrozenBuiltIn,
    /// Learning as the audio goes from the breaths heard so far.
    Learning {
        /// Breaths heard since the stream started.
        breaths: usize,
        /// See the type's docs.
        level_db: Option<i16>,
    },
    /// Frozen by the user.
    Frozen {
        /// Breaths it was learned from.
        breaths: usize,
        /// See the type's docs.
        level_db: Option<i16>,
    },
    /// Learned from the breath-like file.
    BreathLike {
        /// Breaths it was learned from.
        breaths: usize,
        /// See the type's docs.
        level_db: Option<i16>,
    },
}

/// Bits of the breath count in [`VoiceShown::to_bits`].
const COUNT_BITS: u32 = 32;
/// Bits of the level's depth under the speech in [`VoiceShown::to_bits`], above the count (all
/// ones: no level).
const LEVEL_BITS: u32 = 16;
/// The deepest level shown, dB under the speech (levels lie at most this far under it).
const LEVEL_SPAN_DB: f64 = 1000.0;

impl VoiceShown {
    /// The editor's line; `setting_db`: the Breath level that plays a learned voice at its own
    /// level with the current breathing preset
    /// ([`pneuma_core::engine::EngineConfig::learned_level_setting_db`]).
    pub fn text(&self, setting_db: Option<f32>) -> String {
        let breaths = |n: usize| format!("{n} breath{}", if n == 1 { "" } else { "s" });
        let learned = |n: usize, level_db: Option<i16>| match level_db {
            Some(db) => {
                let at = setting_db.map_or(String::new(), |s| {
                    format!(", where {} {s:.0} dB plays them", BREATH_LEVEL_DB.label)
                });
                format!(
                    "{}; this speaker's breaths lie {} dB under the speech{at}",
                    breaths(n),
                    -db
                )
            }
            None => breaths(n),
        };
        let what = match *self {
            Self::NoEngine => "none (the audio passes untouched)".to_owned(),
            Self::BuiltIn => "built-in".to_owned(),
            Self::FrozenBuiltIn => "built-in (frozen before any breath was heard)".to_owned(),
            Self::Learning {
                breaths: n,
                level_db,
            } => format!("learning ({})", learned(n, level_db)),
            Self::Frozen {
                breaths: n,
                level_db,
            } => format!("frozen ({})", learned(n, level_db)),
            Self::BreathLike {
                breaths: n,
                level_db,
            } => {
                format!("from the breath-like file ({})", learned(n, level_db))
            }
        };
        format!("breath voice: {what}")
    }

    /// One word for an atomic: the kind above the level above the count.
    pub fn to_bits(self) -> u64 {
        let (kind, n, level_db) = match self {
            Self::NoEngine => (0, 0, None),
            Self::BuiltIn => (1, 0, None),
            Self::FrozenBuiltIn => (2, 0, None),
            Self::Learning { breaths, level_db } => (3, breaths, level_db),
            Self::Frozen { breaths, level_db } => (4, breaths, level_db),
            Self::BreathLike { breaths, level_db } => (5, breaths, level_db),
        };
        let none = (1u64 << LEVEL_BITS) - 1;
        let depth = level_db.map_or(none, |db| {
            u64::from(db.unsigned_abs()).min(LEVEL_SPAN_DB as u64)
        });
        let count = (n as u64).min((1 << COUNT_BITS) - 1);
        (kind << (COUNT_BITS + LEVEL_BITS)) | (depth << COUNT_BITS) | count
    }

    /// The value [`VoiceShown::to_bits`] made.
    pub fn from_bits(bits: u64) -> Self {
        let breaths = (bits & ((1 << COUNT_BITS) - 1)) as usize;
        let depth = (bits >> COUNT_BITS) & ((1 << LEVEL_BITS) - 1);
        let level_db = (depth != (1 << LEVEL_BITS) - 1).then(|| -(depth as i16));
        match bits >> (COUNT_BITS + LEVEL_BITS) {
            1 => Self::BuiltIn,
            2 => Self::FrozenBuiltIn,
            3 => Self::Learning { breaths, level_db },
            4 => Self::Frozen { breaths, level_db },
            5 => Self::BreathLike { breaths, level_db },
            _ => Self::NoEngine,
        }
    }

    /// Stores it in `cell` (relaxed: a display).
    pub fn store(self, cell: &AtomicU64) {
        cell.store(self.to_bits(), Ordering::Relaxed);
    }

    /// Loads it from `cell`.
    pub fn load(cell: &AtomicU64) -> Self {
        Self::from_bits(cell.load(Ordering::Relaxed))
    }
}

/// The voice mode an engine is built with: the saved voice when the freeze is on and a voice is
/// saved, else `built` (the breath-like file's voice, or learning). Off the audio thread (waits
/// for the saved voice's lock).
pub fn build_mode(params: &PneumaParams, built: BreathVoiceMode) -> BreathVoiceMode {
    match params.breath_voice.get() {
        Some(frozen) if params.freeze_breath_voice.value() => frozen.mode(),
        _ => built,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_status_reads_as_the_issue_asks_and_survives_the_atomic() {
        // The words users read (issue 31), not the code's own strings.
        let cases = [
            (
                VoiceShown::Learning {
                    breaths: 7,
                    level_db: Some(-28),
                },
                "breath voice: learning (7 breaths; this speaker's breaths lie 28 dB under the \
                 speech, where Breath level -22 dB plays them)",
            ),
            (
                VoiceShown::Learning {
                    breaths: 1,
                    level_db: Some(-22),
                },
                "breath voice: learning (1 breath; this speaker's breaths lie 22 dB under the \
                 speech, where Breath level -22 dB plays them)",
            ),
            (
                VoiceShown::Learning {
                    breaths: 0,
                    level_db: None,
                },
                "breath voice: learning (0 breaths)",
            ),
            (
                VoiceShown::Frozen {
                    breaths: 12,
                    level_db: Some(-17),
                },
                "breath voice: frozen (12 breaths; this speaker's breaths lie 17 dB under the \
                 speech, where Breath level -22 dB plays them)",
            ),
            (VoiceShown::BuiltIn, "breath voice: built-in"),
            (
                VoiceShown::FrozenBuiltIn,
                "breath voice: built-in (frozen before any breath was heard)",
            ),
            (
                VoiceShown::BreathLike {
                    breaths: 30,
                    level_db: Some(-31),
                },
                "breath voice: from the breath-like file (30 breaths; this speaker's breaths lie \
                 31 dB under the speech, where Breath level -22 dB plays them)",
            ),
        ];
        let cell = AtomicU64::new(0);
        assert_eq!(VoiceShown::load(&cell), VoiceShown::NoEngine);
        for (shown, text) in cases {
            assert_eq!(shown.text(Some(BREATH_LEVEL_DB.default)), text);
            shown.store(&cell);
            assert_eq!(VoiceShown::load(&cell), shown);
        }
        // Another preset's setting (calm's softer sound), and none (a silent breathing sound).
        let frozen = VoiceShown::Frozen {
            breaths: 12,
            level_db: Some(-17),
        };
        assert_eq!(
            frozen.text(Some(-19.1)),
            "breath voice: frozen (12 breaths; this speaker's breaths lie 17 dB under the \
             speech, where Breath level -19 dB plays them)"
        );
        assert_eq!(
            frozen.text(None),
            "breath voice: frozen (12 breaths; this speaker's breaths lie 17 dB under the \
             speech)"
        );
    }
}

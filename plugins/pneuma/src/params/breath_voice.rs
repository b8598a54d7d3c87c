//! The breath voice the user froze (parameter `freeze_breath_voice`), saved with the plugin
//! state as the persisted field `breath_voice`, so every playback and bounce after the freeze,
//! also after the project is closed and opened again, draws its breaths from the same voice.
//!
//! The audio thread freezes the engine's voice and writes it here; it never waits for the lock
//! ([`SavedVoice::try_store`]: a try-lock of a `Copy` value, tried again at the next block when
//! busy). A restored state (a project or preset loaded) counts as a restore
//! ([`SavedVoice::restores`]), so the audio thread notices it without a lock and a voice it
//! froze a moment before never overwrites the restored one.

use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Mutex, MutexGuard, TryLockError};

use pneuma_core::breathing::learned::LearnedVoice;
use pneuma_core::engine::BreathVoiceMode;
use serde::{Deserialize, Serialize};

/// A frozen breath voice. Held inline (not boxed): the audio thread freezes it, where nothing
/// may allocate.
#[allow(clippy::large_enum_variant)]
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum FrozenVoice {
    /// Frozen before any breath was learned: the built-in voice.
    BuiltIn,
    /// A voice learned from the stream (or from the breath-like file).
    Learned(LearnedVoice),
}

impl FrozenVoice {
    /// What [`pneuma_core::engine::Engine::freeze_voice`] returned.
    pub fn from_engine(voice: Option<LearnedVoice>) -> Self {
        voice.map_or(Self::BuiltIn, Self::Learned)
    }

    /// The engine's voice mode for it.
    pub fn mode(&self) -> BreathVoiceMode {
        match self {
            Self::BuiltIn => BreathVoiceMode::BuiltIn,
            Self::Learned(v) => BreathVoiceMode::Fixed(*v),
        }
    }
}

/// What [`SavedVoice::try_store`] did.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Stored {
    /// The value is saved.
    Written,
    /// Another thread holds the lock: try again at the next block.
    Busy,
    /// A state was restored since the caller last looked: the restored value stays.
    Restored,
}

/// Another thread holds the saved voice's lock: look again at the next block.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Busy;

/// The persisted frozen voice (`None`: nothing frozen) and a count of restores.
#[derive(Debug, Default)]
pub struct SavedVoice {
    frozen: Mutex<Option<FrozenVoice>>,
    /// Raised inside the lock by every restore.
    restores: AtomicU64,
}

impl SavedVoice {
    /// The saved voice. Waits for the lock: not for the audio thread.
    pub fn get(&self) -> Option<FrozenVoice> {
        *self.lock()
    }

    /// How many times a state was restored into it (lock-free).
    pub fn restores(&self) -> u64 {
        self.restores.load(Ordering::Acquire)
    }

    /// The saved voice, or [`Busy`] when another thread holds the lock (audio thread: never
    /// waits).
    pub fn try_get(&self) -> Result<Option<FrozenVoice>, Busy> {
        match self.frozen.try_lock() {
            Ok(v) => Ok(*v),
            Err(TryLockError::Poisoned(p)) => Ok(*p.into_inner()),
            Err(TryLockError::WouldBlock) => Err(Busy),
        }
    }

    /// Saves `frozen` unless a state was restored since `seen_restores` (audio thread: never
    /// waits, never allocates).
    pub fn try_store(&self, frozen: Option<FrozenVoice>, seen_restores: u64) -> Stored {
        let mut guard = match self.frozen.try_lock() {
            Ok(g) => g,
            Err(TryLockError::Poisoned(p)) => p.into_inner(),
            Err(TryLockError::WouldBlock) => return Stored::Busy,
        };
        if self.restores.load(Ordering::Acquire) != seen_restores {
            return Stored::Restored;
        }
        *guard = frozen;
        Stored::Written
    }

    fn lock(&self) -> MutexGuard<'_, Option<FrozenVoice>> {
        self.frozen.lock().unwrap_or_else(|p| p.into_inner())
    }
}

impl<'a> nice_plug::params::persist::PersistentField<'a, Option<FrozenVoice>> for SavedVoice {
    /// A restored state (also the same voice again: the engine takes it afresh).
    fn set(&self, new_value: Option<FrozenVoice>) {
        let mut guard = self.lock();
        *guard = new_value;
        self.restores.fetch_add(1, Ordering::AcqRel);
    }

    fn map<F, R>(&self, f: F) -> R
    where
        F: Fn(&Option<FrozenVoice>) -> R,
    {
        f(&self.lock())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nice_plug::params::persist::PersistentField;

    fn voice() -> LearnedVoice {
        LearnedVoice {
            breaths: 5,
            level_re_speech_db: -24.5,
            speech_db: -18.25,
            length_s: 0.4,
            ..LearnedVoice::default()
        }
    }

    #[test]
    fn a_store_never_overwrites_a_restored_voice_and_never_waits() {
        let saved = SavedVoice::default();
        let seen = saved.restores();
        assert_eq!(
            saved.try_store(Some(FrozenVoice::BuiltIn), seen),
            Stored::Written
        );
        assert_eq!(saved.get(), Some(FrozenVoice::BuiltIn));
        // A state restored in between: the audio thread's older freeze is dropped.
        saved.set(Some(FrozenVoice::Learned(voice())));
        assert_eq!(saved.try_store(None, seen), Stored::Restored);
        assert_eq!(saved.get(), Some(FrozenVoice::Learned(voice())));
        // Held by another thread: busy, not waiting.
        let held = saved.lock();
        assert_eq!(saved.try_store(None, saved.restores()), Stored::Busy);
        assert!(saved.try_get().is_err());
        drop(held);
        assert_eq!(saved.try_store(None, saved.restores()), Stored::Written);
        assert_eq!(saved.try_get(), Ok(None));
    }

    #[test]
    fn the_saved_forms_are_distinct_and_round_trip_bit_for_bit() {
        for frozen in [
            None,
            Some(FrozenVoice::BuiltIn),
            Some(FrozenVoice::Learned(voice())),
        ] {
            let text = serde_json::to_string(&frozen).unwrap();
            let back: Option<FrozenVoice> = serde_json::from_str(&text).unwrap();
            assert_eq!(back, frozen, "{text}");
        }
        assert_eq!(serde_json::to_string(&None::<FrozenVoice>).unwrap(), "null");
        assert_eq!(
            serde_json::to_string(&Some(FrozenVoice::BuiltIn)).unwrap(),
            "\"built_in\""
        );
        assert_eq!(
            FrozenVoice::Learned(voice()).mode(),
            BreathVoiceMode::Fixed(voice())
        );
        assert_eq!(
            FrozenVoice::from_engine(None).mode(),
            BreathVoiceMode::BuiltIn
        );
    }
}

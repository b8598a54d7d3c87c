//! Phrase tracking: speech / pause decisions, phrase onsets and offsets, pause lengths.
//! (Being built: issue 4.)

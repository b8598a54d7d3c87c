//! (Being built.) Encoder: midi_cc.

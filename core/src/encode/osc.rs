//! (Being built.) Encoder: osc.

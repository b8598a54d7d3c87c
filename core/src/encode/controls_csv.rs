//! (Being built.) Encoder: controls_csv.

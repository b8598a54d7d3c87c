//! (Being built.) Encoder: breaths_csv.

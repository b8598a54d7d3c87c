//! (Being built.) Encoder: bvh.

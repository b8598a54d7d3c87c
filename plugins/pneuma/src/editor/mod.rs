//! The plugin's editor and its data path.
//!
//! - [`feed`]: the lock-free path from the audio thread to the GUI.
pub mod feed;

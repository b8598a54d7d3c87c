//! The editor window's size and zoom, a part of the plugin state kept with the parameters (the
//! editor reads and writes it; the parameters own it, so neither imports the other's room).

use serde::{Deserialize, Serialize};

/// The editor window's size (logical points) and zoom, saved with the plugin state.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct EditorLayout {
    /// Width, logical points.
    pub width: u32,
    /// Height, logical points.
    pub height: u32,
    /// The user's zoom on top of the host's scale factor.
    pub zoom: f32,
}

impl Default for EditorLayout {
    fn default() -> Self {
        Self {
            width: 1000,
            height: 680,
            zoom: 1.0,
        }
    }
}

//! The plugin's editor (egui through nice-plug-egui, OpenGL) and its data path.
//!
//! - [`feed`]: the lock-free path from the audio thread to the GUI.
//! - [`history`]: the GUI's last 10 s of frames and breaths, phrases and pauses.
//! - `timeline` (feature `editor`): the scrolling timeline.
//! - [`standalone`]: defaults a standalone program sets for its plugin instance.
//! - `view` (feature `editor`): the window: timeline, head and breathing, controls,
//!   breath-sample picker, output status and the MIDI CC map.
//!
//! The window exists only with the crate's `editor` feature (it links X11 and OpenGL); without
//! it [`create`] returns `None` and hosts show their generic parameter view, while the data path,
//! the saved layout and the state format stay the same. The window is resizable and follows the
//! host's scale factor; its size and zoom are saved in the plugin state ([`EditorLayout`],
//! persisted as `editor_layout`). A standalone program can run without a window
//! ([`set_headless`]).

pub mod feed;
pub mod history;
/// The standalone program's defaults live with the parameters they set (kept here for `pneuma-app`).
pub use crate::params::standalone;
#[cfg(feature = "editor")]
pub mod timeline;
#[cfg(feature = "editor")]
pub mod view;

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, RwLock};

#[cfg(feature = "editor")]
use nice_plug_egui::{create_egui_editor, EguiEditorState, EguiNiceSettings, RepaintNotifier};

use crate::breath_like::VoiceCache;
pub use crate::params::layout::EditorLayout;
use crate::params::PneumaParams;
use feed::EditorShared;

/// Smallest window, logical points.
pub const MIN_SIZE: (u32, u32) = (720, 480);

static HEADLESS: AtomicBool = AtomicBool::new(false);

/// Makes every plugin instance of this process come without an editor (a standalone program's
/// `--no-gui`). Call it before the plugin is created.
pub fn set_headless(headless: bool) {
    HEADLESS.store(headless, Ordering::Relaxed);
}

/// The editor type.
#[cfg(feature = "editor")]
pub type PneumaEditor = nice_plug_egui::EguiEditor<view::EditorApp>;
/// No editor window without the `editor` feature.
#[cfg(not(feature = "editor"))]
pub type PneumaEditor = ();

/// Built without the `editor` feature: no window (`None`), as in a headless process.
#[cfg(not(feature = "editor"))]
pub fn create(
    _params: Arc<PneumaParams>,
    _shared: Arc<EditorShared>,
    _saved_layout: Arc<RwLock<EditorLayout>>,
    _voices: Arc<VoiceCache>,
) -> Option<PneumaEditor> {
    None
}

/// The editor for a plugin instance (`saved_layout`: the persisted size and zoom, updated as
/// the window changes; `voices`: the instance's breath-like voices, shared with its engine
/// builder), or `None` in a headless process. Hosts ask once, right after creating
/// the instance (before a saved state is restored): the saved size is applied when the window
/// opens ([`view::EditorApp`]).
#[cfg(feature = "editor")]
pub fn create(
    params: Arc<PneumaParams>,
    shared: Arc<EditorShared>,
    saved_layout: Arc<RwLock<EditorLayout>>,
    voices: Arc<VoiceCache>,
) -> Option<PneumaEditor> {
    if HEADLESS.load(Ordering::Relaxed) {
        return None;
    }
    let layout = saved_layout.read().map(|l| *l).unwrap_or_default();
    let state = shared
        .window
        .get_or_init(|| {
            EguiEditorState::from_size(
                nice_plug::editor::dpi::LogicalSize::new(
                    layout.width.max(MIN_SIZE.0) as f64,
                    layout.height.max(MIN_SIZE.1) as f64,
                ),
                if layout.zoom.is_finite() && layout.zoom > 0.0 {
                    layout.zoom.clamp(0.5, 3.0)
                } else {
                    1.0
                },
            )
        })
        .clone();
    let settings = EguiNiceSettings::new()
        .with_tile("Pneuma")
        .with_resize_hint(
            nice_plug::editor::ResizeHint::resizable().with_min_logical_size(
                nice_plug::editor::dpi::LogicalSize::new(MIN_SIZE.0 as f32, MIN_SIZE.1 as f32),
            ),
        );
    let app = view::EditorApp::new(params, shared, saved_layout, voices);
    create_egui_editor(state, RepaintNotifier::new(), settings, app)
}

#[cfg(test)]
mod tests {
    use super::*;
    use nice_plug::prelude::Params;

    #[test]
    fn the_window_size_and_zoom_are_saved_with_the_state() {
        let params = PneumaParams::default();
        *params.editor_layout.write().unwrap() = EditorLayout {
            width: 1234,
            height: 777,
            zoom: 1.5,
        };
        let saved = params.serialize_fields();
        assert!(saved.contains_key("editor_layout"), "{:?}", saved.keys());
        let restored = PneumaParams::default();
        restored.deserialize_fields(&saved);
        assert_eq!(
            *restored.editor_layout.read().unwrap(),
            EditorLayout {
                width: 1234,
                height: 777,
                zoom: 1.5
            }
        );
    }

    #[cfg(feature = "editor")]
    #[test]
    fn a_headless_process_has_no_editor() {
        set_headless(true);
        let (_, shared) = feed::channel();
        let params = Arc::new(PneumaParams::default());
        let layout = params.editor_layout.clone();
        let voices = Arc::new(VoiceCache::default());
        let no_window = create(
            params.clone(),
            shared.clone(),
            layout.clone(),
            voices.clone(),
        );
        assert!(no_window.is_none());
        set_headless(false);
        assert!(create(params, shared, layout, voices).is_some());
    }
}

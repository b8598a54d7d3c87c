//! The editor window: an egui app (nice-plug-egui) that drains the data path into its
//! [`History`] on every repaint and draws the timeline, the head and breathing, the main
//! controls, the breath-sample and breath-like pickers, the breath voice's status and the
//! output status.
//!
//! Layout (resizable; the size and zoom are saved with the plugin state):
//! - top: the timeline of the last 10 s;
//! - bottom left: head pose (a drawn head and the three angles) and the breathing signals;
//! - bottom middle: the main controls, the breath voice (freeze, what it does, the breath-like
//!   recording) and the breath-sample picker;
//! - bottom right: output status (OSC target, format, counters) and the MIDI CC map.

use std::sync::atomic::Ordering;
use std::sync::mpsc::{self, Receiver};
use std::sync::{Arc, RwLock};
use std::time::Duration;

use egui::{Align2, Color32, FontId, RichText, Sense, Stroke, Ui, Vec2};
use nice_plug::context::gui::GuiContext;
use nice_plug::prelude::Param;
use nice_plug_egui::resizable_window::ResizableWindow;
use nice_plug_egui::widgets::ParamSlider;
use nice_plug_egui::NiceEguiApp;
use pneuma_core::encode::midi_cc::{CcResolution, CcSignal};
use pneuma_core::settings::placement;
use pneuma_core::ControlFrame;

use super::feed::EditorShared;
use super::history::History;
use super::{timeline, EditorLayout};
use crate::breath_like::VoiceCache;
use crate::params::{ModeChoice, PneumaParams, SamplePath};
use crate::voice::VoiceShown;

const ERROR_COLOUR: Color32 = Color32::from_rgb(255, 110, 100);
const OK_COLOUR: Color32 = Color32::from_rgb(120, 210, 130);

/// A file check's result: the path to use and what to say, or why the file cannot be used.
type Checked = Result<(String, String), String>;

/// A file check (runs on its own thread): a breath sample's or the breath-like recording's.
type CheckFile = Box<dyn FnOnce(String) -> Checked + Send>;

/// A breath sample: read as the engine will, the path and what to say, or why not.
fn check_sample(path: String) -> Checked {
    match crate::load_breath_sample(&path) {
        Ok(Some(_)) => Ok((path, "loaded (used from the next activation)".to_owned())),
        Ok(None) => Ok((String::new(), "built-in breath".to_owned())),
        Err(e) => Err(format!(
            "{e}. Choose a WAV file of one breath (mono or stereo, {}–{} s), or clear the field \
             for the built-in breath.",
            pneuma_core::breathing::MIN_SAMPLE_S,
            pneuma_core::breathing::MAX_SAMPLE_S
        )),
    }
}

/// The breath-like recording: its voice learned as an engine will learn it (`config`), through
/// the instance's cache.
fn check_breath_like(
    cache: &VoiceCache,
    path: String,
    config: &pneuma_core::engine::EngineConfig,
) -> Checked {
    let text = crate::breath_like::check(cache, &path, config)?;
    Ok((path, text))
}

/// A file slot (a breath sample, the breath-like recording): the path being typed, the check
/// running off the GUI thread, and its last result.
struct SamplePicker {
    label: &'static str,
    text: String,
    checking: Option<Receiver<Checked>>,
    result: Option<Checked>,
}

impl SamplePicker {
    fn new(label: &'static str, path: &SamplePath) -> Self {
        Self {
            label,
            text: path.get(),
            checking: None,
            result: None,
        }
    }

    /// Starts checking the file on its own thread (a file read never runs on the GUI or audio
    /// thread).
    fn check(&mut self, check: CheckFile) {
        let (tx, rx) = mpsc::channel();
        let path = self.text.trim().to_owned();
        let spawned = std::thread::Builder::new()
            .name("pneuma-file-check".into())
            .spawn(move || {
                let _ = tx.send(check(path));
            });
        match spawned {
            Ok(_) => self.checking = Some(rx),
            Err(e) => self.result = Some(Err(format!("cannot start the file check: {e}"))),
        }
    }

    /// Takes a finished check; a usable file becomes the slot's path (`true`: the path changed).
    fn poll(&mut self, path: &SamplePath) -> bool {
        let Some(rx) = &self.checking else {
            return false;
        };
        let Ok(result) = rx.try_recv() else {
            return false;
        };
        self.checking = None;
        let changed = match &result {
            Ok((p, _)) if *p != path.get() => {
                path.set_path(p.clone());
                true
            }
            _ => false,
        };
        self.result = Some(result);
        changed
    }

    /// Draws the slot; a click on Load (or Enter) starts `check`.
    fn ui(&mut self, ui: &mut Ui, hint: &str, check: impl FnOnce() -> CheckFile) {
        ui.horizontal(|ui| {
            ui.label(self.label);
            let edit = ui.add(
                egui::TextEdit::singleline(&mut self.text)
                    .hint_text(hint)
                    .desired_width(ui.available_width() - 60.0),
            );
            let enter = edit.lost_focus() && ui.input(|i| i.key_pressed(egui::Key::Enter));
            if (ui.button("Load").clicked() || enter) && self.checking.is_none() {
                self.check(check());
            }
        });
        match &self.result {
            _ if self.checking.is_some() => {
                ui.small("reading…");
            }
            Some(Ok((_, said))) => {
                ui.small(RichText::new(said).color(OK_COLOUR));
            }
            Some(Err(e)) => {
                ui.add(egui::Label::new(RichText::new(e).small().color(ERROR_COLOUR)).wrap());
            }
            None => {}
        }
    }
}

/// The editor's egui app.
pub struct EditorApp {
    params: Arc<PneumaParams>,
    shared: Arc<EditorShared>,
    layout: Arc<RwLock<EditorLayout>>,
    history: History,
    gui: Option<GuiContext>,
    pickers: [SamplePicker; 2],
    breath_like: SamplePicker,
    /// The voices learned from breath-like files, shared with the engine builder.
    voices: Arc<VoiceCache>,
}

impl EditorApp {
    /// An app over the plugin's parameters and the GUI end of the data path, checking
    /// breath-like files through `voices` (the instance's cache).
    pub fn new(
        params: Arc<PneumaParams>,
        shared: Arc<EditorShared>,
        layout: Arc<RwLock<EditorLayout>>,
        voices: Arc<VoiceCache>,
    ) -> Self {
        let pickers = [
            SamplePicker::new("Mouth", &params.breath_sample_mouth),
            SamplePicker::new("Nose", &params.breath_sample_nose),
        ];
        let breath_like = SamplePicker::new("Learn from", &params.breath_like);
        Self {
            params,
            shared,
            layout,
            history: History::default(),
            gui: None,
            pickers,
            breath_like,
            voices,
        }
    }

    fn drain(&mut self) {
        let history = &mut self.history;
        let mut frames = Vec::new();
        let mut breaths = Vec::new();
        self.shared.drain(|f| frames.push(*f), |b| breaths.push(*b));
        for b in &breaths {
            history.push_breath(b);
        }
        for f in &frames {
            history.push_frame(f);
        }
    }

    fn controls(&mut self, ui: &mut Ui) {
        let Some(gui) = &self.gui else {
            return;
        };
        let setter = gui.param_setter();
        let p = &self.params;
        egui::Grid::new("controls").num_columns(2).show(ui, |ui| {
            ui.label("Preset");
            ui.add(ParamSlider::for_param(&p.preset, &setter));
            ui.end_row();
            ui.label("Breath level");
            ui.add(ParamSlider::for_param(&p.breath_level_db, &setter));
            ui.end_row();
            ui.label("Minimum pause");
            ui.add(ParamSlider::for_param(&p.min_pause_s, &setter));
            ui.end_row();
            ui.label("Mode");
            ui.add(ParamSlider::for_param(&p.mode, &setter));
            ui.end_row();
            ui.label("");
            let cost = match p.mode.value() {
                ModeChoice::Lookahead => format!(
                    "costs {:.0} ms of latency (knows each pause before filling it)",
                    p.lookahead_s.value() * 1000.0
                ),
                ModeChoice::Live => "costs no latency (estimates pauses)".to_owned(),
            };
            ui.small(cost);
            ui.end_row();
            ui.label("Insert breaths");
            let mut on = p.insert_breaths.value();
            if ui.checkbox(&mut on, "").changed() {
                setter.begin_set_parameter(&p.insert_breaths);
                setter.set_parameter(&p.insert_breaths, on);
                setter.end_set_parameter(&p.insert_breaths);
            }
            ui.end_row();
            ui.label(placement::SPEECH_ONLY.label);
            let mut speech_only = p.speech_only.value();
            if ui
                .checkbox(&mut speech_only, "")
                .on_hover_text(placement::SPEECH_ONLY.help)
                .changed()
            {
                setter.begin_set_parameter(&p.speech_only);
                setter.set_parameter(&p.speech_only, speech_only);
                setter.end_set_parameter(&p.speech_only);
            }
            ui.end_row();
            ui.label("Head amount");
            ui.add(ParamSlider::for_param(&p.head_amount, &setter));
            ui.end_row();
        });
        ui.separator();
        ui.strong("Breath voice");
        let config = p.engine_config();
        let shown = VoiceShown::load(&self.shared.status.breath_voice);
        ui.small(shown.text(config.learned_level_setting_db()));
        let mut freeze = p.freeze_breath_voice.value();
        if ui
            .checkbox(&mut freeze, p.freeze_breath_voice.name())
            .on_hover_text(
                "Keep this voice for every playback and bounce (saved with the project); off: \
                 learn again from the next playback",
            )
            .changed()
        {
            setter.begin_set_parameter(&p.freeze_breath_voice);
            setter.set_parameter(&p.freeze_breath_voice, freeze);
            setter.end_set_parameter(&p.freeze_breath_voice);
        }
        // The breath-like recording: a new engine learns from it (no restart needed).
        self.breath_like.poll(&p.breath_like);
        let voices = self.voices.clone();
        self.breath_like.ui(
            ui,
            "learn as the audio goes (path to another take)",
            move || {
                let voices = voices.clone();
                Box::new(move |path| check_breath_like(&voices, path, &config))
            },
        );
        ui.separator();
        ui.strong("Breath samples");
        let mut changed = false;
        for (picker, path) in self
            .pickers
            .iter_mut()
            .zip([&p.breath_sample_mouth, &p.breath_sample_nose])
        {
            changed |= picker.poll(path);
            picker.ui(ui, "built-in (path to a WAV)", || Box::new(check_sample));
        }
        if changed {
            // The engine loads samples at activation.
            gui.request_restart();
        }
    }

    fn status(&self, ui: &mut Ui) {
        let p = &self.params;
        let s = &self.shared.status;
        let load = |a: &std::sync::atomic::AtomicU64| a.load(Ordering::Relaxed);
        ui.strong("OSC");
        egui::Grid::new("osc").num_columns(2).show(ui, |ui| {
            ui.label("target");
            let on = p.osc_enabled.value();
            let target = format!("{}:{}", p.osc_host(), p.osc_port.value());
            ui.label(if on {
                target
            } else {
                format!("{target} (off)")
            });
            ui.end_row();
            ui.label("format");
            ui.label(match p.osc_format.value() {
                crate::params::OscFormatChoice::Pneuma => "/pneuma",
                crate::params::OscFormatChoice::Vmc => "VMC",
            });
            ui.end_row();
            ui.label("sent");
            ui.label(load(&s.osc_sent).to_string());
            ui.end_row();
            ui.label("dropped");
            ui.label(load(&s.osc_dropped).to_string());
            ui.end_row();
            ui.label("last error");
            let failed = load(&s.osc_failed);
            if failed > 0 {
                let reason =
                    pneuma_osc::OscError::from_code(s.osc_last_error.load(Ordering::Relaxed))
                        .map_or("check the host (a numeric address) and port", |e| e.text());
                ui.colored_label(ERROR_COLOUR, format!("{reason} ({failed} frames not sent)"));
            } else {
                ui.label("none");
            }
            ui.end_row();
        });
        ui.separator();
        let running = s.engine_running.load(Ordering::Relaxed);
        let rate = s.sample_rate_hz.load(Ordering::Relaxed);
        if rate > 0 {
            let latency_ms =
                f64::from(s.latency_samples.load(Ordering::Relaxed)) * 1000.0 / f64::from(rate);
            if running {
                ui.small(format!("{rate} Hz, latency {latency_ms:.0} ms"));
            } else {
                ui.colored_label(
                    ERROR_COLOUR,
                    format!("{rate} Hz is not supported: audio passes untouched; use 8–768 kHz"),
                );
            }
        }
        let map = p.cc_map();
        let midi_on = p.midi_enabled.value();
        ui.strong(format!(
            "MIDI CC, channel {}{}{}",
            map.channel + 1,
            if map.resolution == CcResolution::Bits14 {
                ", 14-bit"
            } else {
                ""
            },
            if midi_on { "" } else { " (off)" }
        ));
        if let Err(e) = map.validate() {
            ui.colored_label(
                ERROR_COLOUR,
                format!("{e}: the previous CC map stays in use until this is fixed"),
            );
        }
        let lost = load(&s.cc_lost);
        if lost > 0 {
            ui.colored_label(ERROR_COLOUR, format!("{lost} blocks lost CC messages"));
        }
        let set = p.cc_params().map(|cc| cc.value());
        let limit = map.resolution.max_controller();
        egui::Grid::new("ccmap").num_columns(4).show(ui, |ui| {
            for (i, (signal, cc)) in CcSignal::ALL.iter().zip(map.controllers).enumerate() {
                ui.small(signal.name());
                match (cc, set[i]) {
                    (Some(c), _) => ui.small(c.to_string()),
                    // Set, but above what 14-bit pairs can use: the map leaves it off.
                    (None, v) if v > 0 => ui.colored_label(
                        ERROR_COLOUR,
                        RichText::new(format!("{v}: off, 14-bit uses 1-{limit}")).small(),
                    ),
                    (None, _) => ui.small("off"),
                };
                if i % 2 == 1 {
                    ui.end_row();
                }
            }
        });
    }
}

/// Draws a simple head seen from the front: the face outline tilts with roll, the features
/// move sideways with yaw and up and down with pitch.
fn head_view(ui: &mut Ui, frame: &ControlFrame) {
    let size = Vec2::new(150.0, 150.0);
    let (response, painter) = ui.allocate_painter(size, Sense::hover());
    let c = response.rect.center();
    let r = 52.0;
    let h = frame.head;
    let roll = -h.roll_deg.to_radians();
    let rot = |v: Vec2| {
        let (s, co) = roll.sin_cos();
        c + Vec2::new(v.x * co - v.y * s, v.x * s + v.y * co)
    };
    let stroke = Stroke::new(2.0, Color32::from_gray(210));
    painter.circle_stroke(c, r, stroke);
    // Yaw positive = looking to the character's left = the viewer's right.
    let dx = h.yaw_deg.to_radians().sin() * r;
    let dy = -h.pitch_deg.to_radians().sin() * r;
    for ex in [-18.0, 18.0] {
        painter.circle_filled(
            rot(Vec2::new(ex + dx, -12.0 + dy)),
            5.0,
            Color32::from_gray(220),
        );
    }
    painter.line_segment(
        [
            rot(Vec2::new(dx, -2.0 + dy)),
            rot(Vec2::new(dx * 1.2, 10.0 + dy)),
        ],
        stroke,
    );
    let mouth = 3.0 + 14.0 * frame.breathing.mouth_open;
    painter.rect_filled(
        egui::Rect::from_center_size(rot(Vec2::new(dx, 26.0 + dy)), Vec2::new(22.0, mouth)),
        3.0,
        Color32::from_rgb(200, 90, 90),
    );
    painter.text(
        response.rect.left_bottom(),
        Align2::LEFT_BOTTOM,
        format!(
            "pitch {:+.1}°  yaw {:+.1}°  roll {:+.1}°",
            h.pitch_deg, h.yaw_deg, h.roll_deg
        ),
        FontId::proportional(11.0),
        Color32::from_gray(200),
    );
}

/// Bars for the breathing signals (0..1) and the neck pitch.
fn breathing_view(ui: &mut Ui, frame: &ControlFrame) {
    let b = &frame.breathing;
    ui.small(format!(
        "{}  {}",
        b.phase.as_str(),
        if frame.speaking { "speaking" } else { "pause" }
    ));
    for (name, v, colour) in [
        ("lung", b.lung, timeline::LUNG_COLOUR),
        ("thorax", b.thorax, Color32::from_gray(170)),
        ("abdomen", b.abdomen, timeline::PHRASE_COLOUR),
        ("nostrils", b.nostril_flare, timeline::VOICED_COLOUR),
        ("mouth", b.mouth_open, Color32::from_rgb(200, 90, 90)),
    ] {
        ui.horizontal(|ui| {
            ui.add_sized([56.0, 14.0], egui::Label::new(RichText::new(name).small()));
            let (rect, _) = ui.allocate_exact_size(Vec2::new(110.0, 10.0), Sense::hover());
            ui.painter().rect_filled(rect, 2.0, Color32::from_gray(50));
            let mut fill = rect;
            fill.set_width(rect.width() * v.clamp(0.0, 1.0));
            ui.painter().rect_filled(fill, 2.0, colour);
        });
    }
    ui.small(format!("neck pitch {:+.1}°", b.neck_pitch_deg));
}

impl NiceEguiApp for EditorApp {
    fn build(
        &mut self,
        egui_ctx: egui::Context,
        gui: GuiContext,
        _frame: &mut nice_plug_egui::Frame,
    ) -> Result<(), nice_plug_egui::baseview::HandlerError> {
        self.gui = Some(gui);
        self.history = History::default();
        egui_ctx.set_visuals(egui::Visuals::dark());
        // A restored state's size and zoom (the window was created before the state came).
        let saved = self.layout.read().map(|l| *l).unwrap_or_default();
        if saved.zoom.is_finite() && (0.5..=3.0).contains(&saved.zoom) {
            egui_ctx.set_zoom_factor(saved.zoom);
        }
        egui_ctx.send_viewport_cmd(egui::ViewportCommand::InnerSize(Vec2::new(
            saved.width.max(super::MIN_SIZE.0) as f32,
            saved.height.max(super::MIN_SIZE.1) as f32,
        )));
        Ok(())
    }

    fn ui(&mut self, ui: &mut Ui, _frame: &mut nice_plug_egui::Frame) {
        self.drain();
        if crate::params::standalone::close_requested() {
            ui.ctx().send_viewport_cmd(egui::ViewportCommand::Close);
        }
        // The timeline scrolls: draw again in a 30th of a second.
        ui.ctx().request_repaint_after(Duration::from_millis(33));
        let last = self
            .history
            .frames()
            .back()
            .map(|f| f.control)
            // Before any frame: silence (the default frame's 0 dBFS is full scale).
            .unwrap_or_else(|| ControlFrame::rest(0, 0.0));
        ResizableWindow::new("pneuma-editor")
            .min_size(Vec2::new(720.0, 480.0))
            .show(ui, |ui| {
                ui.horizontal(|ui| {
                    ui.heading("Pneuma");
                    ui.small(format!(
                        "f0 {:.0} Hz  level {:+.0} dB",
                        last.f0_hz, last.level_db
                    ));
                    if let Some(note) =
                        self.history.input_peak_db().and_then(|(peak_db, span_s)| {
                            super::history::input_level_note(peak_db, span_s)
                        })
                    {
                        ui.colored_label(ERROR_COLOUR, note);
                    }
                    ui.with_layout(egui::Layout::right_to_left(egui::Align::Center), |ui| {
                        let zoom = ui.ctx().zoom_factor();
                        if ui.small_button("A+").clicked() {
                            ui.ctx().set_zoom_factor((zoom + 0.1).min(3.0));
                        }
                        if ui.small_button("A−").clicked() {
                            ui.ctx().set_zoom_factor((zoom - 0.1).max(0.5));
                        }
                    });
                });
                let timeline_h = (ui.available_height() * 0.48).max(180.0);
                timeline::show(ui, &self.history, timeline_h);
                ui.add_space(4.0);
                ui.columns(3, |cols| {
                    cols[0].strong("Head");
                    head_view(&mut cols[0], &last);
                    cols[0].strong("Breathing");
                    breathing_view(&mut cols[0], &last);
                    cols[1].strong("Controls");
                    self.controls(&mut cols[1]);
                    egui::ScrollArea::vertical()
                        .id_salt("status")
                        .show(&mut cols[2], |ui| self.status(ui));
                });
            });
    }

    fn resized(&mut self, new_size: nice_plug_egui::baseview::WindowSize) {
        if let Ok(mut l) = self.layout.write() {
            l.width = new_size.logical.width.round() as u32;
            l.height = new_size.logical.height.round() as u32;
        }
    }

    fn zoom_factor_changed(&mut self, zoom_factor: f32) {
        if let Ok(mut l) = self.layout.write() {
            l.zoom = zoom_factor;
        }
    }
}

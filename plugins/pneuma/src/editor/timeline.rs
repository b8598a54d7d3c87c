//! The scrolling timeline: the last [`SPAN_S`] seconds in three lanes, newest at the right.
//!
//! 1. Voice: input peak envelope (grey), phrases (blue band along the top) and pauses, inserted
//!    breaths ([`BREATH_COLOUR`] spans) and breaths already in the input ([`EXISTING_BREATH_COLOUR`]).
//! 2. Pitch: f0 trace (log scale 60–500 Hz) and the voiced gate (green strip along the bottom).
//! 3. Lungs: the lung volume sawtooth, with thorax and abdomen.

use egui::{Align2, Color32, FontId, Pos2, Rect, Sense, Stroke, Ui, Vec2};

use super::history::{History, SPAN_S};

/// Inserted breaths: one colour the screenshot test looks for.
pub const BREATH_COLOUR: Color32 = Color32::from_rgb(255, 140, 26);
/// Breaths already in the input (the speaker's own; nothing inserted there).
pub const EXISTING_BREATH_COLOUR: Color32 = Color32::from_rgb(40, 200, 200);
/// Phrases (speaking gate on).
pub const PHRASE_COLOUR: Color32 = Color32::from_rgb(70, 130, 220);
/// The voiced gate.
pub const VOICED_COLOUR: Color32 = Color32::from_rgb(90, 200, 110);
/// The f0 trace.
pub const F0_COLOUR: Color32 = Color32::from_rgb(240, 220, 90);
/// The lung sawtooth.
pub const LUNG_COLOUR: Color32 = Color32::from_rgb(230, 90, 160);
const BACKGROUND: Color32 = Color32::from_rgb(24, 26, 30);
const GRID: Color32 = Color32::from_rgb(55, 58, 64);
const WAVE: Color32 = Color32::from_rgb(170, 175, 185);
const F0_MIN_HZ: f32 = 60.0;
const F0_MAX_HZ: f32 = 500.0;

/// Draws the timeline into the available width, `height` points tall.
pub fn show(ui: &mut Ui, history: &History, height: f32) {
    let width = ui.available_width().max(100.0);
    let (response, painter) = ui.allocate_painter(Vec2::new(width, height), Sense::hover());
    let rect = response.rect;
    painter.rect_filled(rect, 4.0, BACKGROUND);
    let now_s = history.now_s();
    let t0 = now_s - SPAN_S;
    let x_of = |t: f64| rect.left() + ((t - t0) / SPAN_S) as f32 * rect.width();
    let lane_h = rect.height() / 3.0;
    let lanes: [Rect; 3] = std::array::from_fn(|i| {
        Rect::from_min_size(
            Pos2::new(rect.left(), rect.top() + lane_h * i as f32),
            Vec2::new(rect.width(), lane_h),
        )
        .shrink2(Vec2::new(0.0, 3.0))
    });
    let font = FontId::proportional(11.0);
    // Second grid lines, labelled in seconds before now.
    for k in 0..=SPAN_S as i32 {
        let x = x_of(now_s - f64::from(k));
        painter.vline(x, rect.y_range(), Stroke::new(1.0, GRID));
        if k > 0 {
            painter.text(
                Pos2::new(x + 2.0, rect.bottom() - 2.0),
                Align2::LEFT_BOTTOM,
                format!("-{k}s"),
                font.clone(),
                GRID.gamma_multiply(2.0),
            );
        }
    }
    for (lane, name) in lanes.iter().zip(["voice", "f0", "lungs"]) {
        painter.hline(rect.x_range(), lane.bottom() + 1.5, Stroke::new(1.0, GRID));
        painter.text(lane.left_top(), Align2::LEFT_TOP, name, font.clone(), WAVE);
    }

    // Lane 1: phrases, breaths, waveform envelope.
    let voice = lanes[0];
    for seg in history.segments().iter().filter(|s| s.speaking) {
        let (a, b) = (x_of(seg.start_s).max(rect.left()), x_of(seg.end_s));
        if b > a {
            let band = Rect::from_x_y_ranges(a..=b, voice.top()..=voice.top() + 5.0);
            painter.rect_filled(band, 0.0, PHRASE_COLOUR);
        }
    }
    for breath in history.breaths() {
        let (a, b) = (x_of(breath.start_s).max(rect.left()), x_of(breath.end_s));
        if b > a {
            let span =
                Rect::from_x_y_ranges(a..=b.max(a + 2.0), voice.top() + 7.0..=voice.bottom());
            let colour = if breath.existing {
                EXISTING_BREATH_COLOUR
            } else {
                BREATH_COLOUR
            };
            painter.rect_filled(span, 2.0, colour);
        }
    }
    let mid = voice.center().y + 3.0;
    let half = voice.height() / 2.0 - 6.0;
    for f in history.frames() {
        let x = x_of(f.control.time_s);
        if x < rect.left() {
            continue;
        }
        // sqrt: quiet speech stays visible next to loud.
        let a = f.input_peak.clamp(0.0, 1.0).sqrt() * half;
        painter.vline(x, mid - a..=mid + a, Stroke::new(1.0, WAVE));
    }

    // Lane 2: voiced gate and f0.
    let pitch = lanes[1];
    let y_of_f0 = |f0: f32| {
        let u = (f0.clamp(F0_MIN_HZ, F0_MAX_HZ) / F0_MIN_HZ).ln() / (F0_MAX_HZ / F0_MIN_HZ).ln();
        pitch.bottom() - 6.0 - u * (pitch.height() - 8.0)
    };
    let mut trace: Vec<Pos2> = Vec::new();
    let frames = history.frames();
    for (i, f) in frames.iter().enumerate() {
        let x = x_of(f.control.time_s);
        let next_x = frames
            .get(i + 1)
            .map_or(x + 1.0, |n| x_of(n.control.time_s));
        if f.control.voiced && x >= rect.left() {
            let strip = Rect::from_x_y_ranges(
                x..=next_x.max(x + 1.0),
                pitch.bottom() - 4.0..=pitch.bottom(),
            );
            painter.rect_filled(strip, 0.0, VOICED_COLOUR);
        }
        if f.control.voiced && f.control.f0_hz > 0.0 && x >= rect.left() {
            trace.push(Pos2::new(x, y_of_f0(f.control.f0_hz)));
        } else if !trace.is_empty() {
            painter.line(std::mem::take(&mut trace), Stroke::new(2.0, F0_COLOUR));
        }
    }
    if !trace.is_empty() {
        painter.line(trace, Stroke::new(2.0, F0_COLOUR));
    }
    for hz in [100.0, 200.0, 400.0] {
        painter.text(
            Pos2::new(pitch.right() - 2.0, y_of_f0(hz)),
            Align2::RIGHT_CENTER,
            format!("{hz:.0} Hz"),
            font.clone(),
            GRID.gamma_multiply(2.0),
        );
    }

    // Lane 3: lung volume, thorax, abdomen (0..1).
    let lungs = lanes[2];
    let y_of = |v: f32| lungs.bottom() - v.clamp(0.0, 1.0) * (lungs.height() - 12.0);
    let visible = || {
        frames
            .iter()
            .filter(|f| x_of(f.control.time_s) >= rect.left())
    };
    let series = |get: fn(&pneuma_core::BreathingState) -> f32| -> Vec<Pos2> {
        visible()
            .map(|f| Pos2::new(x_of(f.control.time_s), y_of(get(&f.control.breathing))))
            .collect()
    };
    painter.line(
        series(|b| b.thorax),
        Stroke::new(1.0, WAVE.gamma_multiply(0.6)),
    );
    painter.line(series(|b| b.abdomen), Stroke::new(1.0, PHRASE_COLOUR));
    painter.line(series(|b| b.lung), Stroke::new(2.0, LUNG_COLOUR));
}

//! The breathing plot (PNG), in the style of Bernardet et al.'s Figure 4: the lung-volume
//! sawtooth (with thorax and abdomen) on top, the audio waveform below with speech and breath
//! sounds in different colours, the breathing phases shaded in both panels. Time reads in
//! seconds up to a minute, then `m:ss`, from an hour `h:mm:ss` ([`time_label`]). Breaths carry
//! the numbers the marker files give them ([`crate::markers::number`]); where they are too dense
//! for every number, every k-th is numbered ([`numbered_every`]). The thorax is drawn dashed
//! over the lung line over a wide abdomen, so all three show where they are equal.
//!
//! The image has a fixed size whatever the input length: the waveform (given as samples or as an
//! already reduced min/max envelope, evenly spread over its duration) is reduced to its minimum
//! and maximum per pixel column and the controls to at most a few points per column, so hour-long
//! files plot as fast as short ones. When a pixel column spans more than [`MARKER_COLUMN_S`]
//! (files longer than about 80 s) a breath no longer has columns of its own, so breaths are drawn
//! as red markers at their true peak level over the speech waveform instead of colouring whole
//! columns. Text uses an embedded subset of DejaVu Sans Condensed
//! (`cli/assets/fonts`, Bitstream Vera licence), so no system fonts are needed. The file is
//! written to a temporary file and moved into place when complete ([`crate::output`]), with
//! Pneuma's mark ([`crate::png_mark`]).

use std::path::{Path, PathBuf};

use crate::output::{commit_all, Staged};
use std::sync::Once;

use plotters::prelude::*;
use plotters::style::FontStyle;
use pneuma_core::{BreathEvent, ControlFrame, Phase};
use thiserror::Error;

/// Width of the image, pixels.
pub const WIDTH_PX: u32 = 1600;
/// Height of the image, pixels.
pub const HEIGHT_PX: u32 = 800;
/// Column width above which breaths are drawn as markers, seconds.
pub const MARKER_COLUMN_S: f64 = 0.05;
/// Least distance between two breath numbers, pixels.
const NUMBER_SPACING_PX: f64 = 28.0;
const FONT: &str = "pneuma-sans";
const FONT_BYTES: &[u8] = include_bytes!("../assets/fonts/DejaVuSansCondensed-subset.ttf");

/// Colours: speech waveform, breath waveform, phase shading, curves.
const SPEECH: RGBColor = RGBColor(40, 70, 140);
const BREATH: RGBColor = RGBColor(215, 60, 40);
const INSPIRATION_SHADE: RGBColor = RGBColor(255, 222, 200);
const EXPIRATION_SHADE: RGBColor = RGBColor(215, 230, 250);
const LUNG: RGBColor = RGBColor(20, 20, 20);
const THORAX: RGBColor = RGBColor(30, 150, 90);
const ABDOMEN: RGBColor = RGBColor(160, 90, 190);

/// Errors while plotting.
#[derive(Debug, Error)]
pub enum PlotError {
    /// Nothing to plot.
    #[error("nothing to plot: the audio and the controls are both empty")]
    Empty,
    /// The duration is not usable.
    #[error("the plot's duration {0} s is not a finite positive number")]
    Duration(f64),
    /// Drawing failed.
    #[error("cannot draw the plot {path}: {reason}")]
    Draw {
        /// The target file.
        path: PathBuf,
        /// What plotters said.
        reason: String,
    },
    /// Moving the finished file into place failed.
    #[error("cannot write {path}: {source}")]
    Io {
        /// The target file.
        path: PathBuf,
        /// Why.
        source: std::io::Error,
    },
}

fn register_font() {
    static ONCE: Once = Once::new();
    ONCE.call_once(|| {
        // The embedded font is valid; the tests draw a plot and would fail otherwise.
        for name in [FONT, "sans-serif"] {
            let _ = plotters::style::register_font(name, FontStyle::Normal, FONT_BYTES);
        }
    });
}

/// Min/max of the waveform per column and whether the column lies in a breath.
struct Column {
    t_s: f64,
    lo: f32,
    hi: f32,
    breath: bool,
}

fn columns(
    audio: &[f32],
    rate: f64,
    duration_s: f64,
    n: usize,
    breaths: &[BreathEvent],
) -> Vec<Column> {
    let mut out = Vec::with_capacity(n);
    let mut bi = 0;
    for c in 0..n {
        let t0 = duration_s * c as f64 / n as f64;
        let t1 = duration_s * (c + 1) as f64 / n as f64;
        let a = ((t0 * rate) as usize).min(audio.len());
        let b = ((t1 * rate).ceil() as usize).clamp(a, audio.len());
        let (mut lo, mut hi) = (0.0f32, 0.0f32);
        for &v in &audio[a..b] {
            if v.is_finite() {
                lo = lo.min(v);
                hi = hi.max(v);
            }
        }
        while bi < breaths.len() && breaths[bi].end_s < t0 {
            bi += 1;
        }
        let breath = breaths[bi..]
            .iter()
            .take_while(|e| e.start_s <= t1)
            .any(|e| e.end_s >= t0 && e.start_s <= t1);
        out.push(Column {
            t_s: 0.5 * (t0 + t1),
            lo,
            hi,
            breath,
        });
    }
    out
}

/// A time axis label for `t_s` on a plot `duration_s` long: seconds (`12.5`) below a minute,
/// `m:ss` below an hour, `h:mm:ss` beyond.
pub fn time_label(t_s: f64, duration_s: f64) -> String {
    if duration_s < 60.0 {
        return format!("{t_s:.1}");
    }
    let s = t_s.max(0.0).round() as u64;
    if duration_s < 3600.0 {
        format!("{}:{:02}", s / 60, s % 60)
    } else {
        format!("{}:{:02}:{:02}", s / 3600, s / 60 % 60, s % 60)
    }
}

/// The time axis' description for a plot `duration_s` long (the format of [`time_label`]).
fn time_desc(duration_s: f64) -> &'static str {
    if duration_s < 60.0 {
        "time (s)"
    } else if duration_s < 3600.0 {
        "time (m:ss)"
    } else {
        "time (h:mm:ss)"
    }
}

/// Every how many breaths a number is drawn: 1 when the breaths are at least
/// [`NUMBER_SPACING_PX`] apart on average over `width_px` for `duration_s`, else the first of
/// 2, 5, 10, 20, 50, … that spaces them so.
pub fn numbered_every(breaths: usize, duration_s: f64, width_px: f64) -> usize {
    if breaths < 2 || duration_s <= 0.0 {
        return 1;
    }
    let px_per_breath = width_px / breaths as f64;
    (0..)
        .flat_map(|p| [1, 2, 5].map(|m| m * 10usize.pow(p)))
        .find(|&every| px_per_breath * every as f64 >= NUMBER_SPACING_PX || every >= breaths)
        .unwrap_or(breaths)
}

/// Runs of equal phase: (start_s, end_s, phase).
fn phase_runs(controls: &[ControlFrame]) -> Vec<(f64, f64, Phase)> {
    let mut runs: Vec<(f64, f64, Phase)> = Vec::new();
    let half = if controls.len() > 1 {
        0.5 * (controls[1].time_s - controls[0].time_s)
    } else {
        0.0
    };
    for f in controls {
        let (a, b) = (f.time_s - half, f.time_s + half);
        match runs.last_mut() {
            Some(last) if last.2 == f.breathing.phase => last.1 = b,
            _ => runs.push((a.max(0.0), b, f.breathing.phase)),
        }
    }
    runs
}

/// Draws the plot of the waveform `wave` (mono samples or a min/max envelope, evenly spread
/// over `duration_s`), its `controls` and inserted `breaths` (sorted by time) to the PNG file
/// `path`, through a temporary file that replaces `path` only when complete.
pub fn write_plot(
    path: &Path,
    wave: &[f32],
    duration_s: f64,
    controls: &[ControlFrame],
    breaths: &[BreathEvent],
) -> Result<(), PlotError> {
    let io = |source| PlotError::Io {
        path: path.to_owned(),
        source,
    };
    let staged = Staged::new(path).map_err(io)?;
    draw_png(staged.temp(), path, wave, duration_s, controls, breaths)?;
    commit_all(vec![staged]).map_err(|(_, e)| io(e))
}

/// Draws the plot (as [`write_plot`]) straight into `file`; `shown_as` names it in errors.
pub fn draw_png(
    file: &Path,
    shown_as: &Path,
    wave: &[f32],
    duration_s: f64,
    controls: &[ControlFrame],
    breaths: &[BreathEvent],
) -> Result<(), PlotError> {
    if wave.is_empty() && controls.is_empty() {
        return Err(PlotError::Empty);
    }
    if !(duration_s.is_finite() && duration_s >= 0.0) {
        return Err(PlotError::Duration(duration_s));
    }
    register_font();
    draw(file, wave, duration_s, controls, breaths).map_err(|reason| PlotError::Draw {
        path: shown_as.to_owned(),
        reason,
    })
}

fn draw(
    file: &Path,
    audio: &[f32],
    audio_s: f64,
    controls: &[ControlFrame],
    breaths: &[BreathEvent],
) -> Result<(), String> {
    let root = BitMapBackend::new(file, (WIDTH_PX, HEIGHT_PX)).into_drawing_area();
    draw_on(&root, audio, audio_s, controls, breaths)?;
    root.present().map_err(|x| x.to_string())?;
    drop(root);
    // Pneuma's mark, which tells this plot from a user's PNG of its name ([`crate::png_mark`]).
    let png = std::fs::read(file).map_err(|x| x.to_string())?;
    let marked = crate::png_mark::mark(&png).ok_or("the encoder wrote no PNG header")?;
    std::fs::write(file, marked).map_err(|x| x.to_string())
}

/// Draws the plot on `root` ([`WIDTH_PX`] × [`HEIGHT_PX`]).
fn draw_on(
    root: &DrawingArea<BitMapBackend<'_>, plotters::coord::Shift>,
    audio: &[f32],
    audio_s: f64,
    controls: &[ControlFrame],
    breaths: &[BreathEvent],
) -> Result<(), String> {
    let e = |x: &dyn std::fmt::Display| x.to_string();
    let rate = audio.len() as f64 / audio_s.max(1e-9);
    let controls_s = controls.last().map_or(0.0, |f| f.time_s);
    let duration_s = audio_s.max(controls_s).max(1e-3);
    let markers = duration_s / WIDTH_PX as f64 > MARKER_COLUMN_S;
    root.fill(&WHITE).map_err(|x| e(&x))?;
    let (top, bottom) = root.split_vertically(HEIGHT_PX * 9 / 20);
    let label = (FONT, 16).into_font();
    let title = (FONT, 20).into_font();
    let runs = phase_runs(controls);
    let shade = |phase: Phase| match phase {
        Phase::Inspiration => Some(INSPIRATION_SHADE),
        Phase::Expiration => Some(EXPIRATION_SHADE),
        Phase::Rest => None,
    };

    // Top: lung sawtooth with thorax and abdomen.
    let mut chart = ChartBuilder::on(&top)
        .caption(
            "Breathing: lung volume (sawtooth), thorax, abdomen",
            title.clone(),
        )
        .margin(10)
        .x_label_area_size(30)
        .y_label_area_size(60)
        .build_cartesian_2d(0.0..duration_s, 0.0..1.05)
        .map_err(|x| e(&x))?;
    chart
        .configure_mesh()
        .disable_x_mesh()
        .x_label_formatter(&|t: &f64| time_label(*t, duration_s))
        .light_line_style(TRANSPARENT)
        .y_desc("fraction of maximum")
        .label_style(label.clone())
        .axis_desc_style(label.clone())
        .draw()
        .map_err(|x| e(&x))?;
    chart
        .draw_series(runs.iter().filter_map(|&(a, b, p)| {
            shade(p).map(|c| Rectangle::new([(a, 0.0), (b, 1.05)], c.filled()))
        }))
        .map_err(|x| e(&x))?;
    let step = (controls.len() / (4 * WIDTH_PX as usize)).max(1);
    let series = |f: fn(&ControlFrame) -> f32| {
        controls
            .iter()
            .step_by(step)
            .map(move |c| (c.time_s, f(c) as f64))
            .collect::<Vec<_>>()
    };
    // Abdomen first and wide, the lung over it, the thorax dashed on top: all three stay
    // visible where they are equal.
    chart
        .draw_series(segments(
            series(|c| c.breathing.abdomen),
            ABDOMEN.stroke_width(6),
        ))
        .map_err(|x| e(&x))?
        .label("abdomen")
        .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], ABDOMEN.stroke_width(4)));
    chart
        .draw_series(segments(series(|c| c.breathing.lung), LUNG.stroke_width(2)))
        .map_err(|x| e(&x))?
        .label("lung")
        .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], LUNG.stroke_width(2)));
    chart
        .draw_series(DashedLineSeries::new(
            series(|c| c.breathing.thorax),
            8,
            6,
            THORAX.stroke_width(3),
        ))
        .map_err(|x| e(&x))?
        .label("thorax")
        .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 8, y)], THORAX.stroke_width(3)));
    chart
        .configure_series_labels()
        .label_font(label.clone())
        .background_style(WHITE.mix(0.8))
        .border_style(BLACK)
        .position(SeriesLabelPosition::UpperRight)
        .draw()
        .map_err(|x| e(&x))?;

    // Bottom: waveform, speech and breath coloured, phases shaded.
    let cols = columns(audio, rate, duration_s, WIDTH_PX as usize, breaths);
    let peak = cols
        .iter()
        .map(|c| c.hi.max(-c.lo))
        .fold(0.0f32, f32::max)
        .max(1e-3) as f64
        * 1.05;
    let mut wave = ChartBuilder::on(&bottom)
        .caption(
            "Audio: speech (blue) and breaths (red); shading: inspiration (orange), expiration (blue)",
            title,
        )
        .margin(10)
        .x_label_area_size(40)
        .y_label_area_size(60)
        .build_cartesian_2d(0.0..duration_s, -peak..peak)
        .map_err(|x| e(&x))?;
    wave.configure_mesh()
        .disable_x_mesh()
        .y_label_formatter(&|v: &f64| tick(*v))
        .x_label_formatter(&|t: &f64| time_label(*t, duration_s))
        .light_line_style(TRANSPARENT)
        .x_desc(time_desc(duration_s))
        .y_desc("amplitude")
        .label_style(label.clone())
        .axis_desc_style(label)
        .draw()
        .map_err(|x| e(&x))?;
    wave.draw_series(runs.iter().filter_map(|&(a, b, p)| {
        shade(p).map(|c| Rectangle::new([(a, -peak), (b, peak)], c.filled()))
    }))
    .map_err(|x| e(&x))?;
    wave.draw_series(cols.iter().map(|c| {
        let colour = if c.breath && !markers { BREATH } else { SPEECH };
        PathElement::new(vec![(c.t_s, c.lo as f64), (c.t_s, c.hi as f64)], colour)
    }))
    .map_err(|x| e(&x))?;
    if markers {
        // Each breath: a red bar up to its peak level and a dot on top.
        let at = |b: &BreathEvent| {
            (
                0.5 * (b.start_s + b.end_s),
                10f64.powf(b.peak_db as f64 / 20.0).min(peak),
            )
        };
        wave.draw_series(breaths.iter().map(|b| {
            let (t, a) = at(b);
            PathElement::new(vec![(t, -a), (t, a)], BREATH.stroke_width(2))
        }))
        .map_err(|x| e(&x))?;
        wave.draw_series(breaths.iter().map(|b| {
            let (t, a) = at(b);
            Circle::new((t, a), 3, BREATH.filled())
        }))
        .map_err(|x| e(&x))?;
    }
    // The breaths' numbers (as in the marker files) along the top of the waveform.
    let every = numbered_every(breaths.len(), duration_s, f64::from(WIDTH_PX));
    let number_font = (FONT, 13).into_font().color(&BREATH);
    wave.draw_series(
        breaths
            .iter()
            .enumerate()
            .filter(|(i, _)| crate::markers::number(*i).is_multiple_of(every))
            .map(|(i, b)| {
                Text::new(
                    crate::markers::number(i).to_string(),
                    (0.5 * (b.start_s + b.end_s), peak),
                    number_font.clone(),
                )
            }),
    )
    .map_err(|x| e(&x))?;
    Ok(())
}

/// A wide curve through `points` as separate segments, one per pair of neighbours. A
/// polyline's mitred joins at near-reversals (a sawtooth's rise and fall inside one pixel
/// column of a long file) reach far past the points; separate segments have no joins.
fn segments(
    points: Vec<(f64, f64)>,
    style: ShapeStyle,
) -> impl Iterator<Item = PathElement<(f64, f64)>> {
    let elements: Vec<_> = points
        .windows(2)
        .map(|w| PathElement::new(vec![w[0], w[1]], style))
        .collect();
    elements.into_iter()
}

/// An axis tick with two decimals, never "-0.00".
fn tick(v: f64) -> String {
    let s = format!("{v:.2}");
    if s.trim_start_matches('-')
        .chars()
        .all(|c| c == '0' || c == '.')
    {
        "0".into()
    } else {
        s
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use pneuma_core::{BreathKind, BreathingState};

    #[test]
    fn columns_keep_extremes_and_mark_breaths() {
        let audio: Vec<f32> = (0..1000)
            .map(|i| if i == 123 { 0.9 } else { 0.0 })
            .collect();
        let breaths = [BreathEvent {
            start_s: 0.5,
            end_s: 0.6,
            kind: BreathKind::Nose,
            peak_db: -30.0,
        }];
        let cols = columns(&audio, 1000.0, 1.0, 10, &breaths);
        assert_eq!(cols.len(), 10);
        assert_eq!(cols[1].hi, 0.9);
        assert!(cols.iter().filter(|c| c.hi > 0.0).count() == 1);
        assert!(cols[5].breath && !cols[2].breath && !cols[8].breath);
    }

    #[test]
    fn time_reads_in_seconds_then_minutes_then_hours() {
        assert_eq!(time_label(12.5, 25.0), "12.5");
        assert_eq!(time_label(250.0, 406.45), "4:10");
        assert_eq!(time_label(59.6, 600.0), "1:00");
        assert_eq!(time_label(3725.0, 4000.0), "1:02:05");
        assert_eq!(time_label(0.0, 4000.0), "0:00:00");
        assert_eq!(time_desc(25.0), "time (s)");
        assert_eq!(time_desc(406.45), "time (m:ss)");
        assert_eq!(time_desc(3600.0), "time (h:mm:ss)");
    }

    #[test]
    fn breaths_are_numbered_every_one_two_five_ten_as_space_allows() {
        assert_eq!(numbered_every(3, 25.0, 1600.0), 1);
        // 57 breaths in 1600 px: 28 px each.
        assert_eq!(numbered_every(57, 400.0, 1600.0), 1);
        assert_eq!(numbered_every(80, 400.0, 1600.0), 2);
        assert_eq!(numbered_every(200, 3600.0, 1600.0), 5);
        assert_eq!(numbered_every(600, 3600.0, 1600.0), 20);
        assert_eq!(numbered_every(0, 3600.0, 1600.0), 1);
    }

    /// The plot drawn in memory: RGB bytes, [`WIDTH_PX`] × [`HEIGHT_PX`].
    fn pixels(controls: &[ControlFrame], audio: &[f32], audio_s: f64) -> Vec<u8> {
        register_font();
        let mut buf = vec![0u8; (WIDTH_PX * HEIGHT_PX * 3) as usize];
        {
            let root =
                BitMapBackend::with_buffer(&mut buf, (WIDTH_PX, HEIGHT_PX)).into_drawing_area();
            draw_on(&root, audio, audio_s, controls, &[]).expect("draws");
            root.present().expect("present");
        }
        buf
    }

    fn count(buf: &[u8], c: RGBColor) -> usize {
        buf.chunks_exact(3)
            .filter(|p| p[0] == c.0 && p[1] == c.1 && p[2] == c.2)
            .count()
    }

    #[test]
    fn the_thorax_and_lung_show_where_they_equal_the_abdomen() {
        // Lung, thorax and abdomen all the same sawtooth.
        let controls: Vec<ControlFrame> = (0..3000)
            .map(|i| {
                let v = (i % 300) as f32 / 300.0;
                ControlFrame {
                    index: i,
                    time_s: i as f64 * 0.01,
                    breathing: BreathingState {
                        lung: v,
                        thorax: v,
                        abdomen: v,
                        ..Default::default()
                    },
                    ..Default::default()
                }
            })
            .collect();
        let audio = vec![0.0f32; 30 * 100];
        let buf = pixels(&controls, &audio, 30.0);
        // The legend's samples alone are a few dozen pixels each; the lines are thousands.
        for (name, c) in [("thorax", THORAX), ("lung", LUNG), ("abdomen", ABDOMEN)] {
            let n = count(&buf, c);
            assert!(n > 1500, "{name}: {n} pixels of its colour");
        }
    }

    #[test]
    fn curves_of_a_long_file_stay_inside_their_panel() {
        // 34 minutes of breathing: 0.3 s inspirations, 2.5–4 s expirations, so each pixel
        // column (1.3 s) holds a rise and a fall. A wide line joined at such turns threw
        // spikes far over the panel, across the title and into the waveform's panel.
        let rate_hz = 120.0;
        let n = (34.0 * 60.0 * rate_hz) as u64;
        let mut t_in_cycle = 0.0;
        let mut cycle_s = 3.0;
        let mut k = 0u64;
        let controls: Vec<ControlFrame> = (0..n)
            .map(|i| {
                let dt = 1.0 / rate_hz;
                t_in_cycle += dt;
                if t_in_cycle >= cycle_s {
                    t_in_cycle = 0.0;
                    k += 1;
                    cycle_s = 2.8 + 1.5 * ((k * 7919) % 11) as f64 / 10.0;
                }
                let v = if t_in_cycle < 0.3 {
                    0.1 + 0.8 * t_in_cycle / 0.3
                } else {
                    0.9 - 0.8 * (t_in_cycle - 0.3) / (cycle_s - 0.3)
                } as f32;
                ControlFrame {
                    index: i,
                    time_s: i as f64 * dt,
                    breathing: BreathingState {
                        lung: v,
                        thorax: 0.3 * v,
                        abdomen: 0.3 * v,
                        ..Default::default()
                    },
                    ..Default::default()
                }
            })
            .collect();
        let audio = vec![0.0f32; 34 * 60 * 100];
        let buf = pixels(&controls, &audio, 34.0 * 60.0);
        let rows =
            |from: u32, to: u32| &buf[(from * WIDTH_PX * 3) as usize..(to * WIDTH_PX * 3) as usize];
        // Over the title's text (whose antialiased edges hold greys like the lung's) and, for
        // the coloured curves, the whole lower panel.
        let split = HEIGHT_PX * 9 / 20;
        for (name, c) in [("lung", LUNG), ("abdomen", ABDOMEN), ("thorax", THORAX)] {
            assert_eq!(count(rows(0, 8), c), 0, "{name} over the title");
        }
        for (name, c) in [("abdomen", ABDOMEN), ("thorax", THORAX)] {
            assert_eq!(
                count(rows(split, HEIGHT_PX), c),
                0,
                "{name} in the waveform's panel"
            );
        }
        // The abdomen and the thorax (0.3 at most) stay under 0.5 of the top panel (rows 30 to
        // 180 hold 0.5 to 1.05 of its plot area, rows 40 to 320), left of the legend, whose
        // samples of their lines sit at the upper right.
        for (name, c) in [("abdomen", ABDOMEN), ("thorax", THORAX)] {
            let high: usize = rows(30, 180)
                .chunks_exact(3 * WIDTH_PX as usize)
                .map(|row| count(&row[..3 * 1300], c))
                .sum();
            assert_eq!(high, 0, "{name} over 0.5");
        }
        assert!(count(&buf, ABDOMEN) > 1500);
    }

    #[test]
    fn ticks_never_show_negative_zero() {
        assert_eq!(tick(-0.0), "0");
        assert_eq!(tick(-0.001), "0");
        assert_eq!(tick(0.0), "0");
        assert_eq!(tick(-0.25), "-0.25");
        assert_eq!(tick(0.5), "0.50");
    }

    #[test]
    fn phase_runs_merge_equal_phases() {
        let frame = |i: u64, phase| ControlFrame {
            index: i,
            time_s: i as f64 * 0.1,
            breathing: BreathingState {
                phase,
                ..Default::default()
            },
            ..Default::default()
        };
        let frames = [
            frame(0, Phase::Rest),
            frame(1, Phase::Inspiration),
            frame(2, Phase::Inspiration),
            frame(3, Phase::Expiration),
        ];
        let runs = phase_runs(&frames);
        assert_eq!(runs.len(), 3);
        assert_eq!(runs[1].2, Phase::Inspiration);
        assert!((runs[1].0 - 0.05).abs() < 1e-9 && (runs[1].1 - 0.25).abs() < 1e-9);
    }
}

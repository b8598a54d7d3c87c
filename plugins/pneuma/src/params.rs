//! The plugin's parameters and persisted settings.
//!
//! Every `#[id]` is saved in host projects, presets and automation: never change one. The table
//! of ids is in [`PARAM_IDS`] (a test holds the struct to it). Settings that are not numbers
//! (the OSC host, breath sample paths, the breath-like recording, the frozen breath voice
//! ([`breath_voice`])) are persisted fields (`#[persist]`), saved and restored with the state but
//! not automatable.
//!
//! A parameter with the id of a setting of core's table ([`pneuma_core::settings`]) takes its
//! name, default, range, unit and step from the table ([`float_param`], [`int_param`],
//! [`switch_param`]), and hosts file it under the table's group ([`unit_of`]). The others are
//! the plugin's own ([`PLUGIN_ONLY`]: the host's bypass, the preset choice, the output switches
//! and the CC controllers, whose defaults are [`CcSignal::DEFAULT_CONTROLLERS`]). The ranges
//! are the ones the plugin always had, so saved sessions and automation keep their meaning
//! (`automation_compat` and the state fixture of the tests crate prove it).
//!
//! Parameters that change the frame clock or the latency (`mode`, `lookahead_s`,
//! `frame_rate_hz`) need a new engine: the plugin builds one in the background and swaps it in
//! (`crate::rebuild`), reporting the new latency to the host.
//!
//! Change flags: every parameter's callback raises one of the [`ChangeFlags`] (engine settings,
//! CC map, structure), so the audio thread rebuilds the engine settings or the CC map only after
//! a change, never by comparing them every block.
//!
//! Text: every parameter's text parses back to its value (the CC parameters show and accept
//! `off` for 0).

use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::{Arc, RwLock};

use nice_plug::prelude::*;
use pneuma_core::breathing::{BreathingParams, Preset};
use pneuma_core::encode::midi_cc::{CcMap, CcResolution, CcSignal, SIGNAL_COUNT};
use pneuma_core::encode::osc::OscFormat;
use pneuma_core::engine::{EngineConfig, PlacementMode};
use pneuma_core::head::HeadConfig;
use pneuma_core::settings::{self, analysis, breathing, head, output, placement, Kind, Setting};

pub mod breath_voice;
pub mod layout;
pub mod migrate;
pub mod remote;
pub mod standalone;

/// Breathing preset: `Custom` uses the individual breathing controls, the others replace them.
#[derive(Enum, Debug, Clone, Copy, PartialEq, Eq)]
pub enum PresetChoice {
    /// Use the individual breathing parameters.
    #[id = "custom"]
    Custom,
    /// Everyday speech.
    #[id = "neutral"]
    Neutral,
    /// Long, deep, abdominal, nasal.
    #[id = "calm"]
    Calm,
    /// Fast, shallow, thoracic, mouth gasps.
    #[id = "anxious"]
    Anxious,
    /// Slow, sighing, audible.
    #[id = "tired"]
    Tired,
    /// Loud, fast, big quick breaths.
    #[id = "excited"]
    Excited,
}

/// Where breaths are placed.
#[derive(Enum, Debug, Clone, Copy, PartialEq, Eq)]
pub enum ModeChoice {
    /// Delays the audio by the lookahead and knows each pause's length before filling it.
    #[id = "lookahead"]
    Lookahead,
    /// Zero latency: estimates from the recent phrases.
    #[id = "live"]
    Live,
}

/// OSC address space.
#[derive(Enum, Debug, Clone, Copy, PartialEq, Eq)]
pub enum OscFormatChoice {
    /// The `/pneuma/...` address space.
    #[id = "pneuma"]
    #[name = "pneuma"]
    Pneuma,
    /// The VMC protocol.
    #[id = "vmc"]
    #[name = "VMC"]
    Vmc,
}

impl From<OscFormatChoice> for OscFormat {
    fn from(c: OscFormatChoice) -> Self {
        match c {
            OscFormatChoice::Pneuma => OscFormat::Pneuma,
            OscFormatChoice::Vmc => OscFormat::Vmc,
        }
    }
}

/// Parameters added after the settings table (issue 34): sessions and automation saved before
/// them do not hold them and load with their defaults. The compatibility tests check every
/// other parameter against what the plugin saved before.
pub const ADDED_SINCE_SETTINGS_TABLE: &[&str] = &["speech_only", "freeze_breath_voice"];

/// Every parameter id, in declaration order.
pub const PARAM_IDS: &[&str] = &[
    "bypass",
    "preset",
    "thorax_vs_abdomen",
    "capacity_lung",
    "mouth_vs_nose",
    "breath_sound",
    "opening",
    "speaking_loudness",
    "inspiration_length_s",
    "neck_amplitude_deg",
    "breath_level_db",
    "insert_breaths",
    "freeze_breath_voice",
    "speech_only",
    "min_pause_s",
    "mode",
    "lookahead_s",
    "head_amount",
    "head_max_pitch_deg",
    "head_max_yaw_deg",
    "head_max_roll_deg",
    "frame_rate_hz",
    "midi_enabled",
    "midi_channel",
    "cc_14bit",
    "cc_head_range_deg",
    "cc_lung",
    "cc_head_pitch",
    "cc_head_yaw",
    "cc_head_roll",
    "cc_thorax",
    "cc_abdomen",
    "cc_nostril_flare",
    "cc_mouth_open",
    "cc_neck_pitch",
    "cc_speaking",
    "cc_loudness",
    "osc_enabled",
    "osc_port",
    "osc_format",
];

/// The parameters that are no setting of core's table, each with the id of the table's group
/// hosts file it under (empty: at the top) and why it is the plugin's own.
pub const PLUGIN_ONLY: &[(&str, &str, &str)] = &[
    ("bypass", "", "the host's bypass switch"),
    (
        "preset",
        "breathing",
        "a choice among core's breathing presets (Preset::ALL) or the custom controls",
    ),
    (
        "freeze_breath_voice",
        "placement",
        "keeps the breath voice learned so far in the saved state (a session's choice; the CLI \
         learns from the whole file or --breath-like)",
    ),
    (
        "midi_enabled",
        "midi",
        "whether the plugin sends MIDI CC (the CLI writes files)",
    ),
    (
        "cc_",
        "midi",
        "the controller of each CcSignal, 0 (off) to 119; defaults CcSignal::DEFAULT_CONTROLLERS",
    ),
    (
        "osc_enabled",
        "osc",
        "whether the plugin sends OSC (the app's --osc)",
    ),
];

/// The plugin-only entry of `id` (`cc_` stands for every CC controller).
fn plugin_only(id: &str) -> Option<&'static (&'static str, &'static str, &'static str)> {
    PLUGIN_ONLY.iter().find(|(own, _, _)| {
        *own == id || (*own == "cc_" && CcSignal::ALL.iter().any(|s| id == cc_id(*s)))
    })
}

/// The id of the CC controller parameter of `signal`: `cc_` and the signal's name.
fn cc_id(signal: CcSignal) -> String {
    format!("cc_{}", signal.name())
}

/// The unit (VST3) or module (CLAP) a host files a parameter under, by id: the name of its
/// group of core's table ([`settings::GROUPS`]), `bypass` at the top. The declaration order
/// keeps each group one contiguous run (so the flat order hosts show stays the same).
pub fn unit_of(id: &str) -> &'static str {
    let group = match settings::find(id) {
        Some(s) => settings::group_of(s),
        None => plugin_only(id)
            .and_then(|(_, group, _)| settings::GROUPS.iter().find(|g| g.id == *group)),
    };
    group.map_or("", |g| g.name)
}

/// What the host sees: [`PneumaParams`] with every parameter filed under its [`unit_of`]
/// (VST3 units, CLAP modules). Values, ids, order and the persisted fields are the inner
/// struct's.
pub struct HostParams(pub Arc<PneumaParams>);

// `Params` is an unsafe trait: the pointers must stay valid while this object lives. They are
// the inner struct's own pointers, and this object holds the inner struct.
#[allow(unsafe_code)]
unsafe impl Params for HostParams {
    fn param_map(&self) -> Vec<(String, ParamPtr, String)> {
        self.0
            .param_map()
            .into_iter()
            .map(|(id, ptr, _)| {
                let unit = unit_of(&id).to_owned();
                (id, ptr, unit)
            })
            .collect()
    }

    fn serialize_fields(&self) -> std::collections::BTreeMap<String, String> {
        self.0.serialize_fields()
    }

    fn deserialize_fields(&self, serialized: &std::collections::BTreeMap<String, String>) {
        self.0.deserialize_fields(serialized)
    }
}

/// The plugin's parameters and persisted settings.
#[derive(Params)]
pub struct PneumaParams {
    /// The host's bypass switch: the audio passes delayed by the latency (so the track stays
    /// aligned), no breaths, and the controls go to rest. Default off.
    #[id = "bypass"]
    pub bypass: BoolParam,
    /// Breathing preset (custom, neutral, calm, anxious, tired, excited). Default custom.
    #[id = "preset"]
    pub preset: EnumParam<PresetChoice>,
    /// ThoraxVsAbdomen (the table's `thorax_vs_abdomen`).
    #[id = "thorax_vs_abdomen"]
    pub thorax_vs_abdomen: FloatParam,
    /// Lung capacity (the table's `capacity_lung`).
    #[id = "capacity_lung"]
    pub capacity_lung: FloatParam,
    /// MouthVsNose (the table's `mouth_vs_nose`).
    #[id = "mouth_vs_nose"]
    pub mouth_vs_nose: FloatParam,
    /// Breathing sound amplitude (the table's `breath_sound`).
    #[id = "breath_sound"]
    pub breath_sound: FloatParam,
    /// Opening of the inspiration channels (nostrils, mouth) (the table's `opening`).
    #[id = "opening"]
    pub opening: FloatParam,
    /// Speaking loudness (the table's `speaking_loudness`).
    #[id = "speaking_loudness"]
    pub speaking_loudness: FloatParam,
    /// Inspiration length of a full lung, seconds (the table's `inspiration_length_s`).
    #[id = "inspiration_length_s"]
    pub inspiration_length_s: FloatParam,
    /// Neck motion amplitude (head pitch at full lungs), degrees (the table's
    /// `neck_amplitude_deg`).
    #[id = "neck_amplitude_deg"]
    pub neck_amplitude_deg: FloatParam,

    /// Loudness of the inserted breaths, dB relative to the speech level (the table's
    /// `breath_level_db`).
    #[id = "breath_level_db"]
    pub breath_level_db: FloatParam,
    /// Insert breaths into the audio (off: audio passes, controls still leave) (the table's
    /// `insert_breaths`).
    #[id = "insert_breaths"]
    pub insert_breaths: BoolParam,
    /// Keeps the breath voice learned so far (or the built-in one, when nothing was learned)
    /// for every playback from now on, saved in the state as `breath_voice`; off: learning
    /// restarts. Read by the audio thread every block ([`crate::voice`]). Default off.
    #[id = "freeze_breath_voice"]
    pub freeze_breath_voice: BoolParam,
    /// Breaths only into pauses of speech (off: every pause, as `render --any-sound`). New
    /// engine (the table's `speech_only`).
    #[id = "speech_only"]
    pub speech_only: BoolParam,
    /// Shortest pause that gets a full breath, seconds (the table's `min_pause_s`).
    #[id = "min_pause_s"]
    pub min_pause_s: FloatParam,
    /// Lookahead (latency = lookahead) or live (zero latency). New engine (the table's `mode`).
    #[id = "mode"]
    pub mode: EnumParam<ModeChoice>,
    /// Lookahead length (= latency), seconds. New engine (the table's `lookahead_s`).
    #[id = "lookahead_s"]
    pub lookahead_s: FloatParam,

    /// Head-motion amount (0 = still) (the table's `head_amount`).
    #[id = "head_amount"]
    pub head_amount: FloatParam,
    /// Largest |head pitch|, degrees (the table's `head_max_pitch_deg`).
    #[id = "head_max_pitch_deg"]
    pub head_max_pitch_deg: FloatParam,
    /// Largest |head yaw|, degrees (the table's `head_max_yaw_deg`).
    #[id = "head_max_yaw_deg"]
    pub head_max_yaw_deg: FloatParam,
    /// Largest |head roll|, degrees (the table's `head_max_roll_deg`).
    #[id = "head_max_roll_deg"]
    pub head_max_roll_deg: FloatParam,

    /// Control frame rate, Hz. New engine (the table's `frame_rate_hz`).
    #[id = "frame_rate_hz"]
    pub frame_rate_hz: IntParam,

    /// Send MIDI CC. Default on.
    #[id = "midi_enabled"]
    pub midi_enabled: BoolParam,
    /// MIDI channel (the table's `midi_channel`).
    #[id = "midi_channel"]
    pub midi_channel: IntParam,
    /// 14-bit CC pairs (MSB on n, LSB on n + 32) instead of 7-bit (the table's `cc_14bit`).
    #[id = "cc_14bit"]
    pub cc_14bit: BoolParam,
    /// Head angle at the ends of the CC range, degrees (the table's `cc_head_range_deg`).
    #[id = "cc_head_range_deg"]
    pub cc_head_range_deg: FloatParam,
    /// Controller per signal, in [`CcSignal::ALL`] order; 0 = off, 1..119 (1..31 in 14-bit mode).
    #[id = "cc_lung"]
    pub cc_lung: IntParam,
    /// Controller for head pitch (0 = off). Default 16.
    #[id = "cc_head_pitch"]
    pub cc_head_pitch: IntParam,
    /// Controller for head yaw (0 = off). Default 17.
    #[id = "cc_head_yaw"]
    pub cc_head_yaw: IntParam,
    /// Controller for head roll (0 = off). Default 18.
    #[id = "cc_head_roll"]
    pub cc_head_roll: IntParam,
    /// Controller for thorax (0 = off). Default 19.
    #[id = "cc_thorax"]
    pub cc_thorax: IntParam,
    /// Controller for abdomen (0 = off). Default 20.
    #[id = "cc_abdomen"]
    pub cc_abdomen: IntParam,
    /// Controller for nostril flare (0 = off). Default 21.
    #[id = "cc_nostril_flare"]
    pub cc_nostril_flare: IntParam,
    /// Controller for mouth open (0 = off). Default 22.
    #[id = "cc_mouth_open"]
    pub cc_mouth_open: IntParam,
    /// Controller for neck pitch (0 = off). Default 23.
    #[id = "cc_neck_pitch"]
    pub cc_neck_pitch: IntParam,
    /// Controller for the speaking gate (0 = off). Default 24.
    #[id = "cc_speaking"]
    pub cc_speaking: IntParam,
    /// Controller for loudness (0 = off). Default 25.
    #[id = "cc_loudness"]
    pub cc_loudness: IntParam,

    /// Send OSC. Default off.
    #[id = "osc_enabled"]
    pub osc_enabled: BoolParam,
    /// OSC UDP port (the table's `osc_port`).
    #[id = "osc_port"]
    pub osc_port: IntParam,
    /// OSC format: pneuma or VMC (the table's `osc_format`).
    #[id = "osc_format"]
    pub osc_format: EnumParam<OscFormatChoice>,

    /// OSC target: a numeric IP address or `localhost` (names are not looked up). Default
    /// `127.0.0.1`. Persisted, not automatable.
    #[persist = "osc_host"]
    pub osc_host: Arc<RwLock<String>>,
    /// Path of a mouth breath WAV replacing the procedural mouth breath (empty = none).
    #[persist = "breath_sample_mouth"]
    pub breath_sample_mouth: SamplePath,
    /// Path of a nose breath WAV replacing the procedural nose breath (empty = none).
    #[persist = "breath_sample_nose"]
    pub breath_sample_nose: SamplePath,
    /// Path of a recording of the same speaker (the raw take before editing) the breath voice
    /// is learned from when an engine is built, as `render --breath-like` (empty = none: the
    /// voice is learned as the audio goes).
    #[persist = "breath_like"]
    pub breath_like: SamplePath,
    /// The frozen breath voice (`None`: not frozen), written by the audio thread.
    #[persist = "breath_voice"]
    pub breath_voice: breath_voice::SavedVoice,
    /// The editor window's size and zoom.
    #[persist = "editor_layout"]
    pub editor_layout: Arc<RwLock<layout::EditorLayout>>,

    /// Raised by the parameters' callbacks; taken by the audio thread.
    pub changes: Arc<ChangeFlags>,
}

/// What changed since the audio thread last looked: each flag is raised by a parameter callback
/// (any thread, also while a state is restored) and taken (`swap(false)`) by the audio thread.
#[derive(Debug, Default)]
pub struct ChangeFlags {
    /// An engine setting changed (breathing, placement, head).
    pub engine: AtomicBool,
    /// The CC map changed (channel, resolution, a controller, the head range).
    pub cc_map: AtomicBool,
    /// A setting that needs a new activation changed (`mode`, `lookahead_s`, `frame_rate_hz`).
    pub structure: AtomicBool,
}

impl ChangeFlags {
    /// Takes a flag: true if it was raised since the last take.
    pub fn take(flag: &AtomicBool) -> bool {
        flag.swap(false, Ordering::AcqRel)
    }

    /// Lowers every flag (at activation, where everything is read afresh).
    pub fn clear(&self) {
        for flag in [&self.engine, &self.cc_map, &self.structure] {
            flag.store(false, Ordering::Release);
        }
    }
}

/// Which flag a parameter raises.
#[derive(Debug, Clone, Copy)]
enum Raises {
    Engine,
    CcMap,
    /// Structure and engine: the engine keeps the settings it can apply live.
    Structure,
}

/// A value-change callback that raises `raises` in `flags`.
fn raise<T>(flags: &Arc<ChangeFlags>, raises: Raises) -> Arc<dyn Fn(T) + Send + Sync> {
    let flags = flags.clone();
    Arc::new(move |_| {
        match raises {
            Raises::Engine => {}
            Raises::CcMap => {
                flags.cc_map.store(true, Ordering::Release);
                return;
            }
            Raises::Structure => flags.structure.store(true, Ordering::Release),
        }
        flags.engine.store(true, Ordering::Release);
    })
}

/// A persisted file path (a breath sample, the breath-like recording) that counts its changes,
/// so the audio thread notices a restored state (a project or preset loaded while active)
/// without taking a lock and has an engine built that reads the new file ([`crate::rebuild`]).
#[derive(Debug, Default)]
pub struct SamplePath {
    path: RwLock<String>,
    generation: AtomicU64,
}

impl SamplePath {
    /// The path (empty = none). Takes a lock: not for the audio thread.
    pub fn get(&self) -> String {
        self.path.read().map(|p| p.clone()).unwrap_or_default()
    }

    /// Sets the path; a different path counts as a change.
    pub fn set_path(&self, path: String) {
        if let Ok(mut p) = self.path.write() {
            if *p != path {
                *p = path;
                self.generation.fetch_add(1, Ordering::Relaxed);
            }
        }
    }

    /// How many times the path was set (lock-free; for the audio thread).
    pub fn generation(&self) -> u64 {
        self.generation.load(Ordering::Relaxed)
    }
}

impl<'a> nice_plug::params::persist::PersistentField<'a, String> for SamplePath {
    fn set(&self, new_value: String) {
        self.set_path(new_value);
    }

    fn map<F, R>(&self, f: F) -> R
    where
        F: Fn(&String) -> R,
    {
        match self.path.read() {
            Ok(p) => f(&p),
            Err(poisoned) => f(&poisoned.into_inner()),
        }
    }
}

/// The parameter of a number of the table: its label, default, linear range, unit and step.
pub fn float_param(setting: &'static Setting) -> FloatParam {
    let step = match setting.kind {
        Kind::Number { step, .. } => step,
        Kind::Integer { .. } | Kind::Switch | Kind::Choice(_) => 1.0,
    };
    FloatParam::new(
        setting.label,
        setting.default,
        FloatRange::Linear {
            min: setting.min() as f32,
            max: setting.max() as f32,
        },
    )
    .with_unit(setting.unit.suffix())
    .with_step_size(step)
}

/// The whole-number parameter of a setting of the table (an integer, or a number stepped by
/// whole units such as the frame rate): its label, default, range and unit.
pub fn int_param(setting: &'static Setting, default: i32) -> IntParam {
    IntParam::new(
        setting.label,
        default,
        IntRange::Linear {
            min: setting.min() as i32,
            max: setting.max() as i32,
        },
    )
    .with_unit(setting.unit.suffix())
}

/// The switch parameter of a setting of the table: its label and default.
pub fn switch_param(setting: &'static Setting) -> BoolParam {
    BoolParam::new(setting.label, setting.default != 0.0)
}

/// The text of controller 0 (no controller) in the CC parameters.
pub const CC_OFF_TEXT: &str = "off";

fn cc_param(signal: CcSignal, flags: &Arc<ChangeFlags>) -> IntParam {
    let default = i32::from(CcSignal::DEFAULT_CONTROLLERS[signal.index()]);
    let name = format!("CC {}", signal.name().replace('_', " "));
    let max = i32::from(CcResolution::Bits7.max_controller());
    IntParam::new(name, default, IntRange::Linear { min: 0, max })
        .with_value_to_string(Arc::new(|v| {
            if v == 0 {
                CC_OFF_TEXT.to_owned()
            } else {
                v.to_string()
            }
        }))
        .with_string_to_value(Arc::new(parse_cc_text))
        .with_callback(raise(flags, Raises::CcMap))
}

/// Parses a CC parameter's text: `off` (any case) is 0, otherwise a controller number.
fn parse_cc_text(text: &str) -> Option<i32> {
    let text = text.trim();
    if text.eq_ignore_ascii_case(CC_OFF_TEXT) {
        Some(0)
    } else {
        text.parse().ok()
    }
}

impl Default for PneumaParams {
    fn default() -> Self {
        let flags = Arc::new(ChangeFlags::default());
        // A standalone program's defaults (live mode, OSC on); plugin hosts never set them.
        let app = standalone::app_defaults();
        let engine = |p: FloatParam| p.with_callback(raise(&flags, Raises::Engine));
        let cc_map = |p: FloatParam| p.with_callback(raise(&flags, Raises::CcMap));
        Self {
            bypass: BoolParam::new("Bypass", false)
                .make_bypass()
                .with_callback(raise(&flags, Raises::Engine)),
            preset: EnumParam::new("Breathing preset", PresetChoice::Custom)
                .with_callback(raise(&flags, Raises::Engine)),
            thorax_vs_abdomen: engine(float_param(&breathing::THORAX_VS_ABDOMEN)),
            capacity_lung: engine(float_param(&breathing::CAPACITY_LUNG)),
            mouth_vs_nose: engine(float_param(&breathing::MOUTH_VS_NOSE)),
            breath_sound: engine(float_param(&breathing::BREATH_SOUND)),
            opening: engine(float_param(&breathing::OPENING)),
            speaking_loudness: engine(float_param(&breathing::SPEAKING_LOUDNESS)),
            inspiration_length_s: engine(float_param(&breathing::INSPIRATION_LENGTH_S)),
            neck_amplitude_deg: engine(float_param(&breathing::NECK_AMPLITUDE_DEG)),
            breath_level_db: engine(float_param(&placement::BREATH_LEVEL_DB)),
            insert_breaths: switch_param(&placement::INSERT_BREATHS)
                .with_callback(raise(&flags, Raises::Engine)),
            freeze_breath_voice: BoolParam::new("Freeze breath voice", false),
            speech_only: switch_param(&placement::SPEECH_ONLY)
                .with_callback(raise(&flags, Raises::Structure)),
            min_pause_s: engine(float_param(&placement::MIN_PAUSE_S)),
            mode: EnumParam::new(
                placement::MODE.label,
                match app {
                    Some(a) if a.live => ModeChoice::Live,
                    _ => ModeChoice::from_index(placement::MODE.default as usize),
                },
            )
            .with_callback(raise(&flags, Raises::Structure)),
            lookahead_s: float_param(&placement::LOOKAHEAD_S)
                .with_callback(raise(&flags, Raises::Structure)),
            head_amount: engine(float_param(&head::HEAD_AMOUNT)),
            head_max_pitch_deg: engine(float_param(&head::HEAD_MAX_PITCH_DEG)),
            head_max_yaw_deg: engine(float_param(&head::HEAD_MAX_YAW_DEG)),
            head_max_roll_deg: engine(float_param(&head::HEAD_MAX_ROLL_DEG)),
            frame_rate_hz: int_param(
                &analysis::FRAME_RATE_HZ,
                analysis::FRAME_RATE_HZ.default as i32,
            )
            .with_callback(raise(&flags, Raises::Structure)),
            midi_enabled: BoolParam::new("CC output", true),
            midi_channel: int_param(&output::MIDI_CHANNEL, output::MIDI_CHANNEL.default as i32)
                .with_callback(raise(&flags, Raises::CcMap)),
            cc_14bit: switch_param(&output::CC_14BIT).with_callback(raise(&flags, Raises::CcMap)),
            cc_head_range_deg: cc_map(float_param(&output::CC_HEAD_RANGE_DEG)),
            cc_lung: cc_param(CcSignal::Lung, &flags),
            cc_head_pitch: cc_param(CcSignal::HeadPitch, &flags),
            cc_head_yaw: cc_param(CcSignal::HeadYaw, &flags),
            cc_head_roll: cc_param(CcSignal::HeadRoll, &flags),
            cc_thorax: cc_param(CcSignal::Thorax, &flags),
            cc_abdomen: cc_param(CcSignal::Abdomen, &flags),
            cc_nostril_flare: cc_param(CcSignal::NostrilFlare, &flags),
            cc_mouth_open: cc_param(CcSignal::MouthOpen, &flags),
            cc_neck_pitch: cc_param(CcSignal::NeckPitch, &flags),
            cc_speaking: cc_param(CcSignal::Speaking, &flags),
            cc_loudness: cc_param(CcSignal::Loudness, &flags),
            osc_enabled: BoolParam::new("OSC out", app.is_some()),
            osc_port: int_param(
                &output::OSC_PORT,
                i32::from(app.map_or(pneuma_osc::DEFAULT_OSC_PORT, |a| a.osc_port)),
            ),
            osc_format: EnumParam::new(
                output::OSC_FORMAT.label,
                app.map_or(
                    OscFormatChoice::from_index(output::OSC_FORMAT.default as usize),
                    |a| a.osc_format,
                ),
            ),
            osc_host: Arc::new(RwLock::new(
                app.map_or(pneuma_osc::DEFAULT_OSC_HOST, |a| a.osc_host.as_str())
                    .to_owned(),
            )),
            breath_sample_mouth: SamplePath::default(),
            breath_sample_nose: SamplePath::default(),
            breath_like: SamplePath::default(),
            breath_voice: breath_voice::SavedVoice::default(),
            editor_layout: Arc::default(),
            changes: flags,
        }
    }
}

impl PneumaParams {
    /// The CC parameters in [`CcSignal::ALL`] order.
    pub fn cc_params(&self) -> [&IntParam; SIGNAL_COUNT] {
        [
            &self.cc_lung,
            &self.cc_head_pitch,
            &self.cc_head_yaw,
            &self.cc_head_roll,
            &self.cc_thorax,
            &self.cc_abdomen,
            &self.cc_nostril_flare,
            &self.cc_mouth_open,
            &self.cc_neck_pitch,
            &self.cc_speaking,
            &self.cc_loudness,
        ]
    }

    /// The CC map the parameters describe (allocation-free). Controller 0 means off; in 14-bit
    /// mode a signal on a controller above 31 (which cannot carry an MSB/LSB pair) is off too. A
    /// map where two signals share a controller is invalid: the plugin then keeps its last valid
    /// map.
    pub fn cc_map(&self) -> CcMap {
        let resolution = if self.cc_14bit.value() {
            CcResolution::Bits14
        } else {
            CcResolution::Bits7
        };
        let mut controllers = [None; SIGNAL_COUNT];
        for (slot, p) in controllers.iter_mut().zip(self.cc_params()) {
            let v = p.value();
            let usable = v > 0 && v <= i32::from(resolution.max_controller());
            *slot = usable.then_some(v.clamp(0, 127) as u8);
        }
        CcMap {
            channel: (self.midi_channel.value() - 1).clamp(0, 15) as u8,
            resolution,
            controllers,
            head_range_deg: self.cc_head_range_deg.value(),
            ..CcMap::default()
        }
    }

    /// The breathing model's settings: the preset's, or the individual controls with preset
    /// `custom` (the independent settings the plugin does not expose keep their defaults).
    pub fn breathing_params(&self) -> BreathingParams {
        // `Custom` first, then the core's presets in the order of `Preset::ALL`.
        let preset = (self.preset.value().to_index())
            .checked_sub(1)
            .and_then(|i| Preset::ALL.get(i).copied());
        if let Some(p) = preset {
            return p.params();
        }
        BreathingParams {
            thorax_vs_abdomen: self.thorax_vs_abdomen.value(),
            capacity_lung: self.capacity_lung.value(),
            mouth_vs_nose: self.mouth_vs_nose.value(),
            amplitude_breathing_sound: self.breath_sound.value(),
            opening_inspiration_channels: self.opening.value(),
            speaking_loudness: self.speaking_loudness.value(),
            inspiration_length_s: self.inspiration_length_s.value(),
            neck_motion_amplitude_deg: self.neck_amplitude_deg.value(),
            ..BreathingParams::default()
        }
    }

    /// The engine settings the parameters describe; everything the plugin does not expose keeps
    /// [`EngineConfig::default`], so default parameters give exactly the CLI's default render.
    /// Allocation-free.
    pub fn engine_config(&self) -> EngineConfig {
        let mut config = EngineConfig::default();
        config.analysis.frame_rate_hz = f64::from(self.frame_rate_hz.value());
        config.placement.mode = match self.mode.value() {
            ModeChoice::Lookahead => PlacementMode::Lookahead,
            ModeChoice::Live => PlacementMode::Live,
        };
        config.placement.lookahead_s = self.lookahead_s.value();
        config.placement.min_pause_s = self.min_pause_s.value();
        config.placement.breath_level_db = self.breath_level_db.value();
        // Bypassed: the audio still goes through the delay line, without breaths.
        config.placement.insert_breaths = self.insert_breaths.value() && !self.bypass.value();
        config.placement.speech_only = self.speech_only.value();
        config.breathing = self.breathing_params();
        config.head = self.head_config();
        config
    }

    /// The head-motion settings (amount and limits; the rest keep their defaults).
    pub fn head_config(&self) -> HeadConfig {
        HeadConfig {
            amount: self.head_amount.value(),
            max_pitch_deg: self.head_max_pitch_deg.value(),
            max_yaw_deg: self.head_max_yaw_deg.value(),
            max_roll_deg: self.head_max_roll_deg.value(),
            ..HeadConfig::default()
        }
    }

    /// The OSC host (empty if the lock is poisoned or busy).
    pub fn osc_host(&self) -> String {
        self.osc_host.read().map(|h| h.clone()).unwrap_or_default()
    }
}

#[cfg(test)]
// The tests walk every parameter through nice-plug's `ParamPtr`, whose methods are `unsafe` (the
// pointer must not outlive its `PneumaParams`, which every test keeps alive).
#[allow(unsafe_code)]
mod tests;

//! [`Setting`]: what Pneuma knows about one setting (id, label, unit, range, default, scope,
//! help, why the range is what it is), the checks and text conversions every door shares, the
//! typed [`SettingError`], and [`Field`], which binds a setting to the field of a settings
//! struct that holds it (so validation and the string setters walk a table instead of a list
//! of field names).

use thiserror::Error;

/// The unit a setting's numbers are in.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Unit {
    /// A plain number (a ratio, a fraction 0..1, a count).
    None,
    /// Seconds.
    Seconds,
    /// Milliseconds (how the command line gives some settings held in seconds).
    Milliseconds,
    /// Hertz.
    Hertz,
    /// Decibels relative to another level.
    Decibels,
    /// Decibels relative to digital full scale.
    DecibelsFs,
    /// Percent.
    Percent,
    /// Degrees.
    Degrees,
    /// Degrees per second.
    DegreesPerSecond,
    /// Syllables.
    Syllables,
}

impl Unit {
    /// The text after a number: `" s"`, `" dB"`, `"°"`, `""`.
    pub const fn suffix(self) -> &'static str {
        match self {
            Unit::None => "",
            Unit::Seconds => " s",
            Unit::Milliseconds => " ms",
            Unit::Hertz => " Hz",
            Unit::Decibels => " dB",
            Unit::DecibelsFs => " dBFS",
            Unit::Percent => " %",
            Unit::Degrees => "°",
            Unit::DegreesPerSecond => "°/s",
            Unit::Syllables => " syllables",
        }
    }

    /// The factor that turns a number in `self` into one in `to` (1 for the same unit), or
    /// `None` when the units measure different things.
    pub fn factor_to(self, to: Unit) -> Option<f64> {
        match (self, to) {
            (a, b) if a == b => Some(1.0),
            (Unit::Seconds, Unit::Milliseconds) => Some(1000.0),
            (Unit::Milliseconds, Unit::Seconds) => Some(0.001),
            _ => None,
        }
    }
}

/// When a change of the setting takes effect in a running engine.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Scope {
    /// At once, without allocating (the live part of the engine's settings).
    Live,
    /// At the next `prepare`: it sizes or seeds the stream (the stream part).
    Stream,
}

/// What values a setting takes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Kind {
    /// A number in `min..=max`; `step` is the resolution a door shows and snaps to.
    Number {
        /// Lowest value.
        min: f32,
        /// Highest value.
        max: f32,
        /// Display and snapping step.
        step: f32,
    },
    /// A whole number in `min..=max`.
    Integer {
        /// Lowest value.
        min: i32,
        /// Highest value.
        max: i32,
    },
    /// On (1) or off (0).
    Switch,
    /// One of the names, held as its index.
    Choice(&'static [&'static str]),
}

/// One setting: the facts every door derives its option, parameter, check and text from.
#[derive(Debug, PartialEq)]
pub struct Setting {
    /// Stable id: the plugin's parameter id where the plugin has one (saved in host sessions),
    /// the string setters' name, the documentation's name.
    pub id: &'static str,
    /// Short name for people (the plugin parameter's name).
    pub label: &'static str,
    /// Unit of [`Setting::kind`]'s numbers and of [`Setting::default`].
    pub unit: Unit,
    /// The values it takes.
    pub kind: Kind,
    /// Default value (a switch: 0 or 1; a choice: the index).
    pub default: f32,
    /// A value outside the range that turns the feature off, if any (e.g. 0 for a filter).
    pub off: Option<f32>,
    /// When a change takes effect.
    pub scope: Scope,
    /// What it does, for help texts and the documentation.
    pub help: &'static str,
    /// Why the range is what it is.
    pub why: &'static str,
}

/// A bound one setting puts on another (`catch_breath_max_s` at least `catch_breath_min_s`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Relation {
    /// The words before the other setting's name: "at least", "at least 1.5 times".
    pub words: &'static str,
    /// The setting the bound comes from.
    pub other: &'static Setting,
}

/// A value refused by a setting; each message says what to give instead. Doors that show a
/// setting under another name or unit render it with [`SettingError::render`].
#[derive(Debug, Clone, PartialEq, Error)]
pub enum SettingError {
    /// The value lies outside the setting's range, or outside the narrower range another
    /// setting leaves it.
    #[error("{}", self.render(&|s| (s.id.to_owned(), s.unit)))]
    OutOfRange {
        /// The setting.
        setting: &'static Setting,
        /// The value given, in the setting's unit.
        value: f64,
        /// Lowest value allowed here.
        min: f64,
        /// Highest value allowed here.
        max: f64,
        /// Where `min` or `max` comes from another setting.
        relation: Option<Relation>,
    },
    /// The text is not a value of the setting.
    #[error("{}", self.render(&|s| (s.id.to_owned(), s.unit)))]
    NotAValue {
        /// The setting.
        setting: &'static Setting,
        /// The text given.
        text: String,
    },
    /// No setting has this id.
    #[error("unknown setting `{0}`: docs/settings.md lists every setting's id")]
    Unknown(String),
}

/// A range end as it is written in the table: the value of an `f32` end (`0.1` is held as
/// 0.10000000149…) at the 7 significant digits an `f32` keeps.
fn written(end: f64) -> f64 {
    if end == 0.0 || !end.is_finite() {
        return end;
    }
    let scale = 10f64.powi(6 - end.abs().log10().floor() as i32);
    (end * scale).round() / scale
}

/// A number as people read it: `300`, `0.015`, `-22`, to 6 significant digits (settings are
/// held as `f32`, whose noise beyond that a unit conversion would show).
pub fn show_number(value: f64) -> String {
    show_digits(value, 6)
}

/// `value` to `digits` significant digits, trailing zeros dropped.
fn show_digits(value: f64, digits: i32) -> String {
    if value == 0.0 || !value.is_finite() {
        return format!("{}", if value == 0.0 { 0.0 } else { value });
    }
    let decimals = (digits - 1 - value.abs().log10().floor() as i32).clamp(0, 15) as usize;
    let text = format!("{value:.decimals$}");
    let text = if text.contains('.') {
        text.trim_end_matches('0').trim_end_matches('.')
    } else {
        &text
    };
    if text == "-0" {
        "0".to_owned()
    } else {
        text.to_owned()
    }
}

impl SettingError {
    /// The message with each setting named and measured as `name` says (its name and the unit
    /// the door shows it in, e.g. `("--min-pause-ms", Unit::Milliseconds)`).
    pub fn render(&self, name: &dyn Fn(&'static Setting) -> (String, Unit)) -> String {
        match self {
            SettingError::OutOfRange {
                setting,
                value,
                min,
                max,
                relation,
            } => {
                let (label, unit) = name(setting);
                let scale = setting.unit.factor_to(unit).unwrap_or(1.0);
                let because = relation.map_or(String::new(), |r| {
                    format!(" ({} {})", r.words, name(r.other).0)
                });
                // A value just past an end is shown to the digits that tell it from the end.
                let ends = [min, max].map(|e| show_number(e * scale));
                let mut shown = show_number(value * scale);
                if ends.contains(&shown) {
                    shown = show_digits(value * scale, 12);
                }
                format!(
                    "{label} {shown}{} is out of range: use {}{because}",
                    unit.suffix(),
                    setting.range_text_within(*min, *max, unit)
                )
            }
            SettingError::NotAValue { setting, text } => {
                let (label, unit) = name(setting);
                format!("{label}: `{text}` is not {}", setting.expected(unit))
            }
            SettingError::Unknown(id) => {
                format!("unknown setting `{id}`: docs/settings.md lists every setting's id")
            }
        }
    }

    /// The setting the error is about, if any.
    pub fn setting(&self) -> Option<&'static Setting> {
        match self {
            SettingError::OutOfRange { setting, .. } | SettingError::NotAValue { setting, .. } => {
                Some(setting)
            }
            SettingError::Unknown(_) => None,
        }
    }
}

impl Setting {
    /// Lowest value (a switch 0, a choice 0).
    pub fn min(&self) -> f64 {
        match self.kind {
            Kind::Number { min, .. } => f64::from(min),
            Kind::Integer { min, .. } => f64::from(min),
            Kind::Switch | Kind::Choice(_) => 0.0,
        }
    }

    /// Highest value (a switch 1, a choice its last index).
    pub fn max(&self) -> f64 {
        match self.kind {
            Kind::Number { max, .. } => f64::from(max),
            Kind::Integer { max, .. } => f64::from(max),
            Kind::Switch => 1.0,
            Kind::Choice(names) => names.len().saturating_sub(1) as f64,
        }
    }

    /// The names of a choice (empty for other kinds).
    pub fn names(&self) -> &'static [&'static str] {
        match self.kind {
            Kind::Choice(names) => names,
            _ => &[],
        }
    }

    /// `Ok` when `value` is one the setting takes: its off value, or a finite value in the
    /// range (whole for integers, switches and choices). A value that is an `f32` (held in a
    /// config) is compared with the ends as `f32`s; any other as typed, before any narrowing,
    /// with the ends as written: `-5.9999999` is past `-6` although it is `-6.0` as an `f32`.
    pub fn check(&'static self, value: f64) -> Result<(), SettingError> {
        self.check_within(value, self.min(), self.max(), None)
    }

    /// [`Setting::check`] against `min..=max`, a range another setting narrowed (`relation`
    /// says which).
    pub fn check_within(
        &'static self,
        value: f64,
        min: f64,
        max: f64,
        relation: Option<Relation>,
    ) -> Result<(), SettingError> {
        if self.off.is_some_and(|off| f64::from(off) == value) {
            return Ok(());
        }
        let whole = !matches!(self.kind, Kind::Number { .. });
        // A value held as an `f32` (a config field, a plugin parameter) is checked against the
        // ends held so; any other against the ends as written.
        let (min, max) = if f64::from(value as f32) == value {
            (f64::from(min as f32), f64::from(max as f32))
        } else {
            (written(min), written(max))
        };
        // What a unit conversion adds (`700 ms` × 0.001 is 0.7000000000000001 s), and no more.
        let slack = 1e-12 * min.abs().max(max.abs());
        let inside = value.is_finite()
            && value >= min - slack
            && value <= max + slack
            && (!whole || value.fract() == 0.0);
        if inside {
            Ok(())
        } else {
            Err(SettingError::OutOfRange {
                setting: self,
                value,
                min,
                max,
                relation,
            })
        }
    }

    /// `value` clamped into the range (for code that must not fail on a value already checked).
    pub fn clamp(&self, value: f32) -> f32 {
        value.clamp(self.min() as f32, self.max() as f32)
    }

    /// The value `text` gives, in `unit` (e.g. milliseconds for a setting in seconds), checked:
    /// a number (a Unicode minus is a minus), `on`/`off` for a switch, a name for a choice.
    pub fn parse_in(&'static self, text: &str, unit: Unit) -> Result<f64, SettingError> {
        let t = text.trim();
        let not_a_value = || SettingError::NotAValue {
            setting: self,
            text: text.to_owned(),
        };
        let value = match self.kind {
            Kind::Switch => match t.to_ascii_lowercase().as_str() {
                "on" | "true" | "yes" | "1" => 1.0,
                "off" | "false" | "no" | "0" => 0.0,
                _ => return Err(not_a_value()),
            },
            Kind::Choice(names) => names
                .iter()
                .position(|n| n.eq_ignore_ascii_case(t))
                .ok_or_else(not_a_value)? as f64,
            Kind::Number { .. } | Kind::Integer { .. } => {
                let n: f64 = t
                    .replace('\u{2212}', "-")
                    .parse()
                    .map_err(|_| not_a_value())?;
                n * unit.factor_to(self.unit).ok_or_else(not_a_value)?
            }
        };
        self.check(value)?;
        Ok(value)
    }

    /// [`Setting::parse_in`] in the setting's own unit.
    pub fn parse(&'static self, text: &str) -> Result<f64, SettingError> {
        self.parse_in(text, self.unit)
    }

    /// `value` (in the setting's unit) as text in `unit`: `500 ms`, `on`, `live`.
    pub fn show_in(&self, value: f64, unit: Unit) -> String {
        match self.kind {
            Kind::Switch => (if value != 0.0 { "on" } else { "off" }).to_owned(),
            Kind::Choice(names) => names
                .get(value as usize)
                .map_or_else(|| show_number(value), |n| (*n).to_owned()),
            Kind::Number { .. } | Kind::Integer { .. } => {
                let scale = self.unit.factor_to(unit).unwrap_or(1.0);
                format!("{}{}", show_number(value * scale), unit.suffix())
            }
        }
    }

    /// The default as text in `unit`.
    pub fn default_text(&self, unit: Unit) -> String {
        self.show_in(f64::from(self.default), unit)
    }

    /// The values it takes, in words and in `unit`: `300 to 2000 ms`, `0 (off) or 500 to 3500
    /// Hz`, `on or off`, `lookahead or live`.
    pub fn range_text(&self, unit: Unit) -> String {
        self.range_text_within(self.min(), self.max(), unit)
    }

    fn range_text_within(&self, min: f64, max: f64, unit: Unit) -> String {
        match self.kind {
            Kind::Switch => "on or off".to_owned(),
            Kind::Choice(names) => match names.split_last() {
                Some((last, [])) => (*last).to_owned(),
                Some((last, rest)) => format!("{} or {last}", rest.join(", ")),
                None => String::new(),
            },
            Kind::Number { .. } | Kind::Integer { .. } => {
                let scale = self.unit.factor_to(unit).unwrap_or(1.0);
                let off = self.off.map_or(String::new(), |off| {
                    format!("{} (off) or ", show_number(f64::from(off) * scale))
                });
                format!(
                    "{off}{} to {}{}",
                    show_number(min * scale),
                    show_number(max * scale),
                    unit.suffix()
                )
            }
        }
    }

    /// What a text value must be, in words (for errors).
    fn expected(&self, unit: Unit) -> String {
        match self.kind {
            Kind::Switch => "on or off".to_owned(),
            Kind::Choice(_) => format!("one of {}", self.range_text(unit)),
            Kind::Number { .. } | Kind::Integer { .. } => {
                format!("a number: use {}", self.range_text(unit))
            }
        }
    }
}

/// Binds a [`Setting`] to the field of a settings struct `C` that holds it: the table behind
/// the struct's validation and string setter.
pub struct Field<C> {
    /// The setting.
    pub setting: &'static Setting,
    /// The field's value in the setting's unit (a switch 0 or 1, a choice its index).
    pub get: fn(&C) -> f64,
    /// Stores a value (already checked) into the field.
    pub set: fn(&mut C, f64),
}

/// Checks every field of `config` against its setting.
pub fn check_fields<C>(config: &C, fields: &[Field<C>]) -> Result<(), SettingError> {
    fields
        .iter()
        .try_for_each(|f| f.setting.check((f.get)(config)))
}

/// The field of the setting `id`, if `fields` holds it.
pub fn find_field<'a, C>(fields: &'a [Field<C>], id: &str) -> Option<&'a Field<C>> {
    fields.iter().find(|f| f.setting.id == id)
}

/// Sets the setting `id` of `config` to `value` (checked), when `fields` holds it: `None` when
/// it does not.
pub fn set_field<C>(
    config: &mut C,
    fields: &[Field<C>],
    id: &str,
    value: f64,
) -> Option<Result<(), SettingError>> {
    let field = find_field(fields, id)?;
    Some(
        field
            .setting
            .check(value)
            .map(|()| (field.set)(config, value)),
    )
}

/// Sets the setting `id` of `config` from text in the setting's unit.
pub fn set_field_text<C>(
    config: &mut C,
    fields: &[Field<C>],
    id: &str,
    text: &str,
) -> Result<(), SettingError> {
    let field = find_field(fields, id).ok_or_else(|| SettingError::Unknown(id.to_owned()))?;
    let value = field.setting.parse(text)?;
    (field.set)(config, value);
    Ok(())
}

/// Clamps every field of `config` into its setting's range; a value that is not finite gets
/// the default.
pub fn sanitize_fields<C>(config: &mut C, fields: &[Field<C>]) {
    for f in fields {
        let v = (f.get)(config);
        let s = f.setting;
        let sane = if v.is_finite() {
            v.clamp(s.min(), s.max())
        } else {
            f64::from(s.default)
        };
        (f.set)(config, sane);
    }
}

/// Copies the fields of `scope` from `from` into `to`.
pub fn copy_scope<C>(to: &mut C, from: &C, fields: &[Field<C>], scope: Scope) {
    for f in fields.iter().filter(|f| f.setting.scope == scope) {
        (f.set)(to, (f.get)(from));
    }
}

/// A [`Field`] for a numeric field: `field!(SETTING, name)` (the field is `f32` or `f64`), or
/// `field!(switch SETTING, name)` for a `bool` field.
macro_rules! field {
    (switch $setting:path, $name:ident) => {
        $crate::settings::setting::Field {
            setting: &$setting,
            get: |c| if c.$name { 1.0 } else { 0.0 },
            set: |c, v| c.$name = v != 0.0,
        }
    };
    ($setting:path, $name:ident) => {
        $crate::settings::setting::Field {
            setting: &$setting,
            get: |c| f64::from(c.$name),
            set: |c, v| c.$name = v as _,
        }
    };
}
pub(crate) use field;

#[cfg(test)]
mod tests {
    use super::*;
    use crate::settings::analysis::{FRAME_RATE_HZ, LOWPASS_HZ};
    use crate::settings::output::{MIDI_CHANNEL, OSC_FORMAT};
    use crate::settings::placement::{INSERT_BREATHS, LOOKAHEAD_S, MIN_PAUSE_S};

    #[test]
    fn values_are_read_in_the_unit_they_are_typed_in() {
        assert_eq!(LOOKAHEAD_S.parse_in("500", Unit::Milliseconds), Ok(0.5));
        assert_eq!(LOOKAHEAD_S.parse("0.5"), Ok(0.5));
        // The range's ends, typed in milliseconds, are in range (compared at f32 precision).
        assert!(MIN_PAUSE_S.parse_in("100", Unit::Milliseconds).is_ok());
        assert!(MIN_PAUSE_S.parse_in("2000", Unit::Milliseconds).is_ok());
        assert!(MIN_PAUSE_S.parse_in("2001", Unit::Milliseconds).is_err());
        assert_eq!(INSERT_BREATHS.parse(" Off "), Ok(0.0));
        assert_eq!(OSC_FORMAT.parse("VMC"), Ok(1.0));
        assert!(MIDI_CHANNEL.parse("1.5").is_err(), "whole numbers only");
        assert_eq!(LOWPASS_HZ.parse("0"), Ok(0.0), "the off value");
        assert!(LOWPASS_HZ.parse("100").is_err());
        assert!(FRAME_RATE_HZ.check(f64::NAN).is_err());
    }

    #[test]
    fn messages_name_the_setting_in_the_unit_it_is_shown_in() {
        let e = LOOKAHEAD_S.parse_in("0", Unit::Milliseconds).unwrap_err();
        assert_eq!(
            e.to_string(),
            "lookahead_s 0 s is out of range: use 0.3 to 2 s"
        );
        let as_typed = e.render(&|s| (format!("--{}", s.id.replace('_', "-")), Unit::Milliseconds));
        assert_eq!(
            as_typed,
            "--lookahead-s 0 ms is out of range: use 300 to 2000 ms"
        );
        let e = FRAME_RATE_HZ.parse("fast").unwrap_err();
        assert_eq!(
            e.to_string(),
            "frame_rate_hz: `fast` is not a number: use 30 to 240 Hz"
        );
        assert_eq!(
            LOWPASS_HZ.range_text(Unit::Hertz),
            "0 (off) or 500 to 3500 Hz"
        );
        assert_eq!(OSC_FORMAT.range_text(Unit::None), "pneuma or vmc");
        assert_eq!(MIN_PAUSE_S.default_text(Unit::Milliseconds), "250 ms");
        assert_eq!(INSERT_BREATHS.default_text(Unit::None), "on");
        assert_eq!(Unit::Seconds.factor_to(Unit::Hertz), None);
        for (x, text) in [
            (0.3_f32 as f64 * 100.0, "30"),
            (0.015_f32 as f64, "0.015"),
            (-22.0, "-22"),
            (36_000.0, "36000"),
            (0.59999996, "0.6"),
            (-0.0, "0"),
            (1234.5, "1234.5"),
        ] {
            assert_eq!(show_number(x), text, "{x}");
        }
    }

    #[test]
    fn a_value_just_past_an_end_is_refused_though_it_is_the_end_as_an_f32() {
        use crate::settings::placement::BREATH_LEVEL_DB;
        for (text, shown) in [("-5.9999999", "-5.9999999"), ("-40.0000001", "-40.0000001")] {
            assert_eq!(
                (text.parse::<f64>().unwrap() as f32),
                text.parse::<f32>().unwrap()
            );
            let e = BREATH_LEVEL_DB.parse(text).unwrap_err();
            assert_eq!(
                e.to_string(),
                format!("breath_level_db {shown} dB is out of range: use -40 to -6 dB")
            );
        }
        assert!(
            BREATH_LEVEL_DB.parse("-6.0000001").is_ok(),
            "inside the range"
        );
        let e = MIN_PAUSE_S
            .parse_in("2000.0001", Unit::Milliseconds)
            .unwrap_err();
        assert_eq!(
            e.to_string(),
            "min_pause_s 2.0000001 s is out of range: use 0.1 to 2 s"
        );
        // Every end of the table, typed in its own unit or in milliseconds, is in range.
        let numbers = crate::settings::table::all()
            .filter(|s| matches!(s.kind, Kind::Number { .. } | Kind::Integer { .. }));
        for s in numbers {
            for end in [s.min(), s.max()] {
                let typed = show_number(end);
                assert!(s.parse(&typed).is_ok(), "{} {typed}", s.id);
                if s.unit == Unit::Seconds {
                    let ms = show_number(end * 1000.0);
                    let got = s.parse_in(&ms, Unit::Milliseconds);
                    assert!(got.is_ok(), "{} {ms} ms", s.id);
                }
            }
        }
    }
}

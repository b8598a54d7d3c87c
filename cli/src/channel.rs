//! The one channel of a recording that `render --channel` and `analyze --channel` take: `left`,
//! `right` or a channel number from 1 (a multitrack recorder's track), and the error when the
//! input has no such channel.

/// A channel `--channel` picks: `left` (the first), `right` (the second) or its number from 1
/// (a multitrack recorder's track).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Channel(usize);

impl Channel {
    /// The first channel.
    pub const LEFT: Channel = Channel(0);
    /// The second channel.
    pub const RIGHT: Channel = Channel(1);

    /// Its index among the input's channels.
    pub fn index(self) -> usize {
        self.0
    }

    /// Parses `left`, `right` or a channel number from 1 (clap's value parser).
    pub fn parse(text: &str) -> Result<Self, String> {
        match text.trim().to_ascii_lowercase().as_str() {
            "left" => Ok(Self::LEFT),
            "right" => Ok(Self::RIGHT),
            t => match t.parse::<usize>() {
                Ok(n) if n >= 1 => Ok(Channel(n - 1)),
                _ => Err(format!(
                    "'{text}' is not a channel: use left, right or a channel number from 1"
                )),
            },
        }
    }

    /// The error when the input has only `channels` channels.
    pub fn missing(self, channels: usize, input: &str) -> String {
        format!(
            "--channel {self} needs {} channels, and {input} has {channels}: pick one of 1 to \
             {channels}, or drop --channel",
            self.0 + 1
        )
    }
}

impl std::fmt::Display for Channel {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match *self {
            Self::LEFT => f.write_str("left"),
            Self::RIGHT => f.write_str("right"),
            Channel(k) => write!(f, "{}", k + 1),
        }
    }
}

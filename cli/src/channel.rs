//! The one channel of a recording that `render --channel` and `analyze --channel` take: `left`,
//! `right` or a channel number from 1 (a multitrack recorder's track), and the error when the
//! input has no such channel.

/// A channel `--channel` picks: `left` (the first), `right` (the second) or its number from 1
/// (a multitrack recorder's track). It shows as it was typed: `right` stays `right`, `2`
/// stays `2`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Channel {
    /// Its index among the input's channels.
    index: usize,
    /// Typed as `left` or `right` rather than a number.
    named: bool,
}

impl Channel {
    /// The first channel, named `left`.
    pub const LEFT: Channel = Channel {
        index: 0,
        named: true,
    };
    /// The second channel, named `right`.
    pub const RIGHT: Channel = Channel {
        index: 1,
        named: true,
    };

    /// Its index among the input's channels.
    pub fn index(self) -> usize {
        self.index
    }

    /// Parses `left`, `right` or a channel number from 1 (clap's value parser).
    pub fn parse(text: &str) -> Result<Self, String> {
        match text.trim().to_ascii_lowercase().as_str() {
            "left" => Ok(Self::LEFT),
            "right" => Ok(Self::RIGHT),
            t => match t.parse::<usize>() {
                Ok(n) if n >= 1 => Ok(Channel {
                    index: n - 1,
                    named: false,
                }),
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
            self.index + 1
        )
    }
}

impl std::fmt::Display for Channel {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match (self.named, self.index) {
            (true, 0) => f.write_str("left"),
            (true, _) => f.write_str("right"),
            (false, k) => write!(f, "{}", k + 1),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_channel_shows_as_it_was_typed() {
        for typed in ["left", "right", "1", "2", "7"] {
            assert_eq!(Channel::parse(typed).unwrap().to_string(), typed);
        }
        assert_eq!(Channel::parse("2").unwrap().index(), Channel::RIGHT.index());
        let e = Channel::parse("2").unwrap().missing(1, "a.wav");
        assert!(e.starts_with("--channel 2 needs 2 channels"), "{e}");
    }
}

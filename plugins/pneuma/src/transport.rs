//! What the host's transport tells the plugin: starts and jumps of the play position (the
//! stream restarts, [`JumpDetector`]) and a silent pre-roll before the region's audio (the
//! stream starts with the audio, [`PreRoll`]).

/// Detects transport starts and jumps: the first playing block since the detector was made (an
/// activation: what the plugin heard while stopped must not shape the playback, or an export
/// would differ from `pneuma render`), and a playing block that does not start where the last
/// one ended (give or take `tolerance` samples: hosts that derive positions from beats or
/// seconds round them). A block at the same position as the one before is no jump: hosts that
/// compensate latency pre-roll with the position held (Ardour at time 0 feeds the region's first
/// samples while it reports 0), and a reset there would drop the audio already in the delay
/// line. Playing on from where the transport stopped is no jump either.
#[derive(Debug, Default)]
pub struct JumpDetector {
    expected_pos: Option<i64>,
    last_pos: Option<i64>,
    tolerance: i64,
}

impl JumpDetector {
    /// A detector that ignores position errors up to `tolerance` samples.
    pub fn new(tolerance: i64) -> Self {
        Self {
            expected_pos: None,
            last_pos: None,
            tolerance,
        }
    }

    /// True if this block starts the transport or jumps; remembers where it ends.
    pub fn check(&mut self, playing: bool, pos_samples: Option<i64>, block: usize) -> bool {
        let (true, Some(pos)) = (playing, pos_samples) else {
            // Stopped or unknown: keep the last end, so a restart elsewhere is a jump.
            return false;
        };
        let held = self.last_pos == Some(pos);
        let jumped = !held
            && self
                .expected_pos
                .is_none_or(|e| (e - pos).abs() > self.tolerance);
        self.expected_pos = Some(pos + block as i64);
        self.last_pos = Some(pos);
        jumped
    }
}

/// A silent pre-roll: hosts that compensate latency start playing early and feed each track
/// ahead by the plugin's latency `L`, so the input at position `-L` is the region's first sample
/// when the region starts at timeline 0 (Ardour 7: playback from -24 576 and export from
/// -25 344 samples with the 500 ms lookahead, region audio from -24 000 on). Before `-L` they
/// feed digital silence. An engine that heard that silence differs from one that starts with
/// the region (its frame clock, level trackers and breathing cycle ran on), so when the input
/// was exact zeros all the way to `-L`, the stream restarts there and the output equals
/// `pneuma render` of the region. Any sound before `-L` keeps the stream as it is.
#[derive(Debug, Default)]
pub struct PreRoll {
    /// Watching a pre-roll: whether all its input was exact zeros so far.
    silent: Option<bool>,
    /// Where the stream would start: minus the latency.
    start_pos: i64,
}

impl PreRoll {
    /// After a transport start or jump to `pos` with the plugin's `latency_samples`: a pre-roll
    /// is watched if the block starts before `-latency_samples`.
    pub fn start(&mut self, pos: Option<i64>, latency_samples: u32) {
        self.start_pos = -i64::from(latency_samples);
        self.silent = pos.is_some_and(|p| p < self.start_pos).then_some(true);
    }

    /// The transport stopped: no pre-roll any more.
    pub fn stop(&mut self) {
        self.silent = None;
    }

    /// For a playing block at `pos`: the offset in the block where the stream starts, if the
    /// pre-roll before it was silent (the stream restarts there); `None` otherwise. Reads the
    /// input only; never allocates.
    pub fn restart_at(&mut self, pos: Option<i64>, audio: &[&mut [f32]]) -> Option<usize> {
        let silent = self.silent?;
        let Some(pos) = pos else {
            self.silent = None;
            return None;
        };
        let len = audio.iter().map(|c| c.len()).min().unwrap_or(0);
        let before = usize::try_from(self.start_pos.saturating_sub(pos))
            .unwrap_or(0)
            .min(len);
        let silent = silent && audio.iter().all(|c| c[..before].iter().all(|&s| s == 0.0));
        if before < len || pos >= self.start_pos {
            self.silent = None;
            silent.then_some(before)
        } else {
            self.silent = Some(silent);
            None
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn transport_jumps_are_detected_only_while_playing() {
        let mut d = JumpDetector::new(2);
        assert!(!d.check(false, Some(0), 64), "stopped");
        assert!(
            d.check(true, Some(0), 64),
            "the first playing block starts afresh"
        );
        assert!(!d.check(true, Some(64), 64), "contiguous");
        assert!(
            !d.check(true, Some(129), 63),
            "one sample of rounding is no jump"
        );
        assert!(!d.check(true, Some(192), 872), "back on track");
        assert!(d.check(true, Some(1000), 64), "jump forward");
        assert!(!d.check(true, Some(1064), 32));
        assert!(!d.check(false, Some(5000), 32), "stopped: no reset");
        assert!(d.check(true, Some(5000), 32), "restart elsewhere is a jump");
        assert!(!d.check(true, None, 32), "no position: no jump");
        assert!(!d.check(true, Some(5032), 32));
        assert!(!d.check(false, Some(5064), 32), "stopped again");
        assert!(
            !d.check(true, Some(5064), 32),
            "playing on from there is no jump"
        );
        // A held position (latency pre-roll) is no jump, nor is the roll that follows it.
        let mut d = JumpDetector::new(2);
        assert!(d.check(true, Some(0), 512), "start");
        for _ in 0..4 {
            assert!(!d.check(true, Some(0), 512), "pre-roll held at 0");
        }
        assert!(!d.check(true, Some(512), 512), "rolling on");
        assert!(
            d.check(true, Some(0), 512),
            "back to 0 while rolling is a jump"
        );
    }

    #[test]
    fn a_silent_pre_roll_restarts_the_stream_where_the_audio_starts() {
        let block = |v: f32| vec![v; 8];
        // Silence from -20 on: the stream restarts where timeline 0 falls in the block.
        let mut p = PreRoll::default();
        p.start(Some(-20), 0);
        let (mut a, mut b) = (block(0.0), block(0.0));
        assert_eq!(p.restart_at(Some(-20), &[&mut a[..], &mut b[..]]), None);
        assert_eq!(p.restart_at(Some(-12), &[&mut a[..], &mut b[..]]), None);
        assert_eq!(p.restart_at(Some(-4), &[&mut a[..], &mut b[..]]), Some(4));
        assert_eq!(
            p.restart_at(Some(4), &[&mut a[..], &mut b[..]]),
            None,
            "once"
        );
        // A block that starts at 0 (the host split its cycle there).
        p.start(Some(-8), 0);
        assert_eq!(p.restart_at(Some(-8), &[&mut a[..]]), None);
        assert_eq!(p.restart_at(Some(0), &[&mut a[..]]), Some(0));
        // Sound before 0 (a host feeding the region early): no restart.
        p.start(Some(-16), 0);
        let mut loud = block(0.0);
        loud[7] = 0.5;
        assert_eq!(p.restart_at(Some(-16), &[&mut a[..], &mut loud[..]]), None);
        assert_eq!(p.restart_at(Some(-8), &[&mut a[..], &mut b[..]]), None);
        assert_eq!(p.restart_at(Some(0), &[&mut a[..], &mut b[..]]), None);
        // Sound after 0 in the crossing block does not count.
        p.start(Some(-4), 0);
        let mut late = block(0.0);
        late[4] = 0.5;
        assert_eq!(p.restart_at(Some(-4), &[&mut late[..]]), Some(4));
        // With a latency of 10 the stream starts at -10 (the host feeds the region ahead).
        p.start(Some(-16), 10);
        assert_eq!(p.restart_at(Some(-16), &[&mut a[..]]), Some(6));
        p.start(Some(-10), 10);
        assert_eq!(p.restart_at(Some(-10), &[&mut a[..]]), None, "no pre-roll");
        // Starting at or after the stream start, stopping, or losing the position: nothing
        // to watch.
        p.start(Some(0), 0);
        assert_eq!(p.restart_at(Some(0), &[&mut a[..]]), None);
        p.start(Some(-8), 0);
        p.stop();
        assert_eq!(p.restart_at(Some(0), &[&mut a[..]]), None);
        p.start(Some(-8), 0);
        assert_eq!(p.restart_at(None, &[&mut a[..]]), None);
        assert_eq!(p.restart_at(Some(0), &[&mut a[..]]), None);
    }
}

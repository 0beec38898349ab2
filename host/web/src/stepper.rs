//! The fixed 1 kHz physics schedule in a browser: each animation frame runs the match
//! ahead by the time that has passed since the last one, in whole 1 ms steps, and the
//! renderer draws between the two newest steps.
//!
//! A browser gives no thread that wakes every millisecond, so the steps of one frame run
//! together at its start: at 60 Hz about 17 of them. A stalled tab (a background tab,
//! a long garbage collection) would otherwise ask for thousands at once, so at most
//! [`MAX_CATCH_UP_STEPS`] run in one frame and the rest of the backlog is dropped: the
//! match slows down instead of freezing the page.

/// The physics step, s (the game's 1 kHz).
pub const STEP_S: f64 = 1e-3;

/// The most steps one frame runs, 1 ms each: 100 ms of match time, a frame of 10 fps.
pub const MAX_CATCH_UP_STEPS: u32 = 100;

/// How many fixed steps are due, from the elapsed frame times. See the [module](self).
#[derive(Debug, Clone, Default)]
pub struct Stepper {
    /// The clock reading of the last call, s (`None` before the first).
    last_s: Option<f64>,
    /// Time passed and not yet stepped, s, in `[0, STEP_S)` after each call.
    pending_s: f64,
    /// Steps dropped because a frame was later than [`MAX_CATCH_UP_STEPS`] allow.
    dropped: u64,
}

impl Stepper {
    /// A schedule that starts at the first call.
    pub fn new() -> Self {
        Self::default()
    }

    /// The number of 1 ms steps to run now, at clock reading `now_s` (seconds on any
    /// monotonic clock). The first call starts the clock and runs none; a clock that
    /// goes backwards or is not finite runs none and restarts from that reading.
    pub fn due(&mut self, now_s: f64) -> u32 {
        let Some(last) = self.last_s.filter(|l| now_s.is_finite() && now_s >= *l) else {
            self.last_s = now_s.is_finite().then_some(now_s);
            self.pending_s = 0.0;
            return 0;
        };
        self.last_s = Some(now_s);
        self.pending_s += now_s - last;
        let steps = (self.pending_s / STEP_S).floor();
        if steps > f64::from(MAX_CATCH_UP_STEPS) {
            self.dropped += (steps - f64::from(MAX_CATCH_UP_STEPS)) as u64;
            self.pending_s = 0.0;
            return MAX_CATCH_UP_STEPS;
        }
        self.pending_s -= steps * STEP_S;
        steps as u32
    }

    /// Steps dropped so far because frames came too late.
    pub fn dropped(&self) -> u64 {
        self.dropped
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn steps_follow_the_clock_in_whole_milliseconds() {
        let mut s = Stepper::new();
        assert_eq!(s.due(10.0), 0);
        // 60 Hz frames: 16.67 ms each; over a second exactly 1000 steps, never more.
        let mut total = 0;
        for i in 1..=60 {
            total += s.due(10.0 + f64::from(i) / 60.0);
        }
        assert!((999..=1000).contains(&total), "{total}");
        assert_eq!(s.dropped(), 0);
    }

    #[test]
    fn a_stalled_frame_runs_at_most_the_catch_up_and_drops_the_rest() {
        let mut s = Stepper::new();
        s.due(0.0);
        assert_eq!(s.due(5.0), MAX_CATCH_UP_STEPS);
        assert_eq!(s.dropped(), 5000 - u64::from(MAX_CATCH_UP_STEPS));
        // The backlog is gone: the next frame runs only its own time.
        assert_eq!(s.due(5.0105), 10);
    }

    #[test]
    fn a_clock_going_backwards_or_not_finite_runs_nothing() {
        let mut s = Stepper::new();
        s.due(1.0);
        assert_eq!(s.due(0.5), 0);
        assert_eq!(s.due(f64::NAN), 0);
        assert_eq!(s.due(0.6), 0);
        assert_eq!(s.due(0.603), 3);
    }
}

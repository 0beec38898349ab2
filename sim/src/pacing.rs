//! Real-time pacing: one report per wall-clock millisecond.
//!
//! The emulation runs much faster than real time; a pacer tells a real-time loop how
//! many reports are due by now, and when the next one is. If the loop falls far behind
//! (the process was stopped, the machine suspended), the pacer skips the lost wall time
//! instead of bursting out a backlog: emulated time pauses, no report is lost.

use std::time::{Duration, Instant};

/// One report period.
pub const REPORT_PERIOD: Duration = Duration::from_millis(1);

/// Counts reports due against the wall clock.
#[derive(Debug, Clone)]
pub struct RealTimePacer {
    origin: Instant,
    emitted: u64,
    max_backlog: u64,
}

impl RealTimePacer {
    /// A pacer starting now: the first report is due one period from now. At most
    /// `max_backlog` reports are ever due at once.
    pub fn new(max_backlog: u64) -> Self {
        Self::starting_at(Instant::now(), max_backlog)
    }

    /// A pacer whose period 0 starts at `origin`.
    pub fn starting_at(origin: Instant, max_backlog: u64) -> Self {
        Self {
            origin,
            emitted: 0,
            max_backlog: max_backlog.max(1),
        }
    }

    fn due_total(&self, now: Instant) -> u64 {
        let elapsed = now.saturating_duration_since(self.origin);
        (elapsed.as_micros() / REPORT_PERIOD.as_micros()) as u64
    }

    /// Reports due at `now` and not yet emitted (at most the backlog limit; beyond it
    /// the lost wall time is skipped).
    pub fn due(&mut self, now: Instant) -> u64 {
        let behind = self.due_total(now).saturating_sub(self.emitted);
        if behind > self.max_backlog {
            let skip = behind - self.max_backlog;
            self.origin += REPORT_PERIOD * u32::try_from(skip).unwrap_or(u32::MAX);
            return self.max_backlog;
        }
        behind
    }

    /// One report was emitted.
    pub fn emitted(&mut self) {
        self.emitted += 1;
    }

    /// When the next report is due.
    pub fn next_due_at(&self) -> Instant {
        self.origin + REPORT_PERIOD * u32::try_from(self.emitted + 1).unwrap_or(u32::MAX)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn counts_due_reports_and_skips_long_stalls() {
        let t0 = Instant::now();
        let mut p = RealTimePacer::starting_at(t0, 50);
        assert_eq!(p.due(t0), 0);
        assert_eq!(p.next_due_at(), t0 + Duration::from_millis(1));
        assert_eq!(p.due(t0 + Duration::from_micros(2_500)), 2);
        p.emitted();
        p.emitted();
        assert_eq!(p.due(t0 + Duration::from_micros(2_900)), 0);
        assert_eq!(p.next_due_at(), t0 + Duration::from_millis(3));
        // A 10 s stall: only the backlog limit is due, and the clock moves on.
        let later = t0 + Duration::from_secs(10);
        assert_eq!(p.due(later), 50);
        for _ in 0..50 {
            p.emitted();
        }
        assert_eq!(p.due(later), 0);
        assert!(p.next_due_at() > later);
    }
}

//! When settings the host changed are written to flash: as fast as the flash lasts.
//!
//! Settings are applied at once; writing them waits until they have stayed put for
//! [`QUIET_US`] (a tool sweeping a value makes one write, not one per step), or
//! [`MAX_DELAY_US`] after the first unsaved change (settings that never stop changing
//! are still kept), and never sooner than [`MIN_INTERVAL_US`] after the previous write.
//! At one write a second at most, a host that writes settings in a loop fills fewer
//! than a sector's records (113 of the board's 36-byte records in 4 KiB) in a minute,
//! so it causes at most one sector erase a minute. A flush (before a restart) writes
//! what is pending at once, whatever the schedule says.

/// How long the settings must stay unchanged before they are written, µs.
pub const QUIET_US: u64 = 500_000;

/// Longest an unsaved change waits for [`QUIET_US`], µs.
pub const MAX_DELAY_US: u64 = 5_000_000;

/// Shortest time between two writes, µs.
pub const MIN_INTERVAL_US: u64 = 1_000_000;

/// The schedule's state: the unsaved change, if any, and the last write. Times are
/// microseconds on any monotonic clock (the board's: since boot).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct SaveSchedule {
    /// The first and the latest unsaved change.
    pending: Option<(u64, u64)>,
    last_write: Option<u64>,
}

impl SaveSchedule {
    /// Nothing pending, nothing written yet.
    pub const fn new() -> Self {
        Self {
            pending: None,
            last_write: None,
        }
    }

    /// The settings changed at `now_us`.
    pub fn changed(&mut self, now_us: u64) {
        let first = self.pending.map_or(now_us, |(first, _)| first);
        self.pending = Some((first, now_us));
    }

    /// When the pending change is to be written (µs), `None` with nothing pending.
    pub fn due_at(&self) -> Option<u64> {
        let (first, latest) = self.pending?;
        let quiet = latest
            .saturating_add(QUIET_US)
            .min(first.saturating_add(MAX_DELAY_US));
        Some(
            self.last_write
                .map_or(quiet, |at| quiet.max(at.saturating_add(MIN_INTERVAL_US))),
        )
    }

    /// The pending settings were written (or found equal to those in flash) at `now_us`;
    /// `wrote`: the flash was written (a write that was skipped does not count against
    /// [`MIN_INTERVAL_US`]).
    pub fn done(&mut self, now_us: u64, wrote: bool) {
        self.pending = None;
        if wrote {
            self.last_write = Some(now_us);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_change_waits_for_quiet_and_a_burst_is_one_write() {
        let mut s = SaveSchedule::new();
        assert_eq!(s.due_at(), None);
        s.changed(1_000);
        assert_eq!(s.due_at(), Some(1_000 + QUIET_US));
        s.changed(200_000);
        assert_eq!(s.due_at(), Some(200_000 + QUIET_US));
        s.done(700_000, true);
        assert_eq!(s.due_at(), None);
        // The next change waits for quiet and for a second since the write.
        s.changed(800_000);
        assert_eq!(s.due_at(), Some(1_700_000));
    }

    #[test]
    fn changes_that_never_stop_are_written_after_the_longest_delay() {
        let mut s = SaveSchedule::new();
        for k in 0..200u64 {
            s.changed(k * 100_000);
        }
        assert_eq!(s.due_at(), Some(MAX_DELAY_US));
    }
}

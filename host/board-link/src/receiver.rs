//! Raw report bytes → [`InReport`], with link counters.

use foosball_protocol::{decode_in_report, InReport, ReportTiming};

use crate::{BoardError, LinkStats};

/// Decodes raw IN report bytes and keeps [`LinkStats`].
///
/// Lost reports are counted from gaps in the wrapping `u16` sequence number: after report
/// `n` the next is expected to be `n + 1` (65535 is followed by 0). A report whose
/// sequence is `n + 1 + k` counts `k` lost reports. A sequence that goes backwards (a
/// duplicate, or a jump of 32768 or more, which cannot be told apart from one within a
/// `u16`) counts nothing and restarts the expectation from that report.
///
/// Both report versions are read: version 1 (motion only) and version 2 (motion plus
/// the device time and per-paddle packet ages and drop counts, kept as
/// [`last_timing`](ReportReceiver::last_timing)).
///
/// After a reconnect, call [`ReportReceiver::note_reconnect`]: the board's sequence
/// carries on (or restarts) independently of what this side saw, so the next report only
/// re-synchronises the expectation and the jump is not counted as loss.
#[derive(Debug, Clone, Default)]
pub struct ReportReceiver {
    stats: LinkStats,
    /// Sequence number the next report should carry; `None` before the first report
    /// and after a reconnect.
    expected: Option<u16>,
    /// The timing of the last report, if it was version 2.
    timing: Option<ReportTiming>,
}

impl ReportReceiver {
    /// A receiver with zeroed counters, expecting any sequence number.
    pub fn new() -> Self {
        Self::default()
    }

    /// Decodes one report. A malformed one is counted and rejected with
    /// [`BoardError::Malformed`] naming the problem; the receiver stays usable, so the
    /// next good report is accepted.
    pub fn accept(&mut self, bytes: &[u8]) -> Result<InReport, BoardError> {
        let (report, timing) =
            decode_in_report(bytes).inspect_err(|_| self.stats.malformed += 1)?;
        self.timing = timing;
        self.stats.received += 1;
        if let Some(expected) = self.expected {
            let gap = report.sequence.wrapping_sub(expected);
            if gap < 0x8000 {
                self.stats.lost += u64::from(gap);
            }
        }
        self.expected = Some(report.sequence.wrapping_add(1));
        Ok(report)
    }

    /// The device time and per-paddle packet ages and drop counts of the last good
    /// report, `None` when it was version 1 (or before the first).
    pub fn last_timing(&self) -> Option<ReportTiming> {
        self.timing
    }

    /// The counters so far.
    pub fn stats(&self) -> LinkStats {
        self.stats
    }

    /// Records that the link came back: counts a reconnect and forgets the expected
    /// sequence number, so the jump to the board's current sequence is not loss.
    pub fn note_reconnect(&mut self) {
        self.stats.reconnects += 1;
        self.expected = None;
    }

    /// Sequence number the next report is expected to carry, if known.
    pub fn expected_sequence(&self) -> Option<u16> {
        self.expected
    }
}

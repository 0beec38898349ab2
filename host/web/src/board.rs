//! The board as the page sees it: raw IN reports handed over by the page (WebHID's
//! `inputreport` events, or the keyboard's emulated board), decoded by the protocol
//! crate's own decoder through [`ReportReceiver`], and OUT reports queued for the page
//! to send (`HIDDevice.sendReport`).
//!
//! Everything here is target-independent: the browser glue only moves bytes in and out.

use board_link::{Board, BoardError, LinkState, LinkStats, ReportReceiver};
use foosball_protocol::{InReport, OutReport, ReportTiming};
use std::collections::VecDeque;
use std::time::Duration;

/// The most IN reports kept waiting for the game, 250 ms of a 1 kHz board: a page that
/// stops drawing (a background tab) cannot make the queue grow without bound; the
/// oldest reports are dropped (and show as lost reports by their sequence numbers).
pub const MAX_QUEUED_REPORTS: usize = 250;

/// The most OUT reports kept waiting for the page to send.
pub const MAX_QUEUED_OUT: usize = 64;

/// The longest IN report accepted from the page, bytes; anything longer is malformed
/// without being copied.
pub const MAX_REPORT_LEN: usize = 64;

/// A [`Board`] fed with raw report bytes. See the [module](self).
#[derive(Debug)]
pub struct BrowserBoard {
    name: String,
    connected: bool,
    queue: VecDeque<Vec<u8>>,
    out: VecDeque<[u8; foosball_protocol::OUT_REPORT_LEN]>,
    receiver: ReportReceiver,
    sent: u64,
}

impl BrowserBoard {
    /// A board called `name` (shown on the board-lost screen), not connected yet.
    pub fn new(name: impl Into<String>) -> Self {
        Self {
            name: name.into(),
            connected: false,
            queue: VecDeque::new(),
            out: VecDeque::new(),
            receiver: ReportReceiver::new(),
            sent: 0,
        }
    }

    /// The device is open (`true`) or gone (`false`, e.g. WebHID's `disconnect`).
    /// Reports still queued when it goes are dropped.
    pub fn set_connected(&mut self, connected: bool) {
        if connected && !self.connected && self.receiver.stats().received > 0 {
            self.receiver.note_reconnect();
        }
        if !connected {
            self.queue.clear();
        }
        self.connected = connected;
    }

    /// Whether the device is open.
    pub fn is_connected(&self) -> bool {
        self.connected
    }

    /// Renames the board (a WebHID device's product name).
    pub fn set_name(&mut self, name: impl Into<String>) {
        self.name = name.into();
    }

    /// Queues one IN report's bytes as they arrived (without a report id). Over-long
    /// input is replaced by an empty report, which the decoder rejects as malformed.
    pub fn push_report(&mut self, bytes: &[u8]) {
        if self.queue.len() >= MAX_QUEUED_REPORTS {
            self.queue.pop_front();
        }
        let bytes = if bytes.len() > MAX_REPORT_LEN {
            &[][..]
        } else {
            bytes
        };
        self.queue.push_back(bytes.to_vec());
    }

    /// The next OUT report for the page to send, encoded.
    pub fn take_out_report(&mut self) -> Option<[u8; foosball_protocol::OUT_REPORT_LEN]> {
        self.out.pop_front()
    }

    /// OUT reports handed to the page so far (sent or queued).
    pub fn out_reports(&self) -> u64 {
        self.sent
    }
}

impl Board for BrowserBoard {
    fn name(&self) -> String {
        self.name.clone()
    }

    fn poll_report(&mut self, _timeout: Duration) -> Result<Option<InReport>, BoardError> {
        if !self.connected {
            return Err(BoardError::Disconnected);
        }
        match self.queue.pop_front() {
            Some(bytes) => self.receiver.accept(&bytes).map(Some),
            None => Ok(None),
        }
    }

    fn send(&mut self, report: &OutReport) -> Result<(), BoardError> {
        if !self.connected {
            return Err(BoardError::Disconnected);
        }
        if self.out.len() >= MAX_QUEUED_OUT {
            self.out.pop_front();
        }
        self.out.push_back(report.to_bytes());
        self.sent += 1;
        Ok(())
    }

    fn link_state(&self) -> LinkState {
        if self.connected {
            LinkState::Connected
        } else {
            LinkState::Disconnected
        }
    }

    fn stats(&self) -> LinkStats {
        self.receiver.stats()
    }

    fn last_timing(&self) -> Option<ReportTiming> {
        self.receiver.last_timing()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use foosball_protocol::{HapticPulse, LedState, PaddleMotion, PaddleStatus, PADDLES};

    fn report(sequence: u16, axial: i16) -> InReport {
        let mut paddles = [PaddleMotion::default(); PADDLES];
        paddles[0].axial = axial;
        paddles[0].status = PaddleStatus::PRESENT;
        InReport { sequence, paddles }
    }

    #[test]
    fn reports_pass_through_the_protocol_decoder() {
        let mut b = BrowserBoard::new("test");
        assert!(matches!(
            b.poll_report(Duration::ZERO),
            Err(BoardError::Disconnected)
        ));
        b.set_connected(true);
        b.push_report(&report(7, 40).to_bytes());
        b.push_report(&[1, 2, 3]);
        b.push_report(&[0u8; 200]);
        b.push_report(&report(9, -3).to_bytes());
        assert_eq!(b.poll_report(Duration::ZERO).unwrap(), Some(report(7, 40)));
        assert!(matches!(
            b.poll_report(Duration::ZERO),
            Err(BoardError::Malformed(_))
        ));
        assert!(matches!(
            b.poll_report(Duration::ZERO),
            Err(BoardError::Malformed(_))
        ));
        assert_eq!(b.poll_report(Duration::ZERO).unwrap(), Some(report(9, -3)));
        assert_eq!(b.poll_report(Duration::ZERO).unwrap(), None);
        let s = b.stats();
        assert_eq!((s.received, s.malformed, s.lost), (2, 2, 1));
    }

    #[test]
    fn the_queues_are_bounded_and_out_reports_are_encoded() {
        let mut b = BrowserBoard::new("test");
        b.set_connected(true);
        for i in 0..(MAX_QUEUED_REPORTS as u16 + 10) {
            b.push_report(&report(i, 1).to_bytes());
        }
        let first = b.poll_report(Duration::ZERO).unwrap().unwrap();
        assert_eq!(first.sequence, 10);
        let mut out = OutReport {
            haptics: [HapticPulse::default(); PADDLES],
            led: LedState::default(),
        };
        out.haptics[2] = HapticPulse {
            strength: 200,
            duration_ms: 30,
        };
        for _ in 0..MAX_QUEUED_OUT + 5 {
            b.send(&out).unwrap();
        }
        assert_eq!(b.out_reports(), MAX_QUEUED_OUT as u64 + 5);
        let bytes = b.take_out_report().unwrap();
        assert_eq!(OutReport::decode(&bytes).unwrap(), out);
        b.set_connected(false);
        assert!(b.send(&out).is_err());
        assert_eq!(b.link_state(), LinkState::Disconnected);
    }
}

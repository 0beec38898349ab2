//! The reconnecting link shared by [`crate::UsbBoard`] and [`crate::SocketBoard`]: the
//! transport-specific parts sit behind [`Connector`] and [`Transport`], so the state
//! machine (rate-limited reconnects, timeouts, counters) is tested without hardware.

use std::time::{Duration, Instant};

use foosball_protocol::{InReport, OutReport, ReportTiming};

use crate::socket_wire::MAX_PAYLOAD;
use crate::{BoardError, LinkState, LinkStats, ReportReceiver};

/// Buffer for one raw report (one interrupt packet / one frame payload).
pub(crate) type ReportBuf = [u8; MAX_PAYLOAD];

/// How a transfer on an open connection failed.
#[derive(Debug)]
pub(crate) enum TransportError {
    /// The peer is gone (unplugged, socket closed): drop the connection, report
    /// [`BoardError::Disconnected`].
    Gone,
    /// The connection is unusable (stream out of sync, version mismatch): drop it and
    /// report this error.
    Broken(BoardError),
    /// This transfer failed; the connection stays up.
    Transient(BoardError),
}

/// An open connection to a board.
pub(crate) trait Transport: Send {
    /// Name of the connected board.
    fn name(&self) -> String;
    /// Waits at most `timeout` for one raw IN report, copied into `buf`; returns its
    /// length, `None` on timeout.
    fn recv(
        &mut self,
        buf: &mut ReportBuf,
        timeout: Duration,
    ) -> Result<Option<usize>, TransportError>;
    /// Sends one raw OUT report.
    fn send(&mut self, bytes: &[u8]) -> Result<(), TransportError>;
}

/// Opens connections to a board.
pub(crate) trait Connector: Send {
    /// The connection type.
    type Transport: Transport;
    /// Name of the board while not connected.
    fn describe(&self) -> String;
    /// Tries once to open a connection.
    fn connect(&mut self) -> Result<Self::Transport, BoardError>;
    /// Whether a board has arrived since the last call (a hot-plug event, where the
    /// platform reports them): a disconnected link then tries at once, whatever its retry
    /// interval. Without events, `false`: the link looks again once per retry interval.
    fn arrived(&mut self) -> bool {
        false
    }
}

/// Time source, injectable for tests.
pub(crate) trait Clock: Send {
    fn now(&self) -> Instant;
    fn sleep(&self, duration: Duration);
}

/// The real clock.
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct SystemClock;

impl Clock for SystemClock {
    fn now(&self) -> Instant {
        Instant::now()
    }
    fn sleep(&self, duration: Duration) {
        std::thread::sleep(duration);
    }
}

/// A connection that comes and goes: the state machine behind the real boards.
pub(crate) struct Link<C: Connector, K: Clock = SystemClock> {
    connector: C,
    clock: K,
    transport: Option<C::Transport>,
    state: LinkState,
    receiver: ReportReceiver,
    retry_interval: Duration,
    /// When the last connection attempt was made; `None`: the next poll may try at once.
    last_attempt: Option<Instant>,
    ever_connected: bool,
    /// Why the last connection attempt failed, until one succeeds.
    last_connect_error: Option<BoardError>,
}

impl<C: Connector, K: Clock> Link<C, K> {
    /// A disconnected link; the first poll tries to connect.
    pub(crate) fn new(connector: C, clock: K, retry_interval: Duration) -> Self {
        Self {
            connector,
            clock,
            transport: None,
            state: LinkState::Disconnected,
            receiver: ReportReceiver::new(),
            retry_interval,
            last_attempt: None,
            ever_connected: false,
            last_connect_error: None,
        }
    }

    /// Tries to connect now, whatever the rate limit. On failure the error is kept
    /// ([`Link::last_connect_error`]) and `false` returned.
    fn try_connect(&mut self) -> bool {
        self.last_attempt = Some(self.clock.now());
        match self.connector.connect() {
            Ok(transport) => {
                self.on_connected(transport);
                true
            }
            Err(e) => {
                self.state = LinkState::Reconnecting;
                self.last_connect_error = Some(e);
                false
            }
        }
    }

    /// Tries to connect now, whatever the rate limit, returning the connector's error.
    pub(crate) fn connect_now(&mut self) -> Result<(), BoardError> {
        if self.try_connect() {
            Ok(())
        } else {
            Err(self
                .last_connect_error
                .take()
                .unwrap_or(BoardError::Disconnected))
        }
    }

    /// Why the last connection attempt failed, while not connected.
    pub(crate) fn last_connect_error(&self) -> Option<&BoardError> {
        self.last_connect_error.as_ref()
    }

    /// The open transport, connecting first if none is open;
    /// [`BoardError::Disconnected`] (or why connecting failed) otherwise.
    pub(crate) fn transport_mut(&mut self) -> Result<&mut C::Transport, BoardError> {
        if self.transport.is_none() {
            self.connect_now()?;
        }
        self.transport.as_mut().ok_or(BoardError::Disconnected)
    }

    fn on_connected(&mut self, transport: C::Transport) {
        if self.ever_connected {
            self.receiver.note_reconnect();
        }
        self.ever_connected = true;
        self.last_connect_error = None;
        self.transport = Some(transport);
        self.state = LinkState::Connected;
    }

    fn drop_transport(&mut self) {
        self.transport = None;
        self.state = LinkState::Disconnected;
        // Look again straight away on the next poll; rate-limit after that.
        self.last_attempt = None;
    }

    /// When the next connection attempt is due.
    fn next_attempt(&self) -> Option<Instant> {
        self.last_attempt.map(|at| at + self.retry_interval)
    }

    pub(crate) fn retry_interval(&self) -> Duration {
        self.retry_interval
    }

    pub(crate) fn set_retry_interval(&mut self, interval: Duration) {
        self.retry_interval = interval;
    }

    pub(crate) fn connector(&self) -> &C {
        &self.connector
    }

    pub(crate) fn connector_mut(&mut self) -> &mut C {
        &mut self.connector
    }

    /// The open transport, if any (no connection attempt).
    pub(crate) fn transport(&self) -> Option<&C::Transport> {
        self.transport.as_ref()
    }

    pub(crate) fn name(&self) -> String {
        match &self.transport {
            Some(transport) => transport.name(),
            None => self.connector.describe(),
        }
    }

    pub(crate) fn state(&self) -> LinkState {
        self.state
    }

    pub(crate) fn stats(&self) -> LinkStats {
        self.receiver.stats()
    }

    pub(crate) fn last_timing(&self) -> Option<ReportTiming> {
        self.receiver.last_timing()
    }

    pub(crate) fn poll_report(
        &mut self,
        timeout: Duration,
    ) -> Result<Option<InReport>, BoardError> {
        let start = self.clock.now();
        let deadline = start.checked_add(timeout);
        loop {
            let now = self.clock.now();
            let remaining = match deadline {
                Some(deadline) => deadline.saturating_duration_since(now),
                None => Duration::MAX,
            };
            let Some(transport) = self.transport.as_mut() else {
                let due =
                    self.connector.arrived() || self.next_attempt().is_none_or(|at| now >= at);
                if due && self.try_connect() {
                    continue;
                }
                if remaining.is_zero() {
                    return Err(BoardError::Disconnected);
                }
                let until_next = self
                    .next_attempt()
                    .map_or(Duration::ZERO, |at| at.saturating_duration_since(now));
                self.clock.sleep(until_next.min(remaining));
                continue;
            };
            let mut buf: ReportBuf = [0; MAX_PAYLOAD];
            return match transport.recv(&mut buf, remaining) {
                Ok(Some(len)) => self.receiver.accept(&buf[..len]).map(Some),
                Ok(None) => Ok(None),
                Err(TransportError::Gone) => {
                    self.drop_transport();
                    Err(BoardError::Disconnected)
                }
                Err(TransportError::Broken(e)) => {
                    self.drop_transport();
                    Err(e)
                }
                Err(TransportError::Transient(e)) => Err(e),
            };
        }
    }

    pub(crate) fn send(&mut self, report: &OutReport) -> Result<(), BoardError> {
        let Some(transport) = self.transport.as_mut() else {
            return Err(BoardError::Disconnected);
        };
        match transport.send(&report.to_bytes()) {
            Ok(()) => Ok(()),
            Err(TransportError::Gone) => {
                self.drop_transport();
                Err(BoardError::Disconnected)
            }
            Err(TransportError::Broken(e)) => {
                self.drop_transport();
                Err(e)
            }
            Err(TransportError::Transient(e)) => Err(e),
        }
    }
}

#[cfg(test)]
mod tests {
    use std::collections::VecDeque;
    use std::sync::{Arc, Mutex};

    use foosball_protocol::{DecodeError, IN_REPORT_LEN};

    use super::*;

    /// What a scripted transport does on the next `recv`.
    enum Step {
        Report(Vec<u8>),
        Nothing,
        Gone,
        Broken,
        Transient,
    }

    fn report(sequence: u16) -> Step {
        Step::Report(
            InReport {
                sequence,
                ..InReport::default()
            }
            .to_bytes()
            .to_vec(),
        )
    }

    #[derive(Default)]
    struct Shared {
        /// One script per connection, in connection order.
        scripts: VecDeque<VecDeque<Step>>,
        /// Connection attempts made, and the fake times they were made at.
        attempts: Vec<Instant>,
        /// Attempts that fail before a script is handed out.
        failures_before_next: usize,
        /// OUT reports sent.
        sent: Vec<Vec<u8>>,
        /// `send` reports the peer gone.
        send_gone: bool,
        /// Hot-plug arrivals not yet taken by the link.
        arrivals: usize,
    }

    #[derive(Clone)]
    struct FakeClock(Arc<Mutex<Instant>>);

    impl FakeClock {
        fn advance(&self, by: Duration) {
            *self.0.lock().unwrap() += by;
        }
    }

    impl Clock for FakeClock {
        fn now(&self) -> Instant {
            *self.0.lock().unwrap()
        }
        fn sleep(&self, duration: Duration) {
            self.advance(duration);
        }
    }

    struct MockConnector {
        shared: Arc<Mutex<Shared>>,
        clock: FakeClock,
    }

    struct MockTransport {
        shared: Arc<Mutex<Shared>>,
        script: VecDeque<Step>,
    }

    impl Connector for MockConnector {
        type Transport = MockTransport;
        fn describe(&self) -> String {
            "mock (not connected)".into()
        }
        fn connect(&mut self) -> Result<MockTransport, BoardError> {
            let mut shared = self.shared.lock().unwrap();
            shared.attempts.push(self.clock.now());
            if shared.failures_before_next > 0 {
                shared.failures_before_next -= 1;
                return Err(BoardError::NotFound { vid: 1, pid: 2 });
            }
            match shared.scripts.pop_front() {
                Some(script) => Ok(MockTransport {
                    shared: Arc::clone(&self.shared),
                    script,
                }),
                None => Err(BoardError::NotFound { vid: 1, pid: 2 }),
            }
        }
        fn arrived(&mut self) -> bool {
            let mut shared = self.shared.lock().unwrap();
            let arrived = shared.arrivals > 0;
            shared.arrivals = 0;
            arrived
        }
    }

    impl Transport for MockTransport {
        fn name(&self) -> String {
            "mock".into()
        }
        fn recv(
            &mut self,
            buf: &mut ReportBuf,
            _timeout: Duration,
        ) -> Result<Option<usize>, TransportError> {
            match self.script.pop_front().unwrap_or(Step::Nothing) {
                Step::Report(bytes) => {
                    buf[..bytes.len()].copy_from_slice(&bytes);
                    Ok(Some(bytes.len()))
                }
                Step::Nothing => Ok(None),
                Step::Gone => Err(TransportError::Gone),
                Step::Broken => Err(TransportError::Broken(BoardError::Usb("broken".into()))),
                Step::Transient => Err(TransportError::Transient(BoardError::Usb("flaky".into()))),
            }
        }
        fn send(&mut self, bytes: &[u8]) -> Result<(), TransportError> {
            let mut shared = self.shared.lock().unwrap();
            if shared.send_gone {
                return Err(TransportError::Gone);
            }
            shared.sent.push(bytes.to_vec());
            Ok(())
        }
    }

    const RETRY: Duration = Duration::from_millis(250);

    fn link(
        scripts: Vec<Vec<Step>>,
    ) -> (
        Link<MockConnector, FakeClock>,
        Arc<Mutex<Shared>>,
        FakeClock,
    ) {
        let shared = Arc::new(Mutex::new(Shared {
            scripts: scripts.into_iter().map(VecDeque::from).collect(),
            ..Shared::default()
        }));
        let clock = FakeClock(Arc::new(Mutex::new(Instant::now())));
        let connector = MockConnector {
            shared: Arc::clone(&shared),
            clock: clock.clone(),
        };
        (Link::new(connector, clock.clone(), RETRY), shared, clock)
    }

    fn sequence(result: Result<Option<InReport>, BoardError>) -> u16 {
        match result {
            Ok(Some(report)) => report.sequence,
            other => panic!("expected a report, got {other:?}"),
        }
    }

    #[test]
    fn reconnect_resynchronises_sequence_without_counting_loss() {
        let (mut link, _, _) = link(vec![
            vec![report(10), report(11), Step::Gone],
            vec![report(500), report(502)],
        ]);
        assert_eq!(link.state(), LinkState::Disconnected);
        assert_eq!(sequence(link.poll_report(Duration::ZERO)), 10);
        assert_eq!(link.state(), LinkState::Connected);
        assert_eq!(sequence(link.poll_report(Duration::ZERO)), 11);
        assert!(matches!(
            link.poll_report(Duration::ZERO),
            Err(BoardError::Disconnected)
        ));
        assert_eq!(link.state(), LinkState::Disconnected);
        // The first poll after the loss looks again at once.
        assert_eq!(sequence(link.poll_report(Duration::ZERO)), 500);
        assert_eq!(link.state(), LinkState::Connected);
        let stats = link.stats();
        assert_eq!((stats.received, stats.lost, stats.reconnects), (3, 0, 1));
        assert_eq!(sequence(link.poll_report(Duration::ZERO)), 502);
        assert_eq!(link.stats().lost, 1);
    }

    /// A hot-plug arrival makes the next poll look at once, inside the retry interval; only
    /// one look per arrival, and the rate limit holds again after it.
    #[test]
    fn a_hot_plug_arrival_is_looked_at_at_once() {
        let (mut link, shared, clock) = link(vec![]);
        let attempts = |shared: &Arc<Mutex<Shared>>| shared.lock().unwrap().attempts.len();
        assert!(link.poll_report(Duration::ZERO).is_err());
        assert_eq!(attempts(&shared), 1);
        clock.advance(Duration::from_millis(10));
        assert!(link.poll_report(Duration::ZERO).is_err());
        assert_eq!(attempts(&shared), 1, "rescanned with no arrival");
        // Something with the board's ids arrives, but cannot be opened yet.
        shared.lock().unwrap().arrivals = 1;
        assert!(link.poll_report(Duration::ZERO).is_err());
        assert_eq!(attempts(&shared), 2, "did not look at the arrival");
        assert!(link.poll_report(Duration::ZERO).is_err());
        assert_eq!(attempts(&shared), 2, "looked twice for one arrival");
        // The board arrives: connected on the next poll, 20 ms into the retry interval.
        clock.advance(Duration::from_millis(10));
        shared
            .lock()
            .unwrap()
            .scripts
            .push_back(VecDeque::from([report(7)]));
        shared.lock().unwrap().arrivals = 1;
        assert_eq!(sequence(link.poll_report(Duration::ZERO)), 7);
        assert_eq!(link.state(), LinkState::Connected);
        assert_eq!(attempts(&shared), 3);
    }

    #[test]
    fn rescans_are_rate_limited() {
        let (mut link, shared, clock) = link(vec![]);
        let attempts = |shared: &Arc<Mutex<Shared>>| shared.lock().unwrap().attempts.len();
        assert!(matches!(
            link.poll_report(Duration::ZERO),
            Err(BoardError::Disconnected)
        ));
        assert_eq!(attempts(&shared), 1);
        assert_eq!(link.state(), LinkState::Reconnecting);
        assert!(matches!(
            link.last_connect_error(),
            Some(BoardError::NotFound { vid: 1, pid: 2 })
        ));
        for _ in 0..10 {
            assert!(link.poll_report(Duration::ZERO).is_err());
        }
        clock.advance(Duration::from_millis(249));
        assert!(link.poll_report(Duration::ZERO).is_err());
        assert_eq!(attempts(&shared), 1, "rescanned before the retry interval");
        clock.advance(Duration::from_millis(1));
        assert!(link.poll_report(Duration::ZERO).is_err());
        assert_eq!(attempts(&shared), 2);
    }

    #[test]
    fn disconnected_poll_waits_out_its_timeout_retrying() {
        let (mut link, shared, clock) = link(vec![]);
        let start = clock.now();
        assert!(matches!(
            link.poll_report(Duration::from_secs(1)),
            Err(BoardError::Disconnected)
        ));
        assert_eq!(clock.now() - start, Duration::from_secs(1));
        let attempts: Vec<Duration> = shared
            .lock()
            .unwrap()
            .attempts
            .iter()
            .map(|at| *at - start)
            .collect();
        let expected: Vec<Duration> = (0..=4).map(|i| RETRY * i).collect();
        assert_eq!(attempts, expected);
    }

    #[test]
    fn reconnecting_within_a_poll_delivers_the_report() {
        let (mut link, shared, clock) = link(vec![vec![report(7)]]);
        shared.lock().unwrap().failures_before_next = 2;
        let start = clock.now();
        assert_eq!(sequence(link.poll_report(Duration::from_secs(10))), 7);
        assert_eq!(clock.now() - start, RETRY * 2);
        assert_eq!(link.state(), LinkState::Connected);
        assert!(link.last_connect_error().is_none());
        assert_eq!(
            link.stats().reconnects,
            0,
            "the first connection is no reconnect"
        );
    }

    #[test]
    fn malformed_report_is_dropped_and_play_goes_on() {
        let mut truncated = InReport::default().to_bytes().to_vec();
        truncated.truncate(5);
        let (mut link, _, _) = link(vec![vec![report(1), Step::Report(truncated), report(2)]]);
        assert_eq!(sequence(link.poll_report(Duration::ZERO)), 1);
        assert!(matches!(
            link.poll_report(Duration::ZERO),
            Err(BoardError::Malformed(DecodeError::WrongLength {
                expected: IN_REPORT_LEN,
                actual: 5
            }))
        ));
        assert_eq!(link.state(), LinkState::Connected);
        assert_eq!(sequence(link.poll_report(Duration::ZERO)), 2);
        let stats = link.stats();
        assert_eq!((stats.received, stats.malformed, stats.lost), (2, 1, 0));
    }

    #[test]
    fn transient_errors_keep_the_link_broken_ones_drop_it() {
        let (mut link, _, _) = link(vec![
            vec![Step::Transient, Step::Nothing, Step::Broken],
            vec![report(3)],
        ]);
        assert!(
            matches!(link.poll_report(Duration::ZERO), Err(BoardError::Usb(m)) if m == "flaky")
        );
        assert_eq!(link.state(), LinkState::Connected);
        assert!(matches!(link.poll_report(Duration::ZERO), Ok(None)));
        assert!(
            matches!(link.poll_report(Duration::ZERO), Err(BoardError::Usb(m)) if m == "broken")
        );
        assert_eq!(link.state(), LinkState::Disconnected);
        assert_eq!(sequence(link.poll_report(Duration::ZERO)), 3);
        assert_eq!(link.stats().reconnects, 1);
    }

    #[test]
    fn send_reaches_the_transport_and_fails_cleanly_when_gone() {
        let (mut link, shared, _) = link(vec![vec![]]);
        let out = OutReport::default();
        assert!(matches!(link.send(&out), Err(BoardError::Disconnected)));
        link.connect_now().unwrap();
        link.send(&out).unwrap();
        assert_eq!(shared.lock().unwrap().sent, vec![out.to_bytes().to_vec()]);
        shared.lock().unwrap().send_gone = true;
        assert!(matches!(link.send(&out), Err(BoardError::Disconnected)));
        assert_eq!(link.state(), LinkState::Disconnected);
        assert_eq!(link.name(), "mock (not connected)");
    }
}

//! Any [`Board`] → the newest pose and velocity of every rod of a table.
//!
//! [`PaddleTracker`] is the pure part: it takes IN reports (and link errors) and keeps,
//! per rod, the count sums of its paddle, turns them into a pose through the paddle's
//! [`PaddleCalibration`], and converts the paddle frame into the **table frame**
//! (slide along `+y`, angle about `+y`; see [`crate::table`]) with the rod's
//! [`Rod::handle_sign`]. [`BoardInput`] owns a board and a tracker and drains the board
//! once per physics step.
//!
//! * **Slide** is clamped to the rod's travel `±travel/2`. When the counts say the rod
//!   is beyond a stop, the stop is taken as the truth and the tracker shifts its origin
//!   (like a mouse pointer at the screen edge): drift from lost counts or calibration
//!   error is removed every time the player hits a stop.
//! * **Angle** is unbounded (turns accumulate).
//! * **Velocity** (m/s, rad/s) is the pose change over the last
//!   [`VELOCITY_WINDOW_MS`] ms of report time: the sensors send a packet every 5 ms, so
//!   per-report differences are spiky; the window smooths them at the cost of
//!   `VELOCITY_WINDOW_MS / 2` ms of lag. The physics drives rods by their pose; the
//!   velocity is the estimate for driven bodies and kicks.
//! * **Report time** advances by the sequence-number difference (1 ms per report), so
//!   lost reports (gaps) count as time without motion; their motion is lost, and
//!   [`RodInputs::lost_reports`] counts them.
//! * **Lost board** (a link-down error or a disconnected [`LinkState`]): poses are kept,
//!   velocities are zero, and [`RodInputs::health`] is [`InputHealth::BoardLost`] so play
//!   pauses or hands the rods to the computer. When reports flow again, tracking goes on
//!   from the kept poses.
//! * **Absent sensor** (no [`PaddleStatus::PRESENT`]): that rod keeps its pose with zero
//!   velocity and [`RodState::present`] is false.
//! * **Board time** ([`PaddleTracker::set_device_time_tracking`], off by default): when
//!   reports carry the board's timing (version 2), each packet's motion is placed at its
//!   time on the board's clock, the velocity is rebuilt from the packets on that clock
//!   and the pose carried to the report's time ([`super::tracker`]), in place of the
//!   report-time velocity and the fixed prediction horizon. Version 1 reports are
//!   tracked as before.

use super::calibration::{Calibration, PaddleCalibration};
use super::tracker::{DeviceClock, DeviceTrack};
use crate::table::{Rod, Table};
use board_link::{Board, BoardError, LinkState};
use foosball_protocol::{InReport, PaddleStatus, ReportTiming};
use serde::{Deserialize, Serialize};
use std::collections::VecDeque;
use std::time::Duration;

/// Longest pose prediction accepted, ms ([`PaddleTracker::set_prediction_ms`]).
pub const MAX_PREDICTION_MS: u64 = 20;

/// The prediction horizon that covers the mice's packet period (200 samples/s), ms.
pub const MOUSE_PACKET_PREDICTION_MS: u64 = 5;

/// The prediction lead that covers a packet's time on the PS/2 wire (3 bytes of 11
/// bits at 10–16.7 kHz, 2–3.3 ms), ms.
pub const PS2_WIRE_LEAD_MS: u64 = 2;

/// Length of the velocity estimate's window, ms of report time.
pub const VELOCITY_WINDOW_MS: u64 = 10;

/// The pose and velocity of one rod, table frame.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct RodState {
    /// Slide along `+y` from centred, m, within `±travel/2`.
    pub slide_m: f64,
    /// Angle about `+y`, rad, unbounded (0 = men hanging feet down).
    pub angle_rad: f64,
    /// Slide velocity, m/s.
    pub slide_velocity_m_per_s: f64,
    /// Angular velocity about `+y`, rad/s.
    pub angular_velocity_rad_per_s: f64,
    /// Whether the rod's sensor reported itself present in the latest report.
    pub present: bool,
}

/// Whether input is flowing.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum InputHealth {
    /// No report has arrived yet.
    Waiting,
    /// Reports arrive.
    Live,
    /// The board is gone: poses are the last known ones, play should pause or degrade.
    BoardLost,
}

/// The newest input for one physics step: every rod of the table, in table order.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RodInputs {
    /// Per rod of the table (same index as [`Table::rods`]).
    pub rods: Vec<RodState>,
    /// Whether the board is there.
    pub health: InputHealth,
    /// Report time, ms: sequence-number steps since the first report.
    pub time_ms: u64,
    /// Reports lost so far (sequence gaps).
    pub lost_reports: u64,
}

#[derive(Debug, Clone)]
struct RodTrack {
    port: usize,
    half_travel_m: f64,
    sign: f64,
    counts: [i64; 2],
    /// Origin shift in the paddle frame `[slide_m, angle_rad]` (stops, re-homing).
    bias: [f64; 2],
    /// `(time_ms, slide_m, angle_rad)` over the velocity window, paddle frame.
    history: VecDeque<(u64, f64, f64)>,
    /// Report time of the latest report whose counts moved this rod, ms.
    last_motion_ms: u64,
    /// The packets on the board's clock (version 2 reports).
    device: DeviceTrack,
    state: RodState,
}

impl RodTrack {
    fn new(rod: &Rod) -> Self {
        Self {
            port: rod.port,
            half_travel_m: rod.half_travel_m(),
            sign: rod.handle_sign(),
            counts: [0; 2],
            bias: [0.0; 2],
            history: VecDeque::with_capacity(VELOCITY_WINDOW_MS as usize + 2),
            last_motion_ms: 0,
            device: DeviceTrack::default(),
            state: RodState::default(),
        }
    }

    /// Paddle-frame pose from the counts, clamped to the travel (shifting the origin).
    fn paddle_pose(&mut self, cal: &PaddleCalibration) -> [f64; 2] {
        let raw = cal.apply([self.counts[0] as f64, self.counts[1] as f64]);
        let mut slide = raw[0] + self.bias[0];
        let clamped = slide.clamp(-self.half_travel_m, self.half_travel_m);
        if clamped != slide {
            self.bias[0] += clamped - slide;
            slide = clamped;
        }
        [slide, raw[1] + self.bias[1]]
    }

    fn update(&mut self, cal: &PaddleCalibration, time_ms: u64) {
        let [slide, angle] = self.paddle_pose(cal);
        self.history.push_back((time_ms, slide, angle));
        while self
            .history
            .front()
            .is_some_and(|&(t, _, _)| t + VELOCITY_WINDOW_MS < time_ms)
        {
            self.history.pop_front();
        }
        let (v_slide, v_angle) = match self.history.front() {
            Some(&(t0, s0, a0)) if t0 < time_ms => {
                let dt = (time_ms - t0) as f64 * 1e-3;
                ((slide - s0) / dt, (angle - a0) / dt)
            }
            _ => (0.0, 0.0),
        };
        self.state.slide_m = self.sign * slide;
        self.state.angle_rad = self.sign * angle;
        self.state.slide_velocity_m_per_s = self.sign * v_slide;
        self.state.angular_velocity_rad_per_s = self.sign * v_angle;
    }

    /// The pose in the paddle frame, as the counts give it now.
    fn paddle_frame_pose(&self) -> [f64; 2] {
        [
            self.sign * self.state.slide_m,
            self.sign * self.state.angle_rad,
        ]
    }

    fn freeze(&mut self) {
        self.history.clear();
        self.device.clear();
        self.state.slide_velocity_m_per_s = 0.0;
        self.state.angular_velocity_rad_per_s = 0.0;
    }
}

/// Reports (and link errors) → rod states. Pure: no board, no clock.
#[derive(Debug, Clone)]
pub struct PaddleTracker {
    calibration: Calibration,
    rods: Vec<RodTrack>,
    last_sequence: Option<u16>,
    time_ms: u64,
    lost_reports: u64,
    health: InputHealth,
    prediction_ms: u64,
    prediction_lead_ms: u64,
    /// Whether timed reports are tracked on the board's clock.
    device_time: bool,
    /// The board's clock, unwrapped.
    clock: DeviceClock,
    /// Whether the latest report was tracked on the board's clock.
    timed: bool,
}

impl PaddleTracker {
    /// A tracker for `table`'s rods with `calibration`. Every rod starts at its
    /// calibration's offset pose (centred and upright with the defaults).
    pub fn new(table: &Table, calibration: Calibration) -> Self {
        let mut tracker = Self {
            calibration,
            rods: table.rods.iter().map(RodTrack::new).collect(),
            last_sequence: None,
            time_ms: 0,
            lost_reports: 0,
            health: InputHealth::Waiting,
            prediction_ms: 0,
            prediction_lead_ms: 0,
            device_time: false,
            clock: DeviceClock::default(),
            timed: false,
        };
        for rod in &mut tracker.rods {
            let cal = tracker.calibration.paddles[rod.port];
            rod.update(&cal, 0);
            rod.freeze();
        }
        tracker
    }

    /// Takes one IN report without timing (version 1).
    pub fn apply_report(&mut self, report: &InReport) {
        self.apply_timed_report(report, None);
    }

    /// Takes one IN report with its timing when the board sent version 2
    /// ([`board_link::Board::last_timing`]); with board-time tracking on
    /// ([`PaddleTracker::set_device_time_tracking`]) the timing places each packet's
    /// motion on the board's clock.
    pub fn apply_timed_report(&mut self, report: &InReport, timing: Option<&ReportTiming>) {
        let dt = match self.last_sequence {
            Some(last) => {
                let d = u64::from(report.sequence.wrapping_sub(last));
                if d == 0 {
                    // A repeated sequence number: count it as the next report.
                    1
                } else {
                    self.lost_reports += d - 1;
                    d
                }
            }
            None => 0,
        };
        self.last_sequence = Some(report.sequence);
        self.time_ms += dt;
        self.health = InputHealth::Live;
        let timing = timing.filter(|_| self.device_time);
        if let Some(timing) = timing {
            if !self.clock.advance(timing.device_time_us) {
                // The board restarted: its earlier packets are on another clock.
                for rod in &mut self.rods {
                    rod.device.clear();
                }
            }
        }
        self.timed = timing.is_some();
        let now_us = self.clock.now_us();
        for rod in &mut self.rods {
            let paddle = report.paddles[rod.port];
            rod.state.present = paddle.status.contains(PaddleStatus::PRESENT);
            if !rod.state.present {
                rod.freeze();
                continue;
            }
            rod.counts[0] += i64::from(paddle.axial);
            rod.counts[1] += i64::from(paddle.rotation);
            if paddle.axial != 0 || paddle.rotation != 0 {
                rod.last_motion_ms = self.time_ms;
            }
            let cal = self.calibration.paddles[rod.port];
            rod.update(&cal, self.time_ms);
            if let Some(timing) = timing {
                let age = timing.paddles[rod.port].newest_packet_age.as_micros();
                let pose = rod.paddle_frame_pose();
                rod.device.observe(now_us, age, pose);
            }
        }
    }

    /// Takes a failed poll: a link-down error marks the board lost (poses kept,
    /// velocities zero); a malformed report or a passing error changes nothing.
    pub fn apply_error(&mut self, error: &BoardError) {
        if error.is_link_down() {
            self.mark_lost();
        }
    }

    /// Takes the board's link state: anything but connected marks the board lost.
    pub fn apply_link_state(&mut self, state: LinkState) {
        if !state.is_connected() {
            self.mark_lost();
        }
    }

    fn mark_lost(&mut self) {
        if self.health != InputHealth::BoardLost {
            self.health = InputHealth::BoardLost;
            for rod in &mut self.rods {
                rod.freeze();
            }
        }
        // The board restarts its sequence after a reconnect: no gap across it.
        self.last_sequence = None;
    }

    /// Declares rod `rod`'s current table-frame pose to be `slide_m`, `angle_rad` (the
    /// player holds it at a known place: a stop, men upright).
    pub fn rehome(&mut self, rod: usize, slide_m: f64, angle_rad: f64) {
        let Some(track) = self.rods.get_mut(rod) else {
            return;
        };
        let cal = self.calibration.paddles[track.port];
        let raw = cal.apply([track.counts[0] as f64, track.counts[1] as f64]);
        track.bias = [
            track.sign * slide_m - raw[0],
            track.sign * angle_rad - raw[1],
        ];
        track.update(&cal, self.time_ms);
        track.freeze();
    }

    /// Tracks timed (version 2) reports on the board's clock (off by default): each
    /// packet's motion at its board time, the velocity rebuilt from the packets, the
    /// pose carried to the report's time ([`super::tracker`]). The fixed prediction
    /// ([`PaddleTracker::set_prediction_ms`]) then applies only to untimed reports.
    pub fn set_device_time_tracking(&mut self, on: bool) {
        self.device_time = on;
        if !on {
            self.timed = false;
        }
    }

    /// Whether the newest report was tracked on the board's clock.
    pub fn is_device_timed(&self) -> bool {
        self.timed
    }

    /// Predicts poses up to `ms` milliseconds ahead (0 = off, the default): see
    /// [`PaddleTracker::inputs`].
    pub fn set_prediction_ms(&mut self, ms: u64) {
        self.prediction_ms = ms.min(MAX_PREDICTION_MS);
    }

    /// Adds a constant `ms` to the prediction of a moving rod (0 = none, the default):
    /// the transport delay of the counts themselves (a PS/2 packet takes ~2.5 ms on the
    /// wire after the mouse sampled the motion). Only with a prediction horizon.
    pub fn set_prediction_lead_ms(&mut self, ms: u64) {
        self.prediction_lead_ms = ms.min(MAX_PREDICTION_MS);
    }

    /// The prediction horizon, ms (0 = off).
    pub fn prediction_ms(&self) -> u64 {
        self.prediction_ms
    }

    /// The newest state of every rod.
    ///
    /// With a prediction horizon ([`PaddleTracker::set_prediction_ms`]) the pose of a
    /// moving rod is carried forward by its velocity over the time since its counts
    /// last moved (at most the horizon): the mice send a packet every 5 ms, so between
    /// packets the measured pose stands still while the rod moves on. At constant speed
    /// this removes the packet delay from the input-to-rod latency; when the rod stops,
    /// the pose overshoots by at most `velocity × horizon` for a few ms (the velocity
    /// window then sees the stop). The slide stays within the travel.
    pub fn inputs(&self) -> RodInputs {
        RodInputs {
            rods: self.rods.iter().map(|r| self.predicted(r)).collect(),
            health: self.health,
            time_ms: self.time_ms,
            lost_reports: self.lost_reports,
        }
    }

    /// The state of rod `rod` (predicted as in [`PaddleTracker::inputs`]).
    pub fn rod(&self, rod: usize) -> Option<RodState> {
        self.rods.get(rod).map(|r| self.predicted(r))
    }

    fn predicted(&self, r: &RodTrack) -> RodState {
        let mut state = r.state;
        if self.health != InputHealth::Live || !state.present {
            return state;
        }
        if self.timed {
            let (pose, velocity) = r
                .device
                .estimate(self.clock.now_us(), r.paddle_frame_pose());
            state.slide_m = (r.sign * pose[0]).clamp(-r.half_travel_m, r.half_travel_m);
            state.angle_rad = r.sign * pose[1];
            state.slide_velocity_m_per_s = r.sign * velocity[0];
            state.angular_velocity_rad_per_s = r.sign * velocity[1];
            return state;
        }
        if self.prediction_ms == 0 {
            return state;
        }
        let age_ms = self
            .time_ms
            .saturating_sub(r.last_motion_ms)
            .min(self.prediction_ms)
            + self.prediction_lead_ms;
        let age_s = age_ms as f64 * 1e-3;
        state.slide_m = (state.slide_m + state.slide_velocity_m_per_s * age_s)
            .clamp(-r.half_travel_m, r.half_travel_m);
        state.angle_rad += state.angular_velocity_rad_per_s * age_s;
        state
    }

    /// Whether input flows.
    pub fn health(&self) -> InputHealth {
        self.health
    }

    /// The calibration in use.
    pub fn calibration(&self) -> &Calibration {
        &self.calibration
    }
}

/// A board and its tracker: what the match loop polls once per physics step.
pub struct BoardInput<B: Board> {
    board: B,
    tracker: PaddleTracker,
    malformed: u64,
}

impl<B: Board> BoardInput<B> {
    /// Tracks `table`'s rods from `board` with `calibration`.
    pub fn new(board: B, table: &Table, calibration: Calibration) -> Self {
        Self {
            board,
            tracker: PaddleTracker::new(table, calibration),
            malformed: 0,
        }
    }

    /// Takes up to `max_reports` reports that are ready (without waiting) and returns
    /// the newest rod states. A real-time board delivers about one per millisecond, so
    /// a 1 kHz loop calls this with a small cap (it drains a backlog after a stall); a
    /// lockstep emulated board delivers one per poll, so `max_reports = 1` advances it
    /// exactly one millisecond per step.
    pub fn poll(&mut self, max_reports: usize) -> RodInputs {
        self.poll_each(max_reports, |_| {})
    }

    /// [`BoardInput::poll`], handing each report taken to `each` as well, before the
    /// tracker applies it (calibration mode reads the raw counts this way).
    pub fn poll_each(&mut self, max_reports: usize, mut each: impl FnMut(&InReport)) -> RodInputs {
        let mut taken = 0;
        while taken < max_reports {
            match self.board.poll_report(Duration::ZERO) {
                Ok(Some(report)) => {
                    each(&report);
                    let timing = self.board.last_timing();
                    self.tracker.apply_timed_report(&report, timing.as_ref());
                    taken += 1;
                }
                Ok(None) => break,
                Err(BoardError::Malformed(_)) => {
                    self.malformed += 1;
                    taken += 1;
                }
                Err(e) => {
                    self.tracker.apply_error(&e);
                    break;
                }
            }
        }
        if taken == 0 {
            self.tracker.apply_link_state(self.board.link_state());
        }
        self.tracker.inputs()
    }

    /// The tracker (rehoming, the newest states).
    pub fn tracker_mut(&mut self) -> &mut PaddleTracker {
        &mut self.tracker
    }

    /// The tracker.
    pub fn tracker(&self) -> &PaddleTracker {
        &self.tracker
    }

    /// The board (to send haptics, read statistics).
    pub fn board_mut(&mut self) -> &mut B {
        &mut self.board
    }

    /// Malformed reports dropped so far.
    pub fn malformed(&self) -> u64 {
        self.malformed
    }
}

//! Rod motion on the board's clock: what a version 2 IN report's timing lets the
//! tracker do ([`super::paddles::PaddleTracker::set_device_time_tracking`]).
//!
//! A v2 report carries the board's time of its snapshot (µs) and, per paddle, how long
//! before it the paddle's newest PS/2 packet ended. So each packet's motion has a time
//! on the board's clock: the packet's end (report time − packet age) less the time the
//! packet spent on the wire after the mouse sampled it ([`PS2_PACKET_WIRE_US`]). Per
//! rod, [`DeviceTrack`] keeps the poses at those times, rebuilds the velocity from the
//! packets (one every 5 ms at 200 samples/s) over [`DEVICE_VELOCITY_WINDOW_US`] of
//! board time, and carries the newest sample forward to the report's time at that
//! velocity. No fixed horizon is assumed: how far the sample is carried is measured
//! on the board's clock for every report.
//!
//! A mouse sends packets only while it moves, so a packet that is overdue (later than
//! the last packet interval plus [`OVERDUE_MARGIN_US`]) means the rod stopped: the
//! pose falls back to the measured one and the velocity to zero.

use std::collections::VecDeque;

/// How long a 3-byte PS/2 packet takes on the wire after the mouse sampled its motion,
/// µs: 3 frames of 11 clock periods at 12.5 kHz, the middle of the 10–16.7 kHz the
/// PS/2 specification allows (2.0–3.3 ms).
pub const PS2_PACKET_WIRE_US: u64 = 3 * 11 * 80;

/// The window of board time over which the velocity is rebuilt from packets, µs: two
/// packet periods at 200 samples/s, and the age's 100 µs step to spare.
pub const DEVICE_VELOCITY_WINDOW_US: u64 = 10_100;

/// How much later than the last packet interval the next packet may end before the
/// rod is taken as stopped, µs (a byte's time on the wire at 10 kHz, and the age's
/// step).
pub const OVERDUE_MARGIN_US: u64 = 1_200;

/// Two packet ends closer than this are one packet seen twice, µs (the packet age's
/// step is 100 µs, and a packet takes over 2 ms on the wire).
const SAME_PACKET_US: u64 = 300;

/// The packet interval assumed before two packets were seen, µs (200 samples/s).
const DEFAULT_INTERVAL_US: u64 = 5_000;

/// Packet intervals taken into account, µs: 10–500 samples/s.
const INTERVAL_RANGE_US: (u64, u64) = (2_000, 100_000);

/// The board's wrapping `u32` µs clock unwrapped to a `u64`.
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct DeviceClock {
    last_raw: Option<u32>,
    now_us: u64,
}

impl DeviceClock {
    /// Advances to the report time `raw_us`; `false` when the clock went backwards (the
    /// board restarted, or the report is older than the last one): the caller then
    /// forgets what it knew from earlier reports.
    pub(crate) fn advance(&mut self, raw_us: u32) -> bool {
        let forward = match self.last_raw {
            Some(last) => {
                let delta = raw_us.wrapping_sub(last);
                if delta < 1 << 31 {
                    self.now_us += u64::from(delta);
                    true
                } else {
                    false
                }
            }
            None => true,
        };
        self.last_raw = Some(raw_us);
        forward
    }

    /// The unwrapped time of the last report, µs.
    pub(crate) fn now_us(&self) -> u64 {
        self.now_us
    }
}

/// One rod's packets on the board's clock, paddle frame `[slide_m, angle_rad]`.
#[derive(Debug, Clone, Default)]
pub(crate) struct DeviceTrack {
    /// `(sample time µs, pose)` of the packets within the velocity window, oldest first.
    samples: VecDeque<(u64, [f64; 2])>,
    /// When the newest packet ended, µs.
    last_end_us: Option<u64>,
    /// Board time between the last two packets, µs.
    interval_us: Option<u64>,
}

impl DeviceTrack {
    /// Forgets every packet (board restarted, sensor absent, rod re-homed).
    pub(crate) fn clear(&mut self) {
        *self = Self::default();
    }

    /// Takes a report at board time `now_us` in which this rod's newest packet is
    /// `age_us` old (`None`: none within 25.4 ms) and its pose from the counts is `pose`.
    pub(crate) fn observe(&mut self, now_us: u64, age_us: Option<u32>, pose: [f64; 2]) {
        let Some(age_us) = age_us else {
            // No recent packet: the rod rests (the pose can only have changed by a
            // packet older than the window, or an origin shift).
            if let Some(newest) = self.samples.back_mut() {
                newest.1 = pose;
            }
            return;
        };
        let end_us = now_us.saturating_sub(u64::from(age_us));
        let is_new = self
            .last_end_us
            .is_none_or(|last| end_us > last + SAME_PACKET_US);
        if !is_new {
            if let Some(newest) = self.samples.back_mut() {
                newest.1 = pose;
            }
            return;
        }
        if let Some(last) = self.last_end_us {
            self.interval_us = Some(end_us - last);
        }
        self.last_end_us = Some(end_us);
        let sample_us = end_us.saturating_sub(PS2_PACKET_WIRE_US);
        self.samples.push_back((sample_us, pose));
        while self
            .samples
            .front()
            .is_some_and(|&(t, _)| t + DEVICE_VELOCITY_WINDOW_US < sample_us)
        {
            self.samples.pop_front();
        }
    }

    /// The pose and velocity (paddle frame; m, rad, m/s, rad/s) at board time `now_us`,
    /// from `pose`, the pose the counts give now: the newest packet's pose carried
    /// forward from its sample time at the packets' velocity; `pose` itself with zero
    /// velocity before two packets fell within the window or once the next packet is
    /// overdue.
    pub(crate) fn estimate(&self, now_us: u64, pose: [f64; 2]) -> ([f64; 2], [f64; 2]) {
        let still = (pose, [0.0; 2]);
        let (Some(&(t_new, p_new)), Some(&(t_old, p_old)), Some(end_us)) =
            (self.samples.back(), self.samples.front(), self.last_end_us)
        else {
            return still;
        };
        if t_new <= t_old {
            return still;
        }
        let interval = self
            .interval_us
            .unwrap_or(DEFAULT_INTERVAL_US)
            .clamp(INTERVAL_RANGE_US.0, INTERVAL_RANGE_US.1);
        if now_us.saturating_sub(end_us) > interval + OVERDUE_MARGIN_US {
            return still;
        }
        let dt_s = (t_new - t_old) as f64 * 1e-6;
        let velocity = [(p_new[0] - p_old[0]) / dt_s, (p_new[1] - p_old[1]) / dt_s];
        let ahead_s = now_us.saturating_sub(t_new) as f64 * 1e-6;
        (
            [
                pose[0] + velocity[0] * ahead_s,
                pose[1] + velocity[1] * ahead_s,
            ],
            velocity,
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_clock_unwraps_and_notices_a_restart() {
        let mut clock = DeviceClock::default();
        assert!(clock.advance(u32::MAX - 499));
        assert!(clock.advance(500));
        assert_eq!(clock.now_us(), 1_000);
        assert!(!clock.advance(100), "backwards: a restarted board");
    }

    /// A rod at 0.2 m/s whose mouse sends a packet every 5 ms; reports every 1 ms.
    #[test]
    fn packets_on_board_time_give_the_pose_now() {
        let speed = 0.2;
        let mut track = DeviceTrack::default();
        let mut last = ([0.0; 2], [0.0; 2]);
        for ms in 0..40u64 {
            let now = ms * 1_000;
            // The newest packet ended at the last multiple of 5 ms (+ 0.3 ms).
            let end = (now.saturating_sub(300) / 5_000) * 5_000 + 300;
            if end > now || end < PS2_PACKET_WIRE_US {
                continue;
            }
            let sampled = (end - PS2_PACKET_WIRE_US) as f64 * 1e-6;
            let pose = [speed * sampled, 0.0];
            track.observe(now, Some((now - end) as u32), pose);
            last = track.estimate(now, pose);
        }
        // At 39 ms the rod is at 0.2 m/s × 39 ms; the packets' quantised times aside
        // (exact here), the estimate is there.
        assert!((last.0[0] - speed * 0.039).abs() < 1e-9, "{last:?}");
        assert!((last.1[0] - speed).abs() < 1e-9, "{last:?}");
        // No packet for longer than an interval and the margin: the rod stopped.
        let (pose, velocity) = track.estimate(39_000 + 7_000, [0.123, 0.0]);
        assert_eq!((pose, velocity), ([0.123, 0.0], [0.0; 2]));
    }

    /// The tracker on the emulated board (lockstep, version 2 reports): a rod sliding
    /// at a constant speed is tracked within the uncertainty of the packet's time on
    /// the wire (the PS/2 clock's 10–16.7 kHz against the assumed 12.5 kHz: ±0.7 ms),
    /// the packet age's 100 µs step and the emulated sensor's 250 µs frame; the same
    /// reports on report time without prediction lag by the packet period and more.
    #[test]
    fn on_the_emulated_board_the_pose_lags_by_less_than_the_wire_uncertainty() {
        use crate::input::calibration::Calibration;
        use crate::input::paddles::BoardInput;
        use crate::Table;
        use foosball_sim::motion::script::MotionScript;
        use foosball_sim::{BoardConfig, InProcessBoard, Pacing};

        const SPEED: f64 = 0.1;
        const START_S: f64 = 0.6;
        let table = Table::standard();
        let rod = 3;
        let port = table.rods[rod].port;
        let sign = table.rods[rod].handle_sign();
        let json = format!(
            r#"{{"rods":[{{"rod":{port},"segments":[{{"hold":{{"duration_s":{START_S}}}}},
               {{"velocity":{{"duration_s":0.3,"axial_m_per_s":{SPEED},"angle_rad_per_s":0}}}}]}}]}}"#
        );
        // Lag of the tracked slide behind the rod, ms, over the steady ramp.
        let lags = |clock_hz: u32, board_time: bool| -> Vec<f64> {
            let mut config = BoardConfig::default();
            config.wire.clock_hz = clock_hz;
            let script = MotionScript::from_json(&json).unwrap();
            let board =
                InProcessBoard::with_motion(config, Box::new(script), Pacing::Lockstep).unwrap();
            let mut input = BoardInput::new(board, &table, Calibration::default());
            input.tracker_mut().set_device_time_tracking(board_time);
            let mut out = Vec::new();
            for ms in 1..=880u64 {
                let inputs = input.poll(1);
                let t_s = ms as f64 * 1e-3;
                // Steady: the velocity window filled after the ramp began.
                if t_s > START_S + 0.03 {
                    let slide = sign * inputs.rods[rod].slide_m;
                    out.push((t_s - START_S - slide / SPEED) * 1e3);
                }
            }
            assert_eq!(input.tracker().is_device_timed(), board_time);
            out
        };
        let bound = 0.7 + 0.1 + 0.25;
        for clock_hz in [10_000, 12_500, 16_700] {
            let lag = lags(clock_hz, true);
            let worst = lag.iter().copied().map(f64::abs).fold(0.0, f64::max);
            assert!(worst <= bound, "{clock_hz} Hz: lag up to {worst:.2} ms");
        }
        let untimed = lags(12_500, false);
        let mean = untimed.iter().sum::<f64>() / untimed.len() as f64;
        assert!(
            mean > 2.5,
            "report time without prediction lags {mean:.2} ms"
        );
    }

    /// Timed reports with board-time tracking off are tracked exactly as untimed ones;
    /// a board that restarts (its clock going back) starts its packets afresh.
    #[test]
    fn board_time_is_opt_in_and_a_restart_forgets_the_packets() {
        use crate::input::calibration::Calibration;
        use crate::input::paddles::PaddleTracker;
        use crate::Table;
        use foosball_protocol::{InReport, PacketAge, ReportTiming};

        let table = Table::standard();
        let port = table.rods[3].port;
        let report = |sequence: u16, axial: i16| {
            let mut r = InReport::all_present(sequence);
            r.paddles[port].axial = axial;
            r
        };
        let timing = |device_time_us: u32, age_us: u64| {
            let mut t = ReportTiming {
                device_time_us,
                ..ReportTiming::default()
            };
            for p in &mut t.paddles {
                p.newest_packet_age = PacketAge::NONE;
            }
            t.paddles[port].newest_packet_age = PacketAge::from_micros(age_us);
            t
        };
        let mut plain = PaddleTracker::new(&table, Calibration::default());
        let mut off = PaddleTracker::new(&table, Calibration::default());
        let mut on = PaddleTracker::new(&table, Calibration::default());
        on.set_device_time_tracking(true);
        for k in 0..20u16 {
            let packet = k % 5 == 4;
            let r = report(k, if packet { 4 } else { 0 });
            let age = u64::from(k % 5) * 1_000;
            let t = timing(100_000 + u32::from(k) * 1_000, age);
            plain.apply_report(&r);
            off.apply_timed_report(&r, Some(&t));
            on.apply_timed_report(&r, Some(&t));
        }
        assert_eq!(plain.inputs(), off.inputs());
        assert!(!off.is_device_timed() && on.is_device_timed());
        let moving = on.rod(3).unwrap();
        assert!(moving.slide_velocity_m_per_s.abs() > 0.0, "{moving:?}");
        // The board restarts: device time back near zero. One packet since: no
        // velocity until the next.
        on.apply_timed_report(&report(0, 4), Some(&timing(3_000, 200)));
        let restarted = on.rod(3).unwrap();
        assert_eq!(restarted.slide_velocity_m_per_s, 0.0, "{restarted:?}");
        // A version 1 report: back to report time.
        on.apply_report(&report(1, 0));
        assert!(!on.is_device_timed());
    }

    #[test]
    fn one_packet_gives_no_velocity() {
        let mut track = DeviceTrack::default();
        track.observe(10_000, Some(500), [0.01, 0.2]);
        assert_eq!(track.estimate(10_000, [0.01, 0.2]), ([0.01, 0.2], [0.0; 2]));
        // The same packet seen again (older by the report period) is no new packet.
        track.observe(11_000, Some(1_500), [0.01, 0.2]);
        assert_eq!(track.samples.len(), 1);
    }
}

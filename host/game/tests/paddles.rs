//! Board input → rod poses: clamping, velocity, lost boards, gaps, absent sensors.

use board_link::{Board, BoardError, InReport, LinkState, LinkStats, OutReport};
use foosball_protocol::PaddleStatus;
use space_foosball::input::calibration::Calibration;
use space_foosball::input::paddles::{BoardInput, InputHealth, PaddleTracker};
use space_foosball::Table;
use std::collections::VecDeque;
use std::time::Duration;

/// A board that plays back a list of poll results, then says nothing.
struct FakeBoard {
    results: VecDeque<Result<Option<InReport>, BoardError>>,
    state: LinkState,
}

impl Board for FakeBoard {
    fn name(&self) -> String {
        "fake".into()
    }
    fn poll_report(&mut self, _t: Duration) -> Result<Option<InReport>, BoardError> {
        self.results.pop_front().unwrap_or(Ok(None))
    }
    fn send(&mut self, _r: &OutReport) -> Result<(), BoardError> {
        Ok(())
    }
    fn link_state(&self) -> LinkState {
        self.state
    }
    fn stats(&self) -> LinkStats {
        LinkStats::default()
    }
}

/// A report moving `port` by (`axial`, `rotation`) counts, every sensor present.
fn report(sequence: u16, port: usize, axial: i16, rotation: i16) -> InReport {
    let mut r = InReport::all_present(sequence);
    r.paddles[port].axial = axial;
    r.paddles[port].rotation = rotation;
    r
}

fn tracker() -> PaddleTracker {
    PaddleTracker::new(&Table::standard(), Calibration::default())
}

#[test]
fn counts_become_table_frame_poses_with_the_handle_side() {
    let mut t = tracker();
    assert_eq!(t.health(), InputHealth::Waiting);
    // 80 counts = 10 mm at 8 counts/mm; 64 rotation counts = 1 rad on an 8 mm rod.
    let mut r = report(0, 3, 80, 64);
    r.paddles[4].axial = 80; // rod 4: away midfield, handles on the +y side
    r.paddles[4].rotation = 64;
    t.apply_report(&r);
    let home = t.rod(3).unwrap();
    assert!((home.slide_m - 0.010).abs() < 1e-12 && (home.angle_rad - 1.0).abs() < 1e-12);
    let away = t.rod(4).unwrap();
    assert!((away.slide_m + 0.010).abs() < 1e-12 && (away.angle_rad + 1.0).abs() < 1e-12);
    assert_eq!(t.health(), InputHealth::Live);
    assert!(home.present);
}

#[test]
fn slide_is_clamped_to_the_travel_and_the_stop_rehomes_it() {
    let mut t = tracker();
    // Midfield travel ±58 mm: push 100 mm.
    t.apply_report(&report(0, 3, 800, 0));
    let rod = t.rod(3).unwrap();
    assert!((rod.slide_m - 0.058).abs() < 1e-12, "{rod:?}");
    // Coming back 10 mm moves the men at once (the stop redefined the origin).
    t.apply_report(&report(1, 3, -80, 0));
    assert!((t.rod(3).unwrap().slide_m - 0.048).abs() < 1e-12);
    // The angle is unbounded.
    for s in 2..12 {
        t.apply_report(&report(s, 3, 0, 640));
    }
    assert!((t.rod(3).unwrap().angle_rad - 100.0).abs() < 1e-9);
}

#[test]
fn velocity_is_smoothed_over_bursty_packets() {
    let mut t = tracker();
    // 200 packets/s: 8 counts (1 mm) every 5 ms = 0.2 m/s.
    for s in 0..50u16 {
        let axial = if s % 5 == 4 { 8 } else { 0 };
        t.apply_report(&report(s, 3, axial, 0));
    }
    let v = t.rod(3).unwrap().slide_velocity_m_per_s;
    assert!((v - 0.2).abs() < 1e-9, "{v}");
    // Turning backwards at 64 counts per 5 ms = −200 rad/s... 1 rad / 5 ms.
    for s in 50..100u16 {
        let rot = if s % 5 == 4 { -64 } else { 0 };
        t.apply_report(&report(s, 3, 0, rot));
    }
    let rod = t.rod(3).unwrap();
    assert!(
        (rod.angular_velocity_rad_per_s + 200.0).abs() < 1e-6,
        "{rod:?}"
    );
    assert!(rod.slide_velocity_m_per_s.abs() < 1e-12);
}

#[test]
fn sequence_gaps_are_counted_as_time_and_lost_reports() {
    let mut t = tracker();
    t.apply_report(&report(65534, 3, 8, 0));
    t.apply_report(&report(3, 3, 8, 0)); // wraps: 65535, 0, 1, 2 lost
    let inputs = t.inputs();
    assert_eq!(inputs.lost_reports, 4);
    assert_eq!(inputs.time_ms, 5);
    assert!((inputs.rods[3].slide_m - 0.002).abs() < 1e-12);
}

#[test]
fn absent_sensor_holds_its_rod_and_the_others_go_on() {
    let mut t = tracker();
    t.apply_report(&report(0, 3, 80, 0));
    let mut r = report(1, 3, 0, 0);
    r.paddles[3].status = PaddleStatus::empty();
    r.paddles[5].axial = 40;
    t.apply_report(&r);
    let rod3 = t.rod(3).unwrap();
    assert!(!rod3.present);
    assert!((rod3.slide_m - 0.010).abs() < 1e-12);
    assert_eq!(rod3.slide_velocity_m_per_s, 0.0);
    assert!((t.rod(5).unwrap().slide_m - 0.005).abs() < 1e-12);
    // Back (reinitialised): tracking resumes from the held pose.
    let mut r = report(2, 3, 8, 0);
    r.paddles[3].status = PaddleStatus::PRESENT | PaddleStatus::REINITIALISED;
    t.apply_report(&r);
    assert!((t.rod(3).unwrap().slide_m - 0.011).abs() < 1e-12);
}

#[test]
fn lost_board_keeps_poses_reports_board_lost_and_recovers() {
    let mut results: VecDeque<_> = VecDeque::new();
    for s in 0..20u16 {
        results.push_back(Ok(Some(report(s, 0, 8, 0))));
    }
    results.push_back(Err(BoardError::Disconnected));
    results.push_back(Err(BoardError::Malformed(
        foosball_protocol::DecodeError::UnknownVersion {
            found: 9,
            supported: 1,
        },
    )));
    let board = FakeBoard {
        results,
        state: LinkState::Connected,
    };
    let mut input = BoardInput::new(board, &Table::standard(), Calibration::default());
    let live = input.poll(20);
    assert_eq!(live.health, InputHealth::Live);
    assert!((live.rods[0].slide_m - 0.020).abs() < 1e-12);
    assert!(live.rods[0].slide_velocity_m_per_s > 0.0);
    // The next poll hits the disconnect.
    let lost = input.poll(100);
    assert_eq!(lost.health, InputHealth::BoardLost);
    assert_eq!(lost.rods[0].slide_m, live.rods[0].slide_m);
    assert_eq!(lost.rods[0].slide_velocity_m_per_s, 0.0);
    // A malformed report is dropped and counted; still lost until reports flow.
    input.poll(100);
    assert_eq!(input.malformed(), 1);
    input.board_mut().state = LinkState::Reconnecting;
    assert_eq!(input.poll(100).health, InputHealth::BoardLost);
    // Back, with a fresh sequence: no gap counted across the reconnect.
    input
        .board_mut()
        .results
        .push_back(Ok(Some(report(0, 0, -8, 0))));
    input.board_mut().state = LinkState::Connected;
    let back = input.poll(100);
    assert_eq!(back.health, InputHealth::Live);
    assert_eq!(back.lost_reports, 0);
    assert!((back.rods[0].slide_m - 0.019).abs() < 1e-12);
}

#[test]
fn poll_takes_at_most_the_cap() {
    let results = (0..10u16).map(|s| Ok(Some(report(s, 1, 8, 0)))).collect();
    let board = FakeBoard {
        results,
        state: LinkState::Connected,
    };
    let mut input = BoardInput::new(board, &Table::standard(), Calibration::default());
    assert_eq!(input.poll(1).time_ms, 0);
    assert_eq!(input.poll(3).time_ms, 3);
    assert_eq!(input.poll(100).time_ms, 9);
    // Nothing more: idle, still live.
    assert_eq!(input.poll(100).health, InputHealth::Live);
}

#[test]
fn rehome_sets_the_current_pose() {
    let mut t = tracker();
    t.apply_report(&report(0, 6, 123, -45));
    t.rehome(6, 0.1, 0.0); // away defence
    let rod = t.rod(6).unwrap();
    assert!((rod.slide_m - 0.1).abs() < 1e-12 && rod.angle_rad.abs() < 1e-12);
    t.apply_report(&report(1, 6, 8, 0));
    // Away handle: +counts move towards −y.
    assert!((t.rod(6).unwrap().slide_m - 0.099).abs() < 1e-12);
}

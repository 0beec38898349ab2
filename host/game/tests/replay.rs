//! Replay: a recorded match plays back to bit-identical events and final state.
//!
//! The Home team is played through the emulated board (lockstep) following a scripted
//! motion, against the computer; the match records the rod poses it consumed. The
//! recording is saved, loaded, and replayed without the board.

use foosball_sim::motion::script::MotionScript;
use foosball_sim::{BoardConfig, InProcessBoard, Pacing};
use space_foosball::input::calibration::Calibration;
use space_foosball::input::paddles::BoardInput;
use space_foosball::play::{Match, MatchConfig, RodController};
use space_foosball::recording::MatchRecording;
use space_foosball::rules::{RulesConfig, TimedEvent};
use space_foosball::Table;

const STEPS: u64 = 12_000;

/// The Home rods sweep and spin on their own timetables (counting starts after 1 s).
fn script() -> MotionScript {
    let mut tracks = Vec::new();
    for (k, port) in [0usize, 1, 3, 5].into_iter().enumerate() {
        let f = 1.0 + k as f64 * 0.37;
        tracks.push(format!(
            r#"{{"rod":{port},"segments":[
                {{"hold":{{"duration_s":1.0}}}},
                {{"velocity":{{"duration_s":0.3,"axial_m_per_s":{a},"angle_rad_per_s":{w}}}}},
                {{"velocity":{{"duration_s":0.6,"axial_m_per_s":{b},"angle_rad_per_s":{v}}}}},
                {{"move_to":{{"duration_s":0.5,"axial_m":0.0,"angle_rad":0.0}}}},
                {{"velocity":{{"duration_s":2.0,"axial_m_per_s":{c},"angle_rad_per_s":{u}}}}},
                {{"move_to":{{"duration_s":0.7,"axial_m":0.01,"angle_rad":6.2832}}}},
                {{"velocity":{{"duration_s":3.0,"axial_m_per_s":{d},"angle_rad_per_s":{x}}}}}
            ]}}"#,
            a = 0.1 * f,
            w = 8.0 * f,
            b = -0.1 * f,
            v = -12.0,
            c = 0.02,
            u = -15.0 * f,
            d = -0.015,
            x = 9.0,
        ));
    }
    MotionScript::from_json(&format!(r#"{{"rods":[{}]}}"#, tracks.join(","))).unwrap()
}

fn config(table: &Table, seed: u64) -> MatchConfig {
    let mut c = MatchConfig::player_vs_computer(table.clone(), seed);
    c.rules = RulesConfig {
        goals_to_win: 3,
        ..RulesConfig::default()
    };
    c
}

/// Plays `STEPS` steps (or to the end) from the board; the events and the match.
fn play_live(table: &Table, seed: u64) -> (Vec<TimedEvent>, Match) {
    let board =
        InProcessBoard::with_motion(BoardConfig::default(), Box::new(script()), Pacing::Lockstep)
            .unwrap();
    let mut input = BoardInput::new(board, table, Calibration::default());
    let mut m = Match::new(config(table, seed)).unwrap();
    let mut events = Vec::new();
    for _ in 0..STEPS {
        let inputs = input.poll(1);
        events.extend(m.step(&inputs));
        if m.is_over() {
            break;
        }
    }
    (events, m)
}

fn bits(v: [f64; 3]) -> [u64; 3] {
    v.map(f64::to_bits)
}

#[test]
fn a_recorded_match_replays_bit_identically() {
    let table = Table::standard();
    let (events, live) = play_live(&table, 11);
    // Something happened: kicks by the board's rods and the computer's.
    let kicks = events
        .iter()
        .filter(|e| matches!(e.event, space_foosball::rules::Event::Kick { .. }))
        .count();
    assert!(kicks > 5, "{events:?}");
    let recording = live.recording().clone();
    assert_eq!(recording.len() as u64, live.time_ms());
    // Through the file: saved atomically, loaded, validated.
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("match.json");
    recording.save(&path).unwrap();
    let loaded = MatchRecording::load(&path).unwrap();
    assert_eq!(loaded, recording);

    let controllers = [RodController::Player, RodController::Computer];
    let (replayed, replay_events) = Match::replay(&loaded, controllers).unwrap();
    assert_eq!(
        replay_events, events,
        "same events, same times, same speeds"
    );
    assert_eq!(replayed.time_ms(), live.time_ms());
    assert_eq!(replayed.score(), live.score());
    assert_eq!(replayed.phase(), live.phase());
    let (a, b) = (live.snapshot(), replayed.snapshot());
    assert_eq!(bits(a.ball.position), bits(b.ball.position));
    assert_eq!(bits(a.ball.velocity), bits(b.ball.velocity));
    assert_eq!(bits(a.ball_spin), bits(b.ball_spin));
    for (ra, rb) in a.rods.iter().zip(&b.rods) {
        assert_eq!(ra.slide_m.to_bits(), rb.slide_m.to_bits());
        assert_eq!(ra.angle_rad.to_bits(), rb.angle_rad.to_bits());
    }
    // The replay records the same input again.
    assert_eq!(replayed.recording(), &recording);
}

#[test]
fn a_different_seed_or_input_gives_a_different_match() {
    // The comparison above can fail: the seed (serves) and the input change the match.
    let table = Table::standard();
    let (events, live) = play_live(&table, 11);
    let mut other_seed = live.recording().clone();
    other_seed.seed = 12;
    let controllers = [RodController::Player, RodController::Computer];
    let (m2, e2) = Match::replay(&other_seed, controllers).unwrap();
    assert_ne!(e2, events);
    assert_ne!(m2.snapshot().ball.position, live.snapshot().ball.position);
    // Nudge the recorded slides of the Home rods by 2 mm from 1 s on.
    let mut nudged = live.recording().clone();
    if let space_foosball::recording::RecordedInput::Poses(steps) = &mut nudged.input {
        for step in steps.iter_mut().skip(1000) {
            for rod in [0, 1, 3, 5] {
                step[rod][0] += 0.002;
            }
        }
    }
    let (m3, _) = Match::replay(&nudged, controllers).unwrap();
    assert_ne!(
        bits(m3.snapshot().ball.position),
        bits(live.snapshot().ball.position)
    );
}

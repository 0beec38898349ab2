//! The match on its own thread: it steps, publishes snapshots and events, pauses,
//! pauses by itself while the board is lost, and hands the match back.
//! (How well it keeps time is measured by `space-foosball bench`, not asserted here.)

use space_foosball::input::paddles::{InputHealth, RodInputs};
use space_foosball::play::{idle_inputs, Match, MatchConfig, PhysicsThread};
use space_foosball::rules::Event;
use space_foosball::Table;
use std::sync::atomic::{AtomicU8, AtomicUsize, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

fn wait_for(what: &str, mut done: impl FnMut() -> bool) {
    let start = Instant::now();
    while !done() {
        assert!(
            start.elapsed() < Duration::from_secs(30),
            "timed out waiting for {what}"
        );
        std::thread::sleep(Duration::from_millis(5));
    }
}

#[test]
fn steps_publishes_pauses_and_stops() {
    let table = Table::standard();
    let m = Match::new(MatchConfig::computer_vs_computer(table.clone(), 4)).unwrap();
    let calls = Arc::new(AtomicUsize::new(0));
    let counter = Arc::clone(&calls);
    let idle = idle_inputs(&table);
    let thread = PhysicsThread::spawn(m, move || {
        counter.fetch_add(1, Ordering::Relaxed);
        idle.clone()
    });
    // The kickoff comes at 500 ms of match time.
    let mut events = Vec::new();
    wait_for("the kickoff", || {
        events.extend(thread.drain_events());
        events
            .iter()
            .any(|e| matches!(e.event, Event::Serve { .. }))
    });
    let (previous, newest) = thread.latest();
    assert!(
        newest.time_s > previous.time_s,
        "{} {}",
        previous.time_s,
        newest.time_s
    );
    assert!((newest.time_s - previous.time_s - 1e-3).abs() < 1e-9);
    assert_eq!(newest.rods.len(), table.rods.len());
    assert!(!newest.paused);
    // Events come once: drained ones are gone.
    let again = thread.drain_events();
    assert!(again.iter().all(|e| !events.contains(e)));

    thread.set_paused(true);
    assert!(thread.is_paused());
    wait_for("the pause", || thread.latest().1.paused);
    let t_paused = thread.latest().1.time_s;
    let calls_paused = calls.load(Ordering::Relaxed);
    std::thread::sleep(Duration::from_millis(60));
    assert_eq!(thread.latest().1.time_s, t_paused, "no steps while paused");
    // The input is still drained while paused (a board keeps reporting).
    assert!(calls.load(Ordering::Relaxed) > calls_paused);
    thread.set_paused(false);
    wait_for("the resume", || thread.latest().1.time_s > t_paused + 0.02);
    let stats = thread.stats();
    assert!(stats.steps > 500, "{stats:?}");
    let m = thread.stop().expect("the match comes back");
    assert!(m.time_ms() as f64 * 1e-3 >= t_paused + 0.02);
    assert_eq!(m.recording().len() as u64, m.time_ms());
}

#[test]
fn a_lost_board_pauses_the_match_until_it_is_back() {
    let table = Table::standard();
    let m = Match::new(MatchConfig::player_vs_computer(table.clone(), 4)).unwrap();
    // 0 = live, 1 = lost.
    let health = Arc::new(AtomicU8::new(0));
    let h = Arc::clone(&health);
    let idle = idle_inputs(&table);
    let thread = PhysicsThread::spawn(m, move || RodInputs {
        health: if h.load(Ordering::Relaxed) == 1 {
            InputHealth::BoardLost
        } else {
            InputHealth::Live
        },
        ..idle.clone()
    });
    wait_for("some steps", || thread.latest().1.time_s > 0.05);
    health.store(1, Ordering::Relaxed);
    wait_for("the pause", || thread.latest().1.paused);
    assert_eq!(thread.latest().1.input_health, InputHealth::BoardLost);
    let t = thread.latest().1.time_s;
    std::thread::sleep(Duration::from_millis(50));
    assert_eq!(thread.latest().1.time_s, t);
    health.store(0, Ordering::Relaxed);
    wait_for("the resume", || thread.latest().1.time_s > t + 0.01);
    assert!(!thread.latest().1.paused);
    assert!(thread.stop().is_some());
}

/// A match that ends on its thread leaves its recording behind (for the history's replay),
/// once: every step of the match is in it.
#[test]
fn a_finished_match_leaves_its_recording() {
    use space_foosball::play::ThreadOptions;
    use space_foosball::rules::RulesConfig;
    let table = Table::standard();
    let mut config = MatchConfig::computer_vs_computer(table.clone(), 4);
    config.rules = RulesConfig {
        goals_to_win: 1,
        ..RulesConfig::default()
    };
    let m = Match::new(config).unwrap();
    let idle = idle_inputs(&table);
    // As fast as the thread steps: the match's 10–90 s of match time in a few seconds.
    let options = ThreadOptions {
        period: Duration::from_micros(10),
        max_catch_up_steps: 1_000_000,
        ..ThreadOptions::default()
    };
    let thread = PhysicsThread::spawn_with(m, move || idle.clone(), options);
    let start = Instant::now();
    while thread.is_running() {
        assert!(
            start.elapsed() < Duration::from_secs(120),
            "the match did not end"
        );
        std::thread::sleep(Duration::from_millis(20));
    }
    let recording = thread
        .take_recording()
        .expect("the finished match's recording");
    assert!(thread.take_recording().is_none(), "taken once");
    let m = thread.stop().expect("the match comes back");
    assert!(m.is_over());
    assert_eq!(recording.len() as u64, m.time_ms());
    assert_eq!(&recording, m.recording());
}

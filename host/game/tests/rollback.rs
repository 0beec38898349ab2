//! A match saved and restored steps on bit for bit as it did: what rollback netcode needs
//! (restore the frame a late input changes, step again with the right inputs).

use space_foosball::play::{idle_inputs, Match, MatchConfig, MatchSnapshot};
use space_foosball::rules::{RulesConfig, TimedEvent};
use space_foosball::Table;

/// Steps `n` times, returning every event and the snapshot after each step.
fn run(m: &mut Match, table: &Table, n: usize) -> (Vec<TimedEvent>, Vec<MatchSnapshot>) {
    let inputs = idle_inputs(table);
    let mut events = Vec::new();
    let mut snaps = Vec::new();
    for _ in 0..n {
        events.extend(m.step(&inputs));
        snaps.push(m.snapshot());
    }
    (events, snaps)
}

#[test]
fn a_restored_match_replays_the_same_steps_with_its_recording_cut_back() {
    let table = Table::standard();
    let mut config = MatchConfig::computer_vs_computer(table.clone(), 11);
    config.rules = RulesConfig {
        goals_to_win: 99,
        ..RulesConfig::default()
    };
    let mut m = Match::new(config).unwrap();
    // Into play: kickoff, kicks and bounces under way.
    run(&mut m, &table, 1500);
    let saved = m.save();
    let recorded = m.recording().clone();
    // Eight 60 Hz frames and more: 400 steps, through contacts, serves and maybe a goal.
    let (events, snaps) = run(&mut m, &table, 400);
    assert!(!events.is_empty(), "nothing happened in 400 steps");
    m.restore(&saved);
    assert_eq!(
        m.recording(),
        &recorded,
        "the recording is cut back to the save"
    );
    let (again, snaps_again) = run(&mut m, &table, 400);
    assert_eq!(again, events);
    for (k, (a, b)) in snaps.iter().zip(&snaps_again).enumerate() {
        assert_eq!(
            format!("{a:?}"),
            format!("{b:?}"),
            "step {k} after the restore"
        );
    }
    // And a save restored twice gives the same again.
    m.restore(&saved);
    let (third, _) = run(&mut m, &table, 400);
    assert_eq!(third, events);
}

//! Match recordings: the loader rejects the recording, or up to its first 100 steps
//! replay with every body of the match's world finite after each step. Pose
//! recordings replay their poses; report recordings go through the default
//! calibration's paddle tracker, as a board's reports do.

use super::finite::first_non_finite;
use super::{text, Verdict};
use space_foosball::input::calibration::Calibration;
use space_foosball::input::paddles::{InputHealth, PaddleTracker, RodInputs, RodState};
use space_foosball::play::{Match, MatchConfig, RodController};
use space_foosball::recording::{MatchRecording, RecordedInput};

pub(super) fn run(input: &[u8]) -> Verdict {
    let Some(text) = text(input) else {
        return Verdict::Rejected;
    };
    let Ok(recording) = MatchRecording::from_json(text) else {
        return Verdict::Rejected;
    };
    let Ok(reports) = recording.reports() else {
        panic!("a loaded recording's reports do not decode");
    };
    let config = MatchConfig {
        rules: recording.rules,
        seed: recording.seed,
        controllers: [RodController::Player; 2],
        record_inputs: false,
        ..MatchConfig::computer_vs_computer(recording.table.clone(), 0)
    };
    let Ok(mut game) = Match::new(config) else {
        return Verdict::Rejected;
    };
    let steps: Vec<RodInputs> = match &recording.input {
        RecordedInput::Poses(steps) => steps
            .iter()
            .take(super::scene::STEPS)
            .map(|step| RodInputs {
                rods: step
                    .iter()
                    .map(|p| RodState {
                        slide_m: p[0],
                        angle_rad: p[1],
                        present: true,
                        ..RodState::default()
                    })
                    .collect(),
                health: InputHealth::Live,
                time_ms: 0,
                lost_reports: 0,
            })
            .collect(),
        RecordedInput::Reports(_) => {
            let mut tracker = PaddleTracker::new(&recording.table, Calibration::default());
            reports
                .iter()
                .take(super::scene::STEPS)
                .map(|report| {
                    tracker.apply_report(report);
                    tracker.inputs()
                })
                .collect()
        }
    };
    for (i, inputs) in steps.iter().enumerate() {
        game.step(inputs);
        if let Some(body) = first_non_finite(game.arena().world()) {
            panic!("replay step {} left a non-finite state: {body}", i + 1);
        }
    }
    Verdict::Accepted
}

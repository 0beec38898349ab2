//! The page's status line: one JSON object with what the game shows and has done,
//! which the page exposes to scripts (`spaceFoosball.status()`) and the browser test
//! reads.

use crate::frame_stats::FrameStats;
use crate::session::{FrameOut, WebSession};
use foosball_audio::AudioOutput;
use serde_json::{json, Value};

/// What the page knows besides the session: frames drawn, since when, on what.
#[derive(Debug, Clone, Copy)]
pub struct PageFigures<'a> {
    /// Frames drawn.
    pub frames: u64,
    /// Seconds since the page started.
    pub seconds: f64,
    /// The graphics adapter's name.
    pub adapter: &'a str,
    /// The graphics backend (`BrowserWebGpu`, `Gl`).
    pub backend: &'a str,
    /// The recent frame times.
    pub frame_stats: &'a FrameStats,
    /// Where the sounds go.
    pub audio: &'a AudioOutput,
}

/// The status of `session` after the frame `last` (none before the first).
pub fn status(session: &mut WebSession, last: Option<&FrameOut>, page: PageFigures<'_>) -> Value {
    let pair = |v: Option<(f64, f64)>| v.map(|(m, p)| json!({ "median": m, "p95": p }));
    let counters = session.counters();
    let link = session.link_stats();
    let out_reports = session.out_reports();
    let newest = session.newest().clone();
    let rods: Vec<Value> = session
        .rod_inputs()
        .rods
        .iter()
        .map(|r| json!([r.slide_m, r.angle_rad]))
        .collect();
    let physics_rods: Vec<Value> = newest
        .rods
        .iter()
        .map(|r| json!([r.slide_m, r.angle_rad]))
        .collect();
    let controllers = session
        .controllers()
        .map(|c| format!("{c:?}").to_lowercase());
    // The ports whose map is not the nominal one (a stored or fitted calibration).
    let nominal = space_foosball::input::calibration::PaddleCalibration::default();
    let calibrated_ports: Vec<usize> = session
        .calibration()
        .paddles
        .iter()
        .enumerate()
        .filter(|(_, p)| **p != nominal)
        .map(|(port, _)| port)
        .collect();
    json!({
        "frames": page.frames,
        "seconds": page.seconds,
        "adapter": page.adapter,
        "backend": page.backend,
        "frame_interval_ms": pair(page.frame_stats.interval_ms()),
        "frame_work_ms": pair(page.frame_stats.work_ms()),
        "board": session.board_name(),
        "device": session.uses_device(),
        "stage": session.stage().name(),
        "screen": last.map(|o| o.screen.name()),
        "heading": last.map(|o| o.hud.heading.as_str()),
        "lines": last.map(|o| &o.hud.lines),
        "calibration_rod": session.calibration_rod(),
        "calibrated_ports": calibrated_ports,
        "paused": last.is_some_and(|o| o.paused),
        "health": format!("{:?}", session.rod_inputs().health).to_lowercase(),
        "match_time_s": newest.time_s,
        "score": newest.score,
        "ball": newest.ball.position,
        "controllers": controllers,
        "input_rods": rods,
        "physics_rods": physics_rods,
        "steps": counters.steps,
        "dropped_steps": counters.dropped_steps,
        "kicks": counters.kicks,
        "goals": counters.goals,
        "reports": {
            "received": link.received,
            "lost": link.lost,
            "malformed": link.malformed,
            "reconnects": link.reconnects,
        },
        "out_reports": out_reports,
        "sound": {
            "output": page.audio.device_description(),
            "notice": page.audio.notice(),
            "played": page.audio.played(),
        },
    })
}

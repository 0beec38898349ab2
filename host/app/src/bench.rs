//! `space-foosball bench match [--json]`: what one 1 kHz physics step of the full table
//! costs, and how late the rods in physics follow the rods on the board.
//!
//! * **Step time**: the computer against itself on the chosen table (every rod moving,
//!   the ball in play), each `Match::step` timed alone (arena: rods, world steps,
//!   contacts; rules; computer), after a warm-up. Median, mean, 99th percentile, worst,
//!   in µs. The target is under 50 µs (5 % of a core at 1 kHz).
//! * **Input latency**: the emulated board (lockstep, one IN report per 1 ms, exactly
//!   the period of the real board) moves the Home attack rod with a scripted ramp
//!   (constant slide and spin speed); each step the match consumes the newest report
//!   and the rod's pose in physics is compared with where the emulated rod was: the
//!   delay is `(time − when the emulated rod was at the physics pose)`, from the end
//!   of the physics step. It includes the optical sensor frames, the mice's own sample
//!   period (`BoardConfig::firmware_mouse`, 200 samples/s: one packet per 5 ms), the
//!   firmware's 1 ms report and the physics step. Mean and worst over the ramp, slide
//!   and angle; with the tracker's pose prediction over the mice's 5 ms packet period
//!   plus a 2 ms lead for the packet's time on the PS/2 wire (what headless play uses,
//!   `input_latency_ms`), without the lead, and without prediction; and how far the
//!   predicted rod overshoots when the emulated rod stops. The unpredicted delay is split
//!   into how far the servos' target lags the hand (the input chain: on average half the
//!   mice's 5 ms sample period, the packet's 2.64 ms on the wire, the report) and how far
//!   the rod in physics lags its target (the servo).
//! * **Input latency on board time**: the same ramp with the tracker on the board's
//!   clock (`PaddleTracker::set_device_time_tracking`) and no prediction horizon: the
//!   emulated board sends version 2 reports (device time, per-paddle packet age), each
//!   packet's motion is placed at its board time (packet end less its 2.64 ms on the
//!   PS/2 wire), the velocity rebuilt from the packets, and the pose carried to the
//!   report's time. Median, mean and worst over the ramp, and its overshoot.

use anyhow::{bail, Context, Result};
use foosball_sim::motion::script::MotionScript;
use foosball_sim::{BoardConfig, InProcessBoard, Pacing};
use space_foosball::input::calibration::Calibration;
use space_foosball::input::paddles::{BoardInput, MOUSE_PACKET_PREDICTION_MS, PS2_WIRE_LEAD_MS};
use space_foosball::play::{idle_inputs, Match, MatchConfig};
use std::time::Instant;

/// Arguments of `space-foosball bench`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// What to measure.
    #[command(subcommand)]
    pub what: What,
}

/// The benchmarks.
#[derive(clap::Subcommand, Debug)]
pub enum What {
    /// µs per 1 kHz physics step of the full table in play, and input-to-rod latency.
    Match(MatchArgs),
    /// Frame time of the renderer on the demo match (one JSON line).
    Render(crate::render_bench::RenderArgs),
    /// Save, restore and an eight-frame rollback of the match (one JSON line).
    Rollback(crate::rollback_bench::RollbackArgs),
}

/// Arguments of `bench match`.
#[derive(clap::Args, Debug)]
pub struct MatchArgs {
    /// One JSON object on stdout instead of a table.
    #[arg(long)]
    pub json: bool,
    /// Physics steps to time (1 step = 1 ms of match time), after 1000 of warm-up.
    #[arg(long, default_value_t = 30_000)]
    pub steps: u64,
    /// Table: `standard`, `paper` or a TOML file.
    #[arg(long, default_value = "standard")]
    pub table: String,
    /// Seed of the match.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
}

/// Runs a benchmark.
pub fn run(args: &Args) -> Result<()> {
    match &args.what {
        What::Match(m) => run_match(m),
        What::Render(r) => crate::render_bench::run(r),
        What::Rollback(r) => crate::rollback_bench::run(r),
    }
}

const WARM_UP_STEPS: u64 = 1000;

/// Step times, µs, sorted.
fn time_steps(args: &MatchArgs) -> Result<(Vec<f64>, [u32; 2], u64)> {
    let (table, mut m) = crate::headless::endless_match(&args.table, args.seed)?;
    let inputs = idle_inputs(&table);
    for _ in 0..WARM_UP_STEPS {
        m.step(&inputs);
    }
    let mut times = Vec::with_capacity(args.steps as usize);
    for _ in 0..args.steps {
        let t0 = Instant::now();
        let events = m.step(&inputs);
        let dt = t0.elapsed();
        std::hint::black_box(events);
        times.push(dt.as_secs_f64() * 1e6);
    }
    times.sort_by(f64::total_cmp);
    Ok((times, m.score(), m.arena().physics_errors()))
}

fn percentile(sorted: &[f64], p: f64) -> f64 {
    if sorted.is_empty() {
        return f64::NAN;
    }
    let i = ((sorted.len() - 1) as f64 * p).round() as usize;
    sorted[i.min(sorted.len() - 1)]
}

/// The scripted ramp of the latency measurement: rest, then constant speeds.
const RAMP_START_S: f64 = 1.5;
const RAMP_S: f64 = 0.8;
const SLIDE_SPEED_M_PER_S: f64 = 0.1;
const SPIN_RAD_PER_S: f64 = 10.0;
/// Steps of the ramp's beginning left out (the velocity window and packets settle).
const RAMP_SETTLE_MS: u64 = 50;

/// What the latency run measured, ms (overshoot: m and rad).
struct Latency {
    slide_mean: f64,
    slide_worst: f64,
    angle_mean: f64,
    angle_worst: f64,
    /// Median over the ramp's steps, slide and angle delays together.
    median: f64,
    /// Largest slide past the final pose after the ramp stops, m.
    overshoot_slide_m: f64,
    /// Largest angle past the final pose after the ramp stops, rad.
    overshoot_angle_rad: f64,
    /// Mean over the ramp, slide and angle together, of how far the servos' target lags
    /// the hand (the mice's sampling, the PS/2 wire, the report, the tracker), ms.
    target_mean: f64,
}

/// How the tracker of a latency run turns reports into poses.
#[derive(Debug, Clone, Copy)]
enum Tracking {
    /// Report time, with a pose prediction horizon and a lead, ms (0, 0: none).
    Fixed { prediction_ms: u64, lead_ms: u64 },
    /// The board's clock (version 2 timing), no prediction horizon.
    BoardTime,
}

/// Latency of the Home attack rod tracked as `tracking` says.
fn latency(tracking: Tracking) -> Result<Latency> {
    let table = crate::headless::load_table("standard")?;
    let rod = 5;
    let port = table.rods[rod].port;
    let json = format!(
        r#"{{"rods":[{{"rod":{port},"segments":[
            {{"hold":{{"duration_s":{RAMP_START_S}}}}},
            {{"velocity":{{"duration_s":{RAMP_S},"axial_m_per_s":{SLIDE_SPEED_M_PER_S},"angle_rad_per_s":{SPIN_RAD_PER_S}}}}}
        ]}}]}}"#
    );
    let script = MotionScript::from_json(&json).context("latency script")?;
    let board =
        InProcessBoard::with_motion(BoardConfig::default(), Box::new(script), Pacing::Lockstep)
            .context("emulated board")?;
    let mut input = BoardInput::new(board, &table, Calibration::default());
    match tracking {
        Tracking::Fixed {
            prediction_ms,
            lead_ms,
        } => {
            input.tracker_mut().set_prediction_ms(prediction_ms);
            input.tracker_mut().set_prediction_lead_ms(lead_ms);
        }
        Tracking::BoardTime => input.tracker_mut().set_device_time_tracking(true),
    }
    let mut m = Match::new(MatchConfig::player_vs_computer(table.clone(), 1))?;
    let sign = table.rods[rod].handle_sign();
    let (mut slide, mut angle, mut target) = (Vec::new(), Vec::new(), Vec::new());
    let ramp_end_ms = ((RAMP_START_S + RAMP_S) * 1e3) as u64;
    let (final_slide, final_angle) = (SLIDE_SPEED_M_PER_S * RAMP_S, SPIN_RAD_PER_S * RAMP_S);
    let (mut overshoot_slide_m, mut overshoot_angle_rad) = (0.0f64, 0.0f64);
    for k in 0..ramp_end_ms + 200 {
        let inputs = input.poll(1);
        m.step(&inputs);
        // The pose in physics holds from the end of this step.
        let now_s = (k + 1) as f64 * 1e-3;
        if k < (RAMP_START_S * 1e3) as u64 + RAMP_SETTLE_MS {
            continue;
        }
        let pose = m.arena().rod_poses()[rod];
        if k >= ramp_end_ms {
            // Stopped: how far past the final pose does the physics rod go?
            overshoot_slide_m = overshoot_slide_m.max(sign * pose.slide_m - final_slide);
            overshoot_angle_rad = overshoot_angle_rad.max(sign * pose.angle_rad - final_angle);
            continue;
        }
        // When the emulated rod was where the physics rod is now, and where the servos
        // are told to take it.
        let slide_t = RAMP_START_S + sign * pose.slide_m / SLIDE_SPEED_M_PER_S;
        let angle_t = RAMP_START_S + sign * pose.angle_rad / SPIN_RAD_PER_S;
        slide.push((now_s - slide_t) * 1e3);
        angle.push((now_s - angle_t) * 1e3);
        let goal = m.arena().rod_targets()[rod];
        target.push((now_s - RAMP_START_S - sign * goal.slide_m / SLIDE_SPEED_M_PER_S) * 1e3);
        target.push((now_s - RAMP_START_S - sign * goal.angle_rad / SPIN_RAD_PER_S) * 1e3);
    }
    if slide.is_empty() {
        bail!("latency ramp produced no samples");
    }
    if matches!(tracking, Tracking::BoardTime) && !input.tracker().is_device_timed() {
        bail!("the emulated board's reports carried no board time");
    }
    let mean = |v: &[f64]| v.iter().sum::<f64>() / v.len() as f64;
    let worst = |v: &[f64]| v.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    let mut both: Vec<f64> = slide.iter().chain(&angle).copied().collect();
    both.sort_by(f64::total_cmp);
    Ok(Latency {
        median: percentile(&both, 0.5),
        slide_mean: mean(&slide),
        slide_worst: worst(&slide),
        angle_mean: mean(&angle),
        angle_worst: worst(&angle),
        overshoot_slide_m,
        overshoot_angle_rad,
        target_mean: mean(&target),
    })
}

fn run_match(args: &MatchArgs) -> Result<()> {
    if args.steps == 0 {
        bail!("--steps must be at least 1");
    }
    let (times, score, physics_errors) = time_steps(args)?;
    let mean = times.iter().sum::<f64>() / times.len() as f64;
    let median = percentile(&times, 0.5);
    let p99 = percentile(&times, 0.99);
    let worst = times.last().copied().unwrap_or(f64::NAN);
    let fixed = |prediction_ms, lead_ms| {
        latency(Tracking::Fixed {
            prediction_ms,
            lead_ms,
        })
    };
    let predicted = fixed(MOUSE_PACKET_PREDICTION_MS, PS2_WIRE_LEAD_MS)?;
    let packet_only = fixed(MOUSE_PACKET_PREDICTION_MS, 0)?;
    let raw = fixed(0, 0)?;
    let board_time = latency(Tracking::BoardTime)?;
    let input_latency = 0.5 * (predicted.slide_mean + predicted.angle_mean);
    let input_worst = predicted.slide_worst.max(predicted.angle_worst);
    let raw_latency = 0.5 * (raw.slide_mean + raw.angle_mean);
    let arena = space_foosball::arena::ArenaSettings::default();
    if args.json {
        println!(
            "{}",
            serde_json::json!({
                "step_us_median": median,
                "step_us_worst": worst,
                "input_latency_ms": input_latency,
                "step_us_mean": mean,
                "step_us_p99": p99,
                "steps": times.len(),
                "table": args.table,
                "substeps": arena.substeps,
                "score_during_bench": score,
                "physics_errors": physics_errors,
                "input_latency_worst_ms": input_worst,
                "input_latency_slide_ms": predicted.slide_mean,
                "input_latency_angle_ms": predicted.angle_mean,
                "input_prediction_ms": MOUSE_PACKET_PREDICTION_MS,
                "input_prediction_lead_ms": PS2_WIRE_LEAD_MS,
                "input_latency_without_lead_ms": 0.5 * (packet_only.slide_mean + packet_only.angle_mean),
                "prediction_overshoot_slide_mm": predicted.overshoot_slide_m * 1e3,
                "prediction_overshoot_angle_rad": predicted.overshoot_angle_rad,
                "input_latency_unpredicted_ms": raw_latency,
                "input_latency_unpredicted_worst_ms": raw.slide_worst.max(raw.angle_worst),
                "input_latency_median_ms": predicted.median,
                "input_latency_unpredicted_median_ms": raw.median,
                "input_latency_unpredicted_before_servo_ms": raw.target_mean,
                "servo_lag_unpredicted_ms": raw_latency - raw.target_mean,
                "input_latency_board_time_median_ms": board_time.median,
                "input_latency_board_time_ms": 0.5 * (board_time.slide_mean + board_time.angle_mean),
                "input_latency_board_time_worst_ms": board_time.slide_worst.max(board_time.angle_worst),
                "board_time_overshoot_slide_mm": board_time.overshoot_slide_m * 1e3,
                "board_time_overshoot_angle_rad": board_time.overshoot_angle_rad,
                "board_report_period_ms": 1,
                "mouse_sample_rate_hz": 200,
                "release_build": !cfg!(debug_assertions),
            })
        );
    } else {
        println!(
            "physics step of the full table, computer vs computer ({}):",
            args.table
        );
        println!(
            "  {} steps: median {median:.1} µs, mean {mean:.1} µs, p99 {p99:.1} µs, worst {worst:.1} µs",
            times.len()
        );
        println!("input to rod (emulated board, lockstep, 1 ms reports, 200 Hz mice):");
        for (name, l) in [
            (
                format!("predicted {MOUSE_PACKET_PREDICTION_MS} ms + {PS2_WIRE_LEAD_MS} ms lead"),
                &predicted,
            ),
            (
                format!("predicted {MOUSE_PACKET_PREDICTION_MS} ms"),
                &packet_only,
            ),
            ("unpredicted".to_string(), &raw),
            (
                "on board time, unpredicted (v2 reports)".to_string(),
                &board_time,
            ),
        ] {
            println!(
                "  {name}: median {:.2} ms; slide {:.2} ms (worst {:.2}), angle {:.2} ms \
                 (worst {:.2}); overshoot at a stop {:.2} mm, {:.3} rad",
                l.median,
                l.slide_mean,
                l.slide_worst,
                l.angle_mean,
                l.angle_worst,
                l.overshoot_slide_m * 1e3,
                l.overshoot_angle_rad
            );
        }
        println!(
            "  unpredicted, split: the servos' target lags the hand {:.2} ms (mouse sampling, \
             PS/2 wire, report, tracker), the rod lags its target {:.2} ms (the servo)",
            raw.target_mean,
            raw_latency - raw.target_mean
        );
        if cfg!(debug_assertions) {
            println!("(debug build: use --release for representative step times)");
        }
    }
    Ok(())
}

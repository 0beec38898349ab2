//! The hard cases at the defaults: each scene of [`crate::scene::hard`] stepped as its file
//! states it (no solver or integrator setting), and the figures it must hold, each with its
//! bound. `vphys hard` prints them as a table; the physics tests run the same cases.
//!
//! | case | figures (bound) |
//! |---|---|
//! | heavy on a pyramid | deepest overlap over the run (5 cm); fastest body at the end (1 m/s) |
//! | ball in a closed box | farthest from the exact path, bounce by bounce (1 µm); rise of kinetic energy in a step (round-off); farthest outside the walls (1 µm) |
//! | arm on stairs | deepest overlap over the run (2 mm) |
//! | Newton's cradle | the last sphere's shortfall from the struck speed (10 %); the fastest other sphere (10 % of the struck speed) |
//! | dominoes | deepest corner below the ground at the end (5 mm); dominoes never tipped (none) |
//! | stacks of 1:1000 masses | deepest overlap over the run (5 mm); farthest any cube moves (1 cm) |
//!
//! The exact path of the ball: with no gravity and no friction each axis of the ball's
//! centre moves on its own between the walls at `±(inner/2 − r)`, its velocity reversed and
//! scaled by the restitution at each wall (stopped where it meets the wall slower than the
//! restitution threshold). The bound is the sweep's round-off allowance (1 nm an impact)
//! over the fewer than 1000 impacts of a run.

use crate::dynamics::{BodyKind, DynamicsError};
use crate::geometry::{M3, V3};
use crate::pipeline::World;
use crate::scene::hard::{self as scenes, BOX_BALL};
use crate::scene::{SceneError, SceneFile};

/// One hard case: a scene and what it must hold.
#[derive(Clone, Debug)]
pub struct HardCase {
    /// Short name (`vphys hard` prints it).
    pub name: String,
    /// The scene, at the defaults.
    pub scene: SceneFile,
    check: Check,
}

/// What a case measures.
#[derive(Clone, Copy, Debug)]
enum Check {
    /// A pile struck by a heavy body.
    Pile,
    /// The ball among the six walls of a cube of this inner side (m).
    BallInBox { inner: f64, restitution: f64 },
    /// A tree against fixed geometry.
    Arm,
    /// A row of spheres, the first struck at this speed (m/s).
    Cradle { speed: f64 },
    /// Dominoes of these half extents (m).
    Dominoes { half: [f64; 3] },
    /// A stack at rest.
    Stack,
}

/// One measured figure and its bound: the case holds where every figure is at most its bound.
#[derive(Clone, Debug, PartialEq)]
pub struct Figure {
    /// What is measured.
    pub what: &'static str,
    /// The value measured (in `unit`).
    pub value: f64,
    /// The largest value allowed (in `unit`).
    pub bound: f64,
    /// Unit of the value and the bound.
    pub unit: &'static str,
}

impl Figure {
    /// Whether the value is within its bound (a NaN is not).
    pub fn holds(&self) -> bool {
        self.value <= self.bound
    }
}

/// A case's figures after its run.
#[derive(Clone, Debug)]
pub struct Outcome {
    /// The case's name.
    pub name: String,
    /// Steps taken.
    pub steps: u64,
    /// The figures.
    pub figures: Vec<Figure>,
}

impl Outcome {
    /// Whether every figure holds.
    pub fn holds(&self) -> bool {
        self.figures.iter().all(Figure::holds)
    }
}

/// Why a case could not run.
#[derive(Debug, thiserror::Error)]
pub enum HardCaseError {
    /// The scene did not build.
    #[error("{0}")]
    Scene(#[from] SceneError),
    /// A step failed.
    #[error("{0}")]
    Step(#[from] DynamicsError),
}

fn case(name: &str, scene: SceneFile, check: Check) -> HardCase {
    HardCase {
        name: name.to_string(),
        scene,
        check,
    }
}

/// The cases of the hard-case table, as the table states them.
pub fn cases() -> Vec<HardCase> {
    let mut out = vec![case(
        "heavy-on-pyramid",
        scenes::heavy_on_pyramid(500.0, 10, 2.0),
        Check::Pile,
    )];
    for (i, d) in scenes::spread_directions(10).into_iter().enumerate() {
        let v = [60.0 * d[0], 60.0 * d[1], 60.0 * d[2]];
        out.push(ball_case(&format!("ball-in-box-{i}"), v, 0.3, 0.9));
    }
    out.push(case(
        "arm-on-stairs",
        scenes::arm_on_stairs(4, 0.3, 1.0, 0.2, 4),
        Check::Arm,
    ));
    out.push(case(
        "newtons-cradle",
        scenes::newtons_cradle(5, 1.0),
        Check::Cradle { speed: 1.0 },
    ));
    out.push(dominoes_case(
        "dominoes-100",
        100,
        [0.025, 0.25, 0.5],
        0.6,
        1500,
    ));
    out
}

/// Variants of the same kinds with other sizes, masses and speeds.
pub fn variants() -> Vec<HardCase> {
    let d = scenes::spread_directions(3);
    vec![
        case(
            "heavy-on-pyramid-100kg",
            scenes::heavy_on_pyramid(100.0, 6, 1.0),
            Check::Pile,
        ),
        ball_case(
            "ball-in-box-30",
            [30.0 * d[0][0], 30.0 * d[0][1], 30.0 * d[0][2]],
            0.3,
            0.9,
        ),
        ball_case(
            "ball-in-box-120",
            [120.0 * d[1][0], 120.0 * d[1][1], 120.0 * d[1][2]],
            0.5,
            0.9,
        ),
        ball_case(
            "ball-in-box-small",
            [40.0 * d[2][0], 40.0 * d[2][1], 40.0 * d[2][2]],
            0.1,
            0.5,
        ),
        case(
            "arm-on-stairs-3",
            scenes::arm_on_stairs(3, 0.2, 0.5, 0.15, 5),
            Check::Arm,
        ),
        case(
            "newtons-cradle-3",
            scenes::newtons_cradle(3, 3.0),
            Check::Cradle { speed: 3.0 },
        ),
        case(
            "newtons-cradle-8",
            scenes::newtons_cradle(8, 0.8),
            Check::Cradle { speed: 0.8 },
        ),
        dominoes_case("dominoes-small", 30, [0.0045, 0.012, 0.024], 0.03, 600),
        case(
            "stack-1000-on-1",
            scenes::mass_ratio_stack(&[1.0, 1000.0]),
            Check::Stack,
        ),
        case(
            "stack-1-between-1000",
            scenes::mass_ratio_stack(&[1000.0, 1.0, 1000.0]),
            Check::Stack,
        ),
        case(
            "stack-alternating-1000",
            scenes::mass_ratio_stack(&[1.0, 1000.0, 1.0, 1000.0, 1.0, 1000.0]),
            Check::Stack,
        ),
    ]
}

fn ball_case(name: &str, v: [f64; 3], inner: f64, restitution: f64) -> HardCase {
    let scene = scenes::ball_in_box(v, inner, restitution, 1.0 / 60.0);
    case(name, scene, Check::BallInBox { inner, restitution })
}

fn dominoes_case(name: &str, n: usize, half: [f64; 3], spacing: f64, steps: u64) -> HardCase {
    let scene = scenes::dominoes(n, half, spacing, steps);
    case(name, scene, Check::Dominoes { half })
}

/// Runs a case for its scene's steps and measures its figures.
pub fn run(case: &HardCase) -> Result<Outcome, HardCaseError> {
    let mut w = case.scene.build()?;
    let steps = case.scene.steps.unwrap_or(600);
    let figures = match case.check {
        Check::Pile => pile(&mut w, steps)?,
        Check::BallInBox { inner, restitution } => {
            let threshold = case.scene.solver.restitution_threshold;
            ball_in_box(&mut w, steps, inner, restitution, threshold)?
        }
        Check::Arm => vec![deepest_overlap(&mut w, steps, 0.002)?],
        Check::Cradle { speed } => cradle(&mut w, steps, speed)?,
        Check::Dominoes { half } => dominoes(&mut w, steps, half)?,
        Check::Stack => stack(&mut w, steps)?,
    };
    Ok(Outcome {
        name: case.name.clone(),
        steps,
        figures,
    })
}

fn dynamic(w: &World) -> impl Iterator<Item = usize> + '_ {
    (0..w.bodies.len()).filter(|&i| w.bodies.kind[i] == BodyKind::Dynamic)
}

/// The deepest overlap of any contact over `steps` steps, against `bound` (m).
fn deepest_overlap(w: &mut World, steps: u64, bound: f64) -> Result<Figure, HardCaseError> {
    let mut deepest: f64 = 0.0;
    for _ in 0..steps {
        w.step()?;
        deepest = deepest.max(w.max_penetration());
    }
    Ok(Figure {
        what: "deepest overlap over the run",
        value: deepest,
        bound,
        unit: "m",
    })
}

fn pile(w: &mut World, steps: u64) -> Result<Vec<Figure>, HardCaseError> {
    let overlap = deepest_overlap(w, steps, 0.05)?;
    let fastest = dynamic(w)
        .map(|i| w.bodies.vel[i].norm())
        .fold(0.0, f64::max);
    Ok(vec![
        overlap,
        Figure {
            what: "fastest body at the end",
            value: fastest,
            bound: 1.0,
            unit: "m/s",
        },
    ])
}

/// One axis of the ball's exact path after `t` (s): position and velocity.
fn exact_axis(mut x: f64, mut v: f64, t: f64, wall: f64, e: f64, threshold: f64) -> (f64, f64) {
    let mut now = 0.0;
    // Each bounce takes at least the time to cross the box at the current speed, and the
    // speed falls by the restitution at each; past 10⁴ bounces the ball has stopped.
    for _ in 0..10_000 {
        if v == 0.0 {
            return (x, 0.0);
        }
        let target = if v > 0.0 { wall } else { -wall };
        let dt = (target - x) / v;
        if now + dt > t {
            return (x + v * (t - now), v);
        }
        now += dt;
        x = target;
        v = if v.abs() > threshold { -e * v } else { 0.0 };
    }
    (x, 0.0)
}

fn ball_in_box(
    w: &mut World,
    steps: u64,
    inner: f64,
    e: f64,
    threshold: f64,
) -> Result<Vec<Figure>, HardCaseError> {
    let (radius, _) = BOX_BALL;
    let ball = w.bodies.name.iter().position(|n| n == "ball").unwrap_or(0);
    let (p0, v0) = (w.bodies.pos[ball], w.bodies.vel[ball]);
    let wall = inner / 2.0 - radius;
    let e0 = w.bodies.kinetic_energy();
    let (mut off_path, mut outside, mut rise): (f64, f64, f64) = (0.0, f64::NEG_INFINITY, 0.0);
    let mut before = e0;
    for k in 1..=steps {
        w.step()?;
        let t = k as f64 * w.dt;
        let p = w.bodies.pos[ball];
        let exact = V3::from_fn(|a, _| exact_axis(p0[a], v0[a], t, wall, e, threshold).0);
        off_path = off_path.max((p - exact).norm());
        outside = outside.max(p.abs().max() - wall);
        let now = w.bodies.kinetic_energy();
        rise = rise.max(now - before);
        before = now;
    }
    Ok(vec![
        Figure {
            what: "farthest from the exact path",
            value: off_path,
            bound: 1e-6,
            unit: "m",
        },
        Figure {
            what: "largest rise of kinetic energy over a step",
            value: rise,
            bound: 1e-12 * e0,
            unit: "J",
        },
        Figure {
            what: "farthest past the walls",
            value: outside,
            bound: 1e-6,
            unit: "m",
        },
    ])
}

fn cradle(w: &mut World, steps: u64, speed: f64) -> Result<Vec<Figure>, HardCaseError> {
    for _ in 0..steps {
        w.step()?;
    }
    let spheres: Vec<usize> = dynamic(w).collect();
    let (&last, others) = spheres.split_last().unwrap_or((&0, &[]));
    let fastest_other = others
        .iter()
        .map(|&i| w.bodies.vel[i].norm())
        .fold(0.0, f64::max);
    Ok(vec![
        Figure {
            what: "the last sphere's shortfall from the struck speed",
            value: 1.0 - w.bodies.vel[last].x / speed,
            bound: 0.1,
            unit: "–",
        },
        Figure {
            what: "the fastest other sphere, over the struck speed",
            value: fastest_other / speed,
            bound: 0.1,
            unit: "–",
        },
    ])
}

/// The lowest of a box's eight corners (m, world `z`).
fn lowest_corner(rot: &M3, pos: &V3, half: &[f64; 3]) -> f64 {
    let mut low = f64::INFINITY;
    for c in 0..8 {
        let s = |bit: usize| if c >> bit & 1 == 1 { 1.0 } else { -1.0 };
        let corner = pos + rot * V3::new(s(0) * half[0], s(1) * half[1], s(2) * half[2]);
        low = low.min(corner.z);
    }
    low
}

fn dominoes(w: &mut World, steps: u64, half: [f64; 3]) -> Result<Vec<Figure>, HardCaseError> {
    for _ in 0..steps {
        w.step()?;
    }
    let (mut deepest, mut standing): (f64, usize) = (0.0, 0);
    for i in dynamic(w) {
        let (r, p) = (&w.bodies.rot[i], &w.bodies.pos[i]);
        deepest = deepest.max(-lowest_corner(r, p, &half));
        // Never tipped: its long axis still within 5° of the vertical.
        if r[(2, 2)] > 5f64.to_radians().cos() {
            standing += 1;
        }
    }
    Ok(vec![
        Figure {
            what: "deepest corner below the ground at the end",
            value: deepest,
            bound: 0.005,
            unit: "m",
        },
        Figure {
            what: "dominoes never tipped",
            value: standing as f64,
            bound: 0.0,
            unit: "",
        },
    ])
}

fn stack(w: &mut World, steps: u64) -> Result<Vec<Figure>, HardCaseError> {
    let start: Vec<(usize, V3)> = dynamic(w).map(|i| (i, w.bodies.pos[i])).collect();
    let overlap = deepest_overlap(w, steps, 0.005)?;
    let moved = start
        .iter()
        .map(|(i, p)| (w.bodies.pos[*i] - p).norm())
        .fold(0.0, f64::max);
    Ok(vec![
        overlap,
        Figure {
            what: "farthest any cube moves",
            value: moved,
            bound: 0.01,
            unit: "m",
        },
    ])
}

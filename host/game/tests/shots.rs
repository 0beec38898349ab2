//! Shots from a pin, against physics: the hand's targets scripted as a player's hand moves
//! (through [`Arena::set_rod_targets`], the arena's input → servo-target mapping with its
//! bumpers), the ball leaving by the foot's impact alone.
//!
//! * **Snake shot**: the ball pinned under the foot, the hand spins the rod forward from
//!   the pin; the foot lets go, turns over the top and strikes the ball from behind.
//! * **Pull shot**: the ball pinned under the foot is dragged sideways along the rod by the
//!   slide; the foot lets go, the man is pulled past it, wound back, and struck forward
//!   while the hand sweeps the rod back across the ball.
//!
//! Both must leave at 5–15 m/s (hard shots reach about 15 m/s) towards the Away goal, no
//! faster than `(1 + e)` × the foot's speed at impact (an impact on a foot of infinite
//! effective mass with restitution `e`), and along the rod by no more than the man can
//! give there: the sole is round about the rod axis, so its normal impulse has no
//! component along the rod and only friction (at most `μ` × the normal impulse) moves the
//! ball along it, plus what the man's side gives by impact when the rod sweeps sideways,
//! at most `(1 + e)` × the slide's speed.

mod pin;

use pin::{lifted, Sole};
use space_foosball::ai::RodTarget;
use space_foosball::arena::{Arena, ArenaSettings};
use space_foosball::rules::ContactWith;
use space_foosball::Table;

/// Home attack: x = 0.225, a man at y = 0; Home shoots towards +x with negative spin.
const ROD: usize = 5;

/// The pinned ball and the arena holding it.
struct Pinned {
    arena: Arena,
    targets: Vec<RodTarget>,
    /// The rod's angle on the pin, rad.
    angle: f64,
}

/// The attack's middle man lowered at 1 rad/s onto a ball resting in front of the rod, the
/// foot on its top, pressing at the hand's torque for 200 ms.
fn pinned(table: &Table) -> Pinned {
    let r = table.ball.radius_m();
    let sole = Sole::of(table, ROD);
    let dx = sole.ball_offset_for(table, 0.0);
    let mut arena = Arena::new(table).unwrap();
    let mut targets = lifted(table);
    targets[ROD].angle_rad = -1.5;
    arena.set_rod_targets(&targets);
    for _ in 0..300 {
        arena.step();
    }
    arena.place_ball([table.rods[ROD].x_m + dx, 0.0, r], [0.0; 3]);
    let stop = sole.touching_angle(dx, r - table.field.rod_height_m) + 0.5;
    let mut k = 0;
    loop {
        let th = (-1.5 + 1e-3 * k as f64).min(stop);
        targets[ROD].angle_rad = th;
        arena.set_rod_targets(&targets);
        arena.step();
        k += 1;
        if th >= stop && k > 1500 {
            break;
        }
    }
    let angle = arena.rod_poses()[ROD].angle_rad;
    Pinned {
        arena,
        targets,
        angle,
    }
}

/// The hand eases off the pin over 20 ms: its target comes back to where the rod stands,
/// so the servo no longer presses the foot into the ball (a player relaxing the wrist
/// before the shot; lifting off a ball pressed at full torque would fling it).
fn ease(p: &mut Pinned) {
    let at = p.arena.rod_poses()[ROD];
    let from = p.targets[ROD];
    for k in 0..20 {
        let f = (k + 1) as f64 / 20.0;
        p.targets[ROD].angle_rad = from.angle_rad + (at.angle_rad - from.angle_rad) * f;
        p.arena.set_rod_targets(&p.targets);
        p.arena.step();
    }
    p.angle = p.arena.rod_poses()[ROD].angle_rad;
}

/// What a shot did.
#[derive(Debug)]
struct Shot {
    /// The ball's velocity 5 ms after its last contact with the man, m/s.
    velocity: [f64; 3],
    /// The foot's speed (reach × spin) on the step before the strike's first contact, m/s.
    foot_speed: f64,
    /// The rod's slide speed on that step, m/s.
    sweep_speed: f64,
}

/// Drives the arena through `motion(k)` (slide m, angle rad) from step `from` on, until 5 ms
/// after the man's last contact with the ball once the strike began (`strike_from`: the
/// first step at which a contact counts as the strike).
fn shoot(
    p: &mut Pinned,
    table: &Table,
    steps: usize,
    strike_from: usize,
    motion: impl Fn(usize) -> (f64, f64),
) -> Shot {
    let reach = table.character_of(ROD).foot_reach_m;
    let mut foot_speed = None;
    let mut sweep_speed = 0.0;
    let mut last = None;
    for k in 0..steps {
        let (s, th) = motion(k);
        p.targets[ROD] = RodTarget {
            slide_m: s,
            angle_rad: th,
        };
        p.arena.set_rod_targets(&p.targets);
        let [slide_v, spin] = p.arena.rod_velocities()[ROD];
        let step = p.arena.step();
        let man = step
            .contacts
            .iter()
            .any(|c| c.with == (ContactWith::Man { rod: ROD }));
        if man && k >= strike_from {
            if foot_speed.is_none() {
                foot_speed = Some(reach * spin.abs());
                sweep_speed = slide_v.abs();
            }
            last = Some(k);
        }
        if last.is_some_and(|l| k >= l + 5) {
            break;
        }
    }
    Shot {
        velocity: p.arena.ball().velocity,
        foot_speed: foot_speed.expect("the foot strikes the ball"),
        sweep_speed,
    }
}

/// The bounds every shot keeps (see the module docs).
fn check(table: &Table, shot: &Shot, what: &str) {
    let v = shot.velocity;
    let horizontal = v[0].hypot(v[1]);
    let speed = (horizontal * horizontal + v[2] * v[2]).sqrt();
    eprintln!("{what}: {speed:.2} m/s, {shot:?}");
    assert!(
        (5.0..=15.0).contains(&speed),
        "{what}: {speed} m/s, {shot:?}"
    );
    let e = table.ball.restitution;
    assert!(
        speed <= (1.0 + e) * shot.foot_speed,
        "{what}: {speed} m/s from a foot at {} m/s",
        shot.foot_speed
    );
    let mu = (table.ball.friction * ArenaSettings::default().man_friction).sqrt();
    assert!(v[0] > 0.0, "{what}: towards the Away goal, {v:?}");
    // Along the rod the ball gets at most what the man's side, sweeping at the rod's slide
    // speed, can give by impact, `(1 + e) v_slide`, and what friction can give with the
    // forward impulse, `μ v_x`.
    assert!(
        v[1].abs() <= (1.0 + e) * shot.sweep_speed + mu * v[0],
        "{what}: sideways within the sweep and the man's friction (μ = {mu}), {shot:?}"
    );
}

#[test]
fn a_snake_shot_from_a_pin_leaves_fast_and_forward() {
    let table = Table::standard();
    let mut p = pinned(&table);
    ease(&mut p);
    let from = p.angle;
    // The hand rolls the handle forward at 80 rad/s from the pin through a full turn and
    // 1.5 rad of follow-through (the foot leaves the ball forward and up, so the first
    // contacts of the turn are the letting go, not the strike).
    let spin = 80.0;
    let end = from - 2.0 * std::f64::consts::PI - 1.5;
    let shot = shoot(&mut p, &table, 400, 30, |k| {
        (0.0, (from - spin * 1e-3 * (k + 1) as f64).max(end))
    });
    check(&table, &shot, "snake");
}

#[test]
fn a_pull_shot_drags_the_ball_along_the_rod_then_strikes_it() {
    let table = Table::standard();
    let r = table.ball.radius_m();
    let man = table.character_of(ROD);
    let mut p = pinned(&table);
    let pressing = p.targets[ROD].angle_rad;
    let y0 = p.arena.ball().position[1];
    let s0 = p.arena.rod_poses()[ROD].slide_m;
    // Drag: the hand slides the rod 15 mm along +y in 50 ms, pressing all the while (the
    // ball rolls under the foot, falling behind it by half the drag: much further and it
    // rolls out past the sole's end).
    let drag = 0.015;
    for k in 0..100 {
        p.targets[ROD].slide_m = (drag * (k + 1) as f64 / 50.0).min(drag);
        p.targets[ROD].angle_rad = pressing;
        p.arena.set_rod_targets(&p.targets);
        p.arena.step();
    }
    let dragged = p.arena.ball().position[1] - y0;
    let slid = p.arena.rod_poses()[ROD].slide_m - s0;
    // A ball rolling without slipping between a sliding foot and the cloth moves half as
    // far as the foot (10 % less for the slip that the cloth's rolling resistance and the
    // sole's curvature allow); a locked pin moves all the way.
    assert!(
        dragged >= 0.45 * slid && dragged <= slid + 1e-4,
        "dragged {dragged} m by a {slid} m slide"
    );
    ease(&mut p);
    let from = p.angle;
    let yb = p.arena.ball().position[1];
    // Let go and go round: the foot lifts forward off the ball (50 ms), the man is pulled
    // aside past the ball (his foot clear of it by its radius and more), the rod winds back
    // with the foot behind (100 ms), then the hand sweeps the rod back across the ball
    // at 2 m/s while it spins forward at 100 rad/s.
    let aside = yb + 0.5 * man.foot_width_m + r + 0.015;
    let wound = 0.8;
    let (spin, sweep) = (100.0, 2.0);
    // The sweep crosses the ball's y as the foot comes to it (about 0.6 rad past feet
    // down): both start so that they meet there.
    let strike_ms = (wound + 0.6) / spin * 1e3;
    let sweep_start = 150.0 + strike_ms - (aside - yb) / sweep * 1e3;
    let shot = shoot(&mut p, &table, 600, 150, |k| {
        let t = k as f64;
        if t < 50.0 {
            (drag, from - 0.6 * t / 50.0)
        } else if t < 150.0 {
            let f = (t - 50.0) / 100.0;
            (
                drag + (aside - drag) * f,
                from - 0.6 + (wound - from + 0.6) * f,
            )
        } else {
            let slide = if t < sweep_start {
                aside
            } else {
                aside - sweep * (t - sweep_start) * 1e-3
            };
            (
                slide.max(yb - 0.05),
                (wound - spin * (t - 150.0) * 1e-3).max(-2.5),
            )
        }
    });
    check(&table, &shot, "pull");
    // The sweep went towards −y: friction can only drag the ball that way.
    assert!(shot.velocity[1] <= 1e-3, "{shot:?}");
}

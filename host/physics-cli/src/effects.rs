//! `vphys effects`: the cost of each effect added to a base scene, and the cost of the same
//! effect's data present but the effect undeclared (which must equal the base).

use anyhow::Result;
use virtual_physics::pipeline::Effect;
use virtual_physics::scene::builtin::{ball, towers};
use virtual_physics::scene::SceneFile;

use crate::run::{stats, time_steps};

/// The base: 4 × 4 towers of 5 boxes and 16 balls at rest on the ground; gravity, contacts,
/// friction. Materials carry restitution 0.3 and rolling resistance 0.05 and the scene has
/// damping rates and spinning balls, so every effect below has work to do when declared.
fn base() -> SceneFile {
    let mut s = towers(4, 4, 5);
    s.name = "effects-base".into();
    s.materials[0].restitution = 0.3;
    s.materials[0].rolling_resistance = 0.05;
    s.damping.linear = 0.1;
    s.damping.angular = 0.1;
    for i in 0..16 {
        let mut b = ball([-4.0 + 0.1 * i as f64, 5.0, 0.0175], [0.2, 0.0, 0.0]);
        b.name = format!("ball{i}");
        b.material = Some("box".into());
        b.angular_velocity = [0.0, 0.2 / 0.0175, 0.3];
        s.bodies.push(b);
    }
    s
}

/// The base without any effect-specific data (no restitution, rolling resistance or damping
/// rates): the reference an undeclared effect is compared with.
fn bare() -> SceneFile {
    let mut s = base();
    s.materials[0].restitution = 0.0;
    s.materials[0].rolling_resistance = 0.0;
    s.damping.linear = 0.0;
    s.damping.angular = 0.0;
    s
}

fn once(s: &SceneFile, steps: u64) -> Result<f64> {
    let mut w = s.build()?;
    Ok(stats(&time_steps(&mut w, steps, false)?).0)
}

/// Best-of-`rounds` median ms per step of each scene, measured interleaved (round robin) so
/// that machine load drifts affect all of them alike.
fn interleaved(scenes: &[&SceneFile], steps: u64, rounds: usize) -> Result<Vec<f64>> {
    let mut best = vec![f64::INFINITY; scenes.len()];
    for _ in 0..rounds {
        for (b, s) in best.iter_mut().zip(scenes) {
            *b = b.min(once(s, steps)?);
        }
    }
    Ok(best)
}

/// Runs the table.
pub fn run(json: bool, steps: u64) -> Result<()> {
    let rounds = 5;
    let b = base();
    let bare = bare();
    let mut rows = Vec::new();
    // Contacts: the base against gravity only.
    let mut no_contacts = bare.clone();
    no_contacts.effects = vec![Effect::Gravity];
    let t = interleaved(&[&bare, &no_contacts, &b], steps, rounds)?;
    rows.push(("contacts+friction".to_string(), t[0], t[1], t[2]));
    for e in [
        Effect::Restitution,
        Effect::RollingResistance,
        Effect::ContinuousCollision,
        Effect::Gyroscopic,
        Effect::Damping,
        Effect::Sleeping,
    ] {
        let mut with = b.clone();
        with.effects.push(e);
        let t = interleaved(&[&bare, &b, &with], steps, rounds)?;
        rows.push((e.name().to_string(), t[0], t[1], t[2]));
    }
    if json {
        let out = serde_json::json!({
            "base": {"scene": b.name, "bodies": b.bodies.len(), "steps": steps, "rounds": rounds},
            "rows": rows.iter().map(|(n, bare, u, d)| serde_json::json!({
                "effect": n, "bare_ms": bare, "undeclared_ms": u, "declared_ms": d,
                "undeclared_over_bare": u / bare, "declared_over_bare": d / bare,
            })).collect::<Vec<_>>(),
        });
        outln!("{out}");
    } else {
        outln!(
            "base: {} ({} bodies; gravity, contacts, friction), {steps} steps, median ms/step, \
             best of {rounds} interleaved rounds",
            b.name,
            b.bodies.len()
        );
        outln!(
            "{:<20} {:>9} {:>14} {:>12} {:>13} {:>11}",
            "effect",
            "bare ms",
            "undeclared ms",
            "declared ms",
            "undecl/bare",
            "decl/bare"
        );
        for (n, bare, u, d) in &rows {
            outln!(
                "{n:<20} {bare:>9.4} {u:>14.4} {d:>12.4} {:>13.3} {:>11.3}",
                u / bare,
                d / bare
            );
        }
        outln!(
            "bare: no restitution, rolling resistance or damping data; undeclared: the data \
             present, effect not declared\n(contacts+friction row: 'undeclared' is the scene \
             with gravity only)"
        );
    }
    Ok(())
}

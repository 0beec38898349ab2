//! `vphys accuracy --check DIR`: a fresh run's deterministic columns against the committed
//! report, row by row.
//!
//! Compared: `error`, `energy_drift`, `momentum_drift`, `flips`, `penetration` and every
//! `detail` value — what the simulation computes. Never compared: `cpu_s_per_sim_s` and the
//! step costs (timings of this machine).
//!
//! References, both in `DIR`: `accuracy.json`, the full report, and `accuracy-quick.json`, the
//! quick report. A fresh row is compared with the full report's row of the same problem,
//! integrator, step and substeps where the full report has one — so the quick run checks the
//! committed full report on every row they share (all but the towers) — and otherwise with the
//! quick report's (the towers of the quick run are a smaller scene than the full report's).
//! A fresh row found in neither reference is a difference too.
//!
//! Tolerance. The committed JSON holds every number exactly (shortest round-trip form), and
//! the run is deterministic: the same build gives the same bits (Rust neither reorders nor
//! fuses floating-point operations; the four-lane solve is bit for bit the scalar one). What
//! may differ on another machine is the last bit of a libm function (`sin`, `cos`, `exp`)
//! and what the dynamics make of it. Integers (`flips`, `substeps`) must match exactly;
//! floats within `REL` relative — a thousand times finer than the three significant digits
//! the report and the READMEs print — or `ABS` absolute, the level of quantities that are
//! rounding noise themselves (the energy drift of the conserving integrators, about 1e-12,
//! is a sum of rounding errors over 10⁴ steps).

use std::fmt::Write as _;
use std::path::Path;

use anyhow::{bail, Context, Result};
use serde_json::Value;

/// Relative tolerance on floats (see the module docs).
pub const REL: f64 = 1e-6;
/// Absolute tolerance on floats (see the module docs).
pub const ABS: f64 = 1e-12;

/// The float columns compared, besides `detail`.
const FLOAT_COLUMNS: [&str; 4] = ["error", "energy_drift", "momentum_drift", "penetration"];
/// The integer columns compared.
const INT_COLUMNS: [&str; 1] = ["flips"];

/// A row's identity: problem, integrator, step (exact bits; the same constants on both
/// sides), substeps.
type Key = (String, String, u64, Option<u64>);

fn key(row: &Value) -> Key {
    (
        row["problem"].as_str().unwrap_or("").to_string(),
        row["integrator"].as_str().unwrap_or("").to_string(),
        row["dt"].as_f64().unwrap_or(f64::NAN).to_bits(),
        row["substeps"].as_u64(),
    )
}

fn label(row: &Value) -> String {
    let dt = row["dt"].as_f64().unwrap_or(f64::NAN);
    match row["substeps"].as_u64() {
        Some(n) => format!(
            "{} {} substeps={n}",
            row["problem"].as_str().unwrap_or("?"),
            row["integrator"].as_str().unwrap_or("?")
        ),
        None => format!(
            "{} {} dt=1/{:.0}",
            row["problem"].as_str().unwrap_or("?"),
            row["integrator"].as_str().unwrap_or("?"),
            1.0 / dt
        ),
    }
}

/// A float cell: JSON `null` is a diverged run (infinity).
fn float(v: &Value) -> Option<f64> {
    match v {
        Value::Null => Some(f64::INFINITY),
        v => v.as_f64(),
    }
}

/// Whether two committed/fresh floats agree within the tolerance.
pub fn close(a: f64, b: f64) -> bool {
    if a == b {
        return true;
    }
    if !a.is_finite() || !b.is_finite() {
        return false;
    }
    (a - b).abs() <= REL * a.abs().max(b.abs()) + ABS
}

/// The columns in which `fresh` differs from `committed`, as `name committed → fresh`.
pub fn differences(committed: &Value, fresh: &Value) -> Vec<String> {
    let mut out = Vec::new();
    let show = |v: &Value| match v {
        Value::Null => "null".to_string(),
        v => v.to_string(),
    };
    for c in FLOAT_COLUMNS {
        let (a, b) = (committed.get(c), fresh.get(c));
        let same = match (a, b) {
            (None, None) => true,
            (Some(a), Some(b)) => matches!((float(a), float(b)), (Some(x), Some(y)) if close(x, y)),
            _ => false,
        };
        if !same {
            out.push(format!(
                "{c} {} → {}",
                a.map_or("absent".into(), show),
                b.map_or("absent".into(), show)
            ));
        }
    }
    for c in INT_COLUMNS {
        if committed.get(c) != fresh.get(c) {
            out.push(format!(
                "{c} {} → {}",
                committed.get(c).map_or("absent".into(), show),
                fresh.get(c).map_or("absent".into(), show)
            ));
        }
    }
    let empty = serde_json::Map::new();
    let dc = committed["detail"].as_object().unwrap_or(&empty);
    let df = fresh["detail"].as_object().unwrap_or(&empty);
    for name in dc.keys().chain(df.keys().filter(|k| !dc.contains_key(*k))) {
        let (a, b) = (dc.get(name), df.get(name));
        let same =
            matches!((a.and_then(float), b.and_then(float)), (Some(x), Some(y)) if close(x, y));
        if !same {
            out.push(format!(
                "detail.{name} {} → {}",
                a.map_or("absent".into(), show),
                b.map_or("absent".into(), show)
            ));
        }
    }
    out
}

fn read(path: &Path) -> Result<Value> {
    let text = std::fs::read_to_string(path)
        .with_context(|| format!("reading the committed report {}", path.display()))?;
    let v: Value = serde_json::from_str(&text)
        .with_context(|| format!("the committed report {} is not JSON", path.display()))?;
    if !v["rows"].is_array() {
        bail!(
            "the committed report {} has no \"rows\" list",
            path.display()
        );
    }
    Ok(v)
}

/// The outcome of a check: a text to print and how many rows differ.
pub struct Outcome {
    /// One line per differing row, then a summary line.
    pub text: String,
    /// Rows that differ or have no reference.
    pub differing: usize,
    /// Rows compared.
    pub compared: usize,
}

/// Compares `fresh` (a report as JSON) with the references `full` and `quick`.
pub fn compare(fresh: &Value, full: &Value, quick: &Value) -> Outcome {
    let index = |r: &Value| -> Vec<(Key, Value)> {
        r["rows"]
            .as_array()
            .map(|rows| rows.iter().map(|row| (key(row), row.clone())).collect())
            .unwrap_or_default()
    };
    let (full_rows, quick_rows) = (index(full), index(quick));
    let same_scene = |a: &Value, b: &Value| a["towers_scene"] == b["towers_scene"];
    let lookup = |rows: &[(Key, Value)], k: &Key, rf: &Value| {
        let towers_ok = k.0 != "towers" || same_scene(fresh, rf);
        if !towers_ok {
            return None;
        }
        rows.iter().find(|(rk, _)| rk == k).map(|(_, v)| v.clone())
    };
    let mut text = String::new();
    let (mut differing, mut compared, mut against_full) = (0, 0, 0);
    for row in fresh["rows"].as_array().into_iter().flatten() {
        let k = key(row);
        compared += 1;
        let (reference, from) = match lookup(&full_rows, &k, full) {
            Some(r) => {
                against_full += 1;
                (Some(r), "accuracy.json")
            }
            None => (lookup(&quick_rows, &k, quick), "accuracy-quick.json"),
        };
        match reference {
            None => {
                differing += 1;
                let _ = writeln!(text, "no committed row: {}", label(row));
            }
            Some(r) => {
                let d = differences(&r, row);
                if !d.is_empty() {
                    differing += 1;
                    let _ = writeln!(
                        text,
                        "differs from {from} (committed → fresh): {}: {}",
                        label(row),
                        d.join(", ")
                    );
                }
            }
        }
    }
    let _ = writeln!(
        text,
        "accuracy check: {compared} rows ({against_full} against the full report, {} against \
         the quick report), {differing} differ (integers exact; floats within {REL:e} relative \
         or {ABS:e} absolute; timings not compared)",
        compared - against_full
    );
    Outcome {
        text,
        differing,
        compared,
    }
}

/// Reads the references in `dir` and compares `fresh` with them.
pub fn check_dir(fresh: &Value, dir: &Path) -> Result<Outcome> {
    let full = read(&dir.join("accuracy.json"))?;
    let quick = read(&dir.join("accuracy-quick.json"))?;
    Ok(compare(fresh, &full, &quick))
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    fn report(rows: Value, scene: &str) -> Value {
        json!({"rows": rows, "towers_scene": scene, "quick": false})
    }

    fn row(error: f64, flips: u32) -> Value {
        json!({"problem": "tumbling-box", "integrator": "rkmk4", "dt": 0.001, "error": error,
               "cpu_s_per_sim_s": 1.0, "energy_drift": -1.3e-12, "flips": flips})
    }

    #[test]
    fn timings_are_not_compared_and_rounding_passes() {
        let full = report(json!([row(4.1e-9, 3)]), "towers-1120");
        let mut fresh_row = row(4.1e-9 * (1.0 + 1e-9), 3);
        fresh_row["cpu_s_per_sim_s"] = json!(2.0);
        fresh_row["energy_drift"] = json!(-1.3e-12 + 1e-14);
        let fresh = report(json!([fresh_row]), "towers-40");
        let o = compare(&fresh, &full, &report(json!([]), "towers-40"));
        assert_eq!((o.differing, o.compared), (0, 1), "{}", o.text);
    }

    #[test]
    fn a_changed_error_or_flip_count_is_named() {
        let full = report(json!([row(4.1e-9, 3)]), "towers-1120");
        for fresh_row in [row(4.2e-9, 3), row(4.1e-9, 4)] {
            let fresh = report(json!([fresh_row]), "towers-40");
            let o = compare(&fresh, &full, &report(json!([]), "towers-40"));
            assert_eq!(o.differing, 1, "{}", o.text);
            assert!(
                o.text.contains("tumbling-box rkmk4 dt=1/1000"),
                "{}",
                o.text
            );
        }
    }

    #[test]
    fn towers_of_another_scene_use_the_quick_reference() {
        let t = |err: f64| {
            json!({"problem": "towers", "integrator": "rkmk4", "dt": 1.0 / 480.0,
                   "substeps": 8, "error": err, "cpu_s_per_sim_s": 1.0,
                   "detail": {"max_sink_m": err}})
        };
        let full = report(json!([t(0.0086)]), "towers-1120");
        let quick = report(json!([t(0.005)]), "towers-40");
        let fresh = report(json!([t(0.005)]), "towers-40");
        let o = compare(&fresh, &full, &quick);
        assert_eq!(o.differing, 0, "{}", o.text);
        let missing = compare(&fresh, &full, &report(json!([]), "towers-40"));
        assert_eq!(missing.differing, 1, "{}", missing.text);
        assert!(
            missing.text.contains("no committed row"),
            "{}",
            missing.text
        );
    }

    #[test]
    fn a_diverged_run_matches_only_a_diverged_run() {
        assert!(close(f64::INFINITY, f64::INFINITY));
        assert!(!close(f64::INFINITY, 1e300));
        let d = differences(&json!({"error": null}), &json!({"error": 1.0}));
        assert_eq!(d.len(), 1);
    }
}

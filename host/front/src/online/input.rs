//! A side's input for one frame: its rods' poses, quantised.
//!
//! A rod's slide is sent in micrometres and its angle in units of 10 µrad, as 32-bit
//! integers: both sides turn the same integers into the same `f64`s, so the match steps on
//! bit-identical inputs whichever side read the rods. The resolution is far below what a
//! rod's servo or the sensors resolve (the mice count 0.125 mm).

use serde::{Deserialize, Serialize};
use space_foosball::input::paddles::{InputHealth, RodInputs, RodState};
use space_foosball::side::Side;
use space_foosball::Table;

/// Most rods one side has (a foosball table has four).
pub const MAX_RODS_PER_SIDE: usize = 4;

/// Slide units per metre (µm).
const SLIDE_PER_M: f64 = 1e6;
/// Angle units per radian (10 µrad).
const ANGLE_PER_RAD: f64 = 1e5;

/// One side's rods for one frame: per rod of that side, in table order, `[slide, angle]`
/// in µm and 10 µrad.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
pub struct SideInput {
    /// Per rod `[slide µm, angle 10 µrad]`.
    pub rods: [[i32; 2]; MAX_RODS_PER_SIDE],
}

fn quantise(x: f64, per_unit: f64) -> i32 {
    // Saturating: an angle past ±21 000 rad (3 400 turns) is held there.
    let q = (x * per_unit).round();
    if q.is_nan() {
        0
    } else {
        q.clamp(f64::from(i32::MIN), f64::from(i32::MAX)) as i32
    }
}

/// The table's rods of `side`, in table order.
pub fn rods_of(table: &Table, side: Side) -> Vec<usize> {
    (0..table.rods.len())
        .filter(|&i| table.rods[i].team == side)
        .collect()
}

impl SideInput {
    /// `side`'s rods of `poses` (all rods of the table, `[slide m, angle rad]`), quantised.
    pub fn from_poses(table: &Table, side: Side, poses: &[[f64; 2]]) -> Self {
        let mut out = Self::default();
        for (k, rod) in rods_of(table, side)
            .into_iter()
            .take(MAX_RODS_PER_SIDE)
            .enumerate()
        {
            let [slide, angle] = poses.get(rod).copied().unwrap_or_default();
            out.rods[k] = [quantise(slide, SLIDE_PER_M), quantise(angle, ANGLE_PER_RAD)];
        }
        out
    }
}

/// The match's input for a frame from both sides' inputs (`[home, away]`).
pub fn rod_inputs(table: &Table, sides: [&SideInput; 2], time_ms: u64) -> RodInputs {
    let mut rods = vec![RodState::default(); table.rods.len()];
    for (s, side) in Side::BOTH.into_iter().enumerate() {
        for (k, rod) in rods_of(table, side)
            .into_iter()
            .take(MAX_RODS_PER_SIDE)
            .enumerate()
        {
            let [slide, angle] = sides[s].rods[k];
            rods[rod] = RodState {
                slide_m: f64::from(slide) / SLIDE_PER_M,
                angle_rad: f64::from(angle) / ANGLE_PER_RAD,
                present: true,
                ..RodState::default()
            };
        }
    }
    RodInputs {
        rods,
        health: InputHealth::Live,
        time_ms,
        lost_reports: 0,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn poses_survive_the_wire_to_their_quantum_and_sides_keep_their_rods() {
        let table = Table::standard();
        let poses: Vec<[f64; 2]> = (0..table.rods.len())
            .map(|i| [0.01 * i as f64 - 0.03, 1.7 * i as f64 - 40.0])
            .collect();
        let home = SideInput::from_poses(&table, Side::Home, &poses);
        let away = SideInput::from_poses(&table, Side::Away, &poses);
        let back = rod_inputs(&table, [&home, &away], 5);
        for (i, r) in back.rods.iter().enumerate() {
            assert!((r.slide_m - poses[i][0]).abs() <= 0.5e-6, "rod {i}");
            assert!((r.angle_rad - poses[i][1]).abs() <= 0.5e-5, "rod {i}");
        }
        // Far past the range, and not a number: held, not wrapped or lost.
        let wild = SideInput::from_poses(&table, Side::Home, &[[f64::NAN, 1e9]; 8]);
        assert_eq!(wild.rods[0], [0, i32::MAX]);
    }
}

//! What the pin and shot tests share: the rods lifted out of the way, distances, and the
//! geometry of a man's rounded sole on the ball (rod frame: `x` along the table from the
//! rod axis, `z` up from it; metres, radians, rod angle 0 = feet down).

// Each test crate uses its part of these.
#![allow(dead_code)]

use space_foosball::ai::RodTarget;
use space_foosball::arena::ArenaSettings;
use space_foosball::Table;
use std::f64::consts::FRAC_PI_2;

/// Every rod centred with its men lifted horizontal (feet towards `−x`), out of the ball's way.
pub fn lifted(table: &Table) -> Vec<RodTarget> {
    vec![
        RodTarget {
            slide_m: 0.0,
            angle_rad: FRAC_PI_2,
        };
        table.rods.len()
    ]
}

/// Distance between two points, m.
pub fn distance(a: [f64; 3], b: [f64; 3]) -> f64 {
    (0..3).map(|k| (a[k] - b[k]).powi(2)).sum::<f64>().sqrt()
}

/// The sole's geometry: the rounded sole is a capsule along the rod whose axis circles the
/// rod axis at `foot_reach − sole radius`; it touches the ball when that axis is
/// `sole radius + ball radius` from the ball's centre.
pub struct Sole {
    /// Distance of the sole's axis from the rod axis, m.
    pub circle_m: f64,
    /// Sole radius + ball radius, m.
    pub touch_m: f64,
}

impl Sole {
    pub fn of(table: &Table, rod: usize) -> Sole {
        let c = table.character_of(rod);
        let sole = 0.5 * c.body_depth_m;
        Sole {
            circle_m: c.foot_reach_m - sole,
            touch_m: sole + table.ball.radius_m(),
        }
    }

    /// Where the sole's axis is (x, z, relative to the rod axis) at rod angle `theta`.
    pub fn centre(&self, theta: f64) -> (f64, f64) {
        (-self.circle_m * theta.sin(), -self.circle_m * theta.cos())
    }

    /// The ball's centre offset along `x` from the rod (ball on the cloth) at which a foot
    /// in front of the rod (`x > 0`) touches it at `alpha` from its top (positive: the
    /// contact point further from the rod than the top).
    pub fn ball_offset_for(&self, table: &Table, alpha: f64) -> f64 {
        let dz = table.ball.radius_m() + self.touch_m * alpha.cos() - table.field.rod_height_m;
        -self.touch_m * alpha.sin() + (self.circle_m.powi(2) - dz * dz).sqrt()
    }

    /// The rod angle (rad, within `(-π/2, 0)`: foot in front) at which the sole, coming
    /// down from the horizontal, first touches a ball centred at `(dx, dz)` from the rod
    /// axis: a scan in 1 mrad steps, then bisection on the gap.
    pub fn touching_angle(&self, dx: f64, dz: f64) -> f64 {
        let gap = |th: f64| {
            let (x, z) = self.centre(th);
            ((x - dx).powi(2) + (z - dz).powi(2)).sqrt() - self.touch_m
        };
        let mut lo = -FRAC_PI_2;
        assert!(gap(lo) > 0.0, "the ball is below the raised foot");
        let mut hi = lo;
        while gap(hi) > 0.0 {
            lo = hi;
            hi += 1e-3;
            assert!(hi < 0.0, "the foot reaches the ball");
        }
        for _ in 0..60 {
            let mid = 0.5 * (lo + hi);
            if gap(mid) > 0.0 {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        0.5 * (lo + hi)
    }
}

/// The pin's friction bound: the smaller of the cloth's and the man's coefficients with the
/// ball (the engine mixes them as `sqrt(μa μb)`; the cloth carries the ball's friction).
pub fn pin_friction(table: &Table) -> f64 {
    let mu = table.ball.friction;
    mu.min((mu * ArenaSettings::default().man_friction).sqrt())
}

//! Geometric questions about a table that rules and AI ask: can a rod reach the ball,
//! which man is nearest, where does the foot sweep. Table frame, metres.

use super::{Rod, Table};

/// The man of a rod best placed for a lateral position, and the slide that puts him
/// there.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ManChoice {
    /// Index of the man on the rod (from `−y`).
    pub man: usize,
    /// Slide (m) that brings the man closest to the wanted `y`, within the travel.
    pub slide_m: f64,
    /// Remaining lateral miss at that slide, m (0 if he gets there).
    pub miss_m: f64,
}

impl Rod {
    /// The man that can get closest to `y` (m) within the travel, and the slide for it.
    /// Ties go to the man needing the smaller slide change from `current_slide_m`.
    pub fn nearest_man(&self, y: f64, current_slide_m: f64) -> ManChoice {
        let half = self.half_travel_m();
        let mut best: Option<(ManChoice, f64)> = None;
        for (man, offset) in self.man_offsets().into_iter().enumerate() {
            let slide_m = (y - offset).clamp(-half, half);
            let miss_m = (y - offset - slide_m).abs();
            let change = (slide_m - current_slide_m).abs();
            let better = match &best {
                None => true,
                Some((b, b_change)) => {
                    miss_m < b.miss_m - 1e-12
                        || ((miss_m - b.miss_m).abs() <= 1e-12 && change < *b_change)
                }
            };
            if better {
                best = Some((
                    ManChoice {
                        man,
                        slide_m,
                        miss_m,
                    },
                    change,
                ));
            }
        }
        // A validated rod has at least one man.
        best.map(|(b, _)| b).unwrap_or(ManChoice {
            man: 0,
            slide_m: 0.0,
            miss_m: f64::INFINITY,
        })
    }
}

impl Table {
    /// How far along `x` (m) from rod `rod`'s axis a resting ball's centre can be for a
    /// foot of this rod's men to touch it when the rod turns: the foot sweeps a circle
    /// of radius `foot_reach` about the axis, the ball's centre lies `rod_height − r`
    /// below it.
    pub fn reach_x_m(&self, rod: usize) -> f64 {
        let r = self.ball.radius_m();
        let reach = self.character_of(rod).foot_reach_m + r;
        let dz = self.field.rod_height_m - r;
        (reach * reach - dz * dz).max(0.0).sqrt()
    }

    /// Whether some man of rod `rod`, somewhere in its travel, can touch a ball whose
    /// centre is at lateral position `y` (m).
    pub fn rod_covers_y(&self, rod: usize, y: f64) -> bool {
        let r = &self.rods[rod];
        let choice = r.nearest_man(y, 0.0);
        choice.miss_m <= self.character_of(rod).half_width_m() + self.ball.radius_m()
    }

    /// Whether rod `rod` can play a ball at `(x, y)` (m, ball centre on the field).
    pub fn rod_can_reach(&self, rod: usize, x: f64, y: f64) -> bool {
        (x - self.rods[rod].x_m).abs() <= self.reach_x_m(rod) && self.rod_covers_y(rod, y)
    }

    /// Whether any rod can play a ball at `(x, y)`.
    pub fn any_rod_can_reach(&self, x: f64, y: f64) -> bool {
        (0..self.rods.len()).any(|i| self.rod_can_reach(i, x, y))
    }

    /// Foot sole position `(x, z)` (m) of rod `rod`'s men at angle `angle_rad`.
    pub fn foot_xz(&self, rod: usize, angle_rad: f64) -> (f64, f64) {
        let reach = self.character_of(rod).foot_reach_m;
        (
            self.rods[rod].x_m - reach * virtual_physics::transcendental::sin(angle_rad),
            self.field.rod_height_m - reach * virtual_physics::transcendental::cos(angle_rad),
        )
    }
}

#[cfg(test)]
mod tests {
    use crate::table::Table;

    #[test]
    fn nearest_man_picks_the_closest_within_travel() {
        let t = Table::standard();
        let mid = &t.rods[3]; // home midfield: 5 men 118 mm apart, 116 mm travel
        let c = mid.nearest_man(0.10, 0.0);
        assert_eq!(c.man, 3); // offset +0.118, slide −0.018
        assert!((c.slide_m + 0.018).abs() < 1e-12);
        assert_eq!(c.miss_m, 0.0);
        // Beyond the outermost man's travel: clamped, with a miss.
        let c = mid.nearest_man(0.34, 0.0);
        assert_eq!(c.man, 4);
        assert!((c.slide_m - 0.058).abs() < 1e-12);
        assert!((c.miss_m - (0.34 - 0.236 - 0.058)).abs() < 1e-12);
    }

    #[test]
    fn reach_covers_the_gap_between_rods() {
        let t = Table::standard();
        // The feet reach further than half the rod spacing: no dead strip along x.
        for i in 0..t.rods.len() {
            assert!(t.reach_x_m(i) > 0.075, "rod {i}: {}", t.reach_x_m(i));
            assert!(t.rod_can_reach(i, t.rods[i].x_m, 0.0));
        }
        assert!(t.any_rod_can_reach(0.0, 0.0));
        assert!(t.any_rod_can_reach(-0.45, 0.0));
        // Along the side wall no man gets there: a dead-ball strip.
        let y_wall = 0.5 * t.field.width_m - t.ball.radius_m();
        assert!(!t.rod_covers_y(3, y_wall));
        assert!(!t.any_rod_can_reach(0.0, y_wall));
    }

    #[test]
    fn foot_swings_towards_minus_x_for_positive_angle() {
        let t = Table::standard();
        let (x0, z0) = t.foot_xz(0, 0.0);
        assert!((x0 - t.rods[0].x_m).abs() < 1e-12);
        assert!(z0 > 0.0 && z0 < t.ball.diameter_m);
        let (x1, _) = t.foot_xz(0, 0.3);
        assert!(x1 < x0);
    }
}

//! Driving a rod: from the wanted pose to the pose and velocity of one physics step.
//!
//! A rod is a cylindrical joint (slide along `+y`, turn about `+y`) driven as a
//! kinematic body: each step it gets the velocity that takes it from where it is to
//! where the input wants it, so a spun rod hits the ball with the speed of its men's
//! feet (`v = reach · ω`). Two limits shape the motion:
//!
//! * **Rubber bumpers** at the travel ends: inside `±(travel/2 − bumper)` the slide
//!   follows the input exactly; in the last `bumper` metres the wanted slide saturates
//!   smoothly (`tanh`) onto the stop, and the rod covers at most half its remaining
//!   distance to the stop per step, like a rubber ring compressing: it decelerates into
//!   the stop instead of stopping dead, and never passes it.
//! * **Speed limits** (about twice a strong human's): an input jump (a board reconnecting,
//!   a glitch) becomes a fast but finite move over a few steps instead of a teleport.

use crate::ai::RodTarget;

/// Travel limits of one rod and the speeds it may move at.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RodDrive {
    /// Half the axial travel, m.
    pub half_travel_m: f64,
    /// Length of the rubber bumper at each end, m (0 = a hard stop).
    pub bumper_m: f64,
    /// Fastest slide, m/s.
    pub max_slide_speed_m_per_s: f64,
    /// Fastest spin, rad/s.
    pub max_spin_rad_per_s: f64,
}

impl RodDrive {
    /// The slide (m) the rod takes for a wanted slide `wanted_m`: identity in the middle
    /// of the travel, a smooth saturation onto `±half_travel_m` over the bumper.
    pub fn bumper_slide(&self, wanted_m: f64) -> f64 {
        let half = self.half_travel_m;
        let c = self.bumper_m.min(half);
        if !wanted_m.is_finite() {
            return 0.0;
        }
        if c <= 0.0 {
            return wanted_m.clamp(-half, half);
        }
        let knee = half - c;
        if wanted_m.abs() <= knee {
            wanted_m
        } else {
            wanted_m.signum() * (knee + c * ((wanted_m.abs() - knee) / c).tanh())
        }
    }

    /// The next pose after one step of `dt_s` seconds from `current` towards `wanted`,
    /// and the velocity `(slide m/s, spin rad/s)` that gets there.
    pub fn next(&self, current: RodTarget, wanted: RodTarget, dt_s: f64) -> (RodTarget, [f64; 2]) {
        let slide_goal = self.bumper_slide(wanted.slide_m);
        let angle_goal = if wanted.angle_rad.is_finite() {
            wanted.angle_rad
        } else {
            current.angle_rad
        };
        let ds_max = self.max_slide_speed_m_per_s * dt_s;
        let da_max = self.max_spin_rad_per_s * dt_s;
        let mut ds = (slide_goal - current.slide_m).clamp(-ds_max, ds_max);
        // The rubber: within `bumper_m` of the stop the rod covers at most half the
        // remaining distance per step, so it decelerates into the stop over a few
        // steps instead of hitting it at full speed.
        let to_stop = self.half_travel_m - ds.signum() * current.slide_m;
        let c = self.bumper_m.min(self.half_travel_m);
        if c > 0.0 && ds != 0.0 {
            let allowed = if to_stop <= 1e-6 {
                to_stop.max(0.0)
            } else {
                (to_stop - c).max(0.0) + 0.5 * to_stop.min(c)
            };
            ds = ds.signum() * ds.abs().min(allowed);
        }
        let da = (angle_goal - current.angle_rad).clamp(-da_max, da_max);
        let next = RodTarget {
            slide_m: current.slide_m + ds,
            angle_rad: current.angle_rad + da,
        };
        (next, [ds / dt_s, da / dt_s])
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn drive() -> RodDrive {
        RodDrive {
            half_travel_m: 0.09,
            bumper_m: 0.005,
            max_slide_speed_m_per_s: 4.0,
            max_spin_rad_per_s: 150.0,
        }
    }

    #[test]
    fn bumper_is_identity_inside_and_saturates_at_the_stop() {
        let d = drive();
        assert_eq!(d.bumper_slide(0.05), 0.05);
        assert_eq!(d.bumper_slide(-0.085), -0.085);
        let near = d.bumper_slide(0.088);
        assert!(near < 0.088 && near > 0.085, "{near}");
        assert!(d.bumper_slide(0.5) <= 0.09 && d.bumper_slide(0.5) > 0.0899);
        assert!(d.bumper_slide(-10.0) >= -0.09);
        assert_eq!(d.bumper_slide(f64::NAN), 0.0);
        // Monotonic through the knee.
        let mut last = -1.0;
        for i in 0..2000 {
            let s = d.bumper_slide(0.08 + i as f64 * 1e-5);
            assert!(s >= last);
            last = s;
        }
    }

    #[test]
    fn speeds_are_limited_and_reach_the_target() {
        let d = drive();
        let (next, v) = d.next(
            RodTarget::default(),
            RodTarget {
                slide_m: 0.05,
                angle_rad: 10.0,
            },
            1e-3,
        );
        assert!((next.slide_m - 0.004).abs() < 1e-15);
        assert!((next.angle_rad - 0.15).abs() < 1e-12);
        assert!((v[0] - 4.0).abs() < 1e-9 && (v[1] - 150.0).abs() < 1e-9);
        let (next, v) = d.next(
            RodTarget::default(),
            RodTarget {
                slide_m: 0.001,
                angle_rad: -0.02,
            },
            1e-3,
        );
        assert_eq!(next.slide_m, 0.001);
        assert_eq!(next.angle_rad, -0.02);
        assert!((v[0] - 1.0).abs() < 1e-9 && (v[1] + 20.0).abs() < 1e-9);
    }
}

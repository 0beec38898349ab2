//! The player's hand on a rod: from the calibrated input pose to the targets of the rod's
//! two servos.
//!
//! The arena does no physics here: the motors ([`super::rods`]) move the rod, the drive's
//! limits stop it at the travel ends, and contacts stop it on the ball. What this maps is
//! the input: the wanted slide passes through a **rubber bumper** (inside
//! `±(travel/2 − bumper)` it is the input; in the last `bumper` metres it saturates smoothly,
//! `tanh`, onto the stop), so the servo brakes the rod into its stop as a rubber ring would
//! instead of driving it onto the limit at full force; a non-finite input keeps the last
//! target. The target velocity is the target's change over the step (the hand's velocity,
//! the servo's feed-forward).

use crate::ai::RodTarget;

/// The travel of one rod and its rubber bumpers.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RodDrive {
    /// Half the axial travel, m.
    pub half_travel_m: f64,
    /// Length of the rubber bumper at each end, m (0 = a hard stop).
    pub bumper_m: f64,
}

impl RodDrive {
    /// The slide (m) the rod is driven to for a wanted slide `wanted_m`: identity in the
    /// middle of the travel, a smooth saturation onto `±half_travel_m` over the bumper;
    /// 0 for a non-finite input.
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
            wanted_m.signum()
                * (knee + c * virtual_physics::transcendental::tanh((wanted_m.abs() - knee) / c))
        }
    }

    /// The servo targets (slide m, angle rad) for the wanted pose, given the last targets:
    /// the slide through the bumper; a non-finite coordinate keeps its last target.
    pub fn motor_target(&self, wanted: RodTarget, last: RodTarget) -> RodTarget {
        RodTarget {
            slide_m: if wanted.slide_m.is_finite() {
                self.bumper_slide(wanted.slide_m)
            } else {
                last.slide_m
            },
            angle_rad: if wanted.angle_rad.is_finite() {
                wanted.angle_rad
            } else {
                last.angle_rad
            },
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn drive() -> RodDrive {
        RodDrive {
            half_travel_m: 0.09,
            bumper_m: 0.005,
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
    fn non_finite_input_keeps_the_last_target() {
        let d = drive();
        let last = RodTarget {
            slide_m: 0.01,
            angle_rad: 0.2,
        };
        let t = d.motor_target(
            RodTarget {
                slide_m: f64::NAN,
                angle_rad: f64::INFINITY,
            },
            last,
        );
        assert_eq!(t, last);
        let t = d.motor_target(
            RodTarget {
                slide_m: 0.3,
                angle_rad: -1.0,
            },
            last,
        );
        assert!(t.slide_m <= 0.09 && t.angle_rad == -1.0);
    }
}

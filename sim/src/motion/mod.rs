//! Where the rods are: the motion that the emulated sensors observe.
//!
//! Three sources implement [`MotionSource`]:
//! * [`script::MotionScript`]: piecewise motion over time, loaded from a JSON file.
//! * [`live::LiveMotion`]: a target pose per rod set at run time (keyboard/mouse of the
//!   game), followed at a bounded speed.
//! * [`recording::Playback`]: poses recorded over time (by [`recording::Recorder`]) and
//!   played back with linear interpolation.

pub mod live;
pub mod recording;
pub mod script;

use foosball_protocol::PADDLES;
use serde::{Deserialize, Serialize};

/// Pose of one rod.
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RodPose {
    /// Position along the rod's axis, metres (positive away from the player as mounted).
    pub axial_m: f64,
    /// Rotation about the rod's axis, radians (unbounded: turns accumulate).
    pub angle_rad: f64,
}

impl RodPose {
    /// A pose from its axial position (m) and angle (rad).
    pub const fn new(axial_m: f64, angle_rad: f64) -> Self {
        Self { axial_m, angle_rad }
    }

    /// Linear interpolation: `self` at `f = 0`, `other` at `f = 1`.
    pub fn lerp(self, other: Self, f: f64) -> Self {
        Self {
            axial_m: self.axial_m + (other.axial_m - self.axial_m) * f,
            angle_rad: self.angle_rad + (other.angle_rad - self.angle_rad) * f,
        }
    }

    /// Whether both coordinates are finite numbers.
    pub fn is_finite(self) -> bool {
        self.axial_m.is_finite() && self.angle_rad.is_finite()
    }
}

/// Poses of all eight rods, indexed by port.
pub type RodPoses = [RodPose; PADDLES];

/// A source of rod motion in emulated time.
pub trait MotionSource: Send {
    /// Poses of all rods at emulated time `t_us` (µs since the board powered up).
    /// Callers pass non-decreasing times.
    fn poses_at(&mut self, t_us: u64) -> RodPoses;
}

/// Rods that never move (all at pose zero).
#[derive(Debug, Clone, Copy, Default)]
pub struct Stationary;

impl MotionSource for Stationary {
    fn poses_at(&mut self, _t_us: u64) -> RodPoses {
        [RodPose::default(); PADDLES]
    }
}

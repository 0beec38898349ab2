//! Live motion: the game (keyboard, mouse) sets a target pose per rod at run time, and
//! each rod moves towards its target at a bounded speed, as a hand on a real rod would.
//! The bound keeps the emulated sensors seeing continuous motion instead of jumps.

use super::{MotionSource, RodPose, RodPoses};
use foosball_protocol::PADDLES;
use std::sync::{Arc, Mutex, PoisonError};

/// Speed limits of live rods.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LiveLimits {
    /// Fastest axial motion, m/s.
    pub max_axial_m_per_s: f64,
    /// Fastest turning, rad/s.
    pub max_angle_rad_per_s: f64,
}

impl Default for LiveLimits {
    /// 1 m/s axial, 60 rad/s (≈ 10 turns per second): a brisk human hand.
    fn default() -> Self {
        Self {
            max_axial_m_per_s: 1.0,
            max_angle_rad_per_s: 60.0,
        }
    }
}

/// The setter side: cheap to clone and share with the game's input handling.
#[derive(Debug, Clone, Default)]
pub struct LiveHandle {
    targets: Arc<Mutex<RodPoses>>,
}

impl LiveHandle {
    /// Sets the pose `rod` (0–7) should move to. Out-of-range rods and non-finite
    /// poses are ignored (returns `false`).
    pub fn set_target(&self, rod: usize, pose: RodPose) -> bool {
        if rod >= PADDLES || !pose.is_finite() {
            return false;
        }
        self.lock()[rod] = pose;
        true
    }

    /// The current targets.
    pub fn targets(&self) -> RodPoses {
        *self.lock()
    }

    fn lock(&self) -> std::sync::MutexGuard<'_, RodPoses> {
        // The data is plain poses: a panic elsewhere cannot leave it inconsistent.
        self.targets.lock().unwrap_or_else(PoisonError::into_inner)
    }
}

/// Rods following the targets of a [`LiveHandle`].
#[derive(Debug, Clone)]
pub struct LiveMotion {
    handle: LiveHandle,
    limits: LiveLimits,
    poses: RodPoses,
    last_t_us: u64,
}

impl LiveMotion {
    /// Rods at pose zero following `handle`'s targets within `limits`.
    pub fn new(handle: LiveHandle, limits: LiveLimits) -> Self {
        Self {
            handle,
            limits,
            poses: [RodPose::default(); PADDLES],
            last_t_us: 0,
        }
    }

    /// The setter for this source's targets.
    pub fn handle(&self) -> LiveHandle {
        self.handle.clone()
    }
}

fn approach(current: f64, target: f64, max_step: f64) -> f64 {
    let delta = target - current;
    if delta.abs() <= max_step {
        target
    } else {
        current + max_step.copysign(delta)
    }
}

impl MotionSource for LiveMotion {
    fn poses_at(&mut self, t_us: u64) -> RodPoses {
        let dt_s = t_us.saturating_sub(self.last_t_us) as f64 * 1e-6;
        self.last_t_us = self.last_t_us.max(t_us);
        let targets = self.handle.targets();
        for (pose, target) in self.poses.iter_mut().zip(targets) {
            pose.axial_m = approach(
                pose.axial_m,
                target.axial_m,
                self.limits.max_axial_m_per_s * dt_s,
            );
            pose.angle_rad = approach(
                pose.angle_rad,
                target.angle_rad,
                self.limits.max_angle_rad_per_s * dt_s,
            );
        }
        self.poses
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn follows_target_at_bounded_speed() {
        let handle = LiveHandle::default();
        let mut m = LiveMotion::new(handle.clone(), LiveLimits::default());
        assert!(handle.set_target(3, RodPose::new(0.1, -3.0)));
        assert!(!handle.set_target(8, RodPose::new(0.1, 0.0)));
        assert!(!handle.set_target(0, RodPose::new(f64::NAN, 0.0)));
        let p = m.poses_at(50_000); // 50 ms: 0.05 m and 3 rad at most
        assert!((p[3].axial_m - 0.05).abs() < 1e-12);
        assert!((p[3].angle_rad + 3.0).abs() < 1e-12);
        let p = m.poses_at(200_000);
        assert_eq!(p[3], RodPose::new(0.1, -3.0));
        assert_eq!(p[0], RodPose::default());
    }
}

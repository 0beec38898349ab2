//! The optical sensor looking at a rod's surface: rod motion in, mouse counts out.
//!
//! The sensor is mounted beside the rod, looking at its surface. Axial motion of the rod
//! moves the surface along one sensor axis; turning the rod moves the surface by
//! `radius × angle` along the other. The sensor takes a frame every
//! [`crate::board::BoardConfig::sensor_frame_interval_us`]; per frame it converts the
//! surface displacement into counts at the mouse's resolution (1, 2, 4 or 8 counts/mm),
//! applying the imperfections below. Counts accumulate as real numbers, and the mouse
//! takes whole counts out ([`SensorModel::take_counts`]), so the remainder below one
//! count is kept and quantisation error never accumulates (it stays within ±0.5 count
//! over any run, noise aside).
//!
//! Imperfections ([`SensorParams`]):
//! * gain error per axis (fraction: 0.02 reads 2 % too many counts),
//! * cross-talk (fraction of each axis's counts that also appears on the other),
//! * noise (Gaussian, counts rms per frame, seeded and reproducible; its sum grows as a
//!   random walk, σ·√frames),
//! * a maximum tracking speed (surface speed in m/s): a frame whose surface speed
//!   exceeds it loses tracking and reports no motion for that frame,
//! * the 9-bit per-packet limit is the mouse's ([`crate::ps2_device::mouse`]): it clamps
//!   to −256…255 and flags overflow.

use crate::motion::RodPose;
use crate::rng::SimRng;

/// Which mouse axis sees the rod's axial motion (the other sees its rotation).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum SensorAxis {
    /// Mouse X (first delta byte).
    #[default]
    X,
    /// Mouse Y (second delta byte).
    Y,
}

/// How a sensor is mounted on its rod. The emulated board configures the firmware's
/// axis map to match, so the host sees positive axial counts for positive axial motion.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct SensorMount {
    /// Mouse axis that sees axial motion.
    pub axial_axis: SensorAxis,
    /// Axial motion in +metres gives negative counts on that axis.
    pub invert_axial: bool,
    /// Turning in +radians gives negative counts on the other axis.
    pub invert_rotation: bool,
}

/// Parameters of one optical sensor.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SensorParams {
    /// Radius of the rod surface the sensor looks at, metres.
    pub rod_radius_m: f64,
    /// Gain error on the axial axis, fraction (0.0 = exact, 0.02 = 2 % too many counts).
    pub axial_gain_error: f64,
    /// Gain error on the rotation axis, fraction.
    pub rotation_gain_error: f64,
    /// Fraction of each axis's counts that leaks into the other axis.
    pub cross_talk: f64,
    /// Gaussian noise per sensor frame and axis, counts rms.
    pub noise_counts_rms: f64,
    /// Surface speed above which the sensor loses tracking, m/s.
    pub max_speed_m_per_s: f64,
    /// Mounting (axis assignment and signs).
    pub mount: SensorMount,
}

impl Default for SensorParams {
    /// A 16 mm rod (8 mm radius), an ideal sensor (no gain error, cross-talk or noise)
    /// that tracks up to 3 m/s.
    fn default() -> Self {
        Self {
            rod_radius_m: 0.008,
            axial_gain_error: 0.0,
            rotation_gain_error: 0.0,
            cross_talk: 0.0,
            noise_counts_rms: 0.0,
            max_speed_m_per_s: 3.0,
            mount: SensorMount::default(),
        }
    }
}

impl SensorParams {
    /// Checks every parameter is finite and in range; the message names the parameter.
    pub fn validate(&self) -> Result<(), String> {
        let checks: [(&str, f64, f64, f64); 6] = [
            ("rod_radius_m", self.rod_radius_m, 1e-4, 1.0),
            ("axial_gain_error", self.axial_gain_error, -0.9, 10.0),
            ("rotation_gain_error", self.rotation_gain_error, -0.9, 10.0),
            ("cross_talk", self.cross_talk, -1.0, 1.0),
            ("noise_counts_rms", self.noise_counts_rms, 0.0, 1000.0),
            ("max_speed_m_per_s", self.max_speed_m_per_s, 1e-3, 1000.0),
        ];
        for (name, value, lo, hi) in checks {
            if !(value.is_finite() && (lo..=hi).contains(&value)) {
                return Err(format!("{name} must be within {lo}…{hi}, got {value}"));
            }
        }
        Ok(())
    }
}

/// One sensor's state: last observed pose and the counts not yet taken by the mouse.
#[derive(Debug, Clone)]
pub struct SensorModel {
    params: SensorParams,
    last: Option<(u64, RodPose)>,
    /// Counts accumulated per mouse axis (x, y), fractional.
    pending: [f64; 2],
    rng: SimRng,
    frames: u64,
    frames_lost: u64,
}

impl SensorModel {
    /// A sensor with `params` drawing its noise from `rng`.
    pub fn new(params: SensorParams, rng: SimRng) -> Self {
        Self {
            params,
            last: None,
            pending: [0.0; 2],
            rng,
            frames: 0,
            frames_lost: 0,
        }
    }

    /// The parameters.
    pub fn params(&self) -> &SensorParams {
        &self.params
    }

    /// One sensor frame at `t_us` seeing the rod at `pose`, at `counts_per_mm`.
    /// Unpowered (mouse unplugged), the sensor only remembers where the rod is.
    pub fn observe(&mut self, t_us: u64, pose: RodPose, counts_per_mm: f64, powered: bool) {
        let previous = self.last.replace((t_us, pose));
        let Some((t0, p0)) = previous else {
            return;
        };
        if !powered {
            return;
        }
        let axial_mm = (pose.axial_m - p0.axial_m) * 1e3;
        let surface_mm = (pose.angle_rad - p0.angle_rad) * self.params.rod_radius_m * 1e3;
        if axial_mm == 0.0 && surface_mm == 0.0 && self.params.noise_counts_rms == 0.0 {
            return;
        }
        self.frames += 1;
        let dt_s = t_us.saturating_sub(t0) as f64 * 1e-6;
        let distance_m = axial_mm.hypot(surface_mm) * 1e-3;
        if distance_m > self.params.max_speed_m_per_s * dt_s {
            // Too fast (or a jump in no time): tracking lost for this frame.
            self.frames_lost += 1;
            return;
        }
        let axial = axial_mm * counts_per_mm * (1.0 + self.params.axial_gain_error);
        let rotation = surface_mm * counts_per_mm * (1.0 + self.params.rotation_gain_error);
        let mut axial_counts = axial + self.params.cross_talk * rotation;
        let mut rotation_counts = rotation + self.params.cross_talk * axial;
        if self.params.noise_counts_rms > 0.0 {
            axial_counts += self.params.noise_counts_rms * self.rng.normal();
            rotation_counts += self.params.noise_counts_rms * self.rng.normal();
        }
        let mount = self.params.mount;
        if mount.invert_axial {
            axial_counts = -axial_counts;
        }
        if mount.invert_rotation {
            rotation_counts = -rotation_counts;
        }
        let (x, y) = match mount.axial_axis {
            SensorAxis::X => (axial_counts, rotation_counts),
            SensorAxis::Y => (rotation_counts, axial_counts),
        };
        self.pending[0] += x;
        self.pending[1] += y;
    }

    /// Whole counts (x, y) accumulated since the last call, rounded to nearest; the
    /// remainder (within ±0.5) stays for the next call.
    pub fn take_counts(&mut self) -> (i32, i32) {
        let mut out = [0i32; 2];
        for (pending, out) in self.pending.iter_mut().zip(out.iter_mut()) {
            let whole = pending.round();
            // Accumulated counts are far below i32 range for any validated motion.
            *out = whole.clamp(i32::MIN as f64, i32::MAX as f64) as i32;
            *pending -= whole;
        }
        (out[0], out[1])
    }

    /// Whether any whole count is waiting (so a packet would carry motion).
    pub fn has_motion(&self) -> bool {
        self.pending.iter().any(|p| p.abs() >= 0.5)
    }

    /// Forgets accumulated counts (the mouse was reset or lost power).
    pub fn clear(&mut self) {
        self.pending = [0.0; 2];
    }

    /// Frames with motion observed while powered.
    pub fn frames(&self) -> u64 {
        self.frames
    }

    /// Frames whose motion was lost to the tracking-speed limit.
    pub fn frames_lost(&self) -> u64 {
        self.frames_lost
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::TAU;

    fn run(params: SensorParams, cpm: f64, to: RodPose, steps: u64) -> (i64, i64) {
        let mut s = SensorModel::new(params, SimRng::new(1));
        let mut sum = (0i64, 0i64);
        s.observe(0, RodPose::default(), cpm, true);
        for i in 1..=steps {
            let pose = RodPose::default().lerp(to, i as f64 / steps as f64);
            s.observe(i * 500, pose, cpm, true);
            if i % 7 == 0 {
                let (x, y) = s.take_counts();
                sum.0 += x as i64;
                sum.1 += y as i64;
            }
        }
        let (x, y) = s.take_counts();
        (sum.0 + x as i64, sum.1 + y as i64)
    }

    #[test]
    fn counts_match_motion_without_accumulating_quantisation() {
        // 0.1234 m axial and one full turn of an 8 mm radius rod (50.27 mm surface).
        let to = RodPose::new(0.1234, TAU);
        for cpm in [1.0, 2.0, 4.0, 8.0] {
            let (x, y) = run(SensorParams::default(), cpm, to, 2000);
            let want_x = 123.4 * cpm;
            let want_y = 8.0 * TAU * cpm;
            assert!(
                (x as f64 - want_x).abs() <= 0.5 + 1e-9,
                "{cpm}: {x} vs {want_x}"
            );
            assert!(
                (y as f64 - want_y).abs() <= 0.5 + 1e-9,
                "{cpm}: {y} vs {want_y}"
            );
        }
    }

    #[test]
    fn mount_gain_and_cross_talk() {
        let params = SensorParams {
            axial_gain_error: 0.1,
            cross_talk: 0.05,
            mount: SensorMount {
                axial_axis: SensorAxis::Y,
                invert_axial: true,
                invert_rotation: false,
            },
            ..SensorParams::default()
        };
        let (x, y) = run(params, 4.0, RodPose::new(0.1, 0.0), 1000);
        // Axial 400 counts × 1.1 = 440 on −Y; 5 % of it (22) leaks to X.
        assert_eq!(y, -440);
        assert_eq!(x, 22);
    }

    #[test]
    fn too_fast_loses_counts_and_unpowered_counts_nothing() {
        let params = SensorParams {
            max_speed_m_per_s: 0.5,
            ..SensorParams::default()
        };
        // 0.1 m in 100 ms = 1 m/s: every frame too fast.
        let mut s = SensorModel::new(params, SimRng::new(1));
        for i in 0..=200u64 {
            s.observe(i * 500, RodPose::new(i as f64 * 0.0005, 0.0), 8.0, true);
        }
        assert_eq!(s.take_counts(), (0, 0));
        assert_eq!(s.frames_lost(), 200);
        let mut s = SensorModel::new(SensorParams::default(), SimRng::new(1));
        s.observe(0, RodPose::default(), 8.0, false);
        s.observe(500, RodPose::new(0.0001, 0.0), 8.0, false);
        assert_eq!(s.take_counts(), (0, 0));
        // Powered again: motion counts from the pose seen while unpowered.
        s.observe(1000, RodPose::new(0.0002, 0.0), 8.0, true);
        assert_eq!(s.take_counts(), (1, 0));
    }

    #[test]
    fn noise_is_seeded_and_zero_mean() {
        let params = SensorParams {
            noise_counts_rms: 1.0,
            ..SensorParams::default()
        };
        let mut a = SensorModel::new(params, SimRng::new(9));
        let mut b = SensorModel::new(params, SimRng::new(9));
        let mut total = 0i64;
        for i in 0..10_000u64 {
            a.observe(i * 500, RodPose::default(), 4.0, true);
            b.observe(i * 500, RodPose::default(), 4.0, true);
            let (ax, _) = a.take_counts();
            assert_eq!(b.take_counts().0, ax);
            total += ax as i64;
        }
        // Random walk over 10 000 frames: σ ≈ 100 counts.
        assert!(total.abs() < 500, "{total}");
    }

    #[test]
    fn validate_names_the_parameter() {
        let p = SensorParams {
            max_speed_m_per_s: f64::NAN,
            ..SensorParams::default()
        };
        assert!(p.validate().unwrap_err().contains("max_speed_m_per_s"));
        assert!(SensorParams::default().validate().is_ok());
    }
}

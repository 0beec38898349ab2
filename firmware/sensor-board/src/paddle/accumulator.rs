//! Saturating per-paddle sums over one report period.

use foosball_protocol::{PaddleMotion, PaddleStatus};

use super::axis_map::AxisMap;
use crate::mouse::MousePacket;

/// Motion of one paddle since the last report: `i16` sums that saturate instead of
/// wrapping (setting [`PaddleStatus::SATURATED`]), plus sticky status flags.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct PaddleAccumulator {
    axial: i16,
    rotation: i16,
    status: PaddleStatus,
}

/// Adds `delta` to `sum`, clamping to the `i16` range; `true` when clamped.
fn saturating_add(sum: &mut i16, delta: i32) -> bool {
    let total = i32::from(*sum).saturating_add(delta);
    let clamped = total.clamp(i32::from(i16::MIN), i32::from(i16::MAX));
    *sum = clamped as i16;
    clamped != total
}

impl PaddleAccumulator {
    /// Empty: no motion, no flags.
    pub const fn new() -> Self {
        Self {
            axial: 0,
            rotation: 0,
            status: PaddleStatus::empty(),
        }
    }

    /// Adds one mouse packet, mapped by the port's `map`; the mouse's overflow bits
    /// become [`PaddleStatus::AXIAL_OVERFLOW`] / [`PaddleStatus::ROTATION_OVERFLOW`].
    pub fn add_packet(&mut self, packet: &MousePacket, map: &AxisMap) {
        let motion = map.map(packet);
        if motion.axial_overflow {
            self.status |= PaddleStatus::AXIAL_OVERFLOW;
        }
        if motion.rotation_overflow {
            self.status |= PaddleStatus::ROTATION_OVERFLOW;
        }
        self.add(motion.axial, motion.rotation);
    }

    /// Adds motion in counts; a sum that would leave the `i16` range stops at its
    /// limit and sets [`PaddleStatus::SATURATED`].
    pub fn add(&mut self, axial: i32, rotation: i32) {
        let axial_clamped = saturating_add(&mut self.axial, axial);
        let rotation_clamped = saturating_add(&mut self.rotation, rotation);
        if axial_clamped || rotation_clamped {
            self.status |= PaddleStatus::SATURATED;
        }
    }

    /// Sets sticky status flags until the next [`take`](Self::take).
    pub fn flag(&mut self, status: PaddleStatus) {
        self.status |= status;
    }

    /// Axial counts so far.
    pub const fn axial(&self) -> i16 {
        self.axial
    }

    /// Rotation counts so far.
    pub const fn rotation(&self) -> i16 {
        self.rotation
    }

    /// Flags so far.
    pub const fn status(&self) -> PaddleStatus {
        self.status
    }

    /// The motion and flags so far, leaving the accumulator as it is.
    pub const fn peek(&self) -> PaddleMotion {
        PaddleMotion {
            axial: self.axial,
            rotation: self.rotation,
            status: self.status,
        }
    }

    /// Removes motion that was sent (an earlier [`peek`](Self::peek)): its counts are
    /// subtracted (clamped to the `i16` range) and its flags cleared; what arrived
    /// since stays. `PRESENT` is not a sticky flag and is ignored.
    pub fn remove(&mut self, sent: &PaddleMotion) {
        let clamp = |v: i32| v.clamp(i32::from(i16::MIN), i32::from(i16::MAX)) as i16;
        self.axial = clamp(i32::from(self.axial) - i32::from(sent.axial));
        self.rotation = clamp(i32::from(self.rotation) - i32::from(sent.rotation));
        self.status.remove(sent.status);
    }

    /// The period's motion and flags, emptying the accumulator for the next period.
    pub fn take(&mut self) -> PaddleMotion {
        let motion = PaddleMotion {
            axial: self.axial,
            rotation: self.rotation,
            status: self.status,
        };
        *self = Self::new();
        motion
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::paddle::MouseAxis;

    #[test]
    fn removing_a_peek_keeps_what_came_after() {
        let mut acc = PaddleAccumulator::new();
        acc.add(10, -3);
        acc.flag(PaddleStatus::PARITY_ERROR);
        let sent = acc.peek();
        acc.add(5, 7);
        acc.flag(PaddleStatus::FRAMING_ERROR);
        acc.remove(&sent);
        assert_eq!((acc.axial(), acc.rotation()), (5, 7));
        assert_eq!(acc.status(), PaddleStatus::FRAMING_ERROR);
        acc.remove(&acc.peek());
        assert_eq!(acc, PaddleAccumulator::new());
    }

    #[test]
    fn removing_after_saturation_stays_in_range() {
        let mut acc = PaddleAccumulator::new();
        acc.add(i32::from(i16::MAX), 0);
        let sent = acc.peek();
        acc.add(-30_000, 0);
        acc.add(-30_000, 0);
        acc.remove(&sent);
        assert_eq!(acc.axial(), i16::MIN);
    }

    #[test]
    fn sums_and_drains() {
        let mut acc = PaddleAccumulator::new();
        acc.add(10, -3);
        acc.add(-4, -3);
        assert_eq!((acc.axial(), acc.rotation()), (6, -6));
        let motion = acc.take();
        assert_eq!((motion.axial, motion.rotation), (6, -6));
        assert_eq!(motion.status, PaddleStatus::empty());
        assert_eq!(acc, PaddleAccumulator::new());
    }

    #[test]
    fn saturates_positive_without_wrapping() {
        let mut acc = PaddleAccumulator::new();
        for _ in 0..200 {
            acc.add(255, 0);
        }
        assert_eq!(acc.axial(), i16::MAX);
        assert!(acc.status().contains(PaddleStatus::SATURATED));
        let motion = acc.take();
        assert_eq!(motion.axial, i16::MAX);
        assert!(motion.status.contains(PaddleStatus::SATURATED));
        // The flag is per period.
        acc.add(1, 0);
        assert!(!acc.take().status.contains(PaddleStatus::SATURATED));
    }

    #[test]
    fn saturates_negative_without_wrapping() {
        let mut acc = PaddleAccumulator::new();
        for _ in 0..200 {
            acc.add(0, -256);
        }
        assert_eq!(acc.rotation(), i16::MIN);
        assert_eq!(acc.axial(), 0);
        assert!(acc.status().contains(PaddleStatus::SATURATED));
    }

    #[test]
    fn exactly_reaching_the_limit_is_not_saturation() {
        let mut acc = PaddleAccumulator::new();
        acc.add(i32::from(i16::MAX), i32::from(i16::MIN));
        assert_eq!((acc.axial(), acc.rotation()), (i16::MAX, i16::MIN));
        assert!(!acc.status().contains(PaddleStatus::SATURATED));
        acc.add(1, 0);
        assert!(acc.status().contains(PaddleStatus::SATURATED));
    }

    #[test]
    fn extreme_inputs_clamp() {
        let mut acc = PaddleAccumulator::new();
        acc.add(i32::MAX, i32::MIN);
        acc.add(i32::MAX, i32::MIN);
        assert_eq!((acc.axial(), acc.rotation()), (i16::MAX, i16::MIN));
    }

    #[test]
    fn packets_map_axes_and_overflow_flags() {
        let map = AxisMap {
            axial: MouseAxis::Y,
            invert_axial: true,
            invert_rotation: false,
        };
        let mut acc = PaddleAccumulator::new();
        let packet = MousePacket {
            dx: 3,
            dy: 7,
            x_overflow: true,
            y_overflow: false,
            buttons: 0,
        };
        acc.add_packet(&packet, &map);
        let motion = acc.take();
        assert_eq!((motion.axial, motion.rotation), (-7, 3));
        assert!(motion.status.contains(PaddleStatus::ROTATION_OVERFLOW));
        assert!(!motion.status.contains(PaddleStatus::AXIAL_OVERFLOW));
    }
}

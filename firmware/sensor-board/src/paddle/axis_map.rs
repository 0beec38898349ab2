//! Which mouse axis measures a paddle's axial motion and which its rotation.
//!
//! The sensors are mounted in different orientations, so this is configured per port.

use crate::mouse::MousePacket;

/// A mouse sensor axis.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum MouseAxis {
    /// The mouse's X axis (`dx`).
    #[default]
    X,
    /// The mouse's Y axis (`dy`).
    Y,
}

impl MouseAxis {
    /// The other axis.
    pub const fn other(self) -> Self {
        match self {
            Self::X => Self::Y,
            Self::Y => Self::X,
        }
    }
}

/// How one port's sensor is mounted: the `axial` mouse axis measures motion along the
/// rod, the other axis the rod surface's motion from turning; either can be inverted.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct AxisMap {
    /// The mouse axis along the rod. Rotation is the other axis.
    pub axial: MouseAxis,
    /// Negate the axial counts.
    pub invert_axial: bool,
    /// Negate the rotation counts.
    pub invert_rotation: bool,
}

/// One packet's motion in paddle terms, counts at the sensor's resolution.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct MappedMotion {
    /// Counts along the rod.
    pub axial: i32,
    /// Counts of rotation (rod surface motion).
    pub rotation: i32,
    /// The axial axis's counter overflowed in the mouse.
    pub axial_overflow: bool,
    /// The rotation axis's counter overflowed in the mouse.
    pub rotation_overflow: bool,
}

impl AxisMap {
    /// Axial = mouse X, rotation = mouse Y, nothing inverted.
    pub const IDENTITY: Self = Self {
        axial: MouseAxis::X,
        invert_axial: false,
        invert_rotation: false,
    };

    /// The mouse axis measuring rotation (the one that is not axial).
    pub const fn rotation_axis(&self) -> MouseAxis {
        self.axial.other()
    }

    /// Maps a packet to paddle motion. Overflowed deltas are passed on as they are
    /// (the mouse's best value) with the overflow flag.
    pub const fn map(&self, packet: &MousePacket) -> MappedMotion {
        let x = (packet.dx as i32, packet.x_overflow);
        let y = (packet.dy as i32, packet.y_overflow);
        let (axial, rotation) = match self.axial {
            MouseAxis::X => (x, y),
            MouseAxis::Y => (y, x),
        };
        MappedMotion {
            axial: if self.invert_axial { -axial.0 } else { axial.0 },
            rotation: if self.invert_rotation {
                -rotation.0
            } else {
                rotation.0
            },
            axial_overflow: axial.1,
            rotation_overflow: rotation.1,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn packet(dx: i16, dy: i16, x_overflow: bool, y_overflow: bool) -> MousePacket {
        MousePacket {
            dx,
            dy,
            x_overflow,
            y_overflow,
            buttons: 0,
        }
    }

    #[test]
    fn identity() {
        let motion = AxisMap::IDENTITY.map(&packet(5, -7, true, false));
        assert_eq!(
            motion,
            MappedMotion {
                axial: 5,
                rotation: -7,
                axial_overflow: true,
                rotation_overflow: false
            }
        );
        assert_eq!(AxisMap::default(), AxisMap::IDENTITY);
        assert_eq!(AxisMap::IDENTITY.rotation_axis(), MouseAxis::Y);
    }

    #[test]
    fn swapped_axes_swap_overflow_too() {
        let map = AxisMap {
            axial: MouseAxis::Y,
            ..AxisMap::IDENTITY
        };
        assert_eq!(map.rotation_axis(), MouseAxis::X);
        let motion = map.map(&packet(5, -7, true, false));
        assert_eq!(
            motion,
            MappedMotion {
                axial: -7,
                rotation: 5,
                axial_overflow: false,
                rotation_overflow: true
            }
        );
    }

    #[test]
    fn inversions() {
        let map = AxisMap {
            axial: MouseAxis::X,
            invert_axial: true,
            invert_rotation: false,
        };
        let motion = map.map(&packet(-256, 255, false, false));
        assert_eq!((motion.axial, motion.rotation), (256, 255));
        let map = AxisMap {
            axial: MouseAxis::Y,
            invert_axial: false,
            invert_rotation: true,
        };
        let motion = map.map(&packet(-256, 255, false, false));
        assert_eq!((motion.axial, motion.rotation), (255, 256));
    }

    #[test]
    fn extreme_fields_do_not_overflow() {
        let map = AxisMap {
            axial: MouseAxis::X,
            invert_axial: true,
            invert_rotation: true,
        };
        let motion = map.map(&packet(i16::MIN, i16::MIN, false, false));
        assert_eq!(motion.axial, 32_768);
        assert_eq!(motion.rotation, 32_768);
    }
}

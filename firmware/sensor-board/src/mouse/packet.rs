//! The 3-byte PS/2 mouse stream packet.
//!
//! | byte | bits |
//! |---|---|
//! | 0 | 7: Y overflow, 6: X overflow, 5: Y sign, 4: X sign, 3: always 1, 2: middle, 1: right, 0: left |
//! | 1 | X movement, low 8 bits |
//! | 2 | Y movement, low 8 bits |
//!
//! Each delta is 9-bit two's complement (−256..=255 counts, at the configured
//! resolution): the sign bit in byte 0 is bit 8.

/// Byte 0: Y overflow.
const Y_OVERFLOW: u8 = 1 << 7;
/// Byte 0: X overflow.
const X_OVERFLOW: u8 = 1 << 6;
/// Byte 0: Y sign (bit 8 of the Y delta).
const Y_SIGN: u8 = 1 << 5;
/// Byte 0: X sign (bit 8 of the X delta).
const X_SIGN: u8 = 1 << 4;
/// Byte 0: always set; a byte without it cannot start a packet.
const ALWAYS_ONE: u8 = 1 << 3;
/// Byte 0: the three button bits.
const BUTTONS: u8 = 0x07;

/// Bytes in a stream packet.
pub const PACKET_LEN: usize = 3;

/// Smallest delta a packet can carry, counts.
pub const DELTA_MIN: i16 = -256;
/// Largest delta a packet can carry, counts.
pub const DELTA_MAX: i16 = 255;

/// One decoded stream packet: motion since the previous packet.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct MousePacket {
    /// X motion, counts (−256..=255), sign-extended from 9 bits; positive right.
    pub dx: i16,
    /// Y motion, counts (−256..=255), sign-extended from 9 bits; positive up.
    pub dy: i16,
    /// The mouse's X counter overflowed: `dx` is not the whole motion.
    pub x_overflow: bool,
    /// The mouse's Y counter overflowed: `dy` is not the whole motion.
    pub y_overflow: bool,
    /// Buttons: bit 0 left, bit 1 right, bit 2 middle.
    pub buttons: u8,
}

/// Sign-extends a 9-bit two's complement value: `low` is bits 0..8, `negative` bit 8.
pub const fn sign_extend_9(low: u8, negative: bool) -> i16 {
    if negative {
        low as i16 - 256
    } else {
        low as i16
    }
}

impl MousePacket {
    /// Whether `byte` can be byte 0 of a packet (bit 3 set). The driver drops bytes
    /// that cannot, to resynchronise after a lost byte.
    pub const fn is_first_byte(byte: u8) -> bool {
        byte & ALWAYS_ONE != 0
    }

    /// Decodes three packet bytes. Bit 3 of byte 0 is not checked (see
    /// [`Self::is_first_byte`]).
    pub const fn from_bytes(bytes: [u8; PACKET_LEN]) -> Self {
        let status = bytes[0];
        Self {
            dx: sign_extend_9(bytes[1], status & X_SIGN != 0),
            dy: sign_extend_9(bytes[2], status & Y_SIGN != 0),
            x_overflow: status & X_OVERFLOW != 0,
            y_overflow: status & Y_OVERFLOW != 0,
            buttons: status & BUTTONS,
        }
    }

    /// Encodes the packet as a mouse sends it. Deltas outside −256..=255 are clamped
    /// and set the axis's overflow bit; button bits above bit 2 are ignored.
    pub const fn to_bytes(&self) -> [u8; PACKET_LEN] {
        let (dx, x_clamped) = clamp_delta(self.dx);
        let (dy, y_clamped) = clamp_delta(self.dy);
        let mut status = ALWAYS_ONE | (self.buttons & BUTTONS);
        if self.x_overflow || x_clamped {
            status |= X_OVERFLOW;
        }
        if self.y_overflow || y_clamped {
            status |= Y_OVERFLOW;
        }
        if dx < 0 {
            status |= X_SIGN;
        }
        if dy < 0 {
            status |= Y_SIGN;
        }
        [status, dx as u8, dy as u8]
    }
}

/// Clamps to the 9-bit range; `true` when clamped.
const fn clamp_delta(delta: i16) -> (i16, bool) {
    if delta < DELTA_MIN {
        (DELTA_MIN, true)
    } else if delta > DELTA_MAX {
        (DELTA_MAX, true)
    } else {
        (delta, false)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sign_extension_extremes() {
        // +255: sign clear, 0xFF.
        assert_eq!(MousePacket::from_bytes([0x08, 0xFF, 0x00]).dx, 255);
        // −256: sign set, 0x00.
        assert_eq!(
            MousePacket::from_bytes([0x08 | X_SIGN, 0x00, 0x00]).dx,
            -256
        );
        // −1: sign set, 0xFF.
        assert_eq!(MousePacket::from_bytes([0x08 | X_SIGN, 0xFF, 0x00]).dx, -1);
        // 0.
        assert_eq!(MousePacket::from_bytes([0x08, 0x00, 0x00]).dx, 0);
        // Same on Y.
        assert_eq!(MousePacket::from_bytes([0x08, 0x00, 0xFF]).dy, 255);
        assert_eq!(
            MousePacket::from_bytes([0x08 | Y_SIGN, 0x00, 0x00]).dy,
            -256
        );
        assert_eq!(MousePacket::from_bytes([0x08 | Y_SIGN, 0x00, 0xFF]).dy, -1);
        assert_eq!(MousePacket::from_bytes([0x08, 0x00, 0x00]).dy, 0);
    }

    #[test]
    fn sign_bits_are_per_axis() {
        let packet = MousePacket::from_bytes([0x08 | X_SIGN, 0x80, 0x80]);
        assert_eq!((packet.dx, packet.dy), (-128, 128));
        let packet = MousePacket::from_bytes([0x08 | Y_SIGN, 0x80, 0x80]);
        assert_eq!((packet.dx, packet.dy), (128, -128));
    }

    #[test]
    fn overflow_and_button_bits() {
        let packet = MousePacket::from_bytes([0x08 | X_OVERFLOW | 0x01, 0, 0]);
        assert!(packet.x_overflow && !packet.y_overflow);
        assert_eq!(packet.buttons, 0x01);
        let packet = MousePacket::from_bytes([0x08 | Y_OVERFLOW | 0x06, 0, 0]);
        assert!(!packet.x_overflow && packet.y_overflow);
        assert_eq!(packet.buttons, 0x06);
    }

    #[test]
    fn first_byte_check() {
        assert!(MousePacket::is_first_byte(0x08));
        assert!(MousePacket::is_first_byte(0xFF));
        assert!(!MousePacket::is_first_byte(0xF7));
        assert!(!MousePacket::is_first_byte(0x00));
    }

    #[test]
    fn every_delta_round_trips() {
        for delta in DELTA_MIN..=DELTA_MAX {
            let packet = MousePacket {
                dx: delta,
                dy: -1 - delta,
                ..MousePacket::default()
            };
            let bytes = packet.to_bytes();
            assert!(MousePacket::is_first_byte(bytes[0]));
            assert_eq!(MousePacket::from_bytes(bytes), packet);
        }
    }

    #[test]
    fn encoding_clamps_and_flags_overflow() {
        let packet = MousePacket {
            dx: 300,
            dy: -1000,
            ..MousePacket::default()
        };
        let decoded = MousePacket::from_bytes(packet.to_bytes());
        assert_eq!((decoded.dx, decoded.dy), (255, -256));
        assert!(decoded.x_overflow && decoded.y_overflow);
    }
}

//! This firmware's version: `bcdDevice` in the USB device descriptor and the three
//! numbers of the diagnostics Feature report, both from `Cargo.toml`.

/// `bcdDevice`: this crate's version as binary-coded decimal `0xJJMN` (major `JJ`,
/// minor `M`, patch `N`), so a host can tell which firmware it talks to.
pub const DEVICE_RELEASE: u16 = bcd_release(
    env!("CARGO_PKG_VERSION_MAJOR"),
    env!("CARGO_PKG_VERSION_MINOR"),
    env!("CARGO_PKG_VERSION_PATCH"),
);

/// This crate's version: major, minor, patch (the diagnostics Feature report).
pub const FIRMWARE_VERSION: [u8; 3] = [
    decimal(env!("CARGO_PKG_VERSION_MAJOR"), 255) as u8,
    decimal(env!("CARGO_PKG_VERSION_MINOR"), 255) as u8,
    decimal(env!("CARGO_PKG_VERSION_PATCH"), 255) as u8,
];

/// A decimal version component; fails the build above `max` (BCD has no room).
const fn decimal(digits: &str, max: u16) -> u16 {
    let bytes = digits.as_bytes();
    let mut value = 0u16;
    let mut i = 0;
    while i < bytes.len() {
        assert!(
            bytes[i].is_ascii_digit(),
            "version component is not a number"
        );
        value = value * 10 + (bytes[i] - b'0') as u16;
        assert!(value <= max, "version component too large for bcdDevice");
        i += 1;
    }
    value
}

/// `0xJJMN` from the three version components.
const fn bcd_release(major: &str, minor: &str, patch: &str) -> u16 {
    let major = decimal(major, 99);
    ((major / 10) << 12) | ((major % 10) << 8) | (decimal(minor, 9) << 4) | decimal(patch, 9)
}

//! The board's QSPI flash chip beyond the program: its factory-programmed unique id,
//! which becomes the USB serial number, and the driver the configuration store uses.
//!
//! Every flash operation runs from RAM with interrupts off (embassy-rp's `in_ram`);
//! reading the unique id takes a few microseconds and happens once, at boot.

use embassy_rp::flash::{Blocking, Flash};
use embassy_rp::peripherals::FLASH;
use embassy_rp::Peri;
use static_cell::StaticCell;

/// Size of the Pico's W25Q16 flash, bytes.
pub const FLASH_SIZE: usize = 2 * 1024 * 1024;

/// The flash driver (blocking: the store writes a few bytes, rarely).
pub type BoardFlash = Flash<'static, FLASH, Blocking, FLASH_SIZE>;

/// Bytes of the flash's unique id (W25Q: command `0x4B`, 64 bits).
const UNIQUE_ID_LEN: usize = 8;

/// Opens the flash driver.
pub fn open(flash: Peri<'static, FLASH>) -> BoardFlash {
    Flash::new_blocking(flash)
}

/// The USB serial number: the flash's 64-bit unique id as 16 upper-case hex digits,
/// first byte first. If the id cannot be read (the driver refuses off core 0) the
/// serial is all zeros and a warning is logged.
pub fn serial_number(flash: &mut BoardFlash) -> &'static str {
    let mut id = [0u8; UNIQUE_ID_LEN];
    if let Err(err) = flash.blocking_unique_id(&mut id) {
        defmt::warn!("flash unique id unreadable ({}): serial number zero", err);
        id = [0; UNIQUE_ID_LEN];
    }
    static SERIAL: StaticCell<[u8; 2 * UNIQUE_ID_LEN]> = StaticCell::new();
    let text = SERIAL.init(hex(&id));
    // Hex digits are ASCII, so this is always valid UTF-8.
    let serial = core::str::from_utf8(text).unwrap_or("0000000000000000");
    defmt::info!("serial number {=str}", serial);
    serial
}

/// `bytes` as upper-case hex digits, two per byte, first byte first.
fn hex(bytes: &[u8; UNIQUE_ID_LEN]) -> [u8; 2 * UNIQUE_ID_LEN] {
    const DIGITS: &[u8; 16] = b"0123456789ABCDEF";
    let mut out = [0u8; 2 * UNIQUE_ID_LEN];
    for (pair, byte) in out.chunks_exact_mut(2).zip(bytes) {
        pair[0] = DIGITS[usize::from(byte >> 4)];
        pair[1] = DIGITS[usize::from(byte & 0x0F)];
    }
    out
}

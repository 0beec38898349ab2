//! Into the USB bootloader without a host tool: two resets within [`WINDOW`] (a button
//! from the Pico's RUN pin to ground, pressed twice; or the power switched off and on
//! twice, quickly enough) restart the board into the RP2040's USB bootloader, so a
//! sealed cabinet can be reflashed with the firmware it has, whatever it runs.
//!
//! Each boot that is not a watchdog's reset (a crash) leaves a mark in RAM that a reset
//! does not clear (`.uninit`, as `panic.rs`'s record) and wipes it [`WINDOW`] later; a
//! boot that finds the mark was reset within the window of the previous one. SRAM
//! holds random contents at power-on: the mark is a 32-bit pattern and its complement,
//! so a stray match is one in 2⁶⁴.

use core::cell::UnsafeCell;
use core::mem::MaybeUninit;
use core::ptr::{read_volatile, write_volatile};

use embassy_rp::pac;
use embassy_time::{Duration, Timer};

/// How soon after a boot a second reset enters the bootloader.
pub const WINDOW: Duration = Duration::from_millis(500);

/// The mark: the pattern, then its complement.
const MARK: [u32; 2] = [0xB007_7A95, !0xB007_7A95];

/// The mark's RAM, written only at boot (before any task runs) and by [`wipe_task`].
struct Slot(UnsafeCell<MaybeUninit<[u32; 2]>>);

// SAFETY: written at boot before the executor starts and afterwards by `wipe_task`
// alone; never concurrently.
unsafe impl Sync for Slot {}

#[link_section = ".uninit.DOUBLE_TAP"]
static SLOT: Slot = Slot(UnsafeCell::new(MaybeUninit::uninit()));

fn read() -> [u32; 2] {
    // SAFETY: any bit pattern is a valid [u32; 2]; volatile so the read happens.
    unsafe { read_volatile(SLOT.0.get().cast::<[u32; 2]>()) }
}

fn write(value: [u32; 2]) {
    // SAFETY: see `Slot`.
    unsafe { write_volatile(SLOT.0.get().cast::<[u32; 2]>(), value) }
}

/// At boot, before anything else: whether this boot is the second of a double reset.
/// Arms the mark for the next boot otherwise (a watchdog's reset neither counts nor
/// arms: a crash loop must not end in the bootloader).
pub fn second_reset() -> bool {
    let reason = pac::WATCHDOG.reason().read();
    if reason.timer() || reason.force() {
        write([0, 0]);
        return false;
    }
    if read() == MARK {
        write([0, 0]);
        return true;
    }
    write(MARK);
    false
}

/// Wipes the mark [`WINDOW`] after boot: a reset after that is a single one.
#[embassy_executor::task]
pub async fn wipe_task() {
    Timer::after(WINDOW).await;
    write([0, 0]);
}

//! The one IN buffer in flight, at the register level: when the host took it, taking
//! an unsent one back, and when the host's frames start.
//!
//! embassy-rp's `EndpointIn::write` arms the endpoint's buffer and returns; the host
//! takes it at its next IN token. Two things it does not offer are needed to keep
//! exactly one fresh report in flight ([`crate::usb_hid::report_in_task`]):
//!
//! * **when the host took the buffer** — [`TakenHandler`], an extra handler on the
//!   USB interrupt that runs before embassy's own and signals [`TAKEN`] with the time
//!   the buffer-status bit of the IN endpoint was set;
//! * **revoking an armed buffer the host has not taken** (it paused polling, or is
//!   late) so a newer report can replace it — [`revoke`] and [`release`], with the
//!   controller's `EP_ABORT` / `EP_ABORT_DONE` registers (RP2040 B2 and later: the
//!   endpoint NAKs while aborted, and `EP_ABORT_DONE` says when the buffer control
//!   register may be changed).
//!
//! * **when the host's frames start** — the same handler notes the time of each start
//!   of frame (SOF, every 1 ms on a full-speed bus while it is not suspended): the host
//!   sends its IN token somewhere in the frame, so a report armed just before the frame
//!   starts is as fresh as it can be and never being replaced when the token comes
//!   ([`track_frames`], [`last_frame_start`]).
//!
//! embassy-rp keeps the endpoint's data PID in the buffer control register only, so
//! a revoked buffer is left with the PID flipped back, and the next `write` sends
//! the same PID the revoked buffer would have had.

use core::cell::Cell;

use embassy_rp::interrupt::typelevel::{Handler, USBCTRL_IRQ};
use embassy_rp::pac;
use embassy_sync::blocking_mutex::raw::CriticalSectionRawMutex;
use embassy_sync::blocking_mutex::Mutex;
use embassy_sync::signal::Signal;
use embassy_time::{Duration, Instant};

/// The HID interface's interrupt IN endpoint number. embassy-rp gives endpoints the
/// lowest free number; the HID class is the only one, so its IN endpoint is 1 (the
/// firmware-in-the-loop harness checks the descriptor says `0x81`).
pub const IN_ENDPOINT: usize = 1;

/// Longest wait for `EP_ABORT_DONE`: the controller finishes a transaction already
/// under way first, at most one 64-byte full-speed packet (≈ 50 µs) plus handshake.
const ABORT_TIMEOUT: Duration = Duration::from_micros(200);

/// Signalled with the time the host took the armed IN buffer.
pub static TAKEN: Signal<CriticalSectionRawMutex, Instant> = Signal::new();

/// How many times the bus was reset or the configuration changed: both clear the IN
/// buffer without the host taking it ([`bus_changed`], [`bus_epoch`]).
static BUS_EPOCH: Mutex<CriticalSectionRawMutex, Cell<u32>> = Mutex::new(Cell::new(0));

/// Notes a bus reset or a change of configuration (called from the device's bus
/// events, in thread mode, in the same step as the controller's endpoints change).
pub fn bus_changed() {
    BUS_EPOCH.lock(|epoch| epoch.set(epoch.get().wrapping_add(1)));
}

/// The count [`bus_changed`] keeps: a buffer armed at one epoch and found empty at the
/// same epoch was taken by the host, even if its interrupt was missed (`buff_status` is
/// read here before embassy-rp's handler clears it, and a take that lands between the
/// two reads is seen by embassy-rp's alone).
pub fn bus_epoch() -> u32 {
    BUS_EPOCH.lock(Cell::get)
}

/// When the newest start of frame arrived; `None` before the first.
static FRAME_START: Mutex<CriticalSectionRawMutex, Cell<Option<Instant>>> =
    Mutex::new(Cell::new(None));

/// USB interrupt handler, bound before embassy-rp's (which clears the buffer bits):
/// signals [`TAKEN`] when the IN endpoint's buffer completed, and notes each start of
/// frame (embassy-rp leaves that interrupt alone; reading `SOF_RD` clears it).
pub struct TakenHandler;

impl Handler<USBCTRL_IRQ> for TakenHandler {
    unsafe fn on_interrupt() {
        let now = Instant::now();
        if pac::USB.buff_status().read().ep_in(IN_ENDPOINT) {
            TAKEN.signal(now);
        }
        if pac::USB.ints().read().dev_sof() {
            let _frame = pac::USB.sof_rd().read();
            FRAME_START.lock(|at| at.set(Some(now)));
        }
    }
}

/// Turns on the start-of-frame interrupt, after embassy-rp has set up the controller's
/// interrupts (it writes them whole once, when the device is built).
pub fn track_frames() {
    let mut bit = pac::usb::regs::Int(0);
    bit.set_dev_sof(true);
    // The RP2040's atomic set alias of INTE (its address + 0x2000): only this bit is
    // set, so nothing embassy-rp's interrupt handler changes meanwhile is lost.
    let set_alias = (pac::USB.inte().as_ptr() as usize + ATOMIC_SET) as *mut u32;
    // SAFETY: the alias of a register of the USB controller, always mapped; the write
    // sets one interrupt enable bit.
    unsafe { set_alias.write_volatile(bit.0) };
}

/// Offset of a peripheral register's atomic bit-set alias (RP2040 datasheet §2.1.2).
const ATOMIC_SET: usize = 0x2000;

/// Frame starts older than this are not followed: the bus is suspended, or the
/// controller gives no start-of-frame interrupt.
pub const FRAMES_LOST: Duration = Duration::from_millis(3);

/// When the host's newest frame started, if one has.
pub fn last_frame_start() -> Option<Instant> {
    FRAME_START.lock(Cell::get)
}

/// Stops the controller from sending the armed IN buffer and, if the host has not
/// taken it yet, disarms it. Returns `true` when it was disarmed (its report was not
/// sent; the endpoint NAKs until [`release`]), `false` when the host had already
/// taken it (then [`TAKEN`] is or will be signalled) or it was not armed. Always
/// call [`release`] afterwards.
pub fn revoke() -> bool {
    pac::USB
        .ep_abort()
        .modify(|w| w.set_ep_in(IN_ENDPOINT, true));
    let start = Instant::now();
    while !pac::USB.ep_abort_done().read().ep_in(IN_ENDPOINT) {
        if start.elapsed() > ABORT_TIMEOUT {
            // The controller never confirmed: leave the buffer to it.
            return false;
        }
    }
    let control = pac::USB_DPRAM.ep_in_buffer_control(IN_ENDPOINT);
    let armed = control.read();
    if !armed.available(0) {
        return false;
    }
    control.write(|w| {
        // The next write flips the PID: flip it back so the replacement goes out
        // with the PID this buffer had.
        w.set_pid(0, !armed.pid(0));
        w.set_available(0, false);
        w.set_full(0, false);
    });
    true
}

/// Whether the IN buffer is armed (the controller will send it at the next IN token).
pub fn armed() -> bool {
    pac::USB_DPRAM
        .ep_in_buffer_control(IN_ENDPOINT)
        .read()
        .available(0)
}

/// Ends a [`revoke`]: the endpoint answers IN tokens again.
pub fn release() {
    pac::USB
        .ep_abort()
        .modify(|w| w.set_ep_in(IN_ENDPOINT, false));
    pac::USB
        .ep_abort_done()
        .write(|w| w.set_ep_in(IN_ENDPOINT, true));
}

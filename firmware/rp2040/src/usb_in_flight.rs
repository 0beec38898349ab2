//! The one IN buffer in flight, at the register level: when the host took it, and
//! taking an unsent one back.
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
//! embassy-rp keeps the endpoint's data PID in the buffer control register only, so
//! a revoked buffer is left with the PID flipped back, and the next `write` sends
//! the same PID the revoked buffer would have had.

use embassy_rp::interrupt::typelevel::{Handler, USBCTRL_IRQ};
use embassy_rp::pac;
use embassy_sync::blocking_mutex::raw::CriticalSectionRawMutex;
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

/// USB interrupt handler, bound before embassy-rp's (which clears the bits):
/// signals [`TAKEN`] when the IN endpoint's buffer completed.
pub struct TakenHandler;

impl Handler<USBCTRL_IRQ> for TakenHandler {
    unsafe fn on_interrupt() {
        if pac::USB.buff_status().read().ep_in(IN_ENDPOINT) {
            TAKEN.signal(Instant::now());
        }
    }
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

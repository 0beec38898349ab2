//! Panics: the message is kept in RAM that the reset does not clear, then the
//! watchdog resets the chip at once; the next boot reads the message back
//! ([`take_last`]), logs it and keeps it for the host.
//!
//! The record lives in `.uninit` (cortex-m-rt leaves that section as it was at
//! reset: SRAM keeps its contents through a watchdog reset). A magic number, the
//! length and a checksum tell a kept record from the random contents SRAM has at
//! power-on.

use core::cell::UnsafeCell;
use core::fmt::Write;
use core::mem::MaybeUninit;

use embassy_rp::pac;

/// Bytes of the panic message kept (longer messages are cut).
pub const MESSAGE_CAPACITY: usize = 120;

/// Marks a record written by [`panic`].
const MAGIC: u32 = 0x5041_4E43; // "PANC"

/// The kept panic message.
#[repr(C)]
struct Record {
    magic: u32,
    len: u32,
    text: [u8; MESSAGE_CAPACITY],
    check: u32,
}

impl Record {
    /// FNV-1a over the length and the text.
    fn checksum(len: u32, text: &[u8]) -> u32 {
        let mut hash = 0x811C_9DC5u32;
        for byte in len.to_le_bytes().iter().chain(text) {
            hash = (hash ^ u32::from(*byte)).wrapping_mul(0x0100_0193);
        }
        hash
    }
}

/// The record's RAM: written only by the panic handler (interrupts off, nothing else
/// running) and read once at boot before any task runs.
struct Slot(UnsafeCell<MaybeUninit<Record>>);

// SAFETY: accessed only from the panic handler and from `take_last` at boot, never
// concurrently (see `Slot`).
unsafe impl Sync for Slot {}

#[link_section = ".uninit.PANIC_RECORD"]
static RECORD: Slot = Slot(UnsafeCell::new(MaybeUninit::uninit()));

/// Writes into a fixed buffer, cutting what does not fit.
struct Cut<'a> {
    buf: &'a mut [u8],
    len: usize,
}

impl Write for Cut<'_> {
    fn write_str(&mut self, s: &str) -> core::fmt::Result {
        for &byte in s.as_bytes() {
            if self.len == self.buf.len() {
                break;
            }
            self.buf[self.len] = byte;
            self.len += 1;
        }
        Ok(())
    }
}

/// The panic message the previous run left, if it ended in a panic; the record is
/// cleared so it is reported once. Call once at boot, before spawning tasks.
pub fn take_last() -> Option<PanicMessage> {
    // SAFETY: at boot nothing else touches the record (see `Slot`); every bit
    // pattern is a valid `Record` (plain integers and bytes).
    let record = unsafe { (*RECORD.0.get()).assume_init_mut() };
    let len = record.len as usize;
    let kept = record.magic == MAGIC
        && len <= MESSAGE_CAPACITY
        && record.check == Record::checksum(record.len, &record.text[..len]);
    record.magic = 0;
    kept.then(|| PanicMessage::from_bytes(&record.text[..len]))
}

#[panic_handler]
fn panic(info: &core::panic::PanicInfo) -> ! {
    // SAFETY: `cpsid i` only masks interrupts; nothing runs after this but the reset.
    unsafe { core::arch::asm!("cpsid i") };
    // SAFETY: interrupts are off and the executor is not running: the handler is the
    // only code touching the record (see `Slot`).
    let record = unsafe { (*RECORD.0.get()).assume_init_mut() };
    let mut cut = Cut {
        buf: &mut record.text,
        len: 0,
    };
    if let Some(location) = info.location() {
        let _ = write!(cut, "{}:{}: ", location.file(), location.line());
    }
    let _ = write!(cut, "{}", info.message());
    let len = cut.len as u32;
    record.len = len;
    record.check = Record::checksum(len, &record.text[..len as usize]);
    record.magic = MAGIC;
    defmt::error!("panic: {=[u8]:a}", &record.text[..len as usize]);
    // A forced watchdog reset (the next boot reports `ResetReason::Forced`).
    pac::WATCHDOG.ctrl().write(|w| w.set_trigger(true));
    loop {
        core::hint::spin_loop();
    }
}

/// A panic message kept from the previous run: valid UTF-8 (a cut message is cut
/// again at a character boundary), at most [`MESSAGE_CAPACITY`] bytes.
#[derive(Clone, Copy)]
pub struct PanicMessage {
    bytes: [u8; MESSAGE_CAPACITY],
    len: usize,
}

impl PanicMessage {
    /// The longest valid UTF-8 prefix of `bytes`.
    fn from_bytes(bytes: &[u8]) -> Self {
        let len = bytes.len().min(MESSAGE_CAPACITY);
        let valid = match core::str::from_utf8(&bytes[..len]) {
            Ok(s) => s.len(),
            Err(err) => err.valid_up_to(),
        };
        let mut out = [0u8; MESSAGE_CAPACITY];
        out[..valid].copy_from_slice(&bytes[..valid]);
        Self {
            bytes: out,
            len: valid,
        }
    }

    /// The text.
    pub fn as_str(&self) -> &str {
        core::str::from_utf8(&self.bytes[..self.len]).unwrap_or("")
    }
}

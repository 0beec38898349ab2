//! The board's settings kept in flash across resets: `sensor_board::store`'s record
//! store in the last two 4 KiB sectors of the 2 MiB flash, one record per save (the
//! 24 bytes of `BoardSettings::encode_fields`, a sequence number and a CRC-32).
//!
//! At boot [`load`] reads the newest valid record and the settings are applied before
//! the mice are initialised; a missing or damaged record means the defaults. A
//! settings write from the host ([`save`]) is applied at once by the caller and
//! written here by [`save_task`], outside the USB handler, when
//! [`sensor_board::save_schedule`] says (a burst of changes is one write, at most one
//! write a second, so at most one sector erase a minute); settings equal to those in
//! flash are not written again, and [`flush`] writes what is pending at once (before a
//! restart).
//!
//! A save is one page program (typically 0.4 ms with interrupts off); one save in
//! every 113 first erases a sector (typically 45 ms, at most 400 ms for the W25Q16JV),
//! during which nothing else runs: the watchdog is given [`FLASH_WATCHDOG`] for it,
//! and the PS/2 receivers may overflow and recover (counted as FIFO stalls).

use embassy_futures::select::{select, select3, Either, Either3};
use embassy_sync::blocking_mutex::raw::CriticalSectionRawMutex;
use embassy_sync::signal::Signal;
use embassy_time::{Duration, Instant, Timer};
use foosball_protocol::BoardSettings;
use sensor_board::save_schedule::SaveSchedule;
use sensor_board::store::RecordStore;

use crate::board_flash::{BoardFlash, FLASH_SIZE};
use crate::watchdog;

/// Flash sector size, bytes.
const SECTOR: u32 = 4096;
/// Offset of the store's first sector: the last two sectors of the flash. The
/// program (about 62 KiB) starts at offset 0 and never reaches them.
pub const STORE_OFFSET: u32 = FLASH_SIZE as u32 - 2 * SECTOR;

/// How long the watchdog waits while the flash is erased or programmed (a sector
/// erase takes at most 400 ms).
const FLASH_WATCHDOG: Duration = Duration::from_millis(1_000);

/// The record store over the board's flash.
pub type Store = RecordStore<BoardFlash, { BoardSettings::FIELDS_LEN }>;

/// Opens the store and reads the kept settings: `None` if there are none (a new
/// board) or they are unreadable (logged).
pub fn load(flash: BoardFlash) -> (Store, Option<BoardSettings>) {
    let mut store = Store::new(flash, STORE_OFFSET);
    let settings = match store.load() {
        Ok(Some(fields)) => match BoardSettings::decode_fields(&fields) {
            Ok(settings) => {
                defmt::info!("settings loaded from flash");
                Some(settings)
            }
            Err(err) => {
                defmt::warn!("kept settings invalid ({}): defaults", err);
                None
            }
        },
        Ok(None) => {
            defmt::info!("no settings in flash: defaults");
            None
        }
        Err(err) => {
            defmt::warn!("settings store unreadable ({}): defaults", err);
            None
        }
    };
    (store, settings)
}

/// The newest settings to write.
static PENDING: Signal<CriticalSectionRawMutex, BoardSettings> = Signal::new();

/// A request to write the pending settings at once, and its answer.
static FLUSH: Signal<CriticalSectionRawMutex, ()> = Signal::new();
static FLUSHED: Signal<CriticalSectionRawMutex, ()> = Signal::new();

/// Asks [`save_task`] to keep `settings` (a newer call before it wrote them replaces
/// them).
pub fn save(settings: BoardSettings) {
    PENDING.signal(settings);
}

/// Writes the pending settings, if any, without waiting for a quiet moment; returns
/// once they are in flash (or the write failed, logged), at most `timeout` later.
pub async fn flush(timeout: Duration) {
    FLUSHED.reset();
    FLUSH.signal(());
    if let Either::Second(()) = select(FLUSHED.wait(), Timer::after(timeout)).await {
        defmt::warn!("settings not flushed in time");
    }
}

/// Writes the settings [`save`] hands over when [`SaveSchedule`] says; `kept` are those
/// in flash at boot.
#[embassy_executor::task]
pub async fn save_task(mut store: Store, mut kept: Option<BoardSettings>) -> ! {
    let mut schedule = SaveSchedule::new();
    let mut pending = None;
    loop {
        let due = schedule.due_at().map(Instant::from_micros);
        let flushing = match select3(
            PENDING.wait(),
            FLUSH.wait(),
            Timer::at(due.unwrap_or(Instant::MAX)),
        )
        .await
        {
            Either3::First(settings) => {
                pending = Some(settings);
                schedule.changed(Instant::now().as_micros());
                continue;
            }
            Either3::Second(()) => true,
            Either3::Third(()) => false,
        };
        if let Some(settings) = pending.take() {
            let wrote = kept != Some(settings);
            if wrote {
                watchdog::allow(FLASH_WATCHDOG);
                match store.save(&settings.encode_fields()) {
                    Ok(()) => {
                        kept = Some(settings);
                        defmt::info!("settings written to flash");
                    }
                    Err(err) => defmt::warn!("settings not written to flash: {}", err),
                }
            } else {
                defmt::info!("settings unchanged: not written to flash");
            }
            schedule.done(Instant::now().as_micros(), wrote);
        }
        if flushing {
            FLUSHED.signal(());
        }
    }
}

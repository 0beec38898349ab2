//! The board's settings kept in flash across resets: `sensor_board::store`'s record
//! store in the last two 4 KiB sectors of the 2 MiB flash, one record per save (the
//! 24 bytes of `BoardSettings::encode_fields`, a sequence number and a CRC-32).
//!
//! At boot [`load`] reads the newest valid record and the settings are applied before
//! the mice are initialised; a missing or damaged record means the defaults. A
//! settings write from the host ([`save`]) is applied at once by the caller and
//! written here by [`save_task`], outside the USB handler.
//!
//! A save is one page program (typically 0.4 ms with interrupts off); one save in
//! every 113 first erases a sector (typically 45 ms, at most 400 ms for the W25Q16JV),
//! during which nothing else runs: the watchdog is given [`FLASH_WATCHDOG`] for it,
//! and the PS/2 receivers may overflow and recover (counted as FIFO stalls).

use embassy_sync::blocking_mutex::raw::CriticalSectionRawMutex;
use embassy_sync::signal::Signal;
use embassy_time::Duration;
use foosball_protocol::BoardSettings;
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

/// Asks [`save_task`] to keep `settings` (a newer call before it ran replaces it).
pub fn save(settings: BoardSettings) {
    PENDING.signal(settings);
}

/// Writes the settings [`save`] hands over, one record each.
#[embassy_executor::task]
pub async fn save_task(mut store: Store) -> ! {
    loop {
        let settings = PENDING.wait().await;
        watchdog::allow(FLASH_WATCHDOG);
        match store.save(&settings.encode_fields()) {
            Ok(()) => defmt::info!("settings written to flash"),
            Err(err) => defmt::warn!("settings not written to flash: {}", err),
        }
    }
}

//! The settings record store on a NOR flash model: erase to 0xFF in whole sectors,
//! programming only clears bits, and a power cut that stops an erase or a write
//! after any byte.

use embedded_storage::nor_flash::{
    ErrorType, NorFlash, NorFlashError, NorFlashErrorKind, ReadNorFlash,
};
use proptest::prelude::*;
use sensor_board::store::{RecordStore, StoreError};

const SECTOR: usize = 4096;
/// The store's payload: the settings' 24 bytes.
const N: usize = 24;

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum FlashError {
    /// The power went: the operation stopped part-way.
    PowerCut,
    Misaligned,
}

impl NorFlashError for FlashError {
    fn kind(&self) -> NorFlashErrorKind {
        match self {
            Self::PowerCut => NorFlashErrorKind::Other,
            Self::Misaligned => NorFlashErrorKind::NotAligned,
        }
    }
}

/// NOR flash: four sectors, write granularity `W` bytes.
struct Flash<const W: usize> {
    data: Vec<u8>,
    /// Bytes that may still be erased or programmed before the power goes.
    budget: Option<usize>,
    erases: usize,
}

impl<const W: usize> Flash<W> {
    fn blank() -> Self {
        Self {
            data: vec![0xFF; 4 * SECTOR],
            budget: None,
            erases: 0,
        }
    }

    /// Takes one byte of the budget; `false` once the power is gone.
    fn spend(&mut self) -> bool {
        match &mut self.budget {
            Some(0) => false,
            Some(left) => {
                *left -= 1;
                true
            }
            None => true,
        }
    }
}

impl<const W: usize> ErrorType for Flash<W> {
    type Error = FlashError;
}

impl<const W: usize> ReadNorFlash for Flash<W> {
    const READ_SIZE: usize = 1;

    fn read(&mut self, offset: u32, bytes: &mut [u8]) -> Result<(), FlashError> {
        let at = offset as usize;
        bytes.copy_from_slice(&self.data[at..at + bytes.len()]);
        Ok(())
    }

    fn capacity(&self) -> usize {
        self.data.len()
    }
}

impl<const W: usize> NorFlash for Flash<W> {
    const WRITE_SIZE: usize = W;
    const ERASE_SIZE: usize = SECTOR;

    fn erase(&mut self, from: u32, to: u32) -> Result<(), FlashError> {
        let (from, to) = (from as usize, to as usize);
        if from % SECTOR != 0 || to % SECTOR != 0 || to > self.data.len() {
            return Err(FlashError::Misaligned);
        }
        self.erases += 1;
        for at in from..to {
            if !self.spend() {
                return Err(FlashError::PowerCut);
            }
            self.data[at] = 0xFF;
        }
        Ok(())
    }

    fn write(&mut self, offset: u32, bytes: &[u8]) -> Result<(), FlashError> {
        let at = offset as usize;
        if at % W != 0 || bytes.len() % W != 0 || at + bytes.len() > self.data.len() {
            return Err(FlashError::Misaligned);
        }
        for (i, &byte) in bytes.iter().enumerate() {
            if !self.spend() {
                return Err(FlashError::PowerCut);
            }
            // Programming only turns ones into zeros.
            self.data[at + i] &= byte;
        }
        Ok(())
    }
}

/// The store at the last two of the four sectors.
fn store<const W: usize>(flash: Flash<W>) -> RecordStore<Flash<W>, N> {
    RecordStore::new(flash, 2 * SECTOR as u32)
}

fn payload(i: u32) -> [u8; N] {
    let mut p = [0u8; N];
    for (k, b) in p.iter_mut().enumerate() {
        *b = (i as u8).wrapping_mul(31).wrapping_add(k as u8);
    }
    p
}

#[test]
fn blank_flash_holds_nothing_and_a_save_is_loaded_back() {
    let mut s = store(Flash::<1>::blank());
    assert_eq!(s.load(), Ok(None));
    s.save(&payload(1)).unwrap();
    // A power cycle: a new store on the same flash.
    let mut s = store(s.into_inner());
    assert_eq!(s.load(), Ok(Some(payload(1))));
    assert_eq!(s.into_inner().erases, 0, "a blank sector needs no erase");
}

#[test]
fn many_saves_cross_sectors_and_erase_only_when_full() {
    for write_size in [1usize, 4, 16] {
        let saves = match write_size {
            1 => run_saves::<1>(),
            4 => run_saves::<4>(),
            _ => run_saves::<16>(),
        };
        let (slots, erases, count) = saves;
        // The first sector fills without an erase; every later sector switch erases.
        assert_eq!(erases, (count - 1) / slots, "write size {write_size}");
    }
}

fn run_saves<const W: usize>() -> (usize, usize, usize) {
    let slots = RecordStore::<Flash<W>, N>::slots() as usize;
    let count = 3 * slots + 5;
    let mut flash = Flash::<W>::blank();
    for i in 0..count {
        let mut s = store(flash);
        s.save(&payload(i as u32)).unwrap();
        flash = s.into_inner();
        let mut s = store(flash);
        assert_eq!(s.load(), Ok(Some(payload(i as u32))), "save {i}");
        flash = s.into_inner();
    }
    (slots, flash.erases, count)
}

/// Saves `old` (after `before` other saves), then `new` with the power cut after
/// `cut` bytes of erasing and programming; returns what a power cycle loads.
fn cut_during_save(before: usize, cut: usize) -> (Option<[u8; N]>, Flash<1>) {
    let mut s = store(Flash::<1>::blank());
    for i in 0..before {
        s.save(&payload(1000 + i as u32)).unwrap();
    }
    s.save(&payload(1)).unwrap();
    let mut flash = s.into_inner();
    flash.budget = Some(cut);
    let mut s = store(flash);
    let result = s.save(&payload(2));
    let mut flash = s.into_inner();
    flash.budget = None;
    let mut s = store(flash);
    let loaded = s.load().unwrap();
    if result.is_ok() {
        assert_eq!(loaded, Some(payload(2)), "a finished save is the newest");
    } else {
        assert_eq!(result, Err(StoreError::Flash(FlashError::PowerCut)));
    }
    (loaded, s.into_inner())
}

#[test]
fn a_power_cut_while_writing_leaves_the_old_record() {
    let len = RecordStore::<Flash<1>, N>::record_len();
    for cut in 0..len {
        let (loaded, flash) = cut_during_save(0, cut);
        assert_eq!(loaded, Some(payload(1)), "cut after {cut} bytes");
        // And the store goes on: the next save lands and is loaded.
        let mut s = store(flash);
        s.save(&payload(3)).unwrap();
        let mut s = store(s.into_inner());
        assert_eq!(s.load(), Ok(Some(payload(3))), "after a cut at {cut}");
    }
    let (loaded, _) = cut_during_save(0, len);
    assert_eq!(loaded, Some(payload(2)));
}

#[test]
fn a_power_cut_while_erasing_the_other_sector_leaves_the_old_record() {
    let slots = RecordStore::<Flash<1>, N>::slots() as usize;
    let len = RecordStore::<Flash<1>, N>::record_len();
    // Fill the first sector, so the next save erases the second before writing.
    for cut in [0, 1, 17, SECTOR / 2, SECTOR - 1, SECTOR, SECTOR + len / 2] {
        let (loaded, flash) = cut_during_save(slots - 1, cut);
        assert_eq!(loaded, Some(payload(1)), "cut after {cut} bytes");
        let mut s = store(flash);
        s.save(&payload(4)).unwrap();
        let mut s = store(s.into_inner());
        assert_eq!(s.load(), Ok(Some(payload(4))));
    }
    let (loaded, _) = cut_during_save(slots - 1, SECTOR + len);
    assert_eq!(loaded, Some(payload(2)));
}

#[test]
fn a_layout_that_does_not_fit_is_refused() {
    let mut s = RecordStore::<Flash<1>, N>::new(Flash::blank(), 100);
    assert_eq!(s.load(), Err(StoreError::Layout));
    // Two sectors from the last one run past the end.
    let mut s = RecordStore::<Flash<1>, N>::new(Flash::blank(), 3 * SECTOR as u32);
    assert_eq!(s.save(&payload(0)), Err(StoreError::Layout));
}

proptest! {
    /// Whatever the two sectors hold (a foreign program, noise), loading does not
    /// panic, and a save is then loaded back.
    #[test]
    fn any_flash_contents_load_and_take_a_save(
        noise in proptest::collection::vec(any::<u8>(), 2 * SECTOR),
        blank_from in 0usize..=2 * SECTOR,
    ) {
        let mut flash = Flash::<1>::blank();
        flash.data[2 * SECTOR..2 * SECTOR + blank_from].copy_from_slice(&noise[..blank_from]);
        let mut s = store(flash);
        let _ = s.load().unwrap();
        s.save(&payload(9)).unwrap();
        let mut s = store(s.into_inner());
        prop_assert_eq!(s.load(), Ok(Some(payload(9))));
    }
}

/// Records of `N` bytes that fit a sector (the store's slots are the record padded to
/// the write size: 1 byte here).
const SLOTS: usize = SECTOR / (12 + N);

#[test]
fn a_host_writing_settings_in_a_loop_for_a_minute_causes_at_most_one_erase() {
    use sensor_board::save_schedule::SaveSchedule;
    // From every fill level of the current sector: a new value from the host every
    // 50 ms for 60 s, written when the schedule says.
    for already in 0..SLOTS as u32 {
        let mut s = store(Flash::<1>::blank());
        for i in 0..already {
            s.save(&payload(i)).unwrap();
        }
        let mut flash = s.into_inner();
        flash.erases = 0;
        let mut s = store(flash);
        let mut schedule = SaveSchedule::new();
        let mut value = None;
        let mut writes = 0;
        let period_us = 50_000;
        let end_us = 60_000_000;
        let mut now = 0u64;
        while now <= end_us + 10_000_000 {
            if now < end_us && now % period_us == 0 {
                value = Some(payload(1_000 + (now / period_us) as u32));
                schedule.changed(now);
            }
            if schedule.due_at().is_some_and(|at| now >= at) {
                s.save(&value.unwrap()).unwrap();
                schedule.done(now, true);
                writes += 1;
            }
            now += 1_000;
        }
        assert_eq!(s.load().unwrap(), value, "the last value is kept");
        let erases = s.into_inner().erases;
        assert!(
            erases <= 1,
            "{erases} erases from {already} records in ({writes} writes)"
        );
        assert!(writes <= 61, "{writes} writes");
    }
}

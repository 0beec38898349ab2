//! A record store in NOR flash that survives a power cut at any moment: the board's
//! settings kept across resets.
//!
//! Two erase sectors, A and B. Each save appends one record to the sector that holds
//! the newest one:
//!
//! | bytes | field |
//! |---|---|
//! | 4 | magic `SFS1` |
//! | 4 | sequence number, `u32` little-endian, one more than the newest record's |
//! | N | payload |
//! | 4 | CRC-32 (ISO-HDLC, as zlib's) of the bytes above, little-endian |
//!
//! padded with `0xFF` to the flash's write size. [`RecordStore::load`] reads both
//! sectors and takes the valid record (magic and CRC) with the highest sequence
//! number. When the current sector is full, the other one is erased and the record
//! goes to its first slot; only then is the old sector's data superseded. So:
//!
//! * a cut while a record is written leaves it with a bad CRC: it is skipped, the
//!   previous record is the newest valid one, and the next save goes after it;
//! * a cut while the other sector is erased leaves the current sector untouched.
//!
//! The sequence number is not wrapped: at 100 000 erase cycles per sector a chip
//! wears out long before 2³² saves.

use embedded_storage::nor_flash::NorFlash;

/// The record's magic number.
const MAGIC: [u8; 4] = *b"SFS1";
/// Bytes of a record besides its payload: magic, sequence, CRC.
const OVERHEAD: usize = 12;
/// Longest record this store handles, bytes (a stack buffer of this size is used).
pub const MAX_RECORD: usize = 64;

/// CRC-32/ISO-HDLC without a lookup table (a few hundred bytes of code; a record is
/// checked a few hundred times at boot, not in a hot loop).
const CRC: crc::Crc<u32, crc::NoTable> = crc::Crc::<u32, crc::NoTable>::new(&crc::CRC_32_ISO_HDLC);

/// Why the store failed.
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum StoreError<E> {
    /// The flash driver failed.
    #[error("flash error: {0:?}")]
    Flash(E),
    /// The layout does not work on this flash: sectors not aligned or too small for
    /// one record, or a record longer than [`MAX_RECORD`].
    #[error("the record store's layout does not fit this flash")]
    Layout,
    /// A record read back after writing is not what was written (worn-out flash).
    #[error("a record read back differs from what was written")]
    Verify,
}

/// Where the store stands after [`RecordStore::load`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct Position {
    /// The sector (0 or 1) the next record goes to, and its slot there; `None` when
    /// that sector is full and the other one must be erased.
    next: Option<(u32, u32)>,
    /// The sector holding the newest valid record (or sector 0 if there is none).
    current: u32,
    /// The newest valid record's sequence number.
    sequence: Option<u32>,
}

/// Records of an `N`-byte payload in two sectors of `flash`, starting at `base`.
#[derive(Debug)]
pub struct RecordStore<F: NorFlash, const N: usize> {
    flash: F,
    base: u32,
    position: Option<Position>,
}

impl<F: NorFlash, const N: usize> RecordStore<F, N> {
    /// A store in the two erase sectors from `base` (an offset into `flash`).
    pub const fn new(flash: F, base: u32) -> Self {
        Self {
            flash,
            base,
            position: None,
        }
    }

    /// Bytes one record takes: magic, sequence, payload, CRC, padded to the write
    /// size.
    pub const fn record_len() -> usize {
        (OVERHEAD + N).div_ceil(F::WRITE_SIZE) * F::WRITE_SIZE
    }

    /// Records one sector holds.
    pub const fn slots() -> u32 {
        (F::ERASE_SIZE / Self::record_len()) as u32
    }

    /// The flash, back.
    pub fn into_inner(self) -> F {
        self.flash
    }

    fn check_layout(&self) -> Result<(), StoreError<F::Error>> {
        let len = Self::record_len();
        let fits = len <= MAX_RECORD
            && Self::slots() >= 1
            && len % F::READ_SIZE == 0
            && self.base as usize % F::ERASE_SIZE == 0
            && (self.base as usize)
                .checked_add(2 * F::ERASE_SIZE)
                .is_some_and(|end| end <= self.flash.capacity());
        if fits {
            Ok(())
        } else {
            Err(StoreError::Layout)
        }
    }

    fn slot_offset(&self, sector: u32, slot: u32) -> u32 {
        self.base + sector * F::ERASE_SIZE as u32 + slot * Self::record_len() as u32
    }

    /// The newest valid record's payload, `None` if there is none (blank or foreign
    /// flash). Also finds where the next [`save`](Self::save) writes.
    pub fn load(&mut self) -> Result<Option<[u8; N]>, StoreError<F::Error>> {
        self.check_layout()?;
        let len = Self::record_len();
        let mut newest: Option<(u32, u32, [u8; N])> = None; // (sequence, sector, payload)
                                                            // Per sector: the slot after its last written one.
        let mut append = [0u32; 2];
        let mut buf = [0u8; MAX_RECORD];
        for sector in 0..2 {
            for slot in 0..Self::slots() {
                let record = &mut buf[..len];
                self.flash
                    .read(self.slot_offset(sector, slot), record)
                    .map_err(StoreError::Flash)?;
                if record.iter().all(|&b| b == 0xFF) {
                    continue;
                }
                append[sector as usize] = slot + 1;
                if let Some((sequence, payload)) = parse::<N>(record) {
                    if newest.is_none_or(|(best, _, _)| sequence > best) {
                        newest = Some((sequence, sector, payload));
                    }
                }
            }
        }
        let current = newest.map_or(0, |(_, sector, _)| sector);
        let slot = append[current as usize];
        self.position = Some(Position {
            next: (slot < Self::slots()).then_some((current, slot)),
            current,
            sequence: newest.map(|(sequence, _, _)| sequence),
        });
        Ok(newest.map(|(_, _, payload)| payload))
    }

    /// Appends `payload` as the newest record (erasing the other sector first when
    /// the current one is full), then reads it back.
    pub fn save(&mut self, payload: &[u8; N]) -> Result<(), StoreError<F::Error>> {
        let position = match self.position {
            Some(position) => position,
            None => {
                self.load()?;
                self.position.ok_or(StoreError::Layout)?
            }
        };
        let (sector, slot) = match position.next {
            Some(next) => next,
            None => {
                let other = 1 - position.current;
                let from = self.slot_offset(other, 0);
                self.flash
                    .erase(from, from + F::ERASE_SIZE as u32)
                    .map_err(StoreError::Flash)?;
                (other, 0)
            }
        };
        let sequence = position.sequence.map_or(0, |s| s.saturating_add(1));
        let len = Self::record_len();
        let mut record = [0xFFu8; MAX_RECORD];
        record[..4].copy_from_slice(&MAGIC);
        record[4..8].copy_from_slice(&sequence.to_le_bytes());
        record[8..8 + N].copy_from_slice(payload);
        let crc = CRC.checksum(&record[..8 + N]);
        record[8 + N..OVERHEAD + N].copy_from_slice(&crc.to_le_bytes());
        let offset = self.slot_offset(sector, slot);
        // From here on the position is only known again after a look at the flash.
        self.position = None;
        self.flash
            .write(offset, &record[..len])
            .map_err(StoreError::Flash)?;
        let mut back = [0u8; MAX_RECORD];
        self.flash
            .read(offset, &mut back[..len])
            .map_err(StoreError::Flash)?;
        if back[..len] != record[..len] {
            return Err(StoreError::Verify);
        }
        self.position = Some(Position {
            next: (slot + 1 < Self::slots()).then_some((sector, slot + 1)),
            current: sector,
            sequence: Some(sequence),
        });
        Ok(())
    }
}

/// The sequence number and payload of a valid record.
fn parse<const N: usize>(record: &[u8]) -> Option<(u32, [u8; N])> {
    let body = record.get(..8 + N)?;
    let crc = record.get(8 + N..OVERHEAD + N)?;
    if body[..4] != MAGIC || CRC.checksum(body).to_le_bytes() != crc {
        return None;
    }
    let sequence = u32::from_le_bytes([body[4], body[5], body[6], body[7]]);
    let mut payload = [0u8; N];
    payload.copy_from_slice(&body[8..]);
    Some((sequence, payload))
}

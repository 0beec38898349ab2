//! The input slot: the input under test, in a file mapping shared with the supervisor.
//!
//! The child copies every input into the slot before running it. When the child dies
//! (abort on the allocation cap, stack overflow, a panic), the mapping's file still
//! holds that input, and the supervisor saves it. Layout of the file:
//!
//! | offset | size | field |
//! |---|---|---|
//! | 0 | 8 | length of the input, little-endian `u64` |
//! | 8 | 8 | size of an allocation the cap refused while it ran (0: none) |
//! | 16 | ≤ [`crate::MAX_INPUT_LEN`] | the input |

use std::fs::OpenOptions;
use std::io;
use std::path::Path;
use std::sync::atomic::{AtomicPtr, Ordering};

use memmap2::MmapMut;

const HEADER: usize = 16;
/// The file's size, bytes.
pub const SLOT_LEN: usize = HEADER + crate::MAX_INPUT_LEN;

/// Where the refused-allocation field of the open slot lives, for the allocator
/// (which must not allocate to report).
static REFUSED_FIELD: AtomicPtr<u8> = AtomicPtr::new(std::ptr::null_mut());

/// The child's side: a writable mapping of the slot file.
pub struct InputSlot {
    map: MmapMut,
}

impl InputSlot {
    /// Creates (or empties) the slot file at `path` and maps it.
    pub fn create(path: &Path) -> io::Result<Self> {
        let file = OpenOptions::new()
            .read(true)
            .write(true)
            .create(true)
            .truncate(true)
            .open(path)?;
        file.set_len(SLOT_LEN as u64)?;
        // SAFETY: the file is this process's own slot; the supervisor reads it only
        // after this process has exited, so nobody changes it under the mapping.
        let mut map = unsafe { MmapMut::map_mut(&file)? };
        REFUSED_FIELD.store(map[8..16].as_mut_ptr(), Ordering::Release);
        Ok(Self { map })
    }

    /// Puts `input` (at most [`crate::MAX_INPUT_LEN`] bytes) in the slot.
    pub fn set(&mut self, input: &[u8]) {
        let n = input.len().min(crate::MAX_INPUT_LEN);
        self.map[0..8].copy_from_slice(&0u64.to_le_bytes());
        self.map[HEADER..HEADER + n].copy_from_slice(&input[..n]);
        self.map[0..8].copy_from_slice(&(n as u64).to_le_bytes());
    }
}

impl Drop for InputSlot {
    fn drop(&mut self) {
        REFUSED_FIELD.store(std::ptr::null_mut(), Ordering::Release);
    }
}

/// Notes in the open slot (if any) that the allocator refused `size` bytes. Does not
/// allocate.
pub(crate) fn note_allocation_refused(size: usize) {
    let p = REFUSED_FIELD.load(Ordering::Acquire);
    if !p.is_null() {
        let bytes = (size.max(1) as u64).to_le_bytes();
        // SAFETY: `p` points at 8 bytes inside the live mapping of the slot (cleared
        // before the mapping is dropped).
        unsafe { std::ptr::copy_nonoverlapping(bytes.as_ptr(), p, 8) };
    }
}

/// The supervisor's side: what a dead child's slot holds.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct SlotContents {
    /// The input that was under test.
    pub input: Vec<u8>,
    /// The allocation the cap refused, bytes, if one was.
    pub refused_allocation: Option<u64>,
}

/// Reads the slot file at `path`.
pub fn read(path: &Path) -> io::Result<SlotContents> {
    let bytes = std::fs::read(path)?;
    if bytes.len() < HEADER {
        return Err(io::Error::new(
            io::ErrorKind::InvalidData,
            format!("input slot {} is {} bytes", path.display(), bytes.len()),
        ));
    }
    let field = |at: usize| {
        let mut b = [0u8; 8];
        b.copy_from_slice(&bytes[at..at + 8]);
        u64::from_le_bytes(b)
    };
    let len = (field(0) as usize).min(bytes.len() - HEADER);
    let refused = field(8);
    Ok(SlotContents {
        input: bytes[HEADER..HEADER + len].to_vec(),
        refused_allocation: (refused != 0).then_some(refused),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_slot_file_holds_the_last_input_and_the_refused_size() {
        let dir = tempfile::tempdir().expect("a temporary folder");
        let path = dir.path().join("t.slot");
        let mut slot = InputSlot::create(&path).expect("slot");
        slot.set(b"first, longer input");
        slot.set(b"second");
        note_allocation_refused(12345);
        let contents = read(&path).expect("readable");
        assert_eq!(contents.input, b"second");
        assert_eq!(contents.refused_allocation, Some(12345));
        drop(slot);
        // With no slot open, a refusal is not noted anywhere (and does not crash).
        note_allocation_refused(1);
        assert_eq!(
            read(&path).expect("readable").refused_allocation,
            Some(12345)
        );
    }
}

//! A global allocator that counts live heap bytes and refuses to go past a cap.
//!
//! The fuzz runner installs [`CappedAllocator`] as its global allocator. An allocation
//! that would take the live heap past [`set_cap`] bytes fails (returns null), so the
//! process aborts with Rust's "memory allocation of N bytes failed" instead of eating
//! the machine's memory; the failed request is noted in the input slot first, so the
//! supervisor can say that the cap was hit. Unlike an address-space limit
//! (`ulimit -v`), the count does not depend on thread stacks or the mapped binary.

use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::atomic::{AtomicUsize, Ordering};

static LIVE: AtomicUsize = AtomicUsize::new(0);
static PEAK: AtomicUsize = AtomicUsize::new(0);
static CAP: AtomicUsize = AtomicUsize::new(usize::MAX);

/// The system allocator with a cap on live bytes (see the [module](self) docs).
pub struct CappedAllocator;

/// Sets the cap on live heap bytes (the default is no cap).
pub fn set_cap(bytes: usize) {
    CAP.store(bytes, Ordering::Relaxed);
}

/// Live heap bytes now.
pub fn live_bytes() -> usize {
    LIVE.load(Ordering::Relaxed)
}

/// Largest live heap seen, bytes.
pub fn peak_bytes() -> usize {
    PEAK.load(Ordering::Relaxed)
}

/// Books `size` more bytes; false (nothing booked) if that passes the cap.
fn reserve(size: usize) -> bool {
    let cap = CAP.load(Ordering::Relaxed);
    let before = LIVE.fetch_add(size, Ordering::Relaxed);
    let after = before.saturating_add(size);
    if after > cap {
        LIVE.fetch_sub(size, Ordering::Relaxed);
        crate::slot::note_allocation_refused(size);
        return false;
    }
    PEAK.fetch_max(after, Ordering::Relaxed);
    true
}

fn release(size: usize) {
    LIVE.fetch_sub(size, Ordering::Relaxed);
}

// SAFETY: every method forwards to `System` with the caller's layout and only adds
// bookkeeping; a refused allocation returns null, which `GlobalAlloc` allows.
unsafe impl GlobalAlloc for CappedAllocator {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        if !reserve(layout.size()) {
            return std::ptr::null_mut();
        }
        // SAFETY: forwarded with the caller's (non-zero-size) layout.
        let p = unsafe { System.alloc(layout) };
        if p.is_null() {
            release(layout.size());
        }
        p
    }

    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        if !reserve(layout.size()) {
            return std::ptr::null_mut();
        }
        // SAFETY: as in `alloc`.
        let p = unsafe { System.alloc_zeroed(layout) };
        if p.is_null() {
            release(layout.size());
        }
        p
    }

    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        // SAFETY: `ptr` was allocated by `System` with `layout` (through this type).
        unsafe { System.dealloc(ptr, layout) };
        release(layout.size());
    }

    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        let old = layout.size();
        if new_size > old && !reserve(new_size - old) {
            return std::ptr::null_mut();
        }
        // SAFETY: `ptr` was allocated by `System` with `layout`; the caller guarantees
        // `new_size` is valid for its alignment.
        let p = unsafe { System.realloc(ptr, layout, new_size) };
        if p.is_null() {
            if new_size > old {
                release(new_size - old);
            }
        } else if new_size < old {
            release(old - new_size);
        }
        p
    }
}

//! The calibration kept in the browser's `localStorage`, under
//! [`STORAGE_KEY`](crate::calibration_store::STORAGE_KEY). One `setItem` replaces the
//! whole text, so a reader never sees half a file; a page without storage (a private
//! window that refuses it, a full quota) gets the reason in the message.

use crate::calibration_store::{CalibrationStore, STORAGE_KEY};

/// `window.localStorage`.
pub(crate) struct LocalStorage;

fn storage() -> Result<web_sys::Storage, String> {
    web_sys::window()
        .ok_or("the page has no window")?
        .local_storage()
        .map_err(|_| "the browser refuses localStorage".to_string())?
        .ok_or_else(|| "the browser has no localStorage".to_string())
}

/// The most characters read back: a calibration file is about 1.5 kB, so anything much
/// longer is not one (and is not parsed).
const MAX_STORED_CHARS: usize = 64 * 1024;

impl CalibrationStore for LocalStorage {
    fn read(&self) -> Result<Option<String>, String> {
        let text = storage()?
            .get_item(STORAGE_KEY)
            .map_err(|_| "localStorage could not be read".to_string())?;
        match text {
            Some(t) if t.len() > MAX_STORED_CHARS => Err(format!(
                "{} bytes stored, more than a calibration ({MAX_STORED_CHARS} at most)",
                t.len()
            )),
            other => Ok(other),
        }
    }

    fn write(&mut self, text: &str) -> Result<(), String> {
        storage()?
            .set_item(STORAGE_KEY, text)
            .map_err(|_| "localStorage refused it (full, or not allowed)".to_string())
    }

    fn place(&self) -> String {
        format!("this browser's localStorage ({STORAGE_KEY})")
    }
}

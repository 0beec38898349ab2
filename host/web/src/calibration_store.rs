//! Where the page keeps the board's calibration between visits: the browser's
//! `localStorage` on the page (`web::local_storage`), anything that holds one text in
//! the tests. The text is the desktop's calibration file ([`Calibration::to_json`]), so a
//! file the desktop's calibration mode saved can be pasted in and the other way round.
//!
//! What comes back is untrusted (another version of the page, or a person, may have
//! written it): [`load`] parses and validates it with [`Calibration::from_json`], and a
//! bad one gives the defaults and the reason, never a panic or a NaN pose.

use space_foosball::input::calibration::{Calibration, CalibrationError};

/// The `localStorage` key the page keeps the calibration under.
pub const STORAGE_KEY: &str = "space-foosball-calibration";

/// One stored text: the calibration file's JSON.
pub trait CalibrationStore {
    /// The stored text, if any; `Err` names why it could not be read.
    fn read(&self) -> Result<Option<String>, String>;
    /// Replaces the stored text (whole: a reader sees the old text or the new one).
    fn write(&mut self, text: &str) -> Result<(), String>;
    /// Where the text is kept, for messages (`"this browser's localStorage"`).
    fn place(&self) -> String;
}

/// The stored calibration: `Ok(None)` when nothing is stored, `Err` with the reason when
/// what is stored cannot be used (unreadable, not the file's format, or a map that is
/// not invertible or not finite).
pub fn load(store: &dyn CalibrationStore) -> Result<Option<Calibration>, CalibrationError> {
    let place = store.place();
    let text = store
        .read()
        .map_err(|message| CalibrationError::Malformed {
            path: place.clone(),
            message,
        })?;
    text.map(|t| Calibration::from_json(&t, &place)).transpose()
}

/// Saves `calibration` into `store`, refusing an invalid one before anything is written;
/// returns what the screen says.
pub fn save(store: &mut dyn CalibrationStore, calibration: &Calibration) -> String {
    if let Err(e) = calibration.validate() {
        return format!("CALIBRATION NOT SAVED: {e}");
    }
    match store.write(&calibration.to_json()) {
        Ok(()) => format!("CALIBRATION SAVED IN {}", store.place().to_uppercase()),
        Err(e) => format!("CALIBRATION NOT SAVED: {e}"),
    }
}

#[cfg(test)]
pub(crate) mod memory {
    use super::CalibrationStore;

    /// A store in memory; `fail` makes writes fail as a full `localStorage` does.
    #[derive(Debug, Default, Clone)]
    pub struct MemoryStore {
        pub text: std::rc::Rc<std::cell::RefCell<Option<String>>>,
        pub fail: bool,
    }

    impl CalibrationStore for MemoryStore {
        fn read(&self) -> Result<Option<String>, String> {
            Ok(self.text.borrow().clone())
        }
        fn write(&mut self, text: &str) -> Result<(), String> {
            if self.fail {
                return Err("the quota is exceeded".into());
            }
            *self.text.borrow_mut() = Some(text.to_string());
            Ok(())
        }
        fn place(&self) -> String {
            "test store".into()
        }
    }
}

#[cfg(test)]
mod tests {
    use super::memory::MemoryStore;
    use super::*;

    #[test]
    fn a_saved_calibration_loads_back_and_a_bad_one_names_the_problem() {
        let mut store = MemoryStore::default();
        assert!(load(&store).unwrap().is_none());
        let mut c = Calibration::default();
        c.paddles[3].matrix[0][0] *= 1.05;
        assert_eq!(save(&mut store, &c), "CALIBRATION SAVED IN TEST STORE");
        assert_eq!(load(&store).unwrap(), Some(c));
        // Not the file's format, and a map that cannot be inverted.
        *store.text.borrow_mut() = Some("{\"paddles\": 3}".into());
        let e = load(&store).unwrap_err().to_string();
        assert!(e.contains("test store"), "{e}");
        let mut singular = Calibration::default();
        singular.paddles[1].matrix = [[1.0, 2.0], [2.0, 4.0]];
        *store.text.borrow_mut() = Some(singular.to_json());
        assert!(load(&store).is_err());
        // An invalid calibration is never written; a failing store says why.
        let before = store.text.borrow().clone();
        assert!(save(&mut store, &singular).starts_with("CALIBRATION NOT SAVED"));
        assert_eq!(*store.text.borrow(), before);
        store.fail = true;
        assert!(save(&mut store, &c).contains("quota"), "{c:?}");
    }
}

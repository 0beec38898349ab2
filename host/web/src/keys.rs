//! The page's keys: physical key codes (layout independent, `W` is where US keyboards
//! have W) → the emulated board's controls, as on the desktop.

use crate::keyboard::Key;
use winit::keyboard::KeyCode;

/// The emulated board's control for a physical key, if any.
pub fn map_key(code: KeyCode) -> Option<Key> {
    Some(match code {
        KeyCode::Digit1 => Key::Rod(0),
        KeyCode::Digit2 => Key::Rod(1),
        KeyCode::Digit3 => Key::Rod(2),
        KeyCode::Digit4 => Key::Rod(3),
        KeyCode::KeyW | KeyCode::ArrowUp => Key::SlideAway,
        KeyCode::KeyS | KeyCode::ArrowDown => Key::SlideNear,
        KeyCode::KeyD | KeyCode::ArrowRight => Key::SpinForward,
        KeyCode::KeyA | KeyCode::ArrowLeft => Key::SpinBack,
        KeyCode::Space => Key::Kick,
        KeyCode::Enter | KeyCode::NumpadEnter => Key::Push,
        KeyCode::Tab => Key::SwitchTeam,
        _ => return None,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_desktop_keys_map_to_the_same_controls() {
        assert_eq!(map_key(KeyCode::Digit3), Some(Key::Rod(2)));
        assert_eq!(map_key(KeyCode::ArrowUp), Some(Key::SlideAway));
        assert_eq!(map_key(KeyCode::Space), Some(Key::Kick));
        assert_eq!(map_key(KeyCode::Enter), Some(Key::Push));
        assert_eq!(map_key(KeyCode::KeyQ), None);
    }
}

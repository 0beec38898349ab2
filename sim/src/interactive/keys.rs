//! Bytes typed on a terminal (or piped in) → the keys of the game's key map.
//!
//! Plain characters are keys as they are: `1`–`4`, `w`/`s`, `a`/`d` (either case),
//! space, Enter (`\r` or `\n`), Tab, `q`; the arrow keys arrive as the escape sequences
//! `ESC [ A` … `ESC [ D` (also `ESC O A` …). Ctrl-C and Ctrl-D quit too. Anything else
//! is ignored, including the rest of unknown escape sequences.

/// A key of the interactive board, as the game's keyboard map names them.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Key {
    /// Choose the team's rod `n` (0-based, from its own goal: `1` → 0).
    Rod(usize),
    /// Slide the rod away from the player (`W`, `↑`).
    SlideAway,
    /// Slide the rod towards the player (`S`, `↓`).
    SlideNear,
    /// Spin forward, the feet towards the opponent's goal (`D`, `→`).
    SpinForward,
    /// Spin backward (`A`, `←`).
    SpinBack,
    /// Kick: one full turn forward (`Space`).
    Kick,
    /// Push the rod to its far stop and back (`Enter`).
    Push,
    /// Play the other team (`Tab`).
    SwitchTeam,
    /// Stop the server (`q`, Ctrl-C, Ctrl-D).
    Quit,
}

/// Where the decoder is inside an escape sequence.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
enum State {
    #[default]
    Plain,
    /// After `ESC`.
    Escape,
    /// After `ESC [` or `ESC O`: parameters until a final byte.
    Sequence,
}

/// Turns bytes into [`Key`]s, keeping the state of an escape sequence split across
/// reads.
#[derive(Debug, Clone, Default)]
pub struct KeyDecoder {
    state: State,
}

impl KeyDecoder {
    /// A decoder outside any escape sequence.
    pub fn new() -> Self {
        Self::default()
    }

    /// The key `byte` completes, if any.
    pub fn feed(&mut self, byte: u8) -> Option<Key> {
        match self.state {
            State::Plain => {
                if byte == 0x1b {
                    self.state = State::Escape;
                    return None;
                }
                plain_key(byte)
            }
            State::Escape => {
                self.state = if matches!(byte, b'[' | b'O') {
                    State::Sequence
                } else {
                    State::Plain
                };
                None
            }
            State::Sequence => {
                // Parameter and intermediate bytes (0x20–0x3f) continue the sequence;
                // a final byte (0x40–0x7e) ends it; anything else aborts it.
                if (0x20..=0x3f).contains(&byte) {
                    return None;
                }
                self.state = State::Plain;
                match byte {
                    b'A' => Some(Key::SlideAway),
                    b'B' => Some(Key::SlideNear),
                    b'C' => Some(Key::SpinForward),
                    b'D' => Some(Key::SpinBack),
                    _ => None,
                }
            }
        }
    }

    /// Every key in `bytes`, in order.
    pub fn feed_all(&mut self, bytes: &[u8]) -> Vec<Key> {
        bytes.iter().filter_map(|&b| self.feed(b)).collect()
    }
}

fn plain_key(byte: u8) -> Option<Key> {
    Some(match byte.to_ascii_lowercase() {
        b @ b'1'..=b'4' => Key::Rod(usize::from(b - b'1')),
        b'w' => Key::SlideAway,
        b's' => Key::SlideNear,
        b'd' => Key::SpinForward,
        b'a' => Key::SpinBack,
        b' ' => Key::Kick,
        b'\r' | b'\n' => Key::Push,
        b'\t' => Key::SwitchTeam,
        b'q' | 0x03 | 0x04 => Key::Quit,
        _ => return None,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn plain_characters_are_the_game_keys() {
        let mut d = KeyDecoder::new();
        assert_eq!(
            d.feed_all(b"1234wWsSaAdD \r\n\tq\x03\x04"),
            [
                Key::Rod(0),
                Key::Rod(1),
                Key::Rod(2),
                Key::Rod(3),
                Key::SlideAway,
                Key::SlideAway,
                Key::SlideNear,
                Key::SlideNear,
                Key::SpinBack,
                Key::SpinBack,
                Key::SpinForward,
                Key::SpinForward,
                Key::Kick,
                Key::Push,
                Key::Push,
                Key::SwitchTeam,
                Key::Quit,
                Key::Quit,
                Key::Quit,
            ]
        );
        assert!(d.feed_all(b"05xz!\x7f\x00\xff").is_empty());
    }

    #[test]
    fn arrow_sequences_are_slide_and_spin_even_split_across_reads() {
        let mut d = KeyDecoder::new();
        assert_eq!(
            d.feed_all(b"\x1b[A\x1b[B\x1bOC\x1b[D"),
            [
                Key::SlideAway,
                Key::SlideNear,
                Key::SpinForward,
                Key::SpinBack
            ]
        );
        assert!(d.feed_all(b"\x1b").is_empty());
        assert!(d.feed_all(b"[").is_empty());
        assert_eq!(d.feed_all(b"A"), [Key::SlideAway]);
        // Unknown sequences (F5) are swallowed whole; a modified arrow is the arrow.
        assert_eq!(d.feed_all(b"\x1b[15~w"), [Key::SlideAway]);
        assert_eq!(
            d.feed_all(b"\x1b[1;5Cs"),
            [Key::SpinForward, Key::SlideNear]
        );
        // A lone escape does not eat the next plain key's meaning beyond itself.
        assert_eq!(d.feed_all(b"\x1bxw"), [Key::SlideAway]);
    }
}

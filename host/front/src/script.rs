//! Scripted key presses for unattended runs (`play --demo-input SCRIPT`): a
//! comma-separated list of `SECONDS:KEY` (press and release 0.2 s later),
//! `SECONDS:KEY+` (press) and `SECONDS:KEY-` (release), seconds since the window's
//! first frame showed. A frame hands out at most one press or release per key, so a
//! slow frame never merges a tap's press and release. Keys: `enter`, `space`, `tab`, `esc`, `up`, `down`, `left`, `right`, a letter
//! `a`–`z` or a digit `0`–`9`.
//!
//! `--demo-input start` is the built-in script that leaves the attract screen and starts
//! a match (Home played from the keyboard, against the computer), then slides and kicks:
//! `1.0:enter,2.0:enter,2.6:w+,2.9:w-,3.2:space,3.8:s+,4.1:s-,4.4:space,4.8:w+,5.2:w-`
//! (the goalkeeper rod ends pushed away from its player).

use winit::keyboard::KeyCode;

/// The built-in script `start`.
pub const START: &str =
    "1.0:enter,2.0:enter,2.6:w+,2.9:w-,3.2:space,3.8:s+,4.1:s-,4.4:space,4.8:w+,5.2:w-";

/// Seconds between press and release of a `SECONDS:KEY` entry.
pub const TAP_S: f64 = 0.2;

/// A key press or release at a time.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ScriptedKey {
    /// Seconds since the window's first frame.
    pub at_s: f64,
    /// The key.
    pub key: KeyCode,
    /// Press (true) or release.
    pub pressed: bool,
}

/// A parsed script, consumed in time order.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Script {
    keys: Vec<ScriptedKey>,
    next: usize,
}

fn key_code(name: &str) -> Option<KeyCode> {
    use KeyCode::*;
    const LETTERS: [KeyCode; 26] = [
        KeyA, KeyB, KeyC, KeyD, KeyE, KeyF, KeyG, KeyH, KeyI, KeyJ, KeyK, KeyL, KeyM, KeyN, KeyO,
        KeyP, KeyQ, KeyR, KeyS, KeyT, KeyU, KeyV, KeyW, KeyX, KeyY, KeyZ,
    ];
    const DIGITS: [KeyCode; 10] = [
        Digit0, Digit1, Digit2, Digit3, Digit4, Digit5, Digit6, Digit7, Digit8, Digit9,
    ];
    Some(match name {
        "enter" => Enter,
        "space" => Space,
        "tab" => Tab,
        "esc" => Escape,
        "up" => ArrowUp,
        "down" => ArrowDown,
        "left" => ArrowLeft,
        "right" => ArrowRight,
        _ => {
            let mut chars = name.chars();
            let (Some(c), None) = (chars.next(), chars.next()) else {
                return None;
            };
            match c {
                'a'..='z' => LETTERS[(c as u8 - b'a') as usize],
                '0'..='9' => DIGITS[(c as u8 - b'0') as usize],
                _ => return None,
            }
        }
    })
}

impl std::str::FromStr for Script {
    type Err = String;

    fn from_str(text: &str) -> Result<Self, String> {
        let text = if text == "start" { START } else { text };
        let mut keys = Vec::new();
        for item in text.split(',').map(str::trim).filter(|s| !s.is_empty()) {
            let (t, key) = item
                .split_once(':')
                .ok_or_else(|| format!("{item:?}: expected SECONDS:KEY"))?;
            let at_s: f64 = t
                .trim()
                .parse()
                .ok()
                .filter(|v: &f64| v.is_finite() && *v >= 0.0)
                .ok_or_else(|| format!("{item:?}: {t:?} is not a time in seconds"))?;
            let key = key.trim().to_ascii_lowercase();
            let (name, presses): (&str, &[(f64, bool)]) = if let Some(n) = key.strip_suffix('+') {
                (n, &[(0.0, true)])
            } else if let Some(n) = key.strip_suffix('-') {
                (n, &[(0.0, false)])
            } else {
                (key.as_str(), &[(0.0, true), (TAP_S, false)])
            };
            let code = key_code(name).ok_or_else(|| format!("{item:?}: unknown key {name:?}"))?;
            keys.extend(presses.iter().map(|&(dt, pressed)| ScriptedKey {
                at_s: at_s + dt,
                key: code,
                pressed,
            }));
        }
        keys.sort_by(|a, b| a.at_s.total_cmp(&b.at_s));
        Ok(Script { keys, next: 0 })
    }
}

impl Script {
    /// The presses and releases due by `t_s` not handed out yet, in order, up to (not
    /// including) a second one for the same key: that one waits for the next frame.
    pub fn due(&mut self, t_s: f64) -> Vec<(Option<KeyCode>, bool)> {
        let mut out = Vec::new();
        while let Some(k) = self.keys.get(self.next).filter(|k| k.at_s <= t_s) {
            if out.iter().any(|&(key, _)| key == Some(k.key)) {
                break;
            }
            out.push((Some(k.key), k.pressed));
            self.next += 1;
        }
        out
    }

    #[cfg(test)]
    /// Whether the script has no keys.
    pub fn is_empty(&self) -> bool {
        self.keys.is_empty()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn scripts_parse_and_play_in_time_order() {
        let mut s: Script = "1.5:w-, 0.5:enter, 1:w+".parse().unwrap();
        assert!(s.due(0.4).is_empty());
        assert_eq!(s.due(0.6), vec![(Some(KeyCode::Enter), true)]);
        // A late frame: W's press now, its release on the next frame.
        assert_eq!(
            s.due(2.0),
            vec![(Some(KeyCode::Enter), false), (Some(KeyCode::KeyW), true)]
        );
        assert_eq!(s.due(2.0), vec![(Some(KeyCode::KeyW), false)]);
        assert!(s.due(9.0).is_empty());
        let start: Script = "start".parse().unwrap();
        assert!(!start.is_empty());
    }

    #[test]
    fn bad_scripts_say_what_is_wrong() {
        assert!("1.0".parse::<Script>().unwrap_err().contains("SECONDS:KEY"));
        assert!("x:enter"
            .parse::<Script>()
            .unwrap_err()
            .contains("not a time"));
        assert!("-1:enter"
            .parse::<Script>()
            .unwrap_err()
            .contains("not a time"));
        assert!("1:hyperspace"
            .parse::<Script>()
            .unwrap_err()
            .contains("unknown key"));
    }
}

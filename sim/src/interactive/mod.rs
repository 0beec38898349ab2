//! `sim serve --interactive`: a person plays the emulated board from the keyboard of
//! the terminal `sim serve` runs in, with the game's own key map.
//!
//! | key | does |
//! |---|---|
//! | `1` `2` `3` `4` | choose your team's rod, from your goal forward |
//! | `W` `S`, `↑` `↓` | slide the rod (away from you / towards you) |
//! | `A` `D`, `←` `→` | spin the rod (back / forward) |
//! | `Space` | kick: one full turn towards the opponent's goal |
//! | `Enter` | push the rod to its far stop (start, confirm); it returns 0.25 s after the last `Enter` |
//! | `Tab` | play the other team |
//! | `q`, Ctrl-C | stop the server |
//!
//! On a terminal the keys are read one at a time as they are typed ([`keys`]); when
//! standard input is not a terminal (a pipe, a file) the same characters are read as
//! they come, so a test or a script can type: `\n` is `Enter`, `\t` is `Tab`, a space
//! is `Space`. At the end of such input the rods hold their poses and the server goes
//! on. Key presses become rod targets ([`hands`]), which the emulated rods follow at a
//! hand's speed, so the sensors see continuous motion.

pub mod hands;
pub mod keys;
mod terminal;

use crate::motion::live::LiveHandle;
use hands::HandControls;
use keys::{Key, KeyDecoder};
use std::io::{self, IsTerminal, Read, Write};
use std::os::fd::AsRawFd;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc;
use std::sync::Arc;
use std::time::{Duration, Instant};

/// The one-line help printed at start.
pub const HELP: &str =
    "keys: 1-4 rod, W/S or \u{2191}/\u{2193} slide, A/D or \u{2190}/\u{2192} spin, \
                        Space kick, Enter push, Tab other team, q quit";

/// The running keyboard: restores the terminal when dropped.
pub struct Interactive {
    _terminal: Option<terminal::RawTerminal>,
}

/// Starts reading keys from this process's standard input (the terminal in
/// key-at-a-time mode, when it is one) and driving the rods of `handle`; `Quit` sets
/// `stop`. Notices (the help line, the rod driven) go to standard error.
pub fn start(handle: LiveHandle, stop: Arc<AtomicBool>) -> io::Result<Interactive> {
    let stdin = io::stdin();
    let terminal = if stdin.is_terminal() {
        Some(terminal::RawTerminal::enable(stdin.as_raw_fd())?)
    } else {
        None
    };
    start_with(stdin, handle, stop, |line| {
        // A closed standard error is no reason to stop playing.
        let _ = writeln!(io::stderr(), "sim serve: {line}");
    })?;
    Ok(Interactive {
        _terminal: terminal,
    })
}

/// [`start`] reading keys from `input` and sending notices to `notice`.
pub fn start_with(
    mut input: impl Read + Send + 'static,
    handle: LiveHandle,
    stop: Arc<AtomicBool>,
    notice: impl Fn(&str) + Send + 'static,
) -> io::Result<()> {
    let (keys_tx, keys_rx) = mpsc::channel();
    let reader_stop = Arc::clone(&stop);
    std::thread::Builder::new()
        .name("sim-keys".into())
        .spawn(move || {
            let mut decoder = KeyDecoder::new();
            let mut bytes = [0u8; 256];
            loop {
                let n = match input.read(&mut bytes) {
                    Ok(0) => return,
                    Ok(n) => n,
                    Err(e) if e.kind() == io::ErrorKind::Interrupted => continue,
                    Err(_) => return,
                };
                for key in decoder.feed_all(&bytes[..n]) {
                    if key == Key::Quit {
                        reader_stop.store(true, Ordering::Relaxed);
                        return;
                    }
                    if keys_tx.send(key).is_err() {
                        return;
                    }
                }
            }
        })?;
    std::thread::Builder::new()
        .name("sim-hands".into())
        .spawn(move || {
            let mut controls = HandControls::new(handle);
            notice(HELP);
            notice(&format!("keys drive {}", controls.describe()));
            let mut input_open = true;
            while !stop.load(Ordering::Relaxed) {
                let now = Instant::now();
                let wait = controls
                    .next_deadline()
                    .map_or(Duration::from_millis(100), |at| {
                        at.saturating_duration_since(now)
                    });
                if !input_open {
                    if controls.next_deadline().is_none() {
                        return;
                    }
                    std::thread::sleep(wait);
                } else {
                    match keys_rx.recv_timeout(wait) {
                        Ok(key) => {
                            if let Some(line) = controls.key(key, Instant::now()) {
                                notice(&format!("keys drive {line}"));
                            }
                        }
                        Err(mpsc::RecvTimeoutError::Timeout) => {}
                        Err(mpsc::RecvTimeoutError::Disconnected) => {
                            input_open = false;
                            if !stop.load(Ordering::Relaxed) {
                                notice("end of input; the rods hold their poses");
                            }
                        }
                    }
                }
                controls.tick(Instant::now());
            }
        })?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::hands::SLIDE_STEP_M;
    use super::*;
    use std::sync::Mutex;

    #[test]
    fn piped_characters_drive_the_rods_and_q_stops() {
        let handle = LiveHandle::default();
        let stop = Arc::new(AtomicBool::new(false));
        let lines = Arc::new(Mutex::new(Vec::<String>::new()));
        let seen = Arc::clone(&lines);
        start_with(
            io::Cursor::new(b"2ww\t1s".to_vec()),
            handle.clone(),
            Arc::clone(&stop),
            move |line| seen.lock().unwrap().push(line.to_owned()),
        )
        .unwrap();
        let started = Instant::now();
        while lines.lock().unwrap().len() < 5 {
            assert!(started.elapsed() < Duration::from_secs(10), "{lines:?}");
            std::thread::sleep(Duration::from_millis(5));
        }
        let targets = handle.targets();
        assert!((targets[1].axial_m - 2.0 * SLIDE_STEP_M).abs() < 1e-12);
        assert!((targets[7].axial_m + SLIDE_STEP_M).abs() < 1e-12);
        let lines = lines.lock().unwrap().clone();
        assert_eq!(lines[0], HELP);
        assert_eq!(lines[1], "keys drive Home rod 1 (goalkeeper, port 0)");
        assert_eq!(lines[2], "keys drive Home rod 2 (defence, port 1)");
        assert_eq!(lines[3], "keys drive Away rod 1 (goalkeeper, port 7)");
        assert_eq!(lines[4], "end of input; the rods hold their poses");
        assert!(!stop.load(Ordering::Relaxed));

        // `q` stops the server, and nothing after it is read.
        let handle = LiveHandle::default();
        start_with(
            io::Cursor::new(b"qw".to_vec()),
            handle.clone(),
            Arc::clone(&stop),
            |_| {},
        )
        .unwrap();
        while !stop.load(Ordering::Relaxed) {
            assert!(started.elapsed() < Duration::from_secs(10));
            std::thread::sleep(Duration::from_millis(5));
        }
        std::thread::sleep(Duration::from_millis(20));
        assert_eq!(handle.targets()[0].axial_m, 0.0);
    }
}

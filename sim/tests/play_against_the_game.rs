//! A person's game against a separate emulator process, end to end: `sim serve
//! --interactive` gets keys on its standard input as a player would type them, and the
//! windowed game `space-foosball play --board socket:PATH` plays on that board. The
//! first `Enter` pushes a rod (attract screen → character selection), the second starts
//! the match (Home played by a person, since Home's rod moved), then `W W W` slides
//! Home's goalkeeper rod 75 mm away from its player. The JSON line the game prints on
//! exit must say a match is being played, Home by the player, and Home's goalkeeper rod
//! slid.
//!
//! The game's headless mode cannot play against a socket board (it plays computer
//! against computer, or a motion script on its built-in board, and has no title
//! screen), so this is the windowed game, which needs a display and the game's binary:
//! `scripts/test-all` runs it under `xvfb-run` with `SPACE_FOOSBALL_BIN` set to the
//! binary its `cargo test` built and `SPACE_FOOSBALL_REQUIRE_DISPLAY=1`, so there it
//! fails instead of skipping. By hand:
//!
//! ```sh
//! cargo build -p space-foosball-app
//! SPACE_FOOSBALL_BIN=target/debug/space-foosball xvfb-run -a \
//!     cargo test -p foosball-sim --test play_against_the_game -- --nocapture
//! ```

use std::io::{BufRead, BufReader, Write};
use std::path::PathBuf;
use std::process::{Child, Command, Stdio};
use std::sync::mpsc;
use std::time::{Duration, Instant};

/// Home's goalkeeper rod in the table's rod order (the standard table, from the Home
/// goal), and its slide after `W W W`: three 25 mm steps (`sim`'s key map).
const HOME_KEEPER: usize = 0;
const SLID_M: f64 = 0.075;
/// How long the game runs before it prints its state and quits, s.
const GAME_S: &str = "16";

/// The game's binary and a display, or why the test cannot run here.
fn game_binary() -> Result<PathBuf, String> {
    let display = ["DISPLAY", "WAYLAND_DISPLAY"]
        .iter()
        .any(|v| std::env::var(v).is_ok_and(|s| !s.trim().is_empty()));
    if !display {
        return Err("no display (DISPLAY and WAYLAND_DISPLAY unset): run under xvfb-run".into());
    }
    let bin = std::env::var_os("SPACE_FOOSBALL_BIN")
        .map(PathBuf::from)
        .ok_or("SPACE_FOOSBALL_BIN is not set to the space-foosball binary")?;
    if !bin.is_file() {
        return Err(format!(
            "SPACE_FOOSBALL_BIN={} is not a file",
            bin.display()
        ));
    }
    Ok(bin)
}

/// Kills the child when the test ends, whatever happened, unless taken out before.
struct Reaped(Option<Child>);

impl Reaped {
    fn child(&mut self) -> &mut Child {
        self.0.as_mut().expect("child not taken")
    }
}

impl Drop for Reaped {
    fn drop(&mut self) {
        if let Some(child) = self.0.as_mut() {
            let _ = child.kill();
            let _ = child.wait();
        }
    }
}

/// The number or array after `"key": ` in the game's one-line JSON.
fn field<'a>(json: &'a str, key: &str) -> &'a str {
    let k = format!("\"{key}\": ");
    let start = json
        .find(&k)
        .unwrap_or_else(|| panic!("no {key} in {json}"))
        + k.len();
    let rest = &json[start..];
    let end = if rest.starts_with('[') {
        // Arrays of arrays: up to the bracket that closes this one.
        let mut depth = 0;
        rest.char_indices()
            .find_map(|(i, c)| {
                match c {
                    '[' => depth += 1,
                    ']' => depth -= 1,
                    _ => {}
                }
                (depth == 0).then_some(i + 1)
            })
            .unwrap_or(rest.len())
    } else {
        rest.find([',', '}']).unwrap_or(rest.len())
    };
    &rest[..end]
}

fn numbers(s: &str) -> Vec<f64> {
    s.split(['[', ']', ','])
        .map(str::trim)
        .filter(|v| !v.is_empty())
        .map(|v| v.parse().unwrap())
        .collect()
}

#[test]
fn a_player_typing_into_sim_serve_starts_a_match_and_moves_a_rod() {
    let bin = match game_binary() {
        Ok(bin) => bin,
        Err(why) => {
            assert!(
                std::env::var_os("SPACE_FOOSBALL_REQUIRE_DISPLAY").is_none(),
                "SPACE_FOOSBALL_REQUIRE_DISPLAY is set, but: {why}"
            );
            eprintln!("skipping the game against sim serve: {why}");
            return;
        }
    };
    let dir = tempfile::tempdir().unwrap();
    let socket = dir.path().join("board.sock");
    let mut sim = Reaped(Some(
        Command::new(env!("CARGO_BIN_EXE_sim"))
            .args(["serve", "--interactive", "--verbose", "--socket"])
            .arg(&socket)
            .stdin(Stdio::piped())
            .stdout(Stdio::null())
            .stderr(Stdio::piped())
            .spawn()
            .expect("start sim serve"),
    ));
    let (tx, sim_lines) = mpsc::channel();
    let stderr = sim.child().stderr.take().unwrap();
    std::thread::spawn(move || {
        for line in BufReader::new(stderr).lines().map_while(Result::ok) {
            let _ = tx.send(line);
        }
    });
    let mut game = Reaped(Some(
        Command::new(&bin)
            .arg("play")
            .arg("--board")
            .arg(format!("socket:{}", socket.display()))
            .args([
                "--width",
                "320",
                "--height",
                "180",
                "--exit-after-s",
                GAME_S,
            ])
            .arg("--calibration")
            .arg(dir.path().join("cal.json"))
            .env("SPACE_FOOSBALL_AUDIO", "off")
            .env("XDG_RUNTIME_DIR", dir.path())
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .expect("start space-foosball"),
    ));

    // The game connects to the board; then a person types.
    let deadline = Instant::now() + Duration::from_secs(60);
    let mut seen = Vec::new();
    while !seen.iter().any(|l: &String| l.contains("client connected")) {
        let left = deadline.saturating_duration_since(Instant::now());
        match sim_lines.recv_timeout(left) {
            Ok(line) => seen.push(line),
            Err(_) => panic!("the game never connected to sim serve: {seen:?}"),
        }
    }
    let keys = sim.child().stdin.as_mut().unwrap();
    let mut type_keys = |text: &str, then: Duration| {
        keys.write_all(text.as_bytes()).unwrap();
        keys.flush().unwrap();
        std::thread::sleep(then);
    };
    type_keys("", Duration::from_millis(1500)); // the attract screen settles
    type_keys("\n", Duration::from_millis(2000)); // push: character selection
    type_keys("\n", Duration::from_millis(2000)); // push: the match starts
    type_keys("www", Duration::ZERO); // Home's goalkeeper slides away

    let out = game
        .0
        .take()
        .unwrap()
        .wait_with_output()
        .expect("wait for space-foosball");
    let stdout = String::from_utf8_lossy(&out.stdout);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        out.status.success(),
        "space-foosball failed: {stderr}\n(no adapter? apt-get install mesa-vulkan-drivers)"
    );
    let json = stdout.lines().last().unwrap_or_default();
    eprintln!("{json}");
    assert_eq!(
        field(json, "stage"),
        "\"playing\"",
        "left the title screen: {json}"
    );
    let screen = field(json, "screen");
    assert!(
        screen == "\"match\"" || screen == "\"goal-ceremony\"",
        "{json}"
    );
    assert_eq!(
        field(json, "controllers"),
        "[\"player\", \"computer\"]",
        "Home is played by the person typing: {json}"
    );
    let rods = numbers(field(json, "rods"));
    let slide = rods[2 * HOME_KEEPER];
    // The game reads the slide through the sensor counts and its calibration: within
    // 10 % of the keys' 75 mm.
    assert!(
        (slide - SLID_M).abs() < 0.1 * SLID_M,
        "Home goalkeeper slide {slide} m, expected {SLID_M} m: {json}"
    );
}

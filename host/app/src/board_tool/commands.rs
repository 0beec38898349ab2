//! The diagnostics and settings commands of `space-foosball board`: each opens the
//! board ([`target::open_feature`]), asks it through its Feature reports and prints
//! the answer ([`show`]).

use super::keys::Key;
use super::show;
use super::target::{self, FeatureTarget};
use crate::window::board::BoardChoice;
use anyhow::{anyhow, bail, Context, Result};
use board_link::BoardError;
use foosball_protocol::{BoardSettings, PADDLES};
use serde_json::json;
use std::io::{self, Write};
use std::time::{Duration, Instant};

/// How long the board may take to leave the bus after `EnterBootloader` (the
/// firmware waits 20 ms, then restarts).
const BOOTLOADER_LEAVE_TIMEOUT: Duration = Duration::from_secs(3);

/// Prints `text`, or `json` as one line.
fn print(
    json_out: bool,
    text: impl FnOnce() -> String,
    json: impl FnOnce() -> serde_json::Value,
) -> Result<()> {
    let mut out = io::stdout().lock();
    let written = if json_out {
        writeln!(out, "{}", json())
    } else {
        write!(out, "{}", text())
    };
    match written.and_then(|()| out.flush()) {
        // `… | head`: a closed stdout is not an error.
        Err(e) if e.kind() != io::ErrorKind::BrokenPipe => Err(e).context("writing the output"),
        _ => Ok(()),
    }
}

/// The settings of the board `name` of `target`.
fn read_settings(target: &mut FeatureTarget, name: &str) -> Result<BoardSettings> {
    target
        .board
        .settings()
        .with_context(|| format!("reading the settings of {name}"))
}

/// `board info`.
pub fn info(choice: &BoardChoice, serial: Option<&str>, json: bool) -> Result<()> {
    let mut target = target::open_feature(choice, serial)?;
    let name = target.board.name();
    let info = target
        .board
        .device_info()
        .with_context(|| format!("reading the device info of {name}"))?;
    let serial = target.serial_number.as_deref();
    print(
        json,
        || show::info_text(&name, serial, &info),
        || show::info_json(&name, serial, &info),
    )
}

/// `board ports`.
pub fn ports(choice: &BoardChoice, serial: Option<&str>, json: bool) -> Result<()> {
    let mut target = target::open_feature(choice, serial)?;
    let name = target.board.name();
    let settings = read_settings(&mut target, &name)?;
    let diags = (0..PADDLES as u8)
        .map(|port| {
            target
                .board
                .port_diagnostics(port)
                .with_context(|| format!("reading port {port}'s diagnostics from {name}"))
        })
        .collect::<Result<Vec<_>>>()?;
    print(
        json,
        || show::ports_text(&name, &diags, &settings),
        || show::ports_json(&name, &diags, &settings),
    )
}

/// `board settings`.
pub fn settings(choice: &BoardChoice, serial: Option<&str>, json: bool) -> Result<()> {
    let mut target = target::open_feature(choice, serial)?;
    let name = target.board.name();
    let settings = read_settings(&mut target, &name)?;
    print(
        json,
        || show::settings_text(&name, &settings),
        || show::settings_json(&name, &settings),
    )
}

/// `board set KEY VALUE`: the key and value are checked before the board is opened;
/// then read, modify, write, read back.
pub fn set(
    choice: &BoardChoice,
    serial: Option<&str>,
    key: &str,
    value: &str,
    json: bool,
) -> Result<()> {
    let key: Key = key.parse().map_err(|e: String| anyhow!(e))?;
    let new = key.parse_value(value).map_err(|e| anyhow!(e))?;
    let mut target = target::open_feature(choice, serial)?;
    let name = target.board.name();
    let before = read_settings(&mut target, &name)?;
    let wanted = key.with(&before, new);
    target
        .board
        .set_settings(&wanted)
        .with_context(|| format!("writing {key} = {new} to {name}"))?;
    let after = target
        .board
        .settings()
        .with_context(|| format!("reading the settings of {name} back"))?;
    let old = key.get(&before);
    let read_back = key.get(&after);
    if after != wanted {
        bail!("{name} did not keep the settings written: {key} wrote {new}, read back {read_back}");
    }
    let lasts = if target.emulated {
        "the built-in emulated board keeps it until this command ends"
    } else {
        "the board keeps it in flash"
    };
    print(
        json,
        || format!("{name}: {key} {old} -> {read_back} (read back; {lasts})\n"),
        || {
            json!({
                "board": name,
                "key": key.to_string(),
                "old": old.to_json(),
                "new": new.to_json(),
                "read_back": read_back.to_json(),
                "settings": show::settings_ports_json(&after),
            })
        },
    )
}

/// `board bootloader`: sends `EnterBootloader` and waits for the board to leave the
/// bus.
pub fn bootloader(choice: &BoardChoice, serial: Option<&str>, json: bool) -> Result<()> {
    let FeatureTarget {
        mut board,
        serial_number,
        emulated,
    } = target::open_feature(choice, serial)?;
    let name = board.name();
    let sent = Instant::now();
    board
        .enter_bootloader()
        .with_context(|| format!("asking {name} to restart into its bootloader"))?;
    // Gone when its link drops: the reader sees the device vanish.
    loop {
        if !board.link_state().is_connected() {
            break;
        }
        match board.poll_report(Duration::from_millis(20)) {
            Err(BoardError::Disconnected) => break,
            Err(e) if e.is_link_down() => break,
            _ => {}
        }
        if sent.elapsed() > BOOTLOADER_LEAVE_TIMEOUT {
            bail!(
                "{name} accepted the bootloader request but is still on the bus after {} s",
                BOOTLOADER_LEAVE_TIMEOUT.as_secs()
            );
        }
    }
    let left_ms = sent.elapsed().as_millis();
    let who = match &serial_number {
        Some(serial) => format!("{name} (serial {serial})"),
        None => name.clone(),
    };
    let then = if emulated {
        "being emulated, it has no RPI-RP2 drive to come back as"
    } else {
        "it comes back as the RPI-RP2 drive (USB 2e8a:0003): copy a UF2 onto it to flash"
    };
    print(
        json,
        || {
            format!(
                "{who} restarted into its USB bootloader: it left the bus after {left_ms} ms; \
                 {then}\n"
            )
        },
        || {
            json!({
                "board": name,
                "serial_number": serial_number,
                "entered_bootloader": true,
                "left_bus_after_ms": left_ms as u64,
                "emulated": emulated,
            })
        },
    )
}

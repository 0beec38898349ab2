//! What the board's diagnostics and settings commands print: readable text, or one
//! JSON object (`--json`), from the Feature reports as the board answered them.

use foosball_protocol::{
    BoardSettings, DeviceInfo, PortCounters, PortDiagnostics, PortSettings, ResetReason, PADDLES,
};
use serde_json::{json, Map, Value};

/// Every counter of `counters`, named as its field, in field order.
pub fn counters(counters: &PortCounters) -> [(&'static str, u32); 12] {
    // Destructured, so that a counter added to the protocol cannot be left out.
    let PortCounters {
        frames,
        packets,
        framing_errors,
        parity_errors,
        resends,
        dropped,
        retries,
        absences,
        inits,
        restarts,
        fifo_stalls,
        line_faults,
    } = *counters;
    [
        ("frames", frames),
        ("packets", packets),
        ("framing_errors", framing_errors),
        ("parity_errors", parity_errors),
        ("resends", resends),
        ("dropped", dropped),
        ("retries", retries),
        ("absences", absences),
        ("inits", inits),
        ("restarts", restarts),
        ("fifo_stalls", fifo_stalls),
        ("line_faults", line_faults),
    ]
}

/// The reset reason's name.
pub fn reset_reason_name(reason: ResetReason) -> &'static str {
    match reason {
        ResetReason::PowerOn => "power-on",
        ResetReason::WatchdogTimeout => "watchdog",
        ResetReason::Forced => "forced",
        ResetReason::Panic => "panic",
    }
}

fn reset_reason_text(reason: ResetReason) -> &'static str {
    match reason {
        ResetReason::PowerOn => "power-on (or the reset pin, or a debugger)",
        ResetReason::WatchdogTimeout => "watchdog (the sensor loop stalled)",
        ResetReason::Forced => "forced (the firmware reset itself, no panic)",
        ResetReason::Panic => "panic (the firmware panicked and reset)",
    }
}

/// The git hash as text: printable ASCII kept, any other byte shown as `?`.
pub fn git_hash_text(hash: &[u8]) -> String {
    hash.iter()
        .map(|&b| {
            if b.is_ascii_graphic() {
                char::from(b)
            } else {
                '?'
            }
        })
        .collect()
}

/// The ports whose bit is set in `mask`.
fn ports_of(mask: u8) -> Vec<u8> {
    (0..PADDLES as u8)
        .filter(|p| mask & (1 << p) != 0)
        .collect()
}

/// `uptime_us` as seconds, with hours and minutes when there are any.
fn uptime_text(uptime_us: u64) -> String {
    let secs = uptime_us as f64 * 1e-6;
    let whole = uptime_us / 1_000_000;
    let (h, m, s) = (whole / 3600, whole / 60 % 60, whole % 60);
    let frac = uptime_us % 1_000_000 / 1_000;
    match (h, m) {
        (0, 0) => format!("{secs:.3} s"),
        (0, m) => format!("{secs:.3} s ({m} min {s:02}.{frac:03} s)"),
        (h, m) => format!("{secs:.3} s ({h} h {m:02} min {s:02}.{frac:03} s)"),
    }
}

/// The counts per mm of a resolution code (0..=3), `None` for another code.
pub fn counts_per_mm(code: u8) -> Option<u8> {
    (code <= 3).then(|| 1 << code)
}

fn version_text(v: [u8; 3]) -> String {
    format!("{}.{}.{}", v[0], v[1], v[2])
}

/// `board info` as JSON.
pub fn info_json(board: &str, serial: Option<&str>, info: &DeviceInfo) -> Value {
    json!({
        "board": board,
        "serial_number": serial,
        "firmware_version": version_text(info.firmware_version),
        "git_hash": git_hash_text(&info.git_hash),
        "reset_reason": reset_reason_name(info.reset_reason),
        "uptime_us": info.uptime_us,
        "present_ports": ports_of(info.present_ports),
    })
}

/// `board info` as text.
pub fn info_text(board: &str, serial: Option<&str>, info: &DeviceInfo) -> String {
    let present = ports_of(info.present_ports);
    let list: Vec<String> = present.iter().map(u8::to_string).collect();
    let list = if list.is_empty() {
        "none".to_owned()
    } else {
        list.join(" ")
    };
    format!(
        "board:          {board}\n\
         serial number:  {}\n\
         firmware:       {} (git {})\n\
         reset reason:   {}\n\
         uptime:         {}\n\
         mice present:   {list} ({} of {PADDLES})\n",
        serial.unwrap_or("unknown"),
        version_text(info.firmware_version),
        git_hash_text(&info.git_hash),
        reset_reason_text(info.reset_reason),
        uptime_text(info.uptime_us),
        present.len(),
    )
}

/// `board ports` as JSON: each port's diagnostics with its sample rate and resolution.
pub fn ports_json(board: &str, diags: &[PortDiagnostics], settings: &BoardSettings) -> Value {
    let ports: Vec<Value> = diags
        .iter()
        .map(|d| {
            let port = settings.ports.get(usize::from(d.port));
            let counters: Map<String, Value> = counters(&d.counters)
                .iter()
                .map(|&(name, v)| (name.to_owned(), v.into()))
                .collect();
            json!({
                "port": d.port,
                "present": d.present,
                "device_id": d.device_id,
                "counters": counters,
                "sample_rate": port.map(|p| p.sample_rate),
                "resolution_code": port.map(|p| p.resolution_code),
                "counts_per_mm": port.and_then(|p| counts_per_mm(p.resolution_code)),
            })
        })
        .collect();
    json!({ "board": board, "ports": ports })
}

/// `board ports` as text: one column per port, one row per figure.
pub fn ports_text(board: &str, diags: &[PortDiagnostics], settings: &BoardSettings) -> String {
    let mut s = format!("{board}\n");
    let row = |label: &str, cells: Vec<String>| {
        let mut line = format!("{label:<16}");
        for cell in cells {
            line += &format!(" {cell:>10}");
        }
        line.trim_end().to_owned() + "\n"
    };
    let port_settings = |d: &PortDiagnostics| settings.ports.get(usize::from(d.port)).copied();
    s += &row("port", diags.iter().map(|d| d.port.to_string()).collect());
    s += &row(
        "mouse",
        diags
            .iter()
            .map(|d| if d.present { "present" } else { "absent" }.to_owned())
            .collect(),
    );
    s += &row(
        "device id",
        diags
            .iter()
            .map(|d| {
                d.device_id
                    .map_or_else(|| "none".to_owned(), |id| id.to_string())
            })
            .collect(),
    );
    s += &row(
        "samples/s",
        diags
            .iter()
            .map(|d| port_settings(d).map_or_else(|| "?".to_owned(), |p| p.sample_rate.to_string()))
            .collect(),
    );
    s += &row(
        "counts/mm",
        diags
            .iter()
            .map(|d| {
                port_settings(d)
                    .and_then(|p| counts_per_mm(p.resolution_code))
                    .map_or_else(|| "?".to_owned(), |c| c.to_string())
            })
            .collect(),
    );
    let all: Vec<[(&str, u32); 12]> = diags.iter().map(|d| counters(&d.counters)).collect();
    for index in 0..12 {
        let Some(name) = all.first().map(|c| c[index].0) else {
            break;
        };
        s += &row(
            &name.replace('_', " "),
            all.iter().map(|c| c[index].1.to_string()).collect(),
        );
    }
    s
}

/// One port's settings as JSON.
fn port_settings_json(port: usize, p: &PortSettings) -> Value {
    // Destructured, so that a setting added to the protocol cannot be left out.
    let PortSettings {
        axial_is_y,
        invert_axial,
        invert_rotation,
        resolution_code,
        sample_rate,
    } = *p;
    json!({
        "port": port,
        "axial_is_y": axial_is_y,
        "invert_axial": invert_axial,
        "invert_rotation": invert_rotation,
        "resolution_code": resolution_code,
        "counts_per_mm": counts_per_mm(resolution_code),
        "sample_rate": sample_rate,
    })
}

/// The settings as a JSON array, one object per port.
pub fn settings_ports_json(settings: &BoardSettings) -> Value {
    settings
        .ports
        .iter()
        .enumerate()
        .map(|(port, p)| port_settings_json(port, p))
        .collect()
}

/// `board settings` as JSON.
pub fn settings_json(board: &str, settings: &BoardSettings) -> Value {
    json!({ "board": board, "ports": settings_ports_json(settings) })
}

/// `board settings` as text: one row per port.
pub fn settings_text(board: &str, settings: &BoardSettings) -> String {
    let yes_no = |b: bool| if b { "yes" } else { "no" };
    let mut s = format!(
        "{board}\n\
         port  axial axis  invert axial  invert rotation  resolution          sample rate\n"
    );
    for (port, p) in settings.ports.iter().enumerate() {
        let resolution = counts_per_mm(p.resolution_code).map_or_else(
            || format!("{} (?)", p.resolution_code),
            |c| format!("{} ({c} counts/mm)", p.resolution_code),
        );
        s += &format!(
            "{port:<4}  {:<10}  {:<12}  {:<15}  {resolution:<18}  {}/s\n",
            if p.axial_is_y { "mouse Y" } else { "mouse X" },
            yes_no(p.invert_axial),
            yes_no(p.invert_rotation),
            p.sample_rate,
        );
    }
    s += "change one with `space-foosball board set port.N.FIELD VALUE` (FIELD: axial_is_y, \
          invert_axial, invert_rotation, resolution_code, sample_rate)\n";
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn figures_read_as_a_builder_expects() {
        assert_eq!(uptime_text(1_000_000), "1.000 s");
        assert_eq!(
            uptime_text(3_723_456_000),
            "3723.456 s (1 h 02 min 03.456 s)"
        );
        assert_eq!(uptime_text(61_500_000), "61.500 s (1 min 01.500 s)");
        assert_eq!(git_hash_text(b"abc\0\xffdef"), "abc??def");
        assert_eq!(ports_of(0b1000_0101), vec![0, 2, 7]);
        assert_eq!(
            (0..5).map(counts_per_mm).collect::<Vec<_>>(),
            vec![Some(1), Some(2), Some(4), Some(8), None]
        );
    }

    #[test]
    fn every_counter_is_shown_in_both_forms() {
        let diag = PortDiagnostics {
            port: 4,
            present: true,
            device_id: Some(3),
            counters: PortCounters {
                frames: 1,
                packets: 2,
                framing_errors: 3,
                parity_errors: 4,
                resends: 5,
                dropped: 6,
                retries: 7,
                absences: 8,
                inits: 9,
                restarts: 10,
                fifo_stalls: 11,
                line_faults: 4_000_000_000,
            },
        };
        let json = ports_json("b", &[diag], &BoardSettings::DEFAULT);
        let port = &json["ports"][0];
        assert_eq!(port["device_id"], 3);
        assert_eq!(port["sample_rate"], 200);
        assert_eq!(port["counts_per_mm"], 8);
        for (i, (name, value)) in counters(&diag.counters).iter().enumerate() {
            assert_eq!(port["counters"][name], *value, "{name}");
            if i < 11 {
                assert_eq!(*value, i as u32 + 1, "{name} out of order");
            }
        }
        let text = ports_text("b", &[diag], &BoardSettings::DEFAULT);
        assert!(
            text.contains("line faults") && text.contains("4000000000"),
            "{text}"
        );
        assert!(
            text.contains("fifo stalls") && text.contains("present"),
            "{text}"
        );
    }
}

//! The fuzz targets, one per input format from outside.
//!
//! A target takes any bytes. It returns [`Verdict::Rejected`] when the code under test
//! refused the input with an error, [`Verdict::Accepted`] when it took it, and panics
//! when a property fails. What every target asserts besides "no panic, no abort":
//!
//! | target | code under test | property of an accepted input |
//! |---|---|---|
//! | `in-report` | `InReport::decode` | encodes back to the same bytes |
//! | `in-report-v2` | `decode_in_report` (either version), `InReportV2::decode` | encodes back to the same bytes with its version's encoder; both v2 decoders agree; packet ages read back in whole steps |
//! | `out-report` | `OutReport::decode` | encodes back to the same bytes |
//! | `feature-report` | `FeatureReport::decode`, `FeatureReport::decode_command` | encodes back to the same bytes; the two decoders agree but for the board-only kinds |
//! | `ps2` | `Ps2Frame`/`HostFrame` decode, `SensorBoard` (8 × `MouseDriver`) fed wire frames, bytes, send outcomes, time, stuck lines, receiver stalls, report snapshots | a good frame re-encodes to its bits; every IN report decodes, with consecutive sequence numbers |
//! | `socket-frames` | `FrameReader`, any split into reads; IN payloads into `ReportReceiver` | messages re-encode to the bytes consumed; errors are sticky |
//! | `scene` | `SceneFile::from_json` + `build` | 100 steps: each `Ok` step leaves every body finite |
//! | `table` | `Table::from_toml` + `Arena::new` | 100 arena steps: every body finite |
//! | `calibration` | `Calibration::from_json` | 100 reports of extreme motion: every rod pose finite, slide within travel; JSON round trip |
//! | `recording` | `MatchRecording::from_json` | up to 100 steps of replay (poses or reports): every body finite |
//! | `motion-script` | `MotionScript::from_json` | poses finite and within the script limits at 100 times; fault ports valid |
//! | `motion-recording` | `Playback::from_json` | poses finite and within the script limits at 100 times |

mod calibration;
mod feature;
mod finite;
mod motion;
mod protocol;
pub(crate) mod ps2;
mod recording;
mod scene;
mod socket;
mod table;

/// What a target did with an input.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Verdict {
    /// The code under test refused the input with an error.
    Rejected,
    /// The code under test took the input (and every property held).
    Accepted,
}

/// How the mutator treats a target's inputs.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Format {
    /// Binary: byte edits only.
    Bytes,
    /// JSON text: edits of the parsed value tree, and byte edits.
    Json,
    /// TOML text: edits of the parsed value tree, and byte edits.
    Toml,
}

/// One fuzz target.
pub struct Target {
    /// Name: the corpus folder, the command-line name.
    pub name: &'static str,
    /// What it exercises, one line.
    pub about: &'static str,
    /// How inputs are mutated.
    pub format: Format,
    /// Longest mutant, bytes (at most [`crate::MAX_INPUT_LEN`]). The loaders whose
    /// accepted inputs are stepped 100 times get less, so that a mutant that grew
    /// hundreds of bodies measures the physics' speed, not its correctness, only up
    /// to the per-input time limit.
    pub max_len: usize,
    /// Runs one input; panics when a property fails.
    pub run: fn(&[u8]) -> Verdict,
}

/// Every target, in the order the runner takes them.
pub static TARGETS: [Target; 12] = [
    Target {
        name: "in-report",
        about: "USB IN report decoder (device → host)",
        format: Format::Bytes,
        run: protocol::in_report,
        max_len: 64,
    },
    Target {
        name: "in-report-v2",
        about: "USB IN report of either version (v2: device time, packet ages, drops)",
        format: Format::Bytes,
        run: protocol::in_report_any,
        max_len: 128,
    },
    Target {
        name: "out-report",
        about: "USB OUT report decoder (host → device)",
        format: Format::Bytes,
        run: protocol::out_report,
        max_len: 64,
    },
    Target {
        name: "feature-report",
        about: "USB Feature report decoders (diagnostics, settings, select, bootloader)",
        format: Format::Bytes,
        run: feature::run,
        max_len: 128,
    },
    Target {
        name: "ps2",
        about: "PS/2 frames and the sensor board's eight mouse drivers, fed arbitrary wire events",
        format: Format::Bytes,
        run: ps2::run,
        max_len: 4096,
    },
    Target {
        name: "socket-frames",
        about: "emulator socket framing, split into arbitrary reads",
        format: Format::Bytes,
        run: socket::run,
        max_len: 4096,
    },
    Target {
        name: "scene",
        about: "Virtual Physics scene JSON: load, build, 100 steps",
        format: Format::Json,
        run: scene::run,
        max_len: 16 * 1024,
    },
    Target {
        name: "table",
        about: "table TOML: load, build the arena, 100 steps",
        format: Format::Toml,
        run: table::run,
        max_len: 16 * 1024,
    },
    Target {
        name: "calibration",
        about: "calibration file: load, track 100 reports of extreme motion",
        format: Format::Json,
        run: calibration::run,
        max_len: 16 * 1024,
    },
    Target {
        name: "recording",
        about: "match recording: load, replay up to 100 steps",
        format: Format::Json,
        run: recording::run,
        max_len: 64 * 1024,
    },
    Target {
        name: "motion-script",
        about: "emulator motion script: load, sample 100 times",
        format: Format::Json,
        run: motion::script,
        max_len: 16 * 1024,
    },
    Target {
        name: "motion-recording",
        about: "emulator motion recording: load, sample 100 times",
        format: Format::Json,
        run: motion::playback,
        max_len: 64 * 1024,
    },
];

/// The input as UTF-8 text, `None` if it is not (text loaders take `&str`, so bytes
/// that are not UTF-8 never reach them).
fn text(input: &[u8]) -> Option<&str> {
    std::str::from_utf8(input).ok()
}

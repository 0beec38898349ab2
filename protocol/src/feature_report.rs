//! Feature reports: the board's diagnostics and configuration, over the control pipe.
//!
//! One HID Feature report of [`FEATURE_REPORT_LEN`] bytes, no report id. Byte 0 is
//! [`FEATURE_REPORT_VERSION`], byte 1 the [`FeatureReport`] kind; unused bytes are 0.
//! The host writes one with HID SET_REPORT (Feature) and reads one with GET_REPORT
//! (Feature). What GET_REPORT returns is chosen by the last [`FeatureReport::Select`]
//! written (after a reset: [`FeatureKind::DeviceInfo`]).
//!
//! | kind | direction | layout after the two header bytes (little-endian) |
//! |---|---|---|
//! | 1 [`DeviceInfo`] | read | firmware version major, minor, patch (3 × `u8`); git hash (12 ASCII bytes); [`ResetReason`] (`u8`); uptime µs (`u64`); present ports (`u8`, bit = port) |
//! | 2 [`PortDiagnostics`] | read | port (`u8`); flags (`u8`: bit 0 present, bit 1 device id known); device id (`u8`); 3 reserved; twelve [`PortCounters`] (`u32` each, in field order) |
//! | 3 [`BoardSettings`] | read, write | per port 0..8: axis flags (`u8`, [`PortSettings`]), resolution code (`u8`, 0..=3), sample rate (`u8`, samples/s) |
//! | 16 [`FeatureReport::Select`] | write | kind to read next (1, 2 or 3); port (`u8`, for kind 2) |
//! | 17 [`FeatureReport::EnterBootloader`] | write | [`BOOTLOADER_MAGIC`] |
//!
//! A decoder rejects another length, another version, an unknown kind, a reserved
//! byte that is not 0 and any field out of its range, each with a [`DecodeError`]
//! naming it; anything it accepts encodes back to the same bytes.

use crate::error::check_buffer;
use crate::{DecodeError, EncodeError, PADDLES};

/// Length of every Feature report, bytes (fits the 64-byte control buffer).
pub const FEATURE_REPORT_LEN: usize = 56;

/// Layout version in byte 0 of every Feature report.
pub const FEATURE_REPORT_VERSION: u8 = 1;

/// Bytes of the git hash in [`DeviceInfo`] (the abbreviated hash).
pub const GIT_HASH_LEN: usize = 12;

/// What an [`FeatureReport::EnterBootloader`] carries, so that a stray write cannot
/// restart the board.
pub const BOOTLOADER_MAGIC: [u8; 4] = *b"BOOT";

/// Sample rates a PS/2 mouse accepts (`0xF3`), samples per second.
pub const SAMPLE_RATES: [u8; 7] = [10, 20, 40, 60, 80, 100, 200];

/// Bytes before a kind's fields: version and kind.
const HEADER: usize = 2;
/// Counters in [`PortCounters`].
const COUNTERS: usize = 12;
/// Offset of the first counter in a [`PortDiagnostics`] report.
const COUNTERS_AT: usize = 8;
/// Bytes per port in a [`BoardSettings`] report.
const SETTINGS_BYTES: usize = 3;

const _: () = assert!(COUNTERS_AT + 4 * COUNTERS <= FEATURE_REPORT_LEN);
const _: () = assert!(HEADER + SETTINGS_BYTES * PADDLES <= FEATURE_REPORT_LEN);
// Device info: version, hash, reason, uptime and the present byte.
const _: () = assert!(HEADER + 3 + GIT_HASH_LEN + 1 + 8 < FEATURE_REPORT_LEN);

/// The kind byte of a Feature report.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[repr(u8)]
pub enum FeatureKind {
    /// [`DeviceInfo`].
    DeviceInfo = 1,
    /// [`PortDiagnostics`].
    PortDiagnostics = 2,
    /// [`BoardSettings`].
    Settings = 3,
    /// [`FeatureReport::Select`].
    Select = 16,
    /// [`FeatureReport::EnterBootloader`].
    EnterBootloader = 17,
}

impl FeatureKind {
    /// The kind for a raw byte, `None` if unknown.
    pub const fn from_raw(raw: u8) -> Option<Self> {
        match raw {
            1 => Some(Self::DeviceInfo),
            2 => Some(Self::PortDiagnostics),
            3 => Some(Self::Settings),
            16 => Some(Self::Select),
            17 => Some(Self::EnterBootloader),
            _ => None,
        }
    }

    /// Whether only the board sends this kind (device info, port diagnostics).
    pub const fn is_board_only(self) -> bool {
        matches!(self, Self::DeviceInfo | Self::PortDiagnostics)
    }

    /// Whether GET_REPORT can return this kind (it can be [`FeatureReport::Select`]ed).
    pub const fn is_readable(self) -> bool {
        matches!(
            self,
            Self::DeviceInfo | Self::PortDiagnostics | Self::Settings
        )
    }
}

/// Why the board last started.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[repr(u8)]
pub enum ResetReason {
    /// Power-on, the reset pin, or a debugger.
    #[default]
    PowerOn = 0,
    /// The watchdog expired (the sensor loop stalled).
    WatchdogTimeout = 1,
    /// The firmware forced a reset without a panic.
    Forced = 2,
    /// The firmware panicked (it forces a reset and keeps the message).
    Panic = 3,
}

impl ResetReason {
    /// The reason for a raw byte, `None` above 3.
    pub const fn from_raw(raw: u8) -> Option<Self> {
        match raw {
            0 => Some(Self::PowerOn),
            1 => Some(Self::WatchdogTimeout),
            2 => Some(Self::Forced),
            3 => Some(Self::Panic),
            _ => None,
        }
    }
}

/// Who the board is and how long it has run.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct DeviceInfo {
    /// Firmware version: major, minor, patch.
    pub firmware_version: [u8; 3],
    /// The firmware's git commit, abbreviated, as ASCII (any bytes are carried).
    pub git_hash: [u8; GIT_HASH_LEN],
    /// Why the board last started.
    pub reset_reason: ResetReason,
    /// Time since the board started, microseconds.
    pub uptime_us: u64,
    /// Bit `i` set when port `i`'s mouse is present.
    pub present_ports: u8,
}

/// One port's counters since boot (each wraps at `u32::MAX`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct PortCounters {
    /// Frames received, good or bad.
    pub frames: u32,
    /// Movement packets delivered.
    pub packets: u32,
    /// Frames with a bad start or stop bit.
    pub framing_errors: u32,
    /// Frames with bad parity.
    pub parity_errors: u32,
    /// Resend requests (`0xFE`) sent for garbled packets.
    pub resends: u32,
    /// Packets lost for good.
    pub dropped: u32,
    /// Commands sent again after a failed send or a missing reply (a timeout).
    pub retries: u32,
    /// Times the port was declared absent.
    pub absences: u32,
    /// Times initialisation completed.
    pub inits: u32,
    /// Spontaneous mouse restarts seen.
    pub restarts: u32,
    /// Receiver FIFO overflows recovered from.
    pub fifo_stalls: u32,
    /// Times a line was found stuck low.
    pub line_faults: u32,
}

impl PortCounters {
    fn to_array(self) -> [u32; COUNTERS] {
        [
            self.frames,
            self.packets,
            self.framing_errors,
            self.parity_errors,
            self.resends,
            self.dropped,
            self.retries,
            self.absences,
            self.inits,
            self.restarts,
            self.fifo_stalls,
            self.line_faults,
        ]
    }

    fn from_array(c: [u32; COUNTERS]) -> Self {
        Self {
            frames: c[0],
            packets: c[1],
            framing_errors: c[2],
            parity_errors: c[3],
            resends: c[4],
            dropped: c[5],
            retries: c[6],
            absences: c[7],
            inits: c[8],
            restarts: c[9],
            fifo_stalls: c[10],
            line_faults: c[11],
        }
    }
}

/// One port's state and counters.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct PortDiagnostics {
    /// The port, 0..8.
    pub port: u8,
    /// Its mouse is initialised and streaming.
    pub present: bool,
    /// The PS/2 device id the mouse sent after its self-test (0 for a standard
    /// mouse), `None` before one arrived.
    pub device_id: Option<u8>,
    /// Counters since boot.
    pub counters: PortCounters,
}

/// How one port's sensor is mounted and run.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct PortSettings {
    /// The mouse's Y axis measures the rod's axial motion (else X does; rotation is
    /// the other axis). Axis flags bit 0.
    pub axial_is_y: bool,
    /// Negate the axial counts. Axis flags bit 1.
    pub invert_axial: bool,
    /// Negate the rotation counts. Axis flags bit 2.
    pub invert_rotation: bool,
    /// PS/2 resolution code (`0xE8`): 0..=3 for 1, 2, 4, 8 counts/mm.
    pub resolution_code: u8,
    /// Samples per second (`0xF3`), one of [`SAMPLE_RATES`].
    pub sample_rate: u8,
}

impl PortSettings {
    /// The board's defaults: axial = mouse X, nothing inverted, 8 counts/mm,
    /// 200 samples/s.
    pub const DEFAULT: Self = Self {
        axial_is_y: false,
        invert_axial: false,
        invert_rotation: false,
        resolution_code: 3,
        sample_rate: 200,
    };

    /// Known bits of the axis flags byte.
    const AXIS_FLAGS: u8 = 0b111;

    /// Whether every field is in range.
    pub fn check(&self, port: u8) -> Result<(), DecodeError> {
        if self.resolution_code > 3 {
            return Err(bad("resolution", Some(port), self.resolution_code));
        }
        if !SAMPLE_RATES.contains(&self.sample_rate) {
            return Err(bad("sample_rate", Some(port), self.sample_rate));
        }
        Ok(())
    }

    fn axis_flags(&self) -> u8 {
        u8::from(self.axial_is_y)
            | (u8::from(self.invert_axial) << 1)
            | (u8::from(self.invert_rotation) << 2)
    }
}

impl Default for PortSettings {
    fn default() -> Self {
        Self::DEFAULT
    }
}

/// The board's configuration: every port's [`PortSettings`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct BoardSettings {
    /// Indexed by port (0..8).
    pub ports: [PortSettings; PADDLES],
}

impl BoardSettings {
    /// Every port at [`PortSettings::DEFAULT`].
    pub const DEFAULT: Self = Self {
        ports: [PortSettings::DEFAULT; PADDLES],
    };

    /// Bytes of [`encode_fields`](Self::encode_fields).
    pub const FIELDS_LEN: usize = SETTINGS_BYTES * PADDLES;

    /// The per-port fields alone (3 bytes a port), as stored in flash.
    pub fn encode_fields(&self) -> [u8; Self::FIELDS_LEN] {
        let mut out = [0; Self::FIELDS_LEN];
        for (chunk, port) in out.chunks_exact_mut(SETTINGS_BYTES).zip(&self.ports) {
            chunk.copy_from_slice(&[port.axis_flags(), port.resolution_code, port.sample_rate]);
        }
        out
    }

    /// Parses [`encode_fields`](Self::encode_fields) output, checking every field.
    pub fn decode_fields(bytes: &[u8]) -> Result<Self, DecodeError> {
        if bytes.len() != Self::FIELDS_LEN {
            return Err(DecodeError::WrongLength {
                expected: Self::FIELDS_LEN,
                actual: bytes.len(),
            });
        }
        let mut ports = [PortSettings::DEFAULT; PADDLES];
        for (index, (port, chunk)) in ports
            .iter_mut()
            .zip(bytes.chunks_exact(SETTINGS_BYTES))
            .enumerate()
        {
            let index = index as u8;
            let flags = chunk[0];
            if flags & !PortSettings::AXIS_FLAGS != 0 {
                return Err(bad("axis_flags", Some(index), flags));
            }
            *port = PortSettings {
                axial_is_y: flags & 1 != 0,
                invert_axial: flags & 2 != 0,
                invert_rotation: flags & 4 != 0,
                resolution_code: chunk[1],
                sample_rate: chunk[2],
            };
            port.check(index)?;
        }
        Ok(Self { ports })
    }
}

/// A Feature report of any kind.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum FeatureReport {
    /// Board → host: identity and uptime.
    DeviceInfo(DeviceInfo),
    /// Board → host: one port's state and counters.
    PortDiagnostics(PortDiagnostics),
    /// Both ways: the configuration (written: applied and kept in flash).
    Settings(BoardSettings),
    /// Host → board: what the next GET_REPORT returns.
    Select {
        /// A readable kind ([`FeatureKind::is_readable`]).
        kind: FeatureKind,
        /// The port, for [`FeatureKind::PortDiagnostics`] (0..8; 0 otherwise).
        port: u8,
    },
    /// Host → board: restart into the RP2040's USB bootloader (BOOTSEL mode).
    EnterBootloader,
}

fn bad(field: &'static str, paddle: Option<u8>, value: u8) -> DecodeError {
    DecodeError::BadField {
        field,
        paddle,
        value,
    }
}

fn u32_at(bytes: &[u8], at: usize) -> u32 {
    u32::from_le_bytes([bytes[at], bytes[at + 1], bytes[at + 2], bytes[at + 3]])
}

/// Fails unless `bytes[from..]` are all zero.
fn check_reserved(bytes: &[u8], from: usize) -> Result<(), DecodeError> {
    match bytes[from..].iter().find(|&&b| b != 0) {
        Some(&value) => Err(bad("reserved", None, value)),
        None => Ok(()),
    }
}

impl FeatureReport {
    /// The kind byte.
    pub const fn kind(&self) -> FeatureKind {
        match self {
            Self::DeviceInfo(_) => FeatureKind::DeviceInfo,
            Self::PortDiagnostics(_) => FeatureKind::PortDiagnostics,
            Self::Settings(_) => FeatureKind::Settings,
            Self::Select { .. } => FeatureKind::Select,
            Self::EnterBootloader => FeatureKind::EnterBootloader,
        }
    }

    /// Writes the report into `buf` (unused bytes 0), returning
    /// [`FEATURE_REPORT_LEN`].
    pub fn encode(&self, buf: &mut [u8]) -> Result<usize, EncodeError> {
        check_buffer(buf, FEATURE_REPORT_LEN)?;
        let out = &mut buf[..FEATURE_REPORT_LEN];
        out.fill(0);
        out[0] = FEATURE_REPORT_VERSION;
        out[1] = self.kind() as u8;
        let body = &mut out[HEADER..];
        match self {
            Self::DeviceInfo(info) => {
                body[0..3].copy_from_slice(&info.firmware_version);
                body[3..3 + GIT_HASH_LEN].copy_from_slice(&info.git_hash);
                let at = 3 + GIT_HASH_LEN;
                body[at] = info.reset_reason as u8;
                body[at + 1..at + 9].copy_from_slice(&info.uptime_us.to_le_bytes());
                body[at + 9] = info.present_ports;
            }
            Self::PortDiagnostics(diag) => {
                body[0] = diag.port;
                body[1] = u8::from(diag.present) | (u8::from(diag.device_id.is_some()) << 1);
                body[2] = diag.device_id.unwrap_or(0);
                for (chunk, counter) in out[COUNTERS_AT..]
                    .chunks_exact_mut(4)
                    .zip(diag.counters.to_array())
                {
                    chunk.copy_from_slice(&counter.to_le_bytes());
                }
            }
            Self::Settings(settings) => {
                body[..BoardSettings::FIELDS_LEN].copy_from_slice(&settings.encode_fields());
            }
            Self::Select { kind, port } => {
                body[0] = *kind as u8;
                body[1] = *port;
            }
            Self::EnterBootloader => body[..4].copy_from_slice(&BOOTLOADER_MAGIC),
        }
        Ok(FEATURE_REPORT_LEN)
    }

    /// The encoded report as a fixed-size array.
    pub fn to_bytes(&self) -> [u8; FEATURE_REPORT_LEN] {
        let mut out = [0; FEATURE_REPORT_LEN];
        // The array has exactly the needed length, so encoding cannot fail.
        let _ = self.encode(&mut out);
        out
    }

    /// Parses a Feature report, checking its length, version, kind, every field and
    /// that reserved bytes are zero.
    pub fn decode(bytes: &[u8]) -> Result<Self, DecodeError> {
        Self::decode_kinds(bytes, true)
    }

    /// [`decode`](Self::decode) for the kinds a host writes ([`FeatureReport::Select`],
    /// [`FeatureReport::Settings`], [`FeatureReport::EnterBootloader`]); the kinds only
    /// the board sends are a [`DecodeError::BadField`] `kind`. The board uses this, so
    /// their parsing is not in its flash.
    pub fn decode_command(bytes: &[u8]) -> Result<Self, DecodeError> {
        Self::decode_kinds(bytes, false)
    }

    /// The decoder; `board_kinds`: accept device info and port diagnostics too.
    #[inline(always)]
    fn decode_kinds(bytes: &[u8], board_kinds: bool) -> Result<Self, DecodeError> {
        if bytes.len() != FEATURE_REPORT_LEN {
            return Err(DecodeError::WrongLength {
                expected: FEATURE_REPORT_LEN,
                actual: bytes.len(),
            });
        }
        if bytes[0] != FEATURE_REPORT_VERSION {
            return Err(DecodeError::UnknownVersion {
                found: bytes[0],
                supported: FEATURE_REPORT_VERSION,
            });
        }
        let kind = FeatureKind::from_raw(bytes[1])
            .filter(|k| board_kinds || !k.is_board_only())
            .ok_or(bad("kind", None, bytes[1]))?;
        let body = &bytes[HEADER..];
        let (report, used) = match kind {
            FeatureKind::DeviceInfo => {
                let at = 3 + GIT_HASH_LEN;
                let mut git_hash = [0; GIT_HASH_LEN];
                git_hash.copy_from_slice(&body[3..at]);
                let reset_reason =
                    ResetReason::from_raw(body[at]).ok_or(bad("reset_reason", None, body[at]))?;
                let mut uptime = [0; 8];
                uptime.copy_from_slice(&body[at + 1..at + 9]);
                let info = DeviceInfo {
                    firmware_version: [body[0], body[1], body[2]],
                    git_hash,
                    reset_reason,
                    uptime_us: u64::from_le_bytes(uptime),
                    present_ports: body[at + 9],
                };
                (Self::DeviceInfo(info), HEADER + at + 10)
            }
            FeatureKind::PortDiagnostics => {
                let port = body[0];
                if usize::from(port) >= PADDLES {
                    return Err(bad("port", None, port));
                }
                let flags = body[1];
                if flags & !0b11 != 0 {
                    return Err(bad("flags", Some(port), flags));
                }
                let has_id = flags & 2 != 0;
                if !has_id && body[2] != 0 {
                    return Err(bad("device_id", Some(port), body[2]));
                }
                check_reserved(&bytes[..COUNTERS_AT], HEADER + 3)?;
                let mut counters = [0u32; COUNTERS];
                for (i, counter) in counters.iter_mut().enumerate() {
                    *counter = u32_at(bytes, COUNTERS_AT + 4 * i);
                }
                let diag = PortDiagnostics {
                    port,
                    present: flags & 1 != 0,
                    device_id: has_id.then_some(body[2]),
                    counters: PortCounters::from_array(counters),
                };
                (Self::PortDiagnostics(diag), COUNTERS_AT + 4 * COUNTERS)
            }
            FeatureKind::Settings => {
                let fields = &body[..BoardSettings::FIELDS_LEN];
                (
                    Self::Settings(BoardSettings::decode_fields(fields)?),
                    HEADER + BoardSettings::FIELDS_LEN,
                )
            }
            FeatureKind::Select => {
                let selected = FeatureKind::from_raw(body[0])
                    .filter(|k| k.is_readable())
                    .ok_or(bad("selected_kind", None, body[0]))?;
                let port = body[1];
                let port_ok = if selected == FeatureKind::PortDiagnostics {
                    usize::from(port) < PADDLES
                } else {
                    port == 0
                };
                if !port_ok {
                    return Err(bad("port", None, port));
                }
                (
                    Self::Select {
                        kind: selected,
                        port,
                    },
                    HEADER + 2,
                )
            }
            FeatureKind::EnterBootloader => {
                if body[..4] != BOOTLOADER_MAGIC {
                    let wrong = body[..4]
                        .iter()
                        .zip(BOOTLOADER_MAGIC)
                        .find(|(got, want)| **got != *want)
                        .map_or(0, |(got, _)| *got);
                    return Err(bad("bootloader_magic", None, wrong));
                }
                (Self::EnterBootloader, HEADER + 4)
            }
        };
        check_reserved(bytes, used)?;
        Ok(report)
    }
}

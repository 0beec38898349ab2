//! The board's Feature reports from the host side: read its diagnostics, read and
//! write its settings, restart it into its USB bootloader
//! ([`foosball_protocol::FeatureReport`]).
//!
//! A read is two control transfers: a Select naming what to read, then GET_REPORT
//! (Feature). The answer must be of the kind (and port) selected, or it is
//! [`BoardError::Malformed`]. The transfers themselves go through a [`FeaturePipe`]
//! (USB in [`crate::usb`]), so this logic is tested against scripted boards.

use foosball_protocol::{
    BoardSettings, DecodeError, DeviceInfo, FeatureKind, FeatureReport, PortDiagnostics,
    FEATURE_REPORT_LEN, PADDLES,
};

use crate::BoardError;

/// HID GET_REPORT / SET_REPORT of the board's one Feature report
/// ([`FEATURE_REPORT_LEN`] bytes, no report id), whatever carries them: USB control
/// transfers ([`crate::UsbBoard`]) or an emulated board answering as the firmware does
/// (`foosball-sim`'s in-process board).
///
/// Implementors provide the two transfers; the provided methods are the board's
/// requests on top of them (a Select, then GET_REPORT; or one SET_REPORT) and check
/// every answer, so any pipe gets the same checked diagnostics and settings.
pub trait FeaturePipe {
    /// GET_REPORT (Feature): writes the board's answer into `buf` and returns its
    /// length in bytes. [`BoardError::FeatureUnsupported`] when the board refuses
    /// (STALL).
    fn get_feature(&mut self, buf: &mut [u8; FEATURE_REPORT_LEN]) -> Result<usize, BoardError>;

    /// SET_REPORT (Feature) of `report`. [`BoardError::FeatureUnsupported`] when the
    /// board refuses it (STALL).
    fn set_feature(&mut self, report: &[u8; FEATURE_REPORT_LEN]) -> Result<(), BoardError>;

    /// Firmware version and git hash, reset reason, uptime (µs), present ports.
    fn device_info(&mut self) -> Result<DeviceInfo, BoardError> {
        device_info(self)
    }

    /// Port `port`'s (0..8) state, PS/2 device id and counters;
    /// [`BoardError::PortOutOfRange`] for another port, before anything is sent.
    fn port_diagnostics(&mut self, port: u8) -> Result<PortDiagnostics, BoardError> {
        port_diagnostics(self, port)
    }

    /// The board's settings (axis map, resolution and sample rate per port).
    fn settings(&mut self) -> Result<BoardSettings, BoardError> {
        settings(self)
    }

    /// Writes new settings (the board applies them and keeps them in flash). A field
    /// out of range is refused ([`BoardError::Malformed`] naming it) before anything
    /// is sent.
    fn set_settings(&mut self, settings: &BoardSettings) -> Result<(), BoardError> {
        set_settings(self, settings)
    }

    /// Restarts the board into the RP2040's USB bootloader: it leaves the bus and
    /// comes back as the `RPI-RP2` drive.
    fn enter_bootloader(&mut self) -> Result<(), BoardError> {
        enter_bootloader(self)
    }
}

/// Selects `kind` (of `port`), reads the answer and checks it is what was selected.
fn read(
    pipe: &mut (impl FeaturePipe + ?Sized),
    kind: FeatureKind,
    port: u8,
) -> Result<FeatureReport, BoardError> {
    pipe.set_feature(&FeatureReport::Select { kind, port }.to_bytes())?;
    let mut buf = [0; FEATURE_REPORT_LEN];
    let len = pipe.get_feature(&mut buf)?;
    let report = FeatureReport::decode(&buf[..len.min(FEATURE_REPORT_LEN)])?;
    if report.kind() != kind {
        return Err(BoardError::Malformed(DecodeError::BadField {
            field: "kind",
            paddle: None,
            value: report.kind() as u8,
        }));
    }
    Ok(report)
}

/// The board's identity, reset reason and uptime.
pub(crate) fn device_info(
    pipe: &mut (impl FeaturePipe + ?Sized),
) -> Result<DeviceInfo, BoardError> {
    match read(pipe, FeatureKind::DeviceInfo, 0)? {
        FeatureReport::DeviceInfo(info) => Ok(info),
        other => Err(wrong_kind(&other)),
    }
}

/// One port's state and counters; `port` in `0..8`.
pub(crate) fn port_diagnostics(
    pipe: &mut (impl FeaturePipe + ?Sized),
    port: u8,
) -> Result<PortDiagnostics, BoardError> {
    if usize::from(port) >= PADDLES {
        return Err(BoardError::PortOutOfRange { port });
    }
    match read(pipe, FeatureKind::PortDiagnostics, port)? {
        FeatureReport::PortDiagnostics(diag) if diag.port == port => Ok(diag),
        FeatureReport::PortDiagnostics(diag) => Err(BoardError::Malformed(DecodeError::BadField {
            field: "port",
            paddle: None,
            value: diag.port,
        })),
        other => Err(wrong_kind(&other)),
    }
}

/// The board's settings.
pub(crate) fn settings(
    pipe: &mut (impl FeaturePipe + ?Sized),
) -> Result<BoardSettings, BoardError> {
    match read(pipe, FeatureKind::Settings, 0)? {
        FeatureReport::Settings(settings) => Ok(settings),
        other => Err(wrong_kind(&other)),
    }
}

/// Writes new settings (the board applies them and keeps them in flash). Settings
/// with a field out of range are refused here, before anything is sent.
pub(crate) fn set_settings(
    pipe: &mut (impl FeaturePipe + ?Sized),
    settings: &BoardSettings,
) -> Result<(), BoardError> {
    for (port, settings) in (0u8..).zip(&settings.ports) {
        settings.check(port)?;
    }
    pipe.set_feature(&FeatureReport::Settings(*settings).to_bytes())
}

/// Restarts the board into the RP2040's USB bootloader: it leaves the bus and comes
/// back as the `RPI-RP2` drive.
pub(crate) fn enter_bootloader(pipe: &mut (impl FeaturePipe + ?Sized)) -> Result<(), BoardError> {
    pipe.set_feature(&FeatureReport::EnterBootloader.to_bytes())
}

fn wrong_kind(report: &FeatureReport) -> BoardError {
    BoardError::Malformed(DecodeError::BadField {
        field: "kind",
        paddle: None,
        value: report.kind() as u8,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use foosball_protocol::{PortCounters, PortSettings, ResetReason};

    /// A board that answers as the firmware does: a Select chooses what the next
    /// GET_REPORT returns; settings written are kept.
    struct FirmwareLike {
        selected: (FeatureKind, u8),
        settings: BoardSettings,
        bootloader: bool,
        writes: usize,
    }

    impl FirmwareLike {
        fn new() -> Self {
            Self {
                selected: (FeatureKind::DeviceInfo, 0),
                settings: BoardSettings::DEFAULT,
                bootloader: false,
                writes: 0,
            }
        }
    }

    impl FeaturePipe for FirmwareLike {
        fn get_feature(&mut self, buf: &mut [u8; FEATURE_REPORT_LEN]) -> Result<usize, BoardError> {
            let report = match self.selected {
                (FeatureKind::PortDiagnostics, port) => {
                    FeatureReport::PortDiagnostics(PortDiagnostics {
                        port,
                        present: true,
                        device_id: Some(0),
                        counters: PortCounters {
                            frames: 100 + u32::from(port),
                            ..PortCounters::default()
                        },
                    })
                }
                (FeatureKind::Settings, _) => FeatureReport::Settings(self.settings),
                _ => FeatureReport::DeviceInfo(DeviceInfo {
                    firmware_version: [0, 1, 0],
                    git_hash: *b"0123456789ab",
                    reset_reason: ResetReason::WatchdogTimeout,
                    uptime_us: 5_000_000,
                    present_ports: 0xFF,
                }),
            };
            report
                .encode(buf)
                .map_err(|e| BoardError::Usb(e.to_string()))
        }

        fn set_feature(&mut self, report: &[u8; FEATURE_REPORT_LEN]) -> Result<(), BoardError> {
            self.writes += 1;
            match FeatureReport::decode(report) {
                Ok(FeatureReport::Select { kind, port }) => self.selected = (kind, port),
                Ok(FeatureReport::Settings(settings)) => self.settings = settings,
                Ok(FeatureReport::EnterBootloader) => self.bootloader = true,
                // The firmware stalls anything else.
                _ => return Err(BoardError::FeatureUnsupported),
            }
            Ok(())
        }
    }

    /// A board before Feature reports: every request stalls.
    struct OldBoard;

    impl FeaturePipe for OldBoard {
        fn get_feature(&mut self, _: &mut [u8; FEATURE_REPORT_LEN]) -> Result<usize, BoardError> {
            Err(BoardError::FeatureUnsupported)
        }
        fn set_feature(&mut self, _: &[u8; FEATURE_REPORT_LEN]) -> Result<(), BoardError> {
            Err(BoardError::FeatureUnsupported)
        }
    }

    /// A board that answers GET_REPORT with fixed bytes.
    struct Answers(Vec<u8>);

    impl FeaturePipe for Answers {
        fn get_feature(&mut self, buf: &mut [u8; FEATURE_REPORT_LEN]) -> Result<usize, BoardError> {
            let len = self.0.len().min(FEATURE_REPORT_LEN);
            buf[..len].copy_from_slice(&self.0[..len]);
            Ok(len)
        }
        fn set_feature(&mut self, _: &[u8; FEATURE_REPORT_LEN]) -> Result<(), BoardError> {
            Ok(())
        }
    }

    #[test]
    fn reads_device_info_and_every_port() {
        let mut board = FirmwareLike::new();
        let info = device_info(&mut board).unwrap();
        assert_eq!(info.reset_reason, ResetReason::WatchdogTimeout);
        assert_eq!(&info.git_hash, b"0123456789ab");
        for port in 0..8 {
            let diag = port_diagnostics(&mut board, port).unwrap();
            assert_eq!(diag.port, port);
            assert_eq!(diag.counters.frames, 100 + u32::from(port));
        }
        assert!(matches!(
            port_diagnostics(&mut board, 8),
            Err(BoardError::PortOutOfRange { port: 8 })
        ));
    }

    #[test]
    fn settings_written_read_back() {
        let mut board = FirmwareLike::new();
        assert_eq!(settings(&mut board).unwrap(), BoardSettings::DEFAULT);
        let mut new = BoardSettings::DEFAULT;
        new.ports[2] = PortSettings {
            axial_is_y: true,
            invert_axial: true,
            invert_rotation: false,
            resolution_code: 1,
            sample_rate: 80,
        };
        set_settings(&mut board, &new).unwrap();
        assert_eq!(settings(&mut board).unwrap(), new);
    }

    #[test]
    fn settings_out_of_range_are_refused_before_sending() {
        let mut board = FirmwareLike::new();
        let mut bad = BoardSettings::DEFAULT;
        bad.ports[7].sample_rate = 150;
        let err = set_settings(&mut board, &bad).unwrap_err();
        assert!(matches!(
            err,
            BoardError::Malformed(DecodeError::BadField {
                field: "sample_rate",
                paddle: Some(7),
                value: 150
            })
        ));
        assert_eq!(board.writes, 0);
    }

    #[test]
    fn the_bootloader_command_reaches_the_board() {
        let mut board = FirmwareLike::new();
        enter_bootloader(&mut board).unwrap();
        assert!(board.bootloader);
    }

    #[test]
    fn an_old_board_says_it_has_no_feature_reports() {
        assert!(matches!(
            device_info(&mut OldBoard),
            Err(BoardError::FeatureUnsupported)
        ));
        assert!(matches!(
            set_settings(&mut OldBoard, &BoardSettings::DEFAULT),
            Err(BoardError::FeatureUnsupported)
        ));
    }

    #[test]
    fn a_wrong_or_garbled_answer_is_malformed() {
        // Settings where device info was selected.
        let settings = FeatureReport::Settings(BoardSettings::DEFAULT).to_bytes();
        assert!(matches!(
            device_info(&mut Answers(settings.to_vec())),
            Err(BoardError::Malformed(DecodeError::BadField {
                field: "kind",
                ..
            }))
        ));
        // Another port's diagnostics.
        let other = FeatureReport::PortDiagnostics(PortDiagnostics {
            port: 3,
            ..PortDiagnostics::default()
        })
        .to_bytes();
        assert!(matches!(
            port_diagnostics(&mut Answers(other.to_vec()), 2),
            Err(BoardError::Malformed(DecodeError::BadField {
                field: "port",
                ..
            }))
        ));
        // Too short, and noise.
        assert!(matches!(
            settings_read_of(vec![1, 3, 0]),
            Err(BoardError::Malformed(DecodeError::WrongLength { .. }))
        ));
        assert!(matches!(
            settings_read_of(vec![0xEE; FEATURE_REPORT_LEN]),
            Err(BoardError::Malformed(DecodeError::UnknownVersion { .. }))
        ));
    }

    fn settings_read_of(bytes: Vec<u8>) -> Result<BoardSettings, BoardError> {
        settings(&mut Answers(bytes))
    }
}

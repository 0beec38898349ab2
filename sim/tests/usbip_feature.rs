//! Feature reports through the USB/IP loopback: the emulated board answers GET_REPORT
//! and SET_REPORT (Feature) as the firmware does — device info, a selected port's
//! diagnostics, settings written and read back, a malformed write STALLed, and
//! EnterBootloader taking the device off the bus.

use foosball_protocol::{
    BoardSettings, FeatureKind, FeatureReport, PortSettings, BOOTLOADER_MAGIC, FEATURE_REPORT_LEN,
    FEATURE_REPORT_VERSION,
};
use std::io::{Read, Write};
use std::net::{SocketAddr, TcpStream};
use std::time::{Duration, Instant};

/// USB/IP status of a stalled URB (`-EPIPE`).
const STALL: i32 = -32;
/// GET_REPORT (Feature, no report id), up to one Feature report.
const GET_FEATURE: [u8; 8] = [0xA1, 0x01, 0x00, 0x03, 0, 0, FEATURE_REPORT_LEN as u8, 0];
/// SET_REPORT (Feature, no report id) of one Feature report.
const SET_FEATURE: [u8; 8] = [0x21, 0x09, 0x00, 0x03, 0, 0, FEATURE_REPORT_LEN as u8, 0];

mod usbip_loopback;
use usbip_loopback::{be32, connect, read_n, Running};

/// A USBIP_CMD_SUBMIT on endpoint 0.
fn submit(seqnum: u32, dir_in: bool, length: u32, setup: [u8; 8], data: &[u8]) -> Vec<u8> {
    let mut m = Vec::new();
    for v in [
        1u32,
        seqnum,
        0x0001_0002,
        u32::from(dir_in),
        0,
        0,
        length,
        0,
        0,
        0,
    ] {
        m.extend_from_slice(&v.to_be_bytes());
    }
    m.extend_from_slice(&setup);
    m.extend_from_slice(data);
    m
}

/// Reads a USBIP_RET_SUBMIT: (status, data).
fn ret_submit(s: &mut TcpStream, seqnum: u32, dir_in: bool) -> (i32, Vec<u8>) {
    let h = read_n(s, 48);
    assert_eq!(be32(&h, 0), 3, "not RET_SUBMIT: {h:?}");
    assert_eq!(be32(&h, 4), seqnum);
    let status = be32(&h, 20) as i32;
    let len = be32(&h, 24) as usize;
    let data = if dir_in { read_n(s, len) } else { Vec::new() };
    (status, data)
}

fn import_request() -> Vec<u8> {
    let mut import = vec![0x01, 0x11, 0x80, 0x03, 0, 0, 0, 0];
    let mut busid = [0u8; 32];
    busid[..3].copy_from_slice(b"1-1");
    import.extend_from_slice(&busid);
    import
}

/// A host attached to the board and configured it, counting its URBs.
struct Host {
    s: TcpStream,
    seqnum: u32,
}

impl Host {
    fn attach(addr: SocketAddr) -> Self {
        let mut s = connect(addr);
        s.write_all(&import_request()).unwrap();
        assert_eq!(be32(&read_n(&mut s, 8 + 0x138), 4), 0, "import status");
        let mut host = Self { s, seqnum: 0 };
        assert_eq!(
            host.control_out([0, 9, 1, 0, 0, 0, 0, 0], &[]),
            0,
            "SET_CONFIGURATION"
        );
        host
    }

    fn next(&mut self) -> u32 {
        self.seqnum += 1;
        self.seqnum
    }

    fn control_out(&mut self, setup: [u8; 8], data: &[u8]) -> i32 {
        let seqnum = self.next();
        self.s
            .write_all(&submit(seqnum, false, data.len() as u32, setup, data))
            .unwrap();
        ret_submit(&mut self.s, seqnum, false).0
    }

    /// GET_REPORT (Feature), decoded.
    fn get_feature(&mut self) -> FeatureReport {
        let seqnum = self.next();
        self.s
            .write_all(&submit(
                seqnum,
                true,
                FEATURE_REPORT_LEN as u32,
                GET_FEATURE,
                &[],
            ))
            .unwrap();
        let (status, data) = ret_submit(&mut self.s, seqnum, true);
        assert_eq!(status, 0, "GET_REPORT (Feature)");
        FeatureReport::decode(&data).unwrap()
    }

    /// SET_REPORT (Feature) of `report`: the URB's status.
    fn set_feature(&mut self, report: &FeatureReport) -> i32 {
        self.control_out(SET_FEATURE, &report.to_bytes())
    }
}

fn device_info(host: &mut Host) -> foosball_protocol::DeviceInfo {
    match host.get_feature() {
        FeatureReport::DeviceInfo(info) => info,
        other => panic!("expected device info, got {other:?}"),
    }
}

#[test]
fn device_info_is_the_default_and_port_diagnostics_follow_a_select() {
    let server = Running::start();
    let mut host = Host::attach(server.addr);
    let first = device_info(&mut host);
    // Every mouse finishes its 50 ms self-test and initialisation well within 2 s.
    let deadline = Instant::now() + Duration::from_secs(2);
    let mut info = first;
    while info.present_ports != 0xFF && Instant::now() < deadline {
        std::thread::sleep(Duration::from_millis(20));
        info = device_info(&mut host);
    }
    assert_eq!(info.present_ports, 0xFF, "all eight mice present");
    assert!(info.uptime_us > first.uptime_us, "the uptime advances");
    assert_eq!(
        info.firmware_version,
        [
            env!("CARGO_PKG_VERSION_MAJOR").parse::<u8>().unwrap(),
            env!("CARGO_PKG_VERSION_MINOR").parse::<u8>().unwrap(),
            env!("CARGO_PKG_VERSION_PATCH").parse::<u8>().unwrap(),
        ]
    );
    let select = FeatureReport::Select {
        kind: FeatureKind::PortDiagnostics,
        port: 3,
    };
    assert_eq!(host.set_feature(&select), 0, "Select");
    let FeatureReport::PortDiagnostics(diag) = host.get_feature() else {
        panic!("expected port diagnostics");
    };
    assert_eq!(diag.port, 3);
    assert!(diag.present);
    assert_eq!(diag.device_id, Some(0), "a standard mouse");
    assert!(diag.counters.inits >= 1);
    assert!(diag.counters.frames > 0);
    // The selection stays until the next Select.
    assert!(matches!(
        host.get_feature(),
        FeatureReport::PortDiagnostics(d) if d.port == 3
    ));
    drop(host);
    let board = server.stop();
    assert_eq!(
        Some(diag.counters.inits),
        board
            .firmware()
            .port_diagnostics(3)
            .map(|d| d.counters.inits),
        "no re-initialisation since"
    );
}

#[test]
fn settings_written_are_applied_and_read_back() {
    let server = Running::start();
    let mut host = Host::attach(server.addr);
    let select = FeatureReport::Select {
        kind: FeatureKind::Settings,
        port: 0,
    };
    assert_eq!(host.set_feature(&select), 0);
    assert_eq!(
        host.get_feature(),
        FeatureReport::Settings(BoardSettings::DEFAULT)
    );
    let mut settings = BoardSettings::DEFAULT;
    settings.ports[5] = PortSettings {
        axial_is_y: true,
        invert_axial: false,
        invert_rotation: true,
        resolution_code: 1,
        sample_rate: 100,
    };
    assert_eq!(host.set_feature(&FeatureReport::Settings(settings)), 0);
    assert_eq!(host.get_feature(), FeatureReport::Settings(settings));
    drop(host);
    let board = server.stop();
    assert_eq!(board.firmware().settings(), settings);
}

#[test]
fn a_malformed_feature_write_stalls_and_the_pipe_works_after() {
    let server = Running::start();
    let mut host = Host::attach(server.addr);
    let mut wrong_version = FeatureReport::EnterBootloader.to_bytes();
    wrong_version[0] = FEATURE_REPORT_VERSION + 1;
    assert_eq!(host.control_out(SET_FEATURE, &wrong_version), STALL);
    let mut bad_magic = FeatureReport::EnterBootloader.to_bytes();
    bad_magic[2] = BOOTLOADER_MAGIC[0] ^ 1;
    assert_eq!(host.control_out(SET_FEATURE, &bad_magic), STALL);
    // A kind only the board sends.
    let info = FeatureReport::DeviceInfo(Default::default());
    assert_eq!(host.set_feature(&info), STALL);
    // A Select of diagnostics for port 8 (out of range).
    let mut select = FeatureReport::Select {
        kind: FeatureKind::PortDiagnostics,
        port: 0,
    }
    .to_bytes();
    select[3] = 8;
    assert_eq!(host.control_out(SET_FEATURE, &select), STALL);
    // Short of a report.
    let short = [0x21, 0x09, 0x00, 0x03, 0, 0, 3, 0];
    assert_eq!(host.control_out(short, &[1, 3, 0]), STALL);
    // Nothing changed: device info is still selected and the device still answers.
    device_info(&mut host);
    drop(host);
    let board = server.stop();
    assert_eq!(board.firmware().settings(), BoardSettings::DEFAULT);
}

#[test]
fn enter_bootloader_takes_the_device_off_the_bus() {
    let server = Running::start();
    let mut host = Host::attach(server.addr);
    assert_eq!(host.set_feature(&FeatureReport::EnterBootloader), 0);
    let mut rest = Vec::new();
    host.s.read_to_end(&mut rest).unwrap();
    assert!(
        rest.is_empty(),
        "the connection closes after the status stage"
    );
    // The device list is empty and an import is refused.
    let mut s = connect(server.addr);
    s.write_all(&[0x01, 0x11, 0x80, 0x05, 0, 0, 0, 0]).unwrap();
    let mut reply = Vec::new();
    s.read_to_end(&mut reply).unwrap();
    assert_eq!(be32(&reply, 4), 0, "status");
    assert_eq!(be32(&reply, 8), 0, "no device");
    let mut s = connect(server.addr);
    s.write_all(&import_request()).unwrap();
    let mut reply = Vec::new();
    s.read_to_end(&mut reply).unwrap();
    assert_ne!(be32(&reply, 4), 0, "import refused");
    server.stop();
}

//! The USB/IP server on loopback: device list with our ids, import, enumeration,
//! interrupt IN reports and OUT reports — what the kernel's vhci-hcd would do, without
//! the kernel module.

use foosball_protocol::usb::{HID_REPORT_DESCRIPTOR, PRODUCT_ID, VENDOR_ID};
use foosball_protocol::{HapticPulse, InReportV2, OutReport, IN_REPORT_V2_LEN};
use std::io::{Read, Write};
use std::net::TcpStream;
use std::time::Duration;

mod usbip_loopback;
use usbip_loopback::{be16, be32, connect, read_n, Running};

/// A USBIP_CMD_SUBMIT.
fn submit(seqnum: u32, dir_in: bool, ep: u32, length: u32, setup: [u8; 8], data: &[u8]) -> Vec<u8> {
    let mut m = Vec::new();
    for v in [
        1u32,
        seqnum,
        0x0001_0001,
        u32::from(dir_in),
        ep,
        0,
        length,
        0,
        u32::MAX,
        1,
    ] {
        m.extend_from_slice(&v.to_be_bytes());
    }
    m.extend_from_slice(&setup);
    m.extend_from_slice(data);
    m
}

/// Reads a USBIP_RET_SUBMIT: (seqnum, status, data).
fn ret_submit(s: &mut TcpStream, dir_in: bool) -> (u32, i32, Vec<u8>) {
    let h = read_n(s, 48);
    assert_eq!(be32(&h, 0), 3, "not RET_SUBMIT: {h:?}");
    let status = be32(&h, 20) as i32;
    let len = be32(&h, 24) as usize;
    let data = if dir_in { read_n(s, len) } else { Vec::new() };
    (be32(&h, 4), status, data)
}

fn control_in(s: &mut TcpStream, seqnum: u32, setup: [u8; 8]) -> (i32, Vec<u8>) {
    let len = u32::from(u16::from_le_bytes([setup[6], setup[7]]));
    s.write_all(&submit(seqnum, true, 0, len, setup, &[]))
        .unwrap();
    let (seq, status, data) = ret_submit(s, true);
    assert_eq!(seq, seqnum);
    (status, data)
}

#[test]
fn devlist_answers_with_our_vendor_and_product_id() {
    let server = Running::start();
    let mut s = connect(server.addr);
    s.write_all(&[0x01, 0x11, 0x80, 0x05, 0, 0, 0, 0]).unwrap();
    let mut reply = Vec::new();
    s.read_to_end(&mut reply).unwrap(); // the server closes after the list
    assert_eq!(be16(&reply, 2), 0x0005);
    assert_eq!(be32(&reply, 4), 0, "status");
    assert_eq!(be32(&reply, 8), 1, "one device");
    assert_eq!(&reply[0x10C..0x110], b"1-1\0");
    assert_eq!(be16(&reply, 0x138), VENDOR_ID);
    assert_eq!(be16(&reply, 0x13A), PRODUCT_ID);
    assert_eq!(reply[0x144], 3, "HID interface");
    server.stop();
}

#[test]
fn import_enumerate_stream_reports_and_take_out_reports() {
    let server = Running::start();
    // A wrong bus id is refused.
    let mut s = connect(server.addr);
    let mut import = vec![0x01, 0x11, 0x80, 0x03, 0, 0, 0, 0];
    let mut busid = [0u8; 32];
    busid[..3].copy_from_slice(b"9-9");
    import.extend_from_slice(&busid);
    s.write_all(&import).unwrap();
    let reply = read_n(&mut s, 8);
    assert_eq!(be32(&reply, 4), 1);

    let mut s = connect(server.addr);
    busid[..3].copy_from_slice(b"1-1");
    import[8..].copy_from_slice(&busid);
    s.write_all(&import).unwrap();
    let reply = read_n(&mut s, 8 + 0x138);
    assert_eq!(be32(&reply, 4), 0);
    assert_eq!(be16(&reply, 0x134), VENDOR_ID);
    assert_eq!(be16(&reply, 0x136), PRODUCT_ID);

    // Enumeration as the kernel does it.
    let (status, dev) = control_in(&mut s, 1, [0x80, 6, 0, 1, 0, 0, 18, 0]);
    assert_eq!(status, 0);
    assert_eq!(u16::from_le_bytes([dev[8], dev[9]]), VENDOR_ID);
    assert_eq!(u16::from_le_bytes([dev[10], dev[11]]), PRODUCT_ID);
    let (_, head) = control_in(&mut s, 2, [0x80, 6, 0, 2, 0, 0, 9, 0]);
    let total = u16::from_le_bytes([head[2], head[3]]);
    let (_, config) = control_in(&mut s, 3, [0x80, 6, 0, 2, 0, 0, total as u8, 0]);
    assert_eq!(config.len(), usize::from(total));
    let (_, product) = control_in(&mut s, 4, [0x80, 6, 2, 3, 9, 4, 255, 0]);
    assert!(product.len() > 2);
    let (status, _) = control_in(&mut s, 5, [0x80, 6, 0, 6, 0, 0, 10, 0]);
    assert_eq!(status, -32, "device qualifier stalls (full speed only)");
    s.write_all(&submit(6, false, 0, 0, [0, 9, 1, 0, 0, 0, 0, 0], &[]))
        .unwrap();
    assert_eq!(ret_submit(&mut s, false).1, 0);
    let (_, report_desc) = control_in(&mut s, 7, [0x81, 6, 0, 0x22, 0, 0, 255, 0]);
    assert_eq!(report_desc, HID_REPORT_DESCRIPTOR);

    // Interrupt IN: consecutive reports, decodable, in sequence.
    let mut last = None;
    for seq in 100..150u32 {
        s.write_all(&submit(seq, true, 1, 64, [0; 8], &[])).unwrap();
        let (got, status, data) = ret_submit(&mut s, true);
        assert_eq!((got, status, data.len()), (seq, 0, IN_REPORT_V2_LEN));
        let report = InReportV2::decode(&data).unwrap().report;
        if let Some(prev) = last {
            assert!(report.sequence > prev, "{} after {prev}", report.sequence);
        }
        last = Some(report.sequence);
    }

    // Interrupt OUT: a haptic pulse; a malformed report stalls.
    let mut out = OutReport::default();
    out.haptics[4] = HapticPulse {
        strength: 128,
        duration_ms: 20,
    };
    let bytes = out.to_bytes();
    s.write_all(&submit(200, false, 1, bytes.len() as u32, [0; 8], &bytes))
        .unwrap();
    assert_eq!(ret_submit(&mut s, false).1, 0);
    s.write_all(&submit(201, false, 1, 3, [0; 8], &[9, 9, 9]))
        .unwrap();
    assert_eq!(ret_submit(&mut s, false).1, -32);

    // Unlink a pending IN URB.
    s.write_all(&submit(300, true, 1, 64, [0; 8], &[])).unwrap();
    let mut unlink = Vec::new();
    for v in [2u32, 301, 0x0001_0001, 0, 1, 300] {
        unlink.extend_from_slice(&v.to_be_bytes());
    }
    unlink.extend_from_slice(&[0; 24]);
    s.write_all(&unlink).unwrap();
    // Either the URB completed first (RET_SUBMIT 300, then RET_UNLINK status 0) or it
    // was unlinked (RET_UNLINK status -ECONNRESET).
    let h = read_n(&mut s, 48);
    if be32(&h, 0) == 3 {
        assert_eq!(be32(&h, 4), 300);
        read_n(&mut s, be32(&h, 24) as usize);
        let h = read_n(&mut s, 48);
        assert_eq!((be32(&h, 0), be32(&h, 4), be32(&h, 20)), (4, 301, 0));
    } else {
        assert_eq!(
            (be32(&h, 0), be32(&h, 4), be32(&h, 20) as i32),
            (4, 301, -104)
        );
    }

    // Garbage closes the connection, not the server.
    s.write_all(&[0xDE; 48]).unwrap();
    let mut rest = Vec::new();
    let _ = s.read_to_end(&mut rest);
    let mut s = connect(server.addr);
    s.write_all(&[0x01, 0x11, 0x80, 0x05, 0, 0, 0, 0]).unwrap();
    let mut reply = Vec::new();
    s.read_to_end(&mut reply).unwrap();
    assert_eq!(be16(&reply, 0x138), VENDOR_ID);

    let board = server.stop();
    let pulses = board.haptic_events();
    assert_eq!(pulses.len(), 1);
    assert_eq!(
        (pulses[0].paddle, pulses[0].strength, pulses[0].duration_ms),
        (4, 128, 20)
    );
    assert_eq!(board.out_report_counts(), (1, 1));
}

/// HID class requests through the loopback: GET_REPORT gives the latest IN report, a
/// SET_REPORT with a valid OUT report reaches the board, a malformed one STALLs, and
/// the control pipe works again after the stall.
#[test]
fn hid_class_requests_get_and_set_report() {
    let server = Running::start();
    let mut s = connect(server.addr);
    let mut import = vec![0x01, 0x11, 0x80, 0x03, 0, 0, 0, 0];
    let mut busid = [0u8; 32];
    busid[..3].copy_from_slice(b"1-1");
    import.extend_from_slice(&busid);
    s.write_all(&import).unwrap();
    assert_eq!(be32(&read_n(&mut s, 8 + 0x138), 4), 0);
    s.write_all(&submit(1, false, 0, 0, [0, 9, 1, 0, 0, 0, 0, 0], &[]))
        .unwrap();
    assert_eq!(ret_submit(&mut s, false).1, 0, "SET_CONFIGURATION");
    // Let a few reports be made.
    std::thread::sleep(Duration::from_millis(20));
    let (status, report) = control_in(&mut s, 2, [0xA1, 1, 0, 1, 0, 0, 64, 0]);
    assert_eq!(status, 0, "GET_REPORT");
    assert_eq!(report.len(), IN_REPORT_V2_LEN);
    assert!(InReportV2::decode(&report).is_ok());
    let mut out = OutReport::default();
    out.haptics[2] = HapticPulse {
        strength: 77,
        duration_ms: 5,
    };
    let bytes = out.to_bytes();
    let len = bytes.len() as u8;
    let set_report = [0x21, 9, 0, 2, 0, 0, len, 0];
    s.write_all(&submit(3, false, 0, u32::from(len), set_report, &bytes))
        .unwrap();
    assert_eq!(ret_submit(&mut s, false).1, 0, "SET_REPORT");
    s.write_all(&submit(
        4,
        false,
        0,
        3,
        [0x21, 9, 0, 2, 0, 0, 3, 0],
        &[9, 9, 9],
    ))
    .unwrap();
    assert_eq!(
        ret_submit(&mut s, false).1,
        -32,
        "malformed SET_REPORT stalls"
    );
    let (status, config) = control_in(&mut s, 5, [0x80, 8, 0, 0, 0, 0, 1, 0]);
    assert_eq!(
        (status, config),
        (0, vec![1]),
        "GET_CONFIGURATION after the stall"
    );
    drop(s);
    let board = server.stop();
    let pulses = board.haptic_events();
    assert_eq!(pulses.len(), 1);
    assert_eq!((pulses[0].paddle, pulses[0].strength), (2, 77));
    assert_eq!(board.out_report_counts(), (1, 0));
}

//! The USB/IP server on loopback, timed as a client sees it (one JSON line):
//!
//! * `enumeration_ms_median`: connect, OP_REQ_IMPORT and the control transfers a
//!   Linux host makes to enumerate the board (device descriptor, configuration
//!   descriptor head and whole, the language list and three strings, SET_CONFIGURATION,
//!   the HID report descriptor), median of [`ENUMERATIONS`] runs, ms;
//! * `control_round_trip_us_median`: one GET_REPORT control transfer (input report)
//!   from CMD_SUBMIT to RET_SUBMIT, median of [`ROUND_TRIPS`], µs;
//! * `in_urb_us_median`, `in_urb_us_p99`: one interrupt IN URB from CMD_SUBMIT to its
//!   RET_SUBMIT with an IN report, [`ROUND_TRIPS`] back to back, µs. Reports are made
//!   once per millisecond in real time, so this includes the wait for the next one.
//!
//! `cargo bench -p foosball-sim --bench usbip_loopback`

use foosball_sim::board::{BoardConfig, EmulatedBoard};
use foosball_sim::motion::Stationary;
use foosball_sim::usbip::UsbIpServer;
use std::io::{Read, Write};
use std::net::{SocketAddr, TcpStream};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

const ENUMERATIONS: usize = 50;
const ROUND_TRIPS: usize = 2_000;

fn be32(b: &[u8], at: usize) -> u32 {
    u32::from_be_bytes([b[at], b[at + 1], b[at + 2], b[at + 3]])
}

fn submit(seqnum: u32, dir_in: bool, ep: u32, length: u32, setup: [u8; 8]) -> Vec<u8> {
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
    m
}

/// Sends one URB and reads its RET_SUBMIT; the status.
fn urb(s: &mut TcpStream, seqnum: u32, dir_in: bool, ep: u32, setup: [u8; 8], length: u32) -> i32 {
    s.write_all(&submit(seqnum, dir_in, ep, length, setup))
        .unwrap();
    let mut h = [0u8; 48];
    s.read_exact(&mut h).unwrap();
    assert_eq!(be32(&h, 0), 3);
    let mut data = vec![0; if dir_in { be32(&h, 24) as usize } else { 0 }];
    s.read_exact(&mut data).unwrap();
    be32(&h, 20) as i32
}

fn import(addr: SocketAddr) -> TcpStream {
    let mut s = TcpStream::connect(addr).unwrap();
    s.set_nodelay(true).unwrap();
    s.set_read_timeout(Some(Duration::from_secs(5))).unwrap();
    let mut m = vec![0x01, 0x11, 0x80, 0x03, 0, 0, 0, 0];
    let mut busid = [0u8; 32];
    busid[..3].copy_from_slice(b"1-1");
    m.extend_from_slice(&busid);
    s.write_all(&m).unwrap();
    let mut reply = vec![0; 8 + 0x138];
    s.read_exact(&mut reply).unwrap();
    assert_eq!(be32(&reply, 4), 0, "import refused");
    s
}

fn enumerate(s: &mut TcpStream) {
    let transfers: [[u8; 8]; 8] = [
        [0x80, 6, 0, 1, 0, 0, 18, 0],
        [0x80, 6, 0, 2, 0, 0, 9, 0],
        [0x80, 6, 0, 2, 0, 0, 255, 0],
        [0x80, 6, 0, 3, 0, 0, 255, 0],
        [0x80, 6, 1, 3, 9, 4, 255, 0],
        [0x80, 6, 2, 3, 9, 4, 255, 0],
        [0x80, 6, 3, 3, 9, 4, 255, 0],
        [0x81, 6, 0, 0x22, 0, 0, 255, 0],
    ];
    for (i, setup) in transfers.iter().enumerate() {
        assert_eq!(
            urb(s, i as u32 + 1, true, 0, *setup, u32::from(setup[6])),
            0
        );
    }
    assert_eq!(urb(s, 20, false, 0, [0, 9, 1, 0, 0, 0, 0, 0], 0), 0);
}

fn median(v: &mut [f64]) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

fn main() {
    let mut server = UsbIpServer::bind(SocketAddr::from(([127, 0, 0, 1], 0))).unwrap();
    let addr = server.local_addr().unwrap();
    let stop = Arc::new(AtomicBool::new(false));
    let flag = Arc::clone(&stop);
    let thread = std::thread::spawn(move || {
        let mut board = EmulatedBoard::new(BoardConfig::default(), Box::new(Stationary)).unwrap();
        server.run(&mut board, &flag).unwrap();
    });
    let mut enumerations = Vec::new();
    for _ in 0..ENUMERATIONS {
        let t0 = Instant::now();
        let mut s = import(addr);
        enumerate(&mut s);
        enumerations.push(t0.elapsed().as_secs_f64() * 1e3);
        drop(s);
        // Let the server see the connection close before the next import.
        std::thread::sleep(Duration::from_millis(5));
    }
    let mut s = import(addr);
    enumerate(&mut s);
    let mut control = Vec::new();
    for i in 0..ROUND_TRIPS {
        let t0 = Instant::now();
        let status = urb(
            &mut s,
            1000 + i as u32,
            true,
            0,
            [0xA1, 1, 0, 1, 0, 0, 64, 0],
            64,
        );
        control.push(t0.elapsed().as_secs_f64() * 1e6);
        assert_eq!(status, 0, "GET_REPORT");
    }
    let mut in_urbs = Vec::new();
    for i in 0..ROUND_TRIPS {
        let t0 = Instant::now();
        let status = urb(&mut s, 10_000 + i as u32, true, 1, [0; 8], 64);
        in_urbs.push(t0.elapsed().as_secs_f64() * 1e6);
        assert_eq!(status, 0, "interrupt IN");
    }
    stop.store(true, Ordering::Relaxed);
    thread.join().unwrap();
    let p99 = {
        in_urbs.sort_by(f64::total_cmp);
        in_urbs[(in_urbs.len() * 99) / 100]
    };
    println!(
        "{{\"enumeration_ms_median\":{:.3},\"control_round_trip_us_median\":{:.1},\"in_urb_us_median\":{:.1},\"in_urb_us_p99\":{:.1},\"enumerations\":{ENUMERATIONS},\"round_trips\":{ROUND_TRIPS}}}",
        median(&mut enumerations),
        median(&mut control),
        median(&mut in_urbs),
        p99
    );
}

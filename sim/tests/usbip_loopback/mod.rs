//! The USB/IP server on loopback for the tests: a server thread over an emulated board
//! (8 stationary mice, 50 ms self-test), a client connection, and big-endian field reads.
#![allow(dead_code)]

use foosball_sim::board::{BoardConfig, EmulatedBoard};
use foosball_sim::motion::Stationary;
use foosball_sim::usbip::UsbIpServer;
use std::io::Read;
use std::net::{SocketAddr, TcpStream};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::thread::JoinHandle;
use std::time::Duration;

/// A server running on its own thread; stopped when dropped.
pub struct Running {
    pub addr: SocketAddr,
    stop: Arc<AtomicBool>,
    thread: Option<JoinHandle<EmulatedBoard>>,
}

impl Running {
    /// Binds on an ephemeral loopback port and serves the emulated board.
    pub fn start() -> Self {
        let mut server = UsbIpServer::bind(SocketAddr::from(([127, 0, 0, 1], 0))).unwrap();
        let addr = server.local_addr().unwrap();
        let stop = Arc::new(AtomicBool::new(false));
        let flag = stop.clone();
        let mut config = BoardConfig::default();
        config.mouse.self_test_us = 50_000;
        let mut board = EmulatedBoard::new(config, Box::new(Stationary)).unwrap();
        let thread = std::thread::spawn(move || {
            server.run(&mut board, &flag).unwrap();
            board
        });
        Self {
            addr,
            stop,
            thread: Some(thread),
        }
    }

    /// Stops the server and gives the board back.
    pub fn stop(mut self) -> EmulatedBoard {
        self.stop.store(true, Ordering::Relaxed);
        self.thread.take().unwrap().join().unwrap()
    }
}

impl Drop for Running {
    fn drop(&mut self) {
        self.stop.store(true, Ordering::Relaxed);
    }
}

/// A client connection with a 5 s read timeout.
pub fn connect(addr: SocketAddr) -> TcpStream {
    let s = TcpStream::connect(addr).unwrap();
    s.set_read_timeout(Some(Duration::from_secs(5))).unwrap();
    s
}

/// Reads exactly `n` bytes.
pub fn read_n(s: &mut TcpStream, n: usize) -> Vec<u8> {
    let mut buf = vec![0; n];
    s.read_exact(&mut buf).unwrap();
    buf
}

/// Big-endian u16 at `at`.
pub fn be16(b: &[u8], at: usize) -> u16 {
    u16::from_be_bytes([b[at], b[at + 1]])
}

/// Big-endian u32 at `at`.
pub fn be32(b: &[u8], at: usize) -> u32 {
    u32::from_be_bytes([b[at], b[at + 1], b[at + 2], b[at + 3]])
}

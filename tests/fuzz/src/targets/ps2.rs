//! PS/2 frames and the sensor board's mouse drivers, fed arbitrary wire events.
//!
//! The input is an event script (see [`Op`] for the encoding; [`Script`] writes one):
//! frames with any 11 bits, well-framed bytes (often the replies a mouse gives: `0xFA`,
//! `0xAA`, `0x00`, `0xFE`, `0xFC`, packet bytes), polls, send outcomes, time jumps (µs,
//! from any start), stuck lines, receiver stalls, report takes and snapshots (sent or
//! not), on any port number (out-of-range ones included).
//! Properties: frame decoding agrees with encoding; the board never panics; every IN
//! report it builds decodes, says `PRESENT` exactly for the streaming ports, and
//! sequence numbers go up by one per report.

use super::Verdict;
use foosball_protocol::{InReport, PaddleStatus};
use sensor_board::{BoardConfig, HostFrame, LineFault, Ps2Frame, SendError, SensorBoard};

/// Bytes a mouse sends most: ACK, resend, error, self-test passed, device id, and
/// first bytes of movement packets (bit 3 set).
const REPLIES: [u8; 7] = [0xFA, 0xFE, 0xFC, 0xAA, 0x00, 0x08, 0x28];

/// One event of a script. Encoding: 8 bytes of start time (µs, little-endian), then
/// per event an op byte (`% 11` picks the op), a port byte (`% 10`: ports 8 and 9 do
/// not exist and must be ignored) and the op's fields. Missing bytes read as zero.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Op {
    /// 0: a frame with these raw bits (2 bytes, little-endian).
    Frame(u16),
    /// 1: a well-framed mouse reply, [`REPLIES`]`[i % 7]` (1 byte).
    Reply(u8),
    /// 2: any well-framed byte (1 byte).
    Byte(u8),
    /// 3: poll the port (the command it returns is checked, not sent).
    Poll,
    /// 4: the outcome of sending a command: 0 ok, 1 no clock, 2 timeout, 3 no ack
    /// (1 byte, `% 4`).
    Sent(u8),
    /// 5: time passes, then every port is polled: kind byte `% 4` — 0: 1 ms, 1: a
    /// `u16` of µs, 2: a `u32`, 3: a `u64` (saturating).
    Wait(u64),
    /// 6: take an IN report.
    Report,
    /// 7: a movement packet, well framed (3 bytes; bit 3 of the first is forced).
    Packet([u8; 3]),
    /// 8: a line found stuck low: 0 clock, 1 data (1 byte, `% 2`).
    LineFault(u8),
    /// 9: the port's receiver overflowed and was restarted.
    RxStall,
    /// 10: a report snapshot, committed (sent) when the byte is even (1 byte).
    Snapshot(u8),
}

/// Reads little-endian fields off the front of the input; missing bytes are zero.
struct Reader<'a>(&'a [u8]);

impl Reader<'_> {
    fn bytes<const N: usize>(&mut self) -> [u8; N] {
        let mut out = [0u8; N];
        let n = N.min(self.0.len());
        out[..n].copy_from_slice(&self.0[..n]);
        self.0 = &self.0[n..];
        out
    }

    fn u8(&mut self) -> u8 {
        self.bytes::<1>()[0]
    }
}

/// Writes an event script (the seeds of the committed corpus).
#[derive(Debug, Clone, Default)]
pub(crate) struct Script(Vec<u8>);

impl Script {
    /// A script starting at `start_us`.
    pub(crate) fn starting_at(start_us: u64) -> Self {
        Self(start_us.to_le_bytes().to_vec())
    }

    /// Appends `op` on `port`.
    pub(crate) fn op(mut self, port: u8, op: Op) -> Self {
        let out = &mut self.0;
        let code = match op {
            Op::Frame(_) => 0,
            Op::Reply(_) => 1,
            Op::Byte(_) => 2,
            Op::Poll => 3,
            Op::Sent(_) => 4,
            Op::Wait(_) => 5,
            Op::Report => 6,
            Op::Packet(_) => 7,
            Op::LineFault(_) => 8,
            Op::RxStall => 9,
            Op::Snapshot(_) => 10,
        };
        out.extend([code, port]);
        match op {
            Op::Frame(raw) => out.extend(raw.to_le_bytes()),
            Op::Reply(i) | Op::Byte(i) | Op::Sent(i) | Op::LineFault(i) | Op::Snapshot(i) => {
                out.push(i)
            }
            Op::Wait(1_000) => out.push(0),
            Op::Wait(us) => {
                out.push(3);
                out.extend(us.to_le_bytes());
            }
            Op::Packet(bytes) => out.extend(bytes),
            Op::Poll | Op::Report | Op::RxStall => {}
        }
        self
    }

    /// The script's bytes.
    pub(crate) fn into_bytes(self) -> Vec<u8> {
        self.0
    }
}

/// Plays the script in `input` on a fresh board, checking as it goes.
pub(crate) fn play(input: &[u8]) -> SensorBoard {
    let mut r = Reader(input);
    let mut board = SensorBoard::new(BoardConfig::DEFAULT);
    let mut now_us = u64::from_le_bytes(r.bytes());
    let mut next_sequence = board.next_sequence();
    while !r.0.is_empty() {
        let op = r.u8() % 11;
        let port = usize::from(r.u8() % 10);
        match op {
            0 => {
                let raw = u16::from_le_bytes(r.bytes());
                check_frames(raw);
                board.on_frame(port, now_us, Ps2Frame::from_raw(raw));
            }
            1 => {
                let reply = REPLIES[usize::from(r.u8() % 7)];
                board.on_frame(port, now_us, Ps2Frame::encode(reply));
            }
            2 => {
                let byte = r.u8();
                board.on_frame(port, now_us, Ps2Frame::encode(byte));
            }
            3 => {
                if let Some(command) = board.poll(port, now_us) {
                    let frame = HostFrame::encode(command);
                    assert_eq!(frame.decode(), Ok(command), "host frame of {command:#04x}");
                }
            }
            4 => {
                let result = match r.u8() % 4 {
                    0 => Ok(()),
                    1 => Err(SendError::NoClock),
                    2 => Err(SendError::Timeout),
                    _ => Err(SendError::NoAck),
                };
                board.on_command_sent(port, now_us, result);
            }
            5 => {
                let dt = match r.u8() % 4 {
                    0 => 1_000,
                    1 => u64::from(u16::from_le_bytes(r.bytes())),
                    2 => u64::from(u32::from_le_bytes(r.bytes())),
                    _ => u64::from_le_bytes(r.bytes()),
                };
                now_us = now_us.saturating_add(dt);
                for p in 0..sensor_board::PORTS {
                    let _ = board.poll(p, now_us);
                }
            }
            6 => {
                let report = board.take_report(now_us);
                check_report(&board, &report, next_sequence);
                next_sequence = next_sequence.wrapping_add(1);
                assert_eq!(board.next_sequence(), next_sequence, "next sequence");
            }
            8 => {
                let fault = if r.u8() % 2 == 0 {
                    LineFault::ClockStuckLow
                } else {
                    LineFault::DataStuckLow
                };
                board.on_line_fault(port, now_us, fault);
            }
            9 => board.on_rx_stall(port, now_us),
            10 => {
                let report = board.snapshot_report(now_us);
                check_report(&board, &report, next_sequence);
                if r.u8() % 2 == 0 {
                    board.commit(&report);
                    next_sequence = next_sequence.wrapping_add(1);
                }
                assert_eq!(board.next_sequence(), next_sequence, "next sequence");
            }
            _ => {
                let bytes: [u8; 3] = r.bytes();
                for b in [bytes[0] | 0x08, bytes[1], bytes[2]] {
                    board.on_frame(port, now_us, Ps2Frame::encode(b));
                }
            }
        }
    }
    board
}

pub(super) fn run(input: &[u8]) -> Verdict {
    play(input);
    Verdict::Accepted
}

/// A report the board built: it carries the expected sequence number, decodes, and
/// says `PRESENT` exactly for the streaming ports.
fn check_report(board: &SensorBoard, report: &InReport, sequence: u16) {
    assert_eq!(report.sequence, sequence, "report sequence");
    let decoded = InReport::decode(&report.to_bytes());
    assert_eq!(decoded, Ok(*report), "the board's report does not decode");
    for (p, paddle) in report.paddles.iter().enumerate() {
        let present = paddle.status.contains(PaddleStatus::PRESENT);
        assert_eq!(present, board.is_present(p), "port {p} presence");
    }
}

/// Decoding and encoding of both frame kinds agree for the raw bits `raw`.
fn check_frames(raw: u16) {
    let frame = Ps2Frame::from_raw(raw);
    assert_eq!(frame.raw(), raw & 0x7FF, "device frame keeps 11 bits");
    if let Ok(byte) = frame.decode() {
        assert_eq!(Ps2Frame::encode(byte), frame, "device frame {raw:#06x}");
    }
    let host = HostFrame::from_raw(raw);
    assert_eq!(host.raw(), raw & 0x3FF, "host frame keeps 10 bits");
    if let Ok(byte) = host.decode() {
        assert_eq!(HostFrame::encode(byte), host, "host frame {raw:#06x}");
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn seed(name: &str) -> Vec<u8> {
        crate::seeds::seeds("ps2")
            .into_iter()
            .find(|(n, _)| n == name)
            .map(|(_, bytes)| bytes)
            .unwrap_or_else(|| panic!("no seed {name}"))
    }

    #[test]
    fn the_handshake_seed_brings_every_mouse_up() {
        // The script encoding and the driver agree: the seed's replies take all eight
        // drivers through initialisation to streaming.
        let board = play(&seed("valid-handshake-all-ports"));
        assert_eq!(board.present_mask(), 0xFF);
    }

    #[test]
    fn the_streaming_seed_delivers_its_packets() {
        let board = play(&seed("valid-streaming"));
        assert_eq!(board.present_mask(), 0xFF);
        let packets: u32 = (0..8)
            .filter_map(|p| board.driver(p))
            .map(|d| d.stats().packets)
            .sum();
        assert_eq!(packets, 20);
    }

    #[test]
    fn the_line_fault_seed_makes_its_ports_absent_with_the_reason() {
        // A stuck line makes the port absent, and the driver names the fault until a
        // frame arrives again.
        let board = play(&seed("valid-snapshots-and-line-faults"));
        assert!(!board.is_present(5));
        let fault = |p| board.driver(p).and_then(|d| d.line_fault());
        assert_eq!(fault(5), Some(LineFault::ClockStuckLow));
        assert_eq!(fault(6), Some(LineFault::DataStuckLow));
        assert_eq!(board.driver(5).map(|d| d.stats().fifo_stalls), Some(1));
    }

    #[test]
    fn the_unplugged_seed_loses_its_mouse() {
        let board = play(&seed("valid-unplugged"));
        assert_eq!(board.present_mask() & (1 << 4), 0);
    }
}

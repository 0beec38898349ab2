//! Socket frames: the emulator stream, split into arbitrary reads.
//!
//! Input layout: byte 0 is a count `k`, the next `k` bytes are the sizes of the first
//! `k` reads (the rest of the stream arrives in one read), everything after is the
//! stream. Properties: the reader never buffers more than one frame's worth of bytes
//! beyond what was pushed and not yet framed; the messages it yields re-encode to
//! exactly the bytes it consumed; after an error it keeps returning that error; IN
//! report payloads go through the [`ReportReceiver`], whose counters add up.

use super::Verdict;
use board_link::socket_wire::{FrameReader, Message, MAX_FRAME_LEN};
use board_link::ReportReceiver;

pub(super) fn run(input: &[u8]) -> Verdict {
    let Some((&k, rest)) = input.split_first() else {
        return Verdict::Rejected;
    };
    let k = usize::from(k).min(rest.len());
    let (sizes, stream) = rest.split_at(k);
    let mut reads: Vec<&[u8]> = Vec::new();
    let mut left = stream;
    for &size in sizes {
        let (chunk, tail) = left.split_at(usize::from(size).min(left.len()));
        reads.push(chunk);
        left = tail;
    }
    reads.push(left);

    let mut reader = FrameReader::new();
    let mut receiver = ReportReceiver::new();
    let mut reencoded = Vec::new();
    let mut pushed = 0usize;
    let (mut good, mut bad) = (0u64, 0u64);
    for chunk in reads {
        reader.push(chunk);
        pushed += chunk.len();
        loop {
            match reader.next_message() {
                Ok(Some(message)) => {
                    message
                        .encode_into(&mut reencoded)
                        .expect("a decoded message encodes");
                    if let Message::InReport(bytes) = &message {
                        match receiver.accept(bytes) {
                            Ok(_) => good += 1,
                            Err(_) => bad += 1,
                        }
                    }
                }
                Ok(None) => break,
                Err(error) => {
                    assert_eq!(reader.next_message(), Err(error), "errors are sticky");
                    assert_eq!(stream[..reencoded.len()], reencoded[..], "frames consumed");
                    return Verdict::Rejected;
                }
            }
        }
        assert!(
            reader.buffered() < MAX_FRAME_LEN,
            "{} bytes buffered without a whole frame",
            reader.buffered()
        );
        assert_eq!(
            reencoded.len() + reader.buffered(),
            pushed,
            "bytes accounted"
        );
    }
    assert_eq!(stream[..reencoded.len()], reencoded[..], "frames re-encode");
    let stats = receiver.stats();
    assert_eq!(
        (stats.received, stats.malformed),
        (good, bad),
        "receiver counters"
    );
    Verdict::Accepted
}

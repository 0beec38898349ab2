//! `socket_wire`: framing round trips, typed rejection, arbitrary input.

use std::ffi::OsString;
use std::os::unix::net::UnixStream;

use board_link::socket_wire::{
    bind_listener, socket_path_for, write_message, FrameKind, FrameReader, Message, WireError,
    HEADER_LEN, MAX_PAYLOAD,
};
use foosball_protocol::{HapticPulse, InReport, LedState, OutReport, FORMAT_VERSION};
use proptest::prelude::*;

fn sample_messages() -> Vec<Message> {
    let mut report = InReport {
        sequence: 0xBEEF,
        ..InReport::default()
    };
    report.paddles[7].axial = -1;
    let mut out = OutReport {
        led: LedState::FastBlink,
        ..OutReport::default()
    };
    out.haptics[2] = HapticPulse {
        strength: 200,
        duration_ms: 30,
    };
    vec![
        Message::hello(),
        Message::in_report(&report),
        Message::out_report(&out),
        Message::InReport(Vec::new()),
        Message::OutReport(vec![0xAA; MAX_PAYLOAD]),
    ]
}

fn decode_all(reader: &mut FrameReader) -> Vec<Message> {
    let mut messages = Vec::new();
    while let Some(message) = reader.next_message().expect("valid stream") {
        messages.push(message);
    }
    messages
}

#[test]
fn round_trip_of_every_kind() {
    let messages = sample_messages();
    let mut stream = Vec::new();
    for message in &messages {
        message.encode_into(&mut stream).unwrap();
    }
    let mut reader = FrameReader::new();
    reader.push(&stream);
    assert_eq!(decode_all(&mut reader), messages);
    assert_eq!(reader.buffered(), 0);
}

#[test]
fn layout_is_kind_length_payload() {
    let bytes = Message::hello().encode().unwrap();
    assert_eq!(bytes, vec![0x01, 0x01, FORMAT_VERSION]);
    let report = InReport::default();
    let bytes = Message::in_report(&report).encode().unwrap();
    assert_eq!(bytes[..HEADER_LEN], [0x02, report.to_bytes().len() as u8]);
    assert_eq!(bytes[HEADER_LEN..], report.to_bytes());
    let bytes = Message::out_report(&OutReport::default()).encode().unwrap();
    assert_eq!(bytes[0], 0x03);
}

#[test]
fn partial_reads_wait_for_the_rest() {
    let bytes = Message::in_report(&InReport::default()).encode().unwrap();
    let mut reader = FrameReader::new();
    for &byte in &bytes[..bytes.len() - 1] {
        reader.push(&[byte]);
        assert_eq!(reader.next_message(), Ok(None));
    }
    reader.push(&bytes[bytes.len() - 1..]);
    assert_eq!(
        reader.next_message(),
        Ok(Some(Message::in_report(&InReport::default())))
    );
}

#[test]
fn bad_kinds_and_lengths_are_typed_errors() {
    let mut reader = FrameReader::new();
    reader.push(&[0x00, 0x01, 0x01]);
    assert_eq!(reader.next_message(), Err(WireError::UnknownKind(0)));

    let mut reader = FrameReader::new();
    reader.push(&[0x7F]);
    assert_eq!(
        reader.next_message(),
        Ok(None),
        "kind alone: wait for the length"
    );
    reader.push(&[0x00]);
    assert_eq!(reader.next_message(), Err(WireError::UnknownKind(0x7F)));

    // Rejected from the header alone, before any payload arrives.
    let mut reader = FrameReader::new();
    reader.push(&[0x02, MAX_PAYLOAD as u8 + 1]);
    let error = reader.next_message().unwrap_err();
    assert_eq!(
        error,
        WireError::BadLength {
            kind: FrameKind::InReport,
            len: MAX_PAYLOAD + 1,
            min: 0,
            max: MAX_PAYLOAD
        }
    );
    assert!(error.to_string().contains("bad payload length"), "{error}");

    let mut reader = FrameReader::new();
    reader.push(&[0x01, 0x02, FORMAT_VERSION, 0]);
    assert!(matches!(
        reader.next_message(),
        Err(WireError::BadLength {
            kind: FrameKind::Hello,
            len: 2,
            ..
        })
    ));
}

#[test]
fn oversized_payloads_are_not_encoded() {
    let message = Message::OutReport(vec![0; MAX_PAYLOAD + 1]);
    assert!(matches!(
        message.encode(),
        Err(WireError::BadLength {
            kind: FrameKind::OutReport,
            ..
        })
    ));
    let mut sink = Vec::new();
    let error = write_message(&mut sink, &message).unwrap_err();
    assert_eq!(error.kind(), std::io::ErrorKind::InvalidInput);
    assert!(sink.is_empty());
}

#[test]
fn default_socket_path_prefers_the_runtime_dir() {
    assert_eq!(
        socket_path_for(Some(OsString::from("/run/user/1000")), 1000),
        std::path::Path::new("/run/user/1000/space-foosball/board.sock")
    );
    assert_eq!(
        socket_path_for(None, 1000),
        std::path::Path::new("/tmp/space-foosball-1000/board.sock")
    );
    // A relative or empty XDG_RUNTIME_DIR is ignored, as the spec requires.
    assert_eq!(
        socket_path_for(Some(OsString::from("")), 7),
        std::path::Path::new("/tmp/space-foosball-7/board.sock")
    );
    assert!(board_link::socket_wire::default_socket_path().ends_with("board.sock"));
}

#[test]
fn bind_listener_replaces_a_stale_socket_but_not_a_live_one() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("nested").join("board.sock");
    let listener = bind_listener(&path).unwrap();
    let error = bind_listener(&path).unwrap_err();
    assert_eq!(error.kind(), std::io::ErrorKind::AddrInUse);
    drop(listener);
    // The socket file is left behind by a killed server; binding again works.
    assert!(path.exists());
    let _listener = bind_listener(&path).unwrap();
    UnixStream::connect(&path).unwrap();
}

fn message_strategy() -> impl Strategy<Value = Message> {
    prop_oneof![
        any::<u8>().prop_map(|version| Message::Hello { version }),
        proptest::collection::vec(any::<u8>(), 0..=MAX_PAYLOAD).prop_map(Message::InReport),
        proptest::collection::vec(any::<u8>(), 0..=MAX_PAYLOAD).prop_map(Message::OutReport),
    ]
}

proptest! {
    #[test]
    fn round_trip_across_arbitrary_splits(
        messages in proptest::collection::vec(message_strategy(), 0..20),
        cuts in proptest::collection::vec(1usize..40, 0..100),
    ) {
        let mut stream = Vec::new();
        for message in &messages {
            message.encode_into(&mut stream).unwrap();
        }
        let mut reader = FrameReader::new();
        let mut decoded = Vec::new();
        let mut rest = &stream[..];
        for cut in cuts.into_iter().chain(std::iter::once(usize::MAX)) {
            let (chunk, tail) = rest.split_at(cut.min(rest.len()));
            rest = tail;
            reader.push(chunk);
            decoded.extend(decode_all(&mut reader));
        }
        prop_assert_eq!(decoded, messages);
        prop_assert_eq!(reader.buffered(), 0);
    }

    #[test]
    fn arbitrary_bytes_never_panic(
        chunks in proptest::collection::vec(proptest::collection::vec(any::<u8>(), 0..80), 0..10),
    ) {
        let mut reader = FrameReader::new();
        for chunk in chunks {
            reader.read_from(&mut &chunk[..]).unwrap();
            loop {
                match reader.next_message() {
                    Ok(Some(message)) => {
                        // Whatever decodes re-encodes to a valid frame.
                        let bytes = message.encode().unwrap();
                        prop_assert!(bytes.len() <= HEADER_LEN + MAX_PAYLOAD);
                    }
                    Ok(None) => break,
                    Err(error) => {
                        // Errors are sticky: the stream is out of sync.
                        prop_assert_eq!(reader.next_message(), Err(error));
                        return Ok(());
                    }
                }
            }
        }
    }
}

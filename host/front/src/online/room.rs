//! A match by room name: both sides meet through a signalling server (`matchbox_server`)
//! and play over a WebRTC data channel (`matchbox_socket`), on the desktop and in the
//! page alike. The datagrams GGRS sends are encoded here, and what arrives from the
//! other side is decoded to a bound: a datagram that does not decode is dropped and
//! counted, never a panic.

use ggrs::{Message, NonBlockingSocket};
use matchbox_socket::{MessageLoopFuture, PeerState, WebRtcChannel, WebRtcSocket};

pub use matchbox_socket::{Error as TrafficError, PeerId};

/// The signalling server a room is looked up on when none is named: `matchbox_server`
/// on this machine, on its default port.
pub const DEFAULT_SIGNAL: &str = "ws://127.0.0.1:3536";
/// Longest room name, characters.
pub const MAX_ROOM_NAME: usize = 64;
/// Largest datagram decoded, bytes (GGRS's input messages of two sides' rods are a few
/// hundred).
const MAX_DATAGRAM: u64 = 4096;

/// A room name that cannot be used, or a signalling address that is not one.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum RoomError {
    /// Empty, too long, or with characters other than letters, digits, `-` and `_`.
    #[error("room name {0:?}: use 1–{MAX_ROOM_NAME} letters, digits, '-' or '_'")]
    Name(String),
    /// Not a `ws://` or `wss://` address.
    #[error("signalling server {0:?}: give a ws:// or wss:// address (e.g. {DEFAULT_SIGNAL})")]
    Signal(String),
}

/// The address both sides open for room `name` on the signalling server `signal`: the
/// first two to open it are paired.
pub fn room_url(signal: &str, name: &str) -> Result<String, RoomError> {
    let name_ok = !name.is_empty()
        && name.len() <= MAX_ROOM_NAME
        && name
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || c == '-' || c == '_');
    if !name_ok {
        return Err(RoomError::Name(name.to_string()));
    }
    let signal = signal.trim_end_matches('/');
    let scheme_ok = signal.starts_with("ws://") || signal.starts_with("wss://");
    if !scheme_ok || signal.contains(char::is_whitespace) || signal.contains('?') {
        return Err(RoomError::Signal(signal.to_string()));
    }
    Ok(format!("{signal}/{name}?next=2"))
}

/// A room being joined: the socket to the signalling server and the peers it brings.
pub struct Room {
    socket: WebRtcSocket,
    peer: Option<PeerId>,
}

impl Room {
    /// Opens room `url` ([`room_url`]). The returned future carries the socket's traffic
    /// and must be run (a thread's executor on the desktop, the page's event loop in the
    /// browser) for as long as the match is played.
    pub fn open(url: &str) -> (Room, MessageLoopFuture) {
        let (socket, looped) = WebRtcSocket::new_unreliable(url);
        (Room { socket, peer: None }, looped)
    }

    /// The other side, once its data channel is open.
    pub fn peer(&mut self) -> Option<PeerId> {
        if self.peer.is_none() {
            let changes = self.socket.try_update_peers().unwrap_or_default();
            self.peer = changes
                .into_iter()
                .find(|(_, state)| *state == PeerState::Connected)
                .map(|(id, _)| id);
        }
        self.peer
    }

    /// The data channel GGRS plays over (once; `None` after).
    pub fn take_channel(&mut self) -> Option<PeerChannel> {
        self.socket.take_channel(0).ok().map(|channel| PeerChannel {
            channel,
            undecodable: 0,
        })
    }
}

/// GGRS's datagrams over a WebRTC data channel (unreliable, unordered).
pub struct PeerChannel {
    channel: WebRtcChannel,
    undecodable: u64,
}

fn encoding() -> impl bincode::Options {
    use bincode::Options;
    bincode::DefaultOptions::new().with_limit(MAX_DATAGRAM)
}

impl PeerChannel {
    /// Datagrams from the other side that did not decode (dropped).
    pub fn undecodable(&self) -> u64 {
        self.undecodable
    }
}

impl NonBlockingSocket<PeerId> for PeerChannel {
    fn send_to(&mut self, msg: &Message, addr: &PeerId) {
        use bincode::Options;
        if let Ok(bytes) = encoding().serialize(msg) {
            // A closed channel loses the datagram, as the network may: GGRS notices the
            // silence and reports the other side gone.
            let _ = self.channel.try_send(bytes.into(), *addr);
        }
    }

    fn receive_all_messages(&mut self) -> Vec<(PeerId, Message)> {
        use bincode::Options;
        let mut out = Vec::new();
        for (peer, bytes) in self.channel.receive() {
            match encoding().deserialize::<Message>(&bytes) {
                Ok(msg) => out.push((peer, msg)),
                Err(_) => self.undecodable += 1,
            }
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn room_names_and_servers_are_checked() {
        assert_eq!(
            room_url("ws://127.0.0.1:3536/", "cabinet-2_b").unwrap(),
            "ws://127.0.0.1:3536/cabinet-2_b?next=2"
        );
        for bad in ["", "a b", "x/y", "ü", &"r".repeat(MAX_ROOM_NAME + 1)] {
            assert_eq!(
                room_url(DEFAULT_SIGNAL, bad),
                Err(RoomError::Name(bad.to_string()))
            );
        }
        for bad in ["http://x", "127.0.0.1:3536", "ws://a b", "ws://x?y=1"] {
            assert!(matches!(room_url(bad, "r"), Err(RoomError::Signal(_))));
        }
    }

    #[test]
    fn what_does_not_decode_is_dropped_not_a_panic() {
        use bincode::Options;
        // Not a message, a length far past the bound, and a message itself.
        let junk: [&[u8]; 2] = [&[0xff; 9], &[2, 0xfc, 0xff, 0xff, 0xff, 0x7f]];
        for bytes in junk {
            assert!(encoding().deserialize::<Message>(bytes).is_err());
        }
    }
}

//! Online play on this machine: `host` and `join` as two processes, their datagrams through
//! a relay that delays each by 50–150 ms (so they arrive out of order) and drops 5 %. Both
//! sides must end on the same state, with no desync, and the offline replay of the match's
//! recording (the same inputs, no network) must end there too.

mod common;

use common::{spinning_home_script, BIN};
use serde_json::Value;
use std::net::{SocketAddr, UdpSocket};
use std::process::{Command, Stdio};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

/// A free UDP port on the loopback (bound, read, let go).
fn free_port() -> u16 {
    UdpSocket::bind("127.0.0.1:0")
        .unwrap()
        .local_addr()
        .unwrap()
        .port()
}

/// The relay: `a` faces the host, `b` the joining side; what one sends the other gets,
/// late and some of it never.
struct Relay {
    a: SocketAddr,
    b: SocketAddr,
    stop: Arc<AtomicBool>,
    thread: Option<std::thread::JoinHandle<(u64, u64)>>,
}

impl Relay {
    fn start(host: SocketAddr, joiner: SocketAddr) -> Relay {
        let sa = UdpSocket::bind("127.0.0.1:0").unwrap();
        let sb = UdpSocket::bind("127.0.0.1:0").unwrap();
        sa.set_nonblocking(true).unwrap();
        sb.set_nonblocking(true).unwrap();
        let (a, b) = (sa.local_addr().unwrap(), sb.local_addr().unwrap());
        let stop = Arc::new(AtomicBool::new(false));
        let flag = Arc::clone(&stop);
        let thread = std::thread::spawn(move || {
            // A fixed generator: the same delays and drops on every run.
            let mut seed: u64 = 0x9E37_79B9_7F4A_7C15;
            let mut next = move || {
                seed = seed.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1);
                (seed >> 33) as f64 / (1u64 << 31) as f64
            };
            let mut queue: Vec<(Instant, bool, Vec<u8>)> = Vec::new();
            let (mut passed, mut dropped) = (0u64, 0u64);
            let mut buf = [0u8; 2048];
            while !flag.load(Ordering::Relaxed) {
                for (from_host, sock) in [(true, &sa), (false, &sb)] {
                    while let Ok((n, _)) = sock.recv_from(&mut buf) {
                        if next() < 0.05 {
                            dropped += 1;
                            continue;
                        }
                        let delay = Duration::from_millis(50 + (next() * 100.0) as u64);
                        queue.push((Instant::now() + delay, from_host, buf[..n].to_vec()));
                    }
                }
                let now = Instant::now();
                queue.retain(|(due, from_host, bytes)| {
                    if *due > now {
                        return true;
                    }
                    // From the host: out through `b` to the joiner; the other way through `a`.
                    let _ = if *from_host {
                        sb.send_to(bytes, joiner)
                    } else {
                        sa.send_to(bytes, host)
                    };
                    passed += 1;
                    false
                });
                std::thread::sleep(Duration::from_micros(300));
            }
            (passed, dropped)
        });
        Relay {
            a,
            b,
            stop,
            thread: Some(thread),
        }
    }

    fn finish(mut self) -> (u64, u64) {
        self.stop.store(true, Ordering::Relaxed);
        self.thread.take().unwrap().join().unwrap()
    }
}

/// The last line of `replay --state-hash` of a recording: the offline run of its inputs.
fn offline_run(recording: &std::path::Path) -> Value {
    let replay = Command::new(BIN)
        .args([
            "replay",
            "--home",
            "player",
            "--away",
            "player",
            "--state-hash",
        ])
        .arg(recording)
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&replay.stderr);
    assert!(replay.status.success(), "{stderr}");
    let text = String::from_utf8(replay.stdout).unwrap();
    serde_json::from_str(text.lines().last().expect("a last line")).unwrap()
}

fn outcome(out: &std::process::Output, who: &str) -> Value {
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{who} failed: {}\n{stdout}",
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_str(stdout.lines().last().expect("an outcome line")).unwrap()
}

#[test]
fn two_processes_play_one_match_through_a_late_lossy_relay() {
    let dir = tempfile::tempdir().unwrap();
    let script = spinning_home_script();
    let (port_h, port_j) = (free_port(), free_port());
    let host_addr: SocketAddr = format!("127.0.0.1:{port_h}").parse().unwrap();
    let join_addr: SocketAddr = format!("127.0.0.1:{port_j}").parse().unwrap();
    let relay = Relay::start(host_addr, join_addr);
    let frames = "360"; // 6 s of match
    let (rec_h, rec_j) = (dir.path().join("host.json"), dir.path().join("join.json"));
    let host = Command::new(BIN)
        .args([
            "host",
            "--peer",
            &relay.a.to_string(),
            "--port",
            &port_h.to_string(),
        ])
        .args(["--max-frames", frames, "--seed", "9", "--script"])
        .arg(&script)
        .arg("--record")
        .arg(&rec_h)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let joiner = Command::new(BIN)
        .args(["join", &relay.b.to_string(), "--port", &port_j.to_string()])
        .args(["--max-frames", frames, "--seed", "9", "--record"])
        .arg(&rec_j)
        .output()
        .unwrap();
    let host = host.wait_with_output().unwrap();
    let (passed, dropped) = relay.finish();
    for (who, o) in [("host", &host), ("join", &joiner)] {
        eprintln!(
            "{who}: {}{}",
            String::from_utf8_lossy(&o.stdout),
            String::from_utf8_lossy(&o.stderr)
        );
    }
    let (h, j) = (outcome(&host, "host"), outcome(&joiner, "join"));
    eprintln!("host {h}\njoin {j}\nrelay: {passed} datagrams passed, {dropped} dropped");
    assert!(dropped > 0, "the relay dropped nothing");
    for o in [&h, &j] {
        assert_eq!(o["desyncs"], 0, "{o}");
        assert_eq!(o["frames"], 360, "{o}");
    }
    assert_eq!(h["state_hash"], j["state_hash"]);
    assert_eq!(h["score"], j["score"]);
    // Late inputs were predicted and corrected: the sides rolled back and stepped again.
    let rolled = h["rollbacks"].as_u64().unwrap() + j["rollbacks"].as_u64().unwrap();
    assert!(rolled > 0, "no rollback through a 50–150 ms relay");
    // Both stepped on the same inputs, and the offline run of those inputs ends alike.
    assert_eq!(
        std::fs::read(&rec_h).unwrap(),
        std::fs::read(&rec_j).unwrap()
    );
    let offline = offline_run(&rec_h);
    assert_eq!(offline["state_hash"], h["state_hash"], "offline {offline}");
    assert_eq!(offline["score"], h["score"]);
}

/// The joining side is killed after 2.5 s; the host, still playing, says the other side
/// left, and keeps the match as far as both sides played it: it replays.
#[test]
fn a_side_that_leaves_ends_the_match_with_it_kept() {
    let dir = tempfile::tempdir().unwrap();
    let (port_h, port_j) = (free_port(), free_port());
    let rec = dir.path().join("kept.json");
    let host = Command::new(BIN)
        .args(["host", "--peer", &format!("127.0.0.1:{port_j}")])
        .args([
            "--port",
            &port_h.to_string(),
            "--max-frames",
            "3600",
            "--record",
        ])
        .arg(&rec)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let mut joiner = Command::new(BIN)
        .args(["join", &format!("127.0.0.1:{port_h}")])
        .args(["--port", &port_j.to_string(), "--max-frames", "3600"])
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    std::thread::sleep(Duration::from_millis(2500));
    joiner.kill().unwrap();
    joiner.wait().unwrap();
    let host = host.wait_with_output().unwrap();
    let err = String::from_utf8_lossy(&host.stderr);
    assert!(!host.status.success(), "the host played on alone");
    assert!(
        err.contains("left the match") && err.contains("kept"),
        "{err}"
    );
    let kept = offline_run(&rec);
    // At least the second both sides played, and not the hour the host asked for.
    let ms = kept["time_ms"].as_u64().unwrap();
    assert!((1000..60_000).contains(&ms), "kept {ms} ms");

    // Both sides resume the kept match from the same file and play two more seconds: they
    // end alike, on the offline run of the whole match's inputs.
    // The kept match ends where frame `kept_frames` starts (at ⌊f × 1000 / 60⌋ ms).
    let kept_frames = (ms * 60).div_ceil(1000);
    assert_eq!(
        kept_frames * 1000 / 60,
        ms,
        "kept {ms} ms: not a frame's start"
    );
    let frames = (kept_frames + 120).to_string();
    let (port_h, port_j) = (free_port(), free_port());
    let whole = dir.path().join("whole.json");
    let host = Command::new(BIN)
        .args(["host", "--peer", &format!("127.0.0.1:{port_j}")])
        .args(["--port", &port_h.to_string(), "--max-frames", &frames])
        .arg("--resume")
        .arg(&rec)
        .arg("--record")
        .arg(&whole)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let joiner = Command::new(BIN)
        .args(["join", &format!("127.0.0.1:{port_h}")])
        .args(["--port", &port_j.to_string(), "--max-frames", &frames])
        .arg("--resume")
        .arg(&rec)
        .output()
        .unwrap();
    let host = host.wait_with_output().unwrap();
    let (h, j) = (outcome(&host, "host"), outcome(&joiner, "join"));
    for o in [&h, &j] {
        assert_eq!(o["desyncs"], 0, "{o}");
        assert_eq!(o["frames"].to_string(), frames, "{o}");
    }
    assert_eq!(h["state_hash"], j["state_hash"]);
    let offline = offline_run(&whole);
    assert_eq!(offline["state_hash"], h["state_hash"], "offline {offline}");
    assert_eq!(
        offline["time_ms"],
        (kept_frames + 120) * 1000 / 60,
        "{offline}"
    );
}

#[test]
fn no_answer_and_a_bad_address_are_clear_errors() {
    let out = Command::new(BIN)
        .args(["join", "not an address", "--port", &free_port().to_string()])
        .output()
        .unwrap();
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("not an address"), "{err}");
}

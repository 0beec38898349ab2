//! The mouse driver state machine against scripted and emulated mice.

mod common;

use common::{step, FakeMouse, Harness, MS};
use sensor_board::mouse::{
    ABSENT_RETRY_INTERVAL_US, INTER_BYTE_TIMEOUT_US, MAX_INIT_ATTEMPTS, MAX_RESENDS, SEND_ATTEMPTS,
};
use sensor_board::{
    DriverState, LineFault, MouseConfig, MouseDriver, Ps2Frame, Resolution, SendError,
};

fn streaming() -> Harness {
    let mut h = Harness::new(MouseConfig::default());
    h.init();
    h.driver.take_events();
    h
}

/// A fresh driver whose first reset fails twice (no clock): absent.
fn absent() -> Harness {
    let mut h = Harness::new(MouseConfig::default());
    for _ in 0..SEND_ATTEMPTS {
        assert_eq!(h.driver.poll(h.now), Some(0xFF));
        h.now += 25 * MS; // the PIO's own send timeout
        h.driver.on_command_sent(h.now, Err(SendError::NoClock));
    }
    assert_eq!(h.driver.state(), DriverState::Absent);
    h
}

fn bad_parity(byte: u8) -> Ps2Frame {
    Ps2Frame::from_raw(Ps2Frame::encode(byte).raw() ^ (1 << 9))
}

fn bad_stop(byte: u8) -> Ps2Frame {
    Ps2Frame::from_raw(Ps2Frame::encode(byte).raw() & !(1 << 10))
}

// ---------------------------------------------------------------- initialisation

#[test]
fn full_init_sequence_with_the_mouses_answers() {
    let mut h = Harness::new(MouseConfig::default());
    assert_eq!(h.driver.state(), DriverState::Reset);
    assert!(!h.driver.is_present());

    h.expect_send(0xFF);
    h.expect_quiet(); // nothing more until the reset is answered
    assert_eq!(h.recv(0xFA), None);
    assert_eq!(h.driver.state(), DriverState::ResetSelfTest);

    // The self-test takes a while; no command meanwhile.
    assert!(h.run_for(1_000 * MS).is_empty());
    assert_eq!(h.driver.state(), DriverState::ResetSelfTest);
    h.recv(0xAA);
    assert_eq!(h.driver.state(), DriverState::ResetDeviceId);
    h.recv(0x00);
    assert_eq!(h.driver.device_id(), Some(0x00));

    let steps = [
        (DriverState::SetSampleRate, 0xF3),
        (DriverState::SetSampleRateValue, 200),
        (DriverState::SetResolution, 0xE8),
        (DriverState::SetResolutionValue, 3),
        (DriverState::EnableReporting, 0xF4),
    ];
    for (state, byte) in steps {
        assert_eq!(h.driver.state(), state);
        assert!(!h.driver.is_present());
        h.expect_send(byte);
        h.expect_quiet(); // one command at a time
        h.recv(0xFA);
    }
    assert_eq!(h.driver.state(), DriverState::Streaming);
    assert!(h.driver.is_present());
    let events = h.driver.take_events();
    assert!(events.reinitialised);
    assert!(!events.framing_error && !events.parity_error);
    assert!(h.driver.take_events().is_empty(), "events are taken once");
    assert_eq!(h.driver.stats().inits, 1);
}

#[test]
fn resolution_and_sample_rate_are_configurable() {
    let config = MouseConfig {
        sample_rate: 100,
        resolution: Resolution::CountsPerMm2,
        ..MouseConfig::default()
    };
    let mut h = Harness::new(config);
    h.expect_send(0xFF);
    h.recv_all(&[0xFA, 0xAA, 0x00]);
    for byte in [0xF3, 100, 0xE8, 1, 0xF4] {
        h.expect_send(byte);
        h.recv(0xFA);
    }
    assert!(h.driver.is_present());
}

#[test]
fn a_new_config_reaches_a_streaming_mouse_without_a_reset() {
    let mut h = streaming();
    let config = MouseConfig {
        sample_rate: 100,
        resolution: Resolution::CountsPerMm4,
        ..MouseConfig::default()
    };
    h.driver.set_config(config);
    for byte in [0xF3, 100, 0xE8, 2, 0xF4] {
        h.expect_send(byte);
        h.recv(0xFA);
    }
    assert!(h.driver.is_present());
    assert_eq!(h.driver.config(), &config);
    assert_eq!(h.driver.stats().reconfigurations, 1);
    // The same settings again send nothing.
    h.driver.set_config(config);
    h.expect_quiet();
}

#[test]
fn a_new_config_waits_for_the_command_in_flight() {
    let mut h = streaming();
    h.now += 40 * MS; // silent: the liveness probe is due
    assert_eq!(h.driver.poll(h.now), Some(0xE9));
    h.driver.set_config(MouseConfig {
        sample_rate: 40,
        ..MouseConfig::default()
    });
    h.driver.on_command_sent(h.now, Ok(()));
    h.expect_quiet(); // the probe's answer first
    h.recv_all(&[0xFA, 0x20, 3, 200]);
    for byte in [0xF3, 40, 0xE8, 3, 0xF4] {
        h.expect_send(byte);
        h.recv(0xFA);
    }
    assert!(h.driver.is_present());
}

#[test]
fn emulated_mouse_ends_up_configured() {
    let mut driver = MouseDriver::new(MouseConfig::default());
    let mut mouse = FakeMouse::new();
    let mut now = 0;
    while now < 1_000 * MS && !driver.is_present() {
        step(&mut driver, &mut mouse, now);
        now += MS;
    }
    assert!(driver.is_present());
    assert!(mouse.is_streaming());
    assert_eq!(mouse.sample_rate, 200);
    assert_eq!(mouse.resolution, 3);
    assert_eq!(mouse.received, [0xFF, 0xF3, 200, 0xE8, 3, 0xF4]);
}

#[test]
fn self_test_gets_its_two_and_a_half_seconds() {
    let mut h = Harness::new(MouseConfig::default());
    h.expect_send(0xFF);
    h.recv(0xFA);
    // A self-test of a full 2.5 s, and then some.
    assert!(h.run_for(2_900 * MS).is_empty());
    assert_eq!(h.driver.state(), DriverState::ResetSelfTest);
    h.recv(0xAA);
    h.recv(0x00);
    assert_eq!(h.driver.state(), DriverState::SetSampleRate);
}

#[test]
fn self_test_that_never_ends_times_out_absent() {
    let mut h = Harness::new(MouseConfig::default());
    h.expect_send(0xFF);
    h.recv(0xFA);
    h.run_for(2_999 * MS);
    assert_eq!(h.driver.state(), DriverState::ResetSelfTest);
    h.run_for(2 * MS);
    assert_eq!(h.driver.state(), DriverState::Absent);
    assert_eq!(h.driver.stats().absences, 1);
}

#[test]
fn silent_port_during_init_is_retried_once_then_absent() {
    let mut h = Harness::new(MouseConfig::default());
    h.expect_send(0xFF);
    assert!(h.run_for(24 * MS).is_empty());
    assert_eq!(h.driver.state(), DriverState::Reset);
    // No reply in 25 ms: the reset goes out once more.
    assert_eq!(h.run_for(MS), [0xFF]);
    assert_eq!(h.driver.stats().retries, 1);
    assert!(h.run_for(24 * MS).is_empty());
    assert_eq!(h.driver.state(), DriverState::Reset);
    h.run_for(MS);
    assert_eq!(h.driver.state(), DriverState::Absent);
    assert!(!h.driver.is_present());
}

#[test]
fn silent_port_mid_configuration_times_out_absent() {
    let mut h = Harness::new(MouseConfig::default());
    h.expect_send(0xFF);
    h.recv_all(&[0xFA, 0xAA, 0x00]);
    h.expect_send(0xF3);
    h.recv(0xFA);
    h.expect_send(200);
    // No acknowledge for the rate: sent again once, then absent.
    assert_eq!(h.run_for(30 * MS), [200]);
    h.run_for(30 * MS);
    assert_eq!(h.driver.state(), DriverState::Absent);
}

#[test]
fn one_send_failure_is_retried_two_are_absent() {
    for error in [SendError::NoClock, SendError::NoAck, SendError::Timeout] {
        let mut h = Harness::new(MouseConfig::default());
        assert_eq!(h.driver.poll(0), Some(0xFF));
        h.driver.on_command_sent(MS, Err(error));
        assert_eq!(h.driver.state(), DriverState::Reset, "{error:?}: retried");
        // Once the failed attempt's send time (20 ms) is used up.
        assert_eq!(h.driver.poll(19 * MS), None);
        assert_eq!(h.driver.poll(20 * MS), Some(0xFF));
        h.driver.on_command_sent(20 * MS, Err(error));
        assert_eq!(h.driver.state(), DriverState::Absent, "{error:?}");
    }
}

#[test]
fn a_retried_send_that_succeeds_goes_on() {
    let mut h = Harness::new(MouseConfig::default());
    assert_eq!(h.driver.poll(0), Some(0xFF));
    h.driver.on_command_sent(0, Err(SendError::NoAck));
    h.now = 20 * MS;
    h.expect_send(0xFF);
    h.recv(0xFA);
    assert_eq!(h.driver.state(), DriverState::ResetSelfTest);
}

#[test]
fn command_never_reported_sent_times_out_after_the_send_budget() {
    let mut h = Harness::new(MouseConfig::default());
    assert_eq!(h.driver.poll(0), Some(0xFF));
    assert_eq!(h.driver.poll(19 * MS), None);
    assert_eq!(h.driver.state(), DriverState::Reset);
    // 20 ms (PS/2: 15 ms to start clocking + 2 ms frame): once more.
    assert_eq!(h.driver.poll(20 * MS), Some(0xFF));
    assert_eq!(h.driver.poll(40 * MS), None);
    assert_eq!(h.driver.state(), DriverState::Absent);
}

#[test]
fn stray_completion_reports_are_ignored() {
    let mut h = Harness::new(MouseConfig::default());
    h.driver.on_command_sent(0, Err(SendError::NoAck));
    assert_eq!(h.driver.state(), DriverState::Reset);
    h.expect_send(0xFF);
    h.recv(0xFA);
    h.driver.on_command_sent(h.now, Err(SendError::Timeout));
    assert_eq!(h.driver.state(), DriverState::ResetSelfTest);
}

#[test]
fn resend_repeats_the_command() {
    let mut h = Harness::new(MouseConfig::default());
    h.expect_send(0xFF);
    h.recv_all(&[0xFA, 0xAA, 0x00]);
    h.expect_send(0xF3);
    h.recv(0xFA);
    h.expect_send(200);
    h.recv(0xFE);
    assert_eq!(h.driver.state(), DriverState::SetSampleRateValue);
    h.expect_send(200);
    h.recv(0xFA);
    assert_eq!(h.driver.state(), DriverState::SetResolution);
}

#[test]
fn too_many_resends_restart_from_reset() {
    let mut h = Harness::new(MouseConfig::default());
    h.expect_send(0xFF);
    h.recv_all(&[0xFA, 0xAA, 0x00]);
    h.expect_send(0xF3);
    for _ in 0..MAX_RESENDS {
        h.recv(0xFE);
        h.expect_send(0xF3);
    }
    h.recv(0xFE);
    assert_eq!(h.driver.state(), DriverState::Reset);
    h.expect_send(0xFF);
}

#[test]
fn error_reply_restarts_and_repeated_failure_is_absent() {
    let mut h = Harness::new(MouseConfig::default());
    for attempt in 1..=MAX_INIT_ATTEMPTS {
        h.expect_send(0xFF);
        h.recv_all(&[0xFA, 0xAA, 0x00]);
        h.expect_send(0xF3);
        h.recv(0xFC);
        if attempt < MAX_INIT_ATTEMPTS {
            assert_eq!(h.driver.state(), DriverState::Reset, "attempt {attempt}");
        }
    }
    assert_eq!(h.driver.state(), DriverState::Absent);
}

#[test]
fn failed_self_test_restarts() {
    let mut h = Harness::new(MouseConfig::default());
    h.expect_send(0xFF);
    h.recv(0xFA);
    h.recv(0xFC);
    assert_eq!(h.driver.state(), DriverState::Reset);
}

#[test]
fn garbled_reply_during_init_sets_flag_and_restarts() {
    let mut h = Harness::new(MouseConfig::default());
    h.expect_send(0xFF);
    h.recv_all(&[0xFA, 0xAA, 0x00]);
    h.expect_send(0xF3);
    h.driver.on_frame(h.now, bad_parity(0xFA));
    assert_eq!(h.driver.state(), DriverState::Reset);
    assert!(h.driver.events().parity_error);
}

#[test]
fn lost_reset_acknowledge_still_initialises() {
    let mut h = Harness::new(MouseConfig::default());
    h.expect_send(0xFF);
    h.recv_all(&[0xAA, 0x00]);
    assert_eq!(h.driver.state(), DriverState::SetSampleRate);
}

#[test]
fn stale_stream_bytes_before_the_reset_ack_are_ignored() {
    let mut h = Harness::new(MouseConfig::default());
    h.expect_send(0xFF);
    h.recv_all(&[0x08, 0x01, 0x02]);
    assert_eq!(h.driver.state(), DriverState::Reset);
    h.recv(0xFA);
    assert_eq!(h.driver.state(), DriverState::ResetSelfTest);
}

// ---------------------------------------------------------------- streaming packets

#[test]
fn packets_decode_with_sign_extension() {
    let mut h = streaming();
    let cases: [([u8; 3], i16, i16); 5] = [
        ([0x08, 0xFF, 0xFF], 255, 255),
        ([0x38, 0x00, 0x00], -256, -256),
        ([0x38, 0xFF, 0xFF], -1, -1),
        ([0x08, 0x00, 0x00], 0, 0),
        ([0x18, 0x80, 0x05], -128, 5),
    ];
    for (bytes, dx, dy) in cases {
        let packets = h.recv_all(&bytes);
        assert_eq!(packets.len(), 1, "{bytes:02x?}");
        assert_eq!((packets[0].dx, packets[0].dy), (dx, dy), "{bytes:02x?}");
    }
    assert_eq!(h.driver.stats().packets, 5);
}

#[test]
fn overflow_bits_are_reported() {
    let mut h = streaming();
    let p = h.recv_all(&[0x48, 0xFF, 0x00]);
    assert!(p[0].x_overflow && !p[0].y_overflow);
    let p = h.recv_all(&[0x88, 0x00, 0xFF]);
    assert!(!p[0].x_overflow && p[0].y_overflow);
    let p = h.recv_all(&[0xC9, 0x00, 0x00]);
    assert!(p[0].x_overflow && p[0].y_overflow);
    assert_eq!(p[0].buttons, 1);
}

#[test]
fn resync_after_a_dropped_byte() {
    let mut h = streaming();
    // Packet A = [0x08, 0x05, 0x06] loses its byte 0; its bytes 1 and 2 have bit 3
    // clear and are dropped, then packet B is decoded correctly.
    let packets = h.recv_all(&[0x05, 0x06, 0x08, 0x07, 0x01]);
    assert_eq!(packets.len(), 1);
    assert_eq!((packets[0].dx, packets[0].dy), (7, 1));
    assert_eq!(h.driver.stats().resyncs, 2);
}

#[test]
fn resync_after_a_dropped_middle_byte_and_a_pause() {
    let mut h = streaming();
    // Byte 1 of the last packet of a burst is lost: a partial packet waits.
    assert!(h.recv_all(&[0x08, 0x02]).is_empty());
    // The next burst comes much later: the stale partial packet is dropped.
    h.now += INTER_BYTE_TIMEOUT_US + MS;
    let packets = h.recv_all(&[0x18, 0xFE, 0x03]);
    assert_eq!(packets.len(), 1);
    assert_eq!((packets[0].dx, packets[0].dy), (-2, 3));
}

#[test]
fn partial_packet_within_the_gap_is_kept() {
    let mut h = streaming();
    assert!(h.recv_all(&[0x08, 0x02]).is_empty());
    h.now += INTER_BYTE_TIMEOUT_US;
    let packets = h.recv_all(&[0x03]);
    assert_eq!((packets[0].dx, packets[0].dy), (2, 3));
}

#[test]
fn parity_error_mid_packet_asks_for_the_packet_again() {
    let mut h = streaming();
    assert_eq!(h.recv(0x08), None);
    assert_eq!(h.driver.on_frame(h.now, bad_parity(0x10)), None);
    // The rest of the garbled packet is not used: the resend brings it whole.
    assert_eq!(h.recv(0x20), None);
    h.expect_send(0xFE);
    let packets = h.recv_all(&[0x08, 0x10, 0x20]);
    assert_eq!(packets.len(), 1);
    assert_eq!((packets[0].dx, packets[0].dy), (0x10, 0x20));
    let events = h.driver.take_events();
    assert!(events.parity_error && !events.framing_error);
    assert_eq!(h.driver.stats().parity_errors, 1);
    assert_eq!(h.driver.stats().resends, 1);
    assert_eq!(h.driver.stats().dropped, 0);
    // The next packet is fine and needs nothing.
    let packets = h.recv_all(&[0x08, 0x01, 0x02]);
    assert_eq!((packets[0].dx, packets[0].dy), (1, 2));
    h.expect_quiet();
}

#[test]
fn framing_errors_mid_packet_ask_for_the_packet_again() {
    for frame in [
        bad_stop(0x10),
        Ps2Frame::from_raw(Ps2Frame::encode(0x10).raw() | 1),
    ] {
        let mut h = streaming();
        h.recv(0x08);
        h.recv(0x04);
        assert_eq!(h.driver.on_frame(h.now, frame), None);
        let events = h.driver.take_events();
        assert!(events.framing_error && !events.parity_error);
        h.expect_send(0xFE);
        let packets = h.recv_all(&[0x08, 0x04, 0x05]);
        assert_eq!(packets.len(), 1);
        assert_eq!((packets[0].dx, packets[0].dy), (4, 5));
    }
}

#[test]
fn garbled_first_byte_asks_for_the_packet_again() {
    let mut h = streaming();
    h.driver.on_frame(h.now, bad_parity(0x08));
    assert!(h.recv_all(&[0x0F, 0x0F]).is_empty());
    h.expect_send(0xFE);
    // Some mice acknowledge the resend first.
    assert_eq!(h.recv_all(&[0xFA, 0x08, 0x01, 0x01]).len(), 1);
}

#[test]
fn a_stuck_line_is_its_own_fault_until_frames_come_again() {
    let mut h = streaming();
    h.driver.on_line_fault(h.now, LineFault::ClockStuckLow);
    assert_eq!(h.driver.state(), DriverState::Absent);
    assert_eq!(h.driver.line_fault(), Some(LineFault::ClockStuckLow));
    h.driver.on_line_fault(h.now, LineFault::ClockStuckLow);
    assert_eq!(
        h.driver.stats().line_faults,
        1,
        "the same fault found again"
    );
    // Fixed and replugged: the mouse announces itself.
    h.recv_all(&[0xAA, 0x00]);
    assert_eq!(h.driver.line_fault(), None);
    assert_eq!(h.driver.state(), DriverState::SetSampleRate);
}

#[test]
fn a_receiver_overflow_is_counted_and_the_packet_asked_for_again() {
    let mut h = streaming();
    h.recv(0x08);
    h.driver.on_rx_stall(h.now);
    assert_eq!(h.driver.stats().fifo_stalls, 1);
    assert_eq!(h.driver.stats().framing_errors, 0);
    assert!(h.driver.take_events().framing_error, "bytes went missing");
    h.expect_send(0xFE);
    assert_eq!(h.recv_all(&[0x08, 0x07, 0x09]).len(), 1);
    assert!(h.driver.is_present());
}

#[test]
fn a_packet_garbled_every_time_is_dropped_and_counted() {
    let mut h = streaming();
    h.recv(0x08);
    for _ in 0..MAX_RESENDS {
        h.driver.on_frame(h.now, bad_parity(0x10));
        h.expect_send(0xFE);
        h.recv(0x08);
    }
    h.driver.on_frame(h.now, bad_parity(0x10));
    h.expect_quiet();
    assert_eq!(h.driver.stats().resends, u32::from(MAX_RESENDS));
    assert_eq!(h.driver.stats().dropped, 1);
    assert!(h.driver.is_present());
    // The stream goes on.
    assert_eq!(h.recv_all(&[0x08, 0x01, 0x01]).len(), 1);
}

#[test]
fn an_unanswered_resend_drops_the_packet_and_keeps_the_mouse() {
    let mut h = streaming();
    h.driver.on_frame(h.now, bad_parity(0x08));
    h.expect_send(0xFE);
    // A byte proves the mouse is there, but the packet never comes back whole.
    h.recv(0x08);
    h.run_for(31 * MS);
    assert!(h.driver.is_present());
    assert_eq!(h.driver.stats().dropped, 1);
}

// ---------------------------------------------------------------- hot-plug

#[test]
fn spontaneous_self_test_result_reinitialises() {
    let mut h = streaming();
    // The mouse was unplugged and plugged back (or restarted): 0xAA 0x00.
    assert!(h.recv_all(&[0xAA, 0x00]).is_empty());
    assert_eq!(h.driver.state(), DriverState::SetSampleRate);
    assert!(!h.driver.is_present());
    assert!(!h.driver.events().reinitialised);
    for byte in [0xF3, 200, 0xE8, 3, 0xF4] {
        h.expect_send(byte);
        h.recv(0xFA);
    }
    assert!(h.driver.is_present());
    assert!(h.driver.take_events().reinitialised);
    assert_eq!(h.driver.stats().restarts, 1);
    assert_eq!(h.driver.stats().inits, 2);
}

#[test]
fn packet_starting_with_0xaa_is_still_a_packet() {
    let mut h = streaming();
    let packets = h.recv_all(&[0xAA, 0x05, 0x01]);
    assert_eq!(packets.len(), 1);
    assert!(packets[0].y_overflow);
    assert_eq!((packets[0].dx, packets[0].dy), (5, -255));
    assert!(h.driver.is_present());
}

#[test]
fn restart_during_configuration_starts_configuration_over() {
    let mut h = Harness::new(MouseConfig::default());
    h.expect_send(0xFF);
    h.recv_all(&[0xFA, 0xAA, 0x00]);
    h.expect_send(0xF3);
    h.recv(0xFA);
    h.expect_send(200);
    h.recv(0xFA);
    h.expect_send(0xE8);
    h.recv_all(&[0xAA, 0x00]);
    assert_eq!(h.driver.state(), DriverState::SetSampleRate);
    h.expect_send(0xF3);
}

#[test]
fn absent_port_retries_reset_periodically() {
    let mut h = absent();
    let mut retries = Vec::new();
    let start = h.now;
    for t in 1..=1_000u64 {
        h.now = start + t * MS;
        if let Some(byte) = h.driver.poll(h.now) {
            assert_eq!(byte, 0xFF);
            retries.push(h.now);
            h.driver.on_command_sent(h.now, Err(SendError::NoClock));
            assert_eq!(h.driver.state(), DriverState::Absent);
        }
    }
    assert_eq!(retries.len(), 4, "{retries:?}");
    assert!(retries
        .windows(2)
        .all(|w| w[1] - w[0] == ABSENT_RETRY_INTERVAL_US));
    assert_eq!(h.driver.stats().absences, 1, "one absence, many retries");
}

#[test]
fn absent_port_finds_a_replugged_mouse_by_retry() {
    let mut h = absent();
    h.now += ABSENT_RETRY_INTERVAL_US;
    h.expect_send(0xFF);
    assert_eq!(
        h.driver.state(),
        DriverState::Absent,
        "absent until answered"
    );
    h.recv(0xFA);
    assert_eq!(h.driver.state(), DriverState::ResetSelfTest);
    h.recv_all(&[0xAA, 0x00]);
    for byte in [0xF3, 200, 0xE8, 3, 0xF4] {
        h.expect_send(byte);
        h.recv(0xFA);
    }
    assert!(h.driver.is_present());
    assert!(h.driver.take_events().reinitialised);
}

#[test]
fn absent_port_finds_a_replugged_mouse_by_its_announcement() {
    let mut h = absent();
    h.now = 10 * MS;
    h.recv_all(&[0xAA, 0x00]);
    assert_eq!(h.driver.state(), DriverState::SetSampleRate);
    h.expect_send(0xF3);
}

#[test]
fn absent_port_ignores_noise() {
    let mut h = absent();
    h.recv_all(&[0x00, 0xAA, 0x01, 0x00, 0xFA]);
    h.driver.on_frame(h.now, bad_parity(0x00));
    assert_eq!(h.driver.state(), DriverState::Absent);
}

// ---------------------------------------------------------------- silence while streaming

#[test]
fn idle_mouse_is_probed_with_a_status_request_and_stays_present() {
    let mut h = streaming();
    assert!(h.run_for(29 * MS).is_empty());
    assert_eq!(h.run_for(MS), [0xE9]);
    assert_eq!(h.driver.stats().probes, 1);
    // The answer: acknowledge, then streaming + reporting, 8 counts/mm, 200/s.
    assert!(h.recv_all(&[0xFA, 0x20, 0x03, 200]).is_empty());
    assert!(h.driver.is_present());
    h.expect_quiet();
    // Next probe 30 ms after the answer.
    assert!(h.run_for(29 * MS).is_empty());
    assert_eq!(h.run_for(MS), [0xE9]);
    assert!(h.driver.take_events().is_empty(), "probing is not an event");
    assert_eq!(h.driver.stats().reconfigurations, 0);
}

#[test]
fn a_probe_that_cuts_a_packet_short_takes_its_answer_not_the_packet() {
    let mut h = streaming();
    assert!(h.run_for(29 * MS).is_empty());
    // The probe is handed out after 30 ms of silence; the first byte of a packet the
    // mouse had begun arrives before the request-to-send is through.
    h.now += MS;
    assert_eq!(h.driver.poll(h.now), Some(0xE9));
    assert!(h.recv(0x08).is_none());
    h.driver.on_command_sent(h.now, Ok(()));
    // The answer, then the interrupted motion again in a whole packet.
    assert!(h.recv_all(&[0xFA, 0x20, 0x03, 200]).is_empty());
    let packets = h.recv_all(&[0x08, 0x0C, 0x00]);
    assert_eq!(packets.len(), 1);
    assert_eq!((packets[0].dx, packets[0].dy), (12, 0));
    assert!(!packets[0].x_overflow && !packets[0].y_overflow);
    assert!(h.driver.is_present());
    assert_eq!(h.driver.stats().reconfigurations, 0);
}

#[test]
fn a_status_with_other_settings_reconfigures_the_mouse() {
    // Reporting off, 4 counts/mm, 100/s: the power-on defaults of a mouse that
    // restarted without the driver seeing its announcement.
    for status in [
        [0x00, 0x02, 100],
        [0x20, 0x02, 200],
        [0x20, 0x03, 100],
        [0x60, 0x03, 200],
    ] {
        let mut h = streaming();
        assert_eq!(h.run_for(30 * MS), [0xE9]);
        h.recv_all(&[0xFA]);
        h.recv_all(&status);
        assert_eq!(h.driver.state(), DriverState::SetSampleRate, "{status:?}");
        for byte in [0xF3, 200, 0xE8, 3, 0xF4] {
            h.expect_send(byte);
            h.recv(0xFA);
        }
        assert!(h.driver.is_present());
        assert!(h.driver.take_events().reinitialised);
        assert_eq!(h.driver.stats().reconfigurations, 1);
    }
}

#[test]
fn a_doubtful_byte_is_checked_at_once() {
    // A restart whose 0xAA was lost: the lone 0x00 is no packet start.
    let mut h = streaming();
    h.recv(0x00);
    h.expect_send(0xE9);
    h.recv_all(&[0xFA, 0x00, 0x02, 100]);
    assert_eq!(h.driver.state(), DriverState::SetSampleRate);
}

#[test]
fn quick_unannounced_restart_is_reconfigured_within_100_ms() {
    // The emulated mouse restarts with a 20 ms self-test and its 0xAA 0x00 is lost.
    let mut driver = MouseDriver::new(MouseConfig::default());
    let mut mouse = FakeMouse::new();
    mouse.self_test_us = 20 * MS;
    let mut now = 0;
    run(&mut driver, &mut mouse, &mut now, 1_000 * MS);
    assert!(driver.is_present() && mouse.is_streaming());
    driver.take_events();
    let restart_at = now;
    mouse.restart_unannounced(now);
    assert!(!mouse.is_streaming());
    while !mouse.is_streaming() || mouse.resolution != 3 || mouse.sample_rate != 200 {
        assert!(
            now - restart_at <= 100 * MS,
            "not reconfigured within 100 ms: {:?}, sent {:02x?}",
            driver.state(),
            &mouse.received[mouse.received.len().saturating_sub(8)..]
        );
        let until = now + MS;
        run(&mut driver, &mut mouse, &mut now, until);
    }
    let until = now + 5 * MS;
    run(&mut driver, &mut mouse, &mut now, until);
    assert!(driver.is_present());
    assert!(driver.take_events().reinitialised);
    assert_eq!(driver.stats().reconfigurations, 1);
}

#[test]
fn moving_mouse_is_not_probed() {
    let mut h = streaming();
    for _ in 0..100 {
        assert!(h.run_for(5 * MS).is_empty());
        assert_eq!(h.recv_all(&[0x08, 0x01, 0x00]).len(), 1);
    }
    assert_eq!(h.driver.stats().probes, 0);
}

#[test]
fn unplugged_while_streaming_unanswered_probe_is_absent() {
    let mut h = streaming();
    let start = h.now;
    let mut absent_at = None;
    for _ in 0..200 {
        h.run_for(MS);
        if h.driver.state() == DriverState::Absent {
            absent_at = Some(h.now - start);
            break;
        }
    }
    let absent_at = absent_at.expect("declared absent");
    assert!(absent_at <= 100 * MS, "absent after {absent_at} µs");
    // The probe after 30 ms, sent (this harness reports every send as done) but
    // unanswered for 25 ms, twice.
    assert_eq!(absent_at, 80 * MS);
}

#[test]
fn unplugged_while_streaming_probe_send_failure_is_absent() {
    let mut h = streaming();
    h.now += 30 * MS;
    for _ in 0..SEND_ATTEMPTS {
        assert!(h.driver.is_present());
        assert_eq!(h.driver.poll(h.now), Some(0xE9));
        h.now += 25 * MS; // the PIO's own send timeout
        h.driver.on_command_sent(h.now, Err(SendError::NoClock));
    }
    assert_eq!(h.driver.state(), DriverState::Absent);
    let config = MouseConfig::default();
    assert!(config.unplug_detection_us() < 100 * MS);
}

#[test]
fn slow_but_compliant_mouse_stays_present() {
    // PS/2 limits: 15 ms until the mouse clocks the probe in, 2 ms for the frame,
    // 20 ms until its answer.
    let mut h = streaming();
    h.now += 30 * MS;
    assert_eq!(h.driver.poll(h.now), Some(0xE9));
    h.now += 17 * MS;
    assert_eq!(h.driver.poll(h.now), None);
    h.driver.on_command_sent(h.now, Ok(()));
    h.now += 20 * MS;
    assert_eq!(h.driver.poll(h.now), None);
    h.recv_all(&[0xFA, 0x20, 0x03, 200]);
    assert!(h.driver.is_present());
    assert_eq!(h.driver.stats().retries, 0);
}

#[test]
fn probe_answered_by_other_bytes_keeps_the_mouse() {
    let mut h = streaming();
    h.run_for(30 * MS);
    // Instead of acknowledging, the mouse sends a packet (it was already moving).
    assert_eq!(h.recv_all(&[0x08, 0x01, 0x01]).len(), 1);
    h.run_for(30 * MS);
    assert!(h.driver.is_present());
}

#[test]
fn garbled_probe_answer_keeps_the_mouse_and_sets_the_flag() {
    let mut h = streaming();
    h.run_for(30 * MS);
    h.driver.on_frame(h.now, bad_parity(0xFA));
    assert_eq!(h.recv_all(&[0x08, 0x02, 0x03]).len(), 1);
    h.run_for(30 * MS);
    assert!(h.driver.is_present());
    assert!(h.driver.take_events().parity_error);
}

/// Steps `driver` and `mouse` every millisecond until `until`.
fn run(driver: &mut MouseDriver, mouse: &mut FakeMouse, now: &mut u64, until: u64) {
    while *now < until {
        *now += MS;
        step(driver, mouse, *now);
    }
}

#[test]
fn emulated_mouse_unplugged_and_replugged() {
    let mut driver = MouseDriver::new(MouseConfig::default());
    let mut mouse = FakeMouse::new();
    let mut now = 0;
    run(&mut driver, &mut mouse, &mut now, 1_000 * MS);
    assert!(driver.is_present());
    driver.take_events();

    // Idle for seconds: probes keep it present.
    run(&mut driver, &mut mouse, &mut now, 3_000 * MS);
    assert!(driver.is_present());
    assert!(driver.stats().probes >= 30);

    mouse.unplug();
    let unplugged_at = now;
    while driver.is_present() {
        let until = now + MS;
        run(&mut driver, &mut mouse, &mut now, until);
    }
    assert!(now - unplugged_at <= 100 * MS);
    assert_eq!(driver.state(), DriverState::Absent);

    mouse.plug_in(now);
    // Its announcement or the absent port's next reset retry finds it.
    let until = now + 1_000 * MS;
    run(&mut driver, &mut mouse, &mut now, until);
    assert!(driver.is_present());
    assert!(driver.take_events().reinitialised);
    assert!(mouse.is_streaming());
}

#[test]
fn timestamps_far_in_the_future_or_past_do_not_panic() {
    let mut h = streaming();
    assert_eq!(h.driver.poll(u64::MAX), Some(0xE9));
    h.driver.on_command_sent(u64::MAX, Ok(()));
    // Time going backwards: nothing times out.
    assert_eq!(h.driver.poll(0), None);
    assert!(h.driver.is_present());
    // The deadline saturates at u64::MAX: retried once, then absent.
    assert_eq!(h.driver.poll(u64::MAX), Some(0xE9));
    h.driver.on_command_sent(u64::MAX, Ok(()));
    assert_eq!(h.driver.poll(u64::MAX), None);
    assert_eq!(h.driver.state(), DriverState::Absent);
    // The retry time saturates too: the retry happens at u64::MAX.
    assert_eq!(h.driver.poll(u64::MAX), Some(0xFF));
    h.driver.on_frame(0, Ps2Frame::encode(0xFA));
    assert_eq!(h.driver.state(), DriverState::ResetSelfTest);
    assert_eq!(h.driver.poll(u64::MAX), None);
    assert_eq!(h.driver.state(), DriverState::Absent);
}

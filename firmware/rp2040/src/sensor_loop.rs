//! The sensor loop: moves PS/2 traffic between the eight ports and the platform-free
//! [`SensorBoard`], and feeds the watchdog.
//!
//! Every [`PASS_PERIOD`] the sensor task makes one [`pass`]: it drains each port's
//! events (received frames, command outcomes, send timeouts) into the board, then
//! asks the board for the next command per port and sends it. The USB IN task makes
//! a pass of its own right before it snapshots a report ([`snapshot_report`]), so a
//! report holds every frame the PIO had received by then. Both share the ports and
//! the board through [`SENSORS`] (both run in thread mode on the one executor).
//!
//! The board's logic runs on a clock that stands still while the CPU is held (a flash
//! erase, up to 400 ms with interrupts off): the receive rings keep every frame that
//! arrives meanwhile, but when they arrived is unknown, so the mouse drivers' timers
//! (the gap between a packet's bytes, silence, reply deadlines) must not count the hold.
//! The reports' device time stays the real clock.

use core::cell::RefCell;

use embassy_sync::blocking_mutex::raw::ThreadModeRawMutex;
use embassy_sync::blocking_mutex::Mutex;
use embassy_time::{Duration, Instant, Timer};
use foosball_protocol::InReportV2;
use sensor_board::{BoardConfig, HostFrame, LineFault, SensorBoard, PORTS};

use crate::ps2_pio::{Ps2Event, Ps2Ports};
use crate::watchdog::{self, Watchdog};
use crate::{usb_hid, usb_in_flight};

/// How often the ports are serviced. The driver wants a poll at least every
/// millisecond; a port's receive ring holds 400 ms of frames.
pub const PASS_PERIOD: Duration = Duration::from_micros(250);

/// The eight ports and the board logic.
struct Sensors {
    /// `None` until [`sensor_task`] starts.
    ports: Option<Ps2Ports>,
    board: SensorBoard,
    /// Per port: when to look at the lines after a failed send (microseconds; the
    /// pull-ups need a moment to raise a line the state machine just released, and
    /// the look waits for a moment with no command in flight).
    check_lines_at: [Option<u64>; PORTS],
    /// Per port: the line fault seen after the last failed send. A fault counts
    /// when two failed sends in a row see it (a mouse's start bit can look like a
    /// data line held low for an instant).
    suspect: [Option<LineFault>; PORTS],
    /// Per port: the line fault last logged.
    logged: [Option<LineFault>; PORTS],
    /// When the last pass ran (µs, real clock).
    last_pass_us: Option<u64>,
    /// How long the CPU has been held in all, µs: the board's clock is the real one
    /// less this.
    held_us: u64,
}

/// The ports and the board, shared by the sensor task and the USB IN task.
static SENSORS: Mutex<ThreadModeRawMutex, RefCell<Sensors>> = Mutex::new(RefCell::new(Sensors {
    ports: None,
    board: SensorBoard::new(BoardConfig::DEFAULT),
    check_lines_at: [None; PORTS],
    suspect: [None; PORTS],
    logged: [None; PORTS],
    last_pass_us: None,
    held_us: 0,
}));

/// A gap between two passes longer than this is the CPU held (passes come every
/// [`PASS_PERIOD`]; the executor's other work takes far less).
const HOLD_AFTER_US: u64 = 2_000;

/// How long after a failed send the lines are read: 10 kΩ pull-ups on a few
/// nanofarads of cable settle in tens of microseconds.
const LINE_SETTLE_US: u64 = 200;

/// Microseconds since boot, the time base of `sensor-board`.
pub fn now_us() -> u64 {
    Instant::now().as_micros()
}

/// The board's clock at real time `now_us` (see the module documentation), noting a
/// pass at `now_us`.
fn board_time(sensors: &mut Sensors, now_us: u64) -> u64 {
    if let Some(last) = sensors.last_pass_us {
        let gap = now_us.saturating_sub(last);
        if gap > HOLD_AFTER_US {
            sensors.held_us += gap - PASS_PERIOD.as_micros();
        }
    }
    sensors.last_pass_us = Some(now_us);
    now_us.saturating_sub(sensors.held_us)
}

/// One pass over the eight ports at real time `now_us`: frames and command outcomes
/// into the board, the board's next command per port out to the wire. Returns the
/// board's time of the pass.
fn pass(sensors: &mut Sensors, now_us: u64) -> u64 {
    let now_us = board_time(sensors, now_us);
    let Sensors {
        ports,
        board,
        check_lines_at,
        suspect,
        logged,
        ..
    } = sensors;
    let Some(ports) = ports.as_mut() else {
        return now_us;
    };
    for (index, port) in ports.all().into_iter().enumerate() {
        while let Some(event) = port.next_event(now_us) {
            match event {
                Ps2Event::Frame(frame) => board.on_frame(index, now_us, frame),
                Ps2Event::Sent(result) => {
                    if let Err(err) = result {
                        defmt::debug!("port {}: command failed: {}", index, err);
                    }
                    board.on_command_sent(index, now_us, result);
                    if result.is_err() {
                        check_lines_at[index] = Some(now_us + LINE_SETTLE_US);
                    }
                }
                Ps2Event::RxStall => {
                    defmt::warn!("port {}: RX FIFO stalled; receiver restarted", index);
                    board.on_rx_stall(index, now_us);
                }
            }
        }
        if check_lines_at[index].is_some_and(|at| now_us >= at) && !port.sending() {
            check_lines_at[index] = None;
            let fault = port.line_fault();
            if let Some(seen) = fault.filter(|_| fault == suspect[index]) {
                board.on_line_fault(index, now_us, seen);
            }
            suspect[index] = fault;
        }
        let fault = board.driver(index).and_then(|driver| driver.line_fault());
        if fault != logged[index] {
            match fault {
                Some(LineFault::ClockStuckLow) => {
                    defmt::warn!("port {}: clock line stuck low (wiring fault)", index)
                }
                Some(LineFault::DataStuckLow) => {
                    defmt::warn!("port {}: data line stuck low (wiring fault)", index)
                }
                None => defmt::info!("port {}: lines free again", index),
            }
            logged[index] = fault;
        }
        if let Some(byte) = board.poll(index, now_us) {
            defmt::trace!("port {}: sending {=u8:#04x}", index, byte);
            port.send(HostFrame::encode(byte), now_us);
        }
    }
    now_us
}

/// A fresh version 2 IN report: one pass over the ports first, then the motion
/// accumulated since the last [`commit`] with the device time (the real clock) and
/// packet ages (nothing is drained; see [`SensorBoard::snapshot_report_v2`]).
pub fn snapshot_report() -> InReportV2 {
    SENSORS.lock(|sensors| {
        let mut sensors = sensors.borrow_mut();
        let now = now_us();
        let board_now = pass(&mut sensors, now);
        let mut report = sensors.board.snapshot_report_v2(board_now);
        report.timing.device_time_us = now as u32;
        report
    })
}

/// Runs `f` on the board (its drivers' state and counters, its settings).
pub fn with_board<R>(f: impl FnOnce(&mut SensorBoard) -> R) -> R {
    SENSORS.lock(|sensors| f(&mut sensors.borrow_mut().board))
}

/// The host received `sent`: its motion leaves the accumulators.
pub fn commit(sent: &InReportV2) {
    SENSORS.lock(|sensors| sensors.borrow_mut().board.commit(&sent.report));
}

/// How long before the USB task replaces the armed report ([`usb_hid::LEAD`] before
/// each frame) a pass of this task runs, so the replacement's own pass has only the
/// frames of this short while to decode and is done before the frame starts.
const PASS_BEFORE_REPLACEMENT: Duration = Duration::from_micros(100);

/// When the next pass is due after `now`: every [`PASS_PERIOD`] on a grid tied to the
/// host's frames while they are followed (one pass [`PASS_BEFORE_REPLACEMENT`] before the
/// USB task's replacement), else [`PASS_PERIOD`] from `now`.
fn next_pass(now: Instant) -> Instant {
    match usb_in_flight::last_frame_start() {
        Some(start) if now.saturating_duration_since(start) < usb_in_flight::FRAMES_LOST => {
            let period = PASS_PERIOD.as_micros();
            let origin = start.as_micros() + period
                - (usb_hid::LEAD + PASS_BEFORE_REPLACEMENT).as_micros() % period;
            let since = now.as_micros().saturating_sub(origin);
            Instant::from_micros(origin + (since / period + 1) * period)
        }
        _ => now + PASS_PERIOD,
    }
}

/// Services the ports forever, feeding the watchdog after every pass and logging
/// when a sensor comes or goes.
#[embassy_executor::task]
pub async fn sensor_task(ports: Ps2Ports, mut watchdog: Watchdog) -> ! {
    SENSORS.lock(|sensors| sensors.borrow_mut().ports = Some(ports));
    let mut present = 0u8;
    loop {
        let mask = SENSORS.lock(|sensors| {
            let mut sensors = sensors.borrow_mut();
            pass(&mut sensors, now_us());
            sensors.board.present_mask()
        });
        if mask != present {
            defmt::info!("sensors present (bit = port): {=u8:08b}", mask);
            present = mask;
        }
        watchdog::check_in(watchdog::Task::Sensors);
        watchdog.feed();
        Timer::at(next_pass(Instant::now())).await;
    }
}

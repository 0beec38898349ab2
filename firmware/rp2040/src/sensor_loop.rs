//! The sensor loop: moves PS/2 traffic between the eight ports and the platform-free
//! [`SensorBoard`], and feeds the watchdog.
//!
//! Every [`PASS_PERIOD`] the sensor task makes one [`pass`]: it drains each port's
//! events (received frames, command outcomes, send timeouts) into the board, then
//! asks the board for the next command per port and sends it. The USB IN task makes
//! a pass of its own right before it snapshots a report ([`snapshot_report`]), so a
//! report holds every frame the PIO had received by then. Both share the ports and
//! the board through [`SENSORS`] (both run in thread mode on the one executor).

use core::cell::RefCell;

use embassy_sync::blocking_mutex::raw::ThreadModeRawMutex;
use embassy_sync::blocking_mutex::Mutex;
use embassy_time::{Duration, Instant, Ticker};
use foosball_protocol::InReportV2;
use sensor_board::{BoardConfig, HostFrame, LineFault, SensorBoard, PORTS};

use crate::ps2_pio::{Ps2Event, Ps2Ports};
use crate::watchdog::Watchdog;

/// How often the ports are serviced. The driver wants a poll at least every
/// millisecond; a port's RX FIFO holds four frames (≥ 2.4 ms of traffic).
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
}

/// The ports and the board, shared by the sensor task and the USB IN task.
static SENSORS: Mutex<ThreadModeRawMutex, RefCell<Sensors>> = Mutex::new(RefCell::new(Sensors {
    ports: None,
    board: SensorBoard::new(BoardConfig::DEFAULT),
    check_lines_at: [None; PORTS],
    suspect: [None; PORTS],
    logged: [None; PORTS],
}));

/// How long after a failed send the lines are read: 10 kΩ pull-ups on a few
/// nanofarads of cable settle in tens of microseconds.
const LINE_SETTLE_US: u64 = 200;

/// Microseconds since boot, the time base of `sensor-board`.
pub fn now_us() -> u64 {
    Instant::now().as_micros()
}

/// One pass over the eight ports at `now_us`: frames and command outcomes into the
/// board, the board's next command per port out to the wire.
fn pass(sensors: &mut Sensors, now_us: u64) {
    let Sensors {
        ports,
        board,
        check_lines_at,
        suspect,
        logged,
    } = sensors;
    let Some(ports) = ports.as_mut() else {
        return;
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
}

/// A fresh version 2 IN report: one pass over the ports first, then the motion
/// accumulated since the last [`commit`] with the device time and packet ages
/// (nothing is drained; see [`SensorBoard::snapshot_report_v2`]).
pub fn snapshot_report() -> InReportV2 {
    SENSORS.lock(|sensors| {
        let mut sensors = sensors.borrow_mut();
        let now = now_us();
        pass(&mut sensors, now);
        sensors.board.snapshot_report_v2(now)
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

/// Services the ports forever, feeding the watchdog after every pass and logging
/// when a sensor comes or goes.
#[embassy_executor::task]
pub async fn sensor_task(ports: Ps2Ports, mut watchdog: Watchdog) -> ! {
    SENSORS.lock(|sensors| sensors.borrow_mut().ports = Some(ports));
    let mut ticker = Ticker::every(PASS_PERIOD);
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
        watchdog.feed();
        ticker.next().await;
    }
}

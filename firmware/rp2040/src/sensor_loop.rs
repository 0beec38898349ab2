//! The sensor loop: moves PS/2 traffic between the eight ports and the platform-free
//! [`SensorBoard`], and feeds the watchdog.
//!
//! Every [`PASS_PERIOD`] it drains each port's events (received frames, command
//! outcomes, send timeouts) into the board, then asks the board for the next command
//! per port and sends it. The USB IN task drains the board's accumulators into a
//! report every millisecond ([`take_report`]); both share the board through
//! [`BOARD`].

use core::cell::RefCell;

use embassy_sync::blocking_mutex::raw::ThreadModeRawMutex;
use embassy_sync::blocking_mutex::Mutex;
use embassy_time::{Duration, Instant, Ticker};
use foosball_protocol::InReport;
use sensor_board::{BoardConfig, HostFrame, SensorBoard};

use crate::ps2_pio::{Ps2Event, Ps2Ports};
use crate::watchdog::Watchdog;

/// How often the ports are serviced. The driver wants a poll at least every
/// millisecond; a port's RX FIFO holds four frames (≥ 2.4 ms of traffic).
pub const PASS_PERIOD: Duration = Duration::from_micros(250);

/// The board state, shared by the sensor loop and the USB IN task (both run in
/// thread mode on the one executor).
pub static BOARD: Mutex<ThreadModeRawMutex, RefCell<SensorBoard>> =
    Mutex::new(RefCell::new(SensorBoard::new(BoardConfig::DEFAULT)));

/// Microseconds since boot, the time base of `sensor-board`.
pub fn now_us() -> u64 {
    Instant::now().as_micros()
}

/// Drains the accumulators into the next IN report.
pub fn take_report() -> InReport {
    BOARD.lock(|board| board.borrow_mut().take_report(now_us()))
}

/// One pass over the eight ports.
fn service(ports: &mut Ps2Ports, board: &mut SensorBoard, now_us: u64) {
    for (index, port) in ports.all().into_iter().enumerate() {
        while let Some(event) = port.next_event(now_us) {
            match event {
                Ps2Event::Frame(frame) => board.on_frame(index, now_us, frame),
                Ps2Event::Sent(result) => {
                    if let Err(err) = result {
                        defmt::debug!("port {}: command failed: {}", index, err);
                    }
                    board.on_command_sent(index, now_us, result);
                }
            }
        }
        if let Some(byte) = board.poll(index, now_us) {
            defmt::trace!("port {}: sending {=u8:#04x}", index, byte);
            port.send(HostFrame::encode(byte), now_us);
        }
    }
}

/// Services the ports forever, feeding the watchdog after every pass and logging
/// when a sensor comes or goes.
#[embassy_executor::task]
pub async fn sensor_task(mut ports: Ps2Ports, mut watchdog: Watchdog) -> ! {
    let mut ticker = Ticker::every(PASS_PERIOD);
    let mut present = 0u8;
    loop {
        let now = now_us();
        let mask = BOARD.lock(|board| {
            let mut board = board.borrow_mut();
            service(&mut ports, &mut board, now);
            board.present_mask()
        });
        if mask != present {
            defmt::info!("sensors present (bit = port): {=u8:08b}", mask);
            present = mask;
        }
        watchdog.feed();
        ticker.next().await;
    }
}

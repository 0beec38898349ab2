//! USB: a full-speed HID device with one interrupt IN and one interrupt OUT endpoint.
//!
//! * IN, every millisecond: the version 2 [`InReportV2`] of the eight paddles (motion,
//!   device time, packet ages, drop counts), one fresh report
//!   in flight ([`report_in_task`], [`crate::usb_in_flight`]).
//! * OUT (or a HID SET_REPORT control request): an [`OutReport`] with the haptic
//!   pulses and the LED state, handed to [`crate::haptics`] and [`crate::led`]. A
//!   malformed report is logged and ignored; reporting goes on.
//! * Feature (GET_REPORT / SET_REPORT on the control pipe): diagnostics, settings
//!   and the bootloader command, answered by [`crate::feature`].
//!
//! Ids, strings, endpoint size, interval and report descriptor all come from
//! [`foosball_protocol::usb`], which the host builds too.
//!
//! [`InReportV2`]: foosball_protocol::InReportV2

use embassy_futures::select::{select, Either};
use embassy_rp::peripherals::USB;
use embassy_rp::usb::Driver;
use embassy_time::{Duration, Instant, Timer};
use embassy_usb::class::hid::{
    self, HidBootProtocol, HidReader, HidReaderWriter, HidSubclass, HidWriter, ReadError, ReportId,
    RequestHandler,
};
use embassy_usb::control::OutResponse;
use embassy_usb::driver::EndpointError;
use embassy_usb::{Builder, UsbDevice, UsbVersion};
use foosball_protocol::usb::{
    ENDPOINT_MAX_PACKET, HID_REPORT_DESCRIPTOR, MANUFACTURER, POLL_INTERVAL_MS, PRODUCT,
    PRODUCT_ID, VENDOR_ID,
};
use foosball_protocol::{HapticPulse, LedState, OutReport, ResetReason, IN_REPORT_V2_LEN, PADDLES};
use static_cell::StaticCell;

use crate::feature::FeatureHandler;
use crate::{haptics, led, sensor_loop, usb_in_flight, version, watchdog};

/// The RP2040 USB device controller driver.
pub type UsbDriver = Driver<'static, USB>;

/// Largest OUT transfer read: one full packet, so a wrong-length report is read
/// whole and rejected by [`OutReport::decode`] rather than overflowing.
const OUT_BUF_LEN: usize = ENDPOINT_MAX_PACKET as usize;

/// Current the board draws from VBUS (the Pico and the level shifters; mice and
/// motors run from the separate 5 V supply), milliamps.
const MAX_POWER_MA: u16 = 100;

/// The writer half of the HID interface (IN endpoint).
pub type ReportWriter = HidWriter<'static, UsbDriver, IN_REPORT_V2_LEN>;
/// The reader half of the HID interface (OUT endpoint).
pub type ReportReader = HidReader<'static, UsbDriver, OUT_BUF_LEN>;

/// Everything the USB tasks run.
pub struct Usb {
    /// The device (enumeration, control requests); run by [`usb_device_task`].
    pub device: UsbDevice<'static, UsbDriver>,
    /// IN endpoint; run by [`report_in_task`].
    pub writer: ReportWriter,
    /// OUT endpoint; run by [`report_out_task`].
    pub reader: ReportReader,
}

impl Usb {
    /// Builds the device: descriptors (with `serial` as the serial number string),
    /// the HID interface and its endpoints; the Feature reports tell `reset_reason`.
    pub fn new(driver: UsbDriver, serial: &'static str, reset_reason: ResetReason) -> Self {
        let mut config = embassy_usb::Config::new(VENDOR_ID, PRODUCT_ID);
        config.manufacturer = Some(MANUFACTURER);
        config.product = Some(PRODUCT);
        config.serial_number = Some(serial);
        // A plain USB 2.0 device (no BOS descriptor); the class is declared by the
        // interface, so no interface association descriptor either.
        config.bcd_usb = UsbVersion::Two;
        config.device_class = 0;
        config.device_sub_class = 0;
        config.device_protocol = 0;
        config.composite_with_iads = false;
        config.max_power = MAX_POWER_MA;
        config.max_packet_size_0 = 64;
        config.device_release = version::DEVICE_RELEASE;

        static CONFIG_DESCRIPTOR: StaticCell<[u8; 64]> = StaticCell::new();
        static BOS_DESCRIPTOR: StaticCell<[u8; 16]> = StaticCell::new();
        static CONTROL_BUF: StaticCell<[u8; 64]> = StaticCell::new();
        static HID_STATE: StaticCell<hid::State<'static>> = StaticCell::new();
        static REPORT_HANDLER: StaticCell<ReportHandler> = StaticCell::new();
        static BUS_HANDLER: StaticCell<BusHandler> = StaticCell::new();

        let mut builder = Builder::new(
            driver,
            config,
            CONFIG_DESCRIPTOR.init([0; 64]),
            BOS_DESCRIPTOR.init([0; 16]),
            &mut [], // no Microsoft OS descriptors
            CONTROL_BUF.init([0; 64]),
        );
        let hid_config = hid::Config {
            report_descriptor: HID_REPORT_DESCRIPTOR,
            request_handler: Some(REPORT_HANDLER.init(ReportHandler {
                feature: FeatureHandler::new(reset_reason),
            })),
            poll_ms: POLL_INTERVAL_MS,
            max_packet_size: ENDPOINT_MAX_PACKET,
            hid_subclass: HidSubclass::No,
            hid_boot_protocol: HidBootProtocol::None,
        };
        let hid = HidReaderWriter::<_, OUT_BUF_LEN, IN_REPORT_V2_LEN>::new(
            &mut builder,
            HID_STATE.init(hid::State::new()),
            hid_config,
        );
        builder.handler(BUS_HANDLER.init(BusHandler));
        let (reader, writer) = hid.split();
        Self {
            device: builder.build(),
            writer,
            reader,
        }
    }
}

/// Bus events: a suspend or a bus reset stops every motor at once (a pulse must not
/// run on while the host is gone); suspend also turns the LED off (a suspended
/// device may draw 2.5 mA), a reset puts it back to its power-up blinking (no host
/// yet) until the host's next OUT report.
struct BusHandler;

impl BusHandler {
    fn stop_motors() {
        haptics::PULSES.signal([HapticPulse::default(); PADDLES]);
    }
}

impl embassy_usb::Handler for BusHandler {
    fn reset(&mut self) {
        usb_in_flight::bus_changed();
        defmt::info!("USB bus reset: motors stopped");
        Self::stop_motors();
        led::STATE.signal(led::BOOT_STATE);
    }

    fn configured(&mut self, _configured: bool) {
        usb_in_flight::bus_changed();
    }

    fn suspended(&mut self, suspended: bool) {
        if suspended {
            defmt::info!("USB suspended: motors and LED off");
            Self::stop_motors();
            led::STATE.signal(LedState::Off);
        } else {
            defmt::info!("USB resumed");
        }
    }
}

/// Decodes an OUT report and hands it to the haptics and the LED; a malformed one
/// is logged and ignored. Returns whether it was accepted.
fn apply_out_report(bytes: &[u8]) -> bool {
    match OutReport::decode(bytes) {
        Ok(report) => {
            haptics::PULSES.signal(report.haptics);
            led::STATE.signal(report.led);
            true
        }
        Err(err) => {
            defmt::warn!("ignoring malformed OUT report: {}", err);
            false
        }
    }
}

/// The HID class requests: OUT reports sent as SET_REPORT control requests (hosts
/// without interrupt OUT support use them) and the Feature reports
/// ([`FeatureHandler`]).
struct ReportHandler {
    feature: FeatureHandler,
}

impl RequestHandler for ReportHandler {
    fn get_report(&mut self, id: ReportId, buf: &mut [u8]) -> Option<usize> {
        match id {
            ReportId::Feature(0) => self.feature.get(buf),
            _ => None,
        }
    }

    fn set_report(&mut self, id: ReportId, data: &[u8]) -> OutResponse {
        let accepted = match id {
            ReportId::Out(0) => apply_out_report(data),
            ReportId::Feature(0) => self.feature.set(data),
            _ => false,
        };
        if accepted {
            OutResponse::Accepted
        } else {
            OutResponse::Rejected
        }
    }
}

/// Runs the USB device: enumeration, suspend/resume, control requests.
#[embassy_executor::task]
pub async fn usb_device_task(mut device: UsbDevice<'static, UsbDriver>) -> ! {
    device.run().await
}

/// Polling period of the IN endpoint the host was asked for: one frame.
const POLL_PERIOD: Duration = Duration::from_millis(POLL_INTERVAL_MS as u64);

/// How long before the host's next start of frame the armed report is replaced by a
/// fresh one: long enough for a pass over the ports the executor may be in the middle
/// of, the pass of the snapshot and the copy into the USB buffer, so the replacement is
/// done before the frame starts and no IN token of the frame finds the endpoint
/// revoked; short so the report is fresh (measured in the firmware-in-the-loop
/// harness: about 40 µs from the timer to the revoke, 13 µs revoked).
pub const LEAD: Duration = Duration::from_micros(100);

/// The armed report is replaced only while this much time is left before the frame
/// starts (the revoke, the copy and the release take about 13 µs); later, the armed
/// report stays for the frame, a millisecond older but never a NAK.
const REPLACE_TIME: Duration = Duration::from_micros(25);

/// Without frame starts to follow ([`usb_in_flight::FRAMES_LOST`]), how often the armed
/// report is replaced.
const REFRESH: Duration = Duration::from_micros(250);

/// While the endpoint is disabled, how often the IN task checks in with the watchdog.
const IDLE_CHECK_IN: Duration = Duration::from_millis(10);

/// Keeps the freshest IN report armed while the endpoint is enabled.
///
/// The report is a snapshot of the accumulators ([`sensor_loop::snapshot_report`]).
/// As soon as the host has taken one, its motion leaves the accumulators
/// ([`sensor_loop::commit`]; motion that arrived meanwhile stays for the next) and the
/// next is armed at once, so a token that comes early finds data. [`LEAD`] before each
/// start of frame the armed report is replaced by a fresh one (same sequence number: it
/// has not been sent): the host's token comes somewhere in the frame, after its start
/// (at once, or moved by other traffic, or on a hub's 125 µs microframes), and takes a
/// report at most [`LEAD`] older than the frame. The replacement takes the snapshot
/// first and revokes the armed report only for the copy, a few microseconds. After a
/// pause of the host the first report it takes is as fresh. A report that was never
/// sent (bus reset, deconfigured) is never committed, so nothing is lost; a buffer such
/// an event cleared is armed again at the next replacement.
#[embassy_executor::task]
pub async fn report_in_task(mut writer: ReportWriter) -> ! {
    usb_in_flight::track_frames();
    loop {
        // No host yet (or a power-only port): still alive for the watchdog.
        while let Either::Second(()) = select(writer.ready(), Timer::after(IDLE_CHECK_IN)).await {
            watchdog::check_in(watchdog::Task::ReportsIn);
        }
        usb_in_flight::TAKEN.reset();
        defmt::info!("USB IN endpoint enabled: sending reports");
        if let Err(err) = send_reports(&mut writer).await {
            defmt::info!("USB IN endpoint stopped: {}", err);
        }
    }
}

/// When the armed report is next replaced: [`LEAD`] before the next start of frame
/// after `now` (also returned), or [`REFRESH`] from `now` while frame starts are not
/// followed.
fn next_replacement(now: Instant) -> (Instant, Option<Instant>) {
    match usb_in_flight::last_frame_start() {
        Some(start) if now.saturating_duration_since(start) < usb_in_flight::FRAMES_LOST => {
            let mut frame = start + POLL_PERIOD;
            while frame - LEAD <= now {
                frame += POLL_PERIOD;
            }
            (frame - LEAD, Some(frame))
        }
        _ => (now + REFRESH, None),
    }
}

/// The loop of [`report_in_task`]; returns when the endpoint stops.
async fn send_reports(writer: &mut ReportWriter) -> Result<(), EndpointError> {
    let mut armed = sensor_loop::snapshot_report();
    let mut armed_at = usb_in_flight::bus_epoch();
    writer.write(&armed.to_bytes()).await?;
    loop {
        watchdog::check_in(watchdog::Task::ReportsIn);
        let (replace_at, frame) = next_replacement(Instant::now());
        match select(usb_in_flight::TAKEN.wait(), Timer::at(replace_at)).await {
            Either::First(_) => {
                sensor_loop::commit(&armed);
                armed = sensor_loop::snapshot_report();
                armed_at = usb_in_flight::bus_epoch();
                writer.write(&armed.to_bytes()).await?;
            }
            Either::Second(()) => {
                let fresh = sensor_loop::snapshot_report();
                if frame.is_some_and(|start| Instant::now() + REPLACE_TIME > start) {
                    continue;
                }
                let revoked = usb_in_flight::revoke();
                // Still aborted, so nothing can complete meanwhile. A buffer neither
                // armed nor signalled taken was taken (its interrupt missed) if the bus
                // is as it was when it was armed, else cleared by a bus reset or a new
                // configuration, unsent.
                let empty = !revoked && !usb_in_flight::armed() && !usb_in_flight::TAKEN.signaled();
                let taken_unseen = empty && usb_in_flight::bus_epoch() == armed_at;
                if taken_unseen {
                    sensor_loop::commit(&armed);
                    armed = sensor_loop::snapshot_report();
                } else if revoked || empty {
                    armed = fresh;
                }
                let result = if revoked || empty {
                    armed_at = usb_in_flight::bus_epoch();
                    writer.write(&armed.to_bytes()).await
                } else {
                    Ok(())
                };
                usb_in_flight::release();
                result?;
            }
        }
    }
}

/// Reads OUT reports from the interrupt OUT endpoint.
#[embassy_executor::task]
pub async fn report_out_task(mut reader: ReportReader) -> ! {
    let mut buf = [0u8; OUT_BUF_LEN];
    loop {
        reader.ready().await;
        match reader.read(&mut buf).await {
            Ok(len) => {
                apply_out_report(&buf[..len]);
            }
            Err(ReadError::Disabled) => {}
            Err(err) => defmt::warn!("USB OUT read failed: {}", err),
        }
    }
}

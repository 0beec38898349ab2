//! USB: a full-speed HID device with one interrupt IN and one interrupt OUT endpoint.
//!
//! * IN, every millisecond: the [`InReport`] of the eight paddles
//!   ([`crate::sensor_loop::take_report`]).
//! * OUT (or a HID SET_REPORT control request): an [`OutReport`] with the haptic
//!   pulses and the LED state, handed to [`crate::haptics`] and [`crate::led`]. A
//!   malformed report is logged and ignored; reporting goes on.
//!
//! Ids, strings, endpoint size, interval and report descriptor all come from
//! [`foosball_protocol::usb`], which the host builds too.
//!
//! [`InReport`]: foosball_protocol::InReport

use embassy_rp::peripherals::USB;
use embassy_rp::usb::Driver;
use embassy_usb::class::hid::{
    self, HidBootProtocol, HidReader, HidReaderWriter, HidSubclass, HidWriter, ReadError, ReportId,
    RequestHandler,
};
use embassy_usb::control::OutResponse;
use embassy_usb::{Builder, UsbDevice, UsbVersion};
use foosball_protocol::usb::{
    ENDPOINT_MAX_PACKET, HID_REPORT_DESCRIPTOR, MANUFACTURER, POLL_INTERVAL_MS, PRODUCT,
    PRODUCT_ID, VENDOR_ID,
};
use foosball_protocol::{OutReport, IN_REPORT_LEN};
use static_cell::StaticCell;

use crate::{haptics, led, sensor_loop};

/// The RP2040 USB device controller driver.
pub type UsbDriver = Driver<'static, USB>;

/// Largest OUT transfer read: one full packet, so a wrong-length report is read
/// whole and rejected by [`OutReport::decode`] rather than overflowing.
const OUT_BUF_LEN: usize = ENDPOINT_MAX_PACKET as usize;

/// Current the board draws from VBUS (the Pico and the level shifters; mice and
/// motors run from the separate 5 V supply), milliamps.
const MAX_POWER_MA: u16 = 100;

/// The writer half of the HID interface (IN endpoint).
pub type ReportWriter = HidWriter<'static, UsbDriver, IN_REPORT_LEN>;
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
    /// Builds the device: descriptors, the HID interface and its endpoints.
    pub fn new(driver: UsbDriver) -> Self {
        let mut config = embassy_usb::Config::new(VENDOR_ID, PRODUCT_ID);
        config.manufacturer = Some(MANUFACTURER);
        config.product = Some(PRODUCT);
        // A plain USB 2.0 device (no BOS descriptor); the class is declared by the
        // interface, so no interface association descriptor either.
        config.bcd_usb = UsbVersion::Two;
        config.device_class = 0;
        config.device_sub_class = 0;
        config.device_protocol = 0;
        config.composite_with_iads = false;
        config.max_power = MAX_POWER_MA;
        config.max_packet_size_0 = 64;

        static CONFIG_DESCRIPTOR: StaticCell<[u8; 64]> = StaticCell::new();
        static BOS_DESCRIPTOR: StaticCell<[u8; 16]> = StaticCell::new();
        static CONTROL_BUF: StaticCell<[u8; 64]> = StaticCell::new();
        static HID_STATE: StaticCell<hid::State<'static>> = StaticCell::new();
        static OUT_HANDLER: StaticCell<SetReportHandler> = StaticCell::new();

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
            request_handler: Some(OUT_HANDLER.init(SetReportHandler)),
            poll_ms: POLL_INTERVAL_MS,
            max_packet_size: ENDPOINT_MAX_PACKET,
            hid_subclass: HidSubclass::No,
            hid_boot_protocol: HidBootProtocol::None,
        };
        let hid = HidReaderWriter::<_, OUT_BUF_LEN, IN_REPORT_LEN>::new(
            &mut builder,
            HID_STATE.init(hid::State::new()),
            hid_config,
        );
        let (reader, writer) = hid.split();
        Self {
            device: builder.build(),
            writer,
            reader,
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

/// Takes OUT reports sent as HID SET_REPORT control requests (hosts without
/// interrupt OUT support use them).
struct SetReportHandler;

impl RequestHandler for SetReportHandler {
    fn set_report(&mut self, id: ReportId, data: &[u8]) -> OutResponse {
        match id {
            ReportId::Out(0) if apply_out_report(data) => OutResponse::Accepted,
            _ => OutResponse::Rejected,
        }
    }
}

/// Runs the USB device: enumeration, suspend/resume, control requests.
#[embassy_executor::task]
pub async fn usb_device_task(mut device: UsbDevice<'static, UsbDriver>) -> ! {
    device.run().await
}

/// Sends an IN report whenever the host polls (every millisecond while configured).
///
/// The report is taken from the board right after the previous one went out, so
/// each covers the motion of one polling interval. While the host is not polling
/// (unconfigured, suspended, no application reading), nothing is taken and motion
/// accumulates (saturating, flagged) in the board.
#[embassy_executor::task]
pub async fn report_in_task(mut writer: ReportWriter) -> ! {
    loop {
        writer.ready().await;
        defmt::info!("USB IN endpoint enabled: sending reports");
        loop {
            let bytes = sensor_loop::take_report().to_bytes();
            if let Err(err) = writer.write(&bytes).await {
                defmt::info!("USB IN endpoint stopped: {}", err);
                break;
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

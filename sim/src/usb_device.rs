//! The sensor board as a full-speed USB HID device, on `usb_device`'s stack.
//!
//! [`EmulatedUsb`] is what [`crate::usbip`] exports: `usb_device`'s
//! [`UsbDevice`] (enumeration: descriptors, SET_ADDRESS, SET/GET_CONFIGURATION,
//! GET_STATUS, features, interfaces) with [`HidClass`], a small HID class on
//! `usb_device`'s [`UsbClass`] carrying the protocol crate's report descriptor, over
//! [`UrbBus`], a device controller whose wire is the USB/IP URBs. A control URB is
//! played to the stack packet by packet — SETUP, data stage, status stage — exactly as
//! a host controller would; a request nobody accepts stalls.
//!
//! One interface (HID, no boot protocol) with an interrupt IN endpoint `0x81` (IN
//! reports) and an interrupt OUT endpoint `0x01` (OUT reports), 64-byte packets, 1 ms
//! interval — the same layout as the RP2040 firmware's. The HID class answers the HID
//! and report descriptors, GET_REPORT (the latest input report), SET_REPORT (an OUT
//! report, STALLed when malformed), SET/GET_IDLE and SET/GET_PROTOCOL.
//!
//! Feature reports ([`foosball_protocol::FeatureReport`], 56 bytes, no report id) are
//! answered as the firmware answers them: GET_REPORT (Feature) returns the report the
//! last `Select` chose (device info after a reset), read from the sensor board;
//! SET_REPORT (Feature) takes a `Select`, new settings ([`ControlOutcome::Settings`])
//! or `EnterBootloader` ([`ControlOutcome::EnterBootloader`]); anything else STALLs.

mod bus;
mod feature;

pub use bus::UrbBus;

pub(crate) use feature::{FeatureCommand, FeatureSelection};

use foosball_protocol::usb::{
    ENDPOINT_MAX_PACKET, HID_REPORT_DESCRIPTOR, MANUFACTURER, POLL_INTERVAL_MS, PRODUCT,
    PRODUCT_ID, VENDOR_ID,
};
use foosball_protocol::{BoardSettings, OutReport};
use sensor_board::SensorBoard;
use usb_device::class_prelude::{
    control, ControlIn, ControlOut, DescriptorWriter, EndpointIn, EndpointOut, InterfaceNumber,
    UsbBus, UsbBusAllocator, UsbClass,
};
use usb_device::device::{StringDescriptors, UsbDevice, UsbDeviceBuilder, UsbRev, UsbVidPid};
use usb_device::{LangID, UsbDirection};

/// Serial number string of the emulated board.
pub const SERIAL: &str = "EMULATED";
/// Device release number (BCD).
pub const BCD_DEVICE: u16 = 0x0100;
/// The interrupt IN endpoint number.
pub const EP_IN: u8 = 1;
/// The interrupt OUT endpoint number.
pub const EP_OUT: u8 = 1;
/// The only configuration's value (`usb_device` numbers its configuration 1).
pub const CONFIGURATION_VALUE: u8 = 1;
/// Interface class: HID.
pub const CLASS_HID: u8 = 3;
/// Bus power drawn, mA.
const MAX_POWER_MA: usize = 100;

const DESC_HID: u8 = 0x21;
const DESC_HID_REPORT: u8 = 0x22;
const HID_GET_REPORT: u8 = 0x01;
const HID_GET_IDLE: u8 = 0x02;
const HID_GET_PROTOCOL: u8 = 0x03;
const HID_SET_REPORT: u8 = 0x09;
const HID_SET_IDLE: u8 = 0x0A;
const HID_SET_PROTOCOL: u8 = 0x0B;
/// HID report types in GET/SET_REPORT's high byte of wValue.
const REPORT_INPUT: u8 = 1;
const REPORT_OUTPUT: u8 = 2;
const REPORT_FEATURE: u8 = 3;
/// Polls of the stack allowed per packet of a control transfer before giving up.
const POLLS_PER_PACKET: usize = 4;

/// The HID class descriptor (9 bytes) without its length and type bytes.
fn hid_descriptor_body() -> [u8; 7] {
    let [len_lo, len_hi] = (HID_REPORT_DESCRIPTOR.len() as u16).to_le_bytes();
    [0x11, 0x01, 0, 1, DESC_HID_REPORT, len_lo, len_hi]
}

/// The board's HID interface on `usb_device`: report descriptor, interrupt IN and OUT
/// endpoints, the HID class requests.
pub struct HidClass<'a, B: UsbBus> {
    interface: InterfaceNumber,
    ep_in: EndpointIn<'a, B>,
    ep_out: EndpointOut<'a, B>,
    /// The latest IN report, for GET_REPORT.
    input: Vec<u8>,
    /// An OUT report received by SET_REPORT, until taken.
    set_report: Option<Vec<u8>>,
    /// The selected Feature report, encoded, for GET_REPORT (Feature).
    feature: Vec<u8>,
    /// What GET_REPORT (Feature) returns.
    selection: FeatureSelection,
    /// A Feature report received by SET_REPORT that the board acts on, until taken.
    feature_command: Option<FeatureCommand>,
    /// HID idle rate (4 ms units).
    idle: u8,
    /// HID protocol (1: report protocol).
    protocol: u8,
}

impl<'a, B: UsbBus> HidClass<'a, B> {
    /// The interface and its two endpoints, allocated on `alloc`.
    pub fn new(alloc: &'a UsbBusAllocator<B>) -> Self {
        Self {
            interface: alloc.interface(),
            ep_in: alloc.interrupt(ENDPOINT_MAX_PACKET, POLL_INTERVAL_MS),
            ep_out: alloc.interrupt(ENDPOINT_MAX_PACKET, POLL_INTERVAL_MS),
            input: Vec::new(),
            set_report: None,
            feature: Vec::new(),
            selection: FeatureSelection::default(),
            feature_command: None,
            idle: 0,
            protocol: 1,
        }
    }

    fn is_ours(&self, request: &control::Request) -> bool {
        request.recipient == control::Recipient::Interface
            && request.index == u16::from(u8::from(self.interface))
    }
}

impl<B: UsbBus> UsbClass<B> for HidClass<'_, B> {
    fn get_configuration_descriptors(
        &self,
        writer: &mut DescriptorWriter,
    ) -> usb_device::Result<()> {
        // No subclass (no boot protocol), no protocol.
        writer.interface(self.interface, CLASS_HID, 0, 0)?;
        writer.write(DESC_HID, &hid_descriptor_body())?;
        writer.endpoint(&self.ep_in)?;
        writer.endpoint(&self.ep_out)
    }

    fn reset(&mut self) {
        self.set_report = None;
        self.selection = FeatureSelection::default();
        self.feature_command = None;
        self.idle = 0;
        self.protocol = 1;
    }

    fn control_in(&mut self, xfer: ControlIn<B>) {
        let request = *xfer.request();
        if !self.is_ours(&request) {
            return;
        }
        let [_, value_hi] = request.value.to_le_bytes();
        let answered = match (request.request_type, request.request) {
            (control::RequestType::Standard, control::Request::GET_DESCRIPTOR) => match value_hi {
                DESC_HID_REPORT => xfer.accept_with_static(HID_REPORT_DESCRIPTOR),
                DESC_HID => {
                    let mut d = vec![9, DESC_HID];
                    d.extend_from_slice(&hid_descriptor_body());
                    xfer.accept_with(&d)
                }
                _ => xfer.reject(),
            },
            (control::RequestType::Class, HID_GET_REPORT)
                if value_hi == REPORT_INPUT && !self.input.is_empty() =>
            {
                let input = self.input.clone();
                xfer.accept_with(&input)
            }
            (control::RequestType::Class, HID_GET_REPORT) if value_hi == REPORT_FEATURE => {
                let feature = self.feature.clone();
                xfer.accept_with(&feature)
            }
            (control::RequestType::Class, HID_GET_IDLE) => xfer.accept_with(&[self.idle]),
            (control::RequestType::Class, HID_GET_PROTOCOL) => xfer.accept_with(&[self.protocol]),
            (control::RequestType::Class, _) => xfer.reject(),
            // Other standard requests to the interface are the device's.
            _ => return,
        };
        // A failed accept leaves the transfer to the stack, which stalls it.
        let _ = answered;
    }

    fn control_out(&mut self, xfer: ControlOut<B>) {
        let request = *xfer.request();
        if !self.is_ours(&request) || request.request_type != control::RequestType::Class {
            return;
        }
        let [value_lo, value_hi] = request.value.to_le_bytes();
        let answered = match request.request {
            HID_SET_REPORT if value_hi == REPORT_OUTPUT => {
                // A malformed OUT report stalls, as on the interrupt endpoint.
                if OutReport::decode(xfer.data()).is_ok() {
                    self.set_report = Some(xfer.data().to_vec());
                    xfer.accept()
                } else {
                    xfer.reject()
                }
            }
            HID_SET_REPORT if value_hi == REPORT_FEATURE => match self.selection.set(xfer.data()) {
                Ok(command) => {
                    self.feature_command = command;
                    xfer.accept()
                }
                Err(()) => xfer.reject(),
            },
            HID_SET_IDLE => {
                self.idle = value_hi;
                xfer.accept()
            }
            HID_SET_PROTOCOL => {
                self.protocol = value_lo;
                xfer.accept()
            }
            _ => xfer.reject(),
        };
        let _ = answered;
    }
}

/// The device's answer to a control transfer.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum ControlOutcome {
    /// Data stage device → host (at most wLength bytes).
    Data(Vec<u8>),
    /// Done, no data back.
    Ack,
    /// Done: the host sent an OUT report by SET_REPORT (the bytes).
    OutReport(Vec<u8>),
    /// Done: the host wrote these settings (Feature); the board applies them.
    Settings(BoardSettings),
    /// Done: the host asked for the bootloader (Feature); the device leaves the bus.
    EnterBootloader,
    /// Request not supported, or the device did not finish it: STALL.
    Stall,
}

/// A new controller for [`EmulatedUsb::new`].
pub fn allocator() -> UsbBusAllocator<UrbBus> {
    UsbBusAllocator::new(UrbBus::new())
}

/// The board's USB device: `usb_device`'s stack with [`HidClass`] on [`UrbBus`]. See
/// the [module documentation](self).
pub struct EmulatedUsb<'a> {
    device: UsbDevice<'a, UrbBus>,
    hid: HidClass<'a, UrbBus>,
}

impl<'a> EmulatedUsb<'a> {
    /// The device on the controller `alloc` ([`allocator`]), powered and reset.
    pub fn new(alloc: &'a UsbBusAllocator<UrbBus>) -> Self {
        let hid = HidClass::new(alloc);
        let strings = StringDescriptors::new(LangID::EN_US)
            .manufacturer(MANUFACTURER)
            .product(PRODUCT)
            .serial_number(SERIAL);
        let builder = UsbDeviceBuilder::new(alloc, UsbVidPid(VENDOR_ID, PRODUCT_ID))
            .usb_rev(UsbRev::Usb200)
            .device_release(BCD_DEVICE);
        // Constant, valid arguments: one language, 64-byte EP0, 100 mA.
        let builder = builder
            .strings(&[strings])
            .and_then(|b| b.max_packet_size_0(64))
            .and_then(|b| b.max_power(MAX_POWER_MA))
            .unwrap_or_else(|e| unreachable!("USB device settings rejected: {e:?}"));
        let mut usb = Self {
            device: builder.build(),
            hid,
        };
        usb.reset();
        usb
    }

    fn poll(&mut self) {
        self.device.poll(&mut [&mut self.hid]);
    }

    /// A bus reset (a new host attached): unaddressed, unconfigured.
    pub fn reset(&mut self) {
        self.device.bus().request_reset();
        self.poll();
    }

    /// Whether the host has configured the device (interrupt endpoints active).
    pub fn is_configured(&self) -> bool {
        self.device.state() == usb_device::device::UsbDeviceState::Configured
    }

    /// The address the host gave the device (0 before SET_ADDRESS).
    pub fn address(&self) -> u8 {
        self.device.bus().address()
    }

    /// Plays one control transfer to the stack: `setup`, then `data_out` for a
    /// host-to-device request; `input_report` is the latest IN report (GET_REPORT);
    /// Feature reports are read from `board`, `uptime_us` µs after its power-up.
    pub fn control(
        &mut self,
        setup: [u8; 8],
        data_out: &[u8],
        input_report: &[u8],
        board: &SensorBoard,
        uptime_us: u64,
    ) -> ControlOutcome {
        self.hid.input.clear();
        self.hid.input.extend_from_slice(input_report);
        self.hid.set_report = None;
        self.hid.feature_command = None;
        self.hid.feature.clear();
        self.hid
            .feature
            .extend_from_slice(&self.hid.selection.report(board, uptime_us).to_bytes());
        let length = usize::from(u16::from_le_bytes([setup[6], setup[7]]));
        self.device.bus().setup(setup);
        self.poll();
        let outcome = if setup[0] & 0x80 != 0 {
            self.control_in(length)
        } else {
            self.control_out(data_out, length)
        };
        match (
            outcome,
            self.hid.set_report.take(),
            self.hid.feature_command.take(),
        ) {
            (ControlOutcome::Ack, Some(report), _) => ControlOutcome::OutReport(report),
            (ControlOutcome::Ack, None, Some(FeatureCommand::Settings(settings))) => {
                ControlOutcome::Settings(settings)
            }
            (ControlOutcome::Ack, None, Some(FeatureCommand::EnterBootloader)) => {
                ControlOutcome::EnterBootloader
            }
            (outcome, _, _) => outcome,
        }
    }

    fn stalled(&self) -> bool {
        let bus = self.device.bus();
        bus.host_sees_stall(0, UsbDirection::In) || bus.host_sees_stall(0, UsbDirection::Out)
    }

    /// Data stage IN (packets until a short one or wLength), then the status OUT.
    fn control_in(&mut self, length: usize) -> ControlOutcome {
        let max = usize::from(ENDPOINT_MAX_PACKET);
        let mut data = Vec::new();
        let mut polls = 0;
        loop {
            if self.stalled() {
                return ControlOutcome::Stall;
            }
            match self.device.bus().host_in(0) {
                Some(packet) => {
                    data.extend_from_slice(&packet);
                    self.poll();
                    if packet.len() < max || data.len() >= length {
                        break;
                    }
                    polls = 0;
                }
                None => {
                    polls += 1;
                    if polls > POLLS_PER_PACKET {
                        return ControlOutcome::Stall;
                    }
                    self.poll();
                }
            }
        }
        data.truncate(length);
        // Status stage: a zero-length OUT packet.
        if self.device.bus().host_out(0, &[]) {
            self.poll();
        }
        ControlOutcome::Data(data)
    }

    /// Data stage OUT (wLength bytes in packets), then the status IN (zero length).
    fn control_out(&mut self, data_out: &[u8], length: usize) -> ControlOutcome {
        let max = usize::from(ENDPOINT_MAX_PACKET);
        let data = &data_out[..length.min(data_out.len())];
        if data.len() < length {
            return ControlOutcome::Stall;
        }
        for chunk in data.chunks(max) {
            if self.stalled() || !self.device.bus().host_out(0, chunk) {
                return ControlOutcome::Stall;
            }
            self.poll();
        }
        for _ in 0..POLLS_PER_PACKET {
            if self.stalled() {
                return ControlOutcome::Stall;
            }
            if let Some(status) = self.device.bus().host_in(0) {
                // The status stage's completion is when SET_ADDRESS takes effect.
                self.poll();
                return if status.is_empty() {
                    ControlOutcome::Ack
                } else {
                    ControlOutcome::Stall
                };
            }
            self.poll();
        }
        ControlOutcome::Stall
    }

    /// An interrupt OUT transfer on endpoint 0x01: the bytes the HID class read, or
    /// `None` (STALL) when the device is not configured or the transfer is not one
    /// packet.
    pub fn interrupt_out(&mut self, data: &[u8]) -> Option<Vec<u8>> {
        if !self.is_configured() || !self.device.bus().host_out(usize::from(EP_OUT), data) {
            return None;
        }
        self.poll();
        let mut buf = [0u8; ENDPOINT_MAX_PACKET as usize];
        let n = self.hid.ep_out.read(&mut buf).ok()?;
        Some(buf[..n].to_vec())
    }

    /// An interrupt IN transfer on endpoint 0x81 carrying `report`: the HID class
    /// writes it, the host takes it. `None` when the device is not configured or the
    /// report does not fit a packet.
    pub fn interrupt_in(&mut self, report: &[u8]) -> Option<Vec<u8>> {
        if !self.is_configured() {
            return None;
        }
        self.hid.ep_in.write(report).ok()?;
        let packet = self.device.bus().host_in(usize::from(EP_IN));
        self.poll();
        packet
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use sensor_board::BoardConfig as FirmwareConfig;

    fn setup(request_type: u8, request: u8, value: u16, index: u16, length: u16) -> [u8; 8] {
        let [v0, v1] = value.to_le_bytes();
        let [i0, i1] = index.to_le_bytes();
        let [l0, l1] = length.to_le_bytes();
        [request_type, request, v0, v1, i0, i1, l0, l1]
    }

    fn data(outcome: ControlOutcome) -> Vec<u8> {
        match outcome {
            ControlOutcome::Data(d) => d,
            other => panic!("expected data, got {other:?}"),
        }
    }

    #[test]
    fn enumeration_through_the_stack() {
        let alloc = allocator();
        let mut usb = EmulatedUsb::new(&alloc);
        let fw = SensorBoard::new(FirmwareConfig::default());
        let report = [2u8; 63];
        let d = data(usb.control(setup(0x80, 6, 0x0100, 0, 8), &[], &report, &fw, 0));
        assert_eq!(d.len(), 8);
        assert_eq!(d[7], 64, "EP0 max packet");
        let d = data(usb.control(setup(0x80, 6, 0x0100, 0, 18), &[], &report, &fw, 0));
        assert_eq!(u16::from_le_bytes([d[2], d[3]]), 0x0200, "USB 2.0");
        assert_eq!(u16::from_le_bytes([d[8], d[9]]), VENDOR_ID);
        assert_eq!(u16::from_le_bytes([d[10], d[11]]), PRODUCT_ID);
        assert_eq!(u16::from_le_bytes([d[12], d[13]]), BCD_DEVICE);
        assert_eq!(
            usb.control(setup(0x00, 5, 7, 0, 0), &[], &report, &fw, 0),
            ControlOutcome::Ack
        );
        assert_eq!(usb.address(), 7);
        let c = data(usb.control(setup(0x80, 6, 0x0200, 0, 255), &[], &report, &fw, 0));
        assert_eq!(usize::from(u16::from_le_bytes([c[2], c[3]])), c.len());
        // Walk the descriptors: configuration, interface, HID, two endpoints.
        let mut i = 0;
        let mut kinds = Vec::new();
        while i < c.len() {
            kinds.push(c[i + 1]);
            i += usize::from(c[i]);
        }
        assert_eq!(i, c.len());
        assert_eq!(kinds, vec![2, 4, DESC_HID, 5, 5]);
        assert_eq!((c[5], c[9 + 5]), (CONFIGURATION_VALUE, CLASS_HID));
        assert_eq!(c[9 + 9 + 9 + 2], 0x80 | EP_IN);
        assert_eq!(c[9 + 9 + 9 + 7 + 2], EP_OUT);
        let product = data(usb.control(setup(0x80, 6, 0x0302, 0x0409, 255), &[], &report, &fw, 0));
        assert_eq!(usize::from(product[0]), product.len());
        assert_eq!(product.len(), 2 + 2 * PRODUCT.len());
        assert!(!usb.is_configured());
        assert_eq!(
            usb.control(setup(0x00, 9, 1, 0, 0), &[], &report, &fw, 0),
            ControlOutcome::Ack
        );
        assert!(usb.is_configured());
        assert_eq!(
            data(usb.control(setup(0x81, 6, 0x2200, 0, 512), &[], &report, &fw, 0)),
            HID_REPORT_DESCRIPTOR
        );
        assert_eq!(
            data(usb.control(setup(0xA1, 1, 0x0100, 0, 64), &[], &report, &fw, 0)),
            report
        );
        let out = OutReport::default().to_bytes();
        assert_eq!(
            usb.control(
                setup(0x21, 9, 0x0200, 0, out.len() as u16),
                &out,
                &report,
                &fw,
                0
            ),
            ControlOutcome::OutReport(out.to_vec())
        );
        assert_eq!(
            usb.control(setup(0x21, 9, 0x0200, 0, 3), &[1, 2, 3], &report, &fw, 0),
            ControlOutcome::Stall,
            "a malformed SET_REPORT stalls"
        );
        assert_eq!(
            usb.control(setup(0x80, 6, 0x0600, 0, 10), &[], &report, &fw, 0),
            ControlOutcome::Stall,
            "device qualifier: full speed only"
        );
        assert_eq!(
            usb.control(setup(0x40, 0x77, 0, 0, 0), &[], &report, &fw, 0),
            ControlOutcome::Stall
        );
        // After a stall the next transfer works.
        assert_eq!(
            data(usb.control(setup(0x80, 8, 0, 0, 1), &[], &report, &fw, 0)),
            [1]
        );
        // Interrupt endpoints once configured.
        assert_eq!(usb.interrupt_in(&report), Some(report.to_vec()));
        assert_eq!(usb.interrupt_out(&out), Some(out.to_vec()));
        assert_eq!(usb.interrupt_out(&[0; 65]), None, "more than a packet");
        // A bus reset unconfigures it.
        usb.reset();
        assert!(!usb.is_configured());
        assert_eq!(usb.address(), 0);
        assert_eq!(usb.interrupt_in(&report), None);
    }
}

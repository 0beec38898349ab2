//! The sensor board as a full-speed USB HID device: its descriptors and its answers to
//! control requests, built from the protocol crate's ids and HID report descriptor.
//!
//! This is the device side that [`crate::usbip`] exports. It implements the standard
//! requests a host issues during enumeration (GET_DESCRIPTOR for device,
//! configuration, string and HID descriptors, SET_ADDRESS, SET/GET_CONFIGURATION,
//! GET_STATUS, SET/GET_INTERFACE, CLEAR/SET_FEATURE) and the HID class requests
//! (GET_REPORT, SET_REPORT, SET/GET_IDLE, SET/GET_PROTOCOL). Anything else stalls.
//!
//! One interface (HID, no boot protocol) with an interrupt IN endpoint `0x81` (IN
//! reports) and an interrupt OUT endpoint `0x01` (OUT reports), 64-byte packets, 1 ms
//! interval — the same layout as the RP2040 firmware's.

use foosball_protocol::usb::{
    ENDPOINT_MAX_PACKET, HID_REPORT_DESCRIPTOR, MANUFACTURER, POLL_INTERVAL_MS, PRODUCT,
    PRODUCT_ID, VENDOR_ID,
};

/// Serial number string of the emulated board.
pub const SERIAL: &str = "EMULATED";
/// Device release number (BCD).
pub const BCD_DEVICE: u16 = 0x0100;
/// The interrupt IN endpoint number.
pub const EP_IN: u8 = 1;
/// The interrupt OUT endpoint number.
pub const EP_OUT: u8 = 1;
/// The only configuration's value.
pub const CONFIGURATION_VALUE: u8 = 1;
/// Interface class: HID.
pub const CLASS_HID: u8 = 3;

const DESC_DEVICE: u8 = 1;
const DESC_CONFIGURATION: u8 = 2;
const DESC_STRING: u8 = 3;
const DESC_INTERFACE: u8 = 4;
const DESC_ENDPOINT: u8 = 5;
const DESC_HID: u8 = 0x21;
const DESC_HID_REPORT: u8 = 0x22;

/// The 18-byte device descriptor.
pub fn device_descriptor() -> [u8; 18] {
    let [vid_lo, vid_hi] = VENDOR_ID.to_le_bytes();
    let [pid_lo, pid_hi] = PRODUCT_ID.to_le_bytes();
    let [bcd_lo, bcd_hi] = BCD_DEVICE.to_le_bytes();
    [
        18,
        DESC_DEVICE,
        0x00,
        0x02, // USB 2.0
        0,
        0,
        0,  // class per interface
        64, // EP0 max packet
        vid_lo,
        vid_hi,
        pid_lo,
        pid_hi,
        bcd_lo,
        bcd_hi,
        1, // iManufacturer
        2, // iProduct
        3, // iSerialNumber
        1, // one configuration
    ]
}

/// The HID class descriptor (9 bytes).
pub fn hid_descriptor() -> [u8; 9] {
    let [len_lo, len_hi] = (HID_REPORT_DESCRIPTOR.len() as u16).to_le_bytes();
    [
        9,
        DESC_HID,
        0x11,
        0x01, // HID 1.11
        0,    // no country
        1,    // one class descriptor
        DESC_HID_REPORT,
        len_lo,
        len_hi,
    ]
}

/// The configuration descriptor with its interface, HID and endpoint descriptors.
pub fn configuration_descriptor() -> Vec<u8> {
    let [mp_lo, mp_hi] = ENDPOINT_MAX_PACKET.to_le_bytes();
    let mut d = vec![
        9,
        DESC_CONFIGURATION,
        0,
        0, // total length, filled below
        1, // one interface
        CONFIGURATION_VALUE,
        0,    // no string
        0x80, // bus powered
        50,   // 100 mA
        // Interface 0: HID, no subclass (no boot protocol), two endpoints.
        9,
        DESC_INTERFACE,
        0,
        0,
        2,
        CLASS_HID,
        0,
        0,
        0,
    ];
    d.extend_from_slice(&hid_descriptor());
    d.extend_from_slice(&[
        7,
        DESC_ENDPOINT,
        0x80 | EP_IN,
        0x03, // interrupt
        mp_lo,
        mp_hi,
        POLL_INTERVAL_MS,
        7,
        DESC_ENDPOINT,
        EP_OUT,
        0x03,
        mp_lo,
        mp_hi,
        POLL_INTERVAL_MS,
    ]);
    let [len_lo, len_hi] = (d.len() as u16).to_le_bytes();
    d[2] = len_lo;
    d[3] = len_hi;
    d
}

/// String descriptor `index` (0: the language list, US English).
pub fn string_descriptor(index: u8) -> Option<Vec<u8>> {
    let text = match index {
        0 => return Some(vec![4, DESC_STRING, 0x09, 0x04]),
        1 => MANUFACTURER,
        2 => PRODUCT,
        3 => SERIAL,
        _ => return None,
    };
    let units: Vec<u16> = text.encode_utf16().collect();
    let mut d = vec![(2 + 2 * units.len()) as u8, DESC_STRING];
    for u in units {
        d.extend_from_slice(&u.to_le_bytes());
    }
    Some(d)
}

/// A control transfer's SETUP packet.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SetupPacket {
    /// bmRequestType.
    pub request_type: u8,
    /// bRequest.
    pub request: u8,
    /// wValue.
    pub value: u16,
    /// wIndex.
    pub index: u16,
    /// wLength.
    pub length: u16,
}

impl SetupPacket {
    /// Parses the 8 bytes (little-endian fields).
    pub fn parse(bytes: [u8; 8]) -> Self {
        Self {
            request_type: bytes[0],
            request: bytes[1],
            value: u16::from_le_bytes([bytes[2], bytes[3]]),
            index: u16::from_le_bytes([bytes[4], bytes[5]]),
            length: u16::from_le_bytes([bytes[6], bytes[7]]),
        }
    }

    /// Whether the data stage goes device → host.
    pub fn is_in(&self) -> bool {
        self.request_type & 0x80 != 0
    }
}

/// The device's answer to a control transfer.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum ControlOutcome {
    /// Data stage device → host (already cut to wLength).
    Data(Vec<u8>),
    /// Done, no data back.
    Ack,
    /// Done: the host sent an OUT report by SET_REPORT (the bytes).
    OutReport(Vec<u8>),
    /// Request not supported: STALL.
    Stall,
}

/// The device's enumeration state.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct UsbDeviceState {
    /// Address set by SET_ADDRESS.
    pub address: u8,
    /// Current configuration (0: not configured).
    pub configuration: u8,
    /// HID idle rate (4 ms units).
    pub idle: u8,
    /// HID protocol (1: report protocol).
    pub protocol: u8,
}

impl UsbDeviceState {
    /// A freshly attached device (unconfigured, report protocol).
    pub fn new() -> Self {
        Self {
            protocol: 1,
            ..Self::default()
        }
    }

    /// Whether the host has configured the device (interrupt endpoints active).
    pub fn is_configured(&self) -> bool {
        self.configuration != 0
    }

    /// Answers one control transfer. `data_out` is the OUT data stage, `input_report`
    /// the latest IN report (for GET_REPORT).
    pub fn control(
        &mut self,
        setup: SetupPacket,
        data_out: &[u8],
        input_report: &[u8],
    ) -> ControlOutcome {
        let reply = |bytes: &[u8]| {
            let n = bytes.len().min(usize::from(setup.length));
            ControlOutcome::Data(bytes[..n].to_vec())
        };
        let [value_lo, value_hi] = setup.value.to_le_bytes();
        match (setup.request_type, setup.request) {
            // GET_STATUS (device, interface, endpoint).
            (0x80..=0x82, 0x00) => reply(&[0, 0]),
            // CLEAR_FEATURE / SET_FEATURE (device, interface, endpoint).
            (0x00..=0x02, 0x01 | 0x03) => ControlOutcome::Ack,
            // SET_ADDRESS.
            (0x00, 0x05) => {
                self.address = value_lo & 0x7F;
                ControlOutcome::Ack
            }
            // GET_DESCRIPTOR (device-directed).
            (0x80, 0x06) => match value_hi {
                DESC_DEVICE => reply(&device_descriptor()),
                DESC_CONFIGURATION if value_lo == 0 => reply(&configuration_descriptor()),
                DESC_STRING => match string_descriptor(value_lo) {
                    Some(d) => reply(&d),
                    None => ControlOutcome::Stall,
                },
                // Device qualifier and others: a full-speed-only device stalls.
                _ => ControlOutcome::Stall,
            },
            // GET_DESCRIPTOR (interface-directed): HID and HID report descriptors.
            (0x81, 0x06) if setup.index == 0 => match value_hi {
                DESC_HID => reply(&hid_descriptor()),
                DESC_HID_REPORT => reply(HID_REPORT_DESCRIPTOR),
                _ => ControlOutcome::Stall,
            },
            // GET_CONFIGURATION.
            (0x80, 0x08) => reply(&[self.configuration]),
            // SET_CONFIGURATION.
            (0x00, 0x09) => {
                if value_lo == 0 || value_lo == CONFIGURATION_VALUE {
                    self.configuration = value_lo;
                    ControlOutcome::Ack
                } else {
                    ControlOutcome::Stall
                }
            }
            // GET_INTERFACE / SET_INTERFACE (only alternate setting 0).
            (0x81, 0x0A) => reply(&[0]),
            (0x01, 0x0B) if setup.value == 0 => ControlOutcome::Ack,
            // HID GET_REPORT: input report 0 (no report ids).
            (0xA1, 0x01) if value_hi == 1 => reply(input_report),
            // HID GET_IDLE / GET_PROTOCOL.
            (0xA1, 0x02) => reply(&[self.idle]),
            (0xA1, 0x03) => reply(&[self.protocol]),
            // HID SET_REPORT: output report.
            (0x21, 0x09) if value_hi == 2 => ControlOutcome::OutReport(data_out.to_vec()),
            // HID SET_IDLE / SET_PROTOCOL.
            (0x21, 0x0A) => {
                self.idle = value_hi;
                ControlOutcome::Ack
            }
            (0x21, 0x0B) => {
                self.protocol = value_lo;
                ControlOutcome::Ack
            }
            _ => ControlOutcome::Stall,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn setup(request_type: u8, request: u8, value: u16, index: u16, length: u16) -> SetupPacket {
        SetupPacket {
            request_type,
            request,
            value,
            index,
            length,
        }
    }

    #[test]
    fn descriptors_are_consistent() {
        let d = device_descriptor();
        assert_eq!(u16::from_le_bytes([d[8], d[9]]), VENDOR_ID);
        assert_eq!(u16::from_le_bytes([d[10], d[11]]), PRODUCT_ID);
        let c = configuration_descriptor();
        assert_eq!(c.len(), 9 + 9 + 9 + 7 + 7);
        assert_eq!(usize::from(u16::from_le_bytes([c[2], c[3]])), c.len());
        // Walk the descriptors: lengths chain exactly to the end.
        let mut i = 0;
        let mut kinds = Vec::new();
        while i < c.len() {
            kinds.push(c[i + 1]);
            i += usize::from(c[i]);
        }
        assert_eq!(i, c.len());
        assert_eq!(kinds, vec![2, 4, 0x21, 5, 5]);
        let h = hid_descriptor();
        assert_eq!(
            usize::from(u16::from_le_bytes([h[7], h[8]])),
            HID_REPORT_DESCRIPTOR.len()
        );
        let s = string_descriptor(2).unwrap();
        assert_eq!(usize::from(s[0]), s.len());
        assert_eq!(s.len(), 2 + 2 * PRODUCT.len());
        assert_eq!(string_descriptor(9), None);
    }

    #[test]
    fn enumeration_requests() {
        let mut dev = UsbDeviceState::new();
        let report = [1u8; 43];
        assert_eq!(
            dev.control(setup(0x80, 6, 0x0100, 0, 8), &[], &report),
            ControlOutcome::Data(device_descriptor()[..8].to_vec())
        );
        assert_eq!(
            dev.control(setup(0x00, 5, 7, 0, 0), &[], &report),
            ControlOutcome::Ack
        );
        assert_eq!(dev.address, 7);
        let ControlOutcome::Data(c) = dev.control(setup(0x80, 6, 0x0200, 0, 255), &[], &report)
        else {
            panic!()
        };
        assert_eq!(c, configuration_descriptor());
        assert!(!dev.is_configured());
        assert_eq!(
            dev.control(setup(0x00, 9, 1, 0, 0), &[], &report),
            ControlOutcome::Ack
        );
        assert!(dev.is_configured());
        assert_eq!(
            dev.control(setup(0x00, 9, 5, 0, 0), &[], &report),
            ControlOutcome::Stall
        );
        assert_eq!(
            dev.control(setup(0x81, 6, 0x2200, 0, 512), &[], &report),
            ControlOutcome::Data(HID_REPORT_DESCRIPTOR.to_vec())
        );
        assert_eq!(
            dev.control(setup(0xA1, 1, 0x0100, 0, 64), &[], &report),
            ControlOutcome::Data(report.to_vec())
        );
        assert_eq!(
            dev.control(setup(0x21, 9, 0x0200, 0, 3), &[1, 2, 3], &report),
            ControlOutcome::OutReport(vec![1, 2, 3])
        );
        assert_eq!(
            dev.control(setup(0x80, 6, 0x0600, 0, 10), &[], &report),
            ControlOutcome::Stall
        );
        assert_eq!(
            dev.control(setup(0x40, 0x77, 0, 0, 0), &[], &report),
            ControlOutcome::Stall
        );
    }
}

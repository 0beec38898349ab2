//! [`UsbBoard`]: the real sensor board over USB (`rusb`).
//!
//! A reader thread keeps an interrupt IN transfer pending at all times and queues the
//! packets, so the board's 1 kHz reports are not lost while the game is busy between
//! polls; OUT reports go out as interrupt OUT transfers (or HID `SET_REPORT` control
//! transfers on a board without an OUT endpoint). The rusb-independent logic (which
//! interface and endpoints to use, which device to open, which errors mean "unplugged")
//! is in plain functions tested without hardware; the reconnect state machine is shared
//! with the socket board ([`crate::link`]). Where libusb has hot-plug events, an arrival
//! of a device with the board's ids makes the next poll look at once.

use std::path::Path;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc::{self, Receiver, RecvTimeoutError, SyncSender, TryRecvError};
use std::sync::Arc;
use std::thread::JoinHandle;
use std::time::Duration;

use foosball_protocol::usb::{PRODUCT_ID, VENDOR_ID};
use foosball_protocol::{
    BoardSettings, DeviceInfo, InReport, OutReport, PortDiagnostics, ReportTiming,
    FEATURE_REPORT_LEN,
};
use rusb::{Context, DeviceHandle, Direction, TransferType, UsbContext};

use crate::feature::{self, FeaturePipe};
use crate::link::{Connector, Link, ReportBuf, SystemClock, Transport, TransportError};
use crate::socket_wire::MAX_PAYLOAD;
use crate::{Board, BoardError, LinkState, LinkStats, DEFAULT_RETRY_INTERVAL};

/// USB interface class of HID devices.
const HID_CLASS: u8 = 0x03;
/// How long one pending IN transfer waits before the reader thread checks for stop.
const READ_TIMEOUT: Duration = Duration::from_millis(50);
/// Timeout of one OUT transfer.
const WRITE_TIMEOUT: Duration = Duration::from_millis(100);
/// Reports queued between the reader thread and the game (4 s at 1 kHz). When the
/// game stops polling for longer, newer reports are dropped and counted as lost.
const QUEUE_DEPTH: usize = 4096;
/// HID class request `SET_REPORT`, host-to-device, class, interface.
const HID_SET_REPORT_REQUEST_TYPE: u8 = 0x21;
const HID_SET_REPORT: u8 = 0x09;
/// `wValue` of `SET_REPORT`: report type Output (2) in the high byte, report id 0.
const HID_OUTPUT_REPORT_NO_ID: u16 = 0x0200;
/// HID class request `GET_REPORT`, device-to-host, class, interface.
const HID_GET_REPORT_REQUEST_TYPE: u8 = 0xA1;
const HID_GET_REPORT: u8 = 0x01;
/// `wValue` of `GET_REPORT`/`SET_REPORT`: report type Feature (3), report id 0.
const HID_FEATURE_REPORT_NO_ID: u16 = 0x0300;

/// The real sensor board on USB, found by vendor/product id
/// ([`foosball_protocol::usb::VENDOR_ID`]:[`foosball_protocol::usb::PRODUCT_ID`]).
///
/// Opening detaches a kernel driver bound to the HID interface (re-attached when the
/// board is released) and claims the interface; the interrupt endpoints are taken from
/// the configuration descriptor. When the board is unplugged (libusb `NoDevice`, `Io` or
/// `Pipe`) the poll reports [`BoardError::Disconnected`], and later polls rescan the bus,
/// at most once per retry interval ([`DEFAULT_RETRY_INTERVAL`]), until it is back; where
/// libusb reports hot-plug events, a device with the ids that arrives is looked at on the
/// next poll, inside the interval.
///
/// Without root, opening needs the udev rule `udev/70-space-foosball.rules` of this
/// crate ([`BoardError::AccessDenied`] otherwise).
pub struct UsbBoard {
    link: Link<UsbConnector>,
}

impl UsbBoard {
    /// Opens the sensor board ([`VENDOR_ID`]:[`PRODUCT_ID`]) now.
    /// [`BoardError::NotFound`] if none is plugged in.
    pub fn open() -> Result<Self, BoardError> {
        Self::open_ids(VENDOR_ID, PRODUCT_ID)
    }

    /// Opens the first device with the given ids now; [`BoardError::NotFound`] if none.
    pub fn open_ids(vid: u16, pid: u16) -> Result<Self, BoardError> {
        let mut board = Self::new(vid, pid);
        board.link.connect_now()?;
        Ok(board)
    }

    /// Opens the sensor board ([`VENDOR_ID`]:[`PRODUCT_ID`]) whose USB serial number
    /// string is `serial`, for when several are plugged in. Each board with those ids
    /// is opened briefly to read its serial number. [`BoardError::SerialNotFound`]
    /// (naming the serial numbers found) when none has it, [`BoardError::NotFound`]
    /// when no board is plugged in. Reconnects look for the same serial number.
    pub fn open_serial(serial: &str) -> Result<Self, BoardError> {
        let mut board = Self::new(VENDOR_ID, PRODUCT_ID);
        board.link.connector_mut().serial = Some(serial.to_owned());
        board.link.connect_now()?;
        Ok(board)
    }

    /// A board with the given ids that is not opened yet: the first poll looks for it,
    /// and polls keep looking until it is plugged in.
    pub fn new(vid: u16, pid: u16) -> Self {
        Self {
            link: Link::new(
                UsbConnector {
                    vid,
                    pid,
                    serial: None,
                    context: None,
                    hotplug: None,
                },
                SystemClock,
                DEFAULT_RETRY_INTERVAL,
            ),
        }
    }

    /// Vendor and product id looked for.
    pub fn ids(&self) -> (u16, u16) {
        let connector = self.link.connector();
        (connector.vid, connector.pid)
    }

    /// The serial number the board was chosen by ([`UsbBoard::open_serial`]), if any.
    pub fn wanted_serial(&self) -> Option<&str> {
        self.link.connector().serial.as_deref()
    }

    /// The USB serial number string of the board while it is open; `None` while it
    /// is not, or when it has none (or it could not be read).
    pub fn serial_number(&self) -> Option<String> {
        self.link.transport().and_then(|t| t.serial.clone())
    }

    /// How often a missing board is looked for again.
    pub fn retry_interval(&self) -> Duration {
        self.link.retry_interval()
    }

    /// Why the last attempt to reach the board failed (`NotFound`, `AccessDenied`,
    /// a refused connection, …), while it is not connected; polls meanwhile report
    /// [`BoardError::Disconnected`].
    pub fn last_connect_error(&self) -> Option<&BoardError> {
        self.link.last_connect_error()
    }

    /// Sets how often a missing board is looked for again.
    pub fn set_retry_interval(&mut self, interval: Duration) {
        self.link.set_retry_interval(interval);
    }
}

/// The board's Feature reports (diagnostics, settings, bootloader; see
/// [`foosball_protocol::FeatureReport`]), over control transfers on the claimed HID
/// interface. Each connects first if the board is not open. A board whose firmware
/// has no Feature reports answers [`BoardError::FeatureUnsupported`]; IN reports
/// keep flowing meanwhile.
impl UsbBoard {
    /// Firmware version and git hash, reset reason, uptime, present ports.
    pub fn device_info(&mut self) -> Result<DeviceInfo, BoardError> {
        feature::device_info(self.link.transport_mut()?)
    }

    /// Port `port`'s (0..8) state, PS/2 device id and counters.
    pub fn port_diagnostics(&mut self, port: u8) -> Result<PortDiagnostics, BoardError> {
        feature::port_diagnostics(self.link.transport_mut()?, port)
    }

    /// The board's settings (axis map, resolution, sample rate per port).
    pub fn settings(&mut self) -> Result<BoardSettings, BoardError> {
        feature::settings(self.link.transport_mut()?)
    }

    /// Writes new settings; the board applies them at once and keeps them in flash.
    /// A field out of range is refused before anything is sent.
    pub fn set_settings(&mut self, settings: &BoardSettings) -> Result<(), BoardError> {
        feature::set_settings(self.link.transport_mut()?, settings)
    }

    /// Restarts the board into the RP2040's USB bootloader (it comes back as the
    /// `RPI-RP2` drive, ready for a new UF2); this link then reports it gone.
    pub fn enter_bootloader(&mut self) -> Result<(), BoardError> {
        feature::enter_bootloader(self.link.transport_mut()?)
    }
}

/// The Feature report transfers of the open board (connecting first if it is not
/// open), so that code written for any [`FeaturePipe`] works on the real board.
impl FeaturePipe for UsbBoard {
    fn get_feature(&mut self, buf: &mut [u8; FEATURE_REPORT_LEN]) -> Result<usize, BoardError> {
        self.link.transport_mut()?.get_feature(buf)
    }

    fn set_feature(&mut self, report: &[u8; FEATURE_REPORT_LEN]) -> Result<(), BoardError> {
        self.link.transport_mut()?.set_feature(report)
    }
}

impl Board for UsbBoard {
    fn name(&self) -> String {
        self.link.name()
    }
    fn poll_report(&mut self, timeout: Duration) -> Result<Option<InReport>, BoardError> {
        self.link.poll_report(timeout)
    }
    fn send(&mut self, report: &OutReport) -> Result<(), BoardError> {
        self.link.send(report)
    }
    fn link_state(&self) -> LinkState {
        self.link.state()
    }
    fn stats(&self) -> LinkStats {
        self.link.stats()
    }
    fn last_timing(&self) -> Option<ReportTiming> {
        self.link.last_timing()
    }
}

impl std::fmt::Debug for UsbBoard {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("UsbBoard")
            .field("name", &self.link.name())
            .field("state", &self.link.state())
            .field("stats", &self.link.stats())
            .finish()
    }
}

/// One endpoint of an alternate setting, as far as endpoint selection cares.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct EndpointInfo {
    pub address: u8,
    pub is_in: bool,
    pub is_interrupt: bool,
}

/// One alternate setting of one interface.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct AltSettingInfo {
    pub interface: u8,
    pub alt_setting: u8,
    pub class: u8,
    pub endpoints: Vec<EndpointInfo>,
}

/// The interface and endpoints the board is driven through.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct Endpoints {
    pub interface: u8,
    pub alt_setting: u8,
    pub in_address: u8,
    /// `None`: OUT reports go as HID `SET_REPORT` control transfers.
    pub out_address: Option<u8>,
}

/// Picks the interface to use: one with an interrupt IN endpoint, preferring HID
/// interfaces, then ones that also have an interrupt OUT endpoint, then the first.
pub(crate) fn find_endpoints(alt_settings: &[AltSettingInfo]) -> Option<Endpoints> {
    alt_settings
        .iter()
        .filter_map(|alt| {
            let first = |is_in: bool| {
                alt.endpoints
                    .iter()
                    .find(|ep| ep.is_interrupt && ep.is_in == is_in)
                    .map(|ep| ep.address)
            };
            let endpoints = Endpoints {
                interface: alt.interface,
                alt_setting: alt.alt_setting,
                in_address: first(true)?,
                out_address: first(false),
            };
            let rank = (alt.class != HID_CLASS, endpoints.out_address.is_none());
            Some((rank, endpoints))
        })
        .min_by_key(|(rank, _)| *rank)
        .map(|(_, endpoints)| endpoints)
}

/// The alternate settings of a configuration descriptor.
fn describe_config(config: &rusb::ConfigDescriptor) -> Vec<AltSettingInfo> {
    config
        .interfaces()
        .flat_map(|interface| interface.descriptors())
        .map(|alt| AltSettingInfo {
            interface: alt.interface_number(),
            alt_setting: alt.setting_number(),
            class: alt.class_code(),
            endpoints: alt
                .endpoint_descriptors()
                .map(|ep| EndpointInfo {
                    address: ep.address(),
                    is_in: ep.direction() == Direction::In,
                    is_interrupt: ep.transfer_type() == TransferType::Interrupt,
                })
                .collect(),
        })
        .collect()
}

/// Opens the first candidate whose ids match: the first success wins; if every match
/// fails, the last failure is returned; with no match at all, [`BoardError::NotFound`].
pub(crate) fn open_first_match<D, T>(
    candidates: impl IntoIterator<Item = (u16, u16, D)>,
    vid: u16,
    pid: u16,
    mut open: impl FnMut(D) -> Result<T, BoardError>,
) -> Result<T, BoardError> {
    let mut last_error = None;
    for (candidate_vid, candidate_pid, device) in candidates {
        if (candidate_vid, candidate_pid) != (vid, pid) {
            continue;
        }
        match open(device) {
            Ok(opened) => return Ok(opened),
            Err(e) => last_error = Some(e),
        }
    }
    Err(last_error.unwrap_or(BoardError::NotFound { vid, pid }))
}

/// Opens the candidate whose ids match and whose serial number (`serial_of`) is
/// `wanted`. With no candidate of those ids, [`BoardError::NotFound`]; with some but
/// none of that serial number, [`BoardError::SerialNotFound`] listing what each had
/// (its serial number quoted, or why it could not be read).
pub(crate) fn open_by_serial<D, T>(
    candidates: impl IntoIterator<Item = (u16, u16, D)>,
    vid: u16,
    pid: u16,
    wanted: &str,
    mut serial_of: impl FnMut(&D) -> Result<Option<String>, BoardError>,
    open: impl FnOnce(D) -> Result<T, BoardError>,
) -> Result<T, BoardError> {
    let mut found = Vec::new();
    for (candidate_vid, candidate_pid, device) in candidates {
        if (candidate_vid, candidate_pid) != (vid, pid) {
            continue;
        }
        match serial_of(&device) {
            Ok(Some(serial)) if serial == wanted => return open(device),
            Ok(Some(serial)) => found.push(format!("{serial:?}")),
            Ok(None) => found.push("one without a serial number".to_owned()),
            Err(e) => found.push(format!("one whose serial number could not be read ({e})")),
        }
    }
    if found.is_empty() {
        return Err(BoardError::NotFound { vid, pid });
    }
    Err(BoardError::SerialNotFound {
        vid,
        pid,
        wanted: wanted.to_owned(),
        found,
    })
}

/// The serial number string of `device` (opened briefly to read it); `None` when its
/// descriptor names none.
fn read_serial(
    device: &rusb::Device<Context>,
    vid: u16,
    pid: u16,
) -> Result<Option<String>, BoardError> {
    let descriptor = device
        .device_descriptor()
        .map_err(|e| open_error(e, vid, pid, "reading the device descriptor"))?;
    if descriptor.serial_number_string_index().is_none() {
        return Ok(None);
    }
    let handle = device
        .open()
        .map_err(|e| open_error(e, vid, pid, "opening the device"))?;
    handle
        .read_serial_number_string_ascii(&descriptor)
        .map(Some)
        .map_err(|e| open_error(e, vid, pid, "reading the serial number"))
}

/// How a libusb error on an open board is handled.
pub(crate) fn classify(error: rusb::Error) -> TransportError {
    match error {
        rusb::Error::NoDevice | rusb::Error::Io | rusb::Error::Pipe => TransportError::Gone,
        other => TransportError::Transient(BoardError::Usb(other.to_string())),
    }
}

/// A libusb error while opening a board with the given ids.
fn open_error(error: rusb::Error, vid: u16, pid: u16, what: &str) -> BoardError {
    match error {
        rusb::Error::Access => BoardError::AccessDenied { vid, pid },
        // Unplugged between enumeration and opening.
        rusb::Error::NoDevice | rusb::Error::NotFound => BoardError::NotFound { vid, pid },
        rusb::Error::Busy => BoardError::Usb(format!(
            "{what}: the board's interface is busy (another program has it open?)"
        )),
        other => BoardError::Usb(format!("{what}: {other}")),
    }
}

/// Whether this system exposes USB devices to libusb at all (Linux usbfs). Where it
/// does not (containers, build machines), no board can be plugged in.
fn usb_bus_visible() -> bool {
    !cfg!(target_os = "linux") || Path::new("/dev/bus/usb").is_dir()
}

struct UsbConnector {
    vid: u16,
    pid: u16,
    /// Only the board with this serial number string.
    serial: Option<String>,
    /// Made on the first scan and kept; libusb tracks hot-plugged devices in it.
    context: Option<Context>,
    /// Arrivals of boards with these ids, where libusb reports hot-plug events.
    hotplug: Option<HotplugWatch>,
}

/// Hot-plug arrivals of devices with one vendor and product id: a libusb callback sets a
/// flag, and while the link looks for a board a thread handles the context's events, so
/// that the callback runs with no transfer pending. While a board is open the thread
/// rests: the reader thread's transfers are then the only ones handling events (no
/// second thread between a report and the game). Stopped and joined when dropped.
struct HotplugWatch {
    arrived: Arc<AtomicBool>,
    /// Whether the link is looking for a board (set by each look, cleared on connecting).
    looking: Arc<AtomicBool>,
    stop: Arc<AtomicBool>,
    context: Context,
    thread: Option<JoinHandle<()>>,
    /// Deregisters the callback when dropped (after the thread has ended).
    _registration: rusb::Registration<Context>,
}

/// The callback: notes that a device arrived.
struct ArrivalFlag(Arc<AtomicBool>);

impl rusb::Hotplug<Context> for ArrivalFlag {
    fn device_arrived(&mut self, _device: rusb::Device<Context>) {
        self.0.store(true, Ordering::Release);
    }
    fn device_left(&mut self, _device: rusb::Device<Context>) {}
}

/// How long the hot-plug thread waits for events before it checks for stop.
const HOTPLUG_EVENT_WAIT: Duration = Duration::from_millis(200);

impl HotplugWatch {
    /// Watches `context` for arrivals of `vid:pid`; `None` where libusb has no hot-plug
    /// events (Windows) or they cannot be registered: the link then polls.
    fn start(context: &Context, vid: u16, pid: u16) -> Option<Self> {
        if !rusb::has_hotplug() {
            return None;
        }
        let arrived = Arc::new(AtomicBool::new(false));
        let registration = rusb::HotplugBuilder::new()
            .vendor_id(vid)
            .product_id(pid)
            .enumerate(false)
            .register(context, Box::new(ArrivalFlag(Arc::clone(&arrived))))
            .ok()?;
        let stop = Arc::new(AtomicBool::new(false));
        let looking = Arc::new(AtomicBool::new(true));
        let thread = {
            let (context, stop, looking) =
                (context.clone(), Arc::clone(&stop), Arc::clone(&looking));
            std::thread::Builder::new()
                .name("usb-hotplug".into())
                .spawn(move || {
                    while !stop.load(Ordering::Acquire) {
                        let handled = looking.load(Ordering::Acquire)
                            && context.handle_events(Some(HOTPLUG_EVENT_WAIT)).is_ok();
                        if !handled {
                            std::thread::park_timeout(HOTPLUG_EVENT_WAIT);
                        }
                    }
                })
                .ok()?
        };
        Some(Self {
            arrived,
            looking,
            stop,
            context: context.clone(),
            thread: Some(thread),
            _registration: registration,
        })
    }

    /// Whether a device arrived since the last call; the link is looking for a board.
    fn take_arrival(&self) -> bool {
        if !self.looking.swap(true, Ordering::AcqRel) {
            if let Some(thread) = &self.thread {
                thread.thread().unpark();
            }
        }
        self.arrived.swap(false, Ordering::AcqRel)
    }

    /// A board is open: the thread leaves the context's events to the reader and rests.
    fn found(&self) {
        self.looking.store(false, Ordering::Release);
        self.context.interrupt_handle_events();
    }
}

impl Drop for HotplugWatch {
    fn drop(&mut self) {
        self.stop.store(true, Ordering::Release);
        self.context.interrupt_handle_events();
        if let Some(thread) = self.thread.take() {
            thread.thread().unpark();
            let _ = thread.join();
        }
    }
}

impl UsbConnector {
    fn context(&mut self) -> Result<Context, BoardError> {
        if let Some(context) = &self.context {
            return Ok(context.clone());
        }
        let context = Context::new().map_err(|e| {
            if usb_bus_visible() {
                BoardError::Usb(format!("libusb initialisation failed: {e}"))
            } else {
                // No USB device file system: nothing is plugged in that we could see.
                BoardError::NotFound {
                    vid: self.vid,
                    pid: self.pid,
                }
            }
        })?;
        self.hotplug = HotplugWatch::start(&context, self.vid, self.pid);
        self.context = Some(context.clone());
        Ok(context)
    }
}

impl Connector for UsbConnector {
    type Transport = UsbTransport;

    fn describe(&self) -> String {
        match &self.serial {
            Some(serial) => format!(
                "USB {:04x}:{:04x} serial {serial:?} (not connected)",
                self.vid, self.pid
            ),
            None => format!("USB {:04x}:{:04x} (not connected)", self.vid, self.pid),
        }
    }

    fn connect(&mut self) -> Result<UsbTransport, BoardError> {
        let (vid, pid) = (self.vid, self.pid);
        let context = self.context()?;
        let devices = context
            .devices()
            .map_err(|e| BoardError::Usb(format!("listing USB devices: {e}")))?;
        let candidates = devices.iter().filter_map(|device| {
            let descriptor = device.device_descriptor().ok()?;
            Some((descriptor.vendor_id(), descriptor.product_id(), device))
        });
        let opened = match &self.serial {
            Some(wanted) => open_by_serial(
                candidates,
                vid,
                pid,
                wanted,
                |device| read_serial(device, vid, pid),
                |device| UsbTransport::open(&device, vid, pid),
            ),
            None => open_first_match(candidates, vid, pid, |device| {
                UsbTransport::open(&device, vid, pid)
            }),
        };
        if let (Ok(_), Some(watch)) = (&opened, &self.hotplug) {
            watch.found();
        }
        opened
    }

    fn arrived(&mut self) -> bool {
        self.hotplug
            .as_ref()
            .is_some_and(HotplugWatch::take_arrival)
    }
}

/// What the reader thread hands to the game.
enum UsbEvent {
    Report { len: usize, bytes: ReportBuf },
    Error(String),
}

struct UsbTransport {
    handle: Arc<DeviceHandle<Context>>,
    endpoints: Endpoints,
    name: String,
    /// The serial number string, if it has one that could be read.
    serial: Option<String>,
    events: Receiver<UsbEvent>,
    stop: Arc<AtomicBool>,
    reader: Option<JoinHandle<()>>,
}

impl UsbTransport {
    fn open(device: &rusb::Device<Context>, vid: u16, pid: u16) -> Result<Self, BoardError> {
        let name = format!(
            "USB {vid:04x}:{pid:04x} bus {} addr {}",
            device.bus_number(),
            device.address()
        );
        let config = device
            .active_config_descriptor()
            .or_else(|_| device.config_descriptor(0))
            .map_err(|e| open_error(e, vid, pid, "reading the configuration descriptor"))?;
        let endpoints = find_endpoints(&describe_config(&config)).ok_or_else(|| {
            BoardError::Usb(format!(
                "{name}: no interface with an interrupt IN endpoint"
            ))
        })?;
        let handle = device
            .open()
            .map_err(|e| open_error(e, vid, pid, "opening the device"))?;
        let serial = device
            .device_descriptor()
            .ok()
            .and_then(|d| handle.read_serial_number_string_ascii(&d).ok());
        let interface = endpoints.interface;
        // Detach the kernel's HID driver on claim and re-attach it on release; where
        // libusb cannot do that automatically, detach by hand.
        if handle.set_auto_detach_kernel_driver(true).is_err()
            && handle.kernel_driver_active(interface).unwrap_or(false)
        {
            handle
                .detach_kernel_driver(interface)
                .map_err(|e| open_error(e, vid, pid, "detaching the kernel driver"))?;
        }
        handle
            .claim_interface(interface)
            .map_err(|e| open_error(e, vid, pid, "claiming the interface"))?;
        if endpoints.alt_setting != 0 {
            handle
                .set_alternate_setting(interface, endpoints.alt_setting)
                .map_err(|e| open_error(e, vid, pid, "selecting the alternate setting"))?;
        }
        let handle = Arc::new(handle);
        let stop = Arc::new(AtomicBool::new(false));
        let (sender, events) = mpsc::sync_channel(QUEUE_DEPTH);
        let reader = {
            let handle = Arc::clone(&handle);
            let stop = Arc::clone(&stop);
            let endpoint = endpoints.in_address;
            std::thread::Builder::new()
                .name("board-link usb reader".into())
                .spawn(move || read_loop(&handle, endpoint, &sender, &stop))?
        };
        Ok(Self {
            handle,
            endpoints,
            name,
            serial,
            events,
            stop,
            reader: Some(reader),
        })
    }
}

/// Keeps an IN transfer pending until stopped or the board is gone (then drops the
/// sender, which the game sees as the channel disconnecting after the queued reports).
fn read_loop(
    handle: &DeviceHandle<Context>,
    endpoint: u8,
    events: &SyncSender<UsbEvent>,
    stop: &AtomicBool,
) {
    while !stop.load(Ordering::Relaxed) {
        let mut bytes: ReportBuf = [0; MAX_PAYLOAD];
        match handle.read_interrupt(endpoint, &mut bytes, READ_TIMEOUT) {
            // A full queue drops the report; the sequence gap counts it as lost.
            Ok(len) => drop(events.try_send(UsbEvent::Report { len, bytes })),
            Err(rusb::Error::Timeout | rusb::Error::Interrupted) => {}
            Err(e) => match classify(e) {
                TransportError::Gone => return,
                _ => {
                    drop(events.try_send(UsbEvent::Error(e.to_string())));
                    // Do not spin on a persistent error.
                    std::thread::sleep(Duration::from_millis(10));
                }
            },
        }
    }
}

impl Drop for UsbTransport {
    fn drop(&mut self) {
        self.stop.store(true, Ordering::Relaxed);
        if let Some(reader) = self.reader.take() {
            // The thread notices within one READ_TIMEOUT; then the handle is released
            // (interface released, kernel driver re-attached) when the last Arc drops.
            let _ = reader.join();
        }
    }
}

/// A libusb error of a Feature report control transfer: a STALL means the board
/// does not answer it, not that it is gone.
fn feature_error(error: rusb::Error, name: &str) -> BoardError {
    match error {
        rusb::Error::Pipe => BoardError::FeatureUnsupported,
        rusb::Error::NoDevice => BoardError::Disconnected,
        other => BoardError::Usb(format!("{name}: Feature report: {other}")),
    }
}

impl FeaturePipe for UsbTransport {
    fn get_feature(&mut self, buf: &mut [u8; FEATURE_REPORT_LEN]) -> Result<usize, BoardError> {
        self.handle
            .read_control(
                HID_GET_REPORT_REQUEST_TYPE,
                HID_GET_REPORT,
                HID_FEATURE_REPORT_NO_ID,
                u16::from(self.endpoints.interface),
                buf,
                WRITE_TIMEOUT,
            )
            .map_err(|e| feature_error(e, &self.name))
    }

    fn set_feature(&mut self, report: &[u8; FEATURE_REPORT_LEN]) -> Result<(), BoardError> {
        let written = self
            .handle
            .write_control(
                HID_SET_REPORT_REQUEST_TYPE,
                HID_SET_REPORT,
                HID_FEATURE_REPORT_NO_ID,
                u16::from(self.endpoints.interface),
                report,
                WRITE_TIMEOUT,
            )
            .map_err(|e| feature_error(e, &self.name))?;
        if written == report.len() {
            Ok(())
        } else {
            Err(BoardError::Usb(format!(
                "{}: short Feature report ({written} of {} bytes)",
                self.name,
                report.len()
            )))
        }
    }
}

impl Transport for UsbTransport {
    fn name(&self) -> String {
        self.name.clone()
    }

    fn recv(
        &mut self,
        buf: &mut ReportBuf,
        timeout: Duration,
    ) -> Result<Option<usize>, TransportError> {
        let event = if timeout.is_zero() {
            match self.events.try_recv() {
                Ok(event) => event,
                Err(TryRecvError::Empty) => return Ok(None),
                Err(TryRecvError::Disconnected) => return Err(TransportError::Gone),
            }
        } else {
            match self.events.recv_timeout(timeout) {
                Ok(event) => event,
                Err(RecvTimeoutError::Timeout) => return Ok(None),
                Err(RecvTimeoutError::Disconnected) => return Err(TransportError::Gone),
            }
        };
        match event {
            UsbEvent::Report { len, bytes } => {
                *buf = bytes;
                Ok(Some(len))
            }
            UsbEvent::Error(message) => Err(TransportError::Transient(BoardError::Usb(format!(
                "{}: {message}",
                self.name
            )))),
        }
    }

    fn send(&mut self, bytes: &[u8]) -> Result<(), TransportError> {
        let written = match self.endpoints.out_address {
            Some(endpoint) => self.handle.write_interrupt(endpoint, bytes, WRITE_TIMEOUT),
            None => self.handle.write_control(
                HID_SET_REPORT_REQUEST_TYPE,
                HID_SET_REPORT,
                HID_OUTPUT_REPORT_NO_ID,
                u16::from(self.endpoints.interface),
                bytes,
                WRITE_TIMEOUT,
            ),
        }
        .map_err(classify)?;
        if written == bytes.len() {
            Ok(())
        } else {
            Err(TransportError::Transient(BoardError::Usb(format!(
                "{}: short OUT transfer ({written} of {} bytes)",
                self.name,
                bytes.len()
            ))))
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ep(address: u8, is_interrupt: bool) -> EndpointInfo {
        EndpointInfo {
            address,
            is_in: address & 0x80 != 0,
            is_interrupt,
        }
    }

    fn alt(interface: u8, class: u8, endpoints: Vec<EndpointInfo>) -> AltSettingInfo {
        AltSettingInfo {
            interface,
            alt_setting: 0,
            class,
            endpoints,
        }
    }

    #[test]
    fn endpoints_come_from_the_descriptor() {
        // A vendor interface with bulk endpoints first, then the HID interface with
        // unusual endpoint numbers: the HID one's addresses are used.
        let config = [
            alt(0, 0xFF, vec![ep(0x81, false), ep(0x01, false)]),
            alt(2, HID_CLASS, vec![ep(0x05, true), ep(0x83, true)]),
        ];
        assert_eq!(
            find_endpoints(&config),
            Some(Endpoints {
                interface: 2,
                alt_setting: 0,
                in_address: 0x83,
                out_address: Some(0x05),
            })
        );
    }

    #[test]
    fn hid_interface_preferred_then_one_with_an_out_endpoint() {
        let vendor_with_both = alt(0, 0xFF, vec![ep(0x81, true), ep(0x01, true)]);
        let hid_in_only = alt(1, HID_CLASS, vec![ep(0x82, true)]);
        let hid_both = alt(3, HID_CLASS, vec![ep(0x84, true), ep(0x04, true)]);
        let chosen = find_endpoints(&[vendor_with_both.clone(), hid_in_only.clone()]).unwrap();
        assert_eq!((chosen.interface, chosen.out_address), (1, None));
        let chosen = find_endpoints(&[vendor_with_both, hid_in_only, hid_both]).unwrap();
        assert_eq!((chosen.interface, chosen.out_address), (3, Some(0x04)));
    }

    #[test]
    fn no_interrupt_in_endpoint_means_no_usable_interface() {
        assert_eq!(find_endpoints(&[]), None);
        let config = [
            alt(0, HID_CLASS, vec![ep(0x01, true)]),
            alt(1, 0xFF, vec![ep(0x81, false)]),
        ];
        assert_eq!(find_endpoints(&config), None);
    }

    #[test]
    fn enumerating_nothing_is_not_found() {
        let none: Vec<(u16, u16, ())> = Vec::new();
        let result: Result<(), _> = open_first_match(none, VENDOR_ID, PRODUCT_ID, |_| Ok(()));
        assert!(matches!(
            result,
            Err(BoardError::NotFound {
                vid: VENDOR_ID,
                pid: PRODUCT_ID
            })
        ));
        // Other devices on the bus are never opened.
        let others = vec![
            (0x046d, 0xc077, "mouse"),
            (VENDOR_ID, 0x0002, "other test id"),
        ];
        let result: Result<(), _> = open_first_match(others, VENDOR_ID, PRODUCT_ID, |name| {
            panic!("opened {name}")
        });
        let error = result.unwrap_err();
        assert!(matches!(error, BoardError::NotFound { .. }));
        assert!(error.to_string().contains("1209:0001"), "{error}");
    }

    #[test]
    fn the_first_matching_device_that_opens_wins() {
        let devices = vec![
            (VENDOR_ID, PRODUCT_ID, 1),
            (0x1234, 0x5678, 2),
            (VENDOR_ID, PRODUCT_ID, 3),
        ];
        let mut tried = Vec::new();
        let opened = open_first_match(devices, VENDOR_ID, PRODUCT_ID, |n| {
            tried.push(n);
            if n == 1 {
                Err(BoardError::AccessDenied {
                    vid: VENDOR_ID,
                    pid: PRODUCT_ID,
                })
            } else {
                Ok(n)
            }
        });
        assert_eq!(opened.unwrap(), 3);
        assert_eq!(tried, vec![1, 3]);
    }

    #[test]
    fn a_board_that_cannot_be_opened_reports_why() {
        let devices = vec![(VENDOR_ID, PRODUCT_ID, ())];
        let result: Result<(), _> = open_first_match(devices, VENDOR_ID, PRODUCT_ID, |()| {
            Err(open_error(
                rusb::Error::Access,
                VENDOR_ID,
                PRODUCT_ID,
                "opening",
            ))
        });
        let error = result.unwrap_err();
        assert!(matches!(error, BoardError::AccessDenied { .. }));
        assert!(error.to_string().contains("udev"), "{error}");
    }

    /// A board for `open_by_serial`: its number and its serial number (`Err`: it
    /// cannot be read).
    type SerialBoard = (u8, Result<Option<&'static str>, ()>);

    /// Boards for `open_by_serial`, with their ids.
    fn serial_boards() -> Vec<(u16, u16, SerialBoard)> {
        vec![
            (VENDOR_ID, PRODUCT_ID, (1, Ok(Some("E6614C311B4A2F30")))),
            (0x046d, 0xc077, (2, Ok(Some("WANTED")))),
            (VENDOR_ID, PRODUCT_ID, (3, Ok(None))),
            (VENDOR_ID, PRODUCT_ID, (4, Err(()))),
            (VENDOR_ID, PRODUCT_ID, (5, Ok(Some("E6614C311B4A9999")))),
        ]
    }

    fn serial_of(device: &SerialBoard) -> Result<Option<String>, BoardError> {
        device
            .1
            .map(|s| s.map(str::to_owned))
            .map_err(|()| BoardError::AccessDenied {
                vid: VENDOR_ID,
                pid: PRODUCT_ID,
            })
    }

    #[test]
    fn the_board_with_the_serial_number_is_opened() {
        let opened = open_by_serial(
            serial_boards(),
            VENDOR_ID,
            PRODUCT_ID,
            "E6614C311B4A9999",
            serial_of,
            |device| Ok(device.0),
        );
        assert_eq!(opened.unwrap(), 5);
        // Only boards with the board's ids count: another device's serial never does.
        let error = open_by_serial(
            serial_boards(),
            VENDOR_ID,
            PRODUCT_ID,
            "WANTED",
            serial_of,
            |device| -> Result<u8, BoardError> { panic!("opened {}", device.0) },
        )
        .unwrap_err();
        let BoardError::SerialNotFound { wanted, found, .. } = &error else {
            panic!("{error:?}");
        };
        assert_eq!(wanted, "WANTED");
        assert_eq!(found.len(), 4, "{found:?}");
        let text = error.to_string();
        for part in [
            "\"WANTED\"",
            "\"E6614C311B4A2F30\"",
            "\"E6614C311B4A9999\"",
            "without a serial number",
            "could not be read",
            "udev",
        ] {
            assert!(text.contains(part), "{part} missing: {text}");
        }
        assert!(!text.contains('\n'), "{text}");
    }

    #[test]
    fn looking_for_a_serial_number_with_no_board_is_not_found() {
        let none: Vec<(u16, u16, SerialBoard)> = Vec::new();
        let error =
            open_by_serial(none, VENDOR_ID, PRODUCT_ID, "X", serial_of, |d| Ok(d.0)).unwrap_err();
        assert!(matches!(error, BoardError::NotFound { .. }), "{error:?}");
        // A board that opens with an error reports it.
        let error = open_by_serial(
            serial_boards(),
            VENDOR_ID,
            PRODUCT_ID,
            "E6614C311B4A2F30",
            serial_of,
            |_| -> Result<u8, BoardError> { Err(BoardError::Usb("claiming".into())) },
        )
        .unwrap_err();
        assert!(matches!(error, BoardError::Usb(_)), "{error:?}");
    }

    #[test]
    fn unplug_errors_drop_the_link_others_do_not() {
        for gone in [rusb::Error::NoDevice, rusb::Error::Io, rusb::Error::Pipe] {
            assert!(matches!(classify(gone), TransportError::Gone), "{gone}");
        }
        for transient in [
            rusb::Error::Timeout,
            rusb::Error::Busy,
            rusb::Error::Overflow,
            rusb::Error::Interrupted,
        ] {
            assert!(
                matches!(
                    classify(transient),
                    TransportError::Transient(BoardError::Usb(_))
                ),
                "{transient}"
            );
        }
    }

    /// Where libusb has a USB stack and hot-plug events, a watch registers, reports no
    /// arrival before one, rests once a board is found and looks again with the link, and
    /// its thread ends when the watch is dropped. Elsewhere no watch starts and the link
    /// polls (nothing to check).
    #[test]
    fn a_hot_plug_watch_starts_rests_and_stops() {
        let Ok(context) = Context::new() else {
            return;
        };
        let Some(watch) = HotplugWatch::start(&context, VENDOR_ID, PRODUCT_ID) else {
            return;
        };
        assert!(watch.looking.load(Ordering::Acquire));
        assert!(!watch.take_arrival(), "an arrival before any");
        watch.found();
        assert!(!watch.looking.load(Ordering::Acquire));
        assert!(!watch.take_arrival());
        assert!(
            watch.looking.load(Ordering::Acquire),
            "not looking with the link"
        );
        assert!(watch.thread.is_some(), "no event thread");
        drop(watch);
    }
}

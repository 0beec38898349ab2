//! [`UrbBus`]: a `usb_device` [`UsbBus`] whose wire is the USB/IP server's URBs.
//!
//! A device controller holds one packet per endpoint and direction: the device writes
//! an IN packet and the host takes it (then the controller reports the IN complete);
//! the host puts an OUT packet (or a SETUP on endpoint 0) and the device reads it. This
//! bus does the same in memory. The device side is `usb_device`'s stack (its
//! [`UsbDevice`](usb_device::device::UsbDevice) and the classes) through the
//! [`UsbBus`] trait; the host side is the `pub(crate)` methods the server calls for
//! each URB ([`UrbBus::setup`], [`UrbBus::host_out`], [`UrbBus::host_in`], …). A
//! SETUP clears a stall of endpoint 0, as a device controller does.

use std::sync::{Mutex, MutexGuard};
use usb_device::bus::{PollResult, UsbBus};
use usb_device::endpoint::{EndpointAddress, EndpointType};
use usb_device::{Result, UsbDirection, UsbError};

/// Endpoint numbers per direction (0–15), as USB allows.
const ENDPOINTS: usize = 16;
/// Largest packet of a full-speed interrupt or control endpoint, bytes.
const MAX_PACKET: u16 = 64;

/// One endpoint in one direction.
#[derive(Debug, Clone, Default)]
struct Endpoint {
    allocated: bool,
    max_packet: u16,
    /// OUT: a packet from the host the device has not read. IN: a packet the device
    /// wrote that the host has not taken.
    packet: Option<Vec<u8>>,
    stalled: bool,
}

#[derive(Debug, Default)]
struct State {
    out: [Endpoint; ENDPOINTS],
    inn: [Endpoint; ENDPOINTS],
    /// The packet waiting on endpoint 0 OUT is a SETUP.
    setup: bool,
    /// IN endpoints whose packet the host took since the last poll (bit per number).
    in_complete: u16,
    /// A bus reset is to be reported at the next poll.
    reset: bool,
    address: u8,
}

/// The emulated board's USB device controller: one packet per endpoint and direction,
/// `usb_device`'s stack on the device side through [`UsbBus`], the USB/IP server's URBs
/// on the host side (see [`crate::usb_device`]).
#[derive(Debug, Default)]
pub struct UrbBus {
    state: Mutex<State>,
}

impl UrbBus {
    /// A controller with no endpoint allocated.
    pub fn new() -> Self {
        Self::default()
    }

    fn lock(&self) -> MutexGuard<'_, State> {
        // A panic elsewhere cannot leave the plain data inconsistent: go on with it.
        self.state.lock().unwrap_or_else(|e| e.into_inner())
    }

    /// The host resets the bus (a new host attached): the next poll says so.
    pub(crate) fn request_reset(&self) {
        self.lock().reset = true;
    }

    /// The host sends a SETUP packet on endpoint 0 (any unfinished control transfer
    /// is abandoned, and a stall of endpoint 0 cleared).
    pub(crate) fn setup(&self, packet: [u8; 8]) {
        let mut s = self.lock();
        s.out[0].packet = Some(packet.to_vec());
        s.out[0].stalled = false;
        s.inn[0].packet = None;
        s.inn[0].stalled = false;
        s.setup = true;
    }

    /// The host sends an OUT packet on endpoint `number`; `false` when the device has
    /// not read the previous one (the host would get a NAK) or the endpoint is stalled
    /// or does not exist.
    pub(crate) fn host_out(&self, number: usize, data: &[u8]) -> bool {
        let mut s = self.lock();
        let Some(ep) = s.out.get_mut(number) else {
            return false;
        };
        if !ep.allocated
            || ep.stalled
            || ep.packet.is_some()
            || data.len() > usize::from(ep.max_packet)
        {
            return false;
        }
        ep.packet = Some(data.to_vec());
        if number == 0 {
            s.setup = false;
        }
        true
    }

    /// The host polls IN endpoint `number`: the packet the device wrote, if any (the
    /// controller then reports the IN complete at the next poll).
    pub(crate) fn host_in(&self, number: usize) -> Option<Vec<u8>> {
        let mut s = self.lock();
        let packet = s.inn.get_mut(number)?.packet.take()?;
        s.in_complete |= 1 << number;
        Some(packet)
    }

    /// Whether endpoint `number` in `direction` is stalled.
    pub(crate) fn host_sees_stall(&self, number: usize, direction: UsbDirection) -> bool {
        let s = self.lock();
        let eps = match direction {
            UsbDirection::In => &s.inn,
            UsbDirection::Out => &s.out,
        };
        eps.get(number).is_some_and(|ep| ep.stalled)
    }

    /// The address the device took (SET_ADDRESS), 0 before.
    pub(crate) fn address(&self) -> u8 {
        self.lock().address
    }
}

impl UsbBus for UrbBus {
    fn alloc_ep(
        &mut self,
        ep_dir: UsbDirection,
        ep_addr: Option<EndpointAddress>,
        _ep_type: EndpointType,
        max_packet_size: u16,
        _interval: u8,
    ) -> Result<EndpointAddress> {
        if max_packet_size > MAX_PACKET {
            return Err(UsbError::Unsupported);
        }
        let s = self.state.get_mut().unwrap_or_else(|e| e.into_inner());
        let eps = match ep_dir {
            UsbDirection::In => &mut s.inn,
            UsbDirection::Out => &mut s.out,
        };
        let number = match ep_addr {
            Some(addr) => {
                let n = addr.index();
                if n >= ENDPOINTS || eps[n].allocated {
                    return Err(UsbError::InvalidEndpoint);
                }
                n
            }
            None => (1..ENDPOINTS)
                .find(|&n| !eps[n].allocated)
                .ok_or(UsbError::EndpointOverflow)?,
        };
        eps[number] = Endpoint {
            allocated: true,
            max_packet: max_packet_size,
            ..Endpoint::default()
        };
        Ok(EndpointAddress::from_parts(number, ep_dir))
    }

    fn enable(&mut self) {}

    fn reset(&self) {
        let mut guard = self.lock();
        let s = &mut *guard;
        for ep in s.out.iter_mut().chain(s.inn.iter_mut()) {
            ep.packet = None;
            ep.stalled = false;
        }
        s.setup = false;
        s.in_complete = 0;
        s.address = 0;
    }

    fn set_device_address(&self, addr: u8) {
        self.lock().address = addr;
    }

    fn write(&self, ep_addr: EndpointAddress, buf: &[u8]) -> Result<usize> {
        let mut s = self.lock();
        let ep = s
            .inn
            .get_mut(ep_addr.index())
            .filter(|ep| ep.allocated && ep_addr.direction() == UsbDirection::In)
            .ok_or(UsbError::InvalidEndpoint)?;
        if buf.len() > usize::from(ep.max_packet) {
            return Err(UsbError::BufferOverflow);
        }
        if ep.packet.is_some() {
            return Err(UsbError::WouldBlock);
        }
        ep.packet = Some(buf.to_vec());
        Ok(buf.len())
    }

    fn read(&self, ep_addr: EndpointAddress, buf: &mut [u8]) -> Result<usize> {
        let mut s = self.lock();
        let number = ep_addr.index();
        let ep = s
            .out
            .get_mut(number)
            .filter(|ep| ep.allocated && ep_addr.direction() == UsbDirection::Out)
            .ok_or(UsbError::InvalidEndpoint)?;
        let len = match &ep.packet {
            None => return Err(UsbError::WouldBlock),
            Some(p) if p.len() > buf.len() => return Err(UsbError::BufferOverflow),
            Some(p) => p.len(),
        };
        if let Some(p) = ep.packet.take() {
            buf[..len].copy_from_slice(&p);
        }
        if number == 0 {
            s.setup = false;
        }
        Ok(len)
    }

    fn set_stalled(&self, ep_addr: EndpointAddress, stalled: bool) {
        let mut s = self.lock();
        let eps = match ep_addr.direction() {
            UsbDirection::In => &mut s.inn,
            UsbDirection::Out => &mut s.out,
        };
        if let Some(ep) = eps.get_mut(ep_addr.index()) {
            ep.stalled = stalled;
        }
    }

    fn is_stalled(&self, ep_addr: EndpointAddress) -> bool {
        self.host_sees_stall(ep_addr.index(), ep_addr.direction())
    }

    fn suspend(&self) {}

    fn resume(&self) {}

    fn poll(&self) -> PollResult {
        let mut s = self.lock();
        if s.reset {
            s.reset = false;
            return PollResult::Reset;
        }
        let mut ep_out = 0u16;
        let mut ep_setup = 0u16;
        for (n, ep) in s.out.iter().enumerate() {
            if ep.packet.is_some() {
                if n == 0 && s.setup {
                    ep_setup |= 1;
                } else {
                    ep_out |= 1 << n;
                }
            }
        }
        let ep_in_complete = std::mem::take(&mut s.in_complete);
        if ep_out | ep_setup | ep_in_complete == 0 {
            return PollResult::None;
        }
        PollResult::Data {
            ep_out,
            ep_in_complete,
            ep_setup,
        }
    }
}

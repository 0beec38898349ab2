//! What a driver noticed since it was last asked: sticky events and counters.

/// Sticky events since the last [`crate::MouseDriver::take_events`]; they become the
/// per-report flags of [`foosball_protocol::PaddleStatus`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct DriverEvents {
    /// A frame with a bad start or stop bit arrived.
    pub framing_error: bool,
    /// A frame with bad odd parity arrived.
    pub parity_error: bool,
    /// The mouse finished (re-)initialisation and is streaming (power-up, hot-plug,
    /// spontaneous restart, found again after being absent).
    pub reinitialised: bool,
}

impl DriverEvents {
    /// Whether no event is set.
    pub const fn is_empty(&self) -> bool {
        !(self.framing_error || self.parity_error || self.reinitialised)
    }
}

/// A PS/2 line held low by something other than the mouse clocking: a short to
/// ground, a damaged cable or connector, a failed level shifter. Unlike an unplugged
/// mouse (both lines idle high through the pull-ups), the port cannot work at all
/// until it is fixed.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum LineFault {
    /// The clock line stays low with the host not pulling it.
    ClockStuckLow,
    /// The data line stays low with the clock idle (no frame being clocked).
    DataStuckLow,
}

/// Wrapping diagnostic counters since the driver was created.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct DriverStats {
    /// Frames received, good or bad.
    pub frames: u32,
    /// Stream packets delivered.
    pub packets: u32,
    /// Frames with a bad start or stop bit.
    pub framing_errors: u32,
    /// Frames with bad parity.
    pub parity_errors: u32,
    /// Bytes or partial packets dropped to resynchronise the packet stream.
    pub resyncs: u32,
    /// Times the driver declared the port absent (timeout, failed send, failed init).
    pub absences: u32,
    /// Times initialisation completed (the mouse started streaming).
    pub inits: u32,
    /// Spontaneous self-test results (`0xAA 0x00`) seen: mouse restarts or hot-plugs.
    pub restarts: u32,
    /// Status requests sent: to a silent streaming mouse (liveness), or after a
    /// doubtful byte (a restart seen only in part).
    pub probes: u32,
    /// Commands sent again after a failed send or a missing reply.
    pub retries: u32,
    /// Resend requests (`0xFE`) sent for garbled packets.
    pub resends: u32,
    /// Packets lost for good: garbled after every resend, or cut short.
    pub dropped: u32,
    /// Times a line was found stuck low ([`LineFault`]).
    pub line_faults: u32,
    /// Receiver overflows: the RX FIFO was full, bits were lost and the receiver was
    /// restarted (reported by the platform, [`crate::MouseDriver::on_rx_stall`]).
    pub fifo_stalls: u32,
    /// Times the mouse was configured again without a reset: a status request
    /// showed settings other than the configured ones (it restarted unseen), or
    /// [`crate::MouseDriver::set_config`] changed them.
    pub reconfigurations: u32,
}

//! Misbehaviour injected into an emulated PS/2 mouse: parity errors, dropped bytes,
//! silence, hot-unplug and replug, spontaneous restarts.
//!
//! A [`Fault`] is applied to one port, either at once ([`crate::board::EmulatedBoard::inject`])
//! or at an emulated time ([`crate::board::EmulatedBoard::schedule`], or the `faults` list
//! of a motion script). The per-port [`PortFaults`] holds the probabilistic faults and
//! decides them with a seeded generator, so a run is reproducible from its seed.

use crate::rng::SimRng;
use serde::{Deserialize, Serialize};

/// One kind of misbehaviour of a port's mouse.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum Fault {
    /// The mouse is unplugged: it stops driving the lines at once (a frame in progress
    /// is cut off) and loses its settings.
    Unplug,
    /// The mouse is plugged (back) in: it powers up, runs its self-test and sends
    /// `0xAA 0x00`, as after a reset.
    Plug,
    /// The mouse restarts on its own (brown-out, firmware watchdog): self-test, then
    /// `0xAA 0x00`, settings back to defaults, streaming disabled.
    Restart,
    /// The mouse goes silent (hangs): it neither sends nor clocks in commands.
    Silence,
    /// A silent mouse resumes where it stopped.
    Resume,
    /// The mouse drops its next `count` device-to-host bytes (never sends them).
    DropBytes {
        /// Bytes to drop.
        count: u32,
    },
    /// Each device-to-host frame has its parity bit inverted with this probability.
    ParityErrorRate {
        /// Probability per frame, 0–1.
        probability: f64,
    },
    /// Each device-to-host byte is dropped with this probability.
    DropRate {
        /// Probability per byte, 0–1.
        probability: f64,
    },
}

impl Fault {
    /// Checks the fault's parameters (probabilities within 0–1).
    pub fn validate(&self) -> Result<(), String> {
        match *self {
            Fault::ParityErrorRate { probability } | Fault::DropRate { probability } => {
                if probability.is_finite() && (0.0..=1.0).contains(&probability) {
                    Ok(())
                } else {
                    Err(format!(
                        "probability must be between 0 and 1, got {probability}"
                    ))
                }
            }
            _ => Ok(()),
        }
    }
}

/// A fault to apply to one port at a time given in a script.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ScheduledFault {
    /// Emulated time, seconds since power-up.
    pub at_s: f64,
    /// Port (rod) index, 0–7.
    pub port: usize,
    /// What happens.
    pub fault: Fault,
}

/// The fault state of one port, consulted by the wire for every byte it sends.
#[derive(Debug, Clone)]
pub struct PortFaults {
    /// Whether a mouse is plugged into the port.
    pub plugged: bool,
    /// Whether the mouse is hung (see [`Fault::Silence`]).
    pub silent: bool,
    /// Probability per frame of an inverted parity bit.
    pub parity_error_probability: f64,
    /// Probability per byte of dropping it.
    pub drop_probability: f64,
    /// Bytes still to drop unconditionally.
    pub drop_pending: u32,
    /// Frames sent with an inverted parity bit so far.
    pub parity_errors_injected: u64,
    /// Bytes dropped so far.
    pub bytes_dropped: u64,
    rng: SimRng,
}

impl PortFaults {
    /// A well-behaved, plugged-in port whose random faults draw from `rng`.
    pub fn new(rng: SimRng) -> Self {
        Self {
            plugged: true,
            silent: false,
            parity_error_probability: 0.0,
            drop_probability: 0.0,
            drop_pending: 0,
            parity_errors_injected: 0,
            bytes_dropped: 0,
            rng,
        }
    }

    /// Whether the mouse drives the lines at all (plugged and not hung).
    pub fn device_active(&self) -> bool {
        self.plugged && !self.silent
    }

    /// Decides whether the byte about to be sent is dropped.
    pub fn take_drop(&mut self) -> bool {
        let drop = if self.drop_pending > 0 {
            self.drop_pending -= 1;
            true
        } else {
            self.rng.chance(self.drop_probability)
        };
        if drop {
            self.bytes_dropped += 1;
        }
        drop
    }

    /// Decides whether the frame about to be sent gets an inverted parity bit.
    pub fn take_parity_error(&mut self) -> bool {
        let flip = self.rng.chance(self.parity_error_probability);
        if flip {
            self.parity_errors_injected += 1;
        }
        flip
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn faults_parse_from_json() {
        let f: Vec<ScheduledFault> = serde_json::from_str(
            r#"[{"at_s": 1.5, "port": 2, "fault": "unplug"},
                {"at_s": 2, "port": 2, "fault": {"parity_error_rate": {"probability": 0.01}}},
                {"at_s": 3, "port": 0, "fault": {"drop_bytes": {"count": 1}}}]"#,
        )
        .unwrap();
        assert_eq!(f[0].fault, Fault::Unplug);
        assert_eq!(f[1].fault, Fault::ParityErrorRate { probability: 0.01 });
        assert_eq!(f[2].fault, Fault::DropBytes { count: 1 });
        assert!(Fault::DropRate { probability: 1.5 }.validate().is_err());
        assert!(Fault::DropRate { probability: 0.5 }.validate().is_ok());
    }

    #[test]
    fn pending_drops_come_first() {
        let mut f = PortFaults::new(SimRng::new(1));
        f.drop_pending = 2;
        assert!(f.take_drop());
        assert!(f.take_drop());
        assert!(!f.take_drop());
        assert_eq!(f.bytes_dropped, 2);
    }
}

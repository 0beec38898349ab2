//! Kicks → haptic pulses on the board (paper §6).
//!
//! A `Kick { rod, speed }` of a rod played by a person becomes, through
//! [`board_link::haptics::Haptics::kick`], the OUT report that pulses the motor of that
//! rod's paddle (port [`crate::table::Rod::port`]); kicks of computer rods and other
//! events give nothing. The clock is match time (`t_ms` of the event).

use super::RodController;
use crate::rules::{Event, TimedEvent};
use crate::table::Table;
use board_link::haptics::{Haptics, KickFeel};
use foosball_protocol::OutReport;
use std::time::Duration;

/// Turns a match's kick events into OUT reports for the board.
#[derive(Debug, Clone)]
pub struct KickHaptics {
    haptics: Haptics,
    /// Per rod of the table: its paddle port when a person plays it.
    ports: Vec<Option<usize>>,
}

impl KickHaptics {
    /// For `table` with `controllers` (`[home, away]`) and the default feel.
    pub fn new(table: &Table, controllers: [RodController; 2]) -> Self {
        Self::with_feel(table, controllers, KickFeel::DEFAULT)
    }

    /// For `table` with `controllers` and a kick-to-pulse mapping.
    pub fn with_feel(table: &Table, controllers: [RodController; 2], feel: KickFeel) -> Self {
        Self {
            haptics: Haptics::new(feel),
            ports: table
                .rods
                .iter()
                .map(|r| (controllers[r.team.index()] == RodController::Player).then_some(r.port))
                .collect(),
        }
    }

    /// The OUT reports to send for `events`, in order (none for soft kicks, computer
    /// rods and other events).
    pub fn reports(&mut self, events: &[TimedEvent]) -> Vec<OutReport> {
        let mut out = Vec::new();
        for e in events {
            if let Event::Kick { rod, speed } = e.event {
                let Some(Some(port)) = self.ports.get(rod).copied() else {
                    continue;
                };
                let now = Duration::from_millis(e.t_ms);
                if let Some(report) = self.haptics.kick(port, speed as f32, now) {
                    out.push(report);
                }
            }
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rules::ServeReason;
    use crate::side::Side;

    fn kick(t_ms: u64, rod: usize, speed: f64) -> TimedEvent {
        TimedEvent {
            t_ms,
            event: Event::Kick { rod, speed },
        }
    }

    #[test]
    fn player_kicks_pulse_their_paddle_and_nothing_else_does() {
        let table = Table::standard();
        let mut h = KickHaptics::new(&table, [RodController::Player, RodController::Computer]);
        // Rod 5 is the Home attack on port 5; rod 2 is the Away attack (computer).
        let events = [
            kick(10, 5, 3.0),
            kick(11, 2, 3.0),
            kick(12, 5, 0.1), // too soft
            TimedEvent {
                t_ms: 13,
                event: Event::Serve {
                    to: Side::Home,
                    reason: ServeReason::Kickoff,
                },
            },
        ];
        let reports = h.reports(&events);
        assert_eq!(reports.len(), 1);
        let pulse = reports[0].haptics[table.rods[5].port];
        assert!(pulse.strength > 80 && pulse.duration_ms >= 20, "{pulse:?}");
        for (port, p) in reports[0].haptics.iter().enumerate() {
            if port != table.rods[5].port {
                assert_eq!(p.duration_ms, 0, "port {port}");
            }
        }
        // A harder kick is stronger.
        let r2 = h.reports(&[kick(500, 5, 6.0)]);
        assert_eq!(r2[0].haptics[5].strength, 255);
    }
}

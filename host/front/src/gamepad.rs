//! A gamepad, when one is plugged in (gilrs). No gamepad, or no gamepad support on this
//! machine, is not an error: [`Gamepads::state`] is then `None`.

use crate::controls::PadState;
use gilrs::{Axis, Button, Gilrs};

/// Stick deflection below this counts as centred.
const DEAD_ZONE: f32 = 0.15;

/// The first connected gamepad's state, with edges (kick, rod choice) per frame.
pub struct Gamepads {
    gilrs: Option<Gilrs>,
    last: [bool; 3],
    /// Why gamepads are unavailable, if they are.
    pub notice: Option<String>,
}

impl Gamepads {
    /// Opens gamepad support; never fails.
    pub fn open() -> Self {
        match Gilrs::new() {
            Ok(g) => Self {
                gilrs: Some(g),
                last: [false; 3],
                notice: None,
            },
            Err(e) => Self {
                gilrs: None,
                last: [false; 3],
                notice: Some(format!("no gamepad support: {e}")),
            },
        }
    }

    /// The state of the first connected gamepad; `None` without one.
    pub fn state(&mut self) -> Option<PadState> {
        let gilrs = self.gilrs.as_mut()?;
        while gilrs.next_event().is_some() {}
        let (_, pad) = gilrs.gamepads().find(|(_, g)| g.is_connected())?;
        let axis = |a: Axis| {
            let v = pad.value(a);
            if v.abs() < DEAD_ZONE {
                0.0
            } else {
                f64::from(v)
            }
        };
        let now = [
            pad.is_pressed(Button::South),
            pad.is_pressed(Button::LeftTrigger),
            pad.is_pressed(Button::RightTrigger),
        ];
        let edge = |i: usize| now[i] && !self.last[i];
        let state = PadState {
            slide: axis(Axis::LeftStickY),
            spin: axis(Axis::RightStickX),
            kick: edge(0),
            push: pad.is_pressed(Button::Start),
            choose: i32::from(edge(2)) - i32::from(edge(1)),
        };
        self.last = now;
        Some(state)
    }
}

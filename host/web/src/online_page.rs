//! The page's online match, without the page: the front end's online screen
//! (`space_foosball_front::online::screen`: a room on a signalling server, the match with
//! rollback, the lobby, the end or why it stopped) with the page's keyboard, mouse and
//! gamepad as this side's rods.
//!
//! The browser glue opens the room and runs its traffic on the page's event loop;
//! [`OnlinePage::frame`] is called once per animation frame with the page's clock.

use crate::keyboard::KeyboardBoard;
use foosball_render::{FrameSnapshot, Hud, Screen};
use space_foosball::side::Side;
use space_foosball::table::Table;
use space_foosball_front::controls::Key;
use space_foosball_front::online::input::SideInput;
use space_foosball_front::online::rollback::{steps_of_frame, MatchTerms, OnlineMatch};
use space_foosball_front::online::room::{PeerChannel, PeerId, Room};
use space_foosball_front::online::screen::{in_room, OnlineScreen, OnlineStatus, OnlineView};
use space_foosball_front::online::session::OnlineError;

/// The page's online match. See the [module](self).
pub struct OnlinePage {
    screen: OnlineScreen<PeerId, PeerChannel>,
    table: Table,
    side: Side,
    keyboard: KeyboardBoard,
    /// Frames the emulated rods have been moved through.
    moved_to: u64,
}

impl OnlinePage {
    /// The match of `terms` played as `side` in room `room_name`, opened as `room`.
    pub fn new(
        room: Room,
        room_name: &str,
        side: Side,
        terms: MatchTerms,
        input_delay: usize,
    ) -> Result<Self, OnlineError> {
        let mut keyboard = KeyboardBoard::new(&terms.table);
        // The keyboard starts on Home's goalkeeper: Away's player switches team once.
        if side == Side::Away {
            keyboard.key(Key::SwitchTeam, true);
            keyboard.key(Key::SwitchTeam, false);
        }
        let table = terms.table.clone();
        let place = format!("room {room_name}");
        let screen = OnlineScreen::new(
            in_room(room),
            &place,
            side,
            OnlineMatch::new(&terms)?,
            input_delay,
        );
        Ok(Self {
            screen,
            table,
            side,
            keyboard,
            moved_to: 0,
        })
    }

    /// The emulated rods the page's keys, mouse and gamepad move.
    pub fn keyboard(&mut self) -> &mut KeyboardBoard {
        &mut self.keyboard
    }

    /// Advances the lobby or the match to `now_s` (the page's clock, s) and returns what
    /// the frame shows.
    pub fn frame(&mut self, now_s: f64) -> (FrameSnapshot, Screen, Hud) {
        let (table, side, keyboard, moved) = (
            &self.table,
            self.side,
            &mut self.keyboard,
            &mut self.moved_to,
        );
        // This side's rods for frame `f`: the emulated rods moved through the frame's
        // milliseconds (once per frame: a frame held back for the other side is asked for
        // again), then read.
        let mut local = |f: u64| {
            if *moved <= f {
                for _ in 0..steps_of_frame(f) {
                    keyboard.step_report();
                }
                *moved = f + 1;
            }
            let poses: Vec<[f64; 2]> = (0..table.rods.len())
                .map(|r| keyboard.pose(r).unwrap_or_default())
                .collect();
            SideInput::from_poses(table, side, &poses)
        };
        self.screen.frame(now_s, &mut local)
    }

    /// The online match's part of the page's status line.
    pub fn status(&self) -> OnlineStatus {
        self.screen.status()
    }
}

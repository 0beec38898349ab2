//! The page's online match, without the page: a room on a signalling server, the match
//! with rollback (the desktop's own session, `space_foosball_front::online`), the page's
//! keyboard, mouse and gamepad as this side's rods, and what each frame shows: the lobby
//! (room, the other side, ping, input delay), the match, its end, or why it stopped.
//!
//! The browser glue opens the [`Room`] and runs its traffic on the page's event loop;
//! [`OnlinePage::frame`] is called once per animation frame with the page's clock.

use crate::keyboard::KeyboardBoard;
use foosball_render::{FrameSnapshot, Hud, Screen};
use serde_json::{json, Value};
use space_foosball::side::Side;
use space_foosball::table::Table;
use space_foosball_front::match_scene::MatchScene;
use space_foosball_front::online::input::SideInput;
use space_foosball_front::online::rollback::{steps_of_frame, MatchTerms, OnlineMatch};
use space_foosball_front::online::room::{PeerId, Room};
use space_foosball_front::online::session::{
    Notice, OnlineError, OnlineSession, Stand, CONNECT_TIMEOUT_S,
};

/// Where the online match stands.
enum Stage {
    /// Waiting in the room for the other side.
    Meeting(Room),
    /// Playing (or lingering after the end, until the other side has it too).
    Playing {
        /// The room, kept open for the match.
        _room: Room,
        session: Box<OnlineSession<PeerId>>,
    },
    /// Stopped before the end: why.
    Stopped(String),
}

/// The page's online match. See the [module](self).
pub struct OnlinePage {
    table: Table,
    side: Side,
    room_name: String,
    input_delay: usize,
    terms: MatchTerms,
    keyboard: KeyboardBoard,
    scene: MatchScene,
    stage: Stage,
    /// The match before the other side came (drawn in the lobby).
    waiting: OnlineMatch,
    started_s: Option<f64>,
    peer: Option<String>,
    over: bool,
    desync_frames: Vec<i32>,
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
    ) -> anyhow::Result<Self> {
        let waiting = OnlineMatch::new(&terms)?;
        let mut keyboard = KeyboardBoard::new(&terms.table);
        // The keyboard plays this side (it starts on Home's goalkeeper).
        if side == Side::Away {
            keyboard.key(space_foosball_front::controls::Key::SwitchTeam, true);
            keyboard.key(space_foosball_front::controls::Key::SwitchTeam, false);
        }
        Ok(Self {
            table: terms.table.clone(),
            side,
            room_name: room_name.to_string(),
            input_delay,
            scene: MatchScene::new(&terms.table),
            terms,
            keyboard,
            stage: Stage::Meeting(room),
            waiting,
            started_s: None,
            peer: None,
            over: false,
            desync_frames: Vec::new(),
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
        let started = *self.started_s.get_or_insert(now_s);
        let stage = std::mem::replace(&mut self.stage, Stage::Stopped(String::new()));
        self.stage = match stage {
            Stage::Meeting(mut room) => match room.peer() {
                Some(peer) => self.start(room, peer, now_s),
                None if now_s - started > CONNECT_TIMEOUT_S => Stage::Stopped(format!(
                    "NOBODY CAME TO ROOM {} WITHIN {CONNECT_TIMEOUT_S} S",
                    self.room_name
                )),
                None => Stage::Meeting(room),
            },
            Stage::Playing { _room, mut session } => match self.play(&mut session, now_s) {
                Ok(()) => Stage::Playing { _room, session },
                Err(e) => Stage::Stopped(e.to_string().to_uppercase()),
            },
            stopped => stopped,
        };
        self.show()
    }

    fn start(&mut self, mut room: Room, peer: PeerId, now_s: f64) -> Stage {
        let Some(channel) = room.take_channel() else {
            return Stage::Stopped("THE ROOM'S CHANNEL IS GONE".into());
        };
        match OnlineSession::start(
            channel,
            peer,
            self.side,
            &self.terms,
            self.input_delay,
            now_s,
        ) {
            Ok(session) => {
                self.peer = Some(peer.to_string());
                Stage::Playing {
                    _room: room,
                    session: Box::new(session),
                }
            }
            Err(e) => Stage::Stopped(e.to_string().to_uppercase()),
        }
    }

    fn play(&mut self, session: &mut OnlineSession<PeerId>, now_s: f64) -> Result<(), OnlineError> {
        let (table, side, keyboard) = (&self.table, self.side, &mut self.keyboard);
        // This side's rods for frame `f`: the emulated rods moved through the frame's
        // milliseconds (once per frame: a frame held back for the other side is asked for
        // again), then read.
        let moved = &mut self.moved_to;
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
        let mut notices = Vec::new();
        let stand = session.poll(now_s, &mut local, &mut notices)?;
        for n in notices {
            if let Notice::Desync { frame } = n {
                self.desync_frames.push(frame);
            }
        }
        self.over = matches!(stand, Stand::Over | Stand::Closed);
        Ok(())
    }

    fn session(&self) -> Option<&OnlineSession<PeerId>> {
        match &self.stage {
            Stage::Playing { session, .. } => Some(session),
            _ => None,
        }
    }

    fn show(&self) -> (FrameSnapshot, Screen, Hud) {
        let game = self.session().map_or(&self.waiting, |s| s.game());
        let snapshot = self.scene.snapshot(&game.game().snapshot());
        let team = format!("{:?}", self.side).to_uppercase();
        let mut hud = Hud::default();
        hud.lines
            .push(format!("ONLINE: ROOM {}, YOU PLAY {team}", self.room_name));
        let screen = match (&self.stage, self.session()) {
            (Stage::Meeting(_), _) => {
                hud.heading = format!("WAITING IN ROOM {}", self.room_name);
                Screen::Attract
            }
            (Stage::Stopped(why), _) => {
                hud.heading = why.clone();
                Screen::Attract
            }
            (_, Some(s)) => {
                let ping = s
                    .ping_ms()
                    .map_or_else(|| "-".to_string(), |p| p.to_string());
                hud.lines.push(format!(
                    "PEER {}  PING {ping} MS  INPUT DELAY {} FRAMES",
                    self.peer.as_deref().unwrap_or("-"),
                    self.input_delay
                ));
                if !self.desync_frames.is_empty() {
                    hud.heading = "THE TWO SIDES' MATCHES DIFFER".into();
                }
                if self.over {
                    Screen::FinalResult
                } else {
                    Screen::Match
                }
            }
            (_, None) => Screen::Attract,
        };
        (snapshot, screen, hud)
    }

    /// The online match's part of the page's status line.
    pub fn status(&self) -> Value {
        let (stage, error) = match &self.stage {
            Stage::Meeting(_) => ("meeting", None),
            Stage::Playing { .. } if self.over => ("over", None),
            Stage::Playing { .. } => ("playing", None),
            Stage::Stopped(why) => ("stopped", Some(why.as_str())),
        };
        let game = self.session().map_or(&self.waiting, |s| s.game());
        let m = game.game();
        let (rollbacks, resimulated) = game.rollbacks();
        json!({
            "stage": stage,
            "error": error,
            "room": self.room_name,
            "side": self.side,
            "peer": self.peer,
            "ping_ms": self.session().and_then(OnlineSession::ping_ms).map(|p| p as u64),
            "input_delay_frames": self.input_delay,
            "frames": game.end().min(game.state_frame()),
            "match_over": m.is_over(),
            "score": m.score(),
            "state_hash": format!("{:032x}", m.state_hash()),
            "desyncs": self.desync_frames.len(),
            "rollbacks": rollbacks,
            "resimulated_frames": resimulated,
        })
    }
}

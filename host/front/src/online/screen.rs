//! What an online match shows, in the desktop's window and in the page alike: the lobby
//! (where, which team, the other side, its ping, the input delay), the match, its end, or
//! why it stopped (nobody came, the other side left, the two sides' matches differ).

use super::input::SideInput;
use super::rollback::{MatchTerms, OnlineMatch};
use super::room::{PeerId, Room};
use super::session::{Notice, OnlineError, OnlineSession, Stand, CONNECT_TIMEOUT_S};
use crate::match_scene::MatchScene;
use foosball_render::{FrameSnapshot, Hud, Screen};
use serde::Serialize;
use space_foosball::side::Side;
use std::fmt::Debug;
use std::hash::Hash;

/// Tries to start the session (the caller's clock, s): `None` while the other side has
/// not come yet.
pub type Connect<A> = Box<dyn FnMut(f64) -> Result<Option<OnlineSession<A>>, OnlineError>>;

/// Where a match by room starts: when the room's other side has come, over its channel.
/// The room stays open inside the returned closure for as long as it is kept.
pub fn in_room(
    mut room: Room,
    side: Side,
    terms: MatchTerms,
    input_delay: usize,
) -> Connect<PeerId> {
    let mut started = false;
    Box::new(move |now_s| {
        if started {
            return Ok(None);
        }
        let Some(peer) = room.peer() else {
            return Ok(None);
        };
        let channel = room.take_channel().ok_or(OnlineError::ChannelGone)?;
        started = true;
        OnlineSession::start(channel, peer, side, &terms, input_delay, now_s).map(Some)
    })
}

/// Where the online match stands, for a status line.
#[derive(Debug, Clone, Serialize)]
pub struct OnlineStatus {
    /// `meeting`, `playing`, `over` or `stopped`.
    pub stage: &'static str,
    /// Why it stopped.
    pub error: Option<String>,
    /// The room's name or the other side's address.
    pub place: String,
    /// The team played here.
    pub side: Side,
    /// The other side, once it came.
    pub peer: Option<String>,
    /// Round trip to the other side, ms, once measured.
    pub ping_ms: Option<u64>,
    /// Frames of input delay.
    pub input_delay_frames: usize,
    /// Frames played (to the end, once over).
    pub frames: u64,
    /// Whether the match ended (not only its frames).
    pub match_over: bool,
    /// Score `[home, away]`.
    pub score: [u32; 2],
    /// Checksum of the state (hex): the same on both sides.
    pub state_hash: String,
    /// Desyncs detected.
    pub desyncs: usize,
    /// States loaded (rollbacks).
    pub rollbacks: u64,
    /// Frames stepped again after them.
    pub resimulated_frames: u64,
}

/// An online match as a screen: connecting, playing, over or stopped. See the
/// [module](self).
pub trait OnlineView {
    /// Advances to `now_s` (the caller's clock, s), this side's rods for frame `f` from
    /// `local(f)`, and returns what the frame shows.
    fn frame(
        &mut self,
        now_s: f64,
        local: &mut dyn FnMut(u64) -> SideInput,
    ) -> (FrameSnapshot, Screen, Hud);
    /// Where it stands.
    fn status(&self) -> OnlineStatus;
    /// The match as this side has it.
    fn game(&self) -> &OnlineMatch;
}

/// An online match as a screen, its peers named by `A`.
pub struct OnlineScreen<A>
where
    A: Clone + PartialEq + Eq + Hash + Debug + Send + Sync + 'static,
{
    connect: Connect<A>,
    session: Option<OnlineSession<A>>,
    stopped: Option<String>,
    /// The match before the other side came (drawn in the lobby).
    waiting: OnlineMatch,
    scene: MatchScene,
    side: Side,
    place: String,
    input_delay: usize,
    started_s: Option<f64>,
    over: bool,
    desync_frames: Vec<i32>,
}

impl<A> OnlineScreen<A>
where
    A: Clone + PartialEq + Eq + Hash + Debug + Send + Sync + 'static,
{
    /// The match of `terms` played as `side` at `place` (a room's name, an address),
    /// started by `connect`.
    pub fn new(
        connect: Connect<A>,
        place: &str,
        side: Side,
        terms: &MatchTerms,
        input_delay: usize,
    ) -> Result<Self, OnlineError> {
        Ok(Self {
            connect,
            session: None,
            stopped: None,
            waiting: OnlineMatch::new(terms)?,
            scene: MatchScene::new(&terms.table),
            side,
            place: place.to_string(),
            input_delay,
            started_s: None,
            over: false,
            desync_frames: Vec::new(),
        })
    }

    fn step(
        &mut self,
        now_s: f64,
        local: &mut dyn FnMut(u64) -> SideInput,
    ) -> Result<(), OnlineError> {
        let started = *self.started_s.get_or_insert(now_s);
        if self.session.is_none() {
            self.session = (self.connect)(now_s)?;
            if self.session.is_none() && now_s - started > CONNECT_TIMEOUT_S {
                return Err(OnlineError::NoAnswer {
                    peer: self.place.clone(),
                });
            }
        }
        let Some(session) = &mut self.session else {
            return Ok(());
        };
        let mut notices = Vec::new();
        let stand = session.poll(now_s, local, &mut notices)?;
        for n in notices {
            if let Notice::Desync { frame } = n {
                self.desync_frames.push(frame);
            }
        }
        self.over = matches!(stand, Stand::Over | Stand::Closed);
        Ok(())
    }
}

impl<A> OnlineView for OnlineScreen<A>
where
    A: Clone + PartialEq + Eq + Hash + Debug + Send + Sync + 'static,
{
    fn frame(
        &mut self,
        now_s: f64,
        local: &mut dyn FnMut(u64) -> SideInput,
    ) -> (FrameSnapshot, Screen, Hud) {
        if self.stopped.is_none() {
            if let Err(e) = self.step(now_s, local) {
                self.stopped = Some(e.to_string().to_uppercase());
            }
        }
        let snapshot = self.scene.snapshot(&self.game().game().snapshot());
        let team = format!("{:?}", self.side).to_uppercase();
        let mut hud = Hud::default();
        hud.lines.push(format!(
            "ONLINE: {}, YOU PLAY {team}",
            self.place.to_uppercase()
        ));
        let screen = match (&self.stopped, &self.session) {
            (Some(why), _) => {
                hud.heading = why.clone();
                Screen::Attract
            }
            (None, None) => {
                hud.heading = format!("WAITING FOR THE OTHER SIDE ({})", self.place.to_uppercase());
                Screen::Attract
            }
            (None, Some(s)) => {
                let ping = s
                    .ping_ms()
                    .map_or_else(|| "-".to_string(), |p| p.to_string());
                let peer = format!("{:?}", s.remote()).to_uppercase();
                hud.lines.push(format!(
                    "PEER {peer}  PING {ping} MS  INPUT DELAY {} FRAMES",
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
        };
        (snapshot, screen, hud)
    }

    fn status(&self) -> OnlineStatus {
        let stage = match (&self.stopped, &self.session) {
            (Some(_), _) => "stopped",
            (None, None) => "meeting",
            (None, Some(_)) if self.over => "over",
            (None, Some(_)) => "playing",
        };
        let game = self.game();
        let m = game.game();
        let (rollbacks, resimulated_frames) = game.rollbacks();
        OnlineStatus {
            stage,
            error: self.stopped.clone(),
            place: self.place.clone(),
            side: self.side,
            peer: self.session.as_ref().map(|s| format!("{:?}", s.remote())),
            ping_ms: self
                .session
                .as_ref()
                .and_then(OnlineSession::ping_ms)
                .map(|p| u64::try_from(p).unwrap_or(u64::MAX)),
            input_delay_frames: self.input_delay,
            frames: game.end().min(game.state_frame()),
            match_over: m.is_over(),
            score: m.score(),
            state_hash: format!("{:032x}", m.state_hash()),
            desyncs: self.desync_frames.len(),
            rollbacks,
            resimulated_frames,
        }
    }

    fn game(&self) -> &OnlineMatch {
        self.session.as_ref().map_or(&self.waiting, |s| s.game())
    }
}

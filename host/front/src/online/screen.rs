//! What an online match shows, in the desktop's window and in the page alike: the lobby
//! (where, which team, the other side, its ping, the input delay), the match, its end, or
//! why it stopped (nobody came, the other side left, the two sides' matches differ).

use super::input::SideInput;
use super::rollback::OnlineMatch;
use super::room::{PeerChannel, PeerId, Room};
use super::session::{Notice, OnlineError, OnlineSession, Stand, CONNECT_TIMEOUT_S};
use crate::match_scene::MatchScene;
use foosball_render::{FrameSnapshot, Hud, Screen};
use ggrs::NonBlockingSocket;
use serde::Serialize;
use space_foosball::play::MatchSnapshot;
use space_foosball::side::Side;
use std::fmt::Debug;
use std::hash::Hash;

/// Looks for the other side (no sooner than asked): the socket to it and its name, once
/// it is there; `None` while it has not come yet.
pub type Connect<A, S> = Box<dyn FnMut() -> Result<Option<(S, A)>, OnlineError>>;

/// Where a match by room starts: when the room's other side has come, over its channel.
/// The room stays open inside the returned closure for as long as it is kept.
pub fn in_room(mut room: Room) -> Connect<PeerId, PeerChannel> {
    Box::new(move || {
        let Some(peer) = room.peer() else {
            return Ok(None);
        };
        let channel = room.take_channel().ok_or(OnlineError::ChannelGone)?;
        Ok(Some((channel, peer)))
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
    /// The match as this side has it (none once a session failed to start with it).
    fn game(&self) -> Option<&OnlineMatch>;
}

/// An online match as a screen, its peers named by `A`, reached over sockets `S`.
pub struct OnlineScreen<A, S>
where
    A: Clone + PartialEq + Eq + Hash + Debug + Send + Sync + 'static,
    S: NonBlockingSocket<A> + 'static,
{
    connect: Connect<A, S>,
    session: Option<OnlineSession<A>>,
    stopped: Option<String>,
    /// The match until the other side comes (drawn in the lobby).
    waiting: Option<OnlineMatch>,
    /// The table at the start, drawn where there is no match.
    rest: MatchSnapshot,
    scene: MatchScene,
    side: Side,
    place: String,
    input_delay: usize,
    started_s: Option<f64>,
    over: bool,
    desync_frames: Vec<i32>,
}

impl<A, S> OnlineScreen<A, S>
where
    A: Clone + PartialEq + Eq + Hash + Debug + Send + Sync + 'static,
    S: NonBlockingSocket<A> + 'static,
{
    /// The match `game` played as `side` at `place` (a room's name, an address) with
    /// `input_delay` frames of input delay, once `connect` finds the other side.
    pub fn new(
        connect: Connect<A, S>,
        place: &str,
        side: Side,
        game: OnlineMatch,
        input_delay: usize,
    ) -> Self {
        Self {
            connect,
            session: None,
            stopped: None,
            rest: game.game().snapshot(),
            scene: MatchScene::new(game.table()),
            waiting: Some(game),
            side,
            place: place.to_string(),
            input_delay,
            started_s: None,
            over: false,
            desync_frames: Vec::new(),
        }
    }

    fn step(
        &mut self,
        now_s: f64,
        local: &mut dyn FnMut(u64) -> SideInput,
    ) -> Result<(), OnlineError> {
        let started = *self.started_s.get_or_insert(now_s);
        if self.session.is_none() {
            if let Some((socket, remote)) = (self.connect)()? {
                let Some(game) = self.waiting.take() else {
                    return Ok(());
                };
                self.session = Some(OnlineSession::start(
                    socket,
                    remote,
                    self.side,
                    game,
                    self.input_delay,
                    now_s,
                )?);
            } else if now_s - started > CONNECT_TIMEOUT_S {
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

impl<A, S> OnlineView for OnlineScreen<A, S>
where
    A: Clone + PartialEq + Eq + Hash + Debug + Send + Sync + 'static,
    S: NonBlockingSocket<A> + 'static,
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
        let snapshot = match self.game() {
            Some(g) => self.scene.snapshot(&g.game().snapshot()),
            None => self.scene.snapshot(&self.rest),
        };
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
        let (frames, match_over, score, state_hash, (rollbacks, resimulated_frames)) =
            match self.game() {
                Some(g) => (
                    g.end().min(g.state_frame()),
                    g.game().is_over(),
                    g.game().score(),
                    format!("{:032x}", g.game().state_hash()),
                    g.rollbacks(),
                ),
                None => (0, false, self.rest.score, String::new(), (0, 0)),
            };
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
            frames,
            match_over,
            score,
            state_hash,
            desyncs: self.desync_frames.len(),
            rollbacks,
            resimulated_frames,
        }
    }

    fn game(&self) -> Option<&OnlineMatch> {
        match &self.session {
            Some(s) => Some(s.game()),
            None => self.waiting.as_ref(),
        }
    }
}

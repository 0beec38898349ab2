//! The online match's frame loop on GGRS, on the caller's clock: the desktop polls it
//! from a loop that sleeps between frames, the page once per animation frame.

use super::input::SideInput;
use super::rollback::{Foosball, OnlineMatch, FPS, MAX_PREDICTION_FRAMES};
use ggrs::{
    DesyncDetection, GgrsError, GgrsEvent, GgrsRequest, NonBlockingSocket, P2PSession, PlayerType,
    SessionBuilder, SessionState,
};
use space_foosball::side::Side;
use std::fmt::Debug;
use std::hash::Hash;

/// Frames kept on after the end, so the other side gets the inputs it needs to end too.
const LINGER_FRAMES: u64 = 90;
/// Frames between the checksums the sides compare (desync detection).
const DESYNC_INTERVAL: u32 = 10;
/// The longest a session waits for the other side to answer, s.
pub const CONNECT_TIMEOUT_S: f64 = 20.0;
/// Frames one poll advances at most (a page drawn slowly catches up over several).
const MOST_FRAMES_PER_POLL: u32 = 4;

/// Something the players should hear about.
#[derive(Debug, Clone, PartialEq)]
pub enum Notice<A> {
    /// Both sides are in step: play starts.
    Synchronized {
        /// The other side.
        peer: A,
    },
    /// The two sides' states differed at `frame`.
    Desync {
        /// The frame compared.
        frame: i32,
    },
    /// No word from the other side for a while: waiting.
    Interrupted,
    /// The other side answers again.
    Resumed,
}

/// Where a session stands after a poll.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Stand {
    /// Waiting for the other side.
    Connecting,
    /// Playing.
    Playing,
    /// The match is over (or `max_frames` reached) and both sides confirmed its end; the
    /// session lingers on a little so the other side can end too.
    Over,
    /// Done lingering: the session can be dropped.
    Closed,
}

/// Why a session ended before the match did.
#[derive(Debug, thiserror::Error)]
pub enum OnlineError {
    /// The other side left; the match is restored to the frame both sides confirmed.
    #[error("the other side ({peer}) left the match at frame {frame}")]
    Left {
        /// The other side.
        peer: String,
        /// Frames both sides played.
        frame: u64,
    },
    /// Nobody answered in time.
    #[error("no answer from {peer} within {CONNECT_TIMEOUT_S} s")]
    NoAnswer {
        /// Who was waited for.
        peer: String,
    },
    /// GGRS refused something.
    #[error("the rollback session: {0}")]
    Session(#[from] GgrsError),
    /// The match could not be set up.
    #[error("the match: {0}")]
    Match(#[from] space_foosball::play::MatchError),
    /// The room's data channel was taken already.
    #[error("the room's data channel is gone")]
    ChannelGone,
    /// GGRS asked for a state it never had saved.
    #[error("the rollback session lost the match's state of frame {frame}")]
    LostState {
        /// The frame asked for.
        frame: i32,
    },
}

/// An online match in progress: the GGRS session and the match it steps.
pub struct OnlineSession<A>
where
    A: Clone + PartialEq + Eq + Hash + Debug + Send + Sync + 'static,
{
    sess: P2PSession<Foosball<A>>,
    game: OnlineMatch,
    side: Side,
    remote: A,
    /// The clock of the next frame, s; none before the sides are in step.
    next_s: Option<f64>,
    /// The clock at the start, s.
    started_s: f64,
    desyncs: u64,
    over: bool,
    lingered: u64,
}

impl<A> OnlineSession<A>
where
    A: Clone + PartialEq + Eq + Hash + Debug + Send + Sync + 'static,
{
    /// A session of `game` played as `side` against `remote` over `socket`, `input_delay`
    /// frames of input delay (0–8); `now_s` is the caller's clock.
    pub fn start(
        socket: impl NonBlockingSocket<A> + 'static,
        remote: A,
        side: Side,
        game: OnlineMatch,
        input_delay: usize,
        now_s: f64,
    ) -> Result<Self, OnlineError> {
        let local = side.index();
        let sess = SessionBuilder::<Foosball<A>>::new()
            .with_num_players(2)?
            .with_fps(FPS as usize)?
            .with_max_prediction_window(MAX_PREDICTION_FRAMES)
            .with_input_delay(input_delay)
            .with_desync_detection_mode(DesyncDetection::On {
                interval: DESYNC_INTERVAL,
            })
            .add_player(PlayerType::Local, local)?
            .add_player(PlayerType::Remote(remote.clone()), 1 - local)?
            .start_p2p_session(socket)?;
        Ok(Self {
            sess,
            game,
            side,
            remote,
            next_s: None,
            started_s: now_s,
            desyncs: 0,
            over: false,
            lingered: 0,
        })
    }

    /// Talks to the other side and plays the frames due by `now_s` (the caller's clock,
    /// s), this side's rods for frame `f` from `local(f)`. What the players should hear
    /// of goes to `notices`.
    pub fn poll(
        &mut self,
        now_s: f64,
        local: &mut dyn FnMut(u64) -> SideInput,
        notices: &mut Vec<Notice<A>>,
    ) -> Result<Stand, OnlineError> {
        self.sess.poll_remote_clients();
        self.handle_events(notices)?;
        if self.sess.current_state() != SessionState::Running {
            if now_s - self.started_s > CONNECT_TIMEOUT_S {
                return Err(OnlineError::NoAnswer {
                    peer: format!("{:?}", self.remote),
                });
            }
            return Ok(Stand::Connecting);
        }
        let frame_s = 1.0 / FPS as f64;
        let next = self.next_s.get_or_insert(now_s);
        // A page stalled for long does not try to catch up on every frame it missed.
        if now_s - *next > f64::from(MOST_FRAMES_PER_POLL) * frame_s {
            *next = now_s;
        }
        for _ in 0..MOST_FRAMES_PER_POLL {
            let Some(next) = self.next_s.filter(|&n| now_s >= n) else {
                break;
            };
            // A side ahead of the other waits a little (GGRS's recommendation, in effect).
            let slower = if self.sess.frames_ahead() > 0 {
                1.1
            } else {
                1.0
            };
            self.next_s = Some(next + frame_s * slower);
            // This side's rods for the frame the session is at (a frame held back for the
            // other side is asked for again, its input the same).
            let frame = u64::try_from(self.sess.current_frame()).unwrap_or(0);
            let input = local(self.game.match_frame(frame));
            self.sess.add_local_input(self.side.index(), input)?;
            let requests = match self.sess.advance_frame() {
                Ok(requests) => requests,
                Err(GgrsError::PredictionThreshold) => continue,
                Err(e) => return Err(e.into()),
            };
            let advanced = requests
                .iter()
                .any(|r| matches!(r, GgrsRequest::AdvanceFrame { .. }));
            self.game.handle(requests)?;
            if !advanced {
                continue;
            }
            if self.over {
                self.lingered += 1;
                continue;
            }
            // The state is final once every frame up to its end is confirmed by both sides.
            let end = self.game.end();
            let confirmed = u64::try_from(self.sess.confirmed_frame() + 1).unwrap_or(0);
            self.over = self.game.state_frame() >= end && self.game.match_frame(confirmed) >= end;
        }
        Ok(match (self.over, self.lingered >= LINGER_FRAMES) {
            (false, _) => Stand::Playing,
            (true, false) => Stand::Over,
            (true, true) => Stand::Closed,
        })
    }

    fn handle_events(&mut self, notices: &mut Vec<Notice<A>>) -> Result<(), OnlineError> {
        let confirmed = self.sess.confirmed_frame();
        let events: Vec<GgrsEvent<Foosball<A>>> = self.sess.events().collect();
        for e in events {
            match e {
                GgrsEvent::DesyncDetected { frame, .. } => {
                    self.desyncs += 1;
                    notices.push(Notice::Desync { frame });
                }
                GgrsEvent::Disconnected { addr } if !self.over => {
                    let frame = u64::try_from(confirmed + 1).unwrap_or(0);
                    self.game.restore_to(frame);
                    return Err(OnlineError::Left {
                        peer: format!("{addr:?}"),
                        frame: self.game.match_frame(frame),
                    });
                }
                GgrsEvent::NetworkInterrupted { .. } => notices.push(Notice::Interrupted),
                GgrsEvent::NetworkResumed { .. } => notices.push(Notice::Resumed),
                GgrsEvent::Synchronized { addr } => {
                    notices.push(Notice::Synchronized { peer: addr })
                }
                _ => {}
            }
        }
        Ok(())
    }

    /// The match as this side has it (predicted frames included).
    pub fn game(&self) -> &OnlineMatch {
        &self.game
    }

    /// The team played here.
    pub fn side(&self) -> Side {
        self.side
    }

    /// The other side.
    pub fn remote(&self) -> &A {
        &self.remote
    }

    /// Desyncs GGRS detected (0: both sides stepped alike).
    pub fn desyncs(&self) -> u64 {
        self.desyncs
    }

    /// Round trip to the other side, ms, once measured.
    pub fn ping_ms(&self) -> Option<u128> {
        self.sess
            .network_stats(1 - self.side.index())
            .ok()
            .map(|s| s.ping)
    }

    /// Frames this side is ahead of the other (negative: behind).
    pub fn frames_ahead(&self) -> i32 {
        self.sess.frames_ahead()
    }
}

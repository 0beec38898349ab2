//! The match as the frames draw it: the table in play, the effects of its events
//! (kicks, bounces, goals) while they show, and when the last goal was scored; the
//! sounds those events make. The window and the page feed it the match's snapshots and
//! events; it gives them the frame to draw.

use crate::view;
use foosball_audio::Sound;
use foosball_render::scene::PARTICLE_LIFETIME_S;
use foosball_render::{
    BallSnapshot, EventKind, FrameSnapshot, RenderEvent, RodPose, TableGeometry,
};
use space_foosball::play::MatchSnapshot;
use space_foosball::rules::{Event, TimedEvent};
use space_foosball::table::Table;

/// How long the goal ceremony shows after a goal, s.
pub const GOAL_CEREMONY_S: f64 = 2.5;

/// Bounces softer than this make no sound, m/s.
pub const QUIET_BOUNCE_M_S: f64 = 0.25;

/// How many kicks and goals a batch of events held.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct EventCounts {
    /// Kicks.
    pub kicks: u64,
    /// Goals.
    pub goals: u64,
}

/// See the [module](self).
#[derive(Debug, Clone)]
pub struct MatchScene {
    table: Table,
    view: TableGeometry,
    events: Vec<RenderEvent>,
    last_goal_s: Option<f64>,
}

impl MatchScene {
    /// The scene of a match on `table`, nothing happened yet.
    pub fn new(table: &Table) -> Self {
        Self {
            table: table.clone(),
            view: view::table_geometry(table),
            events: Vec::new(),
            last_goal_s: None,
        }
    }

    /// A new match on `table`: no effects showing, no goal yet.
    pub fn restart(&mut self, table: &Table) {
        *self = Self::new(table);
    }

    /// When the last goal was scored (the caller's clock, s), if one was.
    pub fn last_goal_s(&self) -> Option<f64> {
        self.last_goal_s
    }

    /// Whether the goal ceremony shows at `now_s` (the caller's clock, s).
    pub fn goal_ceremony(&self, now_s: f64) -> bool {
        self.last_goal_s
            .is_some_and(|t| now_s - t < GOAL_CEREMONY_S)
    }

    /// The frame of snapshot `s`, with the effects showing.
    pub fn snapshot(&self, s: &MatchSnapshot) -> FrameSnapshot {
        let rods: Vec<RodPose> = s
            .rods
            .iter()
            .map(|r| RodPose {
                slide_m: r.slide_m,
                angle_rad: r.angle_rad,
            })
            .collect();
        let ball = BallSnapshot {
            position: s.ball.position,
            velocity: s.ball.velocity,
        };
        FrameSnapshot::posed(
            &self.view,
            s.time_s,
            &rods,
            ball,
            s.score,
            self.events.clone(),
        )
    }

    /// The frame between the two newest snapshots (1 ms apart at 1 kHz): drawn half a
    /// step behind the newest, never extrapolated.
    pub fn interpolated(&self, prev: &MatchSnapshot, newest: &MatchSnapshot) -> FrameSnapshot {
        let a = self.snapshot(prev);
        let b = self.snapshot(newest);
        let t = 0.5 * (prev.time_s + newest.time_s);
        FrameSnapshot::at_time(&a, &b, t)
    }

    /// Takes the match's `events` up to snapshot `newest` at `now_s` (the caller's
    /// clock, s): their effects join the frames, their sounds go to `sounds`, effects
    /// too old to show are dropped. Returns how many kicks and goals they held.
    pub fn take_events(
        &mut self,
        events: &[TimedEvent],
        newest: &MatchSnapshot,
        now_s: f64,
        sounds: &mut Vec<Sound>,
    ) -> EventCounts {
        let ball = newest.ball.position;
        let mut counts = EventCounts::default();
        for e in events {
            let time_s = e.t_ms as f64 * 1e-3;
            match e.event {
                Event::Kick { speed, .. } => {
                    counts.kicks += 1;
                    self.events.push(RenderEvent {
                        time_s,
                        kind: EventKind::Kick,
                        position: ball,
                        speed,
                    });
                    sounds.push(Sound::Kick {
                        speed_m_s: speed as f32,
                    });
                }
                Event::Bounce { speed } => {
                    self.events.push(RenderEvent {
                        time_s,
                        kind: EventKind::Bounce,
                        position: ball,
                        speed,
                    });
                    if speed >= QUIET_BOUNCE_M_S {
                        sounds.push(Sound::Bounce {
                            speed_m_s: speed as f32,
                        });
                    }
                }
                Event::Goal { side, .. } => {
                    counts.goals += 1;
                    let x = self.table.goal_line_x(side.other());
                    self.events.push(RenderEvent {
                        time_s,
                        kind: EventKind::Goal(view::team(side)),
                        position: [x, 0.0, 0.03],
                        speed: 4.0,
                    });
                    self.last_goal_s = Some(now_s);
                    sounds.push(Sound::GoalFanfare);
                }
                Event::Serve { .. } | Event::MatchOver { .. } => {}
            }
        }
        let horizon = newest.time_s - PARTICLE_LIFETIME_S - 0.5;
        self.events.retain(|e| e.time_s >= horizon);
        counts
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use space_foosball::play::{Match, MatchConfig};
    use space_foosball::side::Side;

    #[test]
    fn a_goal_shows_its_ceremony_for_its_time_and_sounds_the_fanfare() {
        let table = Table::standard();
        let mut scene = MatchScene::new(&table);
        let snap = Match::new(MatchConfig::computer_vs_computer(table.clone(), 0))
            .unwrap()
            .snapshot();
        let mut sounds = Vec::new();
        let events = [
            TimedEvent {
                t_ms: 10,
                event: Event::Bounce { speed: 0.1 },
            },
            TimedEvent {
                t_ms: 12,
                event: Event::Goal {
                    side: Side::Home,
                    score: [1, 0],
                },
            },
        ];
        let counts = scene.take_events(&events, &snap, 100.0, &mut sounds);
        assert_eq!(counts, EventCounts { kicks: 0, goals: 1 });
        assert_eq!(
            sounds,
            vec![Sound::GoalFanfare],
            "a quiet bounce makes no sound"
        );
        assert!(scene.goal_ceremony(100.0 + GOAL_CEREMONY_S - 0.01));
        assert!(!scene.goal_ceremony(100.0 + GOAL_CEREMONY_S));
        scene.restart(&table);
        assert_eq!(scene.last_goal_s(), None);
    }
}

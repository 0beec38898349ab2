//! The match on its own thread at a fixed 1 kHz.
//!
//! Step `k` is due at `origin + k ms`. The thread sleeps until shortly before the
//! deadline and spins the rest (sleep alone overshoots by tens of µs), calls the input
//! closure for the newest rod inputs, steps the match, and publishes a snapshot. If it
//! is late it catches up, at most [`ThreadOptions::max_catch_up_steps`] steps at once;
//! a larger backlog (the process was stopped, the machine is overloaded) is dropped by
//! moving the origin: match time then lags wall time by the dropped steps, but the loop
//! never keeps running behind. While paused, the input closure is still called once per
//! millisecond (so a board's reports are drained and its health seen) but the match
//! does not step; on resume the schedule restarts from now.
//!
//! The renderer reads the newest and the previous snapshot ([`PhysicsThread::latest`])
//! to interpolate; sound, particles and haptics drain the events
//! ([`PhysicsThread::drain_events`]).

use super::{Match, MatchSnapshot};
use crate::input::paddles::{InputHealth, RodInputs};
use crate::recording::MatchRecording;
use crate::rules::TimedEvent;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex, MutexGuard};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

/// How the physics thread keeps time.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ThreadOptions {
    /// Step period (1 ms for 1 kHz).
    pub period: Duration,
    /// Most steps run back to back to catch up after being late; beyond that the
    /// backlog is dropped.
    pub max_catch_up_steps: u32,
    /// Sleep until this long before a deadline, then spin.
    pub spin: Duration,
    /// Pause on its own while the input says the board is lost
    /// ([`InputHealth::BoardLost`]); resume when it is back.
    pub pause_when_board_lost: bool,
}

impl Default for ThreadOptions {
    /// 1 ms period, catch up at most 20 steps, spin the last 150 µs, pause on a lost
    /// board.
    fn default() -> Self {
        Self {
            period: Duration::from_millis(1),
            max_catch_up_steps: 20,
            spin: Duration::from_micros(150),
            pause_when_board_lost: true,
        }
    }
}

/// Counters of the physics thread.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct ThreadStats {
    /// Match steps taken.
    pub steps: u64,
    /// Steps run late (after their deadline by more than one period).
    pub late_steps: u64,
    /// Steps dropped because the backlog exceeded the catch-up limit.
    pub dropped_steps: u64,
    /// Slowest step (input + match step + snapshot), µs.
    pub worst_step_us: f64,
}

struct Shared {
    snapshots: Mutex<(MatchSnapshot, MatchSnapshot)>,
    events: Mutex<Vec<TimedEvent>>,
    /// The match's recording, left here when the match is over.
    recording: Mutex<Option<MatchRecording>>,
    stats: Mutex<ThreadStats>,
    paused: AtomicBool,
    stop: AtomicBool,
}

/// Locks, recovering the data if another thread panicked while holding the lock (the
/// data is plain values, always consistent between assignments).
fn lock<T>(m: &Mutex<T>) -> MutexGuard<'_, T> {
    m.lock().unwrap_or_else(|e| e.into_inner())
}

/// A match running on its own thread. See the [module](self) docs.
pub struct PhysicsThread {
    shared: Arc<Shared>,
    handle: Option<JoinHandle<Match>>,
}

impl PhysicsThread {
    /// Runs `m` at 1 kHz with the default [`ThreadOptions`]; `input` is called once per
    /// step for the newest rod inputs and must not block.
    pub fn spawn(m: Match, input: impl FnMut() -> RodInputs + Send + 'static) -> PhysicsThread {
        Self::spawn_with(m, input, ThreadOptions::default())
    }

    /// Runs `m` with `options`.
    pub fn spawn_with(
        m: Match,
        mut input: impl FnMut() -> RodInputs + Send + 'static,
        options: ThreadOptions,
    ) -> PhysicsThread {
        let first = m.snapshot();
        let shared = Arc::new(Shared {
            snapshots: Mutex::new((first.clone(), first)),
            events: Mutex::new(Vec::new()),
            recording: Mutex::new(None),
            stats: Mutex::new(ThreadStats::default()),
            paused: AtomicBool::new(false),
            stop: AtomicBool::new(false),
        });
        let inner = Arc::clone(&shared);
        let handle = std::thread::Builder::new()
            .name("physics".into())
            .spawn(move || run(m, &mut input, &inner, options))
            .ok();
        PhysicsThread { shared, handle }
    }

    /// The previous and the newest snapshot (for interpolation).
    pub fn latest(&self) -> (MatchSnapshot, MatchSnapshot) {
        lock(&self.shared.snapshots).clone()
    }

    /// The events since the last call.
    pub fn drain_events(&self) -> Vec<TimedEvent> {
        std::mem::take(&mut *lock(&self.shared.events))
    }

    /// The match's recording, once the match is over (the first call after that takes it;
    /// `None` before, and after it is taken).
    pub fn take_recording(&self) -> Option<MatchRecording> {
        lock(&self.shared.recording).take()
    }

    /// Pauses (true) or resumes (false) the match.
    pub fn set_paused(&self, paused: bool) {
        self.shared.paused.store(paused, Ordering::Release);
    }

    /// Whether [`PhysicsThread::set_paused`] paused the match.
    pub fn is_paused(&self) -> bool {
        self.shared.paused.load(Ordering::Acquire)
    }

    /// The thread's counters.
    pub fn stats(&self) -> ThreadStats {
        *lock(&self.shared.stats)
    }

    /// Whether the thread is still running (it ends when the match is over or on
    /// [`PhysicsThread::stop`]).
    pub fn is_running(&self) -> bool {
        self.handle.as_ref().is_some_and(|h| !h.is_finished())
    }

    /// Stops the thread and returns the match. `None` if the thread could not be
    /// started or panicked.
    pub fn stop(mut self) -> Option<Match> {
        self.shared.stop.store(true, Ordering::Release);
        self.handle.take().and_then(|h| h.join().ok())
    }
}

impl Drop for PhysicsThread {
    fn drop(&mut self) {
        self.shared.stop.store(true, Ordering::Release);
        if let Some(h) = self.handle.take() {
            let _ = h.join();
        }
    }
}

fn wait_until(deadline: Instant, spin: Duration) {
    let now = Instant::now();
    if deadline > now + spin {
        std::thread::sleep(deadline - now - spin);
    }
    while Instant::now() < deadline {
        std::hint::spin_loop();
    }
}

fn run(
    mut m: Match,
    input: &mut dyn FnMut() -> RodInputs,
    shared: &Shared,
    options: ThreadOptions,
) -> Match {
    let period = options.period.max(Duration::from_micros(10));
    let mut origin = Instant::now();
    let mut due: u64 = 0; // steps due since `origin`
    let mut was_paused = false;
    while !shared.stop.load(Ordering::Acquire) {
        let deadline = origin + period * (due as u32).min(u32::MAX - 1);
        wait_until(deadline, options.spin);
        let started = Instant::now();
        let inputs = input();
        let lost = options.pause_when_board_lost && inputs.health == InputHealth::BoardLost;
        let paused = shared.paused.load(Ordering::Acquire) || lost;
        if paused {
            if !was_paused {
                let mut snaps = lock(&shared.snapshots);
                snaps.1.paused = true;
                snaps.1.input_health = inputs.health;
                snaps.0 = snaps.1.clone();
            }
            was_paused = true;
            origin = Instant::now();
            due = 1;
            continue;
        }
        if was_paused {
            was_paused = false;
            origin = started;
            due = 0;
        }
        let events = m.step(&inputs);
        let snapshot = m.snapshot();
        {
            let mut snaps = lock(&shared.snapshots);
            let newest = std::mem::replace(&mut snaps.1, snapshot);
            snaps.0 = newest;
        }
        if !events.is_empty() {
            lock(&shared.events).extend(events);
        }
        let took = started.elapsed();
        due += 1;
        // Behind schedule? Catch up within the limit, drop the rest.
        let now = Instant::now();
        let behind =
            now.saturating_duration_since(origin + period * due.min(u32::MAX as u64 - 1) as u32);
        let behind_steps = (behind.as_nanos() / period.as_nanos().max(1)) as u64;
        {
            let mut st = lock(&shared.stats);
            st.steps += 1;
            st.worst_step_us = st.worst_step_us.max(took.as_secs_f64() * 1e6);
            if now > deadline + period {
                st.late_steps += 1;
            }
            if behind_steps > u64::from(options.max_catch_up_steps) {
                st.dropped_steps += behind_steps - u64::from(options.max_catch_up_steps);
            }
        }
        if behind_steps > u64::from(options.max_catch_up_steps) {
            // Keep only `max_catch_up_steps` of backlog.
            origin = now
                .checked_sub(period * options.max_catch_up_steps)
                .unwrap_or(now);
            due = 0;
        }
        if m.is_over() {
            *lock(&shared.recording) = Some(m.recording().clone());
            break;
        }
        // Keep `due` small so the multiplication above never overflows.
        if due >= 1_000_000 {
            origin += period * due as u32;
            due = 0;
        }
    }
    m
}

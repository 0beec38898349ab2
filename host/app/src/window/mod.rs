//! The windowed game of `space-foosball play`: a winit window drawn by
//! `foosball_render::WindowRenderer`, a [`session::Session`] (board, screens, match on
//! its 1 kHz physics thread), sound, and the emulated board's keyboard, mouse and
//! gamepad controls ([`controls`]) when no board is plugged in.
//!
//! * [`board`]: which board (USB, else the built-in emulated board; or a socket).
//! * [`session`]: everything but the window; tests drive it directly.
//! * [`flow`]: the screens driven by the rods.
//! * [`calibrate`]: calibration mode.
//! * [`controls`], [`gamepad`]: keyboard, mouse, gamepad → emulated rods.
//! * [`script`]: scripted key presses (`--demo-input`) for unattended checks.

pub mod args;
pub mod board;
#[cfg(test)]
mod calibration_e2e;
pub(crate) mod cpu;
pub mod session;
pub use space_foosball_front::{calibrate, controls, flow, gamepad, script};

use anyhow::{anyhow, Context, Result};
use board::BoardChoice;
use controls::{map_key, Controls};
use flow::Stage;
use foosball_audio::AudioOutput;
use foosball_render::{DrawTimes, PresentChoice, WindowRenderer};
use foosball_sim::motion::live::LiveHandle;
use foosball_sim::motion::RodPose as PaddlePose;
use gamepad::Gamepads;
use script::Script;
use session::{FrameOut, Session, SessionOptions};
use space_foosball::input::calibration::Calibration;
use space_foosball::table::Table;
use std::path::PathBuf;
use std::sync::Arc;
use std::time::Instant;
use winit::application::ApplicationHandler;
use winit::dpi::PhysicalSize;
use winit::event::{DeviceEvent, DeviceId, ElementState, KeyEvent, MouseScrollDelta, WindowEvent};
use winit::event_loop::{ActiveEventLoop, ControlFlow, EventLoop};
use winit::keyboard::{KeyCode, PhysicalKey};
use winit::window::{CursorGrabMode, Fullscreen, Window, WindowId};

/// How `play` runs its window.
#[derive(Debug, Clone)]
pub struct WindowOptions {
    /// Which board.
    pub board: BoardChoice,
    /// The table.
    pub table: Table,
    /// Window size, pixels.
    pub size: (u32, u32),
    /// Borderless fullscreen.
    pub fullscreen: bool,
    /// Vsync (FIFO) or low latency (mailbox where offered).
    pub present: PresentChoice,
    /// Seed of the first match.
    pub seed: u64,
    /// The calibration file (loaded at start; calibration mode saves it).
    pub calibration_path: Option<PathBuf>,
    /// Start in calibration mode.
    pub calibrate: bool,
    /// The match history finished matches go into (none: not kept).
    pub history_path: Option<PathBuf>,
    /// Quit this many seconds after the first frame showed (unattended checks).
    pub exit_after_s: Option<f64>,
    /// Write the last presented frame here as PNG when quitting.
    pub capture_window: Option<PathBuf>,
    /// Scripted key presses.
    pub script: Script,
}

/// Key hints for the emulated board, shown at the bottom of the screens.
fn key_hints() -> Vec<String> {
    vec![
        "1-4 ROD  MOUSE/W/S SLIDE  MOUSE/A/D/WHEEL SPIN  SPACE KICK".into(),
        "ENTER PUSH  TAB OTHER TEAM  C CALIBRATE  ESC PAUSE/QUIT".into(),
    ]
}

/// Opens the window and plays until the window closes or the player quits.
pub fn run(options: WindowOptions) -> Result<()> {
    let event_loop = EventLoop::new().context("could not connect to the display")?;
    event_loop.set_control_flow(ControlFlow::Poll);
    let mut app = App::new(options)?;
    event_loop
        .run_app(&mut Windowed(&mut app))
        .context("the window's event loop failed")?;
    if let Some(e) = app.error.take() {
        return Err(e);
    }
    app.report();
    Ok(())
}

/// A click hands the mouse to the game (hidden, kept in the window: its motion slides and
/// spins the rod); `Esc` or leaving the window gives it back.
pub(crate) fn grab_mouse(w: &Window, grab: bool) {
    if grab {
        // Locked where the platform can, else confined; neither is fatal.
        let _ = w
            .set_cursor_grab(CursorGrabMode::Locked)
            .or_else(|_| w.set_cursor_grab(CursorGrabMode::Confined));
    } else {
        let _ = w.set_cursor_grab(CursorGrabMode::None);
    }
    w.set_cursor_visible(!grab);
}

/// A wheel's turn in lines (> 0: away from the player).
pub(crate) fn wheel_lines(delta: MouseScrollDelta) -> f64 {
    match delta {
        MouseScrollDelta::LineDelta(_, y) => f64::from(y),
        MouseScrollDelta::PixelDelta(p) => p.y / 40.0,
    }
}

/// Opens the game's window (`size` pixels, or borderless fullscreen) and its renderer.
pub(crate) fn open_window(
    el: &ActiveEventLoop,
    (w, h): (u32, u32),
    fullscreen: bool,
    present: PresentChoice,
) -> Result<(Arc<Window>, WindowRenderer)> {
    let mut attrs = Window::default_attributes()
        .with_title("Space Foosball")
        .with_inner_size(PhysicalSize::new(w, h));
    if fullscreen {
        attrs = attrs.with_fullscreen(Some(Fullscreen::Borderless(None)));
    }
    let window = Arc::new(
        el.create_window(attrs)
            .map_err(|e| anyhow!(e).context("could not open the window"))?,
    );
    let size = window.inner_size();
    let (w, h) = if size.width > 0 && size.height > 0 {
        (size.width, size.height)
    } else {
        (w, h)
    };
    let renderer =
        WindowRenderer::new(Arc::clone(&window), w, h, present).map_err(|e| anyhow!(e))?;
    Ok((window, renderer))
}

/// What the game's window makes of `event` besides drawing, shared by `play`'s window and
/// the online window: it closes, resizes the renderer, moves the emulated rods (wheel),
/// grabs the mouse on a click and lets go of it and of every held key when the window
/// loses focus. A key pressed or released is returned for the caller's own keys.
pub(crate) fn handle_event(
    el: &ActiveEventLoop,
    event: &WindowEvent,
    window: Option<&Window>,
    renderer: Option<&mut WindowRenderer>,
    controls: &mut Controls,
) -> Option<(KeyCode, bool)> {
    match event {
        WindowEvent::CloseRequested => el.exit(),
        WindowEvent::Resized(size) => {
            if let Some(r) = renderer {
                r.resize(size.width, size.height);
            }
        }
        WindowEvent::KeyboardInput {
            event:
                KeyEvent {
                    physical_key: PhysicalKey::Code(code),
                    state,
                    repeat: false,
                    ..
                },
            ..
        } => return Some((*code, *state == ElementState::Pressed)),
        WindowEvent::MouseWheel { delta, .. } => controls.wheel(wheel_lines(*delta)),
        WindowEvent::MouseInput {
            state: ElementState::Pressed,
            ..
        } => {
            if let Some(w) = window {
                grab_mouse(w, true);
            }
        }
        WindowEvent::Focused(false) => {
            if let Some(w) = window {
                grab_mouse(w, false);
            }
            // Keys released while the window had no focus never arrive: let go of all.
            controls.release_all();
        }
        _ => {}
    }
    None
}

/// Opens the board of `choice` and the calibration it is read through (the file at
/// `calibration_path`, or the defaults where there is none or it cannot be used), saying
/// on stderr what the player should know.
pub(crate) fn open_board(
    choice: &BoardChoice,
    calibration_path: Option<&std::path::Path>,
) -> Result<(board::Opened, Calibration)> {
    let opened = board::open(choice)?;
    if let Some(n) = &opened.notice {
        eprintln!("space-foosball: {n}");
    }
    let calibration = match calibration_path {
        Some(path) => {
            let (c, warning) = Calibration::load_or_default(path);
            if let Some(w) = warning {
                eprintln!("space-foosball: calibration not used ({w}); using the defaults");
            }
            c
        }
        None => Calibration::default(),
    };
    Ok((opened, calibration))
}

/// What the one winit handler ([`Windowed`]) needs of a game window.
pub(crate) struct WindowParts<'a> {
    /// The window, once open.
    pub window: Option<Arc<Window>>,
    /// Its renderer, once open.
    pub renderer: Option<&'a mut WindowRenderer>,
    /// The emulated board's controls.
    pub controls: &'a mut Controls,
}

/// A game window: `play`'s, or the online match's.
pub(crate) trait GameWindow {
    /// Opens the window and its renderer (once).
    fn open(&mut self, el: &ActiveEventLoop);
    /// Draws a frame.
    fn redraw(&mut self, el: &ActiveEventLoop);
    /// A key went down (`pressed`) or up.
    fn key(&mut self, el: &ActiveEventLoop, code: KeyCode, pressed: bool);
    /// Its window, renderer and controls.
    fn parts(&mut self) -> WindowParts<'_>;
}

/// The winit handler of a game window: events to the controls and keys, a frame drawn
/// whenever the loop waits.
pub(crate) struct Windowed<'a, T: GameWindow>(pub &'a mut T);

impl<T: GameWindow> ApplicationHandler for Windowed<'_, T> {
    fn resumed(&mut self, el: &ActiveEventLoop) {
        self.0.open(el);
    }

    fn window_event(&mut self, el: &ActiveEventLoop, _id: WindowId, event: WindowEvent) {
        if event == WindowEvent::RedrawRequested {
            return self.0.redraw(el);
        }
        let parts = self.0.parts();
        let key = handle_event(
            el,
            &event,
            parts.window.as_deref(),
            parts.renderer,
            parts.controls,
        );
        if let Some((code, pressed)) = key {
            self.0.key(el, code, pressed);
        }
    }

    fn device_event(&mut self, _el: &ActiveEventLoop, _id: DeviceId, event: DeviceEvent) {
        if let DeviceEvent::MouseMotion { delta: (dx, dy) } = event {
            self.0.parts().controls.mouse_motion(dx, dy);
        }
    }

    fn about_to_wait(&mut self, _el: &ActiveEventLoop) {
        if let Some(w) = self.0.parts().window {
            w.request_redraw();
        }
    }
}

struct App {
    options: WindowOptions,
    window: Option<Arc<Window>>,
    renderer: Option<WindowRenderer>,
    session: Session,
    live: Option<LiveHandle>,
    controls: Controls,
    pads: Gamepads,
    audio: AudioOutput,
    error: Option<anyhow::Error>,
    started: Instant,
    last_tick: Instant,
    frames: u64,
    stages: FrameStages,
    last: Option<FrameOut>,
    capture_written: bool,
}

/// Where the frames' time went on the window's thread, summed over the frames after
/// the first (which also compiles the driver's shaders).
#[derive(Debug, Default)]
struct FrameStages {
    /// When the first frame was presented, and the latest.
    first: Option<Instant>,
    latest: Option<Instant>,
    /// Frames summed below (every frame after the first).
    n: u64,
    /// The session's frame: board, screens, the physics thread's snapshots, ms.
    session_ms: f64,
    /// The renderer's stages, ms.
    draw: DrawTimes,
}

impl FrameStages {
    fn add(&mut self, now: Instant, session_ms: f64, draw: DrawTimes) {
        self.latest = Some(now);
        if self.first.is_none() {
            self.first = Some(now);
            return;
        }
        self.n += 1;
        self.session_ms += session_ms;
        self.draw.acquire_ms += draw.acquire_ms;
        self.draw.build_ms += draw.build_ms;
        self.draw.encode_ms += draw.encode_ms;
        self.draw.present_ms += draw.present_ms;
    }

    /// Frames per second from the first presented frame to the latest.
    fn fps(&self) -> f64 {
        match (self.first, self.latest) {
            (Some(a), Some(b)) if b > a => self.n as f64 / (b - a).as_secs_f64(),
            _ => 0.0,
        }
    }

    /// `{"session": …, "acquire": …, …}`: mean ms per frame of each stage, and the
    /// mean time between frames.
    fn json(&self) -> String {
        let n = self.n.max(1) as f64;
        let interval = match (self.first, self.latest) {
            (Some(a), Some(b)) => (b - a).as_secs_f64() * 1e3 / n,
            _ => 0.0,
        };
        format!(
            "{{\"session\": {:.2}, \"acquire\": {:.2}, \"build\": {:.2}, \"encode\": {:.2}, \
             \"present\": {:.2}, \"interval\": {interval:.2}}}",
            self.session_ms / n,
            self.draw.acquire_ms / n,
            self.draw.build_ms / n,
            self.draw.encode_ms / n,
            self.draw.present_ms / n,
        )
    }
}

impl App {
    fn new(options: WindowOptions) -> Result<App> {
        let (opened, calibration) =
            open_board(&options.board, options.calibration_path.as_deref())?;
        let key_hints = if opened.live.is_some() {
            key_hints()
        } else {
            vec!["ESC PAUSE/QUIT - C CALIBRATE".into()]
        };
        let mut session = Session::new(
            opened.board,
            options.table.clone(),
            calibration,
            SessionOptions {
                seed: options.seed,
                calibration_path: options.calibration_path.clone(),
                key_hints,
                history_path: options.history_path.clone(),
            },
        )?;
        if options.calibrate {
            session.start_calibration();
        }
        let audio = AudioOutput::open();
        let pads = Gamepads::open();
        if let Some(n) = &pads.notice {
            eprintln!("space-foosball: {n}");
        }
        let now = Instant::now();
        Ok(App {
            controls: Controls::new(&options.table),
            options,
            window: None,
            renderer: None,
            session,
            live: opened.live,
            pads,
            audio,
            error: None,
            started: now,
            last_tick: now,
            frames: 0,
            stages: FrameStages::default(),
            last: None,
            capture_written: false,
        })
    }

    fn fail(&mut self, el: &ActiveEventLoop, e: anyhow::Error) {
        if self.error.is_none() {
            self.error = Some(e);
        }
        el.exit();
    }

    /// One line of JSON on stdout when the window closes: what it showed last.
    fn report(&self) {
        let Some(last) = &self.last else { return };
        let elapsed = self.started.elapsed().as_secs_f64();
        let (adapter, present) = self
            .renderer
            .as_ref()
            .map(|r| (r.adapter().name.clone(), r.present_mode()))
            .unwrap_or_default();
        let b = last.snapshot.ball.position;
        let (w, h) = self.renderer.as_ref().map_or((0, 0), WindowRenderer::size);
        let controllers = self.session.controllers();
        let rods: Vec<String> = last
            .snapshot
            .rods
            .iter()
            .map(|r| format!("[{:.4}, {:.4}]", r.slide_m, r.angle_rad))
            .collect();
        let startup = self
            .stages
            .first
            .map_or(0.0, |t| (t - self.started).as_secs_f64());
        let cpu: Vec<String> = cpu::thread_cpu_seconds()
            .iter()
            .map(|(name, s)| format!("{name:?}: {s:.2}"))
            .collect();
        println!(
            "{{\"frames\": {}, \"seconds\": {elapsed:.2}, \"startup_s\": {startup:.2}, \
             \"fps\": {:.1}, \"frame_ms\": {}, \"cpu_s\": {{{}}}, \"adapter\": {adapter:?}, \
             \"present_mode\": {present:?}, \"board\": {:?}, \"stage\": {:?}, \"screen\": {:?}, \
             \"match_time_s\": {:.3}, \"paused\": {}, \"score\": [{}, {}], \
             \"ball\": [{:.5}, {:.5}, {:.5}], \"width\": {w}, \"height\": {h}, \"sound\": {:?}, \
             \"input\": {:?}, \"controllers\": [{:?}, {:?}], \"rods\": [{}], \"hud_lines\": {}}}",
            self.frames,
            self.stages.fps(),
            self.stages.json(),
            cpu.join(", "),
            self.session.board_name(),
            last.stage.name(),
            last.screen.name(),
            last.match_time_s,
            last.paused,
            last.snapshot.score[0],
            last.snapshot.score[1],
            b[0],
            b[1],
            b[2],
            if self.audio.is_silent() {
                "silent"
            } else {
                "on"
            },
            format!("{:?}", last.health).to_lowercase(),
            format!("{:?}", controllers[0]).to_lowercase(),
            format!("{:?}", controllers[1]).to_lowercase(),
            rods.join(", "),
            serde_json::to_string(&last.hud.lines).unwrap_or_else(|_| "[]".into()),
        );
    }

    fn grab_mouse(&mut self, grab: bool) {
        if let Some(w) = &self.window {
            grab_mouse(w, grab);
        }
    }
}

impl GameWindow for App {
    fn open(&mut self, el: &ActiveEventLoop) {
        if self.window.is_some() {
            return;
        }
        let opened = open_window(
            el,
            self.options.size,
            self.options.fullscreen,
            self.options.present,
        );
        let (window, r) = match opened {
            Ok(o) => o,
            Err(e) => return self.fail(el, e),
        };
        eprintln!(
            "space-foosball: drawing on {} ({}), present mode {}, board: {}",
            r.adapter().name,
            r.adapter().backend,
            r.present_mode(),
            self.session.board_name()
        );
        self.renderer = Some(r);
        window.request_redraw();
        self.window = Some(window);
    }

    fn redraw(&mut self, el: &ActiveEventLoop) {
        let now = Instant::now();
        let dt = now.duration_since(self.last_tick).as_secs_f64();
        self.last_tick = now;
        // Unattended runs count from the first presented frame, so that a slow start
        // (the driver compiling its shaders on a loaded machine) never bunches the
        // script's keys or cuts the run short.
        let t = self
            .stages
            .first
            .map_or(0.0, |first| now.duration_since(first).as_secs_f64());
        for (key, pressed) in self.options.script.due(t) {
            if let Some(code) = key {
                self.key(el, code, pressed);
            }
        }
        if let Some(rod) = self.session.calibration_rod() {
            self.controls.select_rod(rod);
        }
        let pad = self.pads.state();
        self.controls.tick(dt, pad);
        if let Some(live) = &self.live {
            for (port, [axial_m, angle_rad]) in self.controls.paddle_targets() {
                live.set_target(port, PaddlePose::new(axial_m, angle_rad));
            }
        }
        let mut out = match self.session.frame() {
            Ok(o) => o,
            Err(e) => return self.fail(el, e),
        };
        let session_ms = now.elapsed().as_secs_f64() * 1e3;
        if self.live.is_some()
            && matches!(
                out.stage,
                Stage::Attract | Stage::CharacterSelect | Stage::Playing
            )
        {
            let rod = self.controls.keyboard_key_number();
            let team = format!("{:?}", self.controls.keyboard_team()).to_uppercase();
            out.hud
                .lines
                .insert(0, format!("KEYBOARD: {team} ROD {rod}"));
            // The rods in the players' hands glow on the table: the keyboard's, and the
            // gamepad's when one is plugged in, of teams a person plays.
            if out.stage == Stage::Playing {
                let players = self.session.controllers();
                let pad_rod = pad.and(self.controls.pad_rod());
                let held = [self.controls.keyboard_rod(), pad_rod]
                    .into_iter()
                    .flatten();
                let rods = &self.options.table.rods;
                out.snapshot.held_rods.extend(held.filter(|&r| {
                    rods.get(r).is_some_and(|rod| {
                        players[rod.team.index()] == space_foosball::play::RodController::Player
                    })
                }));
            }
        }
        for s in &out.sounds {
            self.audio.play(*s);
        }
        let quitting = self.options.exit_after_s.is_some_and(|limit| t >= limit);
        let capture = quitting && self.options.capture_window.is_some();
        let Some(renderer) = self.renderer.as_mut() else {
            return;
        };
        match renderer.draw(&out.snapshot, out.screen, &out.hud, capture) {
            Ok(picture) => {
                self.frames += 1;
                let times = renderer.last_draw_times();
                self.stages.add(Instant::now(), session_ms, times);
                if let (Some(img), Some(path)) = (picture, &self.options.capture_window) {
                    let written = img.to_png().map_err(anyhow::Error::from).and_then(|png| {
                        space_foosball::atomic_file::write_atomic(path, &png)
                            .with_context(|| format!("writing {}", path.display()))
                    });
                    if let Err(e) = written {
                        return self.fail(el, e);
                    }
                    self.capture_written = true;
                }
            }
            Err(e) => return self.fail(el, anyhow!(e).context("drawing the frame")),
        }
        self.last = Some(out);
        if quitting && (self.capture_written || !capture) {
            el.exit();
        }
    }

    fn key(&mut self, el: &ActiveEventLoop, code: KeyCode, pressed: bool) {
        if pressed {
            match code {
                KeyCode::Escape => match self.session.escape() {
                    Ok(true) => {
                        el.exit();
                        return;
                    }
                    Ok(false) => self.grab_mouse(false),
                    Err(e) => return self.fail(el, e),
                },
                KeyCode::KeyC if self.session.stage() == Stage::Attract => {
                    self.session.start_calibration();
                }
                KeyCode::Enter if self.session.user_paused() => {
                    self.session.set_user_paused(false);
                    return;
                }
                KeyCode::KeyT | KeyCode::KeyG if self.session.stage() == Stage::Calibration => {
                    if let Some(rod) = self.session.calibration_rod() {
                        let turns = if code == KeyCode::KeyT { 1.0 } else { -1.0 };
                        self.controls.turn_paddle(rod, turns);
                    }
                }
                _ => {}
            }
        }
        if let Some(k) = map_key(code) {
            self.controls.key(k, pressed);
        }
    }

    fn parts(&mut self) -> WindowParts<'_> {
        WindowParts {
            window: self.window.clone(),
            renderer: self.renderer.as_mut(),
            controls: &mut self.controls,
        }
    }
}

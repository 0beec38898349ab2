//! `space-foosball host --window` and `join --window`: the online match in the game's
//! window. The front end's online screen (`space_foosball_front::online::screen`: the
//! lobby with the other side, its ping and the input delay, the match, its end, or why it
//! stopped) is drawn each frame; this side's rods are the board's (USB, else the built-in
//! emulated board on the keyboard, mouse and gamepad, as in `play`). The window stays on
//! the last screen until it is closed or Esc is pressed; its status is the last line on
//! stdout.

use crate::window::board::BoardChoice;
use crate::window::controls::{map_key, Controls, Key};
use crate::window::gamepad::Gamepads;
use crate::window::{open_board, open_window, GameWindow, WindowParts, Windowed};
use anyhow::{anyhow, Context, Result};
use board_link::Board;
use foosball_render::{PresentChoice, WindowRenderer};
use foosball_sim::motion::live::LiveHandle;
use foosball_sim::motion::RodPose as PaddlePose;
use space_foosball::input::paddles::BoardInput;
use space_foosball::side::Side;
use space_foosball::Table;
use space_foosball_front::online::input::SideInput;
use space_foosball_front::online::rollback::OnlineMatch;
use space_foosball_front::online::screen::{OnlineStatus, OnlineView};
use std::path::PathBuf;
use std::sync::Arc;
use std::time::Instant;
use winit::event_loop::{ActiveEventLoop, ControlFlow, EventLoop};
use winit::keyboard::KeyCode;
use winit::window::Window;

/// Most reports taken from the board in one frame (a backlog after a stall).
const REPORTS_PER_FRAME: usize = 1000;

/// How the online window runs.
pub struct OnlineWindow {
    /// Which board.
    pub board: BoardChoice,
    /// The calibration the board is read through (a file, or the defaults).
    pub calibration_path: Option<PathBuf>,
    /// Window size, pixels.
    pub size: (u32, u32),
    /// Borderless fullscreen.
    pub fullscreen: bool,
    /// Close this many seconds after the first frame showed, or a little after the match
    /// is over if that comes first (unattended checks).
    pub exit_after_s: Option<f64>,
}

/// Called once when the match is over on both sides, or stopped after frames both sides
/// played (the other side left): keeps it (recording, history).
pub type KeepMatch = Box<dyn FnMut(&OnlineMatch) -> Result<()>>;

struct App {
    view: Box<dyn OnlineView>,
    side: Side,
    table: Table,
    input: BoardInput<Box<dyn Board>>,
    live: Option<LiveHandle>,
    controls: Controls,
    pads: Gamepads,
    options: OnlineWindow,
    keep: KeepMatch,
    kept: bool,
    window: Option<Arc<Window>>,
    renderer: Option<WindowRenderer>,
    clock: Instant,
    last_tick: Instant,
    first_frame: Option<Instant>,
    /// When the match ended (over on both sides, or stopped).
    over_at: Option<Instant>,
    error: Option<anyhow::Error>,
}

/// How long an unattended window stays on the end before closing: longer than the
/// session lingers for the other side (90 frames).
const UNATTENDED_END_S: f64 = 2.0;

/// Plays the online match `view` as `side` on `table` in a window until it is closed;
/// `keep` is called once the match is over. Returns where the match stood.
pub fn run(
    view: Box<dyn OnlineView>,
    side: Side,
    table: Table,
    options: OnlineWindow,
    keep: KeepMatch,
) -> Result<OnlineStatus> {
    let (opened, calibration) = open_board(&options.board, options.calibration_path.as_deref())?;
    let mut controls = Controls::new(&table);
    // The keyboard starts on Home's goalkeeper: Away's player switches team once.
    if side == Side::Away {
        controls.key(Key::SwitchTeam, true);
        controls.key(Key::SwitchTeam, false);
    }
    let pads = Gamepads::open();
    let now = Instant::now();
    let mut app = App {
        view,
        side,
        input: BoardInput::new(opened.board, &table, calibration),
        table,
        live: opened.live,
        controls,
        pads,
        options,
        keep,
        kept: false,
        window: None,
        renderer: None,
        clock: now,
        last_tick: now,
        first_frame: None,
        over_at: None,
        error: None,
    };
    let event_loop = EventLoop::new().context("could not connect to the display")?;
    event_loop.set_control_flow(ControlFlow::Poll);
    event_loop
        .run_app(&mut Windowed(&mut app))
        .context("the window's event loop failed")?;
    if let Some(e) = app.error.take() {
        return Err(e);
    }
    Ok(app.view.status())
}

impl App {
    fn fail(&mut self, el: &ActiveEventLoop, e: anyhow::Error) {
        if self.error.is_none() {
            self.error = Some(e);
        }
        el.exit();
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
            PresentChoice::Vsync,
        );
        match opened {
            Ok((window, renderer)) => {
                eprintln!(
                    "space-foosball: drawing on {} ({})",
                    renderer.adapter().name,
                    renderer.adapter().backend
                );
                window.request_redraw();
                self.window = Some(window);
                self.renderer = Some(renderer);
            }
            Err(e) => self.fail(el, e),
        }
    }

    fn redraw(&mut self, el: &ActiveEventLoop) {
        let now = Instant::now();
        let dt = now.duration_since(self.last_tick).as_secs_f64();
        self.last_tick = now;
        self.controls.tick(dt, self.pads.state());
        if let Some(live) = &self.live {
            for (port, [axial_m, angle_rad]) in self.controls.paddle_targets() {
                live.set_target(port, PaddlePose::new(axial_m, angle_rad));
            }
        }
        // This side's rods for every frame played now: the board's newest poses.
        let rods = self.input.poll(REPORTS_PER_FRAME);
        let poses: Vec<[f64; 2]> = rods.rods.iter().map(|r| [r.slide_m, r.angle_rad]).collect();
        let (table, side) = (&self.table, self.side);
        let mut local = |_frame: u64| SideInput::from_poses(table, side, &poses);
        let (snapshot, screen, mut hud) = self
            .view
            .frame(self.clock.elapsed().as_secs_f64(), &mut local);
        if self.live.is_some() {
            let rod = self.controls.keyboard_key_number();
            hud.lines
                .insert(0, format!("KEYBOARD: ROD {rod}  ESC QUITS"));
        }
        // Kept once: at the end both sides confirmed, or as far as both played when the
        // other side left.
        let status = self.view.status();
        let ended = status.stage == "over" || (status.stage == "stopped" && status.frames > 0);
        if !self.kept && ended {
            self.kept = true;
            self.over_at = Some(Instant::now());
            if let Some(Err(e)) = self.view.game().map(|g| (self.keep)(g)) {
                eprintln!("space-foosball: {e:#}");
            }
        }
        let Some(renderer) = self.renderer.as_mut() else {
            return;
        };
        if let Err(e) = renderer.draw(&snapshot, screen, &hud, false) {
            return self.fail(el, anyhow!(e).context("drawing the frame"));
        }
        let first = *self.first_frame.get_or_insert_with(Instant::now);
        let shown_s = first.elapsed().as_secs_f64();
        let ended = self
            .over_at
            .is_some_and(|t| t.elapsed().as_secs_f64() >= UNATTENDED_END_S);
        if self
            .options
            .exit_after_s
            .is_some_and(|limit| shown_s >= limit || ended)
        {
            el.exit();
        }
    }

    fn key(&mut self, el: &ActiveEventLoop, code: KeyCode, pressed: bool) {
        if pressed && code == KeyCode::Escape {
            el.exit();
            return;
        }
        if let Some(k) = map_key(code) {
            // The other team's rods are the other side's: the keyboard stays on this one.
            if k != Key::SwitchTeam {
                self.controls.key(k, pressed);
            }
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

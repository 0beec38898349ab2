//! The page: a winit window on the page's `<canvas id="game">`, drawn by
//! [`foosball_render::WindowRenderer`] (WebGPU where the browser gives an adapter for
//! it, else WebGL2; opened asynchronously, the game running behind until it is), one [`WebSession::frame`] per animation
//! frame, keys and mouse to the emulated board, and the functions the page's JavaScript
//! calls ([`exports`]).
//!
//! URL parameters: `seed=N` (the first match's seed, default 1), `script=…` (scripted
//! keys, the desktop's `--demo-input` format, in seconds of simulated time: the match's
//! 1 ms steps since the page started, so that a key is held for the match time the
//! script says however slowly a software renderer draws).
//!
//! Online play ([`crate::online_page`]): `room=NAME` meets the other side (a desktop's
//! `space-foosball host --room NAME`, or another page) in that room of the signalling
//! server `signal=ws://…` (default `ws://127.0.0.1:3536`), playing `side=away` (default)
//! or `home`, with `goals=N` (default 5), `delay=N` frames of input delay (0–8, default
//! 2) and `frames=N` to stop after N frames; both sides must give the same seed, goals
//! and frames.
//!
//! Keys beside the controls': C at the attract screen starts calibration mode (T / G
//! turn the rod one turn forward / back, Esc leaves and keeps the fits in
//! `localStorage`, [`local_storage`]).

mod exports;
mod local_storage;

use crate::controls::map_key;
use crate::frame_stats::FrameStats;
use crate::gamepad::Gamepads;
use crate::keyboard::KeyboardBoard;
use crate::online_page::OnlinePage;
use crate::script::Script;
use crate::session::WebSession;
use exports::{with_shared, Shared};
use foosball_audio::AudioOutput;
use foosball_render::{PresentChoice, WindowRenderer};
use space_foosball::side::Side;
use space_foosball::table::Table;
use space_foosball_front::online::rollback::MatchTerms;
use space_foosball_front::online::room::{room_url, Room, DEFAULT_SIGNAL};
use std::cell::RefCell;
use std::rc::Rc;
use std::sync::Arc;
use wasm_bindgen::prelude::*;
use winit::application::ApplicationHandler;
use winit::event::{DeviceEvent, DeviceId, ElementState, KeyEvent, MouseScrollDelta, WindowEvent};
use winit::event_loop::{ActiveEventLoop, ControlFlow, EventLoop};
use winit::keyboard::{KeyCode, PhysicalKey};
use winit::platform::web::{EventLoopExtWebSys, WindowAttributesExtWebSys};
use winit::window::{CursorGrabMode, Window, WindowId};

/// The page's clock, s (`performance.now()`).
fn now_s() -> f64 {
    web_sys::window()
        .and_then(|w| w.performance())
        .map_or(0.0, |p| p.now() * 1e-3)
}

/// Shows `message` in the page's `#message` element and on the console.
fn show_message(message: &str) {
    web_sys::console::error_1(&message.into());
    if let Some(el) = web_sys::window()
        .and_then(|w| w.document())
        .and_then(|d| d.get_element_by_id("message"))
    {
        el.set_text_content(Some(message));
    }
}

/// A URL parameter of the page.
fn url_param(name: &str) -> Option<String> {
    let search = web_sys::window()?.location().search().ok()?;
    web_sys::UrlSearchParams::new_with_str(&search)
        .ok()?
        .get(name)
}

/// The page's entry point: reads the URL parameters and starts the game loop.
#[wasm_bindgen(start)]
pub fn start() {
    console_error_panic_hook::set_once();
    if let Err(e) = run() {
        show_message(&format!("space-foosball: {e:#}"));
    }
}

/// A whole-number URL parameter in `range`, if the page has it.
fn number_param(name: &str, range: std::ops::RangeInclusive<u64>) -> anyhow::Result<Option<u64>> {
    let Some(text) = url_param(name) else {
        return Ok(None);
    };
    match text.parse::<u64>() {
        Ok(n) if range.contains(&n) => Ok(Some(n)),
        Ok(_) => anyhow::bail!("{name}={text} is not in {}–{}", range.start(), range.end()),
        Err(_) => anyhow::bail!("{name}={text:?} is not a whole number"),
    }
}

/// The online match the URL asks for (`room=…`), its room opened and its traffic
/// running on the page's event loop; none without `room`.
fn online_from_url(seed: u64) -> anyhow::Result<Option<OnlinePage>> {
    let Some(name) = url_param("room") else {
        return Ok(None);
    };
    let signal = url_param("signal").unwrap_or_else(|| DEFAULT_SIGNAL.to_string());
    let side = match url_param("side").as_deref() {
        None | Some("away") => Side::Away,
        Some("home") => Side::Home,
        Some(other) => anyhow::bail!("side={other:?}: give home or away"),
    };
    let goals = number_param("goals", 1..=99)?.unwrap_or(5);
    let max_frames = number_param("frames", 1..=u64::from(u32::MAX))?;
    let delay = number_param("delay", 0..=8)?.unwrap_or(2);
    let url = room_url(&signal, &name)?;
    let (room, carried) = Room::open(&url);
    wasm_bindgen_futures::spawn_local(async move {
        if let Err(e) = carried.await {
            show_message(&format!("space-foosball: the signalling server: {e}"));
        }
    });
    let terms = MatchTerms {
        table: Table::standard(),
        seed,
        goals: goals as u32,
        max_frames,
    };
    Ok(Some(OnlinePage::new(
        room,
        &name,
        side,
        terms,
        delay as usize,
    )?))
}

fn run() -> anyhow::Result<()> {
    let seed = number_param("seed", 0..=u64::MAX)?.unwrap_or(1);
    let online = online_from_url(seed)?;
    let script: Script = match url_param("script") {
        Some(s) => s.parse().map_err(|e| anyhow::anyhow!("script: {e}"))?,
        None => Script::default(),
    };
    let mut session = WebSession::new(Table::standard(), seed)?;
    if let Err(e) = session.use_calibration_store(Box::new(local_storage::LocalStorage)) {
        web_sys::console::warn_1(&format!("space-foosball: calibration not used: {e}").into());
    }
    let pads = Gamepads::open();
    if let Some(n) = &pads.notice {
        web_sys::console::warn_1(&format!("space-foosball: {n}").into());
    }
    // Web Audio: the browser holds it suspended until a person's gesture on the page,
    // after which `AudioOutput::resume` starts it.
    let audio = AudioOutput::open();
    let event_loop = EventLoop::new().map_err(|e| anyhow::anyhow!("no event loop: {e}"))?;
    event_loop.set_control_flow(ControlFlow::Wait);
    event_loop.spawn_app(App {
        session,
        online,
        script,
        pads,
        audio,
        audio_resumed_s: f64::NEG_INFINITY,
        window: None,
        renderer: None,
        opening: Rc::new(RefCell::new(None)),
        started: now_s(),
        frames: 0,
        failed: false,
        frame_stats: FrameStats::default(),
    });
    Ok(())
}

struct App {
    session: WebSession,
    /// The online match, where the URL asks for one (it then replaces the local screens).
    online: Option<OnlinePage>,
    script: Script,
    pads: Gamepads,
    audio: AudioOutput,
    /// The page clock when the sound was last asked to resume, s.
    audio_resumed_s: f64,
    window: Option<Arc<Window>>,
    renderer: Option<WindowRenderer>,
    /// The renderer being opened (its adapter and device are awaited), once ready.
    opening: Rc<RefCell<Option<Result<WindowRenderer, String>>>>,
    /// The page clock when the game started, s.
    started: f64,
    frames: u64,
    failed: bool,
    frame_stats: FrameStats,
}

impl App {
    fn fail(&mut self, message: String) {
        self.failed = true;
        show_message(&message);
        with_shared(|s| s.error = Some(message));
    }

    /// Asks the browser to start the sound: at once after a person's key or click (a
    /// gesture the page's audio may start on), else at most once a second (a gesture
    /// elsewhere on the page, such as the board's connect button, also allows it).
    fn resume_audio(&mut self, gesture: bool) {
        let now = now_s();
        if gesture || now - self.audio_resumed_s >= 1.0 {
            self.audio_resumed_s = now;
            self.audio.resume();
        }
    }

    /// The emulated rods the keys, mouse and gamepad move: the online match's, or the
    /// local session's while no device drives it.
    fn emulated(&mut self) -> Option<&mut KeyboardBoard> {
        match &mut self.online {
            Some(online) => Some(online.keyboard()),
            None => self.session.keyboard(),
        }
    }

    fn key(&mut self, code: KeyCode, pressed: bool) {
        if let Some(online) = &mut self.online {
            if let Some(k) = map_key(code) {
                online.keyboard().key(k, pressed);
            }
            return;
        }
        if pressed && code == KeyCode::Escape {
            if let Err(e) = self.session.escape() {
                return self.fail(format!("space-foosball: {e:#}"));
            }
            self.grab_mouse(false);
            return;
        }
        if pressed && code == KeyCode::Enter && self.session.user_paused() {
            self.session.set_user_paused(false);
            return;
        }
        if pressed && code == KeyCode::KeyC {
            self.session.start_calibration();
        }
        if pressed && matches!(code, KeyCode::KeyT | KeyCode::KeyG) {
            let rod = self.session.calibration_rod();
            if let (Some(rod), Some(kb)) = (rod, self.session.keyboard()) {
                kb.turn_paddle(rod, if code == KeyCode::KeyT { 1.0 } else { -1.0 });
            }
        }
        if let (Some(k), Some(kb)) = (map_key(code), self.session.keyboard()) {
            kb.key(k, pressed);
        }
    }

    fn grab_mouse(&self, grab: bool) {
        let Some(w) = &self.window else { return };
        let mode = if grab {
            CursorGrabMode::Locked
        } else {
            CursorGrabMode::None
        };
        // The browser may refuse (no user gesture): not fatal.
        let _ = w.set_cursor_grab(mode);
        w.set_cursor_visible(!grab);
    }

    /// Takes what the page's JavaScript handed over since the last frame.
    fn take_page_input(&mut self) {
        let Shared {
            reports,
            device_events,
            ..
        } = with_shared(|s| Shared {
            reports: std::mem::take(&mut s.reports),
            device_events: std::mem::take(&mut s.device_events),
            ..Shared::default()
        });
        for event in device_events {
            match event {
                exports::DeviceEvent::Opened(name) => {
                    if self.session.uses_device() {
                        self.session.device_connected(true);
                    } else {
                        self.session.use_device(&name);
                    }
                }
                exports::DeviceEvent::Closed => self.session.device_connected(false),
            }
        }
        for r in reports {
            self.session.device_report(&r);
        }
    }

    /// One animation frame of the online match.
    fn redraw_online(&mut self, now: f64) {
        for (code, pressed) in self.script.due(now - self.started) {
            if let Some(code) = code {
                self.key(code, pressed);
            }
        }
        let pad = self.pads.state();
        let Some(online) = self.online.as_mut() else {
            return;
        };
        online.keyboard().gamepad(pad);
        let (snapshot, screen, hud) = online.frame(now);
        let online_status = serde_json::to_value(online.status()).unwrap_or_default();
        let Some(mut status) = self.present(now, &snapshot, screen, &hud, None) else {
            with_shared(|s| s.status = serde_json::json!({ "online": online_status }).to_string());
            return;
        };
        status["online"] = online_status;
        with_shared(|s| s.status = status.to_string());
    }

    /// Draws the frame and asks for the next; the page's status line after it, or none
    /// where the renderer is still opening or drawing failed (the game then stops).
    fn present(
        &mut self,
        now: f64,
        snapshot: &foosball_render::FrameSnapshot,
        screen: foosball_render::Screen,
        hud: &foosball_render::Hud,
        last: Option<&crate::session::FrameOut>,
    ) -> Option<serde_json::Value> {
        let renderer = self.renderer_ready()?;
        let adapter = renderer.adapter().name.clone();
        let backend = renderer.adapter().backend.clone();
        if let Err(e) = renderer.draw(snapshot, screen, hud, false) {
            self.fail(format!("space-foosball: drawing the frame: {e}"));
            return None;
        }
        self.frames += 1;
        self.frame_stats.frame(now * 1e3, now_s() * 1e3);
        let page = crate::status::PageFigures {
            frames: self.frames,
            seconds: now - self.started,
            adapter: &adapter,
            backend: &backend,
            frame_stats: &self.frame_stats,
            audio: &self.audio,
        };
        let status = crate::status::status(&mut self.session, last, page);
        if let Some(w) = &self.window {
            w.request_redraw();
        }
        Some(status)
    }

    /// The renderer once it has opened (a failure to open ends the game); `None` while
    /// it is still opening, with the next frame asked for.
    fn renderer_ready(&mut self) -> Option<&mut WindowRenderer> {
        if self.renderer.is_none() {
            let opened = self.opening.borrow_mut().take();
            match opened {
                Some(Ok(r)) => {
                    web_sys::console::log_1(
                        &format!(
                            "space-foosball: drawing on {} ({}), board: {}",
                            r.adapter().name,
                            r.adapter().backend,
                            self.session.board_name()
                        )
                        .into(),
                    );
                    self.renderer = Some(r);
                }
                Some(Err(e)) => {
                    self.fail(e);
                    return None;
                }
                None => {}
            }
        }
        if self.renderer.is_none() {
            // Still opening: the game runs on; the next frame looks again.
            if let Some(w) = &self.window {
                w.request_redraw();
            }
        }
        self.renderer.as_mut()
    }

    fn redraw(&mut self) {
        if self.failed {
            return;
        }
        let now = now_s();
        if self.online.is_some() {
            return self.redraw_online(now);
        }
        // Scripted keys on the match's clock, before this frame's steps run.
        for (code, pressed) in self.script.due(self.session.clock_s()) {
            if let Some(code) = code {
                self.key(code, pressed);
            }
        }
        self.take_page_input();
        let pad = self.pads.state();
        let calibrating = self.session.calibration_rod();
        if let Some(kb) = self.session.keyboard() {
            if let Some(rod) = calibrating {
                kb.select_rod(rod);
            }
            kb.gamepad(pad);
        }
        self.resume_audio(false);
        let mut out = match self.session.frame(now) {
            Ok(o) => o,
            Err(e) => return self.fail(format!("space-foosball: {e:#}")),
        };
        if let Some(kb) = self.session.keyboard() {
            let rod = kb.keyboard_key_number();
            let team = format!("{:?}", kb.keyboard_team()).to_uppercase();
            let held = [kb.keyboard_rod(), kb.pad_rod()];
            out.hud
                .lines
                .insert(0, format!("KEYBOARD: {team} ROD {rod}"));
            if out.stage == crate::flow::Stage::Playing {
                out.snapshot.held_rods.extend(held.into_iter().flatten());
            }
        }
        for sound in out.sounds.drain(..) {
            self.audio.play(sound);
        }
        while let Some(r) = self.session.take_out_report() {
            with_shared(|s| s.push_out(r.to_vec()));
        }
        if let Some(status) = self.present(now, &out.snapshot, out.screen, &out.hud, Some(&out)) {
            with_shared(|s| s.status = status.to_string());
        }
    }
}

impl ApplicationHandler for App {
    fn resumed(&mut self, el: &ActiveEventLoop) {
        if self.window.is_some() || self.failed {
            return;
        }
        let canvas = web_sys::window()
            .and_then(|w| w.document())
            .and_then(|d| d.get_element_by_id("game"))
            .and_then(|e| e.dyn_into::<web_sys::HtmlCanvasElement>().ok());
        let Some(canvas) = canvas else {
            return self.fail("space-foosball: the page has no <canvas id=\"game\">".into());
        };
        let (w, h) = (canvas.width().max(1), canvas.height().max(1));
        let attrs = Window::default_attributes()
            .with_title("Space Foosball")
            .with_canvas(Some(canvas));
        let window = match el.create_window(attrs) {
            Ok(w) => Arc::new(w),
            Err(e) => return self.fail(format!("space-foosball: no window: {e}")),
        };
        let opening = Rc::clone(&self.opening);
        let target = Arc::clone(&window);
        wasm_bindgen_futures::spawn_local(async move {
            let r = WindowRenderer::new_in_browser(target, w, h, PresentChoice::Vsync).await;
            *opening.borrow_mut() = Some(r.map_err(|e| format!("space-foosball: {e}")));
        });
        window.request_redraw();
        self.window = Some(window);
    }

    fn window_event(&mut self, _el: &ActiveEventLoop, _id: WindowId, event: WindowEvent) {
        match event {
            WindowEvent::Resized(size) => {
                if let Some(r) = &mut self.renderer {
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
            } => {
                if state == ElementState::Pressed {
                    self.resume_audio(true);
                }
                self.key(code, state == ElementState::Pressed);
            }
            WindowEvent::MouseWheel { delta, .. } => {
                let lines = match delta {
                    MouseScrollDelta::LineDelta(_, y) => f64::from(y),
                    MouseScrollDelta::PixelDelta(p) => p.y / 40.0,
                };
                if let Some(kb) = self.emulated() {
                    kb.wheel(lines);
                }
            }
            WindowEvent::MouseInput {
                state: ElementState::Pressed,
                ..
            } => {
                self.resume_audio(true);
                self.grab_mouse(true);
            }
            WindowEvent::Focused(false) => {
                self.grab_mouse(false);
                // Keys released while the page had no focus never arrive: let go of all.
                if let Some(kb) = self.emulated() {
                    kb.release_all();
                }
            }
            WindowEvent::RedrawRequested => self.redraw(),
            _ => {}
        }
    }

    fn device_event(&mut self, _el: &ActiveEventLoop, _id: DeviceId, event: DeviceEvent) {
        if let DeviceEvent::MouseMotion { delta: (dx, dy) } = event {
            if let Some(kb) = self.emulated() {
                kb.mouse_motion(dx, dy);
            }
        }
    }
}

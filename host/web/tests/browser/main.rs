//! The game in a real browser: headless Chromium (Debian's `chromium`) with WebGL2 on
//! SwiftShader loads the built page (`./scripts/web --build-only`, or
//! `$SPACE_FOOSBALL_WEB_DIST`) from a loopback server and
//!
//! * plays a match from scripted keys (the desktop's `start` script: push, push, slide,
//!   kick), with the menu's sounds on Web Audio and a scripted gamepad on the other
//!   team's goalkeeper, and checks the canvas as the desktop's window test checks its
//!   frame: not blank, the cloth, both teams' colours, the score display, and the ball
//!   where the physics puts it (the picture and the status are taken in the same
//!   animation frame);
//! * feeds recorded IN reports at the WebHID boundary (a scripted `HIDDevice` whose
//!   `inputreport` events carry the bytes) through the wasm decoder and checks the rod
//!   poses against the same reports through the tracker natively; plays a match from
//!   them until a kick of a person's rod sends a haptic OUT report, which must decode to
//!   a pulse on that rod's port; and checks that losing the board pauses play.
//!
//! Ignored by `cargo test` (it needs the wasm bundle and Chromium): the web step of
//! `scripts/test-all` runs it with `--ignored`.

mod cdp;
mod online;
mod picture;
mod server;

use cdp::Browser;
use foosball_protocol::{InReport, OutReport};
use foosball_render::scene::score_rect;
use foosball_render::Camera;
use picture::Picture;
use serde_json::Value;
use space_foosball::input::calibration::Calibration;
use space_foosball::input::paddles::{PaddleTracker, MOUSE_PACKET_PREDICTION_MS, PS2_WIRE_LEAD_MS};
use space_foosball::side::Side;
use space_foosball::table::Table;
use std::path::PathBuf;

/// The canvas size of the page, pixels.
const W: u32 = 960;
const H: u32 = 540;

fn dist() -> PathBuf {
    let dir = std::env::var_os("SPACE_FOOSBALL_WEB_DIST")
        .map(PathBuf::from)
        .unwrap_or_else(|| {
            let target = option_env!("CARGO_TARGET_DIR").map_or_else(
                || PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../target"),
                PathBuf::from,
            );
            target.join("web-dist")
        });
    assert!(
        dir.join("index.html").is_file() && dir.join("pkg").is_dir(),
        "no built page in {} (build it with ./scripts/web --build-only)",
        dir.display()
    );
    dir
}

fn open(query: &str) -> Browser {
    open_with(query, &[])
}

/// Chromium's WebGPU on SwiftShader's Vulkan (headless Chromium on Linux gives no WebGPU
/// adapter without them: `navigator.gpu` is there, `requestAdapter()` answers null).
const WEBGPU_FLAGS: [&str; 4] = [
    "--enable-unsafe-webgpu",
    "--use-webgpu-adapter=swiftshader",
    "--enable-features=Vulkan",
    "--use-vulkan=swiftshader",
];

fn open_with(query: &str, flags: &[&str]) -> Browser {
    let base = server::serve(&dist());
    let mut b = Browser::open(
        &format!("{base}/index.html?{query}"),
        W + 40,
        H + 160,
        flags,
    );
    // The wasm module is loaded and drawing.
    let s = b.wait_for(
        "window.spaceFoosball ? spaceFoosball.status() : null",
        60.0,
        "first frame",
        |v| v.get("error").is_some() || v["frames"].as_u64().is_some_and(|f| f >= 2),
    );
    assert!(s.get("error").is_none(), "the game stopped: {s}");
    eprintln!("drawing on {} ({} frames)", s["adapter"], s["frames"]);
    b
}

/// The canvas's picture and the status of the same animation frame.
fn capture(b: &mut Browser) -> (Picture, Value) {
    let v = b.eval(
        "new Promise(r => requestAnimationFrame(() => r({ \
           png: document.getElementById('game').toDataURL('image/png'), \
           status: spaceFoosball.status() })))",
    );
    let png = v["png"].as_str().expect("a data URL");
    (Picture::from_data_url(png), v["status"].clone())
}

fn numbers(v: &Value) -> Vec<f64> {
    v.as_array()
        .map(|a| a.iter().filter_map(Value::as_f64).collect())
        .unwrap_or_default()
}

#[test]
#[ignore = "needs the wasm bundle and Chromium: run by the web step of scripts/test-all"]
fn a_match_from_scripted_keys_runs_and_the_canvas_shows_it() {
    let mut b = open("seed=3&script=start&pad=fake");
    // Without WebGPU's flags this browser has `navigator.gpu` but no adapter for it: the
    // page must fall back to WebGL2.
    let s = b.eval("spaceFoosball.status()");
    assert_eq!(s["backend"], "Gl", "{s}");
    // The script pushes at 1 s and 2 s: a match as Home against the computer.
    let s = b.wait_for("spaceFoosball.status()", 120.0, "match time 1.5 s", |v| {
        v.get("error").is_some()
            || (v["stage"] == "playing" && v["match_time_s"].as_f64().unwrap_or(0.0) >= 1.5)
    });
    assert!(s.get("error").is_none(), "{s}");
    assert_eq!(
        s["controllers"],
        serde_json::json!(["player", "computer"]),
        "{s}"
    );
    assert_eq!(s["health"], "live", "{s}");
    assert_eq!(s["paused"], false, "{s}");
    // The keys reached the physics: the script slid Home's goalkeeper away from its
    // player (+y) at 2.6–2.9 s, past any play of a centred rod.
    let s = b.wait_for("spaceFoosball.status()", 60.0, "the script's slide", |v| {
        let keeper = Table::standard().rods_of(Side::Home).next().unwrap();
        numbers(&v["input_rods"][keeper])
            .first()
            .is_some_and(|s| *s > 0.03)
    });
    let t0 = s["match_time_s"].as_f64().unwrap();
    // The menu's sounds went to Web Audio (the pushes that started the match).
    assert!(s["sound"]["output"].is_string(), "no sound output: {s}");
    assert!(s["sound"]["played"].as_u64().unwrap_or(0) > 0, "{s}");
    // A gamepad (the page's scripted one, read through gilrs's Gamepad API backend)
    // drives the other team's goalkeeper: the left stick up (axes[1] = −1 in the
    // Gamepad API) slides it away from Away's player, −y.
    b.eval("fakePad.axes[1] = -1; fakePad.timestamp += 1; true");
    let away_keeper = Table::standard().rods_of(Side::Away).last().unwrap();
    b.wait_for("spaceFoosball.status()", 60.0, "the gamepad's slide", |v| {
        numbers(&v["input_rods"][away_keeper])
            .first()
            .is_some_and(|s| *s < -0.03)
    });
    b.eval("fakePad.axes[1] = 0; true");

    let (_, s) = picture_of_play(&mut b);
    assert!(s["match_time_s"].as_f64().unwrap() >= t0, "{s}");
    eprintln!(
        "web match: {} frames in {:.1} s, {} physics steps, {} dropped; \
         frame interval {} ms, frame work {} ms (figures, not pass marks)",
        s["frames"],
        s["seconds"].as_f64().unwrap_or(0.0),
        s["steps"],
        s["dropped_steps"],
        s["frame_interval_ms"],
        s["frame_work_ms"]
    );
}

#[test]
#[ignore = "needs the wasm bundle and Chromium: run by the web step of scripts/test-all"]
fn where_the_browser_gives_webgpu_the_page_draws_the_match_on_it() {
    let mut b = open_with("seed=3&script=start", &WEBGPU_FLAGS);
    // Whether this Chromium build gives WebGPU an adapter at all (Debian's does with the
    // flags); the page's choice is checked only where it has one to choose.
    let has_webgpu =
        b.eval("navigator.gpu ? navigator.gpu.requestAdapter().then(a => !!a) : false");
    if has_webgpu != true {
        eprintln!("this Chromium gives WebGPU no adapter even with {WEBGPU_FLAGS:?}: not checked");
        return;
    }
    let s = b.eval("spaceFoosball.status()");
    assert_eq!(s["backend"], "BrowserWebGpu", "{s}");
    b.wait_for("spaceFoosball.status()", 120.0, "a match", |v| {
        v.get("error").is_some() || v["stage"] == "playing"
    });
    let (_, s) = picture_of_play(&mut b);
    assert!(s.get("error").is_none(), "{s}");
    eprintln!(
        "web match on WebGPU ({}): {} frames in {:.1} s; frame interval {} ms, frame work {} \
         ms (figures, not pass marks)",
        s["adapter"],
        s["frames"],
        s["seconds"].as_f64().unwrap_or(0.0),
        s["frame_interval_ms"],
        s["frame_work_ms"]
    );
}

/// A picture of play and the status of its frame, checked as the desktop's window test
/// checks its frame: many colours (not blank), the ball's gold where the physics puts it,
/// the cloth, both teams' colours, the score display. Written to
/// `$CARGO_TARGET_TMPDIR/web-match-<backend>.png`.
fn picture_of_play(b: &mut Browser) -> (Picture, Value) {
    // After a goal, the ceremony shows the ball in the goal, so a capture that lands on
    // it waits for the re-serve (the match runs at a fraction of real time on a loaded
    // machine).
    let deadline = std::time::Instant::now() + std::time::Duration::from_secs(120);
    let (pic, s) = loop {
        let (pic, s) = capture(b);
        if s["screen"] == "match" || std::time::Instant::now() > deadline {
            break (pic, s);
        }
        std::thread::sleep(std::time::Duration::from_millis(250));
    };
    assert_eq!(s["screen"], "match", "no picture of play within 120 s: {s}");
    let name = format!(
        "web-match-{}.png",
        s["backend"].as_str().unwrap_or("unknown")
    );
    pic.save(&PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(name));
    assert_eq!((pic.w, pic.h), (W, H));
    // Not blank: many distinct colours.
    assert!(
        pic.distinct_colours() > 500,
        "{} colours",
        pic.distinct_colours()
    );
    // The ball, where the physics put it (the frame draws half a step behind the newest
    // step: well within the search radius of three ball radii).
    let table = Table::standard();
    let geometry = space_foosball_web::view::table_geometry(&table);
    let cam = Camera::for_table(&geometry, W as f32 / H as f32);
    let ball = numbers(&s["ball"]);
    let p = [ball[0], ball[1], ball[2]];
    let (bx, by) = cam.project(p, W, H).expect("ball in view");
    let r = 3.0 * cam.projected_radius(p, table.ball.radius_m(), H).max(2.0);
    let gold = pic.count([bx - r, by - r, bx + r, by + r], |[r, g, b]| {
        r > 170 && g > 110 && b < 110 && r > b + 90
    });
    assert!(gold >= 6, "{gold} ball pixels around ({bx}, {by}): {s}");
    // The cloth fills the middle of the picture.
    let mid = [
        0.3 * W as f32,
        0.35 * H as f32,
        0.7 * W as f32,
        0.65 * H as f32,
    ];
    let area = (0.4 * W as f32 * 0.3 * H as f32) as usize;
    let green = pic.count(mid, |[r, g, b]| g > r + 25 && g > b + 15);
    assert!(green * 4 > area, "cloth: {green} of {area}");
    // Both teams' men.
    let all = [0.0, 0.0, W as f32, H as f32];
    let blue = pic.count(all, |[r, g, b]| b > 150 && r < 110 && b > g + 20);
    let red = pic.count(all, |[r, g, b]| r > 150 && g < 110 && b < 140);
    assert!(blue > 300 && red > 300, "blue {blue}, red {red}");
    // The score display: white digits on the dark panel.
    let white = pic.count(score_rect(W as f32, H as f32), |[r, g, b]| {
        r > 200 && g > 200 && b > 200
    });
    assert!(white > 40, "score display: {white} white pixels");
    (pic, s)
}

/// IN reports of `ms` milliseconds from sequence `first`: each moves the paddle on
/// `port` by `axial` and `rotation` counts, every paddle present.
fn reports(first: u16, ms: u16, moves: &[(usize, i16, i16)]) -> Vec<InReport> {
    (0..ms)
        .map(|i| {
            let mut r = InReport::all_present(first.wrapping_add(i));
            for &(port, axial, rotation) in moves {
                r.paddles[port].axial = axial;
                r.paddles[port].rotation = rotation;
            }
            r
        })
        .collect()
}

/// Hands `reports` to the scripted device, as its `inputreport` events.
fn feed(b: &mut Browser, reports: &[InReport]) {
    let bytes: Vec<Vec<u8>> = reports.iter().map(|r| r.to_bytes().to_vec()).collect();
    let list = serde_json::to_string(&bytes).unwrap();
    b.eval(&format!("for (const r of {list}) fakeHid.input(r); true"));
}

fn received(b: &mut Browser, n: u64) -> Value {
    b.wait_for("spaceFoosball.status()", 30.0, "reports taken", |v| {
        v["reports"]["received"].as_u64().is_some_and(|r| r >= n)
    })
}

#[test]
#[ignore = "needs the wasm bundle and Chromium: run by the web step of scripts/test-all"]
fn webhid_reports_move_the_rods_through_the_wasm_decoder_and_a_kick_sends_a_pulse() {
    let mut b = open("hid=fake&seed=5");
    b.eval("spaceFoosball.connect().then(() => true)");
    let s = b.wait_for("spaceFoosball.status()", 10.0, "the device in use", |v| {
        v["device"] == true
    });
    assert!(
        s["board"].as_str().unwrap().contains("scripted board"),
        "{s}"
    );

    // The decoder itself, exported from wasm: a good report and a truncated one.
    let one = reports(0, 1, &[(2, 5, -7)])[0];
    let d = b.eval(&format!(
        "spaceFoosball.decode({})",
        serde_json::to_string(&one.to_bytes().to_vec()).unwrap()
    ));
    assert_eq!(d["sequence"], 0);
    assert_eq!(numbers(&d["paddles"][2])[..2], [5.0, -7.0], "{d}");
    let bad = b.eval("spaceFoosball.decode([1, 2, 3])");
    assert!(
        bad["error"].as_str().is_some_and(|e| !e.is_empty()),
        "{bad}"
    );

    // Recorded motion: three paddles slide and turn, then 60 still milliseconds (the
    // tracker's prediction has returned to the measured pose by then).
    // (210 reports: within the page's queue of 250, which drops the oldest beyond.)
    let mut recorded = reports(0, 150, &[(0, 3, 0), (3, -2, 4), (6, 1, -3)]);
    recorded.extend(reports(150, 60, &[]));
    feed(&mut b, &recorded);
    let s = received(&mut b, recorded.len() as u64);
    let table = Table::standard();
    let mut tracker = PaddleTracker::new(&table, Calibration::default());
    tracker.set_prediction_ms(MOUSE_PACKET_PREDICTION_MS);
    tracker.set_prediction_lead_ms(PS2_WIRE_LEAD_MS);
    for r in &recorded {
        tracker.apply_report(r);
    }
    let mut moved = 0;
    for (i, rod) in table.rods.iter().enumerate() {
        let got = numbers(&s["input_rods"][i]);
        let want = tracker.rod(i).unwrap();
        assert!(
            (got[0] - want.slide_m).abs() < 1e-12 && (got[1] - want.angle_rad).abs() < 1e-12,
            "rod {i}: browser {got:?}, native {want:?}"
        );
        // And by the default calibration's counts (8 counts/mm, 8 mm rod radius).
        let total = recorded
            .iter()
            .map(|r| f64::from(r.paddles[rod.port].axial))
            .sum::<f64>();
        let slide =
            (rod.handle_sign() * total / 8000.0).clamp(-rod.half_travel_m(), rod.half_travel_m());
        assert!(
            (got[0] - slide).abs() < 1e-9,
            "rod {i}: {got:?} against {slide}"
        );
        moved += usize::from(total != 0.0);
    }
    assert!(moved >= 3, "{moved} rods moved");
    assert_eq!(s["reports"]["malformed"], 0, "{s}");

    // A match from the board: push a Home rod out and back twice (attract → selection →
    // a match with Home played by the board), each 60 mm at 0.5 m/s.
    let keeper = table.rods_of(Side::Home).next().unwrap();
    let port = table.rods[keeper].port;
    let mut seq = recorded.len() as u16;
    // Each motion is followed by 100 still reports: a board reports every millisecond,
    // moving or not, and the tracker's velocity comes from the reports.
    for _ in 0..2 {
        std::thread::sleep(std::time::Duration::from_millis(900));
        let mut out = reports(seq, 120, &[(port, 4, 0)]);
        out.extend(reports(seq + 120, 100, &[]));
        let mut back = reports(seq + 220, 120, &[(port, -4, 0)]);
        back.extend(reports(seq + 340, 100, &[]));
        seq += 440;
        feed(&mut b, &out);
        std::thread::sleep(std::time::Duration::from_millis(500));
        feed(&mut b, &back);
    }
    let s = b.wait_for(
        "spaceFoosball.status()",
        20.0,
        "a match played from the board",
        |v| v["stage"] == "playing",
    );
    assert_eq!(s["controllers"][0], "player", "{s}");

    // Spin every Home rod (about 31 rad/s) until one kicks the ball: its haptic pulse
    // leaves as an OUT report.
    let home: Vec<usize> = table
        .rods_of(Side::Home)
        .map(|r| table.rods[r].port)
        .collect();
    let spin: Vec<(usize, i16, i16)> = home.iter().map(|&p| (p, 0, 2)).collect();
    let start = std::time::Instant::now();
    let sent = loop {
        feed(&mut b, &reports(seq, 100, &spin));
        seq = seq.wrapping_add(100);
        let sent = b.eval("fakeHid.sent");
        if sent.as_array().is_some_and(|a| !a.is_empty()) {
            break sent;
        }
        assert!(
            start.elapsed().as_secs() < 90,
            "no OUT report in 90 s: {}",
            b.eval("JSON.stringify(spaceFoosball.status())")
        );
        std::thread::sleep(std::time::Duration::from_millis(100));
    };
    let first = &sent[0];
    assert_eq!(first["reportId"], 0, "{first}");
    let bytes: Vec<u8> = numbers(&first["bytes"]).iter().map(|&x| x as u8).collect();
    let out = OutReport::decode(&bytes).expect("an OUT report the board decodes");
    let pulsed: Vec<usize> = (0..out.haptics.len())
        .filter(|&p| out.haptics[p].duration_ms > 0)
        .collect();
    assert!(
        !pulsed.is_empty() && pulsed.iter().all(|p| home.contains(p)),
        "pulse on ports {pulsed:?}, Home's are {home:?}: {out:?}"
    );
    for &p in &pulsed {
        // The kick feel: strength 80–255 over 20–60 ms.
        let h = out.haptics[p];
        assert!(
            h.strength >= 80 && (20..=60).contains(&h.duration_ms),
            "{h:?}"
        );
    }
    let s = b.eval("spaceFoosball.status()");
    assert!(s["kicks"].as_u64().unwrap() >= 1, "{s}");

    // Losing the board pauses play; match time stands still; plugging it back resumes.
    b.eval("fakeHid.hid.disconnect(); true");
    let lost = b.wait_for(
        "spaceFoosball.status()",
        10.0,
        "the board-lost screen",
        |v| v["screen"] == "board-lost",
    );
    assert_eq!(lost["paused"], true, "{lost}");
    std::thread::sleep(std::time::Duration::from_millis(600));
    let still = b.eval("spaceFoosball.status()");
    assert_eq!(still["screen"], "board-lost", "{still}");
    assert_eq!(still["match_time_s"], lost["match_time_s"], "{still}");
    b.eval("fakeHid.hid.connect(); true");
    feed(&mut b, &reports(seq, 50, &[]));
    let back = b.wait_for("spaceFoosball.status()", 10.0, "play resumed", |v| {
        v["paused"] == false
            && v["match_time_s"].as_f64().unwrap_or(0.0)
                > still["match_time_s"].as_f64().unwrap_or(0.0)
    });
    assert_ne!(back["screen"], "board-lost", "{back}");
}

/// A key pressed and released on the game's canvas (`code` as `KeyboardEvent.code`).
fn tap(b: &mut Browser, code: &str) {
    b.eval(&format!(
        "{{ const c = document.getElementById('game'); \
           for (const type of ['keydown', 'keyup']) \
             c.dispatchEvent(new KeyboardEvent(type, {{ code: '{code}', key: '{code}', bubbles: true }})); \
           true }}"
    ));
}

/// The reports of one paddle on `port` moved through `poses` (paddle frame, from rest at
/// zero), each reached in 100 ms and held still for the guided motion's hold, by a sensor
/// giving `gain` times the nominal counts.
fn guided_reports(port: usize, gain: f64, poses: &[[f64; 2]], first: u16) -> Vec<InReport> {
    use space_foosball::input::calibration::PaddleCalibration;
    use space_foosball::input::guided::HOLD_MS;
    let nominal = PaddleCalibration::default();
    let (mut at, mut sent, mut seq) = ([0.0; 2], [0.0f64; 2], first);
    let mut out = Vec::new();
    let mut push = |counts: [f64; 2], seq: &mut u16| {
        let mut r = InReport::all_present(*seq);
        *seq = seq.wrapping_add(1);
        r.paddles[port].axial = counts[0] as i16;
        r.paddles[port].rotation = counts[1] as i16;
        out.push(r);
    };
    for pose in poses {
        for i in 1..=100 {
            let f = f64::from(i) / 100.0;
            let p = [at[0] + (pose[0] - at[0]) * f, at[1] + (pose[1] - at[1]) * f];
            let want = nominal.counts_for(p).unwrap().map(|c| c * gain);
            let d = [(want[0] - sent[0]).round(), (want[1] - sent[1]).round()];
            sent = [sent[0] + d[0], sent[1] + d[1]];
            push(d, &mut seq);
        }
        for _ in 0..HOLD_MS + 50 {
            push([0.0; 2], &mut seq);
        }
        at = *pose;
    }
    out
}

/// Runs `before` (JavaScript) in the page, reloads it, and returns the status once the
/// reloaded page has drawn.
fn reload(b: &mut Browser, before: &str) -> Value {
    b.eval(&format!(
        "{before} setTimeout(() => location.reload(), 50); true"
    ));
    std::thread::sleep(std::time::Duration::from_millis(1000));
    b.wait_for(
        "window.spaceFoosball ? spaceFoosball.status() : null",
        60.0,
        "the page loaded again",
        |v| v["frames"].as_u64().is_some_and(|f| f >= 2),
    )
}

#[test]
#[ignore = "needs the wasm bundle and Chromium: run by the web step of scripts/test-all"]
fn calibration_mode_in_the_browser_fits_a_rod_keeps_it_in_local_storage_and_reloads_it() {
    let mut b = open("hid=fake&seed=9");
    b.eval("spaceFoosball.connect().then(() => true)");
    b.wait_for("spaceFoosball.status()", 10.0, "the device in use", |v| {
        v["device"] == true
    });
    tap(&mut b, "KeyC");
    let s = b.wait_for("spaceFoosball.status()", 10.0, "calibration mode", |v| {
        v["stage"] == "calibration"
    });
    assert!(
        s["heading"].as_str().unwrap().starts_with("ROD 1 OF 8"),
        "{s}"
    );
    assert_eq!(s["screen"], "calibration", "{s}");
    // The first rod's guided motion from a sensor that counts 4 % too many, fed at the
    // WebHID boundary (200 reports at a time: within the page's queue).
    let table = Table::standard();
    let (rod, port, gain) = (0, table.rods[0].port, 1.04);
    let motion = space_foosball::input::guided::GuidedMotion::standard(
        table.rods[rod].travel_m,
        space_foosball_web::calibrate::TURNS,
    );
    let mut poses = vec![[0.03, 0.0]];
    poses.extend(motion.steps.iter().map(|s| s.pose));
    let all = guided_reports(port, gain, &poses, 0);
    let mut fed = 0;
    for chunk in all.chunks(200) {
        feed(&mut b, chunk);
        fed += chunk.len() as u64;
        received(&mut b, fed);
    }
    let s = b.wait_for("spaceFoosball.status()", 10.0, "rod 1 fitted", |v| {
        v["calibration_rod"] == 1
    });
    assert!(
        s["heading"].as_str().unwrap().starts_with("ROD 2 OF 8"),
        "{s}"
    );
    assert!(s["lines"][0].as_str().unwrap().contains("GOOD"), "{s}");
    // Esc leaves, uses the fit and keeps it in localStorage: the desktop's file format,
    // the fit undoing the sensor's gain within 1 %.
    tap(&mut b, "Escape");
    let s = b.wait_for("spaceFoosball.status()", 10.0, "the attract screen", |v| {
        v["stage"] == "attract"
    });
    assert_eq!(numbers(&s["calibrated_ports"]), [port as f64], "{s}");
    let stored = b.eval("localStorage.getItem('space-foosball-calibration')");
    let stored = Calibration::from_json(stored.as_str().expect("a stored text"), "stored")
        .expect("a calibration file");
    let nominal = space_foosball::input::calibration::PaddleCalibration::default();
    for axis in 0..2 {
        let ratio = stored.paddles[port].matrix[axis][axis] / nominal.matrix[axis][axis] * gain;
        assert!((ratio - 1.0).abs() < 0.01, "{:?}", stored.paddles[port]);
    }
    // The next visit reads the board through it; a text that is not a calibration is
    // not used, and the screen says why.
    let s = reload(&mut b, "");
    assert_eq!(numbers(&s["calibrated_ports"]), [port as f64], "{s}");
    let s = reload(
        &mut b,
        "localStorage.setItem('space-foosball-calibration', '{\"paddles\": NaN}');",
    );
    assert_eq!(s["calibrated_ports"], serde_json::json!([]), "{s}");
    let said = s["lines"].as_array().unwrap().iter().any(|l| {
        l.as_str()
            .is_some_and(|l| l.starts_with("CALIBRATION NOT USED") && l.contains("localStorage"))
    });
    assert!(said, "{s}");
}

#[test]
#[ignore = "needs the wasm bundle and Chromium: run by the web step of scripts/test-all"]
fn the_reference_match_in_wasm_plays_as_the_desktop_recorded_it() {
    // The desktop's record: `cargo test -p space-foosball --features enhanced-determinism
    // --test cross_target` checks a desktop build against the same file.
    let path =
        PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../game/tests/golden/reference-match.json");
    let recorded: Value =
        serde_json::from_str(&std::fs::read_to_string(&path).expect("the record")).unwrap();
    let mut b = open("seed=1");
    let text = b.eval("spaceFoosball.referenceMatch()");
    let played: Value = serde_json::from_str(text.as_str().expect("JSON text")).unwrap();
    eprintln!("wasm: {played}");
    assert!(played.get("error").is_none(), "{played}");
    assert_eq!(
        played, recorded,
        "the wasm build played the reference match differently from the desktop's record"
    );
}

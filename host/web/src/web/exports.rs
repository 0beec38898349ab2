//! The functions the page's JavaScript calls, and what they share with the game loop.
//! WebHID's events arrive between animation frames: they are queued here (bounded) and
//! taken by the next frame.

use crate::board::{MAX_QUEUED_OUT, MAX_QUEUED_REPORTS, MAX_REPORT_LEN};
use std::cell::RefCell;
use std::collections::VecDeque;
use wasm_bindgen::prelude::*;

/// A device came or went.
#[derive(Debug, Clone)]
pub(crate) enum DeviceEvent {
    /// Opened (its product name).
    Opened(String),
    /// Gone (unplugged, closed).
    Closed,
}

/// What the page and the game loop share.
#[derive(Debug, Default)]
pub(crate) struct Shared {
    /// IN reports not yet taken by a frame.
    pub reports: VecDeque<Vec<u8>>,
    /// Devices opened and closed since the last frame.
    pub device_events: Vec<DeviceEvent>,
    /// OUT reports for the page to send.
    pub out: VecDeque<Vec<u8>>,
    /// The newest status line (JSON).
    pub status: String,
    /// Why the game stopped, if it did.
    pub error: Option<String>,
}

impl Shared {
    /// Queues an OUT report, dropping the oldest when the page does not send them.
    pub fn push_out(&mut self, report: Vec<u8>) {
        if self.out.len() >= MAX_QUEUED_OUT {
            self.out.pop_front();
        }
        self.out.push_back(report);
    }
}

thread_local! {
    static SHARED: RefCell<Shared> = RefCell::new(Shared::default());
}

/// Runs `f` on the shared state.
pub(crate) fn with_shared<T>(f: impl FnOnce(&mut Shared) -> T) -> T {
    SHARED.with(|s| f(&mut s.borrow_mut()))
}

/// One IN report from the device (WebHID `inputreport`: the report's bytes, without a
/// report id). Decoded by the game's next frame, through the protocol crate.
#[wasm_bindgen]
pub fn hid_report(bytes: &[u8]) {
    with_shared(|s| {
        if s.reports.len() >= MAX_QUEUED_REPORTS {
            s.reports.pop_front();
        }
        // Over-long input is not copied: an empty report, refused as malformed.
        let kept = if bytes.len() > MAX_REPORT_LEN {
            Vec::new()
        } else {
            bytes.to_vec()
        };
        s.reports.push_back(kept);
    });
}

/// A device was opened: from now on its reports drive the rods (the first one replaces
/// the keyboard's emulated board; a later one is the board coming back).
#[wasm_bindgen]
pub fn hid_opened(product_name: &str) {
    let name: String = product_name.chars().take(64).collect();
    let name = if name.is_empty() {
        "WebHID board".to_string()
    } else {
        format!("WebHID {name}")
    };
    with_shared(|s| s.device_events.push(DeviceEvent::Opened(name)));
}

/// The device is gone: play pauses and the board-lost screen shows.
#[wasm_bindgen]
pub fn hid_closed() {
    with_shared(|s| s.device_events.push(DeviceEvent::Closed));
}

/// The next OUT report (haptics) to send with `sendReport(0, …)`, if any.
#[wasm_bindgen]
pub fn take_out_report() -> Option<Vec<u8>> {
    with_shared(|s| s.out.pop_front())
}

/// The board's USB vendor id, for `navigator.hid.requestDevice` filters.
#[wasm_bindgen]
pub fn usb_vendor_id() -> u16 {
    foosball_protocol::usb::VENDOR_ID
}

/// The board's USB product id.
#[wasm_bindgen]
pub fn usb_product_id() -> u16 {
    foosball_protocol::usb::PRODUCT_ID
}

/// The board's vendor-defined HID usage page.
#[wasm_bindgen]
pub fn usb_usage_page() -> u16 {
    foosball_protocol::usb::VENDOR_USAGE_PAGE
}

/// One IN report decoded by the protocol crate, as JSON: `{"sequence", "paddles":
/// [[axial, rotation, status], …]}`, or `{"error": …}` naming what is wrong.
#[wasm_bindgen]
pub fn decode_in_report(bytes: &[u8]) -> String {
    match foosball_protocol::decode_in_report(bytes) {
        Ok((r, _)) => serde_json::json!({
            "sequence": r.sequence,
            "paddles": r
                .paddles
                .iter()
                .map(|p| [i32::from(p.axial), i32::from(p.rotation), i32::from(p.status.bits())])
                .collect::<Vec<_>>(),
        }),
        Err(e) => serde_json::json!({ "error": e.to_string() }),
    }
    .to_string()
}

/// The game's newest status line (JSON; see `status.rs`), or `{"error": …}` if it
/// stopped.
#[wasm_bindgen]
pub fn status() -> String {
    with_shared(|s| match &s.error {
        Some(e) => serde_json::json!({ "error": e }).to_string(),
        None => s.status.clone(),
    })
}

/// The reference match ([`space_foosball::play::reference`]) played here, as JSON: what
/// the browser test compares with the desktop's committed record (the wasm build steps
/// with the same `libm` functions as a desktop build with `enhanced-determinism`).
#[wasm_bindgen]
pub fn reference_match() -> String {
    use space_foosball::play::reference::{play_reference, REFERENCE_GOALS, REFERENCE_SEED};
    let table = space_foosball::Table::standard();
    match play_reference(&table, REFERENCE_SEED, REFERENCE_GOALS) {
        Ok(outcome) => serde_json::to_string(&outcome).unwrap_or_default(),
        Err(e) => serde_json::json!({ "error": e.to_string() }).to_string(),
    }
}

/// Times `repeats` (1–100) rollbacks of eight frames of the full table in this page
/// ([`space_foosball_front::online::rollback_timing`], the desktop's `bench rollback`),
/// as JSON.
#[wasm_bindgen]
pub fn bench_rollback(repeats: u32) -> String {
    use space_foosball_front::online::rollback_timing::{endless_match, time_rollbacks};
    let table = space_foosball::Table::standard();
    let performance = web_sys::window().and_then(|w| w.performance());
    let Some(performance) = performance else {
        return serde_json::json!({ "error": "the page has no performance clock" }).to_string();
    };
    let now_s = || performance.now() * 1e-3;
    let figures = endless_match(&table, 1)
        .map_err(|e| e.to_string())
        .and_then(|mut m| {
            time_rollbacks(&table, &mut m, repeats.clamp(1, 100), &now_s).map_err(|e| e.to_string())
        });
    match figures {
        Ok(f) => serde_json::to_string(&f).unwrap_or_default(),
        Err(e) => serde_json::json!({ "error": e }).to_string(),
    }
}

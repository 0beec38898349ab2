//! Match history: every finished match kept in SQLite, listed by `space-foosball history`.
//!
//! * [`record`] — what is kept of a match: when, how (local or online), the teams, the
//!   score, its length, and every shot with its speed; built from the match's events.
//! * [`store`] — the database (`rusqlite` with its bundled SQLite): one transaction per
//!   match (with its replay, the match's recording, gzip-compressed), so a process killed
//!   mid-write leaves the matches before it intact.
//! * [`played`] — the windowed game's match gathered as it is played, kept when it ends.
//! * [`cli`] — `space-foosball history [--json] [--limit N] [--history FILE]`, and
//!   `--replay ID --out FILE`.

pub mod cli;
pub mod played;
pub mod record;
pub mod store;

pub use record::{MatchRecord, Mode};
pub use store::HistoryStore;

//! The history database: SQLite through `rusqlite` (its bundled library, so nothing is
//! needed from the system).
//!
//! Each match goes in with its shots in one transaction: SQLite's write-ahead log makes the
//! commit atomic, so a process killed (or a cabinet switched off) while it writes leaves
//! every match before it intact and this one either whole or absent. The file is opened
//! with `synchronous = FULL`, so a committed match survives a power cut too.
//!
//! Beside a match lies its replay where one was made: the match's recording (the inputs of
//! every step, what `space-foosball replay` plays) as gzip-compressed JSON, in the same
//! transaction.

use super::record::{MatchRecord, Mode, Shot};
use rusqlite::{params, Connection, OpenFlags, OptionalExtension};
use space_foosball::recording::MatchRecording;
use space_foosball::side::Side;
use std::io::{Read, Write};
use std::path::{Path, PathBuf};
use std::time::Duration;

/// The schema's version, kept in SQLite's `user_version` (2: the replays beside the
/// matches).
const SCHEMA_VERSION: i64 = 2;

/// Largest replay read back, uncompressed (bytes): the largest recording the game loads.
const MAX_REPLAY_BYTES: u64 = space_foosball::recording::MAX_RECORDING_BYTES;

/// Longest a writer waits for another process's write to finish.
const BUSY_TIMEOUT: Duration = Duration::from_secs(5);

/// Most matches one listing returns.
pub const MAX_LIST: usize = 10_000;

const SCHEMA: &str = "
CREATE TABLE IF NOT EXISTS matches (
    id INTEGER PRIMARY KEY,
    finished_unix_s INTEGER NOT NULL,
    mode TEXT NOT NULL CHECK (mode IN ('local', 'online')),
    table_name TEXT NOT NULL,
    home_team TEXT NOT NULL,
    away_team TEXT NOT NULL,
    home_score INTEGER NOT NULL CHECK (home_score >= 0),
    away_score INTEGER NOT NULL CHECK (away_score >= 0),
    duration_ms INTEGER NOT NULL CHECK (duration_ms >= 0),
    seed INTEGER NOT NULL
);
CREATE TABLE IF NOT EXISTS shots (
    match_id INTEGER NOT NULL REFERENCES matches(id) ON DELETE CASCADE,
    t_ms INTEGER NOT NULL,
    side TEXT NOT NULL CHECK (side IN ('home', 'away')),
    rod INTEGER NOT NULL,
    speed_m_s REAL NOT NULL
);
CREATE INDEX IF NOT EXISTS shots_by_match ON shots(match_id);
CREATE TABLE IF NOT EXISTS replays (
    match_id INTEGER PRIMARY KEY REFERENCES matches(id) ON DELETE CASCADE,
    gzip_json BLOB NOT NULL
);
";

/// What went wrong with the history database.
#[derive(Debug, thiserror::Error)]
pub enum HistoryError {
    /// No path for the database: none given and no home or data folder known.
    #[error("no place for the match history: set SPACE_FOOSBALL_HISTORY or HOME")]
    NoPath,
    /// The folder for the database could not be made.
    #[error("cannot make the history folder {path}: {source}")]
    Folder {
        /// The folder.
        path: PathBuf,
        /// Why.
        source: std::io::Error,
    },
    /// SQLite refused (a file that is not a database, a full disk, a locked file).
    #[error("match history {path}: {source}")]
    Sqlite {
        /// The database file.
        path: PathBuf,
        /// SQLite's error.
        source: rusqlite::Error,
    },
    /// The file was written by a newer program, or holds a row this program cannot read.
    #[error("match history {path}: {what}")]
    Content {
        /// The database file.
        path: PathBuf,
        /// What is wrong.
        what: String,
    },
}

/// Where the history is kept by default: `$SPACE_FOOSBALL_HISTORY`, else
/// `$XDG_DATA_HOME/space-foosball/history.sqlite3`, else
/// `$HOME/.local/share/space-foosball/history.sqlite3`.
pub fn default_path() -> Result<PathBuf, HistoryError> {
    let var = |name: &str| std::env::var_os(name).filter(|v| !v.is_empty());
    if let Some(p) = var("SPACE_FOOSBALL_HISTORY") {
        return Ok(PathBuf::from(p));
    }
    let data = var("XDG_DATA_HOME")
        .map(PathBuf::from)
        .or_else(|| var("HOME").map(|h| PathBuf::from(h).join(".local/share")))
        .ok_or(HistoryError::NoPath)?;
    Ok(data.join("space-foosball").join("history.sqlite3"))
}

/// The open history database.
pub struct HistoryStore {
    conn: Connection,
    path: PathBuf,
}

impl HistoryStore {
    /// Opens (creating it and its folder if needed) the database at `path`.
    pub fn open(path: &Path) -> Result<Self, HistoryError> {
        if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
            std::fs::create_dir_all(dir).map_err(|source| HistoryError::Folder {
                path: dir.to_path_buf(),
                source,
            })?;
        }
        let flags = OpenFlags::SQLITE_OPEN_READ_WRITE
            | OpenFlags::SQLITE_OPEN_CREATE
            | OpenFlags::SQLITE_OPEN_NO_MUTEX;
        let sql = |source| HistoryError::Sqlite {
            path: path.to_path_buf(),
            source,
        };
        let conn = Connection::open_with_flags(path, flags).map_err(sql)?;
        conn.busy_timeout(BUSY_TIMEOUT).map_err(sql)?;
        conn.pragma_update(None, "journal_mode", "WAL")
            .map_err(sql)?;
        conn.pragma_update(None, "synchronous", "FULL")
            .map_err(sql)?;
        conn.pragma_update(None, "foreign_keys", "ON")
            .map_err(sql)?;
        let version: i64 = conn
            .pragma_query_value(None, "user_version", |r| r.get(0))
            .map_err(sql)?;
        if version > SCHEMA_VERSION {
            return Err(HistoryError::Content {
                path: path.to_path_buf(),
                what: format!(
                    "written by a newer Space Foosball (schema {version}, this one reads up \
                     to {SCHEMA_VERSION})"
                ),
            });
        }
        conn.execute_batch(SCHEMA).map_err(sql)?;
        conn.pragma_update(None, "user_version", SCHEMA_VERSION)
            .map_err(sql)?;
        Ok(Self {
            conn,
            path: path.to_path_buf(),
        })
    }

    fn sql(&self, source: rusqlite::Error) -> HistoryError {
        HistoryError::Sqlite {
            path: self.path.clone(),
            source,
        }
    }

    /// Adds a finished match, its shots and its replay (where one was made) in one
    /// transaction; its new id.
    pub fn add(
        &mut self,
        m: &MatchRecord,
        replay: Option<&MatchRecording>,
    ) -> Result<i64, HistoryError> {
        let replay = replay
            .map(|r| compress(&r.to_json()))
            .transpose()
            .map_err(|e| HistoryError::Content {
                path: self.path.clone(),
                what: format!("compressing the replay: {e}"),
            })?;
        let path = self.path.clone();
        let sql = |source| HistoryError::Sqlite {
            path: path.clone(),
            source,
        };
        let tx = self.conn.transaction().map_err(sql)?;
        let id = {
            let insert = |tx: &rusqlite::Transaction<'_>| -> rusqlite::Result<i64> {
                tx.execute(
                    "INSERT INTO matches (finished_unix_s, mode, table_name, home_team, \
                     away_team, home_score, away_score, duration_ms, seed) \
                     VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7, ?8, ?9)",
                    params![
                        m.finished_unix_s,
                        m.mode.as_str(),
                        m.table,
                        m.teams[0],
                        m.teams[1],
                        m.score[0],
                        m.score[1],
                        i64::try_from(m.duration_ms).unwrap_or(i64::MAX),
                        // SQLite's integers are signed: the seed's bits, as they are.
                        m.seed as i64,
                    ],
                )?;
                let id = tx.last_insert_rowid();
                let mut shot = tx.prepare_cached(
                    "INSERT INTO shots (match_id, t_ms, side, rod, speed_m_s) \
                     VALUES (?1, ?2, ?3, ?4, ?5)",
                )?;
                for s in &m.shots {
                    shot.execute(params![
                        id,
                        i64::try_from(s.t_ms).unwrap_or(i64::MAX),
                        side_word(s.side),
                        s.rod,
                        s.speed_m_s,
                    ])?;
                }
                if let Some(blob) = &replay {
                    tx.execute(
                        "INSERT INTO replays (match_id, gzip_json) VALUES (?1, ?2)",
                        params![id, blob],
                    )?;
                }
                Ok(id)
            };
            insert(&tx).map_err(sql)?
        };
        tx.commit().map_err(sql)?;
        Ok(id)
    }

    /// The newest `limit` matches (at most [`MAX_LIST`]), newest first, with their shots.
    pub fn recent(&self, limit: usize) -> Result<Vec<MatchRecord>, HistoryError> {
        let limit = limit.min(MAX_LIST) as i64;
        let mut stmt = self
            .conn
            .prepare(
                "SELECT id, finished_unix_s, mode, table_name, home_team, away_team, \
                 home_score, away_score, duration_ms, seed, \
                 EXISTS (SELECT 1 FROM replays WHERE match_id = matches.id) \
                 FROM matches ORDER BY id DESC LIMIT ?1",
            )
            .map_err(|e| self.sql(e))?;
        let rows = stmt
            .query_map(params![limit], |r| {
                Ok((
                    r.get::<_, i64>(0)?,
                    r.get::<_, i64>(1)?,
                    r.get::<_, String>(2)?,
                    r.get::<_, String>(3)?,
                    [r.get::<_, String>(4)?, r.get::<_, String>(5)?],
                    [r.get::<_, i64>(6)?, r.get::<_, i64>(7)?],
                    r.get::<_, i64>(8)?,
                    r.get::<_, i64>(9)?,
                    r.get::<_, bool>(10)?,
                ))
            })
            .map_err(|e| self.sql(e))?;
        let mut out = Vec::new();
        for row in rows {
            let (id, finished, mode, table, teams, score, duration, seed, has_replay) =
                row.map_err(|e| self.sql(e))?;
            let content = |what: String| HistoryError::Content {
                path: self.path.clone(),
                what: format!("match {id}: {what}"),
            };
            let mode = Mode::parse(&mode).ok_or_else(|| content(format!("mode {mode:?}")))?;
            let score = score.map(|s| u32::try_from(s).unwrap_or(0));
            out.push(MatchRecord {
                id,
                finished_unix_s: finished,
                mode,
                table,
                teams,
                score,
                duration_ms: u64::try_from(duration).unwrap_or(0),
                seed: seed as u64,
                shots: self.shots_of(id)?,
                has_replay,
            });
        }
        Ok(out)
    }

    /// The replay of match `id`: `None` where the match has none (or there is no such
    /// match); an error names a replay that cannot be read back.
    pub fn replay(&self, id: i64) -> Result<Option<MatchRecording>, HistoryError> {
        let blob: Option<Vec<u8>> = self
            .conn
            .query_row(
                "SELECT gzip_json FROM replays WHERE match_id = ?1",
                params![id],
                |r| r.get(0),
            )
            .optional()
            .map_err(|e| self.sql(e))?;
        let content = |what: String| HistoryError::Content {
            path: self.path.clone(),
            what: format!("the replay of match {id}: {what}"),
        };
        let Some(blob) = blob else {
            return Ok(None);
        };
        let mut text = String::new();
        flate2::read::GzDecoder::new(blob.as_slice())
            .take(MAX_REPLAY_BYTES + 1)
            .read_to_string(&mut text)
            .map_err(|e| content(e.to_string()))?;
        if text.len() as u64 > MAX_REPLAY_BYTES {
            return Err(content(format!(
                "larger than {} MiB uncompressed",
                MAX_REPLAY_BYTES >> 20
            )));
        }
        MatchRecording::from_json(&text)
            .map(Some)
            .map_err(|e| content(e.to_string()))
    }

    fn shots_of(&self, id: i64) -> Result<Vec<Shot>, HistoryError> {
        let mut stmt = self
            .conn
            .prepare_cached(
                "SELECT t_ms, side, rod, speed_m_s FROM shots WHERE match_id = ?1 \
                 ORDER BY rowid",
            )
            .map_err(|e| self.sql(e))?;
        let rows = stmt
            .query_map(params![id], |r| {
                Ok((
                    r.get::<_, i64>(0)?,
                    r.get::<_, String>(1)?,
                    r.get::<_, i64>(2)?,
                    r.get::<_, f64>(3)?,
                ))
            })
            .map_err(|e| self.sql(e))?;
        let mut out = Vec::new();
        for row in rows {
            let (t_ms, side, rod, speed) = row.map_err(|e| self.sql(e))?;
            let side = parse_side(&side).ok_or_else(|| HistoryError::Content {
                path: self.path.clone(),
                what: format!("match {id}: a shot's side {side:?}"),
            })?;
            out.push(Shot {
                t_ms: u64::try_from(t_ms).unwrap_or(0),
                side,
                rod: u32::try_from(rod).unwrap_or(0),
                speed_m_s: speed,
            });
        }
        Ok(out)
    }

    /// SQLite's own check of the file: `ok`, or the problems it found.
    pub fn integrity(&self) -> Result<String, HistoryError> {
        self.conn
            .pragma_query_value(None, "integrity_check", |r| r.get(0))
            .map_err(|e| self.sql(e))
    }
}

/// A recording's JSON, gzip-compressed.
fn compress(json: &str) -> std::io::Result<Vec<u8>> {
    let mut gz = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::default());
    gz.write_all(json.as_bytes())?;
    gz.finish()
}

fn side_word(side: Side) -> &'static str {
    match side {
        Side::Home => "home",
        Side::Away => "away",
    }
}

fn parse_side(word: &str) -> Option<Side> {
    match word {
        "home" => Some(Side::Home),
        "away" => Some(Side::Away),
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn record(score: [u32; 2], speeds: &[f64]) -> MatchRecord {
        MatchRecord {
            id: 0,
            finished_unix_s: 1_800_000_000,
            mode: Mode::Local,
            table: "standard".into(),
            teams: ["computer".into(), "Nova".into()],
            score,
            duration_ms: 93_250,
            seed: u64::MAX - 3,
            shots: speeds
                .iter()
                .enumerate()
                .map(|(i, &v)| Shot {
                    t_ms: 1000 * i as u64,
                    side: if i % 2 == 0 { Side::Home } else { Side::Away },
                    rod: i as u32,
                    speed_m_s: v,
                })
                .collect(),
            has_replay: false,
        }
    }

    #[test]
    fn a_match_comes_back_as_it_went_in_newest_first() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("sub/history.sqlite3");
        let mut store = HistoryStore::open(&path).unwrap();
        let first = record([5, 3], &[2.5, 7.25, 0.5]);
        let second = record([1, 5], &[]);
        let a = store.add(&first, None).unwrap();
        let b = store.add(&second, None).unwrap();
        assert!(b > a);
        drop(store);
        let store = HistoryStore::open(&path).unwrap();
        let got = store.recent(10).unwrap();
        assert_eq!(got.len(), 2);
        assert_eq!(got[0], MatchRecord { id: b, ..second });
        assert_eq!(got[1], MatchRecord { id: a, ..first });
        assert_eq!(got[1].fastest_shot().unwrap().speed_m_s, 7.25);
        assert_eq!(store.recent(1).unwrap().len(), 1);
        assert_eq!(store.integrity().unwrap(), "ok");
    }

    #[test]
    fn a_file_that_is_not_a_database_is_a_clear_error() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("history.sqlite3");
        std::fs::write(
            &path,
            b"these are not the bytes of an SQLite database file....",
        )
        .unwrap();
        let e = HistoryStore::open(&path).err().expect("refused");
        let text = e.to_string();
        assert!(text.contains("history.sqlite3"), "{text}");
    }

    #[test]
    fn a_newer_schema_is_refused_not_rewritten() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("history.sqlite3");
        let conn = Connection::open(&path).unwrap();
        conn.pragma_update(None, "user_version", SCHEMA_VERSION + 1)
            .unwrap();
        drop(conn);
        let e = HistoryStore::open(&path).err().expect("refused");
        assert!(e.to_string().contains("newer"), "{e}");
    }

    #[test]
    fn a_replay_comes_back_as_it_went_in_and_a_damaged_one_is_named() {
        use space_foosball::rules::RulesConfig;
        use space_foosball::Table;
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("history.sqlite3");
        let mut store = HistoryStore::open(&path).unwrap();
        let rec = MatchRecording::of_poses(9, Table::standard(), RulesConfig::default());
        let with = store.add(&record([2, 1], &[3.0]), Some(&rec)).unwrap();
        let without = store.add(&record([0, 2], &[]), None).unwrap();
        assert_eq!(store.replay(with).unwrap(), Some(rec));
        assert_eq!(store.replay(without).unwrap(), None);
        assert_eq!(store.replay(12345).unwrap(), None);
        let listed = store.recent(10).unwrap();
        assert_eq!(
            listed
                .iter()
                .map(|m| (m.id, m.has_replay))
                .collect::<Vec<_>>(),
            [(without, false), (with, true)]
        );
        // Bytes that are not gzip, and gzip of what is not a recording: named, not a panic.
        for blob in [vec![0u8, 0xff, 7], compress("{\"seed\": 1}").unwrap()] {
            store
                .conn
                .execute(
                    "UPDATE replays SET gzip_json = ?1 WHERE match_id = ?2",
                    params![blob, with],
                )
                .unwrap();
            let e = store.replay(with).expect_err("refused");
            assert!(
                e.to_string()
                    .contains(&format!("the replay of match {with}")),
                "{e}"
            );
        }
    }
}

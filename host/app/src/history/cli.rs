//! `space-foosball history`: the matches kept, newest first, and the best of them; a
//! match's replay written out to a file.

use super::record::MatchRecord;
use super::store::{default_path, HistoryStore, MAX_LIST};
use anyhow::{bail, Result};
use serde::Serialize;
use std::collections::BTreeMap;
use std::io::Write;
use std::path::PathBuf;

/// Options of `space-foosball history`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// The history database (default: `$SPACE_FOOSBALL_HISTORY`, else
    /// `~/.local/share/space-foosball/history.sqlite3`).
    #[arg(long, value_name = "FILE")]
    pub history: Option<PathBuf>,
    /// How many of the newest matches to list (1–10000).
    #[arg(long, default_value_t = 20)]
    pub limit: usize,
    /// Print one JSON object: the database's path and SQLite's integrity check (`ok`), the
    /// matches (with their shots and whether their replay is kept), the top scorers and the
    /// fastest shot.
    #[arg(long)]
    pub json: bool,
    /// Write the replay kept beside match ID to `--out` (a recording `space-foosball replay`
    /// plays) instead of listing.
    #[arg(long, value_name = "ID", requires = "out")]
    pub replay: Option<i64>,
    /// Where `--replay` writes the recording (written whole or not at all).
    #[arg(long, value_name = "FILE", requires = "replay")]
    pub out: Option<PathBuf>,
}

/// A team's goals over the matches listed.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Scorer {
    /// Who played the team (a character's name, `computer`, a peer).
    pub team: String,
    /// Goals scored.
    pub goals: u64,
    /// Matches won.
    pub wins: u64,
}

/// The fastest shot of the matches listed.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct FastestShot {
    /// The match it was in.
    pub match_id: i64,
    /// Who played the team that shot.
    pub team: String,
    /// Its speed, m/s.
    pub speed_m_s: f64,
}

/// The top scorers (most goals first, then most wins, then by name), at most `n`.
pub fn top_scorers(matches: &[MatchRecord], n: usize) -> Vec<Scorer> {
    let mut by_team: BTreeMap<&str, (u64, u64)> = BTreeMap::new();
    for m in matches {
        for (k, team) in m.teams.iter().enumerate() {
            let e = by_team.entry(team).or_default();
            e.0 += u64::from(m.score[k]);
            e.1 += u64::from(m.winner().is_some_and(|w| w.index() == k));
        }
    }
    let mut out: Vec<Scorer> = by_team
        .into_iter()
        .map(|(team, (goals, wins))| Scorer {
            team: team.to_string(),
            goals,
            wins,
        })
        .collect();
    out.sort_by_key(|s| std::cmp::Reverse((s.goals, s.wins)));
    out.truncate(n);
    out
}

/// The fastest shot over `matches`, if any shot was made.
pub fn fastest_shot(matches: &[MatchRecord]) -> Option<FastestShot> {
    matches
        .iter()
        .filter_map(|m| m.fastest_shot().map(|s| (m, s)))
        .max_by(|a, b| a.1.speed_m_s.total_cmp(&b.1.speed_m_s))
        .map(|(m, s)| FastestShot {
            match_id: m.id,
            team: m.teams[s.side.index()].clone(),
            speed_m_s: s.speed_m_s,
        })
}

/// `YYYY-MM-DD hh:mm` (UTC) of `unix_s` (civil from days, Hinnant's algorithm).
pub fn utc_minute(unix_s: i64) -> String {
    let days = unix_s.div_euclid(86_400);
    let secs = unix_s.rem_euclid(86_400);
    let z = days + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z - era * 146_097;
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let day = doy - (153 * mp + 2) / 5 + 1;
    let month = if mp < 10 { mp + 3 } else { mp - 9 };
    let year = yoe + era * 400 + i64::from(month <= 2);
    format!(
        "{year:04}-{month:02}-{day:02} {:02}:{:02}",
        secs / 3600,
        (secs / 60) % 60
    )
}

/// `m:ss` of a match time in ms.
fn minutes(ms: u64) -> String {
    let s = ms / 1000;
    format!("{}:{:02}", s / 60, s % 60)
}

/// One readable line of a match.
pub fn line(m: &MatchRecord) -> String {
    let fastest = m.fastest_shot().map_or_else(String::new, |s| {
        format!("  fastest shot {:.1} m/s", s.speed_m_s)
    });
    let replay = if m.has_replay { "  replay" } else { "" };
    format!(
        "#{:<4} {} UTC  {:<6} {:<8} {} {} – {} {}  {}{}{}",
        m.id,
        utc_minute(m.finished_unix_s),
        m.mode.as_str(),
        m.table,
        m.teams[0],
        m.score[0],
        m.score[1],
        m.teams[1],
        minutes(m.duration_ms),
        fastest,
        replay
    )
}

/// Runs `space-foosball history`.
pub fn run(args: &Args) -> Result<()> {
    if !(1..=MAX_LIST).contains(&args.limit) {
        bail!("--limit must be 1–{MAX_LIST}, got {}", args.limit);
    }
    let path = match &args.history {
        Some(p) => p.clone(),
        None => default_path()?,
    };
    // Listing creates nothing: no file yet is an empty history.
    let store = path
        .exists()
        .then(|| HistoryStore::open(&path))
        .transpose()?;
    if let (Some(id), Some(out)) = (args.replay, &args.out) {
        let Some(recording) = store.as_ref().map(|s| s.replay(id)).transpose()?.flatten() else {
            bail!("no replay of match {id} in {}", path.display());
        };
        recording
            .save(out)
            .map_err(|e| anyhow::anyhow!("writing the replay of match {id}: {e}"))?;
        println!(
            "the replay of match {id} is in {} (space-foosball replay {})",
            out.display(),
            out.display()
        );
        return Ok(());
    }
    let integrity = match &store {
        Some(s) => s.integrity()?,
        None => "ok".to_string(),
    };
    let matches = match &store {
        Some(s) => s.recent(args.limit)?,
        None => Vec::new(),
    };
    let scorers = top_scorers(&matches, 5);
    let fastest = fastest_shot(&matches);
    // Written, not printed: a closed pipe (`| head`) is an error, not a panic.
    let mut out = std::io::stdout().lock();
    if args.json {
        writeln!(
            out,
            "{}",
            serde_json::json!({
                "history": path,
                "integrity": integrity,
                "matches": matches,
                "top_scorers": scorers,
                "fastest_shot": fastest,
            })
        )?;
        return Ok(());
    }
    if integrity != "ok" {
        eprintln!(
            "space-foosball: SQLite's check of {}: {integrity}",
            path.display()
        );
    }
    if matches.is_empty() {
        writeln!(out, "no matches kept yet in {}", path.display())?;
        return Ok(());
    }
    writeln!(
        out,
        "{} newest matches in {}:",
        matches.len(),
        path.display()
    )?;
    for m in &matches {
        writeln!(out, "{}", line(m))?;
    }
    writeln!(out, "top scorers:")?;
    for s in &scorers {
        writeln!(out, "  {:<12} {} goals, {} wins", s.team, s.goals, s.wins)?;
    }
    if let Some(f) = fastest {
        writeln!(
            out,
            "fastest shot: {:.1} m/s by {} (match #{})",
            f.speed_m_s, f.team, f.match_id
        )?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dates_in_utc() {
        assert_eq!(utc_minute(0), "1970-01-01 00:00");
        // 2000-02-29 12:34 UTC, a leap day.
        assert_eq!(utc_minute(951_827_640), "2000-02-29 12:34");
        assert_eq!(utc_minute(-60), "1969-12-31 23:59");
    }
}

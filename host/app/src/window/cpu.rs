//! CPU time per thread of this process, from Linux's `/proc/self/task/*/stat`: the
//! window's report uses it to say where a frame's time goes on a software GPU (the
//! driver's rasteriser threads), the physics thread and the window's own thread.
//! Elsewhere, or when `/proc` cannot be read, the list is empty.

use std::collections::BTreeMap;

/// Clock ticks per second of `/proc`'s `utime`/`stime` (`USER_HZ`, 100 on Linux).
const TICKS_PER_S: f64 = 100.0;

/// CPU seconds (user + system) used so far by each thread of this process, summed by
/// thread name; the main thread (the window's: events, session, drawing) is `main`.
pub(crate) fn thread_cpu_seconds() -> BTreeMap<String, f64> {
    let mut out = BTreeMap::new();
    let Ok(tasks) = std::fs::read_dir("/proc/self/task") else {
        return out;
    };
    let pid = std::process::id().to_string();
    for task in tasks.flatten() {
        let Ok(stat) = std::fs::read_to_string(task.path().join("stat")) else {
            continue;
        };
        let Some((name, seconds)) = parse_stat(&stat) else {
            continue;
        };
        let name = if task.file_name().to_str() == Some(pid.as_str()) {
            "main".to_string()
        } else {
            name
        };
        *out.entry(name).or_insert(0.0) += seconds;
    }
    out
}

/// `(name, cpu seconds)` of one `stat` line: `tid (name) state ppid … utime stime …`.
/// The name may hold spaces and parentheses, so it ends at the last `)`.
fn parse_stat(stat: &str) -> Option<(String, f64)> {
    let open = stat.find('(')?;
    let close = stat.rfind(')')?;
    let name = stat.get(open + 1..close)?.to_string();
    let fields: Vec<&str> = stat.get(close + 1..)?.split_whitespace().collect();
    // After the name: state (field 3), …, utime (14), stime (15).
    let utime: u64 = fields.get(11)?.parse().ok()?;
    let stime: u64 = fields.get(12)?.parse().ok()?;
    Some((name, (utime + stime) as f64 / TICKS_PER_S))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn stat_lines_give_name_and_seconds() {
        let line = "4242 (llvmpipe-0) S 1 2 3 4 5 6 7 8 9 10 150 25 0 0 20 0 3 0 99";
        assert_eq!(parse_stat(line), Some(("llvmpipe-0".into(), 1.75)));
        // A name with spaces and a parenthesis.
        let odd = "7 (a (b) c) R 1 2 3 4 5 6 7 8 9 10 3 1 0";
        assert_eq!(parse_stat(odd), Some(("a (b) c".into(), 0.04)));
        assert_eq!(parse_stat("7 (short) R 1 2"), None);
        assert_eq!(parse_stat("garbage"), None);
        assert_eq!(parse_stat("7 (x) R 1 2 3 4 5 6 7 8 9 10 -3 1 0"), None);
    }

    #[test]
    fn this_process_has_a_main_thread_on_linux() {
        let t = thread_cpu_seconds();
        if cfg!(target_os = "linux") {
            assert!(t.contains_key("main"), "{t:?}");
            assert!(t.values().all(|s| s.is_finite() && *s >= 0.0));
        }
    }
}

//! Frame times in the page: the interval between animation frames and the time each
//! frame's own work took (physics steps, screens, scene, submitting to WebGL), over the
//! last [`WINDOW`] frames, as medians and 95th percentiles.

use std::collections::VecDeque;

/// Frames the figures cover.
pub const WINDOW: usize = 240;

/// Recent frame times. See the [module](self).
#[derive(Debug, Clone, Default)]
pub struct FrameStats {
    last_start_ms: Option<f64>,
    intervals: VecDeque<f64>,
    work: VecDeque<f64>,
}

fn push(q: &mut VecDeque<f64>, v: f64) {
    if v.is_finite() && v >= 0.0 {
        if q.len() == WINDOW {
            q.pop_front();
        }
        q.push_back(v);
    }
}

/// The `p`-quantile (0–1) of `q` by the nearest rank, `None` when empty.
fn quantile(q: &VecDeque<f64>, p: f64) -> Option<f64> {
    let mut v: Vec<f64> = q.iter().copied().collect();
    v.sort_by(f64::total_cmp);
    let i = ((p * v.len() as f64).ceil() as usize).clamp(1, v.len().max(1)) - 1;
    v.get(i).copied()
}

impl FrameStats {
    /// A frame started at `start_ms` and its work ended at `end_ms` (ms, one clock).
    pub fn frame(&mut self, start_ms: f64, end_ms: f64) {
        if let Some(last) = self.last_start_ms {
            push(&mut self.intervals, start_ms - last);
        }
        self.last_start_ms = Some(start_ms);
        push(&mut self.work, end_ms - start_ms);
    }

    /// Median and 95th percentile of the interval between frames, ms.
    pub fn interval_ms(&self) -> Option<(f64, f64)> {
        Some((
            quantile(&self.intervals, 0.5)?,
            quantile(&self.intervals, 0.95)?,
        ))
    }

    /// Median and 95th percentile of a frame's own work, ms.
    pub fn work_ms(&self) -> Option<(f64, f64)> {
        Some((quantile(&self.work, 0.5)?, quantile(&self.work, 0.95)?))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn medians_and_percentiles_of_the_recent_frames() {
        let mut s = FrameStats::default();
        assert_eq!(s.interval_ms(), None);
        for i in 0..100 {
            let start = f64::from(i) * 20.0;
            s.frame(start, start + f64::from(i % 10));
        }
        assert_eq!(s.interval_ms(), Some((20.0, 20.0)));
        assert_eq!(s.work_ms(), Some((4.0, 9.0)));
        s.frame(f64::NAN, 0.0);
        for i in 0..2 * WINDOW {
            s.frame(5000.0 + i as f64 * 10.0, 5000.0 + i as f64 * 10.0 + 1.0);
        }
        assert_eq!(s.interval_ms(), Some((10.0, 10.0)));
        assert_eq!(s.work_ms(), Some((1.0, 1.0)));
    }
}

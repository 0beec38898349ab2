//! Islands (bodies connected by touching contacts or joints) and sleeping: an island whose
//! bodies have all been slow for [`TIME_TO_SLEEP`] goes to sleep as a whole (velocities zeroed,
//! skipped by integration, narrow phase and solver); an island with any moving body is awake,
//! which wakes sleeping bodies that an awake body touches.

use crate::dynamics::{BodyKind, BodySet};
use crate::geometry::Manifold;

use super::union_find::UnionFind;

/// Seconds of rest before an island sleeps.
pub(crate) const TIME_TO_SLEEP: f64 = 0.5;
/// Speed below which a body counts as resting (m/s).
pub(crate) const LINEAR_SLEEP_SPEED: f64 = 0.05;
/// Angular speed below which a body counts as resting (rad/s).
pub(crate) const ANGULAR_SLEEP_SPEED: f64 = 0.05;

/// Union–find buffers, kept between steps.
#[derive(Clone, Debug, Default)]
pub(crate) struct Islands {
    sets: UnionFind,
    min_sleep: Vec<f64>,
}

impl Islands {
    /// Updates sleep timers over `dt` (s), builds islands from touching manifolds and joint
    /// pairs, and sets `awake`. Returns the number of islands of dynamic bodies.
    pub(crate) fn update(
        &mut self,
        bodies: &mut BodySet,
        manifolds: &[Manifold],
        joints: &[(usize, usize)],
        dt: f64,
    ) -> usize {
        let n = bodies.len();
        self.sets.reset(n);
        self.min_sleep.clear();
        self.min_sleep.resize(n, f64::INFINITY);
        for i in 0..n {
            if bodies.kind[i] != BodyKind::Dynamic || !bodies.awake[i] {
                continue;
            }
            let slow = bodies.vel[i].norm_squared() < LINEAR_SLEEP_SPEED * LINEAR_SLEEP_SPEED
                && bodies.omega[i].norm_squared() < ANGULAR_SLEEP_SPEED * ANGULAR_SLEEP_SPEED;
            bodies.sleep_time[i] = if slow { bodies.sleep_time[i] + dt } else { 0.0 };
        }
        let moving_kinematic = |b: &BodySet, i: usize| {
            b.kind[i] == BodyKind::Kinematic
                && (b.vel[i].norm_squared() > 0.0 || b.omega[i].norm_squared() > 0.0)
        };
        for m in manifolds {
            if m.len == 0 || m.min_separation() > 0.0 {
                continue;
            }
            let (a, b) = (m.a as usize, m.b as usize);
            let (da, db) = (
                bodies.kind[a] == BodyKind::Dynamic,
                bodies.kind[b] == BodyKind::Dynamic,
            );
            if da && db {
                self.sets.union(a, b);
            } else if da && moving_kinematic(bodies, b) {
                bodies.sleep_time[a] = 0.0;
            } else if db && moving_kinematic(bodies, a) {
                bodies.sleep_time[b] = 0.0;
            }
        }
        for &(a, b) in joints {
            if bodies.kind[a] == BodyKind::Dynamic && bodies.kind[b] == BodyKind::Dynamic {
                self.sets.union(a, b);
            }
        }
        let mut islands = 0;
        for i in 0..n {
            if bodies.kind[i] == BodyKind::Dynamic {
                let r = self.sets.find(i);
                if self.min_sleep[r] == f64::INFINITY {
                    islands += 1;
                }
                self.min_sleep[r] = self.min_sleep[r].min(bodies.sleep_time[i]);
            }
        }
        for i in 0..n {
            if bodies.kind[i] != BodyKind::Dynamic {
                continue;
            }
            let r = self.sets.find(i);
            let awake = self.min_sleep[r] < TIME_TO_SLEEP;
            if !awake && bodies.awake[i] {
                bodies.vel[i].fill(0.0);
                bodies.omega[i].fill(0.0);
            }
            bodies.awake[i] = awake;
        }
        islands
    }
}

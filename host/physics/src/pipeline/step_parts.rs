//! A step taken in parts where a tree's links move farther in it than its contacts see.
//!
//! A tree's contacts are found at the step's start, and each keeps its normal, its point on
//! the link (moved with the link's pose at each substep) and its Jacobian rows for the whole
//! step. A tree in contact whose links move by more than the speculative distance in one step
//! can reach an edge or a face that none of its contacts saw, or meet one along another normal
//! (a falling arm pivoting on one step's edge swings its far end onto the next); and a link
//! that turns far within the step is pushed along rows that no longer describe how its
//! contact points move, which can give the tree energy (a spinning chain landing on the
//! ground, or on another chain, whipped its far end off at 10 m/s). Such a step is taken as
//! `n` steps of `dt / n` on `substeps / n` substeps each: the same substep, so the solver's
//! cost is unchanged, while collision and preparation run `n` times and each part's contacts
//! are found, and their rows formed, where the links are then (what `vphys hard --finer N`
//! measures). The parts are decided from the last step's contacts before a step; a tree
//! that meets something it did not touch in the last step (a chain's first landing) is
//! found by the step's own collision, which then stops the step and takes it in parts. A
//! tree whose every coordinate follows a motor or prescribed motion (a
//! servo-driven rod) is left whole: it goes where its drives take it, within their force
//! limits, and the contacts it meets on the way stop it through them, so the step is split
//! for the falling and swinging trees that nothing holds.

use super::world::World;
use super::StepCounters;
use crate::dynamics::DynamicsError;

/// The most parts a step is split into.
const MAX_PARTS: usize = 4;

/// Tree `tree`'s bit in a set of trees (the 64th and later share the last).
fn tree_bit(tree: usize) -> u64 {
    1 << tree.min(63)
}

impl World {
    /// Into how many parts this step is split: 1, unless a tree not driven in every
    /// coordinate had a contact in the last step; then the farthest any of its link proxies'
    /// points travels over the step (`|v| + |ω| · reach`, m, at the step's start) in
    /// speculative distances, rounded up, within `1 ..= min(MAX_PARTS, substeps)` and
    /// dividing `substeps`. Last step's contacts name their trees by index; a tree removed
    /// since is passed over (another tree moved into its index is measured instead, which
    /// at worst splits a step that need not be).
    pub(super) fn step_parts(&self) -> usize {
        let substeps = self.settings.substeps.max(1);
        let spec = self.settings.speculative_distance;
        if self.tree_contacts.contacts.is_empty() || substeps < 2 || spec <= 0.0 {
            return 1;
        }
        // The trees with a contact, a bit each (trees past the 63rd share the last bit, and
        // all their proxies are measured); the trees driven in every coordinate, found once
        // each (those past the 63rd asked each time: their bit is not theirs alone).
        let (mut trees, mut driven) = (0u64, 0u64);
        for tree in self.tree_contacts.trees_touching() {
            let bit = tree_bit(tree);
            if (trees | driven) & bit != 0 {
                continue;
            }
            if self.articulated.get(tree).is_none_or(|a| a.fully_driven()) {
                if tree < 63 {
                    driven |= bit;
                }
                continue;
            }
            trees |= bit;
        }
        self.parts_for(trees)
    }

    /// Into how many parts a whole step whose collision has just run must be split instead:
    /// 1, unless a tree not driven in every coordinate meets something this step that it
    /// did not touch in the last (a chain's first landing, which `step_parts` cannot see
    /// coming); then as `step_parts` counts for those trees.
    pub(super) fn parts_on_arrival(&self) -> usize {
        let (Some(narrow), true) = (self.narrow.as_ref(), self.settings.substeps >= 2) else {
            return 1;
        };
        if self.proxies.iter().all(Option::is_none) {
            return 1;
        }
        // Trees already weighed before the step (they touched something in the last one),
        // trees found driven (asked once each, as in `step_parts`), and the arriving trees.
        let mut seen: u64 = self
            .tree_contacts
            .trees_touching()
            .fold(0, |t, k| t | tree_bit(k));
        let mut trees = 0u64;
        for m in &narrow.manifolds {
            for i in [m.a as usize, m.b as usize] {
                let Some(Some(p)) = self.proxies.get(i) else {
                    continue;
                };
                let bit = tree_bit(p.tree);
                if seen & bit != 0 {
                    continue;
                }
                if self
                    .articulated
                    .get(p.tree)
                    .is_some_and(|a| !a.fully_driven())
                {
                    trees |= bit;
                }
                if p.tree < 63 {
                    seen |= bit;
                }
            }
        }
        self.parts_for(trees)
    }

    /// The parts for the trees in `trees` (`tree_bit`): their links' farthest travel over the
    /// step in speculative distances, rounded up, within `1 ..= min(MAX_PARTS, substeps)` and
    /// dividing `substeps`.
    fn parts_for(&self, trees: u64) -> usize {
        let (substeps, spec) = (
            self.settings.substeps.max(1),
            self.settings.speculative_distance,
        );
        if trees == 0 || spec <= 0.0 {
            return 1;
        }
        let travel = self.links_travel(trees);
        if travel.is_nan() || travel <= spec {
            return 1;
        }
        let n = (travel / spec).ceil().min(MAX_PARTS.min(substeps) as f64) as usize;
        // Parts of whole substeps: the largest divisor of `substeps` not above `n`.
        (1..=n).rev().find(|k| substeps % k == 0).unwrap_or(1)
    }

    /// The farthest any point of the link proxies of the trees in `trees` (`tree_bit`)
    /// travels over the step at its velocities now (m).
    fn links_travel(&self, trees: u64) -> f64 {
        let mut travel: f64 = 0.0;
        for (i, p) in self.proxies.iter().enumerate() {
            if p.is_none_or(|p| trees & tree_bit(p.tree) == 0) {
                continue;
            }
            let w = self.bodies.omega[i];
            let turn = w.norm();
            let reach = if turn > 0.0 {
                let axis = self.bodies.rot[i].tr_mul(&(w / turn));
                self.bodies.shape[i].reach_about(&axis)
            } else {
                0.0
            };
            travel = travel.max((self.bodies.vel[i].norm() + turn * reach) * self.dt);
        }
        travel
    }

    /// The step as `parts` steps of `dt / parts`, each on `substeps / parts` substeps; the
    /// clock ends at the step's end exactly, and the counters add up the parts' work.
    pub(super) fn step_in_parts(&mut self, parts: usize) -> Result<(), DynamicsError> {
        let (dt, substeps, t0) = (self.dt, self.settings.substeps, self.time);
        self.dt = dt / parts as f64;
        self.settings.substeps = substeps / parts;
        let mut done = StepCounters::default();
        let mut result = Ok(());
        for _ in 0..parts {
            result = self.step_unguarded(false).map(|_| ());
            done.add_part(&self.counters);
            if result.is_err() {
                break;
            }
        }
        self.dt = dt;
        self.settings.substeps = substeps;
        self.time = t0 + dt;
        self.counters = done;
        result
    }
}

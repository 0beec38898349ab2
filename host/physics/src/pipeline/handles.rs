//! Handles: how code outside the engine names a body, a joint, a tree or a link.
//!
//! The world stores its bodies densely (structure of arrays, see `dynamics::body_set`), so a
//! body's storage index changes when another body is removed. A handle does not: it is a
//! slot number and the slot's generation, and the slot table maps it to the current index.
//! A removed body's slot is reused with the next generation, so an old handle to it is stale
//! (accessors answer `None`) rather than silently naming a newer body.

/// A body of a [`World`](super::World): free, kinematic or fixed, or the proxy of a tree link.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct BodyHandle {
    slot: u32,
    generation: u32,
}

/// A joint between two bodies of a [`World`](super::World).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct JointHandle {
    slot: u32,
    generation: u32,
}

/// An articulated tree of a [`World`](super::World). Trees are never removed, so a tree
/// handle stays valid for the world's life.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct TreeHandle(pub(crate) u32);

/// A link (body) of an articulated tree: the tree and the link's index in the model's body
/// order (parents before children).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct LinkHandle {
    /// The tree.
    pub tree: TreeHandle,
    /// Index of the link in the tree's model.
    pub(crate) link: u32,
}

impl TreeHandle {
    /// The link `link` of this tree (its index in the model's body order).
    pub fn link(self, link: usize) -> LinkHandle {
        LinkHandle {
            tree: self,
            link: link as u32,
        }
    }

    pub(crate) fn index(self) -> usize {
        self.0 as usize
    }
}

/// What a handle type needs from the slot table.
pub(crate) trait SlotHandle: Copy {
    fn from_parts(slot: u32, generation: u32) -> Self;
    fn slot(self) -> u32;
    fn generation(self) -> u32;
}

macro_rules! slot_handle {
    ($t:ty) => {
        impl SlotHandle for $t {
            fn from_parts(slot: u32, generation: u32) -> Self {
                Self { slot, generation }
            }
            fn slot(self) -> u32 {
                self.slot
            }
            fn generation(self) -> u32 {
                self.generation
            }
        }
    };
}
slot_handle!(BodyHandle);
slot_handle!(JointHandle);

/// No dense index: the slot is free.
const VACANT: u32 = u32::MAX;

/// Slot table: handle ↔ dense index, with generations and a free list.
#[derive(Clone, Debug, Default)]
pub(crate) struct Slots {
    /// Per slot: generation and dense index (`VACANT` when free).
    slots: Vec<(u32, u32)>,
    /// Per dense index: its slot.
    dense_slot: Vec<u32>,
    /// Free slots, reused last in, first out.
    free: Vec<u32>,
}

impl Slots {
    /// A handle for a new element appended at dense index `self.len()`.
    pub(crate) fn insert<H: SlotHandle>(&mut self) -> H {
        let dense = self.dense_slot.len() as u32;
        let slot = match self.free.pop() {
            Some(s) => {
                self.slots[s as usize].1 = dense;
                s
            }
            None => {
                self.slots.push((0, dense));
                (self.slots.len() - 1) as u32
            }
        };
        self.dense_slot.push(slot);
        H::from_parts(slot, self.slots[slot as usize].0)
    }

    /// The dense index of `h`, `None` when stale.
    pub(crate) fn index<H: SlotHandle>(&self, h: H) -> Option<usize> {
        let &(generation, dense) = self.slots.get(h.slot() as usize)?;
        (generation == h.generation() && dense != VACANT).then_some(dense as usize)
    }

    /// The handle of dense index `i`.
    pub(crate) fn handle<H: SlotHandle>(&self, i: usize) -> H {
        let slot = self.dense_slot[i];
        H::from_parts(slot, self.slots[slot as usize].0)
    }

    /// Frees dense index `i` the way `Vec::swap_remove` does: the last element moves into
    /// `i`. Returns the old index of the moved element, if one moved.
    pub(crate) fn swap_remove(&mut self, i: usize) -> Option<usize> {
        let last = self.dense_slot.len() - 1;
        let slot = self.dense_slot.swap_remove(i);
        let entry = &mut self.slots[slot as usize];
        entry.0 = entry.0.wrapping_add(1);
        entry.1 = VACANT;
        self.free.push(slot);
        (i != last).then(|| {
            let moved = self.dense_slot[i];
            self.slots[moved as usize].1 = i as u32;
            last
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn handles_survive_removal_of_others_and_go_stale_when_removed() {
        let mut s = Slots::default();
        let a: BodyHandle = s.insert();
        let b: BodyHandle = s.insert();
        let c: BodyHandle = s.insert();
        assert_eq!(s.swap_remove(0), Some(2)); // c moves into 0
        assert_eq!(s.index(a), None);
        assert_eq!(s.index(b), Some(1));
        assert_eq!(s.index(c), Some(0));
        let d: BodyHandle = s.insert(); // reuses a's slot, next generation
        assert_ne!(d, a);
        assert_eq!(s.index(a), None);
        assert_eq!(s.index(d), Some(2));
        assert_eq!(s.handle::<BodyHandle>(2), d);
        assert_eq!(s.swap_remove(2), None); // the last one: nothing moves
        assert_eq!(s.index(d), None);
    }
}

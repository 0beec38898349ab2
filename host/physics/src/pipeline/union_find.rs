//! Disjoint sets of body indices (union–find with path halving): the islands of bodies that
//! touch or are joined, for sleeping (`islands`) and for extra substeps (`island_substeps`).

/// The sets, kept between steps (no allocation once grown).
#[derive(Clone, Debug, Default)]
pub(crate) struct UnionFind {
    parent: Vec<u32>,
}

impl UnionFind {
    /// `n` sets of one index each.
    pub(crate) fn reset(&mut self, n: usize) {
        self.parent.clear();
        self.parent.extend(0..n as u32);
    }

    /// The representative of `i`'s set (the least index that was joined to it).
    pub(crate) fn find(&mut self, mut i: usize) -> usize {
        while self.parent[i] as usize != i {
            let p = self.parent[i] as usize;
            self.parent[i] = self.parent[p];
            i = p;
        }
        i
    }

    /// Joins the sets of `a` and `b`.
    pub(crate) fn union(&mut self, a: usize, b: usize) {
        let (ra, rb) = (self.find(a), self.find(b));
        if ra != rb {
            self.parent[ra.max(rb)] = ra.min(rb) as u32;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn joined_indices_share_a_representative() {
        let mut u = UnionFind::default();
        u.reset(6);
        u.union(4, 2);
        u.union(2, 5);
        u.union(0, 1);
        assert_eq!([u.find(2), u.find(4), u.find(5)], [2, 2, 2]);
        assert_eq!([u.find(0), u.find(1)], [0, 0]);
        assert_eq!(u.find(3), 3);
        u.union(1, 5);
        assert!((0..6).filter(|&i| i != 3).all(|i| u.find(i) == 0));
    }
}

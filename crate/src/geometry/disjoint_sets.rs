//! Disjoint sets (union-find) over `0..n`, used for welding classes and mesh components.

/// Union-find whose representative is always the smallest member, so classes can be numbered
/// in the order of their first member without extra bookkeeping.
#[derive(Clone, Debug)]
pub struct DisjointSets {
    parent: Vec<u32>,
}

impl DisjointSets {
    /// `n` singleton sets.
    pub fn new(n: usize) -> Self {
        Self {
            parent: (0..n as u32).collect(),
        }
    }

    /// The representative (smallest member) of `v`'s set, halving paths on the way.
    pub fn find(&mut self, mut v: u32) -> u32 {
        while self.parent[v as usize] != v {
            let grand = self.parent[self.parent[v as usize] as usize];
            self.parent[v as usize] = grand;
            v = grand;
        }
        v
    }

    /// Merges the sets of `a` and `b`.
    pub fn union(&mut self, a: u32, b: u32) {
        let (ra, rb) = (self.find(a), self.find(b));
        if ra != rb {
            self.parent[ra.max(rb) as usize] = ra.min(rb);
        }
    }

    /// Dense labels `0..count` for the members that `include` accepts, numbered in the order of
    /// each set's smallest included member; excluded members get `u32::MAX`.
    pub fn labels(&mut self, include: impl Fn(usize) -> bool) -> (Vec<u32>, usize) {
        let n = self.parent.len();
        let mut label = vec![u32::MAX; n];
        let mut root_label = vec![u32::MAX; n];
        let mut count = 0u32;
        for v in (0..n).filter(|&v| include(v)) {
            let r = self.find(v as u32) as usize;
            if root_label[r] == u32::MAX {
                root_label[r] = count;
                count += 1;
            }
            label[v] = root_label[r];
        }
        (label, count as usize)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn unions_and_labels() {
        let mut s = DisjointSets::new(6);
        s.union(4, 1);
        s.union(5, 4);
        s.union(2, 3);
        assert_eq!(s.find(5), 1);
        assert_eq!(s.labels(|_| true), (vec![0, 1, 2, 2, 1, 1], 3));
        assert_eq!(s.labels(|v| v != 0), (vec![u32::MAX, 0, 1, 1, 0, 0], 2));
    }
}

//! Where a reconstruction's wrong edges are: each predicted edge that the ground truth lacks is
//! put in one class by how its two vertices relate in the ground truth. Edge F1 says how many
//! edges are wrong; this says which kind of mistake bounds it (issue 14;
//! docs/experiments/2026-11-27-wrong-edges.md).
//!
//! Classes, first match wins, for a wrong edge `(i, j)`:
//! 1. **quad diagonal**: `i` and `j` have two common neighbours `k`, `l` that are joined, so
//!    `i-k-l` and `j-k-l` are ground-truth triangles and `(i, j)` is the other diagonal of their
//!    quad (an artist's split of a planar quad is arbitrary to the geometry);
//! 2. **two hops**: otherwise, a common neighbour;
//! 3. **near in space**: farther apart in the ground truth's graph, but closer than
//!    [`NEAR_EDGE_LENGTHS`] mean edge lengths (the two sides of a thin part, touching pieces);
//! 4. **far**: everything else.

use glam::Vec3;
use serde::{Deserialize, Serialize};

use crate::geometry::topology::{Edge, adjacency, canonical_edges};

/// The radius of "near in space", in mean ground-truth edge lengths of the mesh.
pub const NEAR_EDGE_LENGTHS: f32 = 2.0;

/// Counts of wrong edges by class (module docs).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct WrongEdgeKinds {
    pub quad_diagonal: usize,
    pub two_hops: usize,
    pub near_in_space: usize,
    pub far: usize,
}

impl WrongEdgeKinds {
    /// All wrong edges.
    pub fn total(&self) -> usize {
        self.quad_diagonal + self.two_hops + self.near_in_space + self.far
    }
}

impl std::ops::Add for WrongEdgeKinds {
    type Output = Self;

    fn add(self, o: Self) -> Self {
        Self {
            quad_diagonal: self.quad_diagonal + o.quad_diagonal,
            two_hops: self.two_hops + o.two_hops,
            near_in_space: self.near_in_space + o.near_in_space,
            far: self.far + o.far,
        }
    }
}

/// Classifies the edges of `predicted` that are not in `actual`. `positions` are the ground
/// truth's vertices, indexed like both edge sets; a predicted edge naming a vertex past them
/// (a padding slot) counts as far.
pub fn wrong_edge_kinds(predicted: &[Edge], actual: &[Edge], positions: &[Vec3]) -> WrongEdgeKinds {
    let n = positions.len();
    let actual = canonical_edges(actual);
    let actual: Vec<Edge> = actual.into_iter().filter(|e| (e[1] as usize) < n).collect();
    let neighbours = adjacency(n, &actual);
    let joined = |a: u32, b: u32| actual.binary_search(&[a.min(b), a.max(b)]).is_ok();
    let mean_edge = if actual.is_empty() {
        0.0
    } else {
        actual
            .iter()
            .map(|&[a, b]| positions[a as usize].distance(positions[b as usize]))
            .sum::<f32>()
            / actual.len() as f32
    };
    let near = NEAR_EDGE_LENGTHS * mean_edge;
    let mut kinds = WrongEdgeKinds::default();
    for [i, j] in canonical_edges(predicted) {
        if joined(i, j) {
            continue;
        }
        if j as usize >= n {
            kinds.far += 1;
            continue;
        }
        // Neighbour lists are sorted: merge them for the common neighbours.
        let common: Vec<u32> = neighbours[i as usize]
            .iter()
            .copied()
            .filter(|k| neighbours[j as usize].binary_search(k).is_ok())
            .collect();
        let quad = common
            .iter()
            .enumerate()
            .any(|(x, &k)| common[x + 1..].iter().any(|&l| joined(k, l)));
        if quad {
            kinds.quad_diagonal += 1;
        } else if !common.is_empty() {
            kinds.two_hops += 1;
        } else if positions[i as usize].distance(positions[j as usize]) < near {
            kinds.near_in_space += 1;
        } else {
            kinds.far += 1;
        }
    }
    kinds
}

/// How the decoder scores the two diagonals of the ground truth's quads: two triangles
/// `i-k-l`, `j-k-l` whose shared edge `k-l` is the diagonal the artist took and `i-j` (not an
/// edge) the one not taken. Counts over every such quad, summed across meshes; the shares
/// say whether the artist's choice is in the scores at all, and whether the threshold can
/// separate it (issue 14; docs/experiments/2026-11-28-edge-f1-limit.md).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct QuadDiagonals {
    pub quads: usize,
    /// Quads whose taken diagonal scores above the other one.
    pub taken_scores_higher: usize,
    /// Quads whose two diagonals both score above the threshold.
    pub both_above_threshold: usize,
    /// Of those, the quads whose taken diagonal scores higher.
    pub both_above_taken_higher: usize,
}

impl std::ops::Add for QuadDiagonals {
    type Output = Self;

    fn add(self, o: Self) -> Self {
        Self {
            quads: self.quads + o.quads,
            taken_scores_higher: self.taken_scores_higher + o.taken_scores_higher,
            both_above_threshold: self.both_above_threshold + o.both_above_threshold,
            both_above_taken_higher: self.both_above_taken_higher + o.both_above_taken_higher,
        }
    }
}

/// [`QuadDiagonals`] of the ground truth's `actual` edges over `n` vertices, `score(a, b)` being
/// the decoder's score of the pair (an edge where it exceeds `tau`).
pub fn quad_diagonals(
    actual: &[Edge],
    n: usize,
    score: impl Fn(u32, u32) -> f32,
    tau: f32,
) -> QuadDiagonals {
    let actual: Vec<Edge> = canonical_edges(actual)
        .into_iter()
        .filter(|e| (e[1] as usize) < n)
        .collect();
    let neighbours = adjacency(n, &actual);
    let joined = |a: u32, b: u32| actual.binary_search(&[a.min(b), a.max(b)]).is_ok();
    let mut out = QuadDiagonals::default();
    for &[k, l] in &actual {
        let common: Vec<u32> = neighbours[k as usize]
            .iter()
            .copied()
            .filter(|c| neighbours[l as usize].binary_search(c).is_ok())
            .collect();
        for (x, &i) in common.iter().enumerate() {
            for &j in &common[x + 1..] {
                if joined(i, j) {
                    continue; // a tetrahedron's corner, not a quad
                }
                let (taken, other) = (score(k, l), score(i, j));
                out.quads += 1;
                out.taken_scores_higher += (taken > other) as usize;
                if taken > tau && other > tau {
                    out.both_above_threshold += 1;
                    out.both_above_taken_higher += (taken > other) as usize;
                }
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::primitives::grid;
    use crate::geometry::topology::edges;

    #[test]
    fn each_kind_of_wrong_edge_is_told_apart() {
        // A 4 x 4 grid: vertex (i, j) is 5 j + i, and each quad is split along
        // (i, j)-(i+1, j+1), so (1, 0)-(0, 1) is the diagonal the split did not take.
        let g = grid(4, 4);
        let actual = edges(&g.faces);
        let v = |i: u32, j: u32| 5 * j + i;
        assert!(actual.contains(&[v(0, 0), v(1, 1)]));
        let diagonal = [v(1, 0), v(0, 1)];
        let two_hops = [v(0, 0), v(2, 0)];
        let far = [v(0, 0), v(4, 4)];
        let mut predicted = actual.clone();
        predicted.extend([diagonal, two_hops, far]);
        let kinds = wrong_edge_kinds(&predicted, &actual, &g.positions);
        assert_eq!(
            kinds,
            WrongEdgeKinds {
                quad_diagonal: 1,
                two_hops: 1,
                near_in_space: 0,
                far: 1,
            }
        );
        assert_eq!(kinds.total(), 3);
        // A padding slot is far; a correct edge is not counted at all.
        let pad = [0, g.positions.len() as u32];
        let kinds = wrong_edge_kinds(&[pad, actual[0]], &actual, &g.positions);
        assert_eq!((kinds.far, kinds.total()), (1, 1));
    }

    #[test]
    fn quad_diagonals_compare_the_taken_diagonal_with_the_other() {
        // A 2 x 1 strip, each square split along (i, j)-(i+1, j+1): three edges have two
        // triangles, so three quads. Left square: the untaken diagonal scores higher. Right
        // square: both pass tau, the taken one higher. The middle edge (1, 0)-(1, 1) is the
        // taken diagonal of the parallelogram (0, 0)-(1, 0)-(2, 1)-(1, 1): only it passes tau.
        let g = grid(2, 1);
        let actual = edges(&g.faces);
        let v = |i: u32, j: u32| 3 * j + i;
        let taken_left = [v(0, 0), v(1, 1)];
        assert!(actual.contains(&taken_left));
        let scored = [
            ([v(1, 0), v(0, 1)], 2.0),
            (taken_left, -1.0),
            ([v(1, 1), v(2, 0)], 0.5),
            ([v(0, 0), v(2, 1)], -5.0),
        ];
        let score = |a: u32, b: u32| {
            let pair = [a.min(b), a.max(b)];
            scored
                .iter()
                .find(|(p, _)| [p[0].min(p[1]), p[0].max(p[1])] == pair)
                .map_or(1.0, |&(_, s)| s)
        };
        let q = quad_diagonals(&actual, g.positions.len(), score, 0.0);
        assert_eq!(
            q,
            QuadDiagonals {
                quads: 3,
                taken_scores_higher: 2,
                both_above_threshold: 1,
                both_above_taken_higher: 1,
            }
        );
    }

    #[test]
    fn pairs_close_in_space_but_far_in_the_graph_are_near() {
        // Two unit triangles stacked 0.1 apart: joining them is "near in space".
        let positions = [
            Vec3::ZERO,
            Vec3::X,
            Vec3::Y,
            Vec3::new(0.0, 0.0, 0.1),
            Vec3::new(1.0, 0.0, 0.1),
            Vec3::new(0.0, 1.0, 0.1),
        ];
        let actual = [[0, 1], [1, 2], [0, 2], [3, 4], [4, 5], [3, 5]];
        let kinds = wrong_edge_kinds(&[[0, 3], [1, 4]], &actual, &positions);
        assert_eq!(kinds.near_in_space, 2);
        assert_eq!(kinds.total(), 2);
    }
}

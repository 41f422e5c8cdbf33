//! Small exact meshes for tests and benchmarks: octahedron, icosphere, cube, open grid.
//! All are counter-clockwise seen from outside (or from +z for the grid).

use std::collections::HashMap;

use glam::Vec3;

use crate::Mesh;

/// The unit octahedron: 6 vertices on the axes, 8 faces.
pub fn octahedron() -> Mesh {
    let positions = vec![Vec3::X, -Vec3::X, Vec3::Y, -Vec3::Y, Vec3::Z, -Vec3::Z];
    let faces = vec![
        [0, 2, 4],
        [2, 1, 4],
        [1, 3, 4],
        [3, 0, 4],
        [2, 0, 5],
        [1, 2, 5],
        [3, 1, 5],
        [0, 3, 5],
    ];
    Mesh::new(positions, faces)
}

/// An icosphere of radius 1: the icosahedron with each triangle split in four `subdivisions`
/// times. Vertex counts 12, 42, 162, 642, 2562, 10242 for 0..=5 subdivisions.
pub fn icosphere(subdivisions: u32) -> Mesh {
    let t = (1.0 + 5f32.sqrt()) / 2.0;
    let mut positions: Vec<Vec3> = [
        (-1.0, t, 0.0),
        (1.0, t, 0.0),
        (-1.0, -t, 0.0),
        (1.0, -t, 0.0),
        (0.0, -1.0, t),
        (0.0, 1.0, t),
        (0.0, -1.0, -t),
        (0.0, 1.0, -t),
        (t, 0.0, -1.0),
        (t, 0.0, 1.0),
        (-t, 0.0, -1.0),
        (-t, 0.0, 1.0),
    ]
    .iter()
    .map(|&(x, y, z)| Vec3::new(x, y, z).normalize())
    .collect();
    let mut faces: Vec<[u32; 3]> = vec![
        [0, 11, 5],
        [0, 5, 1],
        [0, 1, 7],
        [0, 7, 10],
        [0, 10, 11],
        [1, 5, 9],
        [5, 11, 4],
        [11, 10, 2],
        [10, 7, 6],
        [7, 1, 8],
        [3, 9, 4],
        [3, 4, 2],
        [3, 2, 6],
        [3, 6, 8],
        [3, 8, 9],
        [4, 9, 5],
        [2, 4, 11],
        [6, 2, 10],
        [8, 6, 7],
        [9, 8, 1],
    ];
    for _ in 0..subdivisions {
        let mut midpoints: HashMap<(u32, u32), u32> = HashMap::new();
        let mut midpoint = |a: u32, b: u32, positions: &mut Vec<Vec3>| -> u32 {
            *midpoints.entry((a.min(b), a.max(b))).or_insert_with(|| {
                let m = (positions[a as usize] + positions[b as usize]).normalize();
                positions.push(m);
                positions.len() as u32 - 1
            })
        };
        let mut next = Vec::with_capacity(faces.len() * 4);
        for &[a, b, c] in &faces {
            let ab = midpoint(a, b, &mut positions);
            let bc = midpoint(b, c, &mut positions);
            let ca = midpoint(c, a, &mut positions);
            next.extend([[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]);
        }
        faces = next;
    }
    Mesh::new(positions, faces)
}

/// The cube [-1,1]^3: 8 vertices, 12 faces.
pub fn cube() -> Mesh {
    let positions = (0..8)
        .map(|i| {
            let s = |bit: u32| if i & (1 << bit) != 0 { 1.0 } else { -1.0 };
            Vec3::new(s(0), s(1), s(2))
        })
        .collect();
    let faces = vec![
        [0, 2, 1],
        [1, 2, 3],
        [4, 5, 6],
        [5, 7, 6],
        [0, 1, 4],
        [1, 5, 4],
        [2, 6, 3],
        [3, 6, 7],
        [0, 4, 2],
        [2, 4, 6],
        [1, 3, 5],
        [3, 7, 5],
    ];
    Mesh::new(positions, faces)
}

/// An open grid of `nx` x `ny` quads on z = 0 spanning `[0, 1]^2`, each quad cut along the
/// diagonal from its (0,0) corner to its (1,1) corner. Vertex (i, j) has index `j * (nx+1) + i`.
pub fn grid(nx: u32, ny: u32) -> Mesh {
    let mut positions = Vec::new();
    for j in 0..=ny {
        for i in 0..=nx {
            positions.push(Vec3::new(i as f32 / nx as f32, j as f32 / ny as f32, 0.0));
        }
    }
    let v = |i: u32, j: u32| j * (nx + 1) + i;
    let mut faces = Vec::new();
    for j in 0..ny {
        for i in 0..nx {
            faces.push([v(i, j), v(i + 1, j), v(i + 1, j + 1)]);
            faces.push([v(i, j), v(i + 1, j + 1), v(i, j + 1)]);
        }
    }
    Mesh::new(positions, faces)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn counts_and_orientation() {
        for (s, v) in [(0, 12), (1, 42), (2, 162), (3, 642), (4, 2562)] {
            let m = icosphere(s);
            assert_eq!(m.positions.len(), v);
            assert_eq!(m.faces.len(), 20 * 4usize.pow(s));
            assert!(
                m.signed_volume() > 0.0,
                "icosphere({s}) faces point inwards"
            );
        }
        assert!(octahedron().signed_volume() > 0.0);
        assert!((cube().signed_volume() - 8.0).abs() < 1e-5);
        let g = grid(4, 4);
        assert_eq!((g.positions.len(), g.faces.len()), (25, 32));
        for f in 0..g.faces.len() {
            let [a, b, c] = g.triangle(f);
            assert!((b - a).cross(c - a).z > 0.0);
        }
    }
}

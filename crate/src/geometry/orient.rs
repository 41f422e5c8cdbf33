//! Faces turned outward: each piece of a consistently wound mesh wound so that the volume it
//! encloses is positive.
//!
//! Extraction winds every piece consistently but picks the side it faces by chance: a closed
//! L-bracket came back inside out. glTF's materials are single-sided unless they say otherwise,
//! so a viewer culls such a mesh's outside and lights its inside. No library the project uses
//! does this one step on an index list, so it is written here.

use glam::DVec3;

use crate::Mesh;
use crate::geometry::topology::edge_pieces;

/// A piece whose enclosed volume is below this share of its area to the power 3/2 (a flat
/// card, a strip) has no outside to face; it is left as it is.
const FLAT_VOLUME: f64 = 1e-4;

/// Reverses the winding of each piece of `mesh` ([`edge_pieces`]: faces joined across edges) whose signed
/// volume, taken about the piece's own area centroid so that an open piece counts too, is
/// negative: a closed piece then faces out exactly, an open one (a box with a missing side,
/// a bowl) the way its bulk says. Pieces too flat to enclose anything
/// ([`FLAT_VOLUME`]) are kept. Vertex normals, where the mesh has them, are negated with
/// their faces. Returns how many pieces were turned.
pub fn orient_outward(mesh: &mut Mesh) -> usize {
    let (pieces, count) = edge_pieces(&mesh.faces);
    let mut area = vec![0.0f64; count];
    let mut centroid = vec![DVec3::ZERO; count];
    for (f, &p) in pieces.iter().enumerate() {
        let [a, b, c] = mesh.triangle(f).map(|v| v.as_dvec3());
        let w = 0.5 * (b - a).cross(c - a).length();
        area[p as usize] += w;
        centroid[p as usize] += w * (a + b + c) / 3.0;
    }
    for (c, &a) in centroid.iter_mut().zip(&area) {
        if a > 0.0 {
            *c /= a;
        }
    }
    let mut volume = vec![0.0f64; count];
    for (f, &p) in pieces.iter().enumerate() {
        let o = centroid[p as usize];
        let [a, b, c] = mesh.triangle(f).map(|v| v.as_dvec3() - o);
        volume[p as usize] += a.dot(b.cross(c)) / 6.0;
    }
    let turn: Vec<bool> = volume
        .iter()
        .zip(&area)
        .map(|(&v, &a)| v < -FLAT_VOLUME * a.powf(1.5))
        .collect();
    let mut flipped_vertex = vec![false; mesh.positions.len()];
    for (face, &p) in mesh.faces.iter_mut().zip(&pieces) {
        if turn[p as usize] {
            face.swap(1, 2);
            for &v in face.iter() {
                flipped_vertex[v as usize] = true;
            }
        }
    }
    if mesh.normals.len() == mesh.positions.len() {
        for (n, _) in mesh
            .normals
            .iter_mut()
            .zip(&flipped_vertex)
            .filter(|(_, f)| **f)
        {
            *n = -*n;
        }
    }
    turn.iter().filter(|&&t| t).count()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::primitives::cube;

    fn inside_out(mut m: Mesh) -> Mesh {
        for f in &mut m.faces {
            f.swap(1, 2);
        }
        m
    }

    #[test]
    fn an_inside_out_box_is_turned_and_an_outward_one_kept() {
        let mut outward = cube();
        assert!(outward.signed_volume() > 0.0);
        let faces = outward.faces.clone();
        assert_eq!(orient_outward(&mut outward), 0);
        assert_eq!(outward.faces, faces);
        let mut turned = inside_out(cube());
        assert_eq!(orient_outward(&mut turned), 1);
        assert_eq!(turned.faces, faces);
    }

    #[test]
    fn an_open_box_faces_out_by_its_bulk_and_each_piece_on_its_own() {
        // A box without its top (two faces gone), far from the origin so that the volume
        // must be taken about the piece itself; beside it a whole box facing out.
        let mut open = inside_out(cube());
        let top: Vec<usize> = (0..open.faces.len())
            .filter(|&f| open.triangle(f).iter().all(|v| v.y > 0.0))
            .collect();
        assert_eq!(top.len(), 2);
        open.faces = (0..open.faces.len())
            .filter(|f| !top.contains(f))
            .map(|f| open.faces[f])
            .collect();
        for p in &mut open.positions {
            *p += glam::Vec3::new(5.0, 0.0, 0.0);
        }
        let mut both = open.clone();
        let whole = cube();
        let offset = both.positions.len() as u32;
        both.positions.extend(&whole.positions);
        both.faces
            .extend(whole.faces.iter().map(|f| f.map(|v| v + offset)));
        assert_eq!(orient_outward(&mut both), 1);
        // Every face of the open box now faces away from its centre.
        for f in 0..open.faces.len() {
            let [a, b, c] = both.triangle(f);
            let centre = glam::Vec3::new(5.0, 0.0, 0.0);
            assert!((b - a).cross(c - a).dot((a + b + c) / 3.0 - centre) > 0.0);
        }
        assert_eq!(
            &both.faces[open.faces.len()..],
            &{
                let mut w = whole.faces.clone();
                for f in &mut w {
                    *f = f.map(|v| v + offset);
                }
                w
            }[..]
        );
    }

    #[test]
    fn a_flat_card_is_left_alone() {
        let mut card = Mesh {
            positions: vec![
                glam::Vec3::ZERO,
                glam::Vec3::X,
                glam::Vec3::new(1.0, 1.0, 0.0),
                glam::Vec3::Y,
            ],
            faces: vec![[0, 2, 1], [0, 3, 2]],
            ..Default::default()
        };
        let faces = card.faces.clone();
        assert_eq!(orient_outward(&mut card), 0);
        assert_eq!(card.faces, faces);
    }
}

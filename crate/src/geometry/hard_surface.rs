//! The hard-surface set: eight closed, faceted shapes an artist would model with few faces
//! (a box, an L-bracket, a wedge, a stair of three steps, a 12-sided cylinder, a table, a house
//! and a hollow box open at the top). Each is exact and small, so a test can ask whether
//! generation gives back flat faces, sharp creases and true corners. Y is up; sizes are in
//! arbitrary units (the evaluation normalises). `tests/fixtures/hard_surface/` holds them as
//! OBJ with their 4,096-point samples, clean and with 1% noise (CC0, made by this module).

use glam::Vec3;

use crate::Mesh;
use crate::geometry::clean::weld;

/// The set, by name, in a fixed order.
pub fn hard_surface_set() -> Vec<(&'static str, Mesh)> {
    vec![
        ("box", cuboid(Vec3::ZERO, Vec3::new(2.0, 1.0, 1.4))),
        (
            "l_bracket",
            prism(
                &[
                    [0.0, 0.0],
                    [1.2, 0.0],
                    [1.2, 0.25],
                    [0.25, 0.25],
                    [0.25, 1.0],
                    [0.0, 1.0],
                ],
                0.8,
            ),
        ),
        ("wedge", prism(&[[0.0, 0.0], [1.5, 0.0], [0.0, 0.8]], 1.0)),
        (
            "stair",
            prism(
                &[
                    [0.0, 0.0],
                    [1.5, 0.0],
                    [1.5, 1.2],
                    [1.0, 1.2],
                    [1.0, 0.8],
                    [0.5, 0.8],
                    [0.5, 0.4],
                    [0.0, 0.4],
                ],
                1.0,
            ),
        ),
        ("cylinder12", cylinder(12, 0.5, 1.2)),
        ("table", table()),
        (
            "house",
            prism(
                &[[0.0, 0.0], [1.2, 0.0], [1.2, 0.8], [0.6, 1.3], [0.0, 0.8]],
                1.6,
            ),
        ),
        ("hollow_box", hollow_box(Vec3::new(1.0, 0.8, 1.0), 0.08)),
    ]
}

/// Appends the quad `p` (a planar loop) as two triangles facing `outward`.
fn quad(positions: &mut Vec<Vec3>, faces: &mut Vec<[u32; 3]>, p: [Vec3; 4], outward: Vec3) {
    let base = positions.len() as u32;
    positions.extend(p);
    let n = (p[1] - p[0]).cross(p[2] - p[0]);
    let (a, b, c, d) = (base, base + 1, base + 2, base + 3);
    if n.dot(outward) >= 0.0 {
        faces.extend([[a, b, c], [a, c, d]]);
    } else {
        faces.extend([[a, c, b], [a, d, c]]);
    }
}

/// Welds the corners the quads share.
fn welded(positions: Vec<Vec3>, faces: Vec<[u32; 3]>) -> Mesh {
    weld(&Mesh::new(positions, faces), 1e-6).0
}

/// The axis-aligned box from `min` to `max`, 8 vertices and 12 faces.
pub fn cuboid(min: Vec3, max: Vec3) -> Mesh {
    let (mut positions, mut faces) = (Vec::new(), Vec::new());
    add_cuboid(&mut positions, &mut faces, min, max);
    welded(positions, faces)
}

fn add_cuboid(positions: &mut Vec<Vec3>, faces: &mut Vec<[u32; 3]>, min: Vec3, max: Vec3) {
    let start = positions.len();
    let corner = |x: bool, y: bool, z: bool| {
        Vec3::new(
            if x { max.x } else { min.x },
            if y { max.y } else { min.y },
            if z { max.z } else { min.z },
        )
    };
    for axis in 0..3 {
        for high in [false, true] {
            // The four corners with this axis fixed, in a loop.
            let loop4 =
                [(false, false), (true, false), (true, true), (false, true)].map(|(s, t)| {
                    let mut bits = [false; 3];
                    bits[axis] = high;
                    bits[(axis + 1) % 3] = s;
                    bits[(axis + 2) % 3] = t;
                    corner(bits[0], bits[1], bits[2])
                });
            let mut outward = Vec3::ZERO;
            outward[axis] = if high { 1.0 } else { -1.0 };
            quad(positions, faces, loop4, outward);
        }
    }
    // Weld this box's own corners only (a table's legs touch its top but stay apart).
    let mut part = Mesh::new(
        positions[start..].to_vec(),
        faces[faces.len() - 12..]
            .iter()
            .map(|f| f.map(|v| v - start as u32))
            .collect(),
    );
    part = weld(&part, 1e-6).0;
    positions.truncate(start);
    faces.truncate(faces.len() - 12);
    positions.extend(&part.positions);
    faces.extend(part.faces.iter().map(|f| f.map(|v| v + start as u32)));
}

/// The counter-clockwise polygon `profile` (x, y) extruded along z by `depth`, its caps
/// triangulated by ear clipping.
pub fn prism(profile: &[[f32; 2]], depth: f32) -> Mesh {
    let n = profile.len() as u32;
    let mut positions: Vec<Vec3> = profile.iter().map(|&[x, y]| Vec3::new(x, y, 0.0)).collect();
    positions.extend(profile.iter().map(|&[x, y]| Vec3::new(x, y, depth)));
    let mut faces = Vec::new();
    for [a, b, c] in ear_clip(profile) {
        // The far cap faces +z (counter-clockwise), the near one -z.
        faces.push([a + n, b + n, c + n]);
        faces.push([a, c, b]);
    }
    for i in 0..n {
        let j = (i + 1) % n;
        faces.push([i, j, j + n]);
        faces.push([i, j + n, i + n]);
    }
    Mesh::new(positions, faces)
}

/// Triangles of a simple counter-clockwise polygon by ear clipping.
fn ear_clip(profile: &[[f32; 2]]) -> Vec<[u32; 3]> {
    let p = |i: u32| glam::Vec2::from_array(profile[i as usize]);
    let cross = |a: glam::Vec2, b: glam::Vec2, c: glam::Vec2| (b - a).perp_dot(c - a);
    let mut left: Vec<u32> = (0..profile.len() as u32).collect();
    let mut out = Vec::new();
    while left.len() > 3 {
        let k = left.len();
        let ear = (0..k).find(|&i| {
            let (a, b, c) = (left[(i + k - 1) % k], left[i], left[(i + 1) % k]);
            cross(p(a), p(b), p(c)) > 0.0
                && left.iter().all(|&q| {
                    q == a
                        || q == b
                        || q == c
                        || !(cross(p(a), p(b), p(q)) >= 0.0
                            && cross(p(b), p(c), p(q)) >= 0.0
                            && cross(p(c), p(a), p(q)) >= 0.0)
                })
        });
        let Some(i) = ear else { break };
        out.push([left[(i + k - 1) % k], left[i], left[(i + 1) % k]]);
        left.remove(i);
    }
    if left.len() == 3 {
        out.push([left[0], left[1], left[2]]);
    }
    out
}

/// An upright `sides`-sided prism of circumradius `radius` and height `height` (y up).
pub fn cylinder(sides: u32, radius: f32, height: f32) -> Mesh {
    let profile: Vec<[f32; 2]> = (0..sides)
        .map(|i| {
            let a = std::f32::consts::TAU * i as f32 / sides as f32;
            [radius * a.cos(), radius * a.sin()]
        })
        .collect();
    // Extruded along z, then turned so the axis is y: (x, y, z) -> (x, z, -y) keeps the winding.
    let mut m = prism(&profile, height);
    for p in &mut m.positions {
        *p = Vec3::new(p.x, p.z, -p.y);
    }
    m
}

/// A table: a top slab on four square legs (five closed boxes).
fn table() -> Mesh {
    let (mut positions, mut faces) = (Vec::new(), Vec::new());
    let (w, d, h, t, leg) = (1.6, 1.0, 0.8, 0.1, 0.1);
    add_cuboid(
        &mut positions,
        &mut faces,
        Vec3::new(0.0, h - t, 0.0),
        Vec3::new(w, h, d),
    );
    for (x, z) in [
        (0.05, 0.05),
        (w - 0.05 - leg, 0.05),
        (0.05, d - 0.05 - leg),
        (w - 0.05 - leg, d - 0.05 - leg),
    ] {
        add_cuboid(
            &mut positions,
            &mut faces,
            Vec3::new(x, 0.0, z),
            Vec3::new(x + leg, h - t, z + leg),
        );
    }
    Mesh::new(positions, faces)
}

/// A box of outer size `size` (y up) with walls and floor `wall` thick and no lid: one closed
/// surface of 16 vertices (outside, rim, inside, floor).
fn hollow_box(size: Vec3, wall: f32) -> Mesh {
    let (mut positions, mut faces) = (Vec::new(), Vec::new());
    let (lo, hi) = (Vec3::ZERO, size);
    let (ilo, ihi) = (
        Vec3::new(wall, wall, wall),
        Vec3::new(size.x - wall, size.y, size.z - wall),
    );
    let at = |x: f32, y: f32, z: f32| Vec3::new(x, y, z);
    // Outer bottom, facing down.
    quad(
        &mut positions,
        &mut faces,
        [
            at(lo.x, 0.0, lo.z),
            at(hi.x, 0.0, lo.z),
            at(hi.x, 0.0, hi.z),
            at(lo.x, 0.0, hi.z),
        ],
        -Vec3::Y,
    );
    // Inner floor, facing up.
    quad(
        &mut positions,
        &mut faces,
        [
            at(ilo.x, wall, ilo.z),
            at(ihi.x, wall, ilo.z),
            at(ihi.x, wall, ihi.z),
            at(ilo.x, wall, ihi.z),
        ],
        Vec3::Y,
    );
    let outer = [
        at(lo.x, 0.0, lo.z),
        at(hi.x, 0.0, lo.z),
        at(hi.x, 0.0, hi.z),
        at(lo.x, 0.0, hi.z),
    ];
    let inner = [
        at(ilo.x, 0.0, ilo.z),
        at(ihi.x, 0.0, ilo.z),
        at(ihi.x, 0.0, ihi.z),
        at(ilo.x, 0.0, ihi.z),
    ];
    let centre = Vec3::new(size.x / 2.0, 0.0, size.z / 2.0);
    for i in 0..4 {
        let j = (i + 1) % 4;
        let up = |p: Vec3, y: f32| Vec3::new(p.x, y, p.z);
        let side = ((outer[i] + outer[j]) / 2.0 - centre).normalize();
        // Outer wall, the rim, then the inner wall (facing the centre).
        quad(
            &mut positions,
            &mut faces,
            [
                up(outer[i], 0.0),
                up(outer[j], 0.0),
                up(outer[j], hi.y),
                up(outer[i], hi.y),
            ],
            side,
        );
        quad(
            &mut positions,
            &mut faces,
            [
                up(outer[i], hi.y),
                up(outer[j], hi.y),
                up(inner[j], hi.y),
                up(inner[i], hi.y),
            ],
            Vec3::Y,
        );
        quad(
            &mut positions,
            &mut faces,
            [
                up(inner[i], wall),
                up(inner[j], wall),
                up(inner[j], hi.y),
                up(inner[i], hi.y),
            ],
            -side,
        );
    }
    welded(positions, faces)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::features::{SHARP_ANGLE_DEG, sharp_edges};
    use crate::geometry::topology::TopologyReport;

    #[test]
    fn every_shape_is_closed_outward_and_creased() {
        let expected_volume = [
            2.8,
            0.8 * (1.2 * 0.25 + 0.25 * 0.75),
            0.6,
            1.0 * (1.5 * 0.4 + 1.0 * 0.4 + 0.5 * 0.4),
            0.0,
            0.0,
            1.6 * (0.96 + 0.3),
            0.8 - 0.84 * 0.72 * 0.84,
        ];
        for (k, (name, m)) in hard_surface_set().into_iter().enumerate() {
            let t = TopologyReport::of(&m);
            assert_eq!(
                (
                    t.boundary_edges,
                    t.non_manifold_edges,
                    t.inconsistent_winding_edges
                ),
                (0, 0, 0),
                "{name}: {t:?}"
            );
            let v = m.signed_volume();
            assert!(v > 0.0, "{name} faces inwards");
            if expected_volume[k] > 0.0 {
                assert!((v - expected_volume[k]).abs() < 1e-4, "{name}: volume {v}");
            }
            assert!(
                !sharp_edges(&m.positions, &m.faces, SHARP_ANGLE_DEG).is_empty(),
                "{name}"
            );
        }
        let table = &hard_surface_set()[5].1;
        assert_eq!(TopologyReport::of(table).components, 5);
        // The 12-sided cylinder: 12 sides and two caps of 10 triangles, 36 sharp edges (the
        // sides meet at 30 degrees exactly, which is not more than 30).
        let cyl = &hard_surface_set()[4].1;
        assert_eq!(cyl.faces.len(), 44);
        assert_eq!(
            sharp_edges(&cyl.positions, &cyl.faces, SHARP_ANGLE_DEG).len(),
            24
        );
    }
}

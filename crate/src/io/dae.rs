//! COLLADA (`.dae`), the XML interchange format (versions 1.4 and 1.5), as exported by
//! Blender, SketchUp, MeshLab and others for the robot descriptions of the training data.
//!
//! What is read: the scene named by `<scene><instance_visual_scene url="#...">` (without one,
//! the first `<visual_scene>`; with no visual scene at all, every `<geometry>` once,
//! untransformed). Its `<node>` tree is walked; each node's transform is the product, in
//! document order, of its `<matrix>` (16 numbers, row by row), `<translate>`, `<rotate>`
//! (axis x y z, angle in degrees), `<scale>` and `<lookat>` elements, composed with its
//! parents'. A node places the geometry of each `<instance_geometry url="#...">`, the source
//! geometry of each `<instance_controller>` (a `<skin>`'s geometry with its
//! `<bind_shape_matrix>` applied, which is the bind pose, or a `<morph>`'s base geometry),
//! and the nodes of each `<instance_node url="#...">` (typically from `<library_nodes>`).
//! All instances are merged into one mesh, the indices of each offset by the vertices before
//! it; where a transform mirrors (negative determinant) its triangles are reversed, so faces
//! keep winding counter-clockwise.
//!
//! A geometry's `<mesh>` gives its vertices through `<vertices><input semantic="POSITION"
//! source="#...">`: a `<source>` whose `<technique_common><accessor>` (`count`, `offset`,
//! `stride`, and the `<param>`s that pick the x, y, z components; params without a `name` are
//! skipped) reads a `<float_array>`. Primitives: `<triangles>`, `<polylist>` (`<vcount>` corners
//! per polygon), `<polygons>` (one `<p>` per polygon; of a `<ph>`, the outer `<p>`, holes
//! ignored), `<trifans>` and `<tristrips>`; polygons are fan-triangulated. Each corner of a
//! `<p>` holds one index per input (the count is the largest `offset` plus one); the `VERTEX`
//! input's index is the vertex. `<lines>` and `<linestrips>` are skipped; so are normals,
//! texture coordinates and materials (the mesh has no normals).
//!
//! Units and axes: positions are multiplied by `<asset><unit meter="...">` (default 1), so
//! the result is in metres. `<up_axis>` (default `Y_UP`) is converted to the glTF convention
//! (+Y up, right-handed): `Z_UP` maps (x, y, z) to (x, z, -y) and `X_UP` maps it to (-y, x, z),
//! both rotations. [`read_dae`] also returns the axis and unit the file declared.
//!
//! Leniencies the real files need: bytes after the closing `</COLLADA>` are ignored (a robot
//! file has the tail of a longer export after it), and a `#id` used inside a geometry is looked
//! up in that geometry first (an exporter reused the same ids in every geometry of a file).
//!
//! Errors: text that is not UTF-8 is `InvalidUtf8`; XML that does not parse (a DTD
//! included), a root other than `<COLLADA>`, a missing element or `#id`, a count that does not
//! match the numbers present, an accessor reading past its array or a node cycle are
//! `Malformed`, at the line of the element at fault; a `<p>` index past its vertices is
//! `IndexOutOfRange`; a used coordinate or transform entry that is NaN or infinite is
//! `NonFinite`; more than [`MAX_NODE_DEPTH`] nested nodes, more than [`MAX_NODE_VISITS`]
//! node instances, vertex and triangle counts over the [`Limits`], or XML the parser would
//! spend more than linear time or memory on (over [`MAX_XML_NODES`] nodes, over
//! [`MAX_XML_ATTRIBUTES`] attributes on one element, many namespace declarations) are
//! `TooLarge`; a `<skew>` transform, a URL to another file and a COLLADA version other than
//! 1.x are `Unsupported`.

use std::collections::HashMap;

use glam::{DMat4, DVec3, Vec3};
use roxmltree::{Document, Node, NodeId, ParsingOptions};

use super::{Format, Limits, Location, ReadError, check_limit, finish, malformed, vertex_limit};
use crate::geometry::mesh::Mesh;

const F: Format = Format::Dae;

/// The deepest node nesting accepted (a `<visual_scene>`'s own nodes are depth 1; each child
/// node or `<instance_node>` adds one).
pub const MAX_NODE_DEPTH: usize = 128;
/// Most node instances expanded while walking the scene (guards against `<instance_node>`s
/// that share subtrees and multiply exponentially).
pub const MAX_NODE_VISITS: u64 = 1 << 20;
/// How many controllers may be chained (a skin of a morph of ...) before the geometry.
const MAX_CONTROLLER_CHAIN: usize = 8;
/// Most XML nodes (elements, text, comments) in a document. The real robot files have at most
/// about 8,000 elements; the parsed tree takes some 80 bytes a node.
pub const MAX_XML_NODES: u32 = 1 << 20;
/// Most attributes on one element (the XML parser's duplicate check is quadratic in it; real
/// files have at most 3).
pub const MAX_XML_ATTRIBUTES: u64 = 64;
/// Most attributes in the whole document (real files have at most about 12,000).
const MAX_XML_ATTRIBUTES_TOTAL: u64 = 1 << 20;
/// Most namespace declarations (`xmlns`): the parser copies the namespaces in scope at each
/// element that declares one. Real files have 1.
const MAX_XML_NAMESPACES: u64 = 64;

/// The axis a COLLADA file declares as up (`<asset><up_axis>`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum UpAxis {
    /// `X_UP`: +X is up and -Y points right.
    X,
    /// `Y_UP`, the default and glTF's convention.
    Y,
    /// `Z_UP`, as Blender and most CAD tools export.
    Z,
}

/// What a COLLADA file declares about its frame, as read by [`read_dae`]. The mesh itself is
/// already converted to metres and +Y up.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DaeInfo {
    /// The declared up axis (`Y` when the file declares none).
    pub up_axis: UpAxis,
    /// Metres per unit of the file (`<unit meter>`, 1 when the file declares none).
    pub meter: f64,
}

/// A geometry read once, in its own coordinates.
struct Geometry {
    positions: Vec<DVec3>,
    faces: Vec<[u32; 3]>,
}

struct Reader<'a, 'input> {
    doc: &'a Document<'input>,
    ids: HashMap<&'a str, Node<'a, 'input>>,
    limits: &'a Limits,
    geometries: HashMap<NodeId, Geometry>,
    visits: u64,
    /// The `<instance_node>` targets on the current path (cycle detection).
    path: Vec<NodeId>,
    positions: Vec<Vec3>,
    faces: Vec<[u32; 3]>,
}

/// The child elements of `n` with local name `name`.
fn children<'a, 'input>(
    n: Node<'a, 'input>,
    name: &'static str,
) -> impl Iterator<Item = Node<'a, 'input>> {
    n.children()
        .filter(move |c| c.is_element() && c.tag_name().name() == name)
}

fn child<'a, 'input>(n: Node<'a, 'input>, name: &'static str) -> Option<Node<'a, 'input>> {
    children(n, name).next()
}

/// The text of an element (its first text child), or "".
fn text<'a>(n: Node<'a, '_>) -> &'a str {
    n.text().unwrap_or("")
}

impl<'a, 'input> Reader<'a, 'input> {
    /// The 1-based line where element `n` starts.
    fn at(&self, n: Node) -> Location {
        Location::Line(self.doc.text_pos_at(n.range().start).row as usize)
    }

    fn bad(&self, n: Node, message: impl Into<String>) -> ReadError {
        malformed(F, self.at(n), message)
    }

    /// The element a `#id` URL attribute of `n` names.
    fn target(&self, n: Node<'a, 'input>, attr: &str) -> Result<Node<'a, 'input>, ReadError> {
        self.target_in(n, attr, None)
    }

    /// The element a `#id` URL attribute of `n` names, looked for first inside `scope`: some
    /// exporters reuse the same ids in every geometry, and mean the one of the same geometry.
    fn target_in(
        &self,
        n: Node<'a, 'input>,
        attr: &str,
        scope: Option<Node<'a, 'input>>,
    ) -> Result<Node<'a, 'input>, ReadError> {
        let tag = n.tag_name().name();
        let Some(url) = n.attribute(attr) else {
            return Err(self.bad(n, format!("`<{tag}>` has no `{attr}`")));
        };
        let Some(id) = url.strip_prefix('#') else {
            return Err(ReadError::Unsupported {
                format: F,
                what: format!("`{url}` in `<{tag}>`: only `#id` references within the file"),
            });
        };
        scope
            .and_then(|s| {
                s.descendants()
                    .find(|d| d.is_element() && d.attribute("id") == Some(id))
            })
            .or_else(|| self.ids.get(id).copied())
            .ok_or_else(|| self.bad(n, format!("`<{tag}>` refers to `#{id}`, which is missing")))
    }

    /// `target_in`, which must be a `<name>` element.
    fn target_named(
        &self,
        n: Node<'a, 'input>,
        attr: &str,
        name: &str,
        scope: Option<Node<'a, 'input>>,
    ) -> Result<Node<'a, 'input>, ReadError> {
        let t = self.target_in(n, attr, scope)?;
        if t.tag_name().name() != name {
            return Err(self.bad(
                n,
                format!(
                    "`{}` names a `<{}>`, not a `<{name}>`",
                    n.attribute(attr).unwrap_or(""),
                    t.tag_name().name()
                ),
            ));
        }
        Ok(t)
    }

    /// A non-negative integer attribute; `default` when absent.
    fn uint_attr(&self, n: Node, attr: &str, default: Option<u64>) -> Result<u64, ReadError> {
        match n.attribute(attr) {
            Some(v) => v.trim().parse().map_err(|_| {
                self.bad(
                    n,
                    format!("`{attr}=\"{v}\"` is not a valid non-negative integer"),
                )
            }),
            None => default
                .ok_or_else(|| self.bad(n, format!("`<{}>` has no `{attr}`", n.tag_name().name()))),
        }
    }

    /// The numbers of an element holding exactly `N` finite ones (a transform).
    fn numbers<const N: usize>(&self, n: Node) -> Result<[f64; N], ReadError> {
        let mut out = [0f64; N];
        let mut k = 0;
        for t in text(n).split_ascii_whitespace() {
            let v: f64 = t
                .parse()
                .map_err(|_| self.bad(n, format!("`{t}` is not a number")))?;
            if k == N {
                k += 1;
                break;
            }
            out[k] = v;
            k += 1;
        }
        if k != N {
            return Err(self.bad(
                n,
                format!("`<{}>` needs exactly {N} numbers", n.tag_name().name()),
            ));
        }
        if out.iter().any(|v| !v.is_finite()) {
            return Err(ReadError::NonFinite {
                format: F,
                location: self.at(n),
            });
        }
        Ok(out)
    }

    /// The local transform of a `<node>`: its transform elements multiplied in order.
    fn local_transform(&self, node: Node) -> Result<DMat4, ReadError> {
        let mut m = DMat4::IDENTITY;
        for c in node.children().filter(|c| c.is_element()) {
            let t = match c.tag_name().name() {
                "matrix" => DMat4::from_cols_array(&self.numbers::<16>(c)?).transpose(),
                "translate" => DMat4::from_translation(DVec3::from_array(self.numbers(c)?)),
                "scale" => DMat4::from_scale(DVec3::from_array(self.numbers(c)?)),
                "rotate" => {
                    let [x, y, z, deg] = self.numbers(c)?;
                    let axis = DVec3::new(x, y, z);
                    if axis.length_squared() < 1e-24 {
                        DMat4::IDENTITY // no axis: no rotation
                    } else {
                        DMat4::from_axis_angle(axis.normalize(), deg.to_radians())
                    }
                }
                "lookat" => {
                    let v: [f64; 9] = self.numbers(c)?;
                    let eye = DVec3::new(v[0], v[1], v[2]);
                    let at = DVec3::new(v[3], v[4], v[5]);
                    let up = DVec3::new(v[6], v[7], v[8]);
                    // The camera-to-parent matrix: right, up, backward, eye as columns.
                    let f = (at - eye).normalize();
                    let r = f.cross(up).normalize();
                    let u = r.cross(f);
                    let m = DMat4::from_cols(
                        r.extend(0.0),
                        u.extend(0.0),
                        (-f).extend(0.0),
                        eye.extend(1.0),
                    );
                    if !m.is_finite() {
                        return Err(self.bad(c, "degenerate `<lookat>`"));
                    }
                    m
                }
                "skew" => {
                    return Err(ReadError::Unsupported {
                        format: F,
                        what: "`<skew>` transforms".into(),
                    });
                }
                _ => continue,
            };
            m *= t;
        }
        if !m.is_finite() {
            return Err(ReadError::NonFinite {
                format: F,
                location: self.at(node),
            });
        }
        Ok(m)
    }

    /// Walks a `<node>` placed by `parent`.
    fn node(
        &mut self,
        node: Node<'a, 'input>,
        parent: DMat4,
        depth: usize,
    ) -> Result<(), ReadError> {
        if depth > MAX_NODE_DEPTH {
            return Err(ReadError::TooLarge {
                format: F,
                what: "node nesting depth",
                value: depth as u64,
                limit: MAX_NODE_DEPTH as u64,
            });
        }
        self.visits += 1;
        check_limit(F, "node instance count", self.visits, MAX_NODE_VISITS)?;
        let world = parent * self.local_transform(node)?;
        for c in node.children().filter(|c| c.is_element()) {
            match c.tag_name().name() {
                "node" => self.node(c, world, depth + 1)?,
                "instance_node" => {
                    let target = self.target_named(c, "url", "node", None)?;
                    if self.path.contains(&target.id()) {
                        return Err(self.bad(c, "`<instance_node>` makes a cycle"));
                    }
                    self.path.push(target.id());
                    self.node(target, world, depth + 1)?;
                    self.path.pop();
                }
                "instance_geometry" => {
                    let g = self.target_named(c, "url", "geometry", None)?;
                    self.instance(g, world, c)?;
                }
                "instance_controller" => {
                    let (g, bind) = self.controller_geometry(c)?;
                    self.instance(g, world * bind, c)?;
                }
                _ => {}
            }
        }
        Ok(())
    }

    /// The geometry an `<instance_controller>` deforms, and the bind-shape matrix to apply.
    fn controller_geometry(
        &self,
        inst: Node<'a, 'input>,
    ) -> Result<(Node<'a, 'input>, DMat4), ReadError> {
        let mut bind = DMat4::IDENTITY;
        let mut c = self.target_named(inst, "url", "controller", None)?;
        for _ in 0..MAX_CONTROLLER_CHAIN {
            let (body, attr) = match (child(c, "skin"), child(c, "morph")) {
                (Some(s), _) => {
                    if let Some(b) = child(s, "bind_shape_matrix") {
                        bind *= DMat4::from_cols_array(&self.numbers::<16>(b)?).transpose();
                    }
                    (s, "source")
                }
                (None, Some(m)) => (m, "source"),
                (None, None) => {
                    return Err(self.bad(c, "`<controller>` has no `<skin>` or `<morph>`"));
                }
            };
            let t = self.target(body, attr)?;
            match t.tag_name().name() {
                "geometry" => return Ok((t, bind)),
                "controller" => c = t,
                other => {
                    return Err(self.bad(
                        body,
                        format!("the controller's source is a `<{other}>`, not a geometry"),
                    ));
                }
            }
        }
        Err(self.bad(inst, "controllers chained too deep (or in a cycle)"))
    }

    /// Adds one instance of geometry `g` placed by `m`; `at` is the instancing element.
    fn instance(&mut self, g: Node<'a, 'input>, m: DMat4, at: Node) -> Result<(), ReadError> {
        if !self.geometries.contains_key(&g.id()) {
            let geometry = self.geometry(g)?;
            self.geometries.insert(g.id(), geometry);
        }
        let geometry = &self.geometries[&g.id()];
        let base = self.positions.len();
        check_limit(
            F,
            "vertex count",
            (base as u64).saturating_add(geometry.positions.len() as u64),
            vertex_limit(self.limits),
        )?;
        check_limit(
            F,
            "triangle count",
            (self.faces.len() as u64).saturating_add(geometry.faces.len() as u64),
            self.limits.max_faces as u64,
        )?;
        self.positions.reserve(geometry.positions.len());
        for p in &geometry.positions {
            let w = m.transform_point3(*p).as_vec3();
            if !w.is_finite() {
                return Err(ReadError::NonFinite {
                    format: F,
                    location: Location::Line(self.doc.text_pos_at(at.range().start).row as usize),
                });
            }
            self.positions.push(w);
        }
        let flip = m.determinant() < 0.0;
        let b = base as u32;
        self.faces.extend(geometry.faces.iter().map(|&[i, j, k]| {
            if flip {
                [b + i, b + k, b + j]
            } else {
                [b + i, b + j, b + k]
            }
        }));
        Ok(())
    }

    /// Reads a `<geometry>` in its own coordinates.
    fn geometry(&self, g: Node<'a, 'input>) -> Result<Geometry, ReadError> {
        let mut out = Geometry {
            positions: Vec::new(),
            faces: Vec::new(),
        };
        // Splines, B-reps and convex meshes carry no triangles we read.
        let Some(mesh) = child(g, "mesh") else {
            return Ok(out);
        };
        let Some(vertices) = child(mesh, "vertices") else {
            return Err(self.bad(mesh, "`<mesh>` has no `<vertices>`"));
        };
        let Some(input) =
            children(vertices, "input").find(|i| i.attribute("semantic") == Some("POSITION"))
        else {
            return Err(self.bad(vertices, "`<vertices>` has no POSITION input"));
        };
        let source = self.target_named(input, "source", "source", Some(g))?;
        out.positions = self.positions_of(source, g)?;
        let count = out.positions.len();
        for prim in mesh.children().filter(|c| c.is_element()) {
            let kind = prim.tag_name().name();
            if !matches!(
                kind,
                "triangles" | "polylist" | "polygons" | "trifans" | "tristrips"
            ) {
                continue; // lines, linestrips, source, vertices, extra
            }
            self.primitive(prim, count, &mut out.faces)?;
        }
        Ok(out)
    }

    /// The x, y, z of every element of a position `<source>`.
    fn positions_of(
        &self,
        source: Node<'a, 'input>,
        g: Node<'a, 'input>,
    ) -> Result<Vec<DVec3>, ReadError> {
        let Some(accessor) = child(source, "technique_common").and_then(|t| child(t, "accessor"))
        else {
            return Err(self.bad(
                source,
                "position `<source>` has no `<technique_common><accessor>`",
            ));
        };
        let count = self.uint_attr(accessor, "count", None)?;
        let offset = self.uint_attr(accessor, "offset", Some(0))?;
        let stride = self.uint_attr(accessor, "stride", Some(1))?;
        check_limit(F, "vertex count", count, vertex_limit(self.limits))?;
        // The components: the params with a name, by position; no params means x, y, z first.
        let params: Vec<Node> = children(accessor, "param").collect();
        let picked: Vec<u64> = if params.is_empty() {
            vec![0, 1, 2]
        } else {
            params
                .iter()
                .enumerate()
                .filter(|(_, p)| p.attribute("name").is_some())
                .map(|(k, _)| k as u64)
                .take(3)
                .collect()
        };
        if picked.len() < 3 {
            return Err(self.bad(accessor, "position accessor has fewer than 3 named params"));
        }
        if stride < params.len().max(3) as u64 {
            return Err(self.bad(
                accessor,
                format!(
                    "accessor stride {stride} is smaller than its {} components",
                    params.len().max(3)
                ),
            ));
        }
        let array = self.target_named(accessor, "source", "float_array", Some(g))?;
        if count == 0 {
            return Ok(Vec::new());
        }
        // The values needed: offset + (count - 1) * stride + the last component + 1.
        let needed = (count - 1)
            .checked_mul(stride)
            .and_then(|v| v.checked_add(offset))
            .and_then(|v| v.checked_add(picked[2] + 1))
            .unwrap_or(u64::MAX);
        let values = self.float_array(array)?;
        if needed > values.len() as u64 {
            return Err(self.bad(
                accessor,
                format!(
                    "accessor reads {needed} values of an array of {}",
                    values.len()
                ),
            ));
        }
        let mut out = Vec::with_capacity(count as usize);
        for e in 0..count {
            let start = (offset + e * stride) as usize;
            let v = DVec3::new(
                values[start + picked[0] as usize],
                values[start + picked[1] as usize],
                values[start + picked[2] as usize],
            );
            if !v.is_finite() {
                return Err(ReadError::NonFinite {
                    format: F,
                    location: self.at(array),
                });
            }
            out.push(v);
        }
        Ok(out)
    }

    /// The numbers of a `<float_array>`, which must hold exactly its `count`.
    fn float_array(&self, array: Node) -> Result<Vec<f64>, ReadError> {
        let count = self.uint_attr(array, "count", None)?;
        let body = text(array);
        // A number takes at least two bytes with its separator: no more can be present.
        let mut values = Vec::with_capacity((count as usize).min(body.len() / 2 + 1));
        for t in body.split_ascii_whitespace() {
            let v: f64 = t
                .parse()
                .map_err(|_| self.bad(array, format!("`{t}` is not a number")))?;
            values.push(v);
        }
        if values.len() as u64 != count {
            return Err(self.bad(
                array,
                format!(
                    "`<float_array>` holds {} numbers but its count is {count}",
                    values.len()
                ),
            ));
        }
        Ok(values)
    }

    /// Triangulates one primitive element onto `faces`; `count` is the vertex count.
    fn primitive(
        &self,
        prim: Node,
        count: usize,
        faces: &mut Vec<[u32; 3]>,
    ) -> Result<(), ReadError> {
        let kind = prim.tag_name().name();
        // Each corner holds one index per input offset.
        let mut slots = 0u64;
        let mut vertex_offset = None;
        for i in children(prim, "input") {
            let offset = self.uint_attr(i, "offset", None)?;
            slots = slots.max(offset.saturating_add(1));
            if i.attribute("semantic") == Some("VERTEX") {
                vertex_offset = Some(offset);
            }
        }
        let Some(vertex_offset) = vertex_offset else {
            return Err(self.bad(prim, format!("`<{kind}>` has no VERTEX input")));
        };
        if slots > 1 << 16 {
            return Err(self.bad(prim, format!("input offset {} is too large", slots - 1)));
        }
        let declared = self.uint_attr(prim, "count", None)?;
        let mut corners: Vec<u32> = Vec::new();
        match kind {
            "triangles" => {
                let p = child(prim, "p");
                self.indices(p, slots, vertex_offset, count, &mut corners)?;
                let n = corners.len() as u64;
                if Some(n) != declared.checked_mul(3) {
                    return Err(self.bad(
                        p.unwrap_or(prim),
                        format!("{n} corners for {declared} triangles"),
                    ));
                }
                check_limit(
                    F,
                    "triangle count",
                    (faces.len() as u64).saturating_add(declared),
                    self.limits.max_faces as u64,
                )?;
                faces.extend(corners.chunks_exact(3).map(|c| [c[0], c[1], c[2]]));
            }
            "polylist" => {
                let p = child(prim, "p");
                self.indices(p, slots, vertex_offset, count, &mut corners)?;
                let vcount = child(prim, "vcount");
                let mut polygons = 0u64;
                let mut used = 0usize;
                for t in vcount.map(text).unwrap_or("").split_ascii_whitespace() {
                    let at = vcount.unwrap_or(prim);
                    let n: usize = t
                        .parse()
                        .map_err(|_| self.bad(at, format!("`{t}` is not a valid corner count")))?;
                    if n > corners.len() - used {
                        return Err(self.bad(
                            at,
                            format!(
                                "`<vcount>` needs more than the {} corners of `<p>`",
                                corners.len()
                            ),
                        ));
                    }
                    super::push_fan(F, &corners[used..used + n], faces, self.limits)?;
                    used += n;
                    polygons += 1;
                }
                if polygons != declared || used != corners.len() {
                    return Err(self.bad(
                        prim,
                        format!(
                            "{polygons} polygons of {used} corners in `<vcount>`, {declared} polygons of {} corners declared",
                            corners.len()
                        ),
                    ));
                }
            }
            _ => {
                // polygons, trifans, tristrips: one `<p>` per polygon, fan or strip.
                let mut n = 0u64;
                for c in prim.children().filter(|c| c.is_element()) {
                    let p = match c.tag_name().name() {
                        "p" => c,
                        "ph" if kind == "polygons" => match child(c, "p") {
                            Some(p) => p,
                            None => return Err(self.bad(c, "`<ph>` has no `<p>`")),
                        },
                        _ => continue,
                    };
                    n += 1;
                    corners.clear();
                    self.indices(Some(p), slots, vertex_offset, count, &mut corners)?;
                    if kind == "tristrips" {
                        for k in 2..corners.len() {
                            let (a, b, c) = (corners[k - 2], corners[k - 1], corners[k]);
                            let tri = if k % 2 == 0 { [a, b, c] } else { [b, a, c] };
                            super::push_fan(F, &tri, faces, self.limits)?;
                        }
                    } else {
                        super::push_fan(F, &corners, faces, self.limits)?;
                    }
                }
                if n != declared {
                    return Err(self.bad(prim, format!("{n} `<p>` elements, {declared} declared")));
                }
            }
        }
        Ok(())
    }

    /// Reads the vertex indices of a `<p>` (every `slots`-th number from `offset`) onto `out`.
    /// Every number must be an index; the count must be a whole number of corners.
    fn indices(
        &self,
        p: Option<Node>,
        slots: u64,
        offset: u64,
        count: usize,
        out: &mut Vec<u32>,
    ) -> Result<(), ReadError> {
        let Some(p) = p else {
            return Ok(());
        };
        let body = text(p);
        out.reserve(body.len() / 2 / slots as usize);
        let mut k = 0u64;
        for t in body.split_ascii_whitespace() {
            let i: u64 = t
                .parse()
                .map_err(|_| self.bad(p, format!("`{t}` is not a valid index")))?;
            if k % slots == offset {
                if i >= count as u64 {
                    return Err(ReadError::IndexOutOfRange {
                        format: F,
                        location: self.at(p),
                        what: "vertices",
                        index: i64::try_from(i).unwrap_or(i64::MAX),
                        count,
                    });
                }
                out.push(i as u32);
            }
            k += 1;
        }
        if !k.is_multiple_of(slots) {
            return Err(self.bad(
                p,
                format!("{k} indices are not a whole number of {slots}-index corners"),
            ));
        }
        Ok(())
    }
}

fn xml_error(e: &roxmltree::Error) -> ReadError {
    if let roxmltree::Error::NodesLimitReached = e {
        return ReadError::TooLarge {
            format: F,
            what: "XML node count",
            value: MAX_XML_NODES as u64 + 1,
            limit: MAX_XML_NODES as u64,
        };
    }
    malformed(
        F,
        Location::Line(e.pos().row as usize),
        format!("not valid XML: {e}"),
    )
}

/// Bounds what the XML parser would spend more than linear time or memory on, in one pass
/// over the text before parsing: attributes per element and in all, and namespace
/// declarations. A tag's attributes are counted by its `=` signs outside quotes up to its `>`
/// (an attribute value cannot hold `<`, so a tag also ends at the next `<`).
fn check_markup(xml: &str) -> Result<(), ReadError> {
    let b = xml.as_bytes();
    let mut total = 0u64;
    let mut i = 0;
    while let Some(off) = b[i..].iter().position(|&c| c == b'<') {
        let mut j = i + off + 1;
        let mut quote = 0u8;
        let mut attributes = 0u64;
        while j < b.len() {
            let c = b[j];
            if c == b'<' {
                break;
            }
            if quote != 0 {
                if c == quote {
                    quote = 0;
                }
            } else {
                match c {
                    b'"' | b'\'' => quote = c,
                    b'=' => attributes += 1,
                    b'>' => break,
                    _ => {}
                }
            }
            j += 1;
        }
        check_limit(
            F,
            "attributes of one XML element",
            attributes,
            MAX_XML_ATTRIBUTES,
        )?;
        total += attributes;
        i = j;
    }
    check_limit(F, "XML attribute count", total, MAX_XML_ATTRIBUTES_TOTAL)?;
    let namespaces = xml.matches("xmlns").count() as u64;
    check_limit(
        F,
        "XML namespace declarations",
        namespaces,
        MAX_XML_NAMESPACES,
    )
}

/// Reads a COLLADA document; the mesh is in metres and +Y up, and the [`DaeInfo`] says what
/// the file declared.
pub fn read_dae(bytes: &[u8], limits: &Limits) -> Result<(Mesh, DaeInfo), ReadError> {
    check_limit(
        F,
        "file size in bytes",
        bytes.len() as u64,
        limits.max_bytes,
    )?;
    let xml = super::utf8(F, bytes)?;
    let xml = xml.strip_prefix('\u{feff}').unwrap_or(xml);
    if xml.trim().is_empty() {
        return Err(ReadError::Empty { format: F });
    }
    check_markup(xml)?;
    let options = || ParsingOptions {
        allow_dtd: false,
        nodes_limit: MAX_XML_NODES,
        ..ParsingOptions::default()
    };
    let doc = match Document::parse_with_options(xml, options()) {
        Ok(d) => d,
        Err(e) => {
            // Bytes after the closing `</COLLADA>` (a shorter export written over a longer
            // one, in a real robot file) are ignored.
            const END: &str = "</COLLADA>";
            let cut = xml.find(END).map(|i| &xml[..i + END.len()]);
            match cut.filter(|c| c.len() < xml.trim_end().len()) {
                Some(c) => Document::parse_with_options(c, options()).map_err(|_| xml_error(&e))?,
                None => return Err(xml_error(&e)),
            }
        }
    };
    let root = doc.root_element();
    if root.tag_name().name() != "COLLADA" {
        return Err(malformed(
            F,
            Location::Line(doc.text_pos_at(root.range().start).row as usize),
            format!(
                "the root element is `<{}>`, not `<COLLADA>`",
                root.tag_name().name()
            ),
        ));
    }
    if let Some(v) = root.attribute("version")
        && !v.starts_with("1.")
    {
        return Err(ReadError::Unsupported {
            format: F,
            what: format!("version {v} (1.4 and 1.5 are known)"),
        });
    }
    let mut ids = HashMap::new();
    for n in doc.descendants().filter(|n| n.is_element()) {
        if let Some(id) = n.attribute("id") {
            ids.entry(id).or_insert(n);
        }
    }
    let mut r = Reader {
        doc: &doc,
        ids,
        limits,
        geometries: HashMap::new(),
        visits: 0,
        path: Vec::new(),
        positions: Vec::new(),
        faces: Vec::new(),
    };

    let mut info = DaeInfo {
        up_axis: UpAxis::Y,
        meter: 1.0,
    };
    if let Some(asset) = child(root, "asset") {
        if let Some(u) = child(asset, "up_axis") {
            info.up_axis = match text(u).trim() {
                "X_UP" => UpAxis::X,
                "Y_UP" => UpAxis::Y,
                "Z_UP" => UpAxis::Z,
                other => return Err(r.bad(u, format!("unknown up axis `{other}`"))),
            };
        }
        if let Some(u) = child(asset, "unit")
            && let Some(m) = u.attribute("meter")
        {
            info.meter = match m.trim().parse::<f64>() {
                Ok(v) if v.is_finite() && v > 0.0 => v,
                _ => return Err(r.bad(u, format!("`meter=\"{m}\"` is not a positive number"))),
            };
        }
    }
    let up = match info.up_axis {
        UpAxis::Y => DMat4::IDENTITY,
        // (x, y, z) -> (x, z, -y)
        UpAxis::Z => DMat4::from_cols(
            glam::DVec4::X,
            glam::DVec4::NEG_Z,
            glam::DVec4::Y,
            glam::DVec4::W,
        ),
        // (x, y, z) -> (-y, x, z)
        UpAxis::X => DMat4::from_cols(
            glam::DVec4::Y,
            glam::DVec4::NEG_X,
            glam::DVec4::Z,
            glam::DVec4::W,
        ),
    };
    let frame = up * DMat4::from_scale(DVec3::splat(info.meter));

    let scene = match child(root, "scene").and_then(|s| child(s, "instance_visual_scene")) {
        Some(i) => Some(r.target_named(i, "url", "visual_scene", None)?),
        None => child(root, "library_visual_scenes").and_then(|l| child(l, "visual_scene")),
    };
    match scene {
        Some(scene) => {
            for n in children(scene, "node") {
                r.node(n, frame, 1)?;
            }
        }
        None => {
            for lib in children(root, "library_geometries") {
                for g in children(lib, "geometry") {
                    r.instance(g, frame, g)?;
                }
            }
        }
    }
    let mesh = finish(F, r.positions, Vec::new(), r.faces)?;
    Ok((mesh, info))
}

pub(super) fn read(bytes: &[u8], limits: &Limits) -> Result<Mesh, ReadError> {
    read_dae(bytes, limits).map(|(m, _)| m)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn doc(up: &str, unit: &str, nodes: &str) -> String {
        format!(
            r##"<?xml version="1.0" encoding="utf-8"?>
<COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1">
  <asset><unit name="cm" meter="{unit}"/><up_axis>{up}</up_axis></asset>
  <library_geometries>
    <geometry id="g"><mesh>
      <source id="g-pos">
        <float_array id="g-arr" count="12">0 0 0 1 0 0 1 1 0 0 1 0</float_array>
        <technique_common><accessor source="#g-arr" count="4" stride="3">
          <param name="X" type="float"/><param name="Y" type="float"/><param name="Z" type="float"/>
        </accessor></technique_common>
      </source>
      <vertices id="g-v"><input semantic="POSITION" source="#g-pos"/></vertices>
      <polylist count="1"><input semantic="VERTEX" source="#g-v" offset="0"/>
        <input semantic="NORMAL" source="#g-v" offset="1"/>
        <vcount>4</vcount><p>0 0 1 0 2 0 3 0</p></polylist></mesh>
    </geometry>
  </library_geometries>
  <library_nodes><node id="lib"><translate>0 0 5</translate><instance_geometry url="#g"/></node></library_nodes>
  <library_visual_scenes><visual_scene id="s">{nodes}</visual_scene></library_visual_scenes>
  <scene><instance_visual_scene url="#s"/></scene>
</COLLADA>"##
        )
    }

    #[test]
    fn units_axes_and_instances() {
        let s = doc(
            "Z_UP",
            "0.01",
            r##"<node><translate>100 0 0</translate><instance_node url="#lib"/></node>
               <node><scale>-1 1 1</scale><instance_geometry url="#g"/></node>"##,
        );
        let (m, info) = read_dae(s.as_bytes(), &Limits::default()).unwrap();
        assert_eq!(
            info,
            DaeInfo {
                up_axis: UpAxis::Z,
                meter: 0.01
            }
        );
        assert_eq!(m.positions.len(), 8);
        // (100, 0, 5) cm, Z up -> (1, 0.05, 0) m, Y up.
        assert!((m.positions[0] - Vec3::new(1.0, 0.05, 0.0)).length() < 1e-6);
        // (1, 1, 0) cm -> (0.01, 0, -0.01) m.
        assert!((m.positions[2] - Vec3::new(1.01, 0.05, -0.01)).length() < 1e-6);
        assert_eq!(m.faces[..2], [[0, 1, 2], [0, 2, 3]]);
        // The mirrored instance is re-wound.
        assert_eq!(m.faces[2..], [[4, 6, 5], [4, 7, 6]]);
    }
}

//! PLY (Stanford polygon file), ascii, binary_little_endian and binary_big_endian.
//!
//! The `vertex` element gives `x y z` (and `nx ny nz` when all three are present); any other
//! vertex property, scalar or list, is skipped. The `face` element's `vertex_indices` (or
//! `vertex_index`) list, of any count and index type, gives polygons, fan-triangulated; other
//! face properties and other elements are skipped. A PLY without faces is a point cloud.
//!
//! Before anything is allocated, each element count is checked against [`Limits`] and (for
//! binary files) against the bytes left: an element needs at least the size of its scalar
//! properties plus its list counts.

use glam::Vec3;

use super::{
    Format, Limits, Location, ReadError, check_limit, finish, malformed, push_fan, vertex_limit,
};
use crate::geometry::mesh::Mesh;

const F: Format = Format::Ply;
/// Longest header accepted.
pub const MAX_HEADER_BYTES: usize = 64 * 1024;

#[derive(Clone, Copy, Debug, PartialEq)]
enum Scalar {
    I8,
    U8,
    I16,
    U16,
    I32,
    U32,
    F32,
    F64,
}

impl Scalar {
    fn parse(s: &str) -> Option<Scalar> {
        Some(match s {
            "char" | "int8" => Scalar::I8,
            "uchar" | "uint8" => Scalar::U8,
            "short" | "int16" => Scalar::I16,
            "ushort" | "uint16" => Scalar::U16,
            "int" | "int32" => Scalar::I32,
            "uint" | "uint32" => Scalar::U32,
            "float" | "float32" => Scalar::F32,
            "double" | "float64" => Scalar::F64,
            _ => return None,
        })
    }
    fn size(self) -> usize {
        match self {
            Scalar::I8 | Scalar::U8 => 1,
            Scalar::I16 | Scalar::U16 => 2,
            Scalar::I32 | Scalar::U32 | Scalar::F32 => 4,
            Scalar::F64 => 8,
        }
    }
    fn is_float(self) -> bool {
        matches!(self, Scalar::F32 | Scalar::F64)
    }
}

#[derive(Debug)]
enum Property {
    Scalar(Scalar, String),
    List(Scalar, Scalar, String),
}

impl Property {
    fn name(&self) -> &str {
        match self {
            Property::Scalar(_, n) | Property::List(_, _, n) => n,
        }
    }
}

#[derive(Debug)]
struct Element {
    name: String,
    count: u64,
    props: Vec<Property>,
}

#[derive(Clone, Copy, Debug, PartialEq)]
enum Encoding {
    Ascii,
    Le,
    Be,
}

struct Header {
    encoding: Encoding,
    elements: Vec<Element>,
    /// Offset of the first data byte.
    data_start: usize,
}

fn parse_header(bytes: &[u8]) -> Result<Header, ReadError> {
    if !(bytes.starts_with(b"ply\n") || bytes.starts_with(b"ply\r")) {
        return Err(malformed(F, Location::Byte(0), "missing `ply` magic line"));
    }
    let window = &bytes[..bytes.len().min(MAX_HEADER_BYTES)];
    let end = find(window, b"end_header").ok_or_else(|| {
        if bytes.len() > MAX_HEADER_BYTES {
            malformed(
                F,
                Location::Unknown,
                format!("no `end_header` in the first {MAX_HEADER_BYTES} bytes"),
            )
        } else {
            malformed(F, Location::Unknown, "no `end_header` line")
        }
    })?;
    let mut data_start = end + b"end_header".len();
    // The header line ends with "\n" or "\r\n" (or, leniently, "\r").
    match bytes.get(data_start) {
        Some(b'\r') => {
            data_start += 1;
            if bytes.get(data_start) == Some(&b'\n') {
                data_start += 1;
            }
        }
        Some(b'\n') => data_start += 1,
        None => {}
        Some(_) => {
            return Err(malformed(
                F,
                Location::Unknown,
                "`end_header` is not followed by a newline",
            ));
        }
    }
    let text = super::utf8(F, &bytes[..end])?;
    let mut encoding = None;
    let mut elements: Vec<Element> = Vec::new();
    for (i, line) in text.lines().enumerate() {
        let loc = || Location::Line(i + 1);
        let mut t = line.split_ascii_whitespace();
        match t.next() {
            None | Some("ply" | "comment" | "obj_info") => {}
            Some("format") => {
                if encoding.is_some() {
                    return Err(malformed(F, loc(), "two `format` lines"));
                }
                encoding = Some(match t.next() {
                    Some("ascii") => Encoding::Ascii,
                    Some("binary_little_endian") => Encoding::Le,
                    Some("binary_big_endian") => Encoding::Be,
                    other => {
                        return Err(malformed(
                            F,
                            loc(),
                            format!("unknown format `{}`", other.unwrap_or("")),
                        ));
                    }
                });
                if t.next() != Some("1.0") {
                    return Err(ReadError::Unsupported {
                        format: F,
                        what: "PLY version other than 1.0".into(),
                    });
                }
            }
            Some("element") => {
                let (Some(name), Some(count)) = (t.next(), t.next()) else {
                    return Err(malformed(F, loc(), "`element` needs a name and a count"));
                };
                let count: u64 = count
                    .parse()
                    .map_err(|_| malformed(F, loc(), format!("bad element count `{count}`")))?;
                elements.push(Element {
                    name: name.to_string(),
                    count,
                    props: Vec::new(),
                });
            }
            Some("property") => {
                let el = elements
                    .last_mut()
                    .ok_or_else(|| malformed(F, loc(), "`property` before any `element`"))?;
                let bad = || malformed(F, loc(), format!("bad property line `{line}`"));
                let prop = match t.next() {
                    Some("list") => {
                        let c = t.next().and_then(Scalar::parse).ok_or_else(bad)?;
                        let v = t.next().and_then(Scalar::parse).ok_or_else(bad)?;
                        if c.is_float() {
                            return Err(malformed(
                                F,
                                loc(),
                                "a list count must be an integer type",
                            ));
                        }
                        Property::List(c, v, t.next().ok_or_else(bad)?.to_string())
                    }
                    Some(ty) => {
                        let s = Scalar::parse(ty).ok_or_else(bad)?;
                        Property::Scalar(s, t.next().ok_or_else(bad)?.to_string())
                    }
                    None => return Err(bad()),
                };
                el.props.push(prop);
            }
            Some(other) => {
                return Err(malformed(
                    F,
                    loc(),
                    format!("unknown header keyword `{other}`"),
                ));
            }
        }
    }
    let encoding = encoding.ok_or_else(|| malformed(F, Location::Unknown, "no `format` line"))?;
    Ok(Header {
        encoding,
        elements,
        data_start,
    })
}

fn find(hay: &[u8], needle: &[u8]) -> Option<usize> {
    hay.windows(needle.len()).position(|w| w == needle)
}

/// Reads values one at a time from the body.
enum Body<'a> {
    Ascii {
        tokens: AsciiTokens<'a>,
        line: usize,
        /// Length of the whole input, reported when the values run out.
        end: u64,
    },
    Bin {
        data: &'a [u8],
        pos: usize,
        big: bool,
    },
}

struct AsciiTokens<'a> {
    text: &'a str,
    pos: usize,
    line: usize,
}

impl<'a> Iterator for AsciiTokens<'a> {
    /// (token, 1-based line).
    type Item = (&'a str, usize);
    fn next(&mut self) -> Option<Self::Item> {
        let b = self.text.as_bytes();
        while self.pos < b.len() && b[self.pos].is_ascii_whitespace() {
            if b[self.pos] == b'\n' {
                self.line += 1;
            }
            self.pos += 1;
        }
        if self.pos >= b.len() {
            return None;
        }
        let start = self.pos;
        while self.pos < b.len() && !b[self.pos].is_ascii_whitespace() {
            self.pos += 1;
        }
        self.text.get(start..self.pos).map(|t| (t, self.line))
    }
    fn size_hint(&self) -> (usize, Option<usize>) {
        (0, Some(self.text.len().saturating_sub(self.pos)))
    }
}

impl Body<'_> {
    fn location(&mut self) -> Location {
        match self {
            Body::Ascii { line, .. } => Location::Line(*line),
            Body::Bin { pos, .. } => Location::Byte(*pos as u64),
        }
    }

    fn value(&mut self, ty: Scalar) -> Result<f64, ReadError> {
        match self {
            Body::Ascii { tokens, line, end } => {
                let (tok, l) = tokens.next().ok_or(ReadError::Truncated {
                    format: F,
                    offset: *end,
                    expected: 1,
                })?;
                *line = l;
                if ty.is_float() {
                    tok.parse::<f64>().map_err(|_| {
                        malformed(F, Location::Line(l), format!("`{tok}` is not a number"))
                    })
                } else {
                    let v: i64 = tok.parse().map_err(|_| {
                        malformed(F, Location::Line(l), format!("`{tok}` is not an integer"))
                    })?;
                    Ok(v as f64)
                }
            }
            Body::Bin { data, pos, big } => {
                let n = ty.size();
                let Some(s) = data.get(*pos..pos.saturating_add(n)) else {
                    return Err(ReadError::Truncated {
                        format: F,
                        offset: *pos as u64,
                        expected: (*pos + n - data.len()) as u64,
                    });
                };
                *pos += n;
                let mut a = [0u8; 8];
                a[..n].copy_from_slice(s);
                if *big {
                    a[..n].reverse();
                }
                Ok(match ty {
                    Scalar::I8 => a[0] as i8 as f64,
                    Scalar::U8 => a[0] as f64,
                    Scalar::I16 => i16::from_le_bytes([a[0], a[1]]) as f64,
                    Scalar::U16 => u16::from_le_bytes([a[0], a[1]]) as f64,
                    Scalar::I32 => i32::from_le_bytes([a[0], a[1], a[2], a[3]]) as f64,
                    Scalar::U32 => u32::from_le_bytes([a[0], a[1], a[2], a[3]]) as f64,
                    Scalar::F32 => f32::from_le_bytes([a[0], a[1], a[2], a[3]]) as f64,
                    Scalar::F64 => f64::from_le_bytes(a),
                })
            }
        }
    }

    /// Reads a list count and checks it is non-negative and fits in what is left.
    fn list_len(&mut self, count_ty: Scalar, item_ty: Scalar) -> Result<usize, ReadError> {
        let loc = self.location();
        let n = self.value(count_ty)?;
        if n < 0.0 {
            return Err(malformed(
                F,
                self.location(),
                format!("negative list length {n}"),
            ));
        }
        let n = n as u64;
        let left = match self {
            Body::Ascii { tokens, .. } => tokens.size_hint().1.unwrap_or(usize::MAX) as u64,
            Body::Bin { data, pos, .. } => ((data.len() - *pos) / item_ty.size()) as u64,
        };
        if n > left {
            return Err(match loc {
                Location::Byte(offset) => ReadError::Truncated {
                    format: F,
                    offset,
                    expected: n.saturating_mul(item_ty.size() as u64),
                },
                loc => malformed(F, loc, format!("list of {n} items is longer than the file")),
            });
        }
        Ok(n as usize)
    }

    fn skip(&mut self, p: &Property) -> Result<(), ReadError> {
        match p {
            Property::Scalar(t, _) => {
                self.value(*t)?;
            }
            Property::List(c, t, _) => {
                let n = self.list_len(*c, *t)?;
                match self {
                    Body::Bin { pos, .. } => *pos += n * t.size(), // list_len checked the fit
                    _ => {
                        for _ in 0..n {
                            self.value(*t)?;
                        }
                    }
                }
            }
        }
        Ok(())
    }
}

pub(super) fn read(bytes: &[u8], limits: &Limits) -> Result<Mesh, ReadError> {
    let h = parse_header(bytes)?;
    let data = bytes.get(h.data_start..).unwrap_or(&[]);
    let mut body = match h.encoding {
        Encoding::Ascii => {
            let text = super::utf8(F, data).map_err(|e| match e {
                ReadError::InvalidUtf8 { format, offset } => ReadError::InvalidUtf8 {
                    format,
                    offset: offset + h.data_start as u64,
                },
                e => e,
            })?;
            let header_lines = bytes[..h.data_start]
                .iter()
                .filter(|&&b| b == b'\n')
                .count();
            Body::Ascii {
                tokens: AsciiTokens {
                    text,
                    pos: 0,
                    line: header_lines + 1,
                },
                line: header_lines + 1,
                end: bytes.len() as u64,
            }
        }
        Encoding::Le | Encoding::Be => Body::Bin {
            data: bytes,
            pos: h.data_start,
            big: h.encoding == Encoding::Be,
        },
    };

    // Size checks before allocating anything.
    let mut min_total: u64 = 0;
    for el in &h.elements {
        if el.count > 0 && el.props.is_empty() {
            return Err(malformed(
                F,
                Location::Unknown,
                format!("element `{}` has no properties", el.name),
            ));
        }
        let per: u64 = match h.encoding {
            // At least one byte per value in ascii (plus separators, ignored here).
            Encoding::Ascii => el.props.len() as u64,
            _ => el
                .props
                .iter()
                .map(|p| match p {
                    Property::Scalar(t, _) => t.size() as u64,
                    Property::List(c, _, _) => c.size() as u64,
                })
                .sum(),
        };
        match el.name.as_str() {
            "vertex" => check_limit(F, "vertex count", el.count, vertex_limit(limits))?,
            "face" => check_limit(F, "face count", el.count, limits.max_faces as u64)?,
            _ => {}
        }
        let need = el
            .count
            .checked_mul(per)
            .and_then(|b| b.checked_add(min_total));
        match need {
            Some(n) if n <= data.len() as u64 => min_total = n,
            _ => {
                return Err(ReadError::Truncated {
                    format: F,
                    offset: bytes.len() as u64,
                    expected: need.map_or(u64::MAX, |n| n - data.len() as u64),
                });
            }
        }
    }

    let mut positions: Vec<Vec3> = Vec::new();
    let mut normals: Vec<Vec3> = Vec::new();
    let mut faces: Vec<[u32; 3]> = Vec::new();
    let mut vertex_count: Option<u64> = None;
    let mut seen_vertex = false;
    let mut corners: Vec<u32> = Vec::new();

    for el in &h.elements {
        match el.name.as_str() {
            "vertex" if !seen_vertex => {
                seen_vertex = true;
                vertex_count = Some(el.count);
                let find = |n: &str| {
                    el.props
                        .iter()
                        .position(|p| matches!(p, Property::Scalar(_, name) if name == n))
                };
                let (Some(x), Some(y), Some(z)) = (find("x"), find("y"), find("z")) else {
                    return Err(malformed(
                        F,
                        Location::Unknown,
                        "vertex element lacks x, y or z",
                    ));
                };
                let nrm = match (find("nx"), find("ny"), find("nz")) {
                    (Some(a), Some(b), Some(c)) => Some([a, b, c]),
                    _ => None,
                };
                let n = el.count as usize;
                positions.reserve_exact(n);
                if nrm.is_some() {
                    normals.reserve_exact(n);
                }
                for _ in 0..el.count {
                    let loc = body.location();
                    let mut p = [0f32; 3];
                    let mut nv = [0f32; 3];
                    for (k, prop) in el.props.iter().enumerate() {
                        if let Property::Scalar(t, _) = prop {
                            let v = body.value(*t)? as f32;
                            if k == x {
                                p[0] = v;
                            } else if k == y {
                                p[1] = v;
                            } else if k == z {
                                p[2] = v;
                            }
                            if let Some(nk) = nrm {
                                for c in 0..3 {
                                    if k == nk[c] {
                                        nv[c] = v;
                                    }
                                }
                            }
                        } else {
                            body.skip(prop)?;
                        }
                    }
                    if !p.iter().all(|c| c.is_finite()) {
                        // Binary: where the vertex starts; ascii: the line just read.
                        let location = match loc {
                            Location::Byte(_) => loc,
                            _ => body.location(),
                        };
                        return Err(ReadError::NonFinite {
                            format: F,
                            location,
                        });
                    }
                    positions.push(Vec3::from_array(p));
                    if nrm.is_some() {
                        normals.push(Vec3::from_array(nv));
                    }
                }
            }
            "face" => {
                let idx = el
                    .props
                    .iter()
                    .position(|p| {
                        matches!(p, Property::List(..))
                            && (p.name() == "vertex_indices" || p.name() == "vertex_index")
                    })
                    .ok_or_else(|| {
                        malformed(
                            F,
                            Location::Unknown,
                            "face element has no vertex_indices list",
                        )
                    })?;
                let nverts = match vertex_count {
                    Some(n) => n,
                    None => h
                        .elements
                        .iter()
                        .find(|e| e.name == "vertex")
                        .map_or(0, |e| e.count),
                };
                faces.reserve_exact(el.count as usize);
                for _ in 0..el.count {
                    for (k, prop) in el.props.iter().enumerate() {
                        match prop {
                            Property::List(c, t, _) if k == idx => {
                                let loc = body.location();
                                let n = body.list_len(*c, *t)?;
                                if n < 3 {
                                    return Err(malformed(
                                        F,
                                        loc,
                                        format!("a face needs at least 3 vertices, not {n}"),
                                    ));
                                }
                                corners.clear();
                                for _ in 0..n {
                                    let loc = body.location();
                                    let v = body.value(*t)?;
                                    if v.fract() != 0.0 || v < 0.0 || v >= nverts as f64 {
                                        return Err(ReadError::IndexOutOfRange {
                                            what: "vertices",
                                            format: F,
                                            location: loc,
                                            index: v as i64,
                                            count: nverts as usize,
                                        });
                                    }
                                    corners.push(v as u32);
                                }
                                push_fan(F, &corners, &mut faces, limits)?;
                            }
                            _ => body.skip(prop)?,
                        }
                    }
                }
            }
            _ => {
                for _ in 0..el.count {
                    for prop in &el.props {
                        body.skip(prop)?;
                    }
                }
            }
        }
    }
    finish(F, positions, normals, faces)
}

/// Binary little-endian PLY: `vertex` with `float x y z` (and `nx ny nz` when the mesh has
/// normals), `face` with `list uchar int vertex_indices` (`uint` if an index exceeds
/// `i32::MAX`). A point cloud has no `face` element.
pub fn write_ply(mesh: &Mesh) -> Vec<u8> {
    let has_n = !mesh.normals.is_empty() && mesh.normals.len() == mesh.positions.len();
    let big_index = mesh.faces.iter().flatten().any(|&i| i > i32::MAX as u32);
    let mut h = String::from("ply\nformat binary_little_endian 1.0\ncomment written by meshflow\n");
    h += &format!("element vertex {}\n", mesh.positions.len());
    h += "property float x\nproperty float y\nproperty float z\n";
    if has_n {
        h += "property float nx\nproperty float ny\nproperty float nz\n";
    }
    if !mesh.faces.is_empty() {
        h += &format!("element face {}\n", mesh.faces.len());
        h += if big_index {
            "property list uchar uint vertex_indices\n"
        } else {
            "property list uchar int vertex_indices\n"
        };
    }
    h += "end_header\n";
    let per_v = if has_n { 24 } else { 12 };
    let mut out =
        Vec::with_capacity(h.len() + mesh.positions.len() * per_v + mesh.faces.len() * 13);
    out.extend_from_slice(h.as_bytes());
    for (i, p) in mesh.positions.iter().enumerate() {
        for c in p.to_array() {
            out.extend_from_slice(&c.to_le_bytes());
        }
        if has_n {
            for c in mesh.normals[i].to_array() {
                out.extend_from_slice(&c.to_le_bytes());
            }
        }
    }
    for f in &mesh.faces {
        out.push(3);
        for &i in f {
            out.extend_from_slice(&i.to_le_bytes());
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ascii_with_extra_properties_and_quads() {
        let s = "ply\nformat ascii 1.0\ncomment hi\nelement vertex 4\nproperty float x\nproperty uchar red\nproperty float y\nproperty list uchar int junk\nproperty float z\nelement face 1\nproperty uchar flags\nproperty list uchar uint vertex_indices\nelement edge 1\nproperty int a\nproperty int b\nend_header\n0 1 0 2 7 7 0\n1 2 0 0 0\n1 3 1 1 9 0\n0 4 1 0 0\n5 4 0 1 2 3\n0 1\n";
        let m = read(s.as_bytes(), &Limits::default()).unwrap();
        assert_eq!(m.positions[2], Vec3::new(1.0, 1.0, 0.0));
        assert_eq!(m.faces, vec![[0, 1, 2], [0, 2, 3]]);
    }

    #[test]
    fn absurd_count_rejected_before_allocating() {
        let s = "ply\nformat binary_little_endian 1.0\nelement vertex 4000000000\nproperty float x\nproperty float y\nproperty float z\nend_header\n";
        assert!(matches!(
            read(s.as_bytes(), &Limits::default()),
            Err(ReadError::TooLarge { .. })
        ));
    }
}

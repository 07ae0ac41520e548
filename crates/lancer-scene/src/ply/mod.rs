//! PLY meshes (the Stanford polygon file format) read into a [`TriangleMesh`], as pbrt-v4's
//! `Shape "plymesh"` uses them.
//!
//! The three encodings are read (`ascii`, `binary_little_endian`, `binary_big_endian`, all
//! version 1.0), with every PLY scalar type. From the `vertex` element come `x y z`, the
//! normal `nx ny nz` and texture coordinates (`u v`, `s t`, `texture_u texture_v` or
//! `texture_s texture_t`); from `face` the `vertex_indices` (or `vertex_index`) lists:
//! triangles as they are, larger polygons as fans. A quad (v₀, v₁, v₂, v₃) gives the two
//! triangles (v₀, v₁, v₂), (v₀, v₂, v₃), kept after all the other faces' triangles, so that
//! pbrt-v4's reading — a bilinear patch (p₀₀, p₁₀, p₀₁, p₁₁) = (v₀, v₁, v₃, v₂) per quad, its
//! `BilinearPatchMesh` — can be taken back from them ([`PlyMesh::split_quads`]), while readers
//! that want triangles (and pbrt-v4's displacement, which splits quads so) use the mesh as
//! it is. A `tristrips` element (triangle strips, `-1` restarting a strip) is read too. Other
//! elements and properties are skipped. A file whose name ends in `.gz` is gunzipped first.
//!
//! The whole file is read into memory and parsed from the slice. Nothing is allocated on the
//! header's word alone: before any element is read, the header's counts are checked against
//! the bytes that follow it.

use lancer::math::{PackedVec3, Vec2};
use lancer::shape::{BilinearMesh, TriangleMesh};
use std::fmt;
use std::io::Read;
use std::path::Path;

mod body;
mod header;
#[cfg(test)]
mod tests;

use body::{Ascii, Binary, Body, ReadError, list_len, skip_element, skip_property};
use header::{Element, Format, Header, Kind, check_sizes, parse_header};

/// Why a PLY file could not be read.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct PlyError {
    /// The file, as named to the reader.
    pub file: String,
    /// What is wrong, one line.
    pub message: String,
}

impl fmt::Display for PlyError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}: {}", self.file, self.message)
    }
}

impl std::error::Error for PlyError {}

/// A mesh read from a PLY file, and what the reader left out.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PlyMesh {
    /// The triangles, in the file's coordinates: those of the faces that are not quads, then
    /// two per quad ((v₀, v₁, v₂), (v₀, v₂, v₃)), in the file's order.
    pub mesh: TriangleMesh,
    /// How many faces are quads: their triangles are the last 2·`quads` of `mesh`.
    pub quads: usize,
    /// Faces with fewer than three vertices, which make no triangle and are skipped.
    pub skipped_faces: u64,
}

impl PlyMesh {
    /// The mesh as pbrt-v4 reads it: the triangles of the faces that are not quads, and the
    /// quads as bilinear patches (p₀₀, p₁₀, p₀₁, p₁₁) = (v₀, v₁, v₃, v₂), both on the file's
    /// vertices; `None` for a part without faces.
    pub fn split_quads(self) -> (Option<TriangleMesh>, Option<BilinearMesh>) {
        let mut tris = self.mesh;
        if self.quads == 0 {
            return ((!tris.indices.is_empty()).then_some(tris), None);
        }
        let plain = tris.indices.len() - 6 * self.quads;
        let indices: Vec<u32> = tris.indices[plain..]
            .chunks_exact(6)
            .flat_map(|t| [t[0], t[1], t[5], t[2]])
            .collect();
        tris.indices.truncate(plain);
        // Quads only: the patches take the vertices rather than a copy of them.
        let vertices = if plain == 0 {
            std::mem::take(&mut tris)
        } else {
            TriangleMesh {
                positions: tris.positions.clone(),
                normals: tris.normals.clone(),
                uvs: tris.uvs.clone(),
                indices: Vec::new(),
                flip_normal: tris.flip_normal,
            }
        };
        let patches = BilinearMesh {
            positions: vertices.positions,
            normals: vertices.normals,
            uvs: vertices.uvs,
            indices,
            flip_normal: vertices.flip_normal,
        };
        ((plain > 0).then_some(tris), Some(patches))
    }
}

/// Reads a PLY file (gunzipping it first when its name ends in `.gz`).
pub fn read_ply(path: &Path) -> Result<PlyMesh, PlyError> {
    let name = path.display().to_string();
    let fail = |message: String| PlyError {
        file: name.clone(),
        message,
    };
    crate::files_read::record(path);
    let raw = std::fs::read(path).map_err(|e| fail(format!("cannot read the file: {e}")))?;
    let gz = path
        .extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| e.eq_ignore_ascii_case("gz"));
    let data = if gz {
        let mut out = Vec::new();
        flate2::read::MultiGzDecoder::new(raw.as_slice())
            .read_to_end(&mut out)
            .map_err(|e| fail(format!("cannot decompress the file: {e}")))?;
        out
    } else {
        raw
    };
    parse_ply(&data, &name)
}

/// Reads PLY data held in memory; `name` names it in messages.
pub fn parse_ply(data: &[u8], name: &str) -> Result<PlyMesh, PlyError> {
    parse(data).map_err(|message| PlyError {
        file: name.to_string(),
        message,
    })
}

fn parse(data: &[u8]) -> Result<PlyMesh, String> {
    let header = parse_header(data)?;
    let body = &data[header.body_start..];
    check_sizes(&header, body.len())?;
    match header.format {
        Format::Ascii => read_body(&mut Ascii { data: body, pos: 0 }, &header),
        Format::Binary { big_endian } => read_body(
            &mut Binary {
                data: body,
                pos: 0,
                big: big_endian,
            },
            &header,
        ),
    }
}
/// Where each vertex property goes: slots 0–2 position, 3–5 normal, 6–7 uv.
struct VertexLayout {
    slots: Vec<Option<usize>>,
    normals: bool,
    uvs: bool,
}

impl VertexLayout {
    fn new(el: &Element) -> Result<VertexLayout, String> {
        let mut slots = vec![None; el.props.len()];
        let (Some(x), Some(y), Some(z)) = (el.scalar("x"), el.scalar("y"), el.scalar("z")) else {
            return Err("the \"vertex\" element has no x, y and z properties".into());
        };
        for (slot, i) in [x, y, z].into_iter().enumerate() {
            slots[i] = Some(slot);
        }
        let normals = match (el.scalar("nx"), el.scalar("ny"), el.scalar("nz")) {
            (Some(a), Some(b), Some(c)) => {
                slots[a] = Some(3);
                slots[b] = Some(4);
                slots[c] = Some(5);
                true
            }
            _ => false,
        };
        let uv_names = [
            ("u", "v"),
            ("s", "t"),
            ("texture_u", "texture_v"),
            ("texture_s", "texture_t"),
        ];
        let uv = uv_names
            .iter()
            .find_map(|(u, v)| Some((el.scalar(u)?, el.scalar(v)?)));
        if let Some((u, v)) = uv {
            slots[u] = Some(6);
            slots[v] = Some(7);
        }
        Ok(VertexLayout {
            slots,
            normals,
            uvs: uv.is_some(),
        })
    }
}

fn read_vertices<B: Body>(
    body: &mut B,
    el: &Element,
    layout: &VertexLayout,
    mesh: &mut TriangleMesh,
) -> Result<(), String> {
    // check_sizes has bounded the count by the data's length.
    let n = el.count as usize;
    mesh.positions.reserve_exact(n);
    if layout.normals {
        mesh.normals.reserve_exact(n);
    }
    if layout.uvs {
        mesh.uvs.reserve_exact(n);
    }
    let mut v = [0.0f64; 8];
    for i in 0..el.count {
        for (p, slot) in el.props.iter().zip(&layout.slots) {
            let r = match (p.kind, slot) {
                (Kind::Scalar(t), Some(s)) => body.float(t).map(|x| v[*s] = x),
                (kind, _) => skip_property(body, kind),
            };
            r.map_err(|e| e.describe("vertex", i, el.count))?;
        }
        let finite = |a: &[f64]| a.iter().all(|x| (*x as f32).is_finite());
        if !finite(&v[0..3]) {
            return Err(format!(
                "vertex {i} has position ({}, {}, {}), which is not finite",
                v[0], v[1], v[2]
            ));
        }
        mesh.positions
            .push(PackedVec3::new(v[0] as f32, v[1] as f32, v[2] as f32));
        if layout.normals {
            if !finite(&v[3..6]) {
                return Err(format!(
                    "vertex {i} has normal ({}, {}, {}), which is not finite",
                    v[3], v[4], v[5]
                ));
            }
            mesh.normals
                .push(PackedVec3::new(v[3] as f32, v[4] as f32, v[5] as f32));
        }
        if layout.uvs {
            if !finite(&v[6..8]) {
                return Err(format!(
                    "vertex {i} has texture coordinates ({}, {}), which are not finite",
                    v[6], v[7]
                ));
            }
            mesh.uvs.push(Vec2::new(v[6] as f32, v[7] as f32));
        }
    }
    Ok(())
}

/// How the index lists of an element are read.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Polygons {
    /// `face`: each list a polygon, triangulated as a fan.
    Faces,
    /// `tristrips`: each list triangle strips, `-1` ending one.
    Strips,
}

/// Reads an element of index lists (the property at `list`), appending triangles to
/// `indices` and the vertices of quads to `quads`; returns how many faces had fewer than three
/// vertices.
fn read_polygons<B: Body>(
    body: &mut B,
    el: &Element,
    list: usize,
    polygons: Polygons,
    vertex_count: usize,
    indices: &mut Vec<u32>,
    quads: &mut Vec<u32>,
) -> Result<u64, String> {
    let Kind::List { count, item } = el.props[list].kind else {
        return Err(format!(
            "the \"{}\" property of \"{}\" is a single number, not a list",
            el.props[list].name, el.name
        ));
    };
    if !item.is_integer() {
        return Err(format!(
            "the \"{}\" lists of \"{}\" hold floating-point numbers, not vertex indices",
            el.props[list].name, el.name
        ));
    }
    let mut skipped = 0;
    for i in 0..el.count {
        let describe = |e: ReadError| e.describe(&el.name, i, el.count);
        for (j, p) in el.props.iter().enumerate() {
            if j != list {
                skip_property(body, p.kind).map_err(describe)?;
                continue;
            }
            let n = list_len(body, count).map_err(describe)?;
            let vertex = |k: i64| -> Result<u32, String> {
                if (0..vertex_count as i64).contains(&k) {
                    Ok(k as u32)
                } else {
                    Err(format!(
                        "{} {i} refers to vertex {k} but there are {vertex_count} vertices",
                        el.name
                    ))
                }
            };
            match polygons {
                Polygons::Faces if n < 3 => {
                    body.skip(item, n).map_err(describe)?;
                    skipped += 1;
                }
                Polygons::Faces if n == 4 => {
                    for _ in 0..4 {
                        quads.push(vertex(body.int(item).map_err(describe)?)?);
                    }
                }
                Polygons::Faces => {
                    let first = vertex(body.int(item).map_err(describe)?)?;
                    let mut prev = vertex(body.int(item).map_err(describe)?)?;
                    for _ in 2..n {
                        let next = vertex(body.int(item).map_err(describe)?)?;
                        indices.extend_from_slice(&[first, prev, next]);
                        prev = next;
                    }
                }
                Polygons::Strips => {
                    let (mut a, mut b) = (None, None);
                    let mut odd = false;
                    for _ in 0..n {
                        let k = body.int(item).map_err(describe)?;
                        if k == -1 {
                            (a, b, odd) = (None, None, false);
                            continue;
                        }
                        let c = vertex(k)?;
                        if let (Some(a), Some(b)) = (a, b) {
                            // Repeated vertices join strips; they make no triangle.
                            if a != b && b != c && a != c {
                                let t = if odd { [b, a, c] } else { [a, b, c] };
                                indices.extend_from_slice(&t);
                            }
                            odd = !odd;
                        }
                        (a, b) = (b, Some(c));
                    }
                }
            }
        }
    }
    Ok(skipped)
}

fn read_body<B: Body>(body: &mut B, header: &Header) -> Result<PlyMesh, String> {
    let mut vertex_elements = header.elements.iter().filter(|e| e.name == "vertex");
    let Some(vertex_el) = vertex_elements.next() else {
        return Err("there is no \"vertex\" element".into());
    };
    if vertex_elements.next().is_some() {
        return Err("there are two \"vertex\" elements".into());
    }
    let vertex_count = usize::try_from(vertex_el.count)
        .ok()
        .filter(|&n| n <= u32::MAX as usize)
        .ok_or_else(|| {
            format!(
                "{} vertices are more than lancer's 32-bit indices can address",
                vertex_el.count
            )
        })?;
    let layout = VertexLayout::new(vertex_el)?;
    let mut out = PlyMesh::default();
    let mut quads = Vec::new();
    for el in &header.elements {
        let polygons = match el.name.as_str() {
            "vertex" => {
                read_vertices(body, el, &layout, &mut out.mesh)?;
                continue;
            }
            "face" => Polygons::Faces,
            "tristrips" => Polygons::Strips,
            _ => {
                skip_element(body, el)?;
                continue;
            }
        };
        let Some(list) = el
            .property("vertex_indices")
            .or_else(|| el.property("vertex_index"))
        else {
            return Err(format!(
                "the \"{}\" element has no \"vertex_indices\" list",
                el.name
            ));
        };
        out.skipped_faces += read_polygons(
            body,
            el,
            list,
            polygons,
            vertex_count,
            &mut out.mesh.indices,
            &mut quads,
        )?;
    }
    // The quads' triangles last: (v₀, v₁, v₂), (v₀, v₂, v₃).
    out.quads = quads.len() / 4;
    out.mesh.indices.reserve_exact(6 * out.quads);
    for q in quads.chunks_exact(4) {
        out.mesh
            .indices
            .extend_from_slice(&[q[0], q[1], q[2], q[0], q[2], q[3]]);
    }
    out.mesh.validate()?;
    Ok(out)
}

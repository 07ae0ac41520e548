//! Wavefront OBJ meshes (and their MTL material libraries) read into [`TriangleMesh`]es, for
//! pbrt-v4's `Shape "objmesh"` and for rendering an `.obj` file directly.
//!
//! Read from the OBJ: `v` (positions; a fourth `w` and trailing vertex colours are ignored),
//! `vt` (texture coordinates, `u v`), `vn` (normals), `f` (faces of three or more corners, each
//! `v`, `v/vt`, `v//vn` or `v/vt/vn`, indices from 1 or negative for "counting back from the
//! last one read"), `usemtl` and `mtllib`. Polygons are triangulated as fans (a quad gives two
//! triangles). Objects and groups (`o`, `g`), smoothing groups (`s`), points and lines (`p`,
//! `l`) and everything else are skipped. A line ending in `\` continues on the next.
//!
//! The file's separate position/uv/normal arrays become per-vertex arrays as a renderer needs:
//! every distinct `(v, vt, vn)` triple of a mesh becomes one vertex. When some corners of a mesh
//! have a normal (or uv) and others do not, the mesh gets none (the renderer then uses the
//! geometric normal, or pbrt's default uvs).
//!
//! Errors name the file and line: numbers that do not parse or are not finite, index 0, and
//! indices out of range for the vertices the file holds.

use lancer::math::{PackedVec3, Rgb, Vec2};
use lancer::shape::TriangleMesh;
use std::collections::HashMap;
use std::fmt;
use std::path::Path;

/// Why an OBJ or MTL file could not be read.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ObjError {
    /// The file, as named to the reader.
    pub file: String,
    /// The 1-based line, when the error is on one.
    pub line: Option<u32>,
    /// What is wrong, one line.
    pub message: String,
}

impl fmt::Display for ObjError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.line {
            Some(line) => write!(f, "{}:{line}: {}", self.file, self.message),
            None => write!(f, "{}: {}", self.file, self.message),
        }
    }
}

impl std::error::Error for ObjError {}

/// One corner of a face: indices (from 0) into the file's positions, uvs and normals.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
struct Corner {
    v: u32,
    vt: Option<u32>,
    vn: Option<u32>,
}

/// A triangle of the file: its corners and the index of its material in
/// [`ObjFile::material_names`] (`None` before any `usemtl`).
#[derive(Clone, Copy, Debug)]
struct Tri {
    corners: [Corner; 3],
    material: Option<u32>,
}

/// An OBJ file as read: its vertex data and triangles, not yet turned into meshes.
#[derive(Clone, Debug, Default)]
pub struct ObjFile {
    positions: Vec<PackedVec3>,
    uvs: Vec<Vec2>,
    normals: Vec<PackedVec3>,
    tris: Vec<Tri>,
    /// Material names in the order `usemtl` first named them.
    pub material_names: Vec<String>,
    /// The line of each material's first `usemtl`, parallel to `material_names`.
    pub material_lines: Vec<u32>,
    /// The material libraries `mtllib` named, as written (relative to the OBJ's folder),
    /// with the line naming them.
    pub mtllibs: Vec<(u32, String)>,
    /// Faces with fewer than three corners, skipped.
    pub skipped_faces: u64,
}

impl ObjFile {
    /// Number of triangles (after fan triangulation).
    pub fn triangle_count(&self) -> usize {
        self.tris.len()
    }

    /// Every triangle of the file in one mesh (objects, groups and materials merged), as
    /// pbrt's `objmesh` uses it.
    pub fn merged_mesh(&self) -> TriangleMesh {
        self.build(self.tris.iter())
    }

    /// One mesh per material: `(index into material_names or None, mesh)`, in order of first
    /// use, meshes without triangles left out.
    pub fn meshes_by_material(&self) -> Vec<(Option<u32>, TriangleMesh)> {
        // One pass into buckets (a file may have thousands of materials).
        let mut slot: HashMap<Option<u32>, usize> = HashMap::new();
        let mut buckets: Vec<(Option<u32>, Vec<&Tri>)> = Vec::new();
        for t in &self.tris {
            let i = *slot.entry(t.material).or_insert_with(|| {
                buckets.push((t.material, Vec::new()));
                buckets.len() - 1
            });
            buckets[i].1.push(t);
        }
        buckets
            .into_iter()
            .map(|(m, tris)| (m, self.build(tris.iter().copied())))
            .collect()
    }

    /// A mesh from some of the triangles, one vertex per distinct corner triple.
    fn build<'a>(&self, tris: impl Iterator<Item = &'a Tri> + Clone) -> TriangleMesh {
        let all_uv = tris
            .clone()
            .all(|t| t.corners.iter().all(|c| c.vt.is_some()));
        let all_n = tris
            .clone()
            .all(|t| t.corners.iter().all(|c| c.vn.is_some()));
        let mut mesh = TriangleMesh::default();
        let mut seen: HashMap<Corner, u32> = HashMap::new();
        for t in tris {
            for c in t.corners {
                // Attributes the mesh does not keep must not split vertices.
                let key = Corner {
                    v: c.v,
                    vt: if all_uv { c.vt } else { None },
                    vn: if all_n { c.vn } else { None },
                };
                let index = *seen.entry(key).or_insert_with(|| {
                    mesh.positions.push(self.positions[c.v as usize]);
                    if let (true, Some(vt)) = (all_uv, key.vt) {
                        mesh.uvs.push(self.uvs[vt as usize]);
                    }
                    if let (true, Some(vn)) = (all_n, key.vn) {
                        mesh.normals.push(self.normals[vn as usize]);
                    }
                    (mesh.positions.len() - 1) as u32
                });
                mesh.indices.push(index);
            }
        }
        mesh
    }
}

/// Reads an OBJ file (its material libraries are named in [`ObjFile::mtllibs`], not read).
pub fn read_obj(path: &Path) -> Result<ObjFile, ObjError> {
    let name = path.display().to_string();
    let text = read_text(path, &name)?;
    parse_obj(&text, &name)
}

fn read_text(path: &Path, name: &str) -> Result<String, ObjError> {
    crate::files_read::record(path);
    let bytes = std::fs::read(path).map_err(|e| ObjError {
        file: name.to_string(),
        line: None,
        message: format!("cannot read the file: {e}"),
    })?;
    // Exporters write Latin-1 names in comments now and then; do not refuse the file for that.
    Ok(String::from_utf8_lossy(&bytes).into_owned())
}

/// The logical lines of an OBJ or MTL text, with their 1-based line numbers: comments cut,
/// `\` continuations joined, blank lines left out.
fn logical_lines(text: &str) -> Vec<(u32, String)> {
    let mut out = Vec::new();
    let mut pending: Option<(u32, String)> = None;
    for (i, raw) in text.lines().enumerate() {
        let line_no = i as u32 + 1;
        let (start, mut acc) = pending.take().unwrap_or((line_no, String::new()));
        let content = raw.split('#').next().unwrap_or("");
        let trimmed = content.trim_end();
        if let Some(stripped) = trimmed.strip_suffix('\\') {
            acc.push_str(stripped);
            acc.push(' ');
            pending = Some((start, acc));
            continue;
        }
        acc.push_str(trimmed);
        if !acc.trim().is_empty() {
            out.push((start, acc));
        }
    }
    if let Some((start, acc)) = pending
        && !acc.trim().is_empty()
    {
        out.push((start, acc));
    }
    out
}

/// Reads OBJ text held in memory; `name` names it in messages.
pub fn parse_obj(text: &str, name: &str) -> Result<ObjFile, ObjError> {
    let fail = |line: u32, message: String| ObjError {
        file: name.to_string(),
        line: Some(line),
        message,
    };
    let mut obj = ObjFile::default();
    let mut material: Option<u32> = None;
    // Faces as read, checked against the final counts at the end (a file may in principle
    // name vertices that come later).
    let mut face_lines: Vec<u32> = Vec::new();
    let mut corners: Vec<Corner> = Vec::new();
    for (line_no, line) in logical_lines(text) {
        let mut words = line.split_whitespace();
        let Some(keyword) = words.next() else {
            continue;
        };
        match keyword {
            "v" => {
                let [x, y, z] =
                    floats::<3>(&mut words, "a position \"v\"").map_err(|m| fail(line_no, m))?;
                obj.positions.push(PackedVec3::new(x, y, z));
            }
            "vt" => {
                // `v` (and `w`) may be left out; u alone means v = 0.
                let rest: Vec<&str> = words.collect();
                if rest.is_empty() {
                    return Err(fail(
                        line_no,
                        "a texture coordinate \"vt\" needs at least u".into(),
                    ));
                }
                let u = number(rest[0]).map_err(|m| fail(line_no, m))?;
                let v = match rest.get(1) {
                    Some(w) => number(w).map_err(|m| fail(line_no, m))?,
                    None => 0.0,
                };
                obj.uvs.push(Vec2::new(u, v));
            }
            "vn" => {
                let [x, y, z] =
                    floats::<3>(&mut words, "a normal \"vn\"").map_err(|m| fail(line_no, m))?;
                obj.normals.push(PackedVec3::new(x, y, z));
            }
            "f" => {
                corners.clear();
                for w in words {
                    corners.push(
                        corner(w, &obj)
                            .map_err(|m| fail(line_no, format!("face corner '{w}': {m}")))?,
                    );
                }
                if corners.len() < 3 {
                    obj.skipped_faces += 1;
                    continue;
                }
                for i in 1..corners.len() - 1 {
                    obj.tris.push(Tri {
                        corners: [corners[0], corners[i], corners[i + 1]],
                        material,
                    });
                    face_lines.push(line_no);
                }
            }
            "usemtl" => {
                let m = line[keyword.len()..].trim().to_string();
                material = Some(match obj.material_names.iter().position(|n| *n == m) {
                    Some(i) => i as u32,
                    None => {
                        obj.material_names.push(m);
                        obj.material_lines.push(line_no);
                        (obj.material_names.len() - 1) as u32
                    }
                });
            }
            "mtllib" => {
                let rest = line[keyword.len()..].trim();
                if !rest.is_empty() {
                    obj.mtllibs.push((line_no, rest.to_string()));
                }
            }
            _ => {}
        }
    }
    // Every index in range for what the file holds.
    for (t, &line_no) in obj.tris.iter().zip(&face_lines) {
        for c in t.corners {
            let checks = [
                ("position", Some(c.v), obj.positions.len()),
                ("texture coordinate", c.vt, obj.uvs.len()),
                ("normal", c.vn, obj.normals.len()),
            ];
            for (what, index, count) in checks {
                if let Some(i) = index
                    && i as usize >= count
                {
                    return Err(fail(
                        line_no,
                        format!(
                            "{what} index {} is out of range: the file has {count} {what}s",
                            i + 1
                        ),
                    ));
                }
            }
        }
    }
    Ok(obj)
}

/// A finite number.
fn number(word: &str) -> Result<f32, String> {
    match word.parse::<f32>() {
        Ok(x) if x.is_finite() => Ok(x),
        Ok(_) => Err(format!("'{word}' is not a finite number")),
        Err(_) => Err(format!("'{word}' is not a number")),
    }
}

/// The first `N` numbers of a line (more are ignored: `w`, vertex colours).
fn floats<'a, const N: usize>(
    words: &mut impl Iterator<Item = &'a str>,
    what: &str,
) -> Result<[f32; N], String> {
    let mut out = [0.0; N];
    for (i, slot) in out.iter_mut().enumerate() {
        let Some(w) = words.next() else {
            return Err(format!("{what} needs {N} numbers, found {i}"));
        };
        *slot = number(w)?;
    }
    Ok(out)
}

/// One face corner `v`, `v/vt`, `v//vn` or `v/vt/vn`, indices resolved to 0-based.
fn corner(word: &str, obj: &ObjFile) -> Result<Corner, String> {
    let mut parts = word.split('/');
    let v = parts.next().unwrap_or("");
    let vt = parts.next().filter(|s| !s.is_empty());
    let vn = parts.next().filter(|s| !s.is_empty());
    if parts.next().is_some() {
        return Err("more than three '/'-separated indices".into());
    }
    Ok(Corner {
        v: index(v, obj.positions.len(), "position")?,
        vt: vt
            .map(|s| index(s, obj.uvs.len(), "texture coordinate"))
            .transpose()?,
        vn: vn
            .map(|s| index(s, obj.normals.len(), "normal"))
            .transpose()?,
    })
}

/// An OBJ index made 0-based: `i > 0` counts from the first, `i < 0` back from the last of the
/// `count` read so far.
fn index(word: &str, count: usize, what: &str) -> Result<u32, String> {
    let i: i64 = word
        .parse()
        .map_err(|_| format!("{what} index '{word}' is not an integer"))?;
    if i > 0 {
        u32::try_from(i - 1).map_err(|_| format!("{what} index {i} is out of range"))
    } else if i < 0 {
        let back = i.unsigned_abs();
        if back as usize > count {
            Err(format!(
                "relative {what} index {i} reaches before the first (only {count} read so far)"
            ))
        } else {
            Ok((count - back as usize) as u32)
        }
    } else {
        Err(format!("{what} index 0: OBJ indices start at 1"))
    }
}

/// A material of an MTL library, the parts lancer uses.
#[derive(Clone, Debug, PartialEq)]
pub struct MtlMaterial {
    /// Its name (`newmtl`).
    pub name: String,
    /// Diffuse colour `Kd`.
    pub kd: Option<Rgb>,
    /// Specular colour `Ks`.
    pub ks: Option<Rgb>,
    /// Specular exponent `Ns`.
    pub ns: Option<f32>,
    /// Emission `Ke`.
    pub ke: Option<Rgb>,
    /// Diffuse texture `map_Kd`, as written.
    pub map_kd: Option<String>,
}

/// Reads an MTL file.
pub fn read_mtl(path: &Path) -> Result<Vec<MtlMaterial>, ObjError> {
    let name = path.display().to_string();
    let text = read_text(path, &name)?;
    parse_mtl(&text, &name)
}

/// Reads MTL text held in memory; `name` names it in messages. Statements other than
/// `newmtl`, `Kd`, `Ks`, `Ke`, `Ns` and `map_Kd` are skipped.
pub fn parse_mtl(text: &str, name: &str) -> Result<Vec<MtlMaterial>, ObjError> {
    let fail = |line: u32, message: String| ObjError {
        file: name.to_string(),
        line: Some(line),
        message,
    };
    let mut out: Vec<MtlMaterial> = Vec::new();
    for (line_no, line) in logical_lines(text) {
        let mut words = line.split_whitespace();
        let Some(keyword) = words.next() else {
            continue;
        };
        if keyword == "newmtl" {
            out.push(MtlMaterial {
                name: line[keyword.len()..].trim().to_string(),
                kd: None,
                ks: None,
                ns: None,
                ke: None,
                map_kd: None,
            });
            continue;
        }
        let rgb = |words: &mut std::str::SplitWhitespace<'_>| -> Result<Rgb, ObjError> {
            let rest: Vec<&str> = words.collect();
            let first = rest
                .first()
                .ok_or_else(|| fail(line_no, format!("{keyword} needs a colour")))?;
            if *first == "spectral" || *first == "xyz" {
                return Err(fail(
                    line_no,
                    format!("{keyword} {first} colours are not supported; give r g b"),
                ));
            }
            let r = number(first).map_err(|m| fail(line_no, m))?;
            // One number is a grey.
            let g = rest
                .get(1)
                .map(|w| number(w))
                .transpose()
                .map_err(|m| fail(line_no, m))?;
            let b = rest
                .get(2)
                .map(|w| number(w))
                .transpose()
                .map_err(|m| fail(line_no, m))?;
            Ok(Rgb::new(r, g.unwrap_or(r), b.unwrap_or(g.unwrap_or(r))))
        };
        let key = keyword.to_ascii_lowercase();
        let Some(m) = out.last_mut() else {
            // Statements before the first `newmtl` belong to no material.
            continue;
        };
        match key.as_str() {
            "kd" => m.kd = Some(rgb(&mut words)?),
            "ks" => m.ks = Some(rgb(&mut words)?),
            "ke" => m.ke = Some(rgb(&mut words)?),
            "ns" => {
                let w = words
                    .next()
                    .ok_or_else(|| fail(line_no, "Ns needs a number".into()))?;
                m.ns = Some(number(w).map_err(|e| fail(line_no, e))?);
            }
            "map_kd" => {
                // Options (`-s 1 1 1`, …) come first; the file name is the last word.
                m.map_kd = line.split_whitespace().last().map(str::to_string);
            }
            _ => {}
        }
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn obj(text: &str) -> ObjFile {
        parse_obj(text, "t.obj").unwrap()
    }

    fn err(text: &str) -> ObjError {
        parse_obj(text, "t.obj").unwrap_err()
    }

    #[test]
    fn a_triangle_is_read_as_it_is() {
        let o = obj("# a triangle\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
        let m = o.merged_mesh();
        assert_eq!(
            m.positions,
            vec![PackedVec3::ZERO, PackedVec3::X, PackedVec3::Y]
        );
        assert_eq!(m.indices, vec![0, 1, 2]);
        assert!(m.normals.is_empty() && m.uvs.is_empty());
        assert!(m.validate().is_ok());
    }

    #[test]
    fn quads_and_polygons_become_fans() {
        let o = obj("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv -1 1 0\nf 1 2 3 4\nf 1 2 3 4 5\n");
        let m = o.merged_mesh();
        assert_eq!(m.triangle_count(), 2 + 3);
        assert_eq!(m.indices, vec![0, 1, 2, 0, 2, 3, 0, 1, 2, 0, 2, 3, 0, 3, 4]);
        assert_eq!(m.positions.len(), 5, "shared corners stay shared");
    }

    #[test]
    fn negative_indices_count_back_from_the_last_read() {
        let o = obj("v 9 9 9\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf -3 -2 -1\n");
        let m = o.merged_mesh();
        assert_eq!(
            m.positions,
            vec![PackedVec3::ZERO, PackedVec3::X, PackedVec3::Y]
        );
        // Relative to the vertices read *so far*, not to the whole file.
        let o = obj("v 0 0 0\nv 1 0 0\nv 0 1 0\nf -3 -2 -1\nv 5 5 5\n");
        assert_eq!(
            o.merged_mesh().positions,
            vec![PackedVec3::ZERO, PackedVec3::X, PackedVec3::Y]
        );
    }

    #[test]
    fn corner_forms_give_per_vertex_uvs_and_normals() {
        let text = "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nvt 0.5 0.5\n\
                    vn 0 0 1\nvn 0 0 -1\n\
                    f 1/1/1 2/2/1 3/3/1\nf 1/4/2 3/3/2 2/2/2\n";
        let m = obj(text).merged_mesh();
        assert!(m.validate().is_ok());
        // Position 1 appears with two different (vt, vn): two vertices. Positions 2 and 3
        // change normal between faces: two each. Six vertices in all.
        assert_eq!(m.positions.len(), 6);
        assert_eq!(m.uvs.len(), 6);
        assert_eq!(m.normals.len(), 6);
        assert_eq!(m.normals[m.indices[0] as usize], PackedVec3::Z);
        assert_eq!(m.normals[m.indices[3] as usize], -PackedVec3::Z);
        assert_eq!(m.uvs[m.indices[3] as usize], Vec2::new(0.5, 0.5));

        // v//vn: normals without uvs.
        let m = obj("v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nf 1//1 2//1 3//1\n").merged_mesh();
        assert_eq!((m.normals.len(), m.uvs.len()), (3, 0));
        // v/vt: uvs without normals.
        let m = obj("v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1/1 2/1 3/1\n").merged_mesh();
        assert_eq!((m.normals.len(), m.uvs.len()), (0, 3));
    }

    #[test]
    fn normals_missing_on_some_faces_drop_them_for_the_mesh() {
        let text = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nvn 0 0 1\nf 1//1 2//1 3//1\nf 2 4 3\n";
        let m = obj(text).merged_mesh();
        assert!(m.normals.is_empty());
        assert_eq!(m.positions.len(), 4, "no split on the dropped attribute");
        assert!(m.validate().is_ok());
    }

    #[test]
    fn materials_split_meshes_and_groups_merge() {
        let text = "mtllib a.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\ng one\nusemtl red\nf 1 2 3\n\
                    g two\nusemtl white\nf 1 3 2\nusemtl red\nf 2 1 3\n";
        let o = obj(text);
        assert_eq!(o.mtllibs, vec![(1, "a.mtl".to_string())]);
        assert_eq!(o.material_lines, vec![6, 9]);
        assert_eq!(
            o.material_names,
            vec!["red".to_string(), "white".to_string()]
        );
        assert_eq!(o.merged_mesh().triangle_count(), 3);
        let parts = o.meshes_by_material();
        assert_eq!(parts.len(), 2);
        assert_eq!(parts[0].0, Some(0));
        assert_eq!(parts[0].1.triangle_count(), 2);
        assert_eq!(parts[1].0, Some(1));
        assert_eq!(parts[1].1.triangle_count(), 1);
    }

    #[test]
    fn continuations_and_comments() {
        let o = obj("v 0 0 0 # origin\nv 1 \\\n 0 0\nv 0 1 0\nf 1 2 \\\n3\n");
        assert_eq!(o.merged_mesh().positions[1], PackedVec3::X);
        assert_eq!(o.triangle_count(), 1);
    }

    #[test]
    fn out_of_range_indices_name_file_and_line() {
        let e = err("v 0 0 0\nv 1 0 0\nv 0 1 0\n\nf 1 2 4\n");
        assert_eq!(e.file, "t.obj");
        assert_eq!(e.line, Some(5));
        assert!(e.message.contains("position index 4"), "{}", e.message);
        assert!(e.to_string().starts_with("t.obj:5: "), "{e}");

        let e = err("v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nf 1//1 2//1 3//2\n");
        assert_eq!(e.line, Some(5));
        assert!(e.message.contains("normal index 2"), "{}", e.message);

        let e = err("v 0 0 0\nv 1 0 0\nf -3 -2 -1\n");
        assert_eq!(e.line, Some(3));
        assert!(e.message.contains("-3"), "{}", e.message);

        let e = err("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n");
        assert!(e.message.contains("start at 1"), "{}", e.message);
    }

    #[test]
    fn bad_numbers_name_file_and_line() {
        let e = err("v 0 0 0\nv 1 zero 0\n");
        assert_eq!((e.file.as_str(), e.line), ("t.obj", Some(2)));
        assert!(e.message.contains("'zero'"), "{}", e.message);
        let e = err("v 0 0 nan\n");
        assert_eq!(e.line, Some(1));
        assert!(e.message.contains("finite"), "{}", e.message);
        let e = err("v 0 0\n");
        assert!(e.message.contains("needs 3 numbers"), "{}", e.message);
        let e = err("v 0 0 0\nf 1 a 1\n");
        assert_eq!(e.line, Some(2));
        assert!(e.message.contains("not an integer"), "{}", e.message);
    }

    #[test]
    fn a_missing_file_is_an_error_naming_it() {
        let e = read_obj(Path::new("/nonexistent/x.obj")).unwrap_err();
        assert!(
            e.to_string().starts_with("/nonexistent/x.obj: cannot read"),
            "{e}"
        );
    }

    #[test]
    fn mtl_colours_and_maps() {
        let text = "newmtl red\nKd 0.8 0.1 0.1\nKs 0.5\nNs 20\nmap_Kd -s 1 1 1 red.png\n\
                    newmtl lamp\nKe 10 9 8\n";
        let m = parse_mtl(text, "a.mtl").unwrap();
        assert_eq!(m.len(), 2);
        assert_eq!(m[0].name, "red");
        assert_eq!(m[0].kd, Some(Rgb::new(0.8, 0.1, 0.1)));
        assert_eq!(m[0].ks, Some(Rgb::new(0.5, 0.5, 0.5)));
        assert_eq!(m[0].ns, Some(20.0));
        assert_eq!(m[0].map_kd.as_deref(), Some("red.png"));
        assert_eq!(m[1].ke, Some(Rgb::new(10.0, 9.0, 8.0)));
        let e = parse_mtl("newmtl a\nKd 1 x 1\n", "a.mtl").unwrap_err();
        assert_eq!((e.file.as_str(), e.line), ("a.mtl", Some(2)));
    }
}

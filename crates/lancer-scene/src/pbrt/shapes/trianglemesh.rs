//! pbrt-v4's `trianglemesh` with inconsistent arrays, treated as `Triangle::CreateMesh` treats
//! them: it reports each problem and goes on with what is usable. Missing `indices` (with other
//! than 3 vertices), missing `P` or an index out of range drop the mesh; `indices` not a multiple
//! of 3 lose their excess; `uv` or `N` of another count than `P` are dropped. lancer warns where
//! pbrt-v4 prints its error, and drops the same things.

use super::super::convert::Fallback;
use super::super::params::ParamList;
use crate::error::SceneError;
use lancer::shape::TriangleMesh;

/// A `trianglemesh`'s arrays made consistent; `None` when the mesh is dropped (the warnings say
/// why).
pub fn triangle_mesh_as_pbrt(p: &ParamList) -> Result<Fallback<Option<TriangleMesh>>, SceneError> {
    let mut notes = Vec::new();
    let positions = p.point3s("P")?.unwrap_or_default();
    let n = positions.len();
    let indices = p.ints("indices")?.map(|(v, _)| v);
    // Read now so that a dropped mesh leaves no parameter "unused".
    let uv_name = if p.has("uv") { "uv" } else { "st" };
    let mut uvs = p.point2s(uv_name)?.unwrap_or_default();
    let mut normals = p.normals("N")?.unwrap_or_default();
    let dropped = |why: String| {
        Ok(Fallback::instead(
            None,
            format!("{why}; the mesh is skipped"),
        ))
    };
    let mut indices = match indices {
        Some(v) if !v.is_empty() => v,
        _ if n == 3 => vec![0, 1, 2],
        _ => {
            return dropped(format!(
                "a \"trianglemesh\" with {n} vertices needs vertex indices \"integer indices\""
            ));
        }
    };
    if indices.len() % 3 != 0 {
        let excess = indices.len() % 3;
        notes.push(format!(
            "\"integer indices\" has {} values, not a multiple of 3: the last {excess} are dropped",
            indices.len()
        ));
        indices.truncate(indices.len() - excess);
    }
    if n == 0 {
        return dropped("a \"trianglemesh\" needs vertex positions \"point3 P\"".to_string());
    }
    if !uvs.is_empty() && uvs.len() != n {
        notes.push(format!(
            "{} uvs for {n} vertices: the uvs are dropped",
            uvs.len()
        ));
        uvs.clear();
    }
    if !normals.is_empty() && normals.len() != n {
        notes.push(format!(
            "{} normals \"N\" for {n} vertices: the normals are dropped",
            normals.len()
        ));
        normals.clear();
    }
    if let Some(bad) = indices.iter().find(|&&i| i < 0 || i as usize >= n) {
        notes.push(format!(
            "vertex index {bad} is out of range for {n} vertices \"P\"; the mesh is skipped"
        ));
        return Ok(Fallback::noted(None, notes));
    }
    if indices.is_empty() {
        notes.push("no triangle is left; the mesh is skipped".to_string());
        return Ok(Fallback::noted(None, notes));
    }
    let mesh = TriangleMesh {
        positions,
        normals,
        uvs,
        indices: indices.into_iter().map(|i| i as u32).collect(),
        flip_normal: false,
    };
    Ok(Fallback::noted(Some(mesh), notes))
}

//! Indexed meshes: shared vertices and `N` indices per face, the data behind triangle meshes
//! (`N` = 3) and bilinear-patch meshes (`N` = 4).

use crate::math::{PackedVec3, Transform, Vec2, Vec3};

/// A rule of a shape's or light's description that is broken: its message (the one message of
/// that rule, whoever checks it) and the fields of the description it is about, so that a
/// scene reader can point at the parameters they came from.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct RuleError {
    /// The fields the rule is about, by their names in the description (`"radius"`, `"z_max"`,
    /// `"indices"`, `"normals"`, …), the most telling last; empty when it is about the whole.
    pub fields: &'static [&'static str],
    /// What is wrong.
    pub message: String,
}

impl RuleError {
    /// The rule on `fields` broken, saying `message`.
    pub fn on(fields: &'static [&'static str], message: impl Into<String>) -> RuleError {
        RuleError {
            fields,
            message: message.into(),
        }
    }
}

impl std::fmt::Display for RuleError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.message)
    }
}

impl std::error::Error for RuleError {}

impl From<RuleError> for String {
    fn from(e: RuleError) -> String {
        e.message
    }
}

/// A triangle mesh: shared vertices and three indices per triangle ((0,0), (1,0), (1,1) is
/// each triangle's own (u, v) when the mesh has none).
pub type TriangleMesh = IndexedMesh<3>;

/// Shared vertices and `N` vertex indices per face.
///
/// In a scene description the positions are in object space; once the scene is built they are
/// in world space (the transform is applied once, not per ray).
#[derive(Clone, PartialEq)]
pub struct IndexedMesh<const N: usize> {
    /// Vertex positions (packed: 12 bytes a vertex).
    pub positions: Vec<PackedVec3>,
    /// Per-vertex shading normals (empty: none).
    pub normals: Vec<PackedVec3>,
    /// Per-vertex (u, v) (empty: each face's own parameterisation, as pbrt does).
    pub uvs: Vec<Vec2>,
    /// `N` vertex indices per face.
    pub indices: Vec<u32>,
    /// Geometric normals flipped: reverse orientation xor a handedness-swapping transform
    /// (pbrt's rule; ignored where per-vertex normals decide the side).
    pub flip_normal: bool,
}

impl<const N: usize> std::fmt::Debug for IndexedMesh<N> {
    /// The arrays as their lengths and digests ([`Digest`](crate::math::digest::Digest)).
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        use crate::math::digest::Digest;
        f.debug_struct("IndexedMesh")
            .field("positions", &Digest(&self.positions))
            .field("normals", &Digest(&self.normals))
            .field("uvs", &Digest(&self.uvs))
            .field("indices", &Digest(&self.indices))
            .field("flip_normal", &self.flip_normal)
            .finish()
    }
}

impl<const N: usize> Default for IndexedMesh<N> {
    fn default() -> Self {
        IndexedMesh {
            positions: Vec::new(),
            normals: Vec::new(),
            uvs: Vec::new(),
            indices: Vec::new(),
            flip_normal: false,
        }
    }
}

impl<const N: usize> IndexedMesh<N> {
    /// Number of faces.
    pub fn face_count(&self) -> usize {
        self.indices.len() / N
    }

    /// Checks that indices come in groups of `N` and are in range, that per-vertex arrays match
    /// the positions, and that positions are finite; the message of the first rule broken
    /// ([`IndexedMesh::check`] also says which array it is about).
    pub fn validate(&self) -> Result<(), String> {
        self.check().map_err(String::from)
    }

    /// [`IndexedMesh::validate`], with the array each rule is about (`indices`, `normals`,
    /// `uvs`, `positions`). The one place these rules are checked.
    pub fn check(&self) -> Result<(), RuleError> {
        if !self.indices.len().is_multiple_of(N) {
            return Err(RuleError::on(
                &["indices"],
                format!(
                    "the mesh has {} indices, not a multiple of {N}",
                    self.indices.len()
                ),
            ));
        }
        let n = self.positions.len();
        if let Some(&bad) = self.indices.iter().find(|&&i| i as usize >= n) {
            return Err(RuleError::on(
                &["indices"],
                format!("index {bad} out of range for {n} vertices"),
            ));
        }
        if !self.normals.is_empty() && self.normals.len() != n {
            return Err(RuleError::on(
                &["normals"],
                format!("{} normals for {n} vertices", self.normals.len()),
            ));
        }
        if !self.uvs.is_empty() && self.uvs.len() != n {
            return Err(RuleError::on(
                &["uvs"],
                format!("{} uvs for {n} vertices", self.uvs.len()),
            ));
        }
        if self.positions.iter().any(|p| !p.is_finite()) {
            return Err(RuleError::on(
                &["positions"],
                "vertex positions must be finite",
            ));
        }
        Ok(())
    }

    /// The mesh moved to world space: positions as points, normals by the inverse transpose
    /// (normalised, and flipped under `ReverseOrientation` as pbrt does).
    pub fn transformed(&self, t: &Transform, reverse_orientation: bool) -> IndexedMesh<N> {
        IndexedMesh {
            positions: self
                .positions
                .iter()
                .map(|&p| t.point(p.into()).into())
                .collect(),
            normals: self
                .normals
                .iter()
                .map(|&n| {
                    let n = t.normal(n.into()).normalize_or_zero();
                    (if reverse_orientation { -n } else { n }).into()
                })
                .collect(),
            uvs: self.uvs.clone(),
            indices: self.indices.clone(),
            flip_normal: reverse_orientation ^ t.swaps_handedness(),
        }
    }

    /// Bytes of the mesh's arrays (their capacity): positions, normals, uvs, indices.
    pub fn heap_bytes(&self) -> usize {
        self.positions.capacity() * size_of::<PackedVec3>()
            + self.normals.capacity() * size_of::<PackedVec3>()
            + self.uvs.capacity() * size_of::<Vec2>()
            + self.indices.capacity() * size_of::<u32>()
    }

    /// Position of vertex `i`, unpacked for computing.
    #[inline]
    pub fn position(&self, i: usize) -> Vec3 {
        self.positions[i].into()
    }

    /// Shading normal of vertex `i`, unpacked for computing (the mesh must have normals).
    #[inline]
    pub fn normal(&self, i: usize) -> Vec3 {
        self.normals[i].into()
    }

    /// The `N` vertex indices of face `i`.
    #[inline]
    pub fn vertices(&self, i: u32) -> [usize; N] {
        let b = N * i as usize;
        std::array::from_fn(|k| self.indices[b + k] as usize)
    }
}

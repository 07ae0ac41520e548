//! Primitives compressed with `KHR_draco_mesh_compression`.
//!
//! Such a primitive's accessors carry no bytes of their own: the extension names a buffer
//! view holding one Draco bitstream, and an `attributes` object mapping each glTF semantic
//! (`POSITION`, `NORMAL`, `TEXCOORD_0`, …) to the *unique id* of a Draco attribute in that
//! stream. The stream is decoded with the `draco-core` crate; this module maps its points
//! and faces back to glTF's vertex and index arrays and checks them against the counts the
//! primitive's accessors declare (the extension requires them to agree).

use draco_core::DataType;
use draco_core::decoder_buffer::DecoderBuffer;
use draco_core::geometry_attribute::PointAttribute;
use draco_core::mesh::Mesh;
use draco_core::mesh_decoder::MeshDecoder;

/// Name of the glTF extension read here.
pub const EXTENSION: &str = "KHR_draco_mesh_compression";

/// The vertex and index arrays of a decoded Draco primitive, in glTF's conventions (uvs not
/// yet flipped).
#[derive(Debug, Clone, Default)]
pub struct DracoPrimitive {
    /// Vertex positions, one per Draco point.
    pub positions: Vec<[f32; 3]>,
    /// Vertex normals (empty when the extension maps no `NORMAL`).
    pub normals: Vec<[f32; 3]>,
    /// Texture coordinates of set 0 (empty when the extension maps no `TEXCOORD_0`).
    pub uvs: Vec<[f32; 2]>,
    /// Vertex indices, three per triangle, in the stream's face order.
    pub indices: Vec<u32>,
}

/// Decodes the Draco primitive described by the extension object `ext` (its `bufferView`
/// and `attributes`) from `buffers`, and checks it against the accessors of `prim`.
pub fn decode_primitive(
    buffers: &[Vec<u8>],
    doc: &::gltf::Document,
    prim: &::gltf::Primitive,
    ext: &::gltf::json::Value,
) -> Result<DracoPrimitive, String> {
    let view_index = ext
        .get("bufferView")
        .and_then(|v| v.as_u64())
        .ok_or_else(|| format!("{EXTENSION}: no bufferView index"))?;
    let view = doc
        .views()
        .nth(view_index as usize)
        .ok_or_else(|| format!("{EXTENSION}: buffer view {view_index} does not exist"))?;
    let bytes = super::data::view_bytes(buffers, &view)?;
    let attributes = ext
        .get("attributes")
        .and_then(|v| v.as_object())
        .ok_or_else(|| format!("{EXTENSION}: no attributes object"))?;
    let unique_id = |semantic: &str| -> Result<Option<u32>, String> {
        match attributes.get(semantic) {
            None => Ok(None),
            Some(v) => v
                .as_u64()
                .and_then(|id| u32::try_from(id).ok())
                .map(Some)
                .ok_or_else(|| {
                    format!("{EXTENSION}: attribute {semantic} is not a Draco attribute id")
                }),
        }
    };

    let mut mesh = Mesh::new();
    MeshDecoder::new()
        .decode(&mut DecoderBuffer::new(bytes), &mut mesh)
        .map_err(|e| {
            format!(
                "the Draco data in buffer view {view_index} cannot be decoded ({} bytes): {e}",
                bytes.len()
            )
        })?;
    let n = mesh.num_points();

    let Some(pos_id) = unique_id("POSITION")? else {
        return Err(format!("{EXTENSION}: the attributes name no POSITION"));
    };
    let positions = read_attribute::<3>(&mesh, pos_id, "POSITION")?;
    let normals = match unique_id("NORMAL")? {
        Some(id) => read_attribute::<3>(&mesh, id, "NORMAL")?,
        None => Vec::new(),
    };
    let uvs = match unique_id("TEXCOORD_0")? {
        Some(id) => read_attribute::<2>(&mesh, id, "TEXCOORD_0")?,
        None => Vec::new(),
    };
    let indices: Vec<u32> = mesh.faces().as_flattened().iter().map(|p| p.0).collect();
    if let Some(&bad) = indices.iter().find(|&&i| i as usize >= n) {
        return Err(format!(
            "the Draco data has a face using point {bad} of {n}"
        ));
    }

    // The accessors keep the counts of the uncompressed data: they must agree.
    let check = |what: &str, accessor: Option<::gltf::Accessor>, got: usize| match accessor {
        Some(a) if a.count() != got => Err(format!(
            "accessor {} ({what}) declares {} elements but the Draco data decodes to {got}",
            a.index(),
            a.count()
        )),
        _ => Ok(()),
    };
    use ::gltf::mesh::Semantic;
    check("POSITION", prim.get(&Semantic::Positions), positions.len())?;
    if !normals.is_empty() {
        check("NORMAL", prim.get(&Semantic::Normals), normals.len())?;
    }
    if !uvs.is_empty() {
        check("TEXCOORD_0", prim.get(&Semantic::TexCoords(0)), uvs.len())?;
    }
    check("indices", prim.indices(), indices.len())?;
    Ok(DracoPrimitive {
        positions,
        normals,
        uvs,
        indices,
    })
}

/// The values of the Draco attribute with unique id `id`, `N` components per point, one per
/// point of the mesh. Integer attributes flagged `normalized` map to [0, 1] (unsigned,
/// x / (2ᵇ − 1)) or [−1, 1] (signed, max(x / (2ᵇ⁻¹ − 1), −1)), as glTF's normalized
/// accessors do.
fn read_attribute<const N: usize>(
    mesh: &Mesh,
    id: u32,
    semantic: &str,
) -> Result<Vec<[f32; N]>, String> {
    let att: &PointAttribute = mesh.attribute_by_unique_id(id).ok_or_else(|| {
        format!("{EXTENSION}: {semantic} names Draco attribute {id}, which the data lacks")
    })?;
    let have = att.num_components() as usize;
    if have != N {
        return Err(format!(
            "Draco attribute {id} ({semantic}) has {have} components per point, {N} expected"
        ));
    }
    let scale = if att.normalized() {
        match att.data_type() {
            DataType::Uint8 => 1.0 / 255.0,
            DataType::Int8 => 1.0 / 127.0,
            DataType::Uint16 => 1.0 / 65535.0,
            DataType::Int16 => 1.0 / 32767.0,
            DataType::Uint32 => 1.0 / 4294967295.0,
            DataType::Int32 => 1.0 / 2147483647.0,
            _ => 1.0,
        }
    } else {
        1.0
    };
    let n = mesh.num_points();
    let flat = att.read_f32s(n, N);
    Ok(flat
        .chunks_exact(N)
        .map(|c| {
            std::array::from_fn(|k| {
                if att.normalized() {
                    (c[k] * scale).max(-1.0)
                } else {
                    c[k]
                }
            })
        })
        .collect())
}

//! The PLY reader's tests: every encoding, scalar type and element, and the errors of
//! broken files.

use super::*;

fn parse_str(text: &str) -> Result<PlyMesh, PlyError> {
    parse_ply(text.as_bytes(), "t.ply")
}

fn mesh(text: &str) -> TriangleMesh {
    parse_str(text).unwrap_or_else(|e| panic!("{e}")).mesh
}

fn error(data: &[u8]) -> String {
    match parse_ply(data, "t.ply") {
        Ok(m) => panic!("expected an error, read {m:?}"),
        Err(e) => e.to_string(),
    }
}

#[track_caller]
fn assert_contains(text: &str, part: &str) {
    assert!(text.contains(part), "{text:?} does not contain {part:?}");
}

const SQUARE: &str = "ply
format ascii 1.0
comment a unit square as one quad
element vertex 4
property float x
property float y
property float z
element face 1
property list uchar int vertex_indices
end_header
0 0 0
1 0 0
1 1 0
0 1 0
4 0 1 2 3
";

#[test]
fn ascii_quad_becomes_two_triangles() {
    let m = mesh(SQUARE);
    assert_eq!(
        m.positions,
        vec![
            PackedVec3::new(0.0, 0.0, 0.0),
            PackedVec3::new(1.0, 0.0, 0.0),
            PackedVec3::new(1.0, 1.0, 0.0),
            PackedVec3::new(0.0, 1.0, 0.0),
        ]
    );
    assert_eq!(m.indices, vec![0, 1, 2, 0, 2, 3]);
    assert!(m.normals.is_empty() && m.uvs.is_empty());
    assert!(!m.flip_normal);
}

/// A triangle, a quad and a pentagon: the quad's two triangles come last, and pbrt-v4's split
/// gives the other faces' triangles and one bilinear patch (v₀, v₁, v₃, v₂).
#[test]
fn quads_become_bilinear_patches_in_pbrts_order() {
    let text = "ply\nformat ascii 1.0\nelement vertex 6\nproperty float x\nproperty float y\n\
                property float z\nproperty float u\nproperty float v\nelement face 3\n\
                property list uchar int vertex_indices\nend_header\n\
                0 0 0 0 0\n1 0 0 1 0\n1 1 0 1 1\n0 1 0 0 1\n2 0 0 2 0\n2 1 0 2 1\n\
                3 1 4 5\n4 0 1 2 3\n5 0 1 4 5 2\n";
    let ply = parse_str(text).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(ply.quads, 1);
    assert_eq!(
        ply.mesh.indices,
        vec![1, 4, 5, 0, 1, 4, 0, 4, 5, 0, 5, 2, 0, 1, 2, 0, 2, 3]
    );
    let (tris, patches) = ply.clone().split_quads();
    let (tris, patches) = (tris.expect("triangles"), patches.expect("patches"));
    assert_eq!(tris.indices, vec![1, 4, 5, 0, 1, 4, 0, 4, 5, 0, 5, 2]);
    assert_eq!(patches.indices, vec![0, 1, 3, 2]);
    assert_eq!(patches.positions, ply.mesh.positions);
    assert_eq!(patches.uvs, ply.mesh.uvs);
    // Quads only: no triangle mesh, and the patches take the vertices read (not a copy).
    let ply = parse_str(SQUARE).unwrap();
    let read = ply.mesh.positions.as_ptr();
    let (tris, patches) = ply.split_quads();
    assert!(tris.is_none());
    let patches = patches.expect("patches");
    assert_eq!(patches.indices, vec![0, 1, 3, 2]);
    assert_eq!(patches.positions.as_ptr(), read);
    // No quads: no patches.
    let tri = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n\
               property float z\nelement face 1\nproperty list uchar int vertex_indices\n\
               end_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
    let (tris, patches) = parse_str(tri).unwrap().split_quads();
    assert_eq!(tris.expect("a triangle").indices, vec![0, 1, 2]);
    assert!(patches.is_none());
}

#[test]
fn crlf_header_and_polygons_as_fans() {
    let text = "ply\r\nformat ascii 1.0\r\nelement vertex 5\r\nproperty double x\r\n\
                property double y\r\nproperty double z\r\nelement face 2\r\n\
                property list uchar uint vertex_index\r\nend_header\r\n\
                0 0 0\r\n1 0 0\r\n2 1 0\r\n1 2 0\r\n0 1 0\r\n5 0 1 2 3 4\r\n3 4 3 2\r\n";
    let m = mesh(text);
    assert_eq!(m.positions.len(), 5);
    assert_eq!(m.indices, vec![0, 1, 2, 0, 2, 3, 0, 3, 4, 4, 3, 2]);
}

#[test]
fn normals_and_each_uv_spelling() {
    for (u, v) in [
        ("u", "v"),
        ("s", "t"),
        ("texture_u", "texture_v"),
        ("texture_s", "texture_t"),
    ] {
        let text = format!(
            "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n\
             property float z\nproperty float nx\nproperty float ny\nproperty float nz\n\
             property float {u}\nproperty float {v}\nelement face 1\n\
             property list uchar int vertex_indices\nend_header\n\
             0 0 0 0 0 1 0 0\n1 0 0 0 0 1 1 0\n0 1 0 0 0 1 0.25 0.75\n3 0 1 2\n"
        );
        let m = mesh(&text);
        assert_eq!(m.normals, vec![PackedVec3::Z; 3], "{u} {v}");
        assert_eq!(
            m.uvs,
            vec![
                Vec2::new(0.0, 0.0),
                Vec2::new(1.0, 0.0),
                Vec2::new(0.25, 0.75)
            ],
            "{u} {v}"
        );
    }
}

#[test]
fn unknown_elements_and_properties_are_skipped() {
    // A list and scalars on the vertex, a material element before the faces, a face list
    // ahead of the indices and a scalar after them, and an edge element at the end.
    let text = "ply
format ascii 1.0
obj_info made by hand
element vertex 3
property list uchar float weights
property float x
property uchar red
property float y
property float z
property double confidence
element material 2
property list int int ids
property float shine
element face 1
property list uchar float texcoord
property list uchar int vertex_indices
property int flags
element edge 1
property int vertex1
property int vertex2
end_header
2 0.5 0.5 0 9 0 0 0.1
0 1 7 0 0 0.2
1 7.5 0 7 1 0 0.3
3 1 2 3 0.5
0 2.5
6 0 0 1 0 0 1 3 0 1 2 77
0 1
";
    let m = mesh(text);
    assert_eq!(
        m.positions,
        vec![
            PackedVec3::ZERO,
            PackedVec3::new(1.0, 0.0, 0.0),
            PackedVec3::new(0.0, 1.0, 0.0)
        ]
    );
    assert_eq!(m.indices, vec![0, 1, 2]);
}

/// The square of [`SQUARE`] in binary, with normals, a double coordinate and every
/// integer type somewhere, in the byte order `be`.
fn binary_square(be: bool) -> Vec<u8> {
    let order = if be { "big" } else { "little" };
    let mut d = format!(
        "ply\nformat binary_{order}_endian 1.0\ncomment every type\n\
         element vertex 4\nproperty float x\nproperty double y\nproperty float32 z\n\
         property char a\nproperty ushort b\nproperty short c\nproperty uint d\n\
         property float nx\nproperty float ny\nproperty float nz\n\
         element face 2\nproperty list ushort int8 junk\n\
         property list uint8 uint16 vertex_indices\nproperty list int uint32 more\n\
         element strip 1\nproperty list int16 int32 xs\nend_header\n"
    )
    .into_bytes();
    macro_rules! put {
        ($v:expr) => {
            d.extend_from_slice(&if be {
                $v.to_be_bytes()
            } else {
                $v.to_le_bytes()
            })
        };
    }
    for (x, y) in [(0.0f32, 0.0f64), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)] {
        put!(x);
        put!(y);
        put!(0.0f32);
        put!(-3i8);
        put!(65000u16);
        put!(-2i16);
        put!(4_000_000_000u32);
        put!(0.0f32);
        put!(0.0f32);
        put!(1.0f32);
    }
    // Face 0: a triangle; face 1: the other half of the square.
    for tri in [[0u16, 1, 2], [0, 2, 3]] {
        put!(2u16);
        put!(-1i8);
        put!(5i8);
        put!(3u8);
        for i in tri {
            put!(i);
        }
        put!(1i32);
        put!(7u32);
    }
    put!(2i16);
    put!(1i32);
    put!(2i32);
    d
}

#[test]
fn binary_both_byte_orders() {
    for be in [false, true] {
        let m = parse_ply(&binary_square(be), "t.ply")
            .unwrap_or_else(|e| panic!("{e}"))
            .mesh;
        assert_eq!(m.positions[2], PackedVec3::new(1.0, 1.0, 0.0), "be {be}");
        assert_eq!(m.positions[3], PackedVec3::new(0.0, 1.0, 0.0), "be {be}");
        assert_eq!(m.normals, vec![PackedVec3::Z; 4], "be {be}");
        assert_eq!(m.indices, vec![0, 1, 2, 0, 2, 3], "be {be}");
    }
}

#[test]
fn binary_truncated_anywhere_is_an_error() {
    let full = binary_square(false);
    let body_start = full.windows(11).position(|w| w == b"end_header\n").unwrap() + 11;
    // 4 vertices of 37 bytes, 2 faces of 19, a strip of 10.
    assert_eq!(full.len() - body_start, 4 * 37 + 2 * 19 + 10);
    for cut in body_start..full.len() {
        let e = error(&full[..cut]);
        // Too short for the header's counts, or cut inside a record.
        assert!(
            e.starts_with("t.ply: the header announces ")
                || (e.starts_with("t.ply: the data ends inside ")
                    && e.ends_with("the file is truncated")),
            "cut at {cut}: {e}"
        );
    }
    // Cut inside the second face's index list.
    let e = error(&full[..body_start + 4 * 37 + 19 + 6]);
    assert_eq!(
        e,
        "t.ply: the data ends inside face 1 of 2: the file is truncated"
    );
}

#[test]
fn ascii_truncated() {
    let text = SQUARE.trim_end().trim_end_matches("3");
    let e = error(text.as_bytes());
    assert_eq!(
        e,
        "t.ply: the data ends inside face 0 of 1: the file is truncated"
    );
}

#[test]
fn out_of_range_and_negative_indices() {
    let e = error(SQUARE.replace("4 0 1 2 3", "4 0 1 9000 3").as_bytes());
    assert_eq!(
        e,
        "t.ply: face 0 refers to vertex 9000 but there are 4 vertices"
    );
    let e = error(SQUARE.replace("4 0 1 2 3", "4 0 -1 2 3").as_bytes());
    assert_contains(&e, "face 0 refers to vertex -1");
}

#[test]
fn non_finite_positions_are_refused() {
    for bad in ["nan", "inf", "-inf", "1e39"] {
        let e = error(
            SQUARE
                .replace("1 1 0\n", &format!("1 {bad} 0\n"))
                .as_bytes(),
        );
        assert_contains(&e, "t.ply: vertex 2 has position (1, ");
        assert_contains(&e, "which is not finite");
    }
}

#[test]
fn not_a_number_names_the_word() {
    let e = error(SQUARE.replace("1 1 0\n", "1 one 0\n").as_bytes());
    assert_eq!(e, "t.ply: vertex 2: \"one\" is not a number");
}

#[test]
fn huge_counts_are_refused_before_reading() {
    // 2^40 faces in a file of a few hundred bytes: refused from the header, at once.
    let huge = "element face 1099511627776";
    let ascii = SQUARE.replace("element face 1", huge);
    let full = binary_square(false);
    let end = full.windows(10).position(|w| w == b"end_header").unwrap();
    let mut binary = String::from_utf8(full[..end].to_vec())
        .unwrap()
        .replace("element face 2", huge)
        .into_bytes();
    binary.extend_from_slice(&full[end..]);
    for data in [ascii.into_bytes(), binary] {
        let start = std::time::Instant::now();
        let e = error(&data);
        assert!(start.elapsed().as_secs_f64() < 0.5);
        assert_contains(
            &e,
            "the header announces 1099511627776 \"face\" elements, more than the",
        );
    }
    // So is an unknown element that would be skipped.
    let text = SQUARE.replace(
        "end_header",
        "element blob 4000000000\nproperty double w\nend_header",
    );
    assert_contains(&error(text.as_bytes()), "4000000000 \"blob\" elements");
    // A list length is not trusted either: the reader stops where the data does.
    let mut d = binary_square(false);
    let at = d.len() - 10;
    d[at..at + 2].copy_from_slice(&i16::MAX.to_le_bytes());
    assert_contains(&error(&d), "inside strip 0 of 1");
}

#[test]
fn header_errors() {
    assert_contains(&error(b"PK\x03\x04"), "not a PLY file");
    assert_contains(&error(b"ply\nformat ascii 1.0\n"), "no \"end_header\"");
    let e = error(
        SQUARE
            .replace("format ascii", "format binary_middle_endian")
            .as_bytes(),
    );
    assert_contains(&e, "header line 2: unknown format \"binary_middle_endian\"");
    let e = error(SQUARE.replace("1.0", "2.0").as_bytes());
    assert_contains(&e, "PLY version 2.0");
    let e = error(
        SQUARE
            .replace("property float y", "property float64x y")
            .as_bytes(),
    );
    assert_contains(&e, "header line 6: unknown type \"float64x\"");
    let e = error(SQUARE.replace("list uchar", "list float").as_bytes());
    assert_contains(&e, "floating-point type");
    let e = error(SQUARE.replace("comment", "remark").as_bytes());
    assert_contains(&e, "header line 3: unknown keyword \"remark\"");
    let e = error(SQUARE.replace("format ascii 1.0\n", "").as_bytes());
    assert_contains(&e, "no \"format\" line");
    let e = error(
        SQUARE
            .replace("property float z", "property float w")
            .as_bytes(),
    );
    assert_contains(&e, "no x, y and z");
    let e = error(SQUARE.replace("vertex_indices", "corners").as_bytes());
    assert_contains(&e, "\"face\" element has no \"vertex_indices\" list");
}

#[test]
fn short_faces_are_counted_and_skipped() {
    let text = SQUARE
        .replace("element face 1", "element face 3")
        .replace("4 0 1 2 3\n", "2 0 1\n3 0 1 2\n0\n");
    let ply = parse_str(&text).unwrap();
    assert_eq!(ply.skipped_faces, 2);
    assert_eq!(ply.mesh.indices, vec![0, 1, 2]);
}

#[test]
fn triangle_strips_alternate_and_restart() {
    let text = "ply\nformat ascii 1.0\nelement vertex 6\nproperty float x\n\
                property float y\nproperty float z\nelement tristrips 1\n\
                property list int int vertex_indices\nend_header\n\
                0 0 0\n1 0 0\n0 1 0\n1 1 0\n0 2 0\n1 2 0\n\
                9 0 1 2 3 -1 2 3 4 5\n";
    let m = mesh(text);
    assert_eq!(m.indices, vec![0, 1, 2, 2, 1, 3, 2, 3, 4, 4, 3, 5]);
}

#[test]
fn gzipped_files_are_read() {
    use flate2::Compression;
    use flate2::write::GzEncoder;
    use std::io::Write;
    let dir = lancer_testing::ScratchDir::new("ply-gzip");
    let path = dir.join("square.ply.gz");
    let mut enc = GzEncoder::new(Vec::new(), Compression::default());
    enc.write_all(SQUARE.as_bytes()).unwrap();
    std::fs::write(&path, enc.finish().unwrap()).unwrap();
    let m = read_ply(&path).unwrap().mesh;
    assert_eq!(m.indices, vec![0, 1, 2, 0, 2, 3]);
    // Not gzip data behind the name: an error naming the file.
    let bad = dir.join("plain.ply.gz");
    std::fs::write(&bad, SQUARE).unwrap();
    let e = read_ply(&bad).unwrap_err();
    assert_eq!(e.file, bad.display().to_string());
    assert_contains(&e.message, "cannot decompress the file");
}

#[test]
fn missing_file_names_it() {
    let e = read_ply(Path::new("/nonexistent/bunny.ply")).unwrap_err();
    assert_eq!(e.file, "/nonexistent/bunny.ply");
    assert_contains(&e.to_string(), "cannot read the file");
}

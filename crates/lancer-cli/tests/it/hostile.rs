//! Hostile inputs: files that lie about their size, indices that point nowhere, images that
//! claim to be enormous, scenes nested without end. Each must end with a clear error naming the
//! file, exit status 2, no panic, no image written, and without the allocator being the one to
//! notice: the peak memory of every run stays under 200 MiB.
//!
//! The inputs are made here, byte by byte, so the list documents what each one lies about.

use crate::common::*;
use std::io::Write;
use std::path::Path;
use std::process::Stdio;
use std::time::{Duration, Instant};

/// The peak memory any one run may use.
const MAX_RSS_KIB: i64 = 200 * 1024;

/// A PLY header with `verts` float x/y/z vertices and `faces` faces, in `format`.
fn ply_header(format: &str, verts: u64, faces: u64) -> Vec<u8> {
    format!(
        "ply\nformat {format} 1.0\nelement vertex {verts}\nproperty float x\nproperty float y\n\
         property float z\nelement face {faces}\nproperty list uchar int vertex_indices\nend_header\n"
    )
    .into_bytes()
}

/// Little-endian vertices of one triangle.
fn triangle_vertices() -> Vec<u8> {
    [0.0f32, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0]
        .iter()
        .flat_map(|v| v.to_le_bytes())
        .collect()
}

/// A PNG signature and IHDR chunk claiming `w`×`h` RGB pixels, and no image data.
fn png_claiming(w: u32, h: u32) -> Vec<u8> {
    let mut b = vec![0x89, b'P', b'N', b'G', 0x0d, 0x0a, 0x1a, 0x0a];
    b.extend_from_slice(&13u32.to_be_bytes());
    b.extend_from_slice(b"IHDR");
    b.extend_from_slice(&w.to_be_bytes());
    b.extend_from_slice(&h.to_be_bytes());
    b.extend_from_slice(&[8, 2, 0, 0, 0]);
    b.extend_from_slice(&[0, 0, 0, 0]); // a wrong CRC too
    b
}

/// An OpenEXR header whose data window claims `side`×`side` pixels, then a few bytes.
fn exr_claiming(side: i32) -> Vec<u8> {
    fn attr(out: &mut Vec<u8>, name: &str, ty: &str, data: &[u8]) {
        out.extend_from_slice(name.as_bytes());
        out.push(0);
        out.extend_from_slice(ty.as_bytes());
        out.push(0);
        out.extend_from_slice(&(data.len() as i32).to_le_bytes());
        out.extend_from_slice(data);
    }
    let mut channels = Vec::new();
    for c in ["B", "G", "R"] {
        channels.extend_from_slice(c.as_bytes());
        channels.push(0);
        channels.extend_from_slice(&2i32.to_le_bytes()); // float
        channels.extend_from_slice(&[0, 0, 0, 0]);
        channels.extend_from_slice(&1i32.to_le_bytes());
        channels.extend_from_slice(&1i32.to_le_bytes());
    }
    channels.push(0);
    let window: Vec<u8> = [0, 0, side - 1, side - 1]
        .iter()
        .flat_map(|v: &i32| v.to_le_bytes())
        .collect();
    let mut b = vec![0x76, 0x2f, 0x31, 0x01, 2, 0, 0, 0];
    attr(&mut b, "channels", "chlist", &channels);
    attr(&mut b, "compression", "compression", &[0]);
    attr(&mut b, "dataWindow", "box2i", &window);
    attr(&mut b, "displayWindow", "box2i", &window);
    attr(&mut b, "lineOrder", "lineOrder", &[0]);
    attr(&mut b, "pixelAspectRatio", "float", &1f32.to_le_bytes());
    attr(&mut b, "screenWindowCenter", "v2f", &[0; 8]);
    attr(&mut b, "screenWindowWidth", "float", &1f32.to_le_bytes());
    b.push(0);
    b.extend_from_slice(&[0; 64]);
    b
}

/// A scene that reads `body` after a small camera, film and light.
fn scene_with(body: &str) -> String {
    format!(
        "LookAt 0 0 5  0 0 0  0 1 0\nCamera \"perspective\"\n\
         Film \"rgb\" \"integer xresolution\" [32] \"integer yresolution\" [32]\nWorldBegin\n\
         LightSource \"point\" \"point3 from\" [0 0 5] \"rgb I\" [10 10 10]\n{body}\n"
    )
}

/// One hostile input: its name, the files to write, the file to render, and words the error
/// must contain.
struct Case {
    name: &'static str,
    files: Vec<(&'static str, Vec<u8>)>,
    scene: &'static str,
    words: &'static str,
}

/// A [`Case`].
fn case(
    name: &'static str,
    files: Vec<(&'static str, Vec<u8>)>,
    scene: &'static str,
    words: &'static str,
) -> Case {
    Case {
        name,
        files,
        scene,
        words,
    }
}

/// The hostile inputs.
fn cases() -> Vec<Case> {
    let mut truncated = ply_header("binary_little_endian", 3, 1);
    truncated.extend(triangle_vertices());
    truncated.extend([3u8, 0, 0, 0, 0, 1]); // the face's indices stop after one and a half
    let mut many_faces = ply_header("binary_little_endian", 3, 1 << 40);
    many_faces.extend(triangle_vertices());
    many_faces.extend([3u8, 0, 0, 0, 0, 1, 0, 0, 0, 2, 0, 0, 0]);
    let mut many_verts = ply_header("ascii", 1 << 40, 1);
    many_verts.extend(b"0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n");
    let mut bad_index = ply_header("ascii", 3, 1);
    bad_index.extend(b"0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n");
    let texture = |file: &str| {
        scene_with(&format!(
            "Texture \"t\" \"spectrum\" \"imagemap\" \"string filename\" \"{file}\"\n\
             Material \"diffuse\" \"texture reflectance\" \"t\"\nShape \"sphere\""
        ))
        .into_bytes()
    };
    let nested = scene_with(&format!(
        "{}Shape \"sphere\"\n{}",
        "AttributeBegin\n".repeat(100_000),
        "AttributeEnd\n".repeat(100_000)
    ));
    vec![
        case(
            "truncated-binary-ply",
            vec![("t.ply", truncated)],
            "t.ply",
            "t.ply",
        ),
        case(
            "ply-2^40-faces",
            vec![("f.ply", many_faces)],
            "f.ply",
            "f.ply",
        ),
        case(
            "ply-2^40-vertices",
            vec![("v.ply", many_verts)],
            "v.ply",
            "v.ply",
        ),
        case(
            "ply-index-out-of-range",
            vec![("i.ply", bad_index)],
            "i.ply",
            "i.ply",
        ),
        case(
            "obj-index-out-of-range",
            vec![("o.obj", b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 7\n".to_vec())],
            "o.obj",
            "out of range",
        ),
        case(
            "obj-relative-index-before-first",
            vec![("r.obj", b"v 0 0 0\nf -1 -2 -3\n".to_vec())],
            "r.obj",
            "r.obj:2",
        ),
        case(
            "png-100000x100000",
            vec![
                ("big.png", png_claiming(100_000, 100_000)),
                ("s.pbrt", texture("big.png")),
            ],
            "s.pbrt",
            "big.png",
        ),
        case(
            "exr-2^30-pixels-a-side",
            vec![
                ("big.exr", exr_claiming(1 << 30)),
                ("s.pbrt", texture("big.exr")),
            ],
            "s.pbrt",
            "big.exr",
        ),
        case(
            "scene-including-itself",
            vec![(
                "self.pbrt",
                scene_with("Include \"self.pbrt\"").into_bytes(),
            )],
            "self.pbrt",
            "self.pbrt",
        ),
        case(
            "100000-nested-blocks",
            vec![("deep.pbrt", nested.into_bytes())],
            "deep.pbrt",
            "nested",
        ),
        case(
            "film-too-large-for-memory",
            vec![(
                "film.pbrt",
                "Film \"rgb\" \"integer xresolution\" [65536] \"integer yresolution\" [65536]\n\
                 WorldBegin\nShape \"sphere\"\n"
                    .as_bytes()
                    .to_vec(),
            )],
            "film.pbrt",
            "memory",
        ),
    ]
}

/// Runs lancer on `scene` in `dir`, with a watchdog against hangs (not a timing: the
/// acceptance script times the runs).
fn run_guarded(dir: &Path, scene: &str) -> (Option<i32>, String) {
    let mut child = lancer()
        .current_dir(dir)
        .args(["render", scene, "-o", "out.png", "--quiet"])
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .expect("lancer runs");
    let start = Instant::now();
    loop {
        if let Some(status) = child.try_wait().unwrap() {
            let mut err = String::new();
            use std::io::Read;
            child
                .stderr
                .take()
                .unwrap()
                .read_to_string(&mut err)
                .unwrap();
            return (status.code(), err);
        }
        if start.elapsed() > Duration::from_secs(60) {
            let _ = child.kill();
            let _ = child.wait();
            return (None, format!("{scene}: still running after 60 s, killed"));
        }
        std::thread::sleep(Duration::from_millis(10));
    }
}

/// The largest peak resident size of the children waited for so far, in KiB.
fn children_max_rss_kib() -> i64 {
    // SAFETY: getrusage writes into the struct we pass and nothing else.
    unsafe {
        let mut usage: libc::rusage = std::mem::zeroed();
        assert_eq!(libc::getrusage(libc::RUSAGE_CHILDREN, &mut usage), 0);
        usage.ru_maxrss
    }
}

/// One test, so that the children's peak memory is that of these runs only.
#[test]
fn hostile_inputs_fail_cleanly_and_cheaply() {
    let mut failures = Vec::new();
    for Case {
        name,
        files,
        scene,
        words,
    } in cases()
    {
        let dir = ScratchDir::new(&format!("hostile-{name}"));
        for (file, bytes) in &files {
            std::fs::File::create(dir.join(file))
                .and_then(|mut f| f.write_all(bytes))
                .unwrap();
        }
        let before = children_max_rss_kib();
        let (code, err) = run_guarded(&dir, scene);
        let peak = children_max_rss_kib();
        let mut problems = Vec::new();
        if code != Some(2) {
            problems.push(format!("exit status {code:?}, expected 2"));
        }
        if err.contains("panicked") {
            problems.push("panicked".into());
        }
        if !err.contains(words) {
            problems.push(format!("the message does not mention '{words}'"));
        }
        if dir.join("out.png").exists() {
            problems.push("an image was written".into());
        }
        if peak > before.max(MAX_RSS_KIB) {
            problems.push(format!("peak memory {peak} KiB > {MAX_RSS_KIB} KiB"));
        }
        if !problems.is_empty() {
            failures.push(format!(
                "{name}: {}\n  stderr: {}",
                problems.join("; "),
                err.trim()
            ));
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

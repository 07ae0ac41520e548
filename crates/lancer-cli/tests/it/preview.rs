//! Live outputs and reports of `lancer render` (`--display-server`, `--preview`, `--stats json`)
//! and `lancer info`.

use crate::common::{ScratchDir, data, read_exr, run_in};
use std::collections::HashMap;
use std::io::Read;
use std::net::TcpListener;
use std::path::Path;

/// One packet of tev's protocol, as an independent reader understands it.
#[derive(Debug)]
enum TevPacket {
    Create {
        name: String,
        width: i32,
        height: i32,
        channels: Vec<String>,
    },
    Update {
        name: String,
        channels: Vec<String>,
        rect: [i32; 4],
        /// Per channel, its values over the rectangle, row-major.
        values: Vec<Vec<f32>>,
    },
}

/// A cursor over one packet's bytes.
struct Fields<'a>(&'a [u8]);

impl Fields<'_> {
    fn take(&mut self, n: usize) -> &[u8] {
        assert!(self.0.len() >= n, "packet shorter than its fields");
        let (a, b) = self.0.split_at(n);
        self.0 = b;
        a
    }
    fn u8(&mut self) -> u8 {
        self.take(1)[0]
    }
    fn i32(&mut self) -> i32 {
        i32::from_le_bytes(self.take(4).try_into().unwrap())
    }
    fn i64(&mut self) -> i64 {
        i64::from_le_bytes(self.take(8).try_into().unwrap())
    }
    fn string(&mut self) -> String {
        let end = self.0.iter().position(|&b| b == 0).expect("NUL-terminated");
        let s = String::from_utf8(self.0[..end].to_vec()).unwrap();
        self.0 = &self.0[end + 1..];
        s
    }
}

/// Splits a byte stream into tev packets (`u32` length including itself, `u8` type, fields).
fn parse_tev(mut bytes: &[u8]) -> Vec<TevPacket> {
    let mut out = Vec::new();
    while !bytes.is_empty() {
        assert!(bytes.len() >= 5, "truncated packet header");
        let len = u32::from_le_bytes(bytes[..4].try_into().unwrap()) as usize;
        assert!(
            len >= 5 && len <= bytes.len(),
            "packet length {len} out of range"
        );
        let mut f = Fields(&bytes[4..len]);
        bytes = &bytes[len..];
        match f.u8() {
            4 => {
                let _focus = f.u8();
                let name = f.string();
                let (width, height, n) = (f.i32(), f.i32(), f.i32());
                let channels = (0..n).map(|_| f.string()).collect();
                assert!(f.0.is_empty(), "trailing bytes in CreateImage");
                out.push(TevPacket::Create {
                    name,
                    width,
                    height,
                    channels,
                });
            }
            6 => {
                let _focus = f.u8();
                let name = f.string();
                let n = f.i32() as usize;
                let channels: Vec<String> = (0..n).map(|_| f.string()).collect();
                let rect = [f.i32(), f.i32(), f.i32(), f.i32()];
                let offsets: Vec<i64> = (0..n).map(|_| f.i64()).collect();
                let strides: Vec<i64> = (0..n).map(|_| f.i64()).collect();
                let floats: Vec<f32> =
                    f.0.chunks_exact(4)
                        .map(|c| f32::from_le_bytes(c.try_into().unwrap()))
                        .collect();
                assert_eq!(f.0.len() % 4, 0);
                let pixels = (rect[2] * rect[3]) as usize;
                let values = (0..n)
                    .map(|c| {
                        (0..pixels)
                            .map(|i| floats[(offsets[c] + i as i64 * strides[c]) as usize])
                            .collect()
                    })
                    .collect();
                // The payload holds exactly what the offsets and strides reach.
                let need = (0..n)
                    .map(|c| offsets[c] + (pixels as i64 - 1) * strides[c] + 1)
                    .max()
                    .unwrap();
                assert_eq!(floats.len() as i64, need);
                out.push(TevPacket::Update {
                    name,
                    channels,
                    rect,
                    values,
                });
            }
            t => panic!("unexpected packet type {t}"),
        }
    }
    out
}

#[test]
fn display_server_streams_every_pixel_in_tevs_protocol() {
    let dir = ScratchDir::new("tev");
    let listener = TcpListener::bind("127.0.0.1:0").unwrap();
    let port = listener.local_addr().unwrap().port();
    let reader = std::thread::spawn(move || {
        let (mut s, _) = listener.accept().unwrap();
        let mut bytes = Vec::new();
        s.read_to_end(&mut bytes).unwrap();
        bytes
    });
    let out = dir.join("tev.exr");
    let o = run_in(
        &dir,
        &[
            "render",
            data("course/03-objects.pbrt").to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
            "--resolution",
            "70x45",
            "--spp",
            "4",
            "--quiet",
            "--display-server",
            &format!("127.0.0.1:{port}"),
        ],
    );
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let packets = parse_tev(&reader.join().unwrap());

    let (w, h) = (70usize, 45usize);
    let name = out.display().to_string();
    match &packets[0] {
        TevPacket::Create {
            name: n,
            width,
            height,
            channels,
        } => {
            assert_eq!(n, &name);
            assert_eq!((*width, *height), (w as i32, h as i32));
            assert_eq!(channels, &["R", "G", "B"]);
        }
        p => panic!("the stream must open with CreateImage, not {p:?}"),
    }
    assert!(
        packets[1..]
            .iter()
            .all(|p| matches!(p, TevPacket::Update { .. }))
    );
    // Per pixel: how many updates covered it, and its last value.
    let mut covered = vec![0u32; w * h];
    let mut last = vec![[f32::NAN; 3]; w * h];
    let mut coverage_before_last = Vec::new();
    let mut values_before_last = Vec::new();
    for p in &packets[1..] {
        let TevPacket::Update {
            name: n,
            channels,
            rect,
            values,
        } = p
        else {
            unreachable!()
        };
        assert_eq!(n, &name);
        assert_eq!(channels, &["R", "G", "B"]);
        let [x, y, rw, rh] = *rect;
        assert!(x >= 0 && y >= 0 && rw > 0 && rh > 0);
        assert!((x + rw) as usize <= w && (y + rh) as usize <= h, "{rect:?}");
        coverage_before_last.push(covered.clone());
        values_before_last.push(last.clone());
        for j in 0..rh as usize {
            for i in 0..rw as usize {
                let k = (y as usize + j) * w + x as usize + i;
                covered[k] += 1;
                let t = j * rw as usize + i;
                last[k] = [values[0][t], values[1][t], values[2][t]];
            }
        }
    }
    assert!(
        covered.iter().all(|&c| c >= 2),
        "tiles and the final update cover every pixel"
    );
    // Tiles were streamed as they finished, not only the final image: before the final
    // update (one strip for so small an image) every pixel had already been sent.
    assert!(packets.len() > 3, "{} packets", packets.len());
    let before_final = coverage_before_last.last().unwrap();
    assert!(before_final.iter().all(|&c| c >= 1));

    let img = read_exr(&out);
    assert_eq!((img.width, img.height), (w, h));
    let max_err = |values: &[[f32; 3]]| {
        let mut m = 0.0f32;
        for (px, want) in values.iter().zip(&img.rgb) {
            for (&v, &e) in px.iter().zip(want) {
                let e = e as f32;
                m = m.max((v - e).abs() / e.abs().max(1e-3));
            }
        }
        m
    };
    let final_err = max_err(&last);
    assert!(final_err < 1e-6, "stream and EXR differ by {final_err}");
    // Each tile is rendered in one pass here, so its update already holds the final pixels.
    let tiles_err = max_err(values_before_last.last().unwrap());
    assert!(
        tiles_err < 1e-6,
        "tile updates and EXR differ by {tiles_err}"
    );
    let mean: f32 = last.iter().map(|p| p[0] + p[1] + p[2]).sum::<f32>() / (w * h) as f32;
    assert!(mean > 0.01, "the streamed image is black");
}

#[test]
fn an_unreachable_display_server_is_a_warning() {
    let dir = ScratchDir::new("tev-down");
    let port = {
        let l = TcpListener::bind("127.0.0.1:0").unwrap();
        l.local_addr().unwrap().port()
    };
    let out = dir.join("out.png");
    let o = run_in(
        &dir,
        &[
            "render",
            data("course/01-sphere.pbrt").to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
            "--resolution",
            "32x24",
            "--spp",
            "1",
            "--quiet",
            "--display-server",
            &format!("127.0.0.1:{port}"),
        ],
    );
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("warning: display server"), "{err}");
    assert!(out.is_file());
}

fn png_pixels(path: &Path) -> (u32, u32, Vec<u8>) {
    let dec = png::Decoder::new(std::io::BufReader::new(std::fs::File::open(path).unwrap()));
    let mut r = dec.read_info().unwrap();
    let mut buf = vec![0; r.output_buffer_size().unwrap()];
    let info = r.next_frame(&mut buf).unwrap();
    buf.truncate(info.buffer_size());
    (info.width, info.height, buf)
}

#[test]
fn preview_leaves_the_final_image_as_a_valid_png() {
    let dir = ScratchDir::new("preview");
    let out = dir.join("out.png");
    let prev = dir.join("prev.png");
    let o = run_in(
        &dir,
        &[
            "render",
            data("course/03-objects.pbrt").to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
            "--resolution",
            "48x30",
            "--spp",
            "2",
            "--quiet",
            "--preview",
            prev.to_str().unwrap(),
            "--preview-every",
            "0.05",
        ],
    );
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let (pw, ph, p) = png_pixels(&prev);
    let (ow, oh, q) = png_pixels(&out);
    assert_eq!((pw, ph), (48, 30));
    assert_eq!((ow, oh), (48, 30));
    assert_eq!(p, q, "the last preview is the final image");
    assert!(p.iter().any(|&b| b > 0));
    // Written atomically: no temporary file is left behind.
    let names: Vec<String> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    assert_eq!(names.len(), 2, "{names:?}");
}

#[test]
fn preview_must_be_a_png_in_a_writable_folder() {
    let dir = ScratchDir::new("preview-bad");
    for (prev, needle) in [
        (dir.join("prev.exr"), "PNG"),
        (dir.join("missing/prev.png"), "does not exist"),
    ] {
        let o = run_in(
            &dir,
            &[
                "render",
                data("course/01-sphere.pbrt").to_str().unwrap(),
                "-o",
                dir.join("o.png").to_str().unwrap(),
                "--preview",
                prev.to_str().unwrap(),
            ],
        );
        assert_eq!(o.status.code(), Some(2));
        assert!(String::from_utf8_lossy(&o.stderr).contains(needle));
        assert!(!dir.join("o.png").exists(), "refused before rendering");
    }
}

#[test]
fn stats_json_reports_the_render() {
    let dir = ScratchDir::new("stats");
    let out = dir.join("cbox.exr");
    let o = run_in(
        &dir,
        &[
            "render",
            data("pt/cbox.pbrt").to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
            "--resolution",
            "40x30",
            "--spp",
            "3",
            "--quiet",
            "--stats",
            "json",
        ],
    );
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).expect("one JSON object");
    assert_eq!(v["samples"].as_u64(), Some(40 * 30 * 3));
    assert_eq!(v["width"].as_u64(), Some(40));
    assert_eq!(v["spp"].as_u64(), Some(3));
    // Spectral is the default mode.
    assert_eq!(v["mode"].as_str(), Some("spectral"));
    // The Cornell box: 8 meshes of 36 triangles in all, nothing else.
    assert_eq!(v["triangles"].as_u64(), Some(36));
    assert_eq!(v["primitives"].as_u64(), Some(36));
    let rays = v["rays"]["total"].as_u64().unwrap();
    assert!(rays >= 40 * 30 * 3, "at least one ray per sample: {rays}");
    let t = &v["time_s"];
    let phase = |k: &str| t[k].as_f64().unwrap();
    for k in ["parse", "build", "render", "write"] {
        assert!(phase(k) >= 0.0, "{k}");
    }
    let sum = phase("parse") + phase("build") + phase("render") + phase("write");
    assert!(phase("total") >= sum * 0.999, "{t}");
    let sps = v["samples_per_s"].as_f64().unwrap();
    assert!((sps * phase("render") - 3600.0).abs() < 1.0, "{sps}");
    assert!(v["bvh"]["nodes"].as_u64().unwrap() >= 1);
    let m = &v["memory"];
    let bvh = m["bvh_bytes"].as_u64().unwrap();
    assert_eq!(v["bvh"]["bytes"].as_u64(), Some(bvh));
    // 36 triangles: 3 × 4-byte indices each at least, a vertex or more apiece.
    assert!(m["mesh_bytes"].as_u64().unwrap() >= 36 * 12);
    let bpt = m["bytes_per_triangle"].as_f64().unwrap();
    let geometry = m["mesh_bytes"].as_u64().unwrap() + m["primitive_bytes"].as_u64().unwrap() + bvh;
    assert!((bpt - geometry as f64 / 36.0).abs() < 1e-9);
    assert!(m["total_bytes"].as_u64().unwrap() >= geometry);
}

/// A small scene spread over files: an include, a PLY (a quad and a triangle: as pbrt-v4, the
/// quad a bilinear patch and the triangle a mesh of its own), an
/// image texture and a spectrum file, plus a 2-triangle `trianglemesh`.
fn write_mesh_scene(dir: &Path) -> std::path::PathBuf {
    std::fs::create_dir_all(dir.join("geo")).unwrap();
    std::fs::write(
        dir.join("geo/parts.ply"),
        "ply\nformat ascii 1.0\nelement vertex 5\nproperty float x\nproperty float y\n\
         property float z\nelement face 2\nproperty list uchar int vertex_indices\nend_header\n\
         -1 -1 0\n1 -1 0\n1 1 0\n-1 1 0\n0 2 0\n4 0 1 2 3\n3 3 2 4\n",
    )
    .unwrap();
    std::fs::write(
        dir.join("geo/shapes.pbrt"),
        "Texture \"t\" \"spectrum\" \"imagemap\" \"string filename\" \"../tex.png\"\n\
         Material \"diffuse\" \"texture reflectance\" \"t\"\n\
         Shape \"plymesh\" \"string filename\" \"parts.ply\"\n",
    )
    .unwrap();
    std::fs::write(dir.join("grey.spd"), "400 0.5\n500 0.5\n600 0.5\n700 0.5\n").unwrap();
    let f = std::fs::File::create(dir.join("tex.png")).unwrap();
    let mut enc = png::Encoder::new(f, 2, 2);
    enc.set_color(png::ColorType::Rgb);
    enc.set_depth(png::BitDepth::Eight);
    let mut wr = enc.write_header().unwrap();
    wr.write_image_data(&[255, 0, 0, 0, 255, 0, 0, 0, 255, 255, 255, 255])
        .unwrap();
    wr.finish().unwrap();
    let scene = dir.join("scene.pbrt");
    std::fs::write(
        &scene,
        "LookAt 0 0 5  0 0 0  0 1 0\nCamera \"perspective\" \"float fov\" [40]\n\
         Film \"rgb\" \"integer xresolution\" [32] \"integer yresolution\" [24]\n\
         WorldBegin\nLightSource \"point\" \"point3 from\" [0 0 4] \"rgb I\" [10 10 10]\n\
         AttributeBegin\nInclude \"geo/shapes.pbrt\"\nAttributeEnd\n\
         Material \"diffuse\" \"spectrum reflectance\" \"grey.spd\"\n\
         Shape \"trianglemesh\" \"point3 P\" [-3 -3 -1  3 -3 -1  3 3 -1]\n\
         \"integer indices\" [0 1 2]\n\
         Shape \"trianglemesh\" \"point3 P\" [-3 -3 -2  3 -3 -2  3 3 -2]\n\
         \"integer indices\" [0 1 2]\n",
    )
    .unwrap();
    scene
}

#[test]
fn info_counts_triangles_and_lists_every_file_read() {
    let dir = ScratchDir::new("info");
    let scene = write_mesh_scene(&dir);
    let o = run_in(
        &dir,
        &["info", scene.to_str().unwrap(), "--files", "--json"],
    );
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    // The PLY's quad is a bilinear patch, as pbrt-v4 makes it: its triangle and the scene's two.
    assert_eq!(v["triangles"].as_u64(), Some(3));
    assert_eq!(v["scene_triangles"].as_u64(), Some(3));
    assert_eq!(v["shapes"]["trianglemesh"].as_u64(), Some(3));
    assert_eq!(v["shapes"]["bilinearmesh"].as_u64(), Some(1));
    assert_eq!(v["lights"]["point"].as_u64(), Some(1));
    // pbrt's default material, then the scene's two.
    assert_eq!(v["materials"]["count"].as_u64(), Some(3));
    // Kinds as pbrt-v4 names them, never Rust's Debug text.
    assert_eq!(v["materials"]["by_kind"]["diffuse"].as_u64(), Some(3));
    // No Integrator directive: pbrt-v4's default.
    assert_eq!(v["integrator"]["name"], "volpath");
    assert!(v["integrator"]["maxdepth"].is_u64());
    assert!(
        v["sampler"]["kind"]
            .as_str()
            .unwrap()
            .chars()
            .all(|c| c.is_ascii_lowercase())
    );
    assert_eq!(v["film"]["width"].as_u64(), Some(32));
    let pos: Vec<f64> = (0..3)
        .map(|i| v["camera"]["position"][i].as_f64().unwrap())
        .collect();
    assert!(
        (pos[2] - 5.0).abs() < 1e-4 && pos[0].abs() < 1e-4,
        "{pos:?}"
    );
    let b = &v["world_bounds"];
    assert!((b["min"][2].as_f64().unwrap() + 2.0).abs() < 1e-4);
    assert!((b["max"][1].as_f64().unwrap() - 3.0).abs() < 1e-4);
    let bpt = v["memory"]["bytes_per_triangle"].as_f64().unwrap();
    assert!(bpt > 12.0, "{bpt}");

    let files: Vec<std::path::PathBuf> = v["files"]
        .as_array()
        .unwrap()
        .iter()
        .map(|p| p.as_str().unwrap().into())
        .collect();
    let canon = |rel: &str| std::fs::canonicalize(dir.join(rel)).unwrap();
    let want = [
        "scene.pbrt",
        "geo/shapes.pbrt",
        "tex.png",
        "geo/parts.ply",
        "grey.spd",
    ];
    for w in want {
        assert!(files.contains(&canon(w)), "{w} missing from {files:?}");
    }
    assert_eq!(files.len(), want.len(), "{files:?}");
    assert!(files.iter().all(|p| p.is_absolute()));
    assert_eq!(files[0], canon("scene.pbrt"), "the scene is read first");

    // The text form says the same.
    let o = run_in(&dir, &["info", scene.to_str().unwrap(), "--files"]);
    assert!(o.status.success());
    let text = String::from_utf8_lossy(&o.stdout);
    assert!(text.contains("3 in world shapes"), "{text}");
    assert!(
        text.contains(canon("geo/parts.ply").to_str().unwrap()),
        "{text}"
    );
    assert!(text.contains("per triangle"), "{text}");
}

#[test]
fn info_reads_a_bare_mesh_and_refuses_a_broken_scene() {
    let dir = ScratchDir::new("info-ply");
    write_mesh_scene(&dir);
    let o = run_in(&dir, &["info", "geo/parts.ply", "--json", "--files"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(v["scene_triangles"].as_u64(), Some(3));
    let files = v["files"].as_array().unwrap();
    assert_eq!(files.len(), 1);
    let counts: HashMap<String, u64> = v["lights"]
        .as_object()
        .unwrap()
        .iter()
        .map(|(k, n)| (k.clone(), n.as_u64().unwrap()))
        .collect();
    assert!(!counts.is_empty(), "a bare mesh is lit: {counts:?}");

    let o = run_in(
        &dir,
        &["info", data("bad/include-self.pbrt").to_str().unwrap()],
    );
    assert_eq!(o.status.code(), Some(2));
    assert!(o.stdout.is_empty());
}

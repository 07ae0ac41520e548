//! pbrt-v4's command-line habits in lancer: its option spellings (`--outfile`, `--nthreads`,
//! `--cropwindow`, `--pixelbounds`, a bare `--stats`), a scene on standard input, `--version`,
//! plain progress lines in a log, renders that survive a hang-up under `nohup`; and the small
//! fixes of issue 21 (warnings printed once by `info`, a missing part named by `merge`).

use crate::common::{ScratchDir, data, lancer, read_exr, run_in, signal_after_first_checkpoint};
use std::io::Write;
use std::os::unix::process::CommandExt;
use std::path::Path;
use std::process::{Command, Output, Stdio};

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

fn bytes(p: &Path) -> Vec<u8> {
    std::fs::read(p).unwrap_or_else(|e| panic!("{}: {e}", p.display()))
}

/// Renders the Cornell box at 40 × 30, 2 spp, seed 3, with `extra` options, in `dir`.
fn cbox(dir: &Path, extra: &[&str]) -> Output {
    let scene = data("pt/cbox.pbrt");
    let mut args = vec!["render", s(&scene), "--resolution", "40x30", "--spp", "2"];
    args.extend_from_slice(&["--seed", "3", "--quiet"]);
    args.extend_from_slice(extra);
    run_in(dir, &args)
}

#[test]
fn pbrt_spellings_give_the_same_image_as_lancers() {
    let dir = ScratchDir::new("pbrt-spellings");
    let o = cbox(
        &dir,
        &["-o", "a.exr", "--threads", "1", "--crop", "0,0.5,0.25,1"],
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let o = cbox(
        &dir,
        &[
            "--outfile",
            "b.exr",
            "--nthreads",
            "1",
            "--cropwindow",
            "0",
            "0.5",
            "0.25",
            "1",
        ],
    );
    assert!(o.status.success(), "{}", stderr(&o));
    // x: ⌈40·0⌉..⌈40·0.5⌉ = 0..20; y: ⌈30·0.25⌉..⌈30·1⌉ = 8..30.
    let b = read_exr(&dir.join("b.exr"));
    assert_eq!((b.width, b.height), (20, 22));
    assert!(bytes(&dir.join("a.exr")) == bytes(&dir.join("b.exr")));
    // --nthreads sets the worker count, as --stats json reports it.
    let o = cbox(&dir, &["-o", "c.exr", "--nthreads", "1", "--stats", "json"]);
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).expect("one JSON object");
    assert_eq!(v["threads"].as_u64(), Some(1));
    assert_eq!(v["mode"].as_str(), Some("spectral"));
    // --rgb renders in RGB, and says so.
    let o = cbox(&dir, &["-o", "d.exr", "--rgb", "--stats", "json"]);
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).expect("one JSON object");
    assert_eq!(v["mode"].as_str(), Some("rgb"));
    // --spectral stays accepted; with --rgb it is a contradiction.
    assert!(cbox(&dir, &["-o", "e.exr", "--spectral"]).status.success());
    let o = cbox(&dir, &["-o", "f.exr", "--spectral", "--rgb"]);
    assert!(
        !o.status.success() && stderr(&o).contains("--rgb"),
        "{}",
        stderr(&o)
    );
}

#[test]
fn pixelbounds_renders_exactly_those_pixels() {
    let dir = ScratchDir::new("pbrt-pixelbounds");
    let o = cbox(&dir, &["-o", "full.exr"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let o = cbox(
        &dir,
        &["-o", "pb.exr", "--pixelbounds", "8", "24", "4", "12"],
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let full = read_exr(&dir.join("full.exr"));
    let pb = read_exr(&dir.join("pb.exr"));
    assert_eq!((pb.width, pb.height), (16, 8));
    // A pixel's samples depend only on the seed, the pixel and the sample index: the bounded
    // render holds the full render's pixels x 8..24, y 4..12.
    for y in 0..8 {
        for x in 0..16 {
            assert_eq!(
                pb.rgb[y * 16 + x],
                full.rgb[(y + 4) * 40 + x + 8],
                "({x}, {y})"
            );
        }
    }
    // Refusals, with exit status 2 and nothing written.
    for (opts, says) in [
        (
            &["--pixelbounds", "40", "50", "0", "10"][..],
            "--pixelbounds 40 50 0 10 selects no pixel of the 40x30 image",
        ),
        (
            &["--pixelbounds", "5", "5", "0", "10"],
            "--pixelbounds 5 5 0 10: pixel bounds need 0 ≤ x0 < x1 and 0 ≤ y0 < y1",
        ),
        (
            &["--cropwindow", "0.5", "0.2", "0", "1"],
            "--cropwindow 0.5 0.2 0 1: a crop window needs 0 ≤ x0 < x1 ≤ 1 and 0 ≤ y0 < y1 ≤ 1",
        ),
        (
            &["--pixelbounds", "0", "4", "0", "4", "--crop", "0,1,0,1"],
            "cannot be used with",
        ),
    ] {
        let mut args = vec!["-o", "bad.exr"];
        args.extend_from_slice(opts);
        let o = cbox(&dir, &args);
        assert_eq!(o.status.code(), Some(2), "{opts:?}: {}", stderr(&o));
        assert!(stderr(&o).contains(says), "{opts:?}: {}", stderr(&o));
        assert!(!dir.join("bad.exr").exists());
    }
}

/// Runs `lancer ARGS` in `dir` with `input` on its standard input.
fn run_with_stdin(dir: &Path, args: &[&str], input: &str) -> Output {
    run_with_stdin_bytes(dir, args, input.as_bytes())
}

/// [`run_with_stdin`] with any bytes.
fn run_with_stdin_bytes(dir: &Path, args: &[&str], input: &[u8]) -> Output {
    let mut child = lancer()
        .current_dir(dir)
        .args(args)
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    child.stdin.take().unwrap().write_all(input).unwrap();
    child.wait_with_output().unwrap()
}

/// `text` as a gzip stream (RFC 1952) of one stored (uncompressed) deflate block.
fn gzip_stored(text: &[u8]) -> Vec<u8> {
    // CRC-32 (IEEE, reflected polynomial 0xEDB88320), bit by bit.
    let mut crc = !0u32;
    for &b in text {
        crc ^= b as u32;
        for _ in 0..8 {
            crc = if crc & 1 == 1 {
                (crc >> 1) ^ 0xEDB8_8320
            } else {
                crc >> 1
            };
        }
    }
    let n = text.len() as u16;
    let mut out = vec![0x1f, 0x8b, 8, 0, 0, 0, 0, 0, 0, 0xff, 1];
    out.extend_from_slice(&n.to_le_bytes());
    out.extend_from_slice(&(!n).to_le_bytes());
    out.extend_from_slice(text);
    out.extend_from_slice(&(!crc).to_le_bytes());
    out.extend_from_slice(&(text.len() as u32).to_le_bytes());
    out
}

#[test]
fn a_gzip_compressed_scene_on_stdin_is_read() {
    let dir = ScratchDir::new("pbrt-stdin-gz");
    let scene = "Film \"rgb\" \"integer xresolution\" [8] \"integer yresolution\" [8]\n\
                 WorldBegin\nShape \"sphere\" \"float radius\" [2]\n";
    let o = run_with_stdin_bytes(
        &dir,
        &["info", "-", "--json"],
        &gzip_stored(scene.as_bytes()),
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(v["film"]["width"].as_u64(), Some(8));
    assert_eq!(v["shapes"]["sphere"].as_u64(), Some(1));
    // A damaged stream says so.
    let mut bad = gzip_stored(scene.as_bytes());
    bad.truncate(bad.len() - 4);
    let o = run_with_stdin_bytes(&dir, &["info", "-"], &bad);
    assert_eq!(o.status.code(), Some(2));
    assert!(
        stderr(&o).starts_with("error: <stdin>: cannot read: cannot decompress"),
        "{}",
        stderr(&o)
    );
}

#[test]
fn a_scene_on_stdin_renders_and_its_errors_name_stdin() {
    let dir = ScratchDir::new("pbrt-stdin");
    // The world is in a file the scene includes by a relative name: read from the current
    // folder when the scene comes on stdin, from the scene's folder when it is a file there.
    std::fs::write(
        dir.join("world.pbrt"),
        "LightSource \"point\" \"point3 from\" [0 2 0] \"rgb I\" [5 5 5]\n\
         Translate 0 0 -3\nShape \"sphere\" \"float radius\" [1]\n",
    )
    .unwrap();
    let scene = "LookAt 0 0 0  0 0 -1  0 1 0\nCamera \"perspective\" \"float fov\" [60]\n\
                 Film \"rgb\" \"integer xresolution\" [24] \"integer yresolution\" [16]\n\
                 Sampler \"independent\" \"integer pixelsamples\" [2]\n\
                 WorldBegin\nInclude \"world.pbrt\"\n";
    std::fs::write(dir.join("scene.pbrt"), scene).unwrap();
    let o = run_with_stdin(&dir, &["render", "-", "-o", "stdin.exr", "--quiet"], scene);
    assert!(o.status.success(), "{}", stderr(&o));
    let o = run_in(&dir, &["render", "scene.pbrt", "-o", "file.exr", "--quiet"]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(bytes(&dir.join("stdin.exr")) == bytes(&dir.join("file.exr")));
    let img = read_exr(&dir.join("stdin.exr"));
    assert!(img.means()[0] > 0.0, "the sphere is lit");

    // An error points at <stdin>, line and column, with the offending line.
    let bad = "Film \"rgb\"\n  Camera \"perspective\" \"float fov\" [ abc ]\n";
    let o = run_with_stdin(&dir, &["render", "-", "-o", "bad.png"], bad);
    assert_eq!(o.status.code(), Some(2));
    let err = stderr(&o);
    assert!(
        err.starts_with("error: <stdin>:2:38: parameter \"float fov\" expects a value"),
        "{err}"
    );
    assert!(
        err.contains("  Camera \"perspective\" \"float fov\" [ abc ]"),
        "{err}"
    );
    assert!(!dir.join("bad.png").exists());
    // `info -` reads stdin too.
    let o = run_with_stdin(&dir, &["info", "-", "--json"], scene);
    assert!(o.status.success(), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(v["film"]["width"].as_u64(), Some(24));
    assert_eq!(v["shapes"]["sphere"].as_u64(), Some(1));
    // The mode `lancer render` uses for it by default.
    assert_eq!(v["mode"].as_str(), Some("spectral"));
}

#[test]
fn version_and_help_describe_lancer() {
    let o = lancer().arg("--version").output().unwrap();
    assert!(o.status.success());
    // `lancer 0.1.0 (commit 0123456789ab; x86_64-unknown-linux-gnu, x86-64-v3)`
    let v = String::from_utf8_lossy(&o.stdout);
    let prefix = format!("lancer {} (commit ", env!("CARGO_PKG_VERSION"));
    assert!(v.starts_with(&prefix), "{v}");
    let (commit, target) = v[prefix.len()..].trim_end().split_once("; ").unwrap();
    assert!(
        commit == "unknown"
            || (commit.len() == 12 && commit.chars().all(|c| c.is_ascii_hexdigit())),
        "{v}"
    );
    assert!(
        target.starts_with(std::env::consts::ARCH) && target.ends_with(')'),
        "{v}"
    );
    let o = lancer().arg("--help").output().unwrap();
    assert!(o.status.success());
    let help = String::from_utf8_lossy(&o.stdout);
    assert_eq!(
        help.lines().next(),
        Some(
            "lancer, a physically based ray tracer: renders pbrt-v4 scenes and glTF, OBJ and \
             PLY models"
        )
    );
    // The render options list pbrt's spellings beside lancer's.
    let o = lancer().args(["render", "--help"]).output().unwrap();
    let help = String::from_utf8_lossy(&o.stdout);
    for alias in [
        "[alias: --outfile]",
        "[alias: --nthreads]",
        "--cropwindow <X0> <X1> <Y0> <Y1>",
    ] {
        assert!(help.contains(alias), "{alias}: {help}");
    }
}

#[test]
fn a_bare_stats_prints_the_text_summary() {
    let dir = ScratchDir::new("pbrt-stats");
    // As pbrt users write it: --stats right before the scene.
    let scene = data("pt/cbox.pbrt");
    let args = [
        "render",
        "--stats",
        s(&scene),
        "-o",
        "c.png",
        "--resolution",
        "40x30",
    ];
    let o = run_in(&dir, &[&args[..], &["--spp", "3", "--quiet"]].concat());
    assert!(o.status.success(), "{}", stderr(&o));
    let out = String::from_utf8_lossy(&o.stdout);
    let lines: Vec<&str> = out.lines().collect();
    assert_eq!(lines[0], format!("statistics of {}", scene.display()));
    assert!(lines[1].starts_with("  time      "), "{out}");
    assert!(
        lines[2].starts_with("  image     c.png, 40x30 pixels, 3 spp, spectral, "),
        "{out}"
    );
    // 40 · 30 · 3 = 3600 camera samples, none of them NaN.
    assert!(lines[3].starts_with("  samples   3600 ("), "{out}");
    assert!(lines[3].ends_with("M/s), 0 NaN or infinite"), "{out}");
    // The Cornell box: 36 triangles, nothing else.
    assert!(
        lines[5].starts_with("  geometry  36 primitives, 36 triangles, BVH of "),
        "{out}"
    );
    assert!(lines[6].starts_with("  memory    meshes "), "{out}");
    assert_eq!(lines.len(), 7, "{out}");
}

#[test]
fn progress_in_a_log_is_plain_lines_at_each_tenth() {
    let dir = ScratchDir::new("pbrt-progress");
    // 64 × 64 pixels at 16 spp: 16 tiles of 16 × 16 pixels, one unit of work each, so each
    // finished unit adds 6.25 % and the tenths are crossed at 12.5, 25, 31.25, 43.75, 50,
    // 62.5, 75, 81.25, 93.75 and 100 %, whatever the order the units finish in.
    let scene = data("pt/cbox.pbrt");
    let o = run_in(
        &dir,
        &[
            "render",
            s(&scene),
            "-o",
            "p.png",
            "--resolution",
            "64x64",
            "--spp",
            "16",
        ],
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let err = stderr(&o);
    assert!(!err.contains('\r') && !err.contains('\x1b'), "{err:?}");
    let percents: Vec<&str> = err
        .lines()
        .filter_map(|l| l.strip_prefix("progress: "))
        .map(|l| l.split('%').next().unwrap())
        .collect();
    assert_eq!(
        percents,
        ["12", "25", "31", "43", "50", "62", "75", "81", "93", "100"],
        "{err}"
    );
    let last = err.lines().rfind(|l| l.starts_with("progress: ")).unwrap();
    assert!(
        last.starts_with("progress: 100% (65536 of 65536 pixel samples), "),
        "{last}"
    );
    // The summary line follows, as on a terminal; --quiet silences both.
    assert!(
        err.lines()
            .last()
            .unwrap()
            .starts_with("p.png: 64x64 pixels"),
        "{err}"
    );
    let o = run_in(
        &dir,
        &[
            "render",
            s(&scene),
            "-o",
            "q.png",
            "--resolution",
            "64x64",
            "--quiet",
        ],
    );
    assert!(o.status.success());
    assert_eq!(stderr(&o), "");
}

/// Starts a long render of the Cornell box in `dir` with SIGHUP ignored (as `nohup` starts
/// it) or at its default, waits until it is under way (its first checkpoint is written, so
/// the signal handling is in place), sends it SIGHUP and returns how it ended.
fn render_hung_up(dir: &Path, ignore_hangup: bool) -> Output {
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_lancer"));
    cmd.current_dir(dir)
        .args(["render", s(&data("pt/cbox.pbrt")), "-o", "h.exr", "--quiet"])
        .args([
            "--spp",
            "512",
            "--resolution",
            "48x48",
            "--checkpoint-every",
            "0.001",
        ])
        .stdout(Stdio::null())
        .stderr(Stdio::piped());
    let disposition = if ignore_hangup {
        libc::SIG_IGN
    } else {
        libc::SIG_DFL
    };
    // SAFETY: between fork and exec the child only sets a signal disposition, which is
    // async-signal-safe; the disposition SIG_IGN survives exec, as nohup relies on.
    unsafe {
        cmd.pre_exec(move || {
            libc::signal(libc::SIGHUP, disposition);
            Ok(())
        });
    }
    let child = cmd.spawn().unwrap();
    signal_after_first_checkpoint(child, &dir.join("h.exr.ckpt"), "HUP")
}

#[test]
fn under_nohup_a_hangup_does_not_stop_the_render() {
    let dir = ScratchDir::new("pbrt-nohup");
    let o = render_hung_up(&dir, true);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    assert!(!stderr(&o).contains("interrupted"), "{}", stderr(&o));
    let img = read_exr(&dir.join("h.exr"));
    assert_eq!((img.width, img.height), (48, 48));
    assert!(img.means().iter().all(|&m| m > 0.01), "{:?}", img.means());
    assert!(
        !dir.join("h.exr.ckpt").exists(),
        "a finished render leaves no checkpoint"
    );
}

#[test]
fn without_nohup_a_hangup_checkpoints_and_stops() {
    let dir = ScratchDir::new("pbrt-hangup");
    let o = render_hung_up(&dir, false);
    assert_eq!(o.status.code(), Some(130), "{}", stderr(&o));
    assert!(stderr(&o).contains("--resume h.exr.ckpt"), "{}", stderr(&o));
    assert!(dir.join("h.exr.ckpt").exists());
}

#[test]
fn info_prints_each_warning_once() {
    let dir = ScratchDir::new("pbrt-info-warn");
    std::fs::write(
        dir.join("w.pbrt"),
        "Camera \"perspective\"\nWorldBegin\nShape \"sphere\"\nShape \"bogus\"\n",
    )
    .unwrap();
    let o = run_in(&dir, &["info", "w.pbrt"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let all = format!("{}{}", String::from_utf8_lossy(&o.stdout), stderr(&o));
    let warning = "w.pbrt:4:1: unknown shape \"bogus\"";
    assert_eq!(all.matches(warning).count(), 1, "{all}");
    assert!(all.contains("warnings      1\n"), "{all}");
}

#[test]
fn merge_names_a_missing_part_plainly() {
    let dir = ScratchDir::new("pbrt-merge-missing");
    let o = run_in(&dir, &["merge", "part-0.exr", "-o", "m.exr"]);
    assert_eq!(o.status.code(), Some(2));
    assert_eq!(stderr(&o), "error: part-0.exr: no such part file\n");
    assert!(!dir.join("m.exr").exists());
}

#[test]
fn a_split_of_one_tile_row_says_row() {
    let dir = ScratchDir::new("pbrt-one-row");
    let scene = data("pt/cbox.pbrt");
    let o = run_in(
        &dir,
        &[
            "render",
            s(&scene),
            "-o",
            "p.exr",
            "--resolution",
            "32x16",
            "--split",
            "1/3",
        ],
    );
    assert_eq!(o.status.code(), Some(2));
    assert!(
        stderr(&o).contains("the image has only 1 row of 16-pixel tiles, too few for 3 parts"),
        "{}",
        stderr(&o)
    );
}

#[test]
fn a_model_requiring_khr_texture_transform_renders() {
    let dir = ScratchDir::new("pbrt-khr-tt");
    let gltf = Path::new(env!("CARGO_MANIFEST_DIR")).join("../lancer-scene/tests/data/gltf");
    let text = std::fs::read_to_string(gltf.join("Triangle/Triangle.gltf"))
        .unwrap()
        .replacen(
            '{',
            r#"{ "extensionsUsed": ["KHR_texture_transform"], "extensionsRequired": ["KHR_texture_transform"],"#,
            1,
        );
    std::fs::write(dir.join("t.gltf"), text).unwrap();
    std::fs::copy(
        gltf.join("Triangle/simpleTriangle.bin"),
        dir.join("simpleTriangle.bin"),
    )
    .unwrap();
    let o = run_in(
        &dir,
        &[
            "render",
            "t.gltf",
            "-o",
            "t.png",
            "--quiet",
            "--resolution",
            "16x16",
            "--spp",
            "1",
        ],
    );
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(dir.join("t.png").is_file());
}

#[test]
fn strict_makes_every_reader_warning_an_error() {
    let dir = ScratchDir::new("pbrt-strict");
    std::fs::write(
        dir.join("w.pbrt"),
        "Film \"rgb\" \"integer xresolution\" 8 \"integer yresolution\" 8\nWorldBegin\n\
         LightSource \"point\"\nShape \"sphere\"\n  \"float radius\" 0.5 \"float colour\" 2\n",
    )
    .unwrap();
    let expected = "error: w.pbrt:5:22: parameter \"float colour\" of Shape \"sphere\" is not used \
                    by lancer; ignored (--strict makes every warning an error)";
    for args in [
        &["info", "w.pbrt", "--strict"][..],
        &["render", "w.pbrt", "-o", "w.png", "--quiet", "--strict"],
    ] {
        let o = run_in(&dir, args);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {}", stderr(&o));
        assert_eq!(stderr(&o).lines().next(), Some(expected), "{args:?}");
    }
    assert!(!dir.join("w.png").exists());
    // Without it, the same scene renders, with its warning.
    let o = run_in(&dir, &["render", "w.pbrt", "-o", "w.png", "--quiet"]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    assert!(stderr(&o).contains("warning: w.pbrt:5:22:"));
}

#[test]
fn info_reports_media_by_kind_and_their_memory() {
    let dir = ScratchDir::new("info-media");
    // A homogeneous fog around the camera and a 2×2×2 density grid.
    let scene = "MakeNamedMedium \"fog\" \"string type\" \"homogeneous\"\n\
                 MediumInterface \"\" \"fog\"\n\
                 Camera \"perspective\"\n\
                 WorldBegin\n\
                 MakeNamedMedium \"smoke\" \"string type\" \"uniformgrid\" \"integer nx\" 2 \
                 \"integer ny\" 2 \"integer nz\" 2 \"float density\" [0 1 0 1 0 1 0 1]\n\
                 MediumInterface \"smoke\" \"fog\"\n\
                 Material \"interface\"\n\
                 Shape \"sphere\"\n";
    let o = run_with_stdin(&dir, &["info", "-", "--json"], scene);
    assert!(o.status.success(), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(v["media"]["count"].as_u64(), Some(2));
    assert_eq!(
        v["media"]["by_kind"]["homogeneous"]["count"].as_u64(),
        Some(1)
    );
    assert_eq!(
        v["media"]["by_kind"]["uniformgrid"]["count"].as_u64(),
        Some(1)
    );
    // The grid holds its 8 densities (4 bytes each) and a majorant grid beside its record.
    let grid = v["media"]["by_kind"]["uniformgrid"]["bytes"]
        .as_u64()
        .unwrap();
    let fog = v["media"]["by_kind"]["homogeneous"]["bytes"]
        .as_u64()
        .unwrap();
    assert!(grid >= fog + 32, "grid {grid} B, fog {fog} B");
    assert!(v["memory"]["media_bytes"].as_u64().unwrap() >= grid + fog);
    assert_eq!(v["warnings"].as_array().map(Vec::len), Some(0), "{v}");
    let o = run_with_stdin(&dir, &["info", "-"], scene);
    let text = String::from_utf8_lossy(&o.stdout);
    assert!(
        text.contains("media         1 homogeneous (") && text.contains("1 uniformgrid ("),
        "{text}"
    );
}

//! README's "pbrt-v4 coverage" tables, kept true: every type pbrt-v4's scene format names
//! (taken from pbrt-v4's `Create` dispatches and its parser) has a row, and each row's status
//! is checked by feeding the reader a minimal scene that uses the type. A `supported` row
//! must load without a warning of the "unsupported" class (the check scripts' pattern); a
//! `not supported` row must load with one, or be refused with an error; an `approximated` row
//! must load (its note says how).

use crate::common::ScratchDir;
use lancer_scene::load;
use std::path::Path;

/// The check scripts' pattern for a warning that says lancer does not do what was asked.
const UNSUPPORTED: [&str; 7] = [
    "not supported",
    "unsupported",
    "not used by lancer",
    "lancer uses",
    "renders it as",
    "instead of",
    "falls back",
];

/// pbrt-v4's types by table heading (src/pbrt/{shapes,materials,textures,lights,cameras,
/// samplers,filters,film,media,lightsamplers}.cpp, cpu/integrators.cpp, cpu/aggregate.cpp,
/// util/spectrum.cpp, util/colorspace.cpp and parser.cpp).
const PBRT_TYPES: &[(&str, &[&str])] = &[
    (
        "Directives",
        &[
            "Accelerator",
            "ActiveTransform",
            "AreaLightSource",
            "Attribute",
            "AttributeBegin",
            "AttributeEnd",
            "Camera",
            "ColorSpace",
            "ConcatTransform",
            "CoordSysTransform",
            "CoordinateSystem",
            "Film",
            "Identity",
            "Import",
            "Include",
            "Integrator",
            "LightSource",
            "LookAt",
            "MakeNamedMaterial",
            "MakeNamedMedium",
            "Material",
            "MediumInterface",
            "NamedMaterial",
            "ObjectBegin",
            "ObjectEnd",
            "ObjectInstance",
            "Option",
            "PixelFilter",
            "ReverseOrientation",
            "Rotate",
            "Sampler",
            "Scale",
            "Shape",
            "Texture",
            "Transform",
            "TransformBegin",
            "TransformEnd",
            "TransformTimes",
            "Translate",
            "WorldBegin",
            "WorldEnd",
        ],
    ),
    (
        "Shapes",
        &[
            "sphere",
            "disk",
            "cylinder",
            "trianglemesh",
            "plymesh",
            "loopsubdiv",
            "bilinearmesh",
            "curve",
        ],
    ),
    (
        "Materials",
        &[
            "diffuse",
            "conductor",
            "dielectric",
            "thindielectric",
            "diffusetransmission",
            "coateddiffuse",
            "coatedconductor",
            "mix",
            "interface",
            "hair",
            "subsurface",
            "measured",
            "none",
        ],
    ),
    (
        "Float textures",
        &[
            "constant",
            "scale",
            "mix",
            "directionmix",
            "bilerp",
            "checkerboard",
            "dots",
            "fbm",
            "wrinkled",
            "windy",
            "imagemap",
            "ptex",
        ],
    ),
    (
        "Spectrum textures",
        &[
            "constant",
            "scale",
            "mix",
            "directionmix",
            "bilerp",
            "checkerboard",
            "dots",
            "marble",
            "imagemap",
            "ptex",
        ],
    ),
    (
        "Texture mappings",
        &["uv", "spherical", "cylindrical", "planar"],
    ),
    (
        "Lights",
        &[
            "point",
            "spot",
            "goniometric",
            "projection",
            "distant",
            "infinite",
        ],
    ),
    ("Area lights", &["diffuse"]),
    (
        "Cameras",
        &["perspective", "orthographic", "spherical", "realistic"],
    ),
    (
        "Samplers",
        &[
            "independent",
            "stratified",
            "halton",
            "sobol",
            "paddedsobol",
            "zsobol",
            "pmj02bn",
        ],
    ),
    (
        "Filters",
        &["box", "gaussian", "mitchell", "sinc", "triangle"],
    ),
    ("Films", &["rgb", "gbuffer", "spectral"]),
    (
        "Integrators",
        &[
            "volpath",
            "path",
            "simplepath",
            "simplevolpath",
            "lightpath",
            "bdpt",
            "mlt",
            "sppm",
            "randomwalk",
            "ambientocclusion",
            "function",
        ],
    ),
    ("Light samplers", &["bvh", "power", "uniform", "exhaustive"]),
    ("Accelerators", &["bvh", "kdtree"]),
    (
        "Media",
        &["homogeneous", "uniformgrid", "rgbgrid", "cloud", "nanovdb"],
    ),
    (
        "Named spectra",
        &[
            "glass-BK7",
            "glass-BAF10",
            "glass-FK51A",
            "glass-LASF9",
            "glass-F5",
            "glass-F10",
            "glass-F11",
            "metal-Ag-eta",
            "metal-Ag-k",
            "metal-Al-eta",
            "metal-Al-k",
            "metal-Au-eta",
            "metal-Au-k",
            "metal-Cu-eta",
            "metal-Cu-k",
            "metal-CuZn-eta",
            "metal-CuZn-k",
            "metal-MgO-eta",
            "metal-MgO-k",
            "metal-TiO2-eta",
            "metal-TiO2-k",
            "stdillum-A",
            "stdillum-D50",
            "stdillum-D65",
            "stdillum-F1",
            "stdillum-F2",
            "stdillum-F3",
            "stdillum-F4",
            "stdillum-F5",
            "stdillum-F6",
            "stdillum-F7",
            "stdillum-F8",
            "stdillum-F9",
            "stdillum-F10",
            "stdillum-F11",
            "stdillum-F12",
            "illum-acesD60",
        ],
    ),
    (
        "Camera sensors",
        &[
            "canon_eos_100d",
            "canon_eos_1dx_mkii",
            "canon_eos_200d",
            "canon_eos_200d_mkii",
            "canon_eos_5d",
            "canon_eos_5d_mkii",
            "canon_eos_5d_mkiii",
            "canon_eos_5d_mkiv",
            "canon_eos_5ds",
            "canon_eos_m",
            "hasselblad_l1d_20c",
            "nikon_d810",
            "nikon_d850",
            "sony_ilce_6400",
            "sony_ilce_7m3",
            "sony_ilce_7rm3",
            "sony_ilce_9",
        ],
    ),
    (
        "Colour spaces",
        &["srgb", "rec2020", "dci-p3", "aces2065-1"],
    ),
];

/// A 2×2 8-bit grey PNG.
fn grey_png(path: &Path) {
    let file = std::fs::File::create(path).unwrap();
    let mut enc = png::Encoder::new(std::io::BufWriter::new(file), 2, 2);
    enc.set_color(png::ColorType::Rgb);
    enc.set_depth(png::BitDepth::Eight);
    enc.write_header()
        .unwrap()
        .write_image_data(&[128u8; 12])
        .unwrap();
}

/// The files the minimal scenes name: a PNG, an ASCII PLY quad, a one-surface lens, an
/// included scene fragment.
fn write_files(dir: &Path) {
    grey_png(&dir.join("t.png"));
    std::fs::write(
        dir.join("q.ply"),
        "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n\
         property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n\
         0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n",
    )
    .unwrap();
    std::fs::write(
        dir.join("lens.dat"),
        "# radius thickness eta aperture\n35 5 1.5 20\n0 30 1 10\n",
    )
    .unwrap();
    std::fs::write(dir.join("inc.pbrt"), "Shape \"sphere\"\n").unwrap();
}

const TRI: &str = r#""point3 P" [0 0 0 1 0 0 0 1 0] "integer indices" [0 1 2]"#;

/// A minimal scene using `name` of kind `heading`: (options block, world block).
fn scene(heading: &str, name: &str) -> (String, String) {
    let o = String::new;
    let w = |s: &str| (String::new(), s.to_string());
    match heading {
        "Directives" => match name {
            "Accelerator" => (r#"Accelerator "bvh""#.into(), o()),
            "ActiveTransform" => w("ActiveTransform StartTime\nActiveTransform All"),
            "AreaLightSource" => w("AreaLightSource \"diffuse\"\nShape \"sphere\""),
            "Attribute" => w("Attribute \"shape\" \"float radius\" 2\nShape \"sphere\""),
            "AttributeBegin" | "AttributeEnd" => w("AttributeBegin\nAttributeEnd"),
            "Camera" => ("Camera \"perspective\"".into(), o()),
            "ColorSpace" => ("ColorSpace \"srgb\"".into(), o()),
            "ConcatTransform" => w("ConcatTransform [1 0 0 0 0 1 0 0 0 0 1 0 0 0 0 1]"),
            "CoordSysTransform" | "CoordinateSystem" => (
                "Camera \"perspective\"".into(),
                "CoordinateSystem \"c\"\nCoordSysTransform \"c\"\nCoordSysTransform \"camera\""
                    .into(),
            ),
            "Film" => ("Film \"rgb\"".into(), o()),
            "Identity" => w("Identity"),
            "Import" => w("Import \"inc.pbrt\""),
            "Include" => w("Include \"inc.pbrt\""),
            "Integrator" => ("Integrator \"path\"".into(), o()),
            "LightSource" => w("LightSource \"point\""),
            "LookAt" => ("LookAt 0 0 -5 0 0 0 0 1 0".into(), o()),
            "MakeNamedMaterial" | "NamedMaterial" => w(
                "MakeNamedMaterial \"m\" \"string type\" \"diffuse\"\nNamedMaterial \"m\"\nShape \"sphere\"",
            ),
            "MakeNamedMedium" | "MediumInterface" => w(
                "MakeNamedMedium \"f\" \"string type\" \"homogeneous\"\nMediumInterface \"f\" \"\"\nShape \"sphere\"",
            ),
            "Material" => w("Material \"diffuse\""),
            "ObjectBegin" | "ObjectEnd" | "ObjectInstance" => {
                w("ObjectBegin \"o\"\nShape \"sphere\"\nObjectEnd\nObjectInstance \"o\"")
            }
            "Option" => ("Option \"integer seed\" 3".into(), o()),
            "PixelFilter" => ("PixelFilter \"box\"".into(), o()),
            "ReverseOrientation" => w("ReverseOrientation\nShape \"sphere\""),
            "Rotate" => w("Rotate 30 0 1 0"),
            "Sampler" => ("Sampler \"halton\"".into(), o()),
            "Scale" => w("Scale 2 2 2"),
            "Shape" => w("Shape \"sphere\""),
            "Texture" => w("Texture \"t\" \"float\" \"constant\""),
            "Transform" => w("Transform [1 0 0 0 0 1 0 0 0 0 1 0 0 0 0 1]"),
            "TransformBegin" | "TransformEnd" => w("TransformBegin\nTransformEnd"),
            "TransformTimes" => ("TransformTimes 0 1".into(), o()),
            "Translate" => w("Translate 1 2 3"),
            "WorldBegin" => w(""),
            "WorldEnd" => w("WorldEnd"),
            _ => panic!("no scene for directive {name}"),
        },
        "Shapes" => w(&format!(
            "Shape \"{name}\" {}",
            match name {
                "trianglemesh" | "loopsubdiv" => TRI.to_string(),
                "plymesh" => "\"string filename\" \"q.ply\"".into(),
                "bilinearmesh" => {
                    r#""point3 P" [0 0 0 1 0 0 0 1 0 1 1 0] "integer indices" [0 1 2 3]"#.into()
                }
                "curve" => r#""point3 P" [0 0 0 1 1 0 2 1 0 3 0 0]"#.into(),
                _ => String::new(),
            }
        )),
        "Materials" => w(&format!(
            "{}Material \"{name}\" {}\nShape \"sphere\"",
            if name == "mix" {
                "MakeNamedMaterial \"a\" \"string type\" \"diffuse\"\n"
            } else {
                ""
            },
            match name {
                "mix" => r#""string materials" ["a" "a"]"#,
                "measured" => r#""string filename" "missing.bsdf""#,
                _ => "",
            }
        )),
        "Float textures" | "Spectrum textures" => {
            let (kind, slot) = if heading == "Float textures" {
                ("float", "float roughness")
            } else {
                ("spectrum", "spectrum reflectance")
            };
            let slot_ty = slot.split(' ').nth(1).unwrap();
            let extra = match name {
                "imagemap" => "\"string filename\" \"t.png\"",
                "ptex" => "\"string filename\" \"t.ptx\"",
                _ => "",
            };
            let material = if kind == "float" {
                "conductor"
            } else {
                "diffuse"
            };
            w(&format!(
                "Texture \"t\" \"{kind}\" \"{name}\" {extra}\n\
                 Material \"{material}\" \"texture {slot_ty}\" \"t\"\nShape \"sphere\""
            ))
        }
        "Texture mappings" => w(&format!(
            "Texture \"t\" \"spectrum\" \"checkerboard\" \"string mapping\" \"{name}\"\n\
             Material \"diffuse\" \"texture reflectance\" \"t\"\nShape \"sphere\""
        )),
        "Lights" => w(&format!(
            "LightSource \"{name}\" {}",
            match name {
                "goniometric" | "projection" => "\"string filename\" \"t.png\"",
                _ => "",
            }
        )),
        "Area lights" => w(&format!("AreaLightSource \"{name}\"\nShape \"sphere\"")),
        "Cameras" => (
            format!(
                "Camera \"{name}\" {}",
                if name == "realistic" {
                    "\"string lensfile\" \"lens.dat\""
                } else {
                    ""
                }
            ),
            o(),
        ),
        "Samplers" => (format!("Sampler \"{name}\""), o()),
        "Filters" => (format!("PixelFilter \"{name}\""), o()),
        "Films" => (
            format!("Film \"{name}\" \"string filename\" \"out.exr\""),
            o(),
        ),
        "Integrators" => (format!("Integrator \"{name}\""), o()),
        "Light samplers" => (
            format!("Integrator \"path\" \"string lightsampler\" \"{name}\""),
            o(),
        ),
        "Accelerators" => (format!("Accelerator \"{name}\""), o()),
        "Media" => w(&format!(
            "MakeNamedMedium \"f\" \"string type\" \"{name}\" {}\nMediumInterface \"f\" \"\"\nShape \"sphere\"",
            match name {
                "uniformgrid" =>
                    r#""integer nx" 1 "integer ny" 1 "integer nz" 1 "float density" [1]"#,
                "rgbgrid" => {
                    r#""integer nx" 1 "integer ny" 1 "integer nz" 1 "rgb sigma_a" [1 1 1] "rgb sigma_s" [1 1 1]"#
                }
                "nanovdb" => r#""string filename" "missing.nvdb""#,
                _ => "",
            }
        )),
        "Named spectra" => w(&if name.starts_with("glass") {
            format!("Material \"dielectric\" \"spectrum eta\" \"{name}\"\nShape \"sphere\"")
        } else if name.starts_with("metal") {
            format!("Material \"conductor\" \"spectrum eta\" \"{name}\"\nShape \"sphere\"")
        } else {
            format!("LightSource \"point\" \"spectrum I\" \"{name}\"")
        }),
        "Camera sensors" => (format!("Film \"rgb\" \"string sensor\" \"{name}\""), o()),
        "Colour spaces" => (format!("ColorSpace \"{name}\""), o()),
        _ => panic!("no scenes for heading {heading}"),
    }
}

/// What the reader says about `name` of kind `heading`: Err(error) or Ok(warnings).
fn outcome(dir: &Path, heading: &str, name: &str) -> Result<Vec<String>, String> {
    let (options, world) = scene(heading, name);
    let path = dir.join("s.pbrt");
    std::fs::write(&path, format!("{options}\nWorldBegin\n{world}\n")).unwrap();
    load(&path)
        .map(|l| l.warnings.iter().map(|w| w.to_string()).collect())
        .map_err(|e| e.to_string())
}

fn unsupported_class(warnings: &[String]) -> bool {
    warnings
        .iter()
        .any(|w| UNSUPPORTED.iter().any(|p| w.to_lowercase().contains(p)))
}

/// The rows of README's "pbrt-v4 coverage" section: (heading, type, status).
fn readme_rows() -> Vec<(String, String, String)> {
    let readme =
        std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("../../README.md"))
            .unwrap();
    let start = readme
        .find("\n## pbrt-v4 coverage\n")
        .expect("README has the section");
    let section = &readme[start + 1..];
    let end = section[3..].find("\n## ").map_or(section.len(), |e| e + 3);
    let mut heading = String::new();
    let mut rows = Vec::new();
    for line in section[..end].lines() {
        if let Some(h) = line.strip_prefix("### ") {
            heading = h.trim().to_string();
        } else if line.starts_with("| `") {
            let cells: Vec<&str> = line.split('|').map(str::trim).collect();
            let status = cells[2].to_string();
            assert!(
                ["supported", "approximated", "not supported"].contains(&status.as_str()),
                "{line}"
            );
            for (i, name) in cells[1].split('`').enumerate() {
                if i % 2 == 1 {
                    rows.push((heading.clone(), name.to_string(), status.clone()));
                }
            }
        }
    }
    rows
}

#[test]
fn readme_coverage_table_lists_every_pbrt_type_once() {
    let rows = readme_rows();
    let mut listed: Vec<(String, String)> = rows
        .iter()
        .map(|(h, n, _)| (h.clone(), n.clone()))
        .collect();
    listed.sort();
    let before = listed.len();
    listed.dedup();
    assert_eq!(before, listed.len(), "a type is listed twice");
    let mut expected: Vec<(String, String)> = PBRT_TYPES
        .iter()
        .flat_map(|(h, names)| names.iter().map(|n| (h.to_string(), n.to_string())))
        .collect();
    expected.sort();
    let missing: Vec<_> = expected.iter().filter(|e| !listed.contains(e)).collect();
    let extra: Vec<_> = listed.iter().filter(|l| !expected.contains(l)).collect();
    assert!(
        missing.is_empty() && extra.is_empty(),
        "missing {missing:?}, extra {extra:?}"
    );
}

#[test]
fn readme_coverage_table_statuses_are_what_the_reader_does() {
    let dir = ScratchDir::new("coverage");
    write_files(&dir);
    let mut wrong = Vec::new();
    for (heading, name, status) in readme_rows() {
        let (options, world) = scene(&heading, &name);
        let needs_missing_file = format!("{options}{world}").contains("missing.");
        let got = outcome(&dir, &heading, &name);
        let ok = match (status.as_str(), &got) {
            ("supported", Ok(w)) => !unsupported_class(w),
            // Types whose data file is not at hand here (a measured BSDF, a NanoVDB grid):
            // the reader accepts the type and fails only on reading the file.
            ("supported", Err(e)) => needs_missing_file && e.contains("cannot read"),
            ("approximated", got) => got.is_ok(),
            ("not supported", Ok(w)) => unsupported_class(w),
            ("not supported", Err(_)) => true,
            _ => false,
        };
        if !ok {
            wrong.push(format!("{heading} / {name} marked {status}: {got:?}"));
        }
    }
    assert!(wrong.is_empty(), "{wrong:#?}");
}

/// Prints what the reader says about every pbrt-v4 type (`cargo test -- --ignored probe
/// --nocapture`), to write the table from.
#[test]
#[ignore]
fn probe() {
    let dir = ScratchDir::new("coverage-probe");
    write_files(&dir);
    for (heading, names) in PBRT_TYPES {
        for name in *names {
            println!("{heading} / {name}: {:?}", outcome(&dir, heading, name));
        }
    }
}

//! Tests of the parser: directives, locations, includes, imports and gzip.

use super::*;

fn all(src: &str) -> Result<Vec<Directive>, SceneError> {
    let mut p = Parser::from_str(src, "t.pbrt", Path::new("."));
    let mut out = Vec::new();
    while let Some(d) = p.next_directive()? {
        out.push(d.directive);
    }
    Ok(out)
}

fn err(src: &str) -> (u32, u32, String) {
    let e = all(src).unwrap_err();
    let l = e.location.expect("located");
    (l.line, l.col, e.message)
}

#[test]
fn directives_and_arguments() {
    let d = all(
        "LookAt 0 0 5  0 0 0  0 1 0\nTransform [1 0 0 0 0 1 0 0 0 0 1 0 0 0 0 1]\n\
                 Shape \"sphere\" \"float radius\" 2 Texture \"t\" \"spectrum\" \"checkerboard\"",
    )
    .unwrap();
    assert!(matches!(d[0], Directive::LookAt(v) if v[2] == 5.0));
    assert!(matches!(d[1], Directive::Transform(m) if m[15] == 1.0));
    assert!(
        matches!(&d[2], Directive::Shape(n, p) if n == "sphere" && p.float("radius", 1.0).unwrap() == 2.0)
    );
    assert!(matches!(&d[3], Directive::Texture(n, _, c, _) if n == "t" && c == "checkerboard"));
}

#[test]
fn malformed_input_is_located() {
    assert_eq!(err("WorldBegin\nSphere \"sphere\"").0, 2);
    assert!(err("Shap \"sphere\"").2.contains("did you mean Shape"));
    assert_eq!(err("Shape \"sphere\" \"float radius\" [2 3").1, 31);
    assert_eq!(err("Translate 1 2").0, 1);
    assert!(err("Translate 1 nan 2").2.contains("finite"));
    assert!(
        err("Shape \"sphere\" \"float radius\" [nan]")
            .2
            .contains("finite")
    );
    assert!(
        err("Shape \"sphere\" \"float radius\"")
            .2
            .contains("no value")
    );
    assert!(err("Shape \"sphere\" \"radius\" 1").2.contains("type name"));
    assert!(err("Shape \"sphere\" 1").2.contains("expected a parameter"));
    assert!(
        err("Include \"does-not-exist.pbrt\"")
            .2
            .contains("no such file")
    );
}

/// A fresh folder for the files of `test`.
fn folder(test: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("lancer-parser-{test}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn gzip(text: &str) -> Vec<u8> {
    use std::io::Write;
    let mut enc = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::default());
    enc.write_all(text.as_bytes()).unwrap();
    enc.finish().unwrap()
}

/// The directives of the file `main` in `dir`, with the file and line each starts at.
fn all_in(dir: &Path, main: &str) -> Result<Vec<(Directive, String, u32)>, SceneError> {
    let mut p = Parser::from_file(&dir.join(main))?;
    let mut out = Vec::new();
    while let Some(d) = p.next_directive()? {
        let file = Path::new(&*d.loc.file).file_name().unwrap();
        out.push((d.directive, file.to_string_lossy().into_owned(), d.loc.line));
    }
    Ok(out)
}

#[test]
fn gzip_compressed_scenes_and_includes_are_read() {
    let dir = folder("gzip");
    std::fs::write(
        dir.join("geom.pbrt.gz"),
        gzip("# compressed\nShape \"sphere\" \"float radius\" [0.5]\n"),
    )
    .unwrap();
    // Recognised by its bytes, not its name.
    std::fs::write(dir.join("more.txt"), gzip("Shape \"disk\"\n")).unwrap();
    std::fs::write(
        dir.join("main.pbrt"),
        "WorldBegin\nInclude \"geom.pbrt.gz\"\nInclude \"more.txt\"\nShape \"cylinder\"\n",
    )
    .unwrap();
    std::fs::write(
        dir.join("main.pbrt.gz"),
        gzip("WorldBegin\nShape \"cone\"\n"),
    )
    .unwrap();
    let d = all_in(&dir, "main.pbrt").unwrap();
    let shapes: Vec<_> = d
        .iter()
        .filter_map(|(d, f, l)| match d {
            Directive::Shape(ty, p) => Some((ty.as_str(), p.float("radius", 1.0).unwrap(), f, *l)),
            _ => None,
        })
        .collect();
    assert_eq!(
        shapes,
        [
            ("sphere", 0.5, &"geom.pbrt.gz".to_string(), 2),
            ("disk", 1.0, &"more.txt".to_string(), 1),
            ("cylinder", 1.0, &"main.pbrt".to_string(), 4),
        ]
    );
    let d = all_in(&dir, "main.pbrt.gz").unwrap();
    assert!(matches!(&d[1].0, Directive::Shape(ty, _) if ty == "cone"));
    // A damaged stream is an error at the Include.
    let mut bad = gzip("Shape \"sphere\"\n");
    bad.truncate(bad.len() - 6);
    std::fs::write(dir.join("bad.pbrt.gz"), bad).unwrap();
    std::fs::write(
        dir.join("b.pbrt"),
        "WorldBegin\n  Include \"bad.pbrt.gz\"\n",
    )
    .unwrap();
    let e = all_in(&dir, "b.pbrt").unwrap_err();
    let l = e.location.clone().unwrap();
    assert_eq!((l.line, l.col), (2, 3));
    assert!(e.message.contains("cannot decompress"), "{}", e.message);
}

#[test]
fn a_parameter_list_continues_after_an_include() {
    let dir = folder("continues");
    std::fs::write(
        dir.join("shape.pbrt"),
        "Material \"diffuse\"\nShape \"sphere\"",
    )
    .unwrap();
    std::fs::write(
        dir.join("main.pbrt"),
        "WorldBegin\nInclude \"shape.pbrt\"\n  \"float radius\" [0.5]\nShape \"disk\"\n",
    )
    .unwrap();
    let d = all_in(&dir, "main.pbrt").unwrap();
    assert_eq!(d.len(), 4);
    let Directive::Shape(ty, p) = &d[2].0 else {
        panic!("a shape, not {:?}", d[2].0)
    };
    assert_eq!(
        (ty.as_str(), d[2].1.as_str(), d[2].2),
        ("sphere", "shape.pbrt", 2)
    );
    assert_eq!(p.float("radius", 1.0).unwrap(), 0.5);
    // The parameter keeps its own place, in the including file.
    let loc = p.location("radius").unwrap();
    assert!(loc.file.ends_with("main.pbrt") && (loc.line, loc.col) == (3, 3));
    assert!(matches!(&d[3].0, Directive::Shape(ty, _) if ty == "disk"));
}

#[test]
fn an_import_is_framed_and_its_directives_cannot_continue_outside() {
    let dir = folder("import");
    std::fs::write(dir.join("geom.pbrt"), "Translate 0 1 0\nShape \"sphere\"").unwrap();
    std::fs::write(
        dir.join("main.pbrt"),
        "WorldBegin\nImport \"geom.pbrt\"\nShape \"disk\"\n",
    )
    .unwrap();
    let d = all_in(&dir, "main.pbrt").unwrap();
    let kinds: Vec<String> = d
        .iter()
        .map(|(d, f, l)| {
            let name = format!("{d:?}");
            let name = name.split(['(', ' ']).next().unwrap().to_string();
            format!("{name}@{f}:{l}")
        })
        .collect();
    assert_eq!(
        kinds,
        [
            "WorldBegin@main.pbrt:1",
            "ImportBegin@main.pbrt:2",
            "Translate@geom.pbrt:1",
            "Shape@geom.pbrt:2",
            "ImportEnd@geom.pbrt:2",
            "Shape@main.pbrt:3",
        ]
    );
    // Parameters after an Import line belong to no directive.
    std::fs::write(
        dir.join("bad.pbrt"),
        "WorldBegin\nImport \"geom.pbrt\"\n  \"float radius\" [2]\n",
    )
    .unwrap();
    let e = all_in(&dir, "bad.pbrt").unwrap_err();
    let l = e.location.unwrap();
    assert!(l.file.ends_with("bad.pbrt") && (l.line, l.col) == (3, 3));
    assert_eq!(
        e.message,
        "expected a directive, found the string \"float radius\""
    );
}

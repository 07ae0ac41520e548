//! `Material "measured"` as pbrt-v4's `MeasuredMaterial::Create` reads it: `string filename`,
//! an RGL `.bsdf` file (a tabulated BRDF, [`MeasuredFile`]), required. The file is read whole
//! (at most [`MAX_FILE_BYTES`]); what is wrong with a bad one is reported with the file's
//! name at the parameter's place.

use super::MaterialWithNames;
use crate::error::SceneError;
use crate::pbrt::convert::{Fallback, Reader};
use lancer::material::{MaterialDesc, MeasuredFile};

/// The largest `.bsdf` file read (RGL's are a few MB; the largest anisotropic ones ~100 MB).
pub const MAX_FILE_BYTES: u64 = 1 << 30;

/// The measured material of the directive `r` reads.
pub(super) fn measured(r: &Reader) -> Result<Fallback<MaterialWithNames>, SceneError> {
    let p = r.params;
    let Some(name) = p.string("filename")?.filter(|n| !n.is_empty()) else {
        return Err(SceneError::general(
            "material \"measured\" needs \"string filename\" (an RGL .bsdf file)",
        ));
    };
    let path = r.dir.resolve(&name);
    let fail = |what: String| p.error_at("filename", format!("{}: {what}", path.display()));
    let len = std::fs::metadata(&path)
        .map_err(|e| fail(format!("cannot read the file: {e}")))?
        .len();
    if len > MAX_FILE_BYTES {
        return Err(fail(format!(
            "{len} bytes; .bsdf files over {MAX_FILE_BYTES} bytes are refused"
        )));
    }
    crate::files_read::record(&path);
    let bytes = std::fs::read(&path).map_err(|e| fail(format!("cannot read the file: {e}")))?;
    let data = MeasuredFile::shared(&bytes, &path.display().to_string())
        .map_err(|e| fail(format!("not a valid .bsdf file: {e}")))?;
    Ok(Fallback::done(MaterialDesc::Measured(data).into()))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::pbrt::convert::testing::{err, typed_in, unused, with_reader};
    use lancer::material::measured::tensor::{Field, Tensor};
    use lancer_testing::ScratchDir;
    use std::path::Path;

    /// The smallest consistent file: every table 2 × 2 and constant, two θᵢ nodes, one φᵢ,
    /// spectra at two wavelengths; `drop` leaves one field out.
    fn tiny(drop: &str) -> Vec<u8> {
        let four = |v: f32| Field::f32(&[1, 2, 2, 2], &[v; 8]);
        let fields = [
            ("theta_i", Field::f32(&[2], &[0.0, 1.5])),
            ("phi_i", Field::f32(&[1], &[0.0])),
            ("ndf", Field::f32(&[2, 2], &[0.3; 4])),
            ("sigma", Field::f32(&[2, 2], &[0.9; 4])),
            ("vndf", four(1.0)),
            ("luminance", four(1.0)),
            ("wavelengths", Field::f32(&[2], &[400.0, 700.0])),
            ("spectra", Field::f32(&[1, 2, 2, 2, 2], &[0.5; 16])),
            ("description", Field::u8(&[4], b"tiny")),
        ];
        let kept: Vec<(&str, &Field)> = fields
            .iter()
            .filter(|(n, _)| *n != drop)
            .map(|(n, f)| (*n, f))
            .collect();
        Tensor::write(&kept)
    }

    fn read(dir: &Path, text: &str) -> Result<Fallback<MaterialWithNames>, SceneError> {
        let (ty, params, loc) = typed_in(text, dir);
        assert_eq!(ty, "measured");
        let out = with_reader(&params, dir, |r| super::super::material(r, &ty, &loc));
        assert!(unused(&params).is_empty());
        out
    }

    #[test]
    fn a_bsdf_file_becomes_a_measured_material() {
        let dir = ScratchDir::new("measured-ok");
        std::fs::write(&*dir.join("tiny.bsdf"), tiny("")).unwrap();
        let f = read(&dir, r#"Material "measured" "string filename" "tiny.bsdf""#).unwrap();
        assert!(f.warnings.is_empty(), "{:?}", f.warnings);
        let MaterialDesc::Measured(d) = f.value.material else {
            panic!("{:?}", f.value.material)
        };
        assert!(d.isotropic && d.description == "tiny");
        assert_eq!(d.wavelengths, [400.0, 700.0]);
        assert!(d.name.ends_with("tiny.bsdf"));
    }

    #[test]
    fn bad_files_are_errors_naming_the_file_and_the_fault() {
        let dir = ScratchDir::new("measured-bad");
        let p = &*dir;
        std::fs::write(p.join("nospectra.bsdf"), tiny("spectra")).unwrap();
        std::fs::write(p.join("novndf.bsdf"), tiny("vndf")).unwrap();
        std::fs::write(p.join("text.bsdf"), b"# not a tensor\n").unwrap();
        let mut cut = tiny("");
        cut.truncate(cut.len() - 3);
        std::fs::write(p.join("cut.bsdf"), cut).unwrap();
        let e = |file: &str| {
            err(read(
                p,
                &format!("Material \"measured\"\n  \"string filename\" \"{file}\""),
            ))
        };
        let at = |file: &str| format!("t.pbrt:2:3: {}: ", p.join(file).display());
        assert_eq!(
            e("novndf.bsdf"),
            at("novndf.bsdf") + "not a valid .bsdf file: the file has no \"vndf\" field"
        );
        assert_eq!(
            e("nospectra.bsdf"),
            at("nospectra.bsdf")
                + "not a valid .bsdf file: the file has neither a \"spectra\" nor an \"rgb\" field"
        );
        assert_eq!(
            e("text.bsdf"),
            at("text.bsdf")
                + "not a valid .bsdf file: not a tensor file (it does not start with \"tensor_file\")"
        );
        assert!(
            e("cut.bsdf")
                .starts_with(&(at("cut.bsdf") + "not a valid .bsdf file: field \"description\"")),
            "{}",
            e("cut.bsdf")
        );
        assert!(e("missing.bsdf").starts_with(&(at("missing.bsdf") + "cannot read the file:")));
        assert_eq!(
            err(read(p, r#"Material "measured""#)),
            "t.pbrt:1:1: material \"measured\" needs \"string filename\" (an RGL .bsdf file)"
        );
    }
}

//! `Material "subsurface"` as pbrt-v4's `SubsurfaceMaterial::Create` reads it: the medium by
//! `name` (a measured preset, g forced to 0), or `sigma_a` with `sigma_s`, or `reflectance`
//! with `mfp` (default 1), or pbrt-v4's default (whole milk's coefficients, per mm); `scale`
//! (1), `eta` (1.33), `g` (0), `roughness`/`uroughness`/`vroughness` (0), `remaproughness`.

use super::{MaterialWithNames, roughness};
use crate::error::SceneError;
use crate::pbrt::convert::{Fallback, Reader};
use lancer::material::{MaterialDesc, SubsurfaceCoefficients, SubsurfaceMaterial};
use lancer::math::Rgb;
use lancer::spectrum::{SpectrumKind, scattering_preset, scattering_preset_names};
use lancer::texture::SpectrumTex;

/// The subsurface material of the directive `r` reads.
pub(super) fn subsurface(r: &Reader) -> Result<Fallback<MaterialWithNames>, SceneError> {
    let p = r.params;
    let mut g = p.float("g", 0.0)?;
    let mut notes = Vec::new();
    let coefficients = if let Some(name) = p.string("name")? {
        let Some(preset) = scattering_preset(&name) else {
            let known: Vec<&str> = scattering_preset_names().collect();
            return Err(SceneError::general(format!(
                "\"{name}\": no such named medium (pbrt-v4's are {})",
                known.join(", ")
            )));
        };
        if g != 0.0 {
            notes.push(
                "non-zero \"g\" ignored with named scattering coefficients (as pbrt-v4 does)"
                    .to_string(),
            );
        }
        // The presets give reduced scattering coefficients: g = 0.
        g = 0.0;
        SubsurfaceCoefficients::Coefficients {
            sigma_a: SpectrumTex::Const(preset.sigma_a),
            sigma_s: SpectrumTex::Const(preset.sigma_prime_s),
        }
    } else {
        let sigma_a = r.opt_spectrum_tex("sigma_a", SpectrumKind::Unbounded)?;
        let sigma_s = r.opt_spectrum_tex("sigma_s", SpectrumKind::Unbounded)?;
        match (sigma_a, sigma_s) {
            (Some(sigma_a), Some(sigma_s)) => {
                SubsurfaceCoefficients::Coefficients { sigma_a, sigma_s }
            }
            (Some(_), None) => {
                return Err(SceneError::general(
                    "material \"subsurface\" has \"sigma_a\" without \"sigma_s\"",
                ));
            }
            (None, Some(_)) => {
                return Err(SceneError::general(
                    "material \"subsurface\" has \"sigma_s\" without \"sigma_a\"",
                ));
            }
            (None, None) => match r.opt_spectrum_tex("reflectance", SpectrumKind::Albedo)? {
                Some(reflectance) => SubsurfaceCoefficients::Reflectance {
                    reflectance,
                    mfp: r.spectrum_tex("mfp", Rgb::ONE, SpectrumKind::Unbounded)?,
                },
                None => SubsurfaceCoefficients::Coefficients {
                    sigma_a: SpectrumTex::Const(Rgb::new(0.0011, 0.0024, 0.014)),
                    sigma_s: SpectrumTex::Const(Rgb::new(2.55, 3.21, 3.77)),
                },
            },
        }
    };
    let scale = p.float("scale", 1.0)?;
    let eta = p.float("eta", 1.33)?;
    if !(eta > 0.0 && eta.is_finite()) {
        return Err(SceneError::general(format!(
            "\"float eta\" of a subsurface material must be positive, not {eta}"
        )));
    }
    if !g.is_finite() {
        return Err(SceneError::general("\"float g\" must be finite"));
    }
    let g = g.clamp(-0.99, 0.99);
    let (uroughness, vroughness) = roughness(r, "")?;
    let m = MaterialDesc::Subsurface(SubsurfaceMaterial {
        coefficients,
        scale,
        eta,
        uroughness,
        vroughness,
        remap_roughness: p.bool("remaproughness", true)?,
        g,
    });
    Ok(Fallback::noted(m.into(), notes))
}

#[cfg(test)]
mod tests {
    use crate::pbrt::convert::TextureNames;
    use crate::pbrt::convert::testing::{err, typed, unused, with_textures};
    use crate::pbrt::materials::material;
    use lancer::material::{MaterialDesc, SubsurfaceCoefficients, SubsurfaceMaterial};
    use lancer::math::Rgb;
    use lancer::texture::{FloatTex, SpectrumTex};
    use std::path::Path;

    /// The material of `text`, its warnings, and the parameters it left unread.
    fn convert(text: &str) -> Result<(MaterialDesc, Vec<String>, Vec<String>), String> {
        let (ty, params, loc) = typed(text);
        let out = with_textures(&params, Path::new("."), &TextureNames::default(), |r| {
            material(r, &ty, &loc)
        });
        let unused = unused(&params);
        match out {
            Ok(f) => Ok((f.value.material, f.warnings, unused)),
            Err(e) => Err(err::<()>(Err(e))),
        }
    }

    #[test]
    fn every_way_of_giving_the_medium() {
        let (m, w, u) = convert(r#"Material "subsurface""#).unwrap();
        assert!(w.is_empty() && u.is_empty());
        let MaterialDesc::Subsurface(SubsurfaceMaterial {
            coefficients,
            scale,
            eta,
            uroughness,
            remap_roughness,
            g,
            ..
        }) = m
        else {
            panic!("{m:?}")
        };
        assert_eq!(
            coefficients,
            SubsurfaceCoefficients::Coefficients {
                sigma_a: SpectrumTex::Const(Rgb::new(0.0011, 0.0024, 0.014)),
                sigma_s: SpectrumTex::Const(Rgb::new(2.55, 3.21, 3.77)),
            }
        );
        assert_eq!(
            (scale, eta, uroughness, remap_roughness),
            (1.0, 1.33, FloatTex::Const(0.0), true)
        );
        assert_eq!(g, 0.0);

        // A preset forces g = 0, with pbrt-v4's note.
        let (m, w, _) = convert(
            r#"Material "subsurface" "string name" "Skin1" "float g" 0.5 "float scale" 20"#,
        )
        .unwrap();
        assert_eq!(
            w,
            ["non-zero \"g\" ignored with named scattering coefficients (as pbrt-v4 does)"]
        );
        let MaterialDesc::Subsurface(SubsurfaceMaterial {
            coefficients,
            scale,
            g,
            ..
        }) = m
        else {
            panic!()
        };
        assert_eq!(
            coefficients,
            SubsurfaceCoefficients::Coefficients {
                sigma_a: SpectrumTex::Const(Rgb::new(0.032, 0.17, 0.48)),
                sigma_s: SpectrumTex::Const(Rgb::new(0.74, 0.88, 1.01)),
            }
        );
        assert_eq!((scale, g), (20.0, 0.0));

        let (m, _, u) = convert(
            r#"Material "subsurface" "rgb reflectance" [0.8 0.6 0.3] "float eta" 1.5 "float g" 0.3 "float roughness" 0.1"#,
        )
        .unwrap();
        assert!(u.is_empty());
        let MaterialDesc::Subsurface(SubsurfaceMaterial {
            coefficients,
            vroughness,
            g,
            eta,
            ..
        }) = m
        else {
            panic!()
        };
        assert_eq!(
            coefficients,
            SubsurfaceCoefficients::Reflectance {
                reflectance: SpectrumTex::Const(Rgb::new(0.8, 0.6, 0.3)),
                mfp: SpectrumTex::Const(Rgb::ONE),
            }
        );
        assert_eq!((vroughness, g, eta), (FloatTex::Const(0.1), 0.3, 1.5));
    }

    #[test]
    fn errors_name_what_is_wrong() {
        assert_eq!(
            convert(r#"Material "subsurface" "rgb sigma_a" [1 1 1]"#).unwrap_err(),
            "t.pbrt:1:1: material \"subsurface\" has \"sigma_a\" without \"sigma_s\""
        );
        let e = convert(r#"Material "subsurface" "string name" "Soup""#).unwrap_err();
        assert!(
            e.starts_with(
                "t.pbrt:1:1: \"Soup\": no such named medium (pbrt-v4's are Apple, Chicken1"
            ),
            "{e}"
        );
        assert_eq!(
            convert(r#"Material "subsurface" "float eta" 0"#).unwrap_err(),
            "t.pbrt:1:1: \"float eta\" of a subsurface material must be positive, not 0"
        );
    }
}

//! `Material` and `MakeNamedMaterial`: pbrt-v4's materials as lancer's [`Material`], with
//! pbrt-v4's defaults. A `mix` names two materials that may not be defined yet: they come back
//! beside it, for the builder to resolve once every name is known.

mod measured;
mod subsurface;

use super::convert::{Fallback, Reader, locate};
use crate::error::{Location, SceneError};
use crate::image_read::Encoding;
use lancer::material::MaterialDesc;
use lancer::material::{
    BumpedMaterial, CoatedConductorMaterial, CoatedDiffuseMaterial, ConductorMaterial,
    DielectricMaterial, DiffuseMaterial, DiffuseTransmissionMaterial, InterfaceMaterial,
    MixMaterial, ThinDielectricMaterial,
};
use lancer::math::Rgb;
use lancer::scene::desc::SceneDesc;
use lancer::spectrum::{SpectrumKind, named_spectrum, spectrum_to_rgb};
use lancer::texture::{
    FloatTex, ImageFilter, ImageTextureDesc, Mapping2D, SpectrumTex, SpectrumTextureDesc, WrapMode,
};

/// A material, and for a `mix` the two names it refers to and where they are written.
#[derive(Clone, Debug)]
pub struct MaterialWithNames {
    /// The material (a `mix` holds placeholder indices until its names are resolved).
    pub material: MaterialDesc,
    /// The names of a `mix`, and where they are given.
    pub mix: Option<(Vec<String>, Location)>,
    /// Its bump or normal map, which the builder wraps around it ([`MaterialDesc::Bumped`]).
    pub bump: Option<BumpMaps>,
}

impl From<MaterialDesc> for MaterialWithNames {
    fn from(material: MaterialDesc) -> MaterialWithNames {
        MaterialWithNames {
            material,
            mix: None,
            bump: None,
        }
    }
}

/// A material's `"texture displacement"` and `"string normalmap"` (pbrt-v4 reads both on
/// every material but `mix` and `interface`; the normal map wins when both are given).
#[derive(Clone, Debug)]
pub struct BumpMaps {
    /// Height texture.
    pub displacement: Option<FloatTex>,
    /// The tangent-space normal image as pbrt-v4 reads it: linear, bilinear, repeat, at the
    /// surface's (u, v) (the image's row 0 at v = 1).
    pub normal_map: Option<ImageTextureDesc>,
}

impl BumpMaps {
    /// Adds these maps around material `base` of `desc`: the normal map as a spectrum texture,
    /// then a [`MaterialDesc::Bumped`] referring to both; returns the latter's index.
    pub fn push_around(self, base: u32, desc: &mut SceneDesc) -> u32 {
        let normal_map = self.normal_map.map(|t| {
            desc.spectrum_textures.push(SpectrumTextureDesc::Image(t));
            desc.spectrum_textures.len() as u32 - 1
        });
        desc.materials.push(MaterialDesc::Bumped(BumpedMaterial {
            base,
            displacement: self.displacement,
            normal_map,
        }));
        desc.materials.len() as u32 - 1
    }
}

/// The bump maps of a material's parameters, if any.
fn bump_maps(r: &Reader) -> Result<Option<BumpMaps>, SceneError> {
    let displacement = if r.params.has("displacement") {
        Some(r.float_tex("displacement", 0.0)?)
    } else {
        None
    };
    let normal_map = match r.params.string("normalmap")?.filter(|n| !n.is_empty()) {
        None => None,
        Some(name) => {
            let image = r
                .images
                .rgb(&r.dir.resolve(&name), Encoding::Linear)
                .map_err(|e| r.params.error_at("normalmap", e.to_string()))?;
            // pbrt-v4's NormalMap reads the image itself bilinearly (no MIP filtering).
            Some(ImageTextureDesc {
                image,
                to_srgb: None,
                mip: false,
                mapping: Mapping2D::default(),
                wrap: WrapMode::Repeat,
                scale: 1.0,
                invert: false,
                filter: ImageFilter::Bilinear,
            })
        }
    };
    Ok(
        (displacement.is_some() || normal_map.is_some()).then_some(BumpMaps {
            displacement,
            normal_map,
        }),
    )
}

/// The linear RGB of one of pbrt's named spectra (the metals' η and k).
fn named_rgb(name: &str) -> Rgb {
    named_spectrum(name)
        .map(|s| spectrum_to_rgb(&s, SpectrumKind::Unbounded))
        .expect("pbrt's named metal spectra are built in")
}

/// pbrt's named metal spectrum `name` as a conductor's default `eta` or `k`: the reduction RGB
/// mode uses ([`named_rgb`]) and the tabulated data spectral mode samples.
fn named_metal(name: &str) -> SpectrumTex {
    let data = lancer::spectrum::named_spectrum_data(name)
        .expect("pbrt's named metal spectra are built in");
    SpectrumTex::Measured(lancer::spectrum::dense::Measured::new(
        &data,
        named_rgb(name),
        SpectrumKind::Unbounded,
    ))
}

/// `uroughness`/`vroughness`, each defaulting to `roughness` (all prefixed by `prefix`, as in
/// `interface.` for the coated materials).
fn roughness(r: &Reader, prefix: &str) -> Result<(FloatTex, FloatTex), SceneError> {
    let rough = r.float_tex(&format!("{prefix}roughness"), 0.0)?;
    let one = |axis: &str| {
        let name = format!("{prefix}{axis}roughness");
        if r.params.has(&name) {
            r.float_tex(&name, 0.0)
        } else {
            Ok(rough)
        }
    };
    Ok((one("u")?, one("v")?))
}

/// The layered materials' random walk: `maxdepth` (default 10) and `nsamples` (default 1).
fn walk(r: &Reader) -> Result<(u32, u32), SceneError> {
    Ok((
        r.params.int_in("maxdepth", 10, 0..=1000)? as u32,
        r.params.int_in("nsamples", 1, 1..=1000)? as u32,
    ))
}

/// The material `ty` at `loc`; an unknown or unsupported one becomes a diffuse one, with a
/// warning.
pub fn material(
    r: &Reader,
    ty: &str,
    loc: &Location,
) -> Result<Fallback<MaterialWithNames>, SceneError> {
    let with_bump = |mut m: Fallback<MaterialWithNames>| -> Result<_, SceneError> {
        if !matches!(
            m.value.material,
            MaterialDesc::Mix(_) | MaterialDesc::Interface(_)
        ) {
            m.value.bump = bump_maps(r)?;
        }
        Ok(m)
    };
    convert(r, ty)
        .and_then(with_bump)
        .map_err(|e| locate(e, loc))
}

fn convert(r: &Reader, ty: &str) -> Result<Fallback<MaterialWithNames>, SceneError> {
    use SpectrumKind::{Albedo, Unbounded};
    let p = r.params;
    let remap = || p.bool("remaproughness", true);
    let diffuse = |default: f32| -> Result<MaterialDesc, SceneError> {
        Ok(MaterialDesc::Diffuse(DiffuseMaterial {
            reflectance: r.spectrum_tex("reflectance", Rgb::splat(default), Albedo)?,
        }))
    };
    let m = match ty {
        "diffuse" => diffuse(0.5)?,
        "conductor" => {
            let (uroughness, vroughness) = roughness(r, "")?;
            MaterialDesc::Conductor(ConductorMaterial {
                eta: r.spectrum_tex_or("eta", named_metal("metal-Cu-eta"), Unbounded)?,
                k: r.spectrum_tex_or("k", named_metal("metal-Cu-k"), Unbounded)?,
                reflectance: r.opt_spectrum_tex("reflectance", Albedo)?,
                uroughness,
                vroughness,
                remap_roughness: remap()?,
            })
        }
        "dielectric" => {
            let (uroughness, vroughness) = roughness(r, "")?;
            MaterialDesc::Dielectric(DielectricMaterial {
                eta: p.dielectric_ior("eta", 1.5, r.dir)?,
                uroughness,
                vroughness,
                remap_roughness: remap()?,
            })
        }
        "thindielectric" => MaterialDesc::ThinDielectric(ThinDielectricMaterial {
            eta: p.dielectric_ior("eta", 1.5, r.dir)?,
        }),
        "diffusetransmission" => MaterialDesc::DiffuseTransmission(DiffuseTransmissionMaterial {
            reflectance: r.spectrum_tex("reflectance", Rgb::splat(0.25), Albedo)?,
            transmittance: r.spectrum_tex("transmittance", Rgb::splat(0.25), Albedo)?,
            scale: p.float("scale", 1.0)?,
        }),
        "coateddiffuse" => {
            let (uroughness, vroughness) = roughness(r, "")?;
            let reflectance = r.spectrum_tex("reflectance", Rgb::splat(0.5), Albedo)?;
            let thickness = r.float_tex("thickness", 0.01)?;
            let eta = p.dielectric_ior("eta", 1.5, r.dir)?;
            let albedo = r.spectrum_tex("albedo", Rgb::ZERO, Albedo)?;
            let g = r.float_tex("g", 0.0)?;
            let (max_depth, n_samples) = walk(r)?;
            MaterialDesc::CoatedDiffuse(CoatedDiffuseMaterial {
                reflectance,
                uroughness,
                vroughness,
                thickness,
                eta,
                albedo,
                g,
                max_depth,
                n_samples,
                remap_roughness: remap()?,
            })
        }
        "coatedconductor" => {
            let (interface_uroughness, interface_vroughness) = roughness(r, "interface.")?;
            let (conductor_uroughness, conductor_vroughness) = roughness(r, "conductor.")?;
            let interface_eta = p.dielectric_ior("interface.eta", 1.5, r.dir)?;
            let conductor_eta =
                r.spectrum_tex_or("conductor.eta", named_metal("metal-Cu-eta"), Unbounded)?;
            let k = r.spectrum_tex_or("conductor.k", named_metal("metal-Cu-k"), Unbounded)?;
            let reflectance = r.opt_spectrum_tex("reflectance", Albedo)?;
            let thickness = r.float_tex("thickness", 0.01)?;
            let albedo = r.spectrum_tex("albedo", Rgb::ZERO, Albedo)?;
            let g = r.float_tex("g", 0.0)?;
            let (max_depth, n_samples) = walk(r)?;
            MaterialDesc::CoatedConductor(CoatedConductorMaterial {
                interface_uroughness,
                interface_vroughness,
                interface_eta,
                conductor_eta,
                k,
                reflectance,
                conductor_uroughness,
                conductor_vroughness,
                thickness,
                albedo,
                g,
                max_depth,
                n_samples,
                remap_roughness: remap()?,
            })
        }
        "mix" => {
            let Some((names, loc)) = p.strings("materials")? else {
                return Err(SceneError::general(
                    "material \"mix\" needs \"string materials\" [\"a\" \"b\"]",
                ));
            };
            if names.len() != 2 {
                return Err(SceneError::at(
                    loc,
                    format!(
                        "\"string materials\" of a mix names 2 materials, not {}",
                        names.len()
                    ),
                ));
            }
            let material = MaterialDesc::Mix(MixMaterial {
                materials: [0, 0],
                amount: r.float_tex("amount", 0.5)?,
            });
            return Ok(Fallback::done(MaterialWithNames {
                material,
                mix: Some((names, loc)),
                bump: None,
            }));
        }
        "interface" | "" | "none" => MaterialDesc::Interface(InterfaceMaterial),
        "hair" => return hair(r),
        "subsurface" => return subsurface::subsurface(r),
        "measured" => return measured::measured(r),
        _ => {
            return Ok(Fallback::instead(
                MaterialDesc::default().into(),
                format!("unknown material \"{ty}\"; lancer renders it as \"diffuse\""),
            ));
        }
    };
    Ok(Fallback::done(m.into()))
}

/// pbrt-v4's `HairMaterial::Create`: absorption from the first of `sigma_a`,
/// `reflectance` (or `color`), `eumelanin`/`pheomelanin` given, the others ignored with a
/// note; eumelanin 1.3 when none is; `eta` 1.55, `beta_m` 0.3, `beta_n` 0.3, `alpha` 2.
fn hair(r: &Reader) -> Result<Fallback<MaterialWithNames>, SceneError> {
    use lancer::material::{HairAbsorption, HairMaterial};
    let sigma_a = r.opt_spectrum_tex("sigma_a", SpectrumKind::Unbounded)?;
    let mut reflectance = r.opt_spectrum_tex("reflectance", SpectrumKind::Albedo)?;
    if reflectance.is_none() {
        reflectance = r.opt_spectrum_tex("color", SpectrumKind::Albedo)?;
    }
    let has_melanin = r.params.has("eumelanin") || r.params.has("pheomelanin");
    let melanin = HairAbsorption::Melanin {
        eumelanin: r.float_tex("eumelanin", 0.0)?,
        pheomelanin: r.float_tex("pheomelanin", 0.0)?,
    };
    let mut notes = Vec::new();
    let mut ignoring = |what: &str, since: &str| {
        notes.push(format!(
            "ignoring \"{what}\" since \"{since}\" was given (as pbrt-v4 does)"
        ))
    };
    let absorption = match (sigma_a, reflectance) {
        (Some(s), refl) => {
            if refl.is_some() {
                ignoring("reflectance", "sigma_a");
            }
            if has_melanin {
                ignoring("eumelanin\"/\"pheomelanin", "sigma_a");
            }
            HairAbsorption::SigmaA(s)
        }
        (None, Some(c)) => {
            if has_melanin {
                ignoring("eumelanin\"/\"pheomelanin", "reflectance");
            }
            HairAbsorption::Reflectance(c)
        }
        (None, None) if has_melanin => melanin,
        (None, None) => HairAbsorption::Melanin {
            eumelanin: FloatTex::Const(1.3),
            pheomelanin: FloatTex::Const(0.0),
        },
    };
    let m = MaterialDesc::Hair(HairMaterial {
        absorption,
        eta: r.float_tex("eta", 1.55)?,
        beta_m: r.float_tex("beta_m", 0.3)?,
        beta_n: r.float_tex("beta_n", 0.3)?,
        alpha: r.float_tex("alpha", 2.0)?,
    });
    Ok(Fallback::noted(m.into(), notes))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::pbrt::convert::TextureNames;
    use crate::pbrt::convert::testing::{err, typed, unused, with_textures};
    use lancer::spectrum::Ior;
    use lancer::texture::SpectrumTex;
    use std::path::Path;

    /// The conversion of the one `Material` of `text` against `textures`, and the messages of
    /// the parameters it left unread.
    fn convert_with(
        text: &str,
        textures: &TextureNames,
    ) -> (Result<Fallback<MaterialWithNames>, SceneError>, Vec<String>) {
        let (ty, params, loc) = typed(text);
        let out = with_textures(&params, Path::new("."), textures, |r| {
            material(r, &ty, &loc)
        });
        (out, unused(&params))
    }

    /// A material that converts without warnings and reads every parameter.
    #[track_caller]
    fn converted(text: &str) -> MaterialDesc {
        let (out, unused) = convert_with(text, &TextureNames::default());
        let f = out.unwrap_or_else(|e| panic!("{e}"));
        assert!(f.warnings.is_empty(), "{:?}", f.warnings);
        assert!(unused.is_empty(), "{unused:?}");
        assert!(f.value.mix.is_none());
        f.value.material
    }

    #[track_caller]
    fn error(text: &str) -> String {
        err(convert_with(text, &TextureNames::default()).0)
    }

    fn grey(v: f32) -> SpectrumTex {
        SpectrumTex::Const(Rgb::splat(v))
    }

    fn rgb(r: f32, g: f32, b: f32) -> SpectrumTex {
        SpectrumTex::Const(Rgb::new(r, g, b))
    }

    const ZERO: FloatTex = FloatTex::Const(0.0);

    #[test]
    fn defaults_are_pbrt_v4s() {
        assert_eq!(
            converted(r#"Material "diffuse""#),
            MaterialDesc::Diffuse(DiffuseMaterial {
                reflectance: grey(0.5)
            })
        );
        let copper = (named_metal("metal-Cu-eta"), named_metal("metal-Cu-k"));
        assert_eq!(
            converted(r#"Material "conductor""#),
            MaterialDesc::Conductor(ConductorMaterial {
                eta: copper.0,
                k: copper.1,
                reflectance: None,
                uroughness: ZERO,
                vroughness: ZERO,
                remap_roughness: true,
            })
        );
        assert_eq!(
            converted(r#"Material "dielectric""#),
            MaterialDesc::Dielectric(DielectricMaterial {
                eta: Ior::Constant(1.5),
                uroughness: ZERO,
                vroughness: ZERO,
                remap_roughness: true,
            })
        );
        assert_eq!(
            converted(r#"Material "thindielectric""#),
            MaterialDesc::ThinDielectric(ThinDielectricMaterial {
                eta: Ior::Constant(1.5)
            })
        );
        assert_eq!(
            converted(r#"Material "diffusetransmission""#),
            MaterialDesc::DiffuseTransmission(DiffuseTransmissionMaterial {
                reflectance: grey(0.25),
                transmittance: grey(0.25),
                scale: 1.0,
            })
        );
        assert_eq!(
            converted(r#"Material "coateddiffuse""#),
            MaterialDesc::CoatedDiffuse(CoatedDiffuseMaterial {
                reflectance: grey(0.5),
                uroughness: ZERO,
                vroughness: ZERO,
                thickness: FloatTex::Const(0.01),
                eta: lancer::spectrum::Ior::Constant(1.5),
                albedo: grey(0.0),
                g: ZERO,
                max_depth: 10,
                n_samples: 1,
                remap_roughness: true,
            })
        );
        assert_eq!(
            converted(r#"Material "coatedconductor""#),
            MaterialDesc::CoatedConductor(CoatedConductorMaterial {
                interface_uroughness: ZERO,
                interface_vroughness: ZERO,
                interface_eta: lancer::spectrum::Ior::Constant(1.5),
                conductor_eta: copper.0,
                k: copper.1,
                reflectance: None,
                conductor_uroughness: ZERO,
                conductor_vroughness: ZERO,
                thickness: FloatTex::Const(0.01),
                albedo: grey(0.0),
                g: ZERO,
                max_depth: 10,
                n_samples: 1,
                remap_roughness: true,
            })
        );
        for ty in ["interface", "none", ""] {
            assert_eq!(
                converted(&format!("Material \"{ty}\"")),
                MaterialDesc::Interface(InterfaceMaterial)
            );
        }
    }

    #[test]
    fn every_parameter_is_read() {
        assert_eq!(
            converted(r#"Material "diffuse" "rgb reflectance" [0.1 0.2 0.3]"#),
            MaterialDesc::Diffuse(DiffuseMaterial {
                reflectance: rgb(0.1, 0.2, 0.3)
            })
        );
        assert_eq!(
            converted(
                r#"Material "conductor" "rgb eta" [0.2 0.3 0.4] "rgb k" [3 2 1]
                   "rgb reflectance" [0.9 0.8 0.7] "float uroughness" 0.1
                   "float vroughness" 0.2 "bool remaproughness" false"#
            ),
            MaterialDesc::Conductor(ConductorMaterial {
                eta: rgb(0.2, 0.3, 0.4),
                k: rgb(3.0, 2.0, 1.0),
                reflectance: Some(rgb(0.9, 0.8, 0.7)),
                uroughness: FloatTex::Const(0.1),
                vroughness: FloatTex::Const(0.2),
                remap_roughness: false,
            })
        );
        // `roughness` gives both directions unless one is named.
        assert_eq!(
            converted(
                r#"Material "dielectric" "float eta" 1.33 "float roughness" 0.3 "float vroughness" 0.4"#
            ),
            MaterialDesc::Dielectric(DielectricMaterial {
                eta: Ior::Constant(1.33),
                uroughness: FloatTex::Const(0.3),
                vroughness: FloatTex::Const(0.4),
                remap_roughness: true,
            })
        );
        assert_eq!(
            converted(r#"Material "thindielectric" "float eta" 1.2"#),
            MaterialDesc::ThinDielectric(ThinDielectricMaterial {
                eta: Ior::Constant(1.2)
            })
        );
        assert_eq!(
            converted(
                r#"Material "diffusetransmission" "rgb reflectance" [0.1 0.1 0.1]
                   "rgb transmittance" [0.7 0.7 0.7] "float scale" 2"#
            ),
            MaterialDesc::DiffuseTransmission(DiffuseTransmissionMaterial {
                reflectance: grey(0.1),
                transmittance: grey(0.7),
                scale: 2.0,
            })
        );
        assert_eq!(
            converted(
                r#"Material "coateddiffuse" "rgb reflectance" [0.2 0.2 0.2] "float roughness" 0.1
                   "float thickness" 0.2 "float eta" 1.4 "rgb albedo" [0.5 0.5 0.5] "float g" 0.3
                   "integer maxdepth" 4 "integer nsamples" 2 "bool remaproughness" false"#
            ),
            MaterialDesc::CoatedDiffuse(CoatedDiffuseMaterial {
                reflectance: grey(0.2),
                uroughness: FloatTex::Const(0.1),
                vroughness: FloatTex::Const(0.1),
                thickness: FloatTex::Const(0.2),
                eta: lancer::spectrum::Ior::Constant(1.4),
                albedo: grey(0.5),
                g: FloatTex::Const(0.3),
                max_depth: 4,
                n_samples: 2,
                remap_roughness: false,
            })
        );
        assert_eq!(
            converted(
                r#"Material "coatedconductor" "float interface.roughness" 0.1
                   "float interface.vroughness" 0.15 "float interface.eta" 1.3
                   "rgb conductor.eta" [0.2 0.2 0.2] "rgb conductor.k" [4 4 4]
                   "rgb reflectance" [0.9 0.9 0.9] "float conductor.uroughness" 0.2
                   "float conductor.vroughness" 0.25 "float thickness" 0.05
                   "rgb albedo" [0.1 0.1 0.1] "float g" -0.2 "integer maxdepth" 3
                   "integer nsamples" 5 "bool remaproughness" false"#
            ),
            MaterialDesc::CoatedConductor(CoatedConductorMaterial {
                interface_uroughness: FloatTex::Const(0.1),
                interface_vroughness: FloatTex::Const(0.15),
                interface_eta: lancer::spectrum::Ior::Constant(1.3),
                conductor_eta: grey(0.2),
                k: grey(4.0),
                reflectance: Some(grey(0.9)),
                conductor_uroughness: FloatTex::Const(0.2),
                conductor_vroughness: FloatTex::Const(0.25),
                thickness: FloatTex::Const(0.05),
                albedo: grey(0.1),
                g: FloatTex::Const(-0.2),
                max_depth: 3,
                n_samples: 5,
                remap_roughness: false,
            })
        );
    }

    #[test]
    fn textures_are_found_by_name_and_kind() {
        let mut textures = TextureNames::default();
        textures.spectra.insert("wood".into(), 2);
        textures.floats.insert("bumps".into(), 1);
        let (out, _) = convert_with(
            r#"Material "conductor" "texture reflectance" "wood" "texture roughness" "bumps""#,
            &textures,
        );
        let MaterialDesc::Conductor(ConductorMaterial {
            reflectance,
            uroughness,
            vroughness,
            ..
        }) = out.unwrap().value.material
        else {
            panic!("a conductor")
        };
        assert_eq!(reflectance, Some(SpectrumTex::Tex(2)));
        assert_eq!(
            (uroughness, vroughness),
            (FloatTex::Tex(1), FloatTex::Tex(1))
        );
        let (out, _) = convert_with(
            "Material \"diffuse\"\n  \"texture reflectance\" \"bumps\"",
            &textures,
        );
        assert_eq!(
            err(out),
            "t.pbrt:2:3: no spectrum texture named \"bumps\" (there is a float texture of that name)"
        );
    }

    #[test]
    fn a_mix_returns_its_names_for_later() {
        let (out, unused) = convert_with(
            "Material \"mix\"\n  \"string materials\" [\"a\" \"b\"] \"float amount\" 0.25",
            &TextureNames::default(),
        );
        assert!(unused.is_empty());
        let f = out.unwrap();
        assert_eq!(
            f.value.material,
            MaterialDesc::Mix(MixMaterial {
                materials: [0, 0],
                amount: FloatTex::Const(0.25),
            })
        );
        let (names, loc) = f.value.mix.expect("names");
        assert_eq!(names, ["a", "b"]);
        assert_eq!(loc.to_string(), "t.pbrt:2:3");
    }

    #[test]
    fn unknown_materials_become_diffuse_with_a_warning() {
        let (out, unused) = convert_with(
            r#"Material "plastic" "float roughness" 0.1"#,
            &TextureNames::default(),
        );
        let f = out.unwrap();
        assert_eq!(f.value.material, MaterialDesc::default());
        assert_eq!(
            f.warnings,
            ["unknown material \"plastic\"; lancer renders it as \"diffuse\""]
        );
        // An unknown material reads nothing: its parameters are reported unused.
        assert_eq!(unused.len(), 1);
    }

    #[test]
    fn hair_takes_its_absorption_as_pbrt_v4_does() {
        use lancer::material::{HairAbsorption, HairMaterial};
        let c = FloatTex::Const;
        let hair = |absorption| {
            MaterialDesc::Hair(HairMaterial {
                absorption,
                eta: c(1.55),
                beta_m: c(0.3),
                beta_n: c(0.3),
                alpha: c(2.0),
            })
        };
        // Nothing given: eumelanin 1.3.
        assert_eq!(
            converted(r#"Material "hair""#),
            hair(HairAbsorption::Melanin {
                eumelanin: c(1.3),
                pheomelanin: c(0.0)
            })
        );
        assert_eq!(
            converted(r#"Material "hair" "float pheomelanin" 2"#),
            hair(HairAbsorption::Melanin {
                eumelanin: c(0.0),
                pheomelanin: c(2.0)
            })
        );
        assert_eq!(
            converted(r#"Material "hair" "rgb color" [0.1 0.2 0.3]"#),
            hair(HairAbsorption::Reflectance(rgb(0.1, 0.2, 0.3)))
        );
        let m = converted(
            r#"Material "hair" "rgb sigma_a" [0.4 0.75 1.6] "float beta_m" 0.25 "float eta" 1.5 "float alpha" 0 "float beta_n" 0.7"#,
        );
        assert_eq!(
            m,
            MaterialDesc::Hair(HairMaterial {
                absorption: HairAbsorption::SigmaA(rgb(0.4, 0.75, 1.6)),
                eta: c(1.5),
                beta_m: c(0.25),
                beta_n: c(0.7),
                alpha: c(0.0),
            })
        );
        // sigma_a wins over the others, with pbrt-v4's note.
        let (out, unused) = convert_with(
            r#"Material "hair" "rgb sigma_a" [1 1 1] "rgb reflectance" [0.5 0.5 0.5] "float eumelanin" 2"#,
            &TextureNames::default(),
        );
        let f = out.unwrap();
        assert!(unused.is_empty(), "{unused:?}");
        assert!(matches!(
            f.value.material,
            MaterialDesc::Hair(HairMaterial {
                absorption: HairAbsorption::SigmaA(_),
                ..
            })
        ));
        assert_eq!(
            f.warnings,
            [
                "ignoring \"reflectance\" since \"sigma_a\" was given (as pbrt-v4 does); \
                 ignoring \"eumelanin\"/\"pheomelanin\" since \"sigma_a\" was given (as pbrt-v4 does)"
            ]
        );
    }

    #[test]
    fn errors_are_at_their_parameter() {
        assert_eq!(
            error(r#"Material "mix""#),
            "t.pbrt:1:1: material \"mix\" needs \"string materials\" [\"a\" \"b\"]"
        );
        assert_eq!(
            error("Material \"mix\"\n  \"string materials\" [\"a\"]"),
            "t.pbrt:2:3: \"string materials\" of a mix names 2 materials, not 1"
        );
        assert_eq!(
            error("Material \"coateddiffuse\"\n  \"integer maxdepth\" -1"),
            "t.pbrt:2:3: \"integer maxdepth\" must be between 0 and 1000, not -1"
        );
        assert_eq!(
            error("Material \"coatedconductor\"\n  \"integer nsamples\" 0"),
            "t.pbrt:2:3: \"integer nsamples\" must be between 1 and 1000, not 0"
        );
        assert_eq!(
            error("Material \"dielectric\"\n  \"float eta\" -1"),
            "t.pbrt:2:3: \"float eta\" must be a positive index of refraction, not -1"
        );
        assert_eq!(
            error("Material \"diffuse\"\n  \"rgb reflectance\" [-1 0 0]"),
            "t.pbrt:2:3: \"rgb reflectance\" has a negative component: -1 0 0"
        );
        assert_eq!(
            error("Material \"diffuse\"\n  \"float reflectance\" 0.5"),
            "t.pbrt:2:3: parameter 'reflectance' must be of type rgb or spectrum or blackbody, not float"
        );
    }
}

#[cfg(test)]
mod bump_tests;

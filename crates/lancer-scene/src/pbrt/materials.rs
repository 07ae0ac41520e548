//! `Material` and `MakeNamedMaterial`: pbrt-v4's materials as lancer's [`Material`], with
//! pbrt-v4's defaults. A `mix` names two materials that may not be defined yet: they come back
//! beside it, for the builder to resolve once every name is known.

use super::convert::{Fallback, Reader, locate};
use crate::error::{Location, SceneError};
use lancer::material::Material;
use lancer::math::Rgb;
use lancer::spectrum::{SpectrumKind, named_spectrum, spectrum_to_rgb};
use lancer::texture::FloatTex;

/// A material, and for a `mix` the two names it refers to and where they are written.
#[derive(Clone, Debug)]
pub struct MaterialWithNames {
    /// The material (a `mix` holds placeholder indices until its names are resolved).
    pub material: Material,
    /// The names of a `mix`, and where they are given.
    pub mix: Option<(Vec<String>, Location)>,
}

impl From<Material> for MaterialWithNames {
    fn from(material: Material) -> MaterialWithNames {
        MaterialWithNames {
            material,
            mix: None,
        }
    }
}

/// The linear RGB of one of pbrt's named spectra (the metals' η and k).
fn named_rgb(name: &str) -> Rgb {
    named_spectrum(name)
        .map(|s| spectrum_to_rgb(&s, SpectrumKind::Unbounded))
        .expect("pbrt's named metal spectra are built in")
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
    convert(r, ty).map_err(|e| locate(e, loc))
}

fn convert(r: &Reader, ty: &str) -> Result<Fallback<MaterialWithNames>, SceneError> {
    use SpectrumKind::{Albedo, Unbounded};
    let p = r.params;
    let remap = || p.bool("remaproughness", true);
    let diffuse = |default: f32| -> Result<Material, SceneError> {
        Ok(Material::Diffuse {
            reflectance: r.spectrum_tex("reflectance", Rgb::splat(default), Albedo)?,
        })
    };
    let m = match ty {
        "diffuse" => diffuse(0.5)?,
        "conductor" => {
            let (uroughness, vroughness) = roughness(r, "")?;
            Material::Conductor {
                eta: r.spectrum_tex("eta", named_rgb("metal-Cu-eta"), Unbounded)?,
                k: r.spectrum_tex("k", named_rgb("metal-Cu-k"), Unbounded)?,
                reflectance: r.opt_spectrum_tex("reflectance", Albedo)?,
                uroughness,
                vroughness,
                remap_roughness: remap()?,
            }
        }
        "dielectric" => {
            let (uroughness, vroughness) = roughness(r, "")?;
            Material::Dielectric {
                eta: p.ior("eta", 1.5, r.dir)?,
                uroughness,
                vroughness,
                remap_roughness: remap()?,
            }
        }
        "thindielectric" => Material::ThinDielectric {
            eta: p.ior("eta", 1.5, r.dir)?,
        },
        "diffusetransmission" => Material::DiffuseTransmission {
            reflectance: r.spectrum_tex("reflectance", Rgb::splat(0.25), Albedo)?,
            transmittance: r.spectrum_tex("transmittance", Rgb::splat(0.25), Albedo)?,
            scale: p.float("scale", 1.0)?,
        },
        "coateddiffuse" => {
            let (uroughness, vroughness) = roughness(r, "")?;
            let reflectance = r.spectrum_tex("reflectance", Rgb::splat(0.5), Albedo)?;
            let thickness = r.float_tex("thickness", 0.01)?;
            let eta = p.ior("eta", 1.5, r.dir)?;
            let albedo = r.spectrum_tex("albedo", Rgb::ZERO, Albedo)?;
            let g = r.float_tex("g", 0.0)?;
            let (max_depth, n_samples) = walk(r)?;
            Material::CoatedDiffuse {
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
            }
        }
        "coatedconductor" => {
            let (interface_uroughness, interface_vroughness) = roughness(r, "interface.")?;
            let (conductor_uroughness, conductor_vroughness) = roughness(r, "conductor.")?;
            let interface_eta = p.ior("interface.eta", 1.5, r.dir)?;
            let conductor_eta =
                r.spectrum_tex("conductor.eta", named_rgb("metal-Cu-eta"), Unbounded)?;
            let k = r.spectrum_tex("conductor.k", named_rgb("metal-Cu-k"), Unbounded)?;
            let reflectance = r.opt_spectrum_tex("reflectance", Albedo)?;
            let thickness = r.float_tex("thickness", 0.01)?;
            let albedo = r.spectrum_tex("albedo", Rgb::ZERO, Albedo)?;
            let g = r.float_tex("g", 0.0)?;
            let (max_depth, n_samples) = walk(r)?;
            Material::CoatedConductor {
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
            }
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
            let material = Material::Mix {
                materials: [0, 0],
                amount: r.float_tex("amount", 0.5)?,
            };
            return Ok(Fallback::done(MaterialWithNames {
                material,
                mix: Some((names, loc)),
            }));
        }
        "interface" | "" | "none" => Material::Interface,
        "measured" | "hair" | "subsurface" => {
            return Ok(Fallback::instead(
                diffuse(0.5)?.into(),
                format!("material \"{ty}\" is not supported yet; lancer renders it as \"diffuse\""),
            ));
        }
        _ => {
            return Ok(Fallback::instead(
                Material::default().into(),
                format!("unknown material \"{ty}\"; lancer renders it as \"diffuse\""),
            ));
        }
    };
    Ok(Fallback::done(m.into()))
}

#[cfg(test)]
mod tests {}

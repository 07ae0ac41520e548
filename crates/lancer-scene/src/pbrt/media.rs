//! `MakeNamedMedium`, `MediumInterface` and `Attribute "medium"`: pbrt-v4's participating media.
//!
//! `MakeNamedMedium` (before or after `WorldBegin`) defines a medium by name, placed by the
//! current transformation; `MediumInterface "inside" ["outside"]` sets the media later shapes
//! bound (one name: both sides; `""`: vacuum), and the camera sits in the current `outside`
//! medium when `Camera` is read. The `homogeneous` medium is converted here ([`medium`]); the
//! others are still read as vacuum, with a warning.

use super::media_grids::grid_medium;
use super::params::ParamList;
use super::search_path::SearchPath;
use crate::error::{Location, SceneError, Warning};
use lancer::math::{Rgb, Transform};
use lancer::medium::{HomogeneousDesc, MediumDesc, MediumInterface};
use lancer::scene::desc::SceneDesc;
use lancer::spectrum::SpectrumKind;
use lancer::spectrum::scattering_presets::{scattering_preset, scattering_preset_names};
use std::collections::HashMap;

/// The medium names of the graphics state (`MediumInterface`): `""` is vacuum.
#[derive(Clone, Debug, Default)]
pub struct CurrentMedia {
    /// Inside the shapes that follow.
    pub inside: String,
    /// Outside them (and around the camera, at `Camera`).
    pub outside: String,
}

impl CurrentMedia {
    /// `MediumInterface "inside" "outside"`.
    pub fn set(&mut self, inside: String, outside: String) -> Result<(), SceneError> {
        (self.inside, self.outside) = (inside, outside);
        Ok(())
    }
}

/// The named media of a scene.
#[derive(Debug, Default)]
pub struct Media {
    /// Each name's index in [`SceneDesc::media`] (`None` for a kind lancer reads as vacuum).
    names: HashMap<String, Option<u32>>,
    /// The camera's medium name and where `Camera` named it.
    camera: Option<(String, Location)>,
}

impl Media {
    /// `MakeNamedMedium "name" …`: converts the medium and records its name; a name defined
    /// twice is an error, as in pbrt-v4. Unread parameters are reported into `warnings`.
    #[allow(clippy::too_many_arguments)]
    pub fn define(
        &mut self,
        name: &str,
        params: &ParamList,
        ctm: Transform,
        dir: &SearchPath,
        desc: &mut SceneDesc,
        warnings: &mut Vec<Warning>,
        loc: &Location,
    ) -> Result<(), SceneError> {
        if self.names.contains_key(name) {
            return Err(SceneError::at(
                loc.clone(),
                format!("named medium \"{name}\" redefined"),
            ));
        }
        let Some(ty) = params.string("type")? else {
            return Err(SceneError::at(
                loc.clone(),
                format!("MakeNamedMedium \"{name}\" needs a \"string type\""),
            ));
        };
        let index = match medium(params, &ty, ctm, dir, warnings, loc)? {
            Some(m) => {
                desc.media.push(m);
                Some(desc.media.len() as u32 - 1)
            }
            None => {
                params.mark_all_used();
                None
            }
        };
        self.names.insert(name.to_string(), index);
        params.report_unused(&format!("MakeNamedMedium \"{name}\""), warnings);
        Ok(())
    }

    /// The index of medium `name` (`""`: vacuum).
    fn index(&self, name: &str, loc: &Location) -> Result<Option<u32>, SceneError> {
        if name.is_empty() {
            return Ok(None);
        }
        self.names.get(name).copied().ok_or_else(|| {
            SceneError::at(
                loc.clone(),
                format!("no medium named \"{name}\" (MakeNamedMedium defines one)"),
            )
        })
    }

    /// The interface of a shape made under `current` (`None` when both sides are vacuum).
    pub fn interface(
        &self,
        current: &CurrentMedia,
        loc: &Location,
    ) -> Result<Option<MediumInterface>, SceneError> {
        let mi = MediumInterface {
            inside: self.index(&current.inside, loc)?,
            outside: self.index(&current.outside, loc)?,
        };
        Ok((mi != MediumInterface::default()).then_some(mi))
    }

    /// The medium a light made under `current` sits in: the current `outside` one (pbrt-v4's
    /// `CurrentOutsideMedium`).
    pub fn outside(
        &self,
        current: &CurrentMedia,
        loc: &Location,
    ) -> Result<Option<u32>, SceneError> {
        self.index(&current.outside, loc)
    }

    /// Records the camera's medium at `Camera`: the current `outside` one.
    pub fn set_camera(&mut self, current: &CurrentMedia, loc: &Location) {
        self.camera = Some((current.outside.clone(), loc.clone()));
    }

    /// The camera's medium, resolved once every medium is known.
    pub fn camera_medium(&self) -> Result<Option<u32>, SceneError> {
        match &self.camera {
            Some((name, loc)) => self.index(name, loc),
            None => Ok(None),
        }
    }
}

/// The medium `ty` from its parameters, as pbrt-v4's `Medium::Create`; `None` (with a warning)
/// for the kinds lancer does not render yet.
pub fn medium(
    params: &ParamList,
    ty: &str,
    ctm: Transform,
    dir: &SearchPath,
    warnings: &mut Vec<Warning>,
    loc: &Location,
) -> Result<Option<MediumDesc>, SceneError> {
    match ty {
        "homogeneous" => homogeneous(params, dir, warnings, loc).map(Some),
        "uniformgrid" | "rgbgrid" | "cloud" | "nanovdb" => {
            Ok(grid_medium(params, ty, ctm, dir, loc)?.map(|g| MediumDesc::Grid(Box::new(g))))
        }
        _ => Err(SceneError::at(
            loc.clone(),
            format!(
                "unknown medium type \"{ty}\" (expected homogeneous, uniformgrid, rgbgrid, cloud \
                 or nanovdb)"
            ),
        )),
    }
}

/// pbrt-v4's `homogeneous`: `preset` (a measured material), else `sigma_a` and `sigma_s`
/// (default 1 each), both times `scale`; `Le` (an illuminant, normalised to luminance 1 when
/// a spectrum) times `Lescale`; Henyey–Greenstein `g`.
fn homogeneous(
    params: &ParamList,
    dir: &SearchPath,
    warnings: &mut Vec<Warning>,
    loc: &Location,
) -> Result<MediumDesc, SceneError> {
    let mut coefficients = None;
    if let Some(name) = params.string("preset")? {
        match scattering_preset(&name) {
            Some(p) => coefficients = Some((p.sigma_a, p.sigma_prime_s)),
            None => {
                let known: Vec<&str> = scattering_preset_names().collect();
                warnings.push(Warning {
                    location: params.location("preset").unwrap_or(loc).clone(),
                    message: format!(
                        "scattering preset \"{name}\" is unknown (known: {}); lancer uses \
                         \"sigma_a\" and \"sigma_s\" instead",
                        known.join(", ")
                    ),
                });
            }
        }
    }
    let (sigma_a, sigma_s) = match coefficients {
        // pbrt-v4 ignores the coefficients a preset replaces; so does lancer, silently.
        Some(c) => {
            let _ = params.color("sigma_a", SpectrumKind::Unbounded, dir)?;
            let _ = params.color("sigma_s", SpectrumKind::Unbounded, dir)?;
            c
        }
        None => (
            params
                .color("sigma_a", SpectrumKind::Unbounded, dir)?
                .unwrap_or(Rgb::ONE),
            params
                .color("sigma_s", SpectrumKind::Unbounded, dir)?
                .unwrap_or(Rgb::ONE),
        ),
    };
    let le = params
        .color("Le", SpectrumKind::Illuminant, dir)?
        .unwrap_or(Rgb::ZERO);
    let g = params.float("g", 0.0)?;
    if !(g > -1.0 && g < 1.0) {
        return Err(params.error_at("g", format!("\"g\" must lie in (-1, 1), not {g}")));
    }
    Ok(MediumDesc::Homogeneous(HomogeneousDesc {
        sigma_a,
        sigma_s,
        scale: params.float("scale", 1.0)?,
        le,
        le_scale: params.float("Lescale", 1.0)?,
        g,
    }))
}

#[cfg(test)]
mod tests;

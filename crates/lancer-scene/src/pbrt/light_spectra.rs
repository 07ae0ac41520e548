//! The spectrum a light's colour is a multiple of, when the scene gave it as a spectrum
//! (`blackbody`, a named illuminant such as `stdillum-F2`, pairs, an `.spd` file): spectral
//! mode then emits that spectrum, normalised as pbrt-v4 normalises it (luminance 1 before
//! `scale`, see [`lancer::spectrum::dense::Measured::new`]), instead of an uplift of its RGB
//! reduction. RGB mode keeps the reduction the light conversions compute
//! ([`super::lights`]).

use super::params::ParamList;
use super::search_path::SearchPath;
use crate::error::SceneError;
use lancer::scene::desc::{LightDesc, SceneDesc};
use lancer::spectrum::SpectrumKind;
use lancer::spectrum::dense::Measured;

/// The spectrum of emission parameter `name` (`"L"`, `"I"`), if given as a spectrum.
pub fn emission_spectrum(
    params: &ParamList,
    name: &str,
    dir: &SearchPath,
) -> Result<Option<Measured>, SceneError> {
    Ok(params
        .measured_color(name, SpectrumKind::Illuminant, dir)?
        .and_then(|(_, m)| m))
}

/// The spectrum of light `light` as its parameters `params` give it: `I` of point, spot and
/// goniometric lights, `L` of distant lights and uniform skies; none for image lights.
pub fn light_spectrum(
    light: &LightDesc,
    params: &ParamList,
    dir: &SearchPath,
) -> Result<Option<Measured>, SceneError> {
    let name = match light {
        LightDesc::Point(_) | LightDesc::Spot(_) | LightDesc::Goniometric(_) => "I",
        LightDesc::Distant(_) | LightDesc::UniformInfinite(_) => "L",
        LightDesc::ImageInfinite(_) | LightDesc::PortalInfinite(_) => return Ok(None),
        LightDesc::Projection(_) | LightDesc::Sunsky(_) => return Ok(None),
    };
    emission_spectrum(params, name, dir)
}

/// Records `spectrum` for the light just pushed last onto `desc.lights`
/// ([`SceneDesc::light_spectra`] stays empty for scenes whose lights are all RGB).
pub fn record(desc: &mut SceneDesc, spectrum: Option<Measured>) {
    if let Some(m) = spectrum {
        let i = desc.lights.len() - 1;
        desc.light_spectra.resize(i, None);
        desc.light_spectra.push(Some(m));
    }
}

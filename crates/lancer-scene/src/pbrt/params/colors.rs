//! The colour- and spectrum-valued lookups of a parameter list (`rgb`, `spectrum`,
//! `blackbody`, indices of refraction, texture-or-constant parameters), apart from the plain
//! numbers and strings of `params.rs`.

use super::*;
use lancer::spectrum::dense::{DenseSpectrum, Measured};

impl ParamList {
    /// A colour given as `rgb`, `spectrum` (pairs, a named spectrum or an `.spd` file relative
    /// to `dir`) or `blackbody`, reduced to linear RGB as `kind` asks. `rgb` values are in the
    /// list's colour space ([`ParamList::in_color_space`]) and come back in linear sRGB
    /// (possibly outside [0, 1]): an illuminant by the spaces' matrices, a reflectance or an
    /// unbounded value as the colour it has under D65 ([`ColorSpace::reflectance_to_srgb`]).
    pub fn color(
        &self,
        name: &str,
        kind: SpectrumKind,
        dir: &SearchPath,
    ) -> Result<Option<Rgb>, SceneError> {
        Ok(self.measured_color(name, kind, dir)?.map(|(c, _)| c))
    }

    /// [`ParamList::color`], with, when the colour was given as a spectrum (`blackbody`,
    /// pairs, a named spectrum, a file), that spectrum ready for spectral mode
    /// ([`Measured::new`]): named spectra from their tabulated data
    /// ([`lancer::spectrum::named_spectrum_data`]), while the reduction stays the one RGB mode
    /// has always used.
    pub fn measured_color(
        &self,
        name: &str,
        kind: SpectrumKind,
        dir: &SearchPath,
    ) -> Result<Option<(Rgb, Option<Measured>)>, SceneError> {
        let Some(p) = self.find(
            name,
            &[ParamType::Rgb, ParamType::Spectrum, ParamType::Blackbody],
        )?
        else {
            return Ok(None);
        };
        let measured = |s: &Spectrum, rgb: Rgb| Some(Measured::new(s, rgb, kind));
        let (rgb, m) = match (p.ty, &p.values) {
            (ParamType::Rgb, Values::Numbers(v)) => {
                if v.len() != 3 {
                    return Err(p.error(format!(
                        "{} takes one colour (3 numbers), found {} numbers",
                        p.decl(),
                        v.len()
                    )));
                }
                let c = Rgb::new(v[0], v[1], v[2]);
                if kind != SpectrumKind::Unbounded && c.min_element() < 0.0 {
                    return Err(p.error(format!(
                        "{} has a negative component: {} {} {}",
                        p.decl(),
                        c.x,
                        c.y,
                        c.z
                    )));
                }
                let a = c.to_array();
                let rgb = Rgb::from_array(match kind {
                    SpectrumKind::Illuminant => self.color_space.rgb_to_srgb(a),
                    _ => self.color_space.reflectance_to_srgb(a),
                });
                (rgb, None)
            }
            (ParamType::Blackbody, Values::Numbers(v)) => {
                if v[0] <= 0.0 {
                    return Err(p.error(format!(
                        "{} needs a positive temperature, not {}",
                        p.decl(),
                        v[0]
                    )));
                }
                // pbrt-v4's blackbody is normalised to a peak of 1; pbrt-v3 wrote a second
                // value, a scale.
                let scale = v.get(1).copied().unwrap_or(1.0);
                let s = Spectrum::Blackbody { kelvin: v[0] };
                let rgb = spectrum_to_rgb(&s, kind) * scale;
                let table = DenseSpectrum::from_spectrum(&s).map(|x| x * scale);
                (rgb, Some(Measured::from_table(table, rgb, kind)))
            }
            (ParamType::Spectrum, Values::Numbers(v)) => {
                let (lambda, values): (Vec<f32>, Vec<f32>) =
                    v.chunks_exact(2).map(|c| (c[0], c[1])).unzip();
                if lambda.windows(2).any(|w| w[1] <= w[0]) {
                    return Err(p.error(format!("{}: wavelengths must increase", p.decl())));
                }
                let s = Spectrum::PiecewiseLinear { lambda, values };
                let rgb = spectrum_to_rgb(&s, kind);
                (rgb, measured(&s, rgb))
            }
            (ParamType::Spectrum, Values::Strings(v)) => {
                let s = named_or_file_spectrum(&v[0], dir).map_err(|m| p.error(m))?;
                let rgb = spectrum_to_rgb(&s, kind);
                let data = lancer::spectrum::named_spectrum_data(&v[0]).unwrap_or(s);
                (rgb, measured(&data, rgb))
            }
            _ => unreachable!("types checked by find"),
        };
        Ok(Some((rgb, m)))
    }

    /// `rgb` values (any number of triples: a grid of colours), with where they are declared.
    pub fn rgbs(&self, name: &str) -> Result<Option<(Vec<Rgb>, Location)>, SceneError> {
        Ok(self.find(name, &[ParamType::Rgb])?.map(|p| {
            let v = p
                .numbers()
                .chunks_exact(3)
                .map(|c| Rgb::new(c[0], c[1], c[2]))
                .collect();
            (v, p.loc.clone())
        }))
    }

    /// An index of refraction as one number: a `float`, or a `spectrum` or `rgb` taken at
    /// [`lancer::spectrum::IOR_WAVELENGTH`] (coatings, which do not disperse).
    pub fn ior(&self, name: &str, default: f32, dir: &SearchPath) -> Result<f32, SceneError> {
        Ok(self.dielectric_ior(name, default, dir)?.constant_value())
    }

    /// A dielectric's index of refraction as pbrt-v4 reads one (a `float`, or any spectrum:
    /// `GetOneSpectrum` of type `Unbounded`). A named glass (`glass-F11`, …) stays its
    /// Sellmeier formula ([`Ior::Glass`]); pairs, files and other named spectra are tabulated
    /// ([`Ior::from_spectrum`]); an `rgb` triple is uplifted as pbrt-v4's
    /// `RGBUnboundedSpectrum` ([`Ior::from_rgb`]). An index that varies disperses in spectral
    /// mode; RGB mode takes its value at [`lancer::spectrum::IOR_WAVELENGTH`].
    pub fn dielectric_ior(
        &self,
        name: &str,
        default: f32,
        dir: &SearchPath,
    ) -> Result<Ior, SceneError> {
        let Some(p) = self.find(
            name,
            &[ParamType::Float, ParamType::Spectrum, ParamType::Rgb],
        )?
        else {
            return Ok(Ior::Constant(default));
        };
        let lambda = lancer::spectrum::IOR_WAVELENGTH;
        let tabulated = |s: &Spectrum, rgb_mode: f32| {
            Ior::from_spectrum(DenseSpectrum::from_spectrum(s), rgb_mode)
        };
        let eta = match &p.values {
            Values::Numbers(v) if p.ty == ParamType::Float => match v.as_slice() {
                [eta] => Ior::Constant(*eta),
                _ => return Err(p.error(format!("{} takes one value", p.decl()))),
            },
            Values::Numbers(_) if p.ty == ParamType::Rgb => {
                let c = self
                    .color(name, SpectrumKind::Unbounded, dir)?
                    .expect("found above");
                Ior::from_rgb(c)
            }
            Values::Numbers(v) => {
                let (lambda_s, values) = v.chunks_exact(2).map(|c| (c[0], c[1])).unzip();
                let s = Spectrum::PiecewiseLinear {
                    lambda: lambda_s,
                    values,
                };
                tabulated(&s, s.eval(lambda))
            }
            Values::Strings(v) => match Ior::named_glass(&v[0]) {
                Some(glass) => glass,
                None => {
                    let s = named_or_file_spectrum(&v[0], dir).map_err(|m| p.error(m))?;
                    let data = lancer::spectrum::named_spectrum_data(&v[0]).unwrap_or(s.clone());
                    tabulated(&data, s.eval(lambda))
                }
            },
            _ => unreachable!("types checked by find"),
        };
        let value = eta.constant_value();
        if !(value.is_finite() && value > 0.0) {
            return Err(p.error(format!(
                "{} must be a positive index of refraction, not {value}",
                p.decl()
            )));
        }
        Ok(eta)
    }

    /// A colour or a texture name.
    pub fn color_or_texture(
        &self,
        name: &str,
        kind: SpectrumKind,
        dir: &SearchPath,
    ) -> Result<Option<ColorParam>, SceneError> {
        if let Some(p) = self.params.iter().find(|p| p.name == name)
            && p.ty == ParamType::Texture
        {
            let t = self.string_of(name, ParamType::Texture)?.expect("given");
            return Ok(Some(ColorParam::Texture(t, p.loc.clone())));
        }
        Ok(self
            .measured_color(name, kind, dir)?
            .map(|(c, m)| m.map_or(ColorParam::Const(c), ColorParam::Measured)))
    }

    /// A float or a texture name.
    pub fn float_or_texture(&self, name: &str) -> Result<Option<FloatParam>, SceneError> {
        if let Some(p) = self.params.iter().find(|p| p.name == name)
            && p.ty == ParamType::Texture
        {
            let t = self.string_of(name, ParamType::Texture)?.expect("given");
            return Ok(Some(FloatParam::Texture(t, p.loc.clone())));
        }
        Ok(self
            .one_number(name, ParamType::Float)?
            .map(|v| FloatParam::Const(v.0)))
    }
}

/// A spectrum named in a scene: one of pbrt's named spectra, or an `.spd` file (relative to
/// `dir`).
fn named_or_file_spectrum(name: &str, dir: &SearchPath) -> Result<Spectrum, String> {
    if let Some(s) = lancer::spectrum::named_spectrum(name) {
        return Ok(s);
    }
    let path = dir.resolve(name);
    crate::files_read::record(&path);
    match std::fs::read_to_string(&path) {
        Ok(text) => parse_spd(&text).map_err(|e| format!("spectrum file {}: {e}", path.display())),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => Err(format!(
            "'{name}' is neither a named spectrum nor a spectrum file ({} not found)",
            path.display()
        )),
        Err(e) => Err(format!("cannot read spectrum file {}: {e}", path.display())),
    }
}

//! Spectra, converted to RGB once at load time.
//!
//! lancer renders in linear sRGB. Scene files may give colours as spectra (constants,
//! blackbodies, sampled data, pbrt-v4's named measured spectra); they are reduced to RGB here,
//! according to what they describe ([`SpectrumKind`]), with the tabulated CIE 1931 observer and
//! illuminant D65 of [`cie`]:
//!
//! - an **illuminant** is reduced to its chromaticity at luminance 1, as pbrt-v4 divides a
//!   light's `scale` by its spectrum's luminance: XYZ = ∫ s·(x̄, ȳ, z̄) / ∫ s·ȳ;
//! - a **reflectance** or an **unbounded** quantity (an index of refraction) is seen under D65,
//!   the white of sRGB, as Mitsuba 3's RGB mode does: XYZ = ∫ s·D65·(x̄, ȳ, z̄) / ∫ D65·ȳ.
//!
//! XYZ then goes to linear sRGB with the standard D65 matrix ([`xyz_to_srgb`]). Integrals are
//! sums over 360–830 nm every 1 nm, the 5 nm tables being interpolated linearly.
//!
//! Spectral mode (the default) goes the other way during rendering: [`uplift`] turns RGB
//! colours back into smooth spectra (Jakob–Hanika), constants given as spectra keep their
//! spectra as 1 nm tables ([`dense`]), and [`sampled`] evaluates them at each path's
//! wavelengths and turns the path's radiance into film RGB.

pub mod cie;
pub mod colorspace;
pub mod dense;
mod fit;
pub mod hero;
mod named;
mod named_data;
mod reduce;
pub mod sampled;
pub mod scattering_presets;
pub mod sensor;
mod sensor_data;
mod table;
pub mod uplift;

pub use colorspace::ColorSpace;
pub use named::{
    IOR_WAVELENGTH, Ior, named_ior, named_spectrum, named_spectrum_data, named_spectrum_names,
};
pub use reduce::{
    PrecomputedRgb, Spectrum, SpectrumKind, blackbody, cie_d65, cie_xyz, parse_spd,
    spectrum_to_rgb, spectrum_to_xyz_unnormalised, xyz_to_srgb,
};
pub use scattering_presets::{scattering_preset, scattering_preset_names};
pub use sensor::{FilmResponse, Sensor};

//! pbrt-v4's named spectra (`"spectrum eta" "metal-Au-eta"`, `"spectrum L" "stdillum-F2"`, …).
//!
//! Each named spectrum is known twice:
//!
//! - as its **data** ([`named_spectrum_data`]), which spectral mode samples at each path's
//!   wavelengths: the tabulated numbers of pbrt-v4's `src/pbrt/util/spectrum.cpp`, copied into
//!   `named_data.rs` by `tools/gen_named_spectra.py` (measured complex indices of refraction of
//!   silver, aluminium, gold, copper, brass (CuZn), magnesium oxide and titanium dioxide; CIE
//!   standard illuminants A, D50, F1 … F12; the ACES white, daylight at 6000 K);
//! - as its **RGB reductions** ([`named_spectrum`], [`Spectrum::Precomputed`]), which RGB mode
//!   uses, computed offline from the same data and stored so that RGB renders keep their bits.
//!
//! Method of the reductions: each spectrum (piecewise linear between its samples, zero outside
//! them) was reduced with the rules of [`spectrum_to_rgb`](super::spectrum_to_rgb) exactly as
//! this module computes them (1 nm sums over 360–830 nm of the interpolated 5 nm CIE 1931 and
//! D65 tables): `unbounded` by the [`SpectrumKind::Unbounded`](super::SpectrumKind::Unbounded)
//! rule (seen under D65) and `illuminant` by the
//! [`SpectrumKind::Illuminant`](super::SpectrumKind::Illuminant) rule (luminance 1); negative
//! components were set to 0. Illuminants are normalised to luminance 1 first, as pbrt-v4 does.
//!
//! Two kinds are exact in both modes instead: `stdillum-D65` (the CIE table of [`cie`]) and the
//! glasses `glass-BK7`, `glass-BAF10`, `glass-FK51A`, `glass-LASF9`, `glass-F5`, `glass-F10`,
//! `glass-F11`, whose index of refraction follows Schott's Sellmeier formulas (pbrt-v4 tabulates
//! them). RGB mode, without dispersion, takes one index per glass: [`named_ior`] gives the
//! value at 550 nm.

use super::dense::{DenseSpectrum, intern};
use super::{PrecomputedRgb, Spectrum, cie, spectrum_to_xyz_unnormalised};
use crate::math::Rgb;

/// pbrt-v4's named spectra known by their reductions: name, reduction as
/// [`SpectrumKind::Unbounded`](super::SpectrumKind::Unbounded), reduction as
/// [`SpectrumKind::Illuminant`](super::SpectrumKind::Illuminant) (see the module documentation
/// for the method).
#[rustfmt::skip]
const PRECOMPUTED: [(&str, [f32; 3], [f32; 3]); 29] = [
    ("metal-Ag-eta", [0.128488, 0.123534, 0.15087], [1.22757, 0.92284, 1.09398]),
    ("metal-Ag-k", [4.06513, 3.28619, 2.3914], [1.41399, 0.914362, 0.628677]),
    ("metal-Al-eta", [1.40749, 0.926649, 0.583982], [1.62539, 0.863362, 0.511108]),
    ("metal-Al-k", [7.74084, 6.60242, 5.35954], [1.35755, 0.922753, 0.711851]),
    ("metal-Au-eta", [0.079961, 0.405085, 1.56061], [0.355036, 0.931515, 3.57906]),
    ("metal-Au-k", [3.39047, 2.50352, 1.77074], [1.4924, 0.893866, 0.600718]),
    ("metal-Cu-eta", [0.105142, 0.977925, 1.20448], [0.256702, 1.1799, 1.4077]),
    ("metal-Cu-k", [3.27375, 2.5925, 2.36881], [1.42759, 0.894905, 0.781397]),
    ("metal-CuZn-eta", [0.418439, 0.520076, 1.12285], [0.971153, 0.913027, 1.94678]),
    ("metal-CuZn-k", [3.66789, 2.68061, 1.7711], [1.51513, 0.891514, 0.557029]),
    ("metal-MgO-eta", [1.73382, 1.74094, 1.75327], [1.20088, 0.948687, 0.91651]),
    ("metal-MgO-k", [0.0, 0.0, 0.0], [28.7561, 0.0, 165.761]),
    ("metal-TiO2-eta", [2.86061, 2.95651, 3.18502], [1.17233, 0.950242, 0.985235]),
    ("metal-TiO2-k", [9.093e-05, 0.0, 0.000565871], [28.983, 0.0, 179.72]),
    ("stdillum-A", [1.5821, 0.867085, 0.27418], [1.84496, 0.826088, 0.233435]),
    ("stdillum-D50", [0.974433, 1.02714, 0.810975], [1.17619, 0.975673, 0.721881]),
    ("stdillum-F1", [0.807301, 1.06352, 1.02553], [0.953648, 1.0196, 0.942416]),
    ("stdillum-F2", [1.18097, 0.972439, 0.610113], [1.33916, 0.943351, 0.561944]),
    ("stdillum-F3", [1.40683, 0.912615, 0.410726], [1.57528, 0.891487, 0.380073]),
    ("stdillum-F4", [1.62211, 0.849507, 0.285852], [1.80486, 0.834698, 0.266282]),
    ("stdillum-F5", [0.77541, 1.07992, 0.968463], [0.914924, 1.03648, 0.889209]),
    ("stdillum-F6", [1.16464, 0.98584, 0.527173], [1.31526, 0.958151, 0.485699]),
    ("stdillum-F7", [0.827727, 1.05242, 1.08356], [1.00009, 1.00037, 0.996052]),
    ("stdillum-F8", [0.978518, 1.02862, 0.790816], [1.17664, 0.975823, 0.719081]),
    ("stdillum-F9", [1.17332, 0.976256, 0.623613], [1.37645, 0.931608, 0.568402]),
    ("stdillum-F10", [1.00675, 1.02883, 0.785965], [1.17316, 0.976971, 0.717961]),
    ("stdillum-F11", [1.22452, 0.974522, 0.576479], [1.41045, 0.925315, 0.530569]),
    ("stdillum-F12", [1.55142, 0.889163, 0.289373], [1.76624, 0.845784, 0.270233]),
    ("illum-acesD60", [0.856666, 1.04812, 1.0197], [1.047, 0.994562, 0.915387]),
];

/// Schott's Sellmeier coefficients `[B1, B2, B3, C1, C2, C3]` (C in µm²) of the glasses pbrt-v4
/// names: n²(λ) = 1 + Σ Bᵢ·λ² / (λ² − Cᵢ), λ in µm. pbrt's `glass-F5`, `glass-F10` and
/// `glass-F11` are Schott SF5, N-SF10 and SF11; the others are N-BK7, N-BAF10, N-FK51A and
/// N-LASF9.
#[rustfmt::skip]
const GLASSES: [(&str, [f64; 6]); 7] = [
    ("glass-BK7", [1.039_612_12, 0.231_792_344, 1.010_469_45, 0.006_000_698_67, 0.020_017_914_4, 103.560_653]),
    ("glass-BAF10", [1.585_149_5, 0.143_559_385, 1.085_212_69, 0.009_266_812_82, 0.042_448_980_5, 105.613_573]),
    ("glass-FK51A", [0.971_247_817, 0.216_901_417, 0.904_651_666, 0.004_723_019_95, 0.015_357_561_2, 168.681_33]),
    ("glass-LASF9", [2.000_295_47, 0.298_926_886, 1.806_918_43, 0.012_142_601_7, 0.053_873_623_6, 156.530_829]),
    ("glass-F5", [1.524_818_89, 0.187_085_527, 1.427_290_15, 0.011_254_756, 0.058_899_539_2, 129.141_675]),
    ("glass-F10", [1.621_539_02, 0.256_287_842, 1.644_475_52, 0.012_224_145_7, 0.059_573_677_5, 147.468_793]),
    ("glass-F11", [1.737_596_95, 0.313_747_346, 1.898_781_01, 0.013_188_707, 0.062_306_814_2, 155.236_29]),
];

/// The wavelength (nm) at which [`named_ior`] evaluates a glass.
pub const IOR_WAVELENGTH: f32 = 550.0;

/// Index of refraction from Sellmeier coefficients at `lambda_nm`.
fn sellmeier(c: &[f64; 6], lambda_nm: f64) -> f64 {
    let l2 = (lambda_nm * 1e-3).powi(2);
    let n2 = 1.0 + (0..3).map(|i| c[i] * l2 / (l2 - c[i + 3])).sum::<f64>();
    n2.sqrt()
}

fn glass(name: &str) -> Option<&'static [f64; 6]> {
    GLASSES.iter().find(|(n, _)| *n == name).map(|(_, c)| c)
}

/// The spectrum pbrt-v4 calls `name`, or `None` if it has no such named spectrum.
///
/// Glasses come back as their index of refraction sampled every 5 nm over 360–830 nm
/// ([`Spectrum::PiecewiseLinear`]), `stdillum-D65` as the CIE table scaled to luminance 1, and
/// every other name (metals, the other illuminants) as its precomputed RGB reductions
/// ([`Spectrum::Precomputed`]). Names are case-sensitive, as in pbrt.
pub fn named_spectrum(name: &str) -> Option<Spectrum> {
    let grid = || (0..cie::SAMPLES).map(|i| cie::LAMBDA_MIN + i as f64 * cie::LAMBDA_STEP);
    if let Some(c) = glass(name) {
        return Some(Spectrum::PiecewiseLinear {
            lambda: grid().map(|l| l as f32).collect(),
            values: grid().map(|l| sellmeier(c, l) as f32).collect(),
        });
    }
    if name == "stdillum-D65" {
        let lambda: Vec<f32> = grid().map(|l| l as f32).collect();
        let values: Vec<f32> = cie::D65.iter().map(|&v| v as f32).collect();
        let raw = Spectrum::PiecewiseLinear {
            lambda: lambda.clone(),
            values: values.clone(),
        };
        // Scaled to luminance 1: ∫ s·ȳ = ∫ ȳ.
        let y = spectrum_to_xyz_unnormalised(&raw)[1]
            / spectrum_to_xyz_unnormalised(&Spectrum::Constant(1.0))[1];
        let values = values.into_iter().map(|v| v / y).collect();
        return Some(Spectrum::PiecewiseLinear { lambda, values });
    }
    PRECOMPUTED
        .iter()
        .find(|(n, _, _)| *n == name)
        .map(|(_, u, i)| {
            Spectrum::Precomputed(PrecomputedRgb {
                unbounded: Rgb::from_array(*u),
                illuminant: Rgb::from_array(*i),
            })
        })
}

/// The data of the spectrum pbrt-v4 calls `name`, as pbrt-v4 evaluates it: the tabulated
/// measurements of a metal or an illuminant ([`super::named_data`], piecewise linear, zero
/// outside the table), a glass's Sellmeier index, the CIE D65 table; `None` for an unknown
/// name. [`named_spectrum`] gives the same spectra as RGB mode reduces them (stored
/// reductions for the tabulated ones).
pub fn named_spectrum_data(name: &str) -> Option<Spectrum> {
    match super::named_data::TABLES.iter().find(|(n, _)| *n == name) {
        Some((_, pairs)) => {
            let (mut lambda, mut values): (Vec<f32>, Vec<f32>) =
                pairs.chunks_exact(2).map(|c| (c[0], c[1])).unzip();
            // pbrt-v4's `FromInterleaved`: a table that stops inside [360, 830] nm is extended
            // by its end values, one nm beyond the range.
            let (lo, hi) = (cie::LAMBDA_MIN as f32, cie::LAMBDA_MAX as f32);
            if lambda[0] > lo {
                lambda.insert(0, lo - 1.0);
                values.insert(0, values[0]);
            }
            if lambda[lambda.len() - 1] < hi {
                lambda.push(hi + 1.0);
                values.push(values[values.len() - 1]);
            }
            let raw = Spectrum::PiecewiseLinear { lambda, values };
            // pbrt-v4 normalises the illuminants to luminance 1: ∫ s·ȳ = ∫ ȳ (it matters
            // where one is used as a reflectance; lights rescale by luminance anyway).
            if !(name.starts_with("stdillum-") || name.starts_with("illum-")) {
                return Some(raw);
            }
            let y = spectrum_to_xyz_unnormalised(&raw)[1]
                / spectrum_to_xyz_unnormalised(&Spectrum::Constant(1.0))[1];
            let Spectrum::PiecewiseLinear { lambda, values } = raw else {
                unreachable!()
            };
            let values = values.into_iter().map(|v| v / y).collect();
            Some(Spectrum::PiecewiseLinear { lambda, values })
        }
        None => named_spectrum(name),
    }
}

/// The single index of refraction of a named glass (`glass-BK7`, …) for a renderer without
/// dispersion: its value at [`IOR_WAVELENGTH`] (550 nm). `None` for any other name.
pub fn named_ior(name: &str) -> Option<f32> {
    glass(name).map(|c| sellmeier(c, IOR_WAVELENGTH as f64) as f32)
}

/// A dielectric's index of refraction as a scene gives it: one number, a named glass whose
/// index varies with wavelength (Sellmeier), or any other spectrum (pairs, a file, an `rgb`
/// uplifted as pbrt-v4's `RGBUnboundedSpectrum`); an index that varies disperses light in
/// spectral mode.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Ior {
    /// The same index at every wavelength.
    Constant(f32),
    /// A named glass (`glass-F11`, …): its Sellmeier coefficients.
    Glass(&'static [f64; 6]),
    /// A spectrum tabulated every nanometre ([`DenseSpectrum`]), not constant.
    Tabulated {
        /// n(λ).
        spectrum: &'static DenseSpectrum,
        /// The single index of RGB mode (the spectrum at [`IOR_WAVELENGTH`]).
        rgb_mode: f32,
    },
}

impl Ior {
    /// The named glass `name` (`glass-BK7`, …), or `None` for any other name.
    pub fn named_glass(name: &str) -> Option<Ior> {
        glass(name).map(Ior::Glass)
    }

    /// The single index a renderer without dispersion uses (RGB mode): a glass's value at
    /// [`IOR_WAVELENGTH`], exactly [`named_ior`].
    pub fn constant_value(&self) -> f32 {
        match *self {
            Ior::Constant(eta) => eta,
            Ior::Glass(c) => sellmeier(c, IOR_WAVELENGTH as f64) as f32,
            Ior::Tabulated { rgb_mode, .. } => rgb_mode,
        }
    }

    /// The index of `spectrum` (pairs, a file, a named spectrum other than a glass): the
    /// constant `rgb_mode` when it does not vary over 360–830 nm, otherwise [`Ior::Tabulated`] with RGB mode's
    /// index `rgb_mode`.
    pub fn from_spectrum(spectrum: DenseSpectrum, rgb_mode: f32) -> Ior {
        if spectrum.is_constant() {
            Ior::Constant(rgb_mode)
        } else {
            Ior::Tabulated {
                spectrum: intern(spectrum),
                rgb_mode,
            }
        }
    }

    /// An index given as an `rgb` triple, as pbrt-v4 reads one (`RGBUnboundedSpectrum`:
    /// 2m·s(λ), m the largest component, s the uplift of rgb/2m): a grey triple is that
    /// constant; any other varies, and RGB mode takes its value at [`IOR_WAVELENGTH`].
    pub fn from_rgb(rgb: Rgb) -> Ior {
        if rgb.x == rgb.y && rgb.y == rgb.z {
            return Ior::Constant(rgb.x.max(0.0));
        }
        let (scale, s) = super::uplift::unbounded_spectrum(rgb);
        let table = DenseSpectrum::from_fn(|l| scale * s.eval(l));
        let rgb_mode = table.at(IOR_WAVELENGTH);
        Ior::from_spectrum(table, rgb_mode)
    }

    /// The index at `lambda_nm`: n(λ) from the Sellmeier formula for a glass.
    pub fn at(&self, lambda_nm: f32) -> f32 {
        match *self {
            Ior::Constant(eta) => eta,
            Ior::Glass(c) => sellmeier(c, lambda_nm as f64) as f32,
            Ior::Tabulated { spectrum, .. } => spectrum.at(lambda_nm),
        }
    }

    /// Whether the index varies with wavelength, so that refraction separates wavelengths
    /// (pbrt-v4 then keeps only the path's hero wavelength).
    pub fn is_dispersive(&self) -> bool {
        matches!(self, Ior::Glass(_) | Ior::Tabulated { .. })
    }
}

/// Every name [`named_spectrum`] knows.
pub fn named_spectrum_names() -> impl Iterator<Item = &'static str> {
    GLASSES
        .iter()
        .map(|(n, _)| *n)
        .chain(std::iter::once("stdillum-D65"))
        .chain(PRECOMPUTED.iter().map(|(n, _, _)| *n))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// pbrt-v4's illuminant tables have luminance 1 (∫ s·ȳ = ∫ ȳ) and are extended by their
    /// end values outside their range: F2's table runs 380–780 nm with 1.18 at 380 and 0.82
    /// at 780 (raw values), so 370 nm has the value of 380 nm and 820 nm that of 780 nm.
    #[test]
    fn illuminant_tables_are_normalised_and_extended_as_pbrts() {
        let f2 = named_spectrum_data("stdillum-F2").unwrap();
        let y = spectrum_to_xyz_unnormalised(&f2)[1]
            / spectrum_to_xyz_unnormalised(&Spectrum::Constant(1.0))[1];
        assert!((y - 1.0).abs() < 1e-4, "{y}");
        assert_eq!(f2.eval(370.0), f2.eval(380.0));
        assert_eq!(f2.eval(820.0), f2.eval(780.0));
        assert!(f2.eval(370.0) > 0.0);
        // Metals keep their measured values.
        let cu = named_spectrum_data("metal-Cu-k").unwrap();
        let raw = super::super::named_data::TABLES
            .iter()
            .find(|(n, _)| *n == "metal-Cu-k")
            .unwrap()
            .1;
        assert_eq!(cu.eval(raw[2 * 10]), raw[2 * 10 + 1]);
    }

    /// A glass's index at two wavelengths is the Sellmeier formula's, computed here by hand for
    /// SF11 (pbrt's glass-F11): n² = 1 + Σ Bᵢλ²/(λ² − Cᵢ).
    #[test]
    fn glass_ior_follows_sellmeier_and_disperses() {
        let f11 = Ior::named_glass("glass-F11").unwrap();
        let by_hand = |l_um: f64| {
            let l2 = l_um * l_um;
            (1.0 + 1.737_596_95 * l2 / (l2 - 0.013_188_707)
                + 0.313_747_346 * l2 / (l2 - 0.062_306_814_2)
                + 1.898_781_01 * l2 / (l2 - 155.236_29))
                .sqrt()
        };
        for l in [450.0f32, 650.0] {
            assert!(
                (f11.at(l) as f64 - by_hand(l as f64 / 1000.0)).abs() < 1e-6,
                "{l} nm"
            );
        }
        // Dense flint: ≈1.819 at 450 nm, ≈1.777 at 650 nm (Schott SF11).
        assert!((f11.at(450.0) - 1.819).abs() < 1e-3 && (f11.at(650.0) - 1.777).abs() < 1e-3);
        assert!(f11.at(450.0) > f11.at(650.0) + 0.02);
        assert!(f11.is_dispersive() && !Ior::Constant(1.5).is_dispersive());
        assert_eq!(f11.constant_value(), named_ior("glass-F11").unwrap());
        assert_eq!(Ior::Constant(1.33).at(400.0), 1.33);
        assert_eq!(Ior::named_glass("metal-Au-eta"), None);
    }
    use crate::math::luminance;
    use crate::spectrum::reduce::{SpectrumKind, spectrum_to_rgb};

    fn rgb(name: &str, kind: SpectrumKind) -> Rgb {
        spectrum_to_rgb(&named_spectrum(name).expect(name), kind)
    }

    /// Reflectance at normal incidence of a conductor, per channel, from its named eta and k.
    fn reflectance(metal: &str) -> Rgb {
        let eta = rgb(&format!("metal-{metal}-eta"), SpectrumKind::Unbounded);
        let k = rgb(&format!("metal-{metal}-k"), SpectrumKind::Unbounded);
        let r = |n: f32, k: f32| ((n - 1.0).powi(2) + k * k) / ((n + 1.0).powi(2) + k * k);
        Rgb::new(r(eta.x, k.x), r(eta.y, k.y), r(eta.z, k.z))
    }

    /// Gold's measured index at pbrt-v4's table wavelengths (values of `Au_eta`, `Au_k` in
    /// pbrt-v4's spectrum.cpp), exact in the data and within 5e-3 (at a kink of k) in the 1 nm table spectral
    /// mode samples (linear interpolation between nanometres of a piecewise-linear table).
    #[test]
    #[allow(clippy::excessive_precision)] // pbrt-v4's numbers as it writes them
    fn gold_is_tabulated_as_pbrt_tabulates_it() {
        let eta = named_spectrum_data("metal-Au-eta").unwrap();
        let k = named_spectrum_data("metal-Au-k").unwrap();
        let (deta, dk) = (
            crate::spectrum::dense::DenseSpectrum::from_spectrum(&eta),
            crate::spectrum::dense::DenseSpectrum::from_spectrum(&k),
        );
        for (l, n, kk) in [
            (399.948975, 1.658, 1.956),
            (495.936707, 0.916, 1.84),
            (551.040771, 0.3455, 2.730625),
            (652.548279, 0.166, 3.15),
            (799.897949, 0.181375, 5.125813),
        ] {
            assert!((eta.eval(l) - n).abs() < 1e-6, "{l}: {}", eta.eval(l));
            assert!((k.eval(l) - kk).abs() < 1e-6, "{l}: {}", k.eval(l));
            assert!((deta.at(l) - n).abs() < 1e-3, "{l}: {}", deta.at(l));
            assert!((dk.at(l) - kk).abs() < 5e-3, "{l}: {}", dk.at(l));
        }
        // Every tabulated name has data; the glasses and D65 keep their exact forms.
        for n in named_spectrum_names() {
            assert!(
                matches!(
                    named_spectrum_data(n),
                    Some(Spectrum::PiecewiseLinear { .. })
                ),
                "{n}"
            );
        }
    }

    #[test]
    fn every_pbrt_name_resolves() {
        let mut names: Vec<String> = ["BK7", "BAF10", "FK51A", "LASF9", "F5", "F10", "F11"]
            .iter()
            .map(|g| format!("glass-{g}"))
            .collect();
        for m in ["Ag", "Al", "Au", "Cu", "CuZn", "MgO", "TiO2"] {
            names.push(format!("metal-{m}-eta"));
            names.push(format!("metal-{m}-k"));
        }
        for i in ["A", "D50", "D65"] {
            names.push(format!("stdillum-{i}"));
        }
        names.extend((1..=12).map(|i| format!("stdillum-F{i}")));
        names.push("illum-acesD60".into());
        for n in &names {
            assert!(named_spectrum(n).is_some(), "{n}");
        }
        let known: Vec<&str> = named_spectrum_names().collect();
        assert_eq!(known.len(), names.len());
        for n in known {
            assert!(named_spectrum(n).is_some(), "{n}");
        }
    }

    #[test]
    fn other_names_are_unknown() {
        for n in ["", "metal-Fe-eta", "glass-bk7", "stdillum-D60", "metal-Cu"] {
            assert!(named_spectrum(n).is_none(), "{n}");
        }
        assert_eq!(named_ior("metal-Cu-eta"), None);
        assert_eq!(named_ior("glass-SF10"), None);
    }

    #[test]
    fn stored_reductions_are_finite_and_non_negative() {
        for (name, u, i) in PRECOMPUTED {
            for v in u.into_iter().chain(i) {
                assert!(v.is_finite() && v >= 0.0, "{name}: {v}");
            }
        }
    }

    #[test]
    fn copper_the_default_conductor() {
        let eta = rgb("metal-Cu-eta", SpectrumKind::Unbounded);
        let k = rgb("metal-Cu-k", SpectrumKind::Unbounded);
        assert!(close(eta, Rgb::new(0.105, 0.978, 1.204), 1e-3), "{eta}");
        assert!(close(k, Rgb::new(3.274, 2.592, 2.369), 1e-3), "{k}");
        let r = reflectance("Cu");
        assert!(r.x > 0.9 && r.x > r.y && r.y > r.z, "{r}");
    }

    #[test]
    fn gold_is_yellow() {
        let eta = rgb("metal-Au-eta", SpectrumKind::Unbounded);
        let k = rgb("metal-Au-k", SpectrumKind::Unbounded);
        assert!(k.x > k.y && k.y > k.z, "{k}");
        assert!(eta.x < eta.y && eta.y < eta.z, "{eta}");
        let r = reflectance("Au");
        assert!(r.x > 0.9 && r.x > r.y && r.y > r.z && r.z < 0.5, "{r}");
    }

    #[test]
    fn silver_and_aluminium_are_bright_and_neutral() {
        let ag = reflectance("Ag");
        assert!(ag.min_element() > 0.9, "{ag}");
        let al = reflectance("Al");
        assert!(al.min_element() > 0.9, "{al}");
        assert!(al.max_element() - al.min_element() < 0.02, "{al}");
    }

    #[test]
    fn brass_sits_between_copper_and_gold() {
        let r = reflectance("CuZn");
        assert!(r.x > r.y && r.y > r.z && r.z > reflectance("Au").z, "{r}");
    }

    #[test]
    fn dielectric_oxides_are_clear() {
        let mgo = rgb("metal-MgO-eta", SpectrumKind::Unbounded);
        assert!(close(mgo, Rgb::splat(1.74), 0.015), "{mgo}");
        assert_eq!(rgb("metal-MgO-k", SpectrumKind::Unbounded), Rgb::ZERO);
        let tio2 = rgb("metal-TiO2-k", SpectrumKind::Unbounded);
        assert!(tio2.max_element() < 1e-3, "{tio2}");
    }

    #[test]
    fn bk7_index_at_550_nm() {
        let n = named_ior("glass-BK7").unwrap();
        assert!((n - 1.5185).abs() < 1e-3, "{n}");
    }

    #[test]
    fn glasses_match_their_catalogue_index_at_the_d_line() {
        // Schott's n_d (587.5618 nm, the helium d line).
        let nd = [
            ("glass-BK7", 1.51680),
            ("glass-BAF10", 1.67003),
            ("glass-FK51A", 1.48656),
            ("glass-LASF9", 1.85025),
            ("glass-F5", 1.67270),
            ("glass-F10", 1.72828),
            ("glass-F11", 1.78472),
        ];
        for (name, n) in nd {
            let got = sellmeier(glass(name).unwrap(), 587.5618);
            assert!((got - n).abs() < 2e-5, "{name}: {got}");
            let at_550 = named_ior(name).unwrap() as f64;
            assert!(at_550 > n && at_550 - n < 0.01, "{name}: {at_550}");
        }
    }

    #[test]
    fn glass_spectra_disperse() {
        let n = named_ior("glass-F11").unwrap();
        let c = rgb("glass-F11", SpectrumKind::Unbounded);
        assert!(c.z > c.y && c.y > c.x, "{c}");
        assert!(close(c, Rgb::splat(n), 0.04), "{c}");
    }

    #[test]
    fn named_d65_is_white_light_of_luminance_one() {
        let d65 = named_spectrum("stdillum-D65").unwrap();
        let rgb = spectrum_to_rgb(&d65, SpectrumKind::Illuminant);
        assert!(close(rgb, Rgb::ONE, 1e-3), "{rgb}");
        let y = spectrum_to_xyz_unnormalised(&d65)[1]
            / spectrum_to_xyz_unnormalised(&Spectrum::Constant(1.0))[1];
        assert!((y - 1.0).abs() < 1e-5, "{y}");
    }

    #[test]
    fn named_illuminants_have_luminance_one() {
        for name in named_spectrum_names().filter(|n| n.contains("illum")) {
            let c = rgb(name, SpectrumKind::Illuminant);
            assert!((luminance(c) - 1.0).abs() < 2e-3, "{name}: {c}");
        }
    }

    #[test]
    fn named_illuminants_have_their_colours() {
        // Illuminant A is a 2856 K black body.
        let a = rgb("stdillum-A", SpectrumKind::Illuminant);
        let bb = spectrum_to_rgb(
            &Spectrum::Blackbody { kelvin: 2856.0 },
            SpectrumKind::Illuminant,
        );
        assert!(close(a, bb, 2e-3), "{a} vs {bb}");
        // F7 simulates D65; D50 and ACES D60 are warmer than D65, D50 the warmer of the two.
        assert!(close(
            rgb("stdillum-F7", SpectrumKind::Illuminant),
            Rgb::ONE,
            5e-3
        ));
        let d50 = rgb("stdillum-D50", SpectrumKind::Illuminant);
        let d60 = rgb("illum-acesD60", SpectrumKind::Illuminant);
        assert!(d50.x > d60.x && d60.x > 1.0 && d50.z < d60.z && d60.z < 1.0);
    }

    fn close(a: Rgb, b: Rgb, tol: f32) -> bool {
        (a - b).abs().max_element() <= tol
    }
}

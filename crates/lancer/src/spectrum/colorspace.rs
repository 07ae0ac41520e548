//! RGB colour spaces, as pbrt-v4's `ColorSpace` directive names them: `srgb`, `rec2020`,
//! `aces2065-1` and `dci-p3`.
//!
//! A space is three primaries (chromaticities xy) and a white illuminant spectrum: D65 for
//! sRGB, Rec. 2020 and DCI-P3 (pbrt-v4's "P3-D65"), the ACES D60 illuminant for ACES 2065-1.
//! Its RGB → XYZ matrix has the primaries' XYZ (at Y = 1) as columns, each scaled so that RGB
//! (1, 1, 1) is the white's XYZ (at Y = 1): M = P · diag(P⁻¹ W).
//!
//! lancer renders in linear sRGB, so scene colours given in another space are converted to
//! linear sRGB where they are read (they may then lie outside [0, 1]: a saturated Rec. 2020
//! green has a negative sRGB red). Illuminants and D65 reflectances convert exactly by
//! [`ColorSpace::to_srgb`] (the colour of a spectrum is linear in it); see
//! [`super::gamut`] for how such colours become spectra.

use glam::{DMat3, DVec3, Mat3};

use super::cie;
use super::sensor_data::ACES_D60;

/// An RGB colour space (pbrt-v4's named `RGBColorSpace`s).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum ColorSpace {
    /// sRGB / Rec. 709 primaries, D65 white (the default, and lancer's rendering space).
    #[default]
    Srgb,
    /// DCI-P3 primaries with a D65 white (pbrt-v4's `dci-p3`, "P3-D65").
    DciP3,
    /// ITU-R BT.2020 primaries, D65 white.
    Rec2020,
    /// ACES 2065-1 (AP0 primaries, ACES D60 white).
    Aces2065_1,
}

impl ColorSpace {
    /// Every space, in pbrt-v4's order of names.
    pub const ALL: [ColorSpace; 4] = [
        ColorSpace::Srgb,
        ColorSpace::Rec2020,
        ColorSpace::Aces2065_1,
        ColorSpace::DciP3,
    ];

    /// The space pbrt-v4 calls `name` (`srgb`, `rec2020`, `aces2065-1`, `dci-p3`).
    pub fn from_name(name: &str) -> Option<ColorSpace> {
        ColorSpace::ALL.into_iter().find(|c| c.name() == name)
    }

    /// pbrt-v4's name of the space.
    pub fn name(self) -> &'static str {
        match self {
            ColorSpace::Srgb => "srgb",
            ColorSpace::DciP3 => "dci-p3",
            ColorSpace::Rec2020 => "rec2020",
            ColorSpace::Aces2065_1 => "aces2065-1",
        }
    }

    /// Chromaticities (x, y) of the red, green and blue primaries.
    pub fn primaries(self) -> [[f64; 2]; 3] {
        match self {
            ColorSpace::Srgb => [[0.64, 0.33], [0.3, 0.6], [0.15, 0.06]],
            ColorSpace::DciP3 => [[0.68, 0.32], [0.265, 0.69], [0.15, 0.06]],
            ColorSpace::Rec2020 => [[0.708, 0.292], [0.17, 0.797], [0.131, 0.046]],
            ColorSpace::Aces2065_1 => [[0.7347, 0.2653], [0.0, 1.0], [0.0001, -0.077]],
        }
    }

    /// Whether the white is the ACES D60 illuminant (else D65).
    fn is_d60(self) -> bool {
        self == ColorSpace::Aces2065_1
    }

    /// The white illuminant's relative power at `lambda` (nm), interpolated linearly in its
    /// 5 nm table; zero outside 360–830 nm.
    pub fn illuminant(self, lambda: f64) -> f64 {
        if !self.is_d60() {
            return cie::d65(lambda);
        }
        if !(cie::LAMBDA_MIN..=cie::LAMBDA_MAX).contains(&lambda) {
            return 0.0;
        }
        let x = (lambda - cie::LAMBDA_MIN) / cie::LAMBDA_STEP;
        let i = (x.floor() as usize).min(cie::SAMPLES - 2);
        let t = x - i as f64;
        ACES_D60[i] * (1.0 - t) + ACES_D60[i + 1] * t
    }

    /// XYZ of the white illuminant at Y = 1: Σ I(λ)·(x̄, ȳ, z̄)(λ) / Σ I(λ)·ȳ(λ) (1 nm steps).
    pub fn white_xyz(self) -> DVec3 {
        let mut xyz = DVec3::ZERO;
        for l in cie::INTEGRATION_RANGE.map(f64::from) {
            xyz += DVec3::from(cie::cmf(l)) * self.illuminant(l);
        }
        xyz / xyz.y
    }

    /// Linear RGB of this space → CIE XYZ. For sRGB the inverse of lancer's standard matrix
    /// ([`cie::XYZ_TO_SRGB`]); for the others P · diag(P⁻¹ W), P the primaries' XYZ at Y = 1
    /// and W the white's ([`ColorSpace::white_xyz`]), as pbrt-v4 builds them.
    pub fn rgb_to_xyz(self) -> DMat3 {
        if self == ColorSpace::Srgb {
            return self.xyz_to_rgb().inverse();
        }
        let p = self
            .primaries()
            .map(|[x, y]| DVec3::new(x / y, 1.0, (1.0 - x - y) / y));
        let p = DMat3::from_cols(p[0], p[1], p[2]);
        let c = p.inverse() * self.white_xyz();
        p * DMat3::from_diagonal(c)
    }

    /// CIE XYZ → linear RGB of this space.
    pub fn xyz_to_rgb(self) -> DMat3 {
        if self == ColorSpace::Srgb {
            // Rows of the standard matrix as the columns of its transpose.
            return DMat3::from_cols_array_2d(&cie::XYZ_TO_SRGB).transpose();
        }
        self.rgb_to_xyz().inverse()
    }

    /// Linear RGB of this space → linear sRGB, through XYZ without chromatic adaptation: exact
    /// for the colour of an illuminant, and of a reflectance when both whites are D65.
    pub fn to_srgb(self) -> DMat3 {
        ColorSpace::Srgb.xyz_to_rgb() * self.rgb_to_xyz()
    }

    /// Converts `rgb` (linear, this space) to linear sRGB with [`ColorSpace::to_srgb`]; sRGB
    /// comes back bit for bit.
    pub fn rgb_to_srgb(self, rgb: [f32; 3]) -> [f32; 3] {
        if self == ColorSpace::Srgb {
            return rgb;
        }
        let v = self.to_srgb() * DVec3::from(rgb.map(f64::from));
        v.as_vec3().to_array()
    }

    /// Converts a reflectance `rgb` (linear, this space, seen under its white) to the linear
    /// sRGB it has under D65. D65 spaces convert by [`ColorSpace::to_srgb`]; ACES 2065-1 is
    /// first adapted from its D60 white to D65 (Bradford, [`white_balance`]), so that its white
    /// stays white, as a constant reflectance is.
    pub fn reflectance_to_srgb(self, rgb: [f32; 3]) -> [f32; 3] {
        if !self.is_d60() {
            return self.rgb_to_srgb(rgb);
        }
        let adapt = white_balance(self.white_xyz(), ColorSpace::Srgb.white_xyz());
        let m = ColorSpace::Srgb.xyz_to_rgb() * adapt * self.rgb_to_xyz();
        (m * DVec3::from(rgb.map(f64::from))).as_vec3().to_array()
    }
}

/// The matrix from linear RGB with primaries `primaries` and white `white` (chromaticities
/// xy, as an OpenEXR `chromaticities` attribute gives them) to linear sRGB, for reflectances:
/// RGB → XYZ by P · diag(P⁻¹ W), then adapted from `white` to D65 (Bradford) and to sRGB.
/// `None` for sRGB's own primaries and white (within 10⁻³), so that those images stay as they
/// are bit for bit, and for degenerate primaries.
pub fn chromaticities_to_srgb(primaries: [[f64; 2]; 3], white: [f64; 2]) -> Option<Mat3> {
    let srgb = ColorSpace::Srgb.primaries();
    let d65 = [0.3127, 0.329];
    let close = |a: [f64; 2], b: [f64; 2]| (a[0] - b[0]).abs() < 1e-3 && (a[1] - b[1]).abs() < 1e-3;
    if (0..3).all(|i| close(primaries[i], srgb[i])) && close(white, d65) {
        return None;
    }
    let xyz = |[x, y]: [f64; 2]| DVec3::new(x / y, 1.0, (1.0 - x - y) / y);
    let p = primaries.map(xyz);
    let p = DMat3::from_cols(p[0], p[1], p[2]);
    let w = xyz(white);
    let det = p.determinant().abs();
    if det.is_nan() || det <= 1e-12 || !w.is_finite() {
        return None;
    }
    let rgb_to_xyz = p * DMat3::from_diagonal(p.inverse() * w);
    let adapt = white_balance(w, ColorSpace::Srgb.white_xyz());
    let m = ColorSpace::Srgb.xyz_to_rgb() * adapt * rgb_to_xyz;
    m.is_finite().then(|| m.as_mat3())
}

/// XYZ → LMS, the Bradford cone response (the matrix pbrt-v4 uses for white balance).
const LMS_FROM_XYZ: [[f64; 3]; 3] = [
    [0.8951, 0.2664, -0.1614],
    [-0.7502, 1.7135, 0.0367],
    [0.0389, -0.0685, 1.0296],
];

/// LMS → XYZ, the inverse of [`LMS_FROM_XYZ`] (as pbrt-v4 tabulates it).
const XYZ_FROM_LMS: [[f64; 3]; 3] = [
    [0.986993, -0.147054, 0.159963],
    [0.432305, 0.51836, 0.0492912],
    [-0.00852866, 0.0400428, 0.968487],
];

/// A matrix from rows.
fn rows(m: &[[f64; 3]; 3]) -> DMat3 {
    DMat3::from_cols_array_2d(m).transpose()
}

/// von Kries white balance in Bradford's cone space: the XYZ → XYZ matrix that takes the white
/// `src` to the white `dst` (both used by chromaticity only, each brought to Y = 1):
/// M = XYZ_from_LMS · diag(LMS(dst) / LMS(src)) · LMS_from_XYZ.
pub fn white_balance(src: DVec3, dst: DVec3) -> DMat3 {
    let (src, dst) = (src / src.y, dst / dst.y);
    let to_lms = rows(&LMS_FROM_XYZ);
    let (s, d) = (to_lms * src, to_lms * dst);
    rows(&XYZ_FROM_LMS) * DMat3::from_diagonal(d / s) * to_lms
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_round_trip_and_whites_are_the_standard_ones() {
        for c in ColorSpace::ALL {
            assert_eq!(ColorSpace::from_name(c.name()), Some(c));
        }
        assert_eq!(ColorSpace::from_name("P3"), None);
        // D65 at (0.3127, 0.3290), ACES D60 at (0.32168, 0.33767), to the tables' precision.
        let xy = |w: DVec3| (w.x / (w.x + w.y + w.z), w.y / (w.x + w.y + w.z));
        let (x, y) = xy(ColorSpace::Rec2020.white_xyz());
        assert!(
            (x - 0.3127).abs() < 5e-4 && (y - 0.329).abs() < 5e-4,
            "{x} {y}"
        );
        let (x, y) = xy(ColorSpace::Aces2065_1.white_xyz());
        assert!(
            (x - 0.32168).abs() < 5e-4 && (y - 0.33767).abs() < 5e-4,
            "{x} {y}"
        );
    }

    #[test]
    fn conversions_match_the_published_matrices() {
        // BT.2020 → BT.709 (ITU-R BT.2087): the first row is (1.6605, −0.5876, −0.0728).
        let m = ColorSpace::Rec2020.to_srgb();
        let r = m.row(0);
        assert!(
            (r.x - 1.6605).abs() < 2e-3 && (r.y + 0.5876).abs() < 2e-3,
            "{r}"
        );
        assert!((r.z + 0.0728).abs() < 2e-3, "{r}");
        // White maps to white in every D65 space; sRGB is the identity bit for bit.
        for c in [ColorSpace::Rec2020, ColorSpace::DciP3] {
            let w = c.rgb_to_srgb([1.0, 1.0, 1.0]);
            assert!(w.iter().all(|v| (v - 1.0).abs() < 2e-3), "{c:?}: {w:?}");
        }
        assert_eq!(
            ColorSpace::Srgb.rgb_to_srgb([0.1, -0.2, 3.0]),
            [0.1, -0.2, 3.0]
        );
        // ACES white is D60: a little warm as an illuminant, white as a reflectance.
        let l = ColorSpace::Aces2065_1.rgb_to_srgb([1.0, 1.0, 1.0]);
        assert!(l[0] > 1.0 && l[2] < 1.0, "{l:?}");
        let a = ColorSpace::Aces2065_1.reflectance_to_srgb([1.0, 1.0, 1.0]);
        assert!(a.iter().all(|v| (v - 1.0).abs() < 3e-3), "{a:?}");
    }

    #[test]
    fn white_balance_takes_one_white_to_the_other() {
        let a = ColorSpace::Aces2065_1.white_xyz();
        let d = ColorSpace::Srgb.white_xyz();
        let m = white_balance(a, d);
        let got = m * a;
        // pbrt-v4's LMS → XYZ matrix is the inverse rounded to 6 digits.
        assert!((got - d).abs().max_element() < 1e-5, "{got} vs {d}");
        let id = white_balance(d, d);
        assert!(id.abs_diff_eq(DMat3::IDENTITY, 1e-5));
    }
}

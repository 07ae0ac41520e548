//! The `marble` texture: veins of a colour spline perturbed by noise, in texture space.

use super::{At, PlainKind, TextureKind};
use crate::math::noise::fbm;
use crate::math::{Rgb, Vec3};
use crate::texture::Mapping3D;

/// pbrt-v4's marble ([`marble`]) in texture space, plain data.
#[derive(Clone, Debug)]
pub struct MarbleTexture {
    /// Texture space.
    pub mapping: Mapping3D,
    /// Maximum number of octaves.
    pub octaves: u32,
    /// Amplitude ratio between octaves (`roughness`).
    pub omega: f32,
    /// Frequency of the veins (`scale`).
    pub scale: f32,
    /// Strength of the noise (`variation`).
    pub variation: f32,
}

/// The colours of pbrt-v4's marble spline.
const SPLINE: [[f32; 3]; 9] = [
    [0.58, 0.58, 0.6],
    [0.58, 0.58, 0.6],
    [0.58, 0.58, 0.6],
    [0.5, 0.5, 0.5],
    [0.6, 0.59, 0.58],
    [0.58, 0.58, 0.6],
    [0.58, 0.58, 0.6],
    [0.2, 0.2, 0.33],
    [0.58, 0.58, 0.6],
];

/// A cubic Bézier segment at u, by de Casteljau's repeated interpolation.
fn cubic_bezier(cp: [Rgb; 4], u: f32) -> Rgb {
    let l = |a: Rgb, b: Rgb| a + (b - a) * u;
    let (a, b, c) = (l(cp[0], cp[1]), l(cp[1], cp[2]), l(cp[2], cp[3]));
    let (d, e) = (l(a, b), l(b, c));
    l(d, e)
}

/// pbrt-v4's `MarbleTexture` at texture-space point `p`: with `q = scale·p`,
/// `m = q.y + variation · fbm(q, ω, octaves)` and `t = ½ + ½ sin m`, the colour is 1.5 times
/// the cubic spline through [`SPLINE`]'s 9 colours (6 segments) at t.
pub fn marble(p: Vec3, octaves: u32, omega: f32, scale: f32, variation: f32) -> Rgb {
    let q = p * scale;
    let m = q.y + variation * fbm(q, Vec3::ZERO, Vec3::ZERO, omega, octaves);
    let t = 0.5 + 0.5 * m.sin();
    const SEGMENTS: usize = SPLINE.len() - 3;
    let first = ((t * SEGMENTS as f32).floor().max(0.0) as usize).min(SEGMENTS - 1);
    let u = t * SEGMENTS as f32 - first as f32;
    let cp = std::array::from_fn(|i| Rgb::from_array(SPLINE[first + i]));
    1.5 * cubic_bezier(cp, u)
}

impl TextureKind<Rgb> for MarbleTexture {
    #[inline(always)]
    fn evaluate(&self, at: &At) -> Rgb {
        marble(
            self.mapping.map(at.tc),
            self.octaves,
            self.omega,
            self.scale,
            self.variation,
        )
    }
}

/// Its description is what the renderer reads.
impl PlainKind for MarbleTexture {}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn marble_follows_the_spline() {
        // Where fbm vanishes (variation 0), t = ½ + ½ sin(scale·y). y = 0: t = ½ → segment 3,
        // u = 0 → 1.5 × colour 3 = 0.75 grey.
        let c = marble(Vec3::new(0.3, 0.0, 0.2), 8, 0.5, 1.0, 0.0);
        assert!((c - Rgb::splat(0.75)).abs().max_element() < 1e-6, "{c}");
        // sin = 1: t = 1 → the last segment at u = 1: 1.5 × colour 8.
        let c = marble(
            Vec3::new(0.0, std::f32::consts::FRAC_PI_2, 0.0),
            8,
            0.5,
            1.0,
            0.0,
        );
        assert!(
            (c - 1.5 * Rgb::new(0.58, 0.58, 0.6)).abs().max_element() < 1e-5,
            "{c}"
        );
    }
}

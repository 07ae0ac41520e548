//! Evaluation of texture parameters against the scene's texture lists, as pbrt-v4's textures'
//! `Evaluate`.

use super::mapping::{Mapping2D, Mapping3D, TexCoord};
use super::procedural::{bilerp, inside_polka_dot, marble, windy};
use super::{FloatTex, FloatTexture, ImageTexture, SpectrumTex, SpectrumTexture, TextureEval};
use crate::math::Rgb;
use crate::math::noise::{fbm, turbulence};

/// True on the even cells of the 2D checkerboard: `⌊s⌋ + ⌊t⌋` even (pbrt-v4's filtered
/// checkerboard with a zero footprint).
pub(super) fn checker(mapping: &Mapping2D, tc: &TexCoord) -> bool {
    let st = mapping.map(tc);
    (st.x.floor() as i64 + st.y.floor() as i64) & 1 == 0
}

/// True on the even cells of the 3D checkerboard: `⌊x⌋ + ⌊y⌋ + ⌊z⌋` even in texture space.
pub(super) fn checker_3d(mapping: &Mapping3D, tc: &TexCoord) -> bool {
    let p = mapping.map(tc);
    (p.x.floor() as i64 + p.y.floor() as i64 + p.z.floor() as i64) & 1 == 0
}

/// An image texture's filtered colour at `tc` over its footprint, before `scale` and
/// `invert`. pbrt-v4 flips t (texture (0, 0) is the image's lower left); the MIP-map's
/// lookups do that.
#[inline]
fn image_value(it: &ImageTexture, tc: &TexCoord) -> Rgb {
    it.mipmap
        .filter(it.filter, it.wrap, &it.mapping.map_footprint(tc))
}

impl TextureEval<'_> {
    /// The value of a float parameter at `tc`.
    #[inline(always)]
    pub fn float(&self, t: FloatTex, tc: &TexCoord) -> f32 {
        // Constants inline (most parameters), textures out of line.
        match t {
            FloatTex::Const(v) => v,
            FloatTex::Tex(i) => self.float_texture(i, tc),
        }
    }

    /// The value of texture `i` at `tc`.
    #[inline(never)]
    fn float_texture(&self, i: u32, tc: &TexCoord) -> f32 {
        match &self.floats[i as usize] {
            FloatTexture::Constant(v) => *v,
            FloatTexture::Image(it) => {
                // pbrt-v4: v = scale·texel; invert gives max(0, 1 − v).
                let v = image_value(it, tc).x * it.scale;
                if it.invert { (1.0 - v).max(0.0) } else { v }
            }
            FloatTexture::Checkerboard {
                mapping,
                tex1,
                tex2,
            } => {
                if checker(mapping, tc) {
                    self.float(*tex1, tc)
                } else {
                    self.float(*tex2, tc)
                }
            }
            FloatTexture::Checkerboard3D {
                mapping,
                tex1,
                tex2,
            } => {
                if checker_3d(mapping, tc) {
                    self.float(*tex1, tc)
                } else {
                    self.float(*tex2, tc)
                }
            }
            FloatTexture::Scale { tex, scale } => {
                // pbrt-v4 skips the texture where the scale is 0.
                let s = self.float(*scale, tc);
                if s == 0.0 {
                    0.0
                } else {
                    self.float(*tex, tc) * s
                }
            }
            FloatTexture::Mix { tex1, tex2, amount } => {
                let a = self.float(*amount, tc);
                (1.0 - a) * self.float(*tex1, tc) + a * self.float(*tex2, tc)
            }
            FloatTexture::Bilerp { mapping, v } => bilerp(mapping.map(tc), v[0], v[1], v[2], v[3]),
            FloatTexture::Dots {
                mapping,
                dot,
                background,
            } => {
                if inside_polka_dot(mapping.map(tc)) {
                    self.float(*dot, tc)
                } else {
                    self.float(*background, tc)
                }
            }
            FloatTexture::Fbm {
                mapping,
                octaves,
                omega,
            } => {
                // pbrt-v4 fades out the octaves finer than the footprint.
                let (p, dpdx, dpdy) = mapping.map_footprint(tc);
                fbm(p, dpdx, dpdy, *omega, *octaves)
            }
            FloatTexture::Wrinkled {
                mapping,
                octaves,
                omega,
            } => {
                let (p, dpdx, dpdy) = mapping.map_footprint(tc);
                turbulence(p, dpdx, dpdy, *omega, *octaves)
            }
            FloatTexture::Windy { mapping } => windy(mapping.map(tc)),
            FloatTexture::DirectionMix { tex1, tex2, dir } => {
                let a = tc.n.dot(*dir).abs();
                a * self.float(*tex1, tc) + (1.0 - a) * self.float(*tex2, tc)
            }
        }
    }

    /// The value of a colour parameter at `tc`.
    #[inline(always)]
    pub fn spectrum(&self, t: SpectrumTex, tc: &TexCoord) -> Rgb {
        // Constants inline (most parameters), textures out of line.
        match t {
            SpectrumTex::Const(v) => v,
            SpectrumTex::Measured(m) => m.rgb,
            SpectrumTex::Tex(i) => self.spectrum_texture(i, tc),
        }
    }

    /// The value of texture `i` at `tc`.
    #[inline(never)]
    fn spectrum_texture(&self, i: u32, tc: &TexCoord) -> Rgb {
        match &self.spectra[i as usize] {
            SpectrumTexture::Constant(v) => *v,
            SpectrumTexture::Image(it) => {
                // pbrt-v4: max(0, invert ? 1 − scale·c : scale·c), in the image's own colour
                // space: texels of a wider space than sRGB may be negative here (their spectra
                // come from `spectrum::uplift`), so only an inverted value is clamped.
                let v = image_value(it, tc) * it.scale;
                if it.invert {
                    (Rgb::ONE - v).max(Rgb::ZERO)
                } else {
                    v
                }
            }
            SpectrumTexture::Checkerboard {
                mapping,
                tex1,
                tex2,
            } => {
                if checker(mapping, tc) {
                    self.spectrum(*tex1, tc)
                } else {
                    self.spectrum(*tex2, tc)
                }
            }
            SpectrumTexture::Checkerboard3D {
                mapping,
                tex1,
                tex2,
            } => {
                if checker_3d(mapping, tc) {
                    self.spectrum(*tex1, tc)
                } else {
                    self.spectrum(*tex2, tc)
                }
            }
            SpectrumTexture::Scale { tex, scale } => {
                let s = self.float(*scale, tc);
                if s == 0.0 {
                    Rgb::ZERO
                } else {
                    self.spectrum(*tex, tc) * s
                }
            }
            SpectrumTexture::Mix { tex1, tex2, amount } => {
                let a = self.float(*amount, tc);
                (1.0 - a) * self.spectrum(*tex1, tc) + a * self.spectrum(*tex2, tc)
            }
            SpectrumTexture::Bilerp { mapping, v } => {
                bilerp(mapping.map(tc), v[0], v[1], v[2], v[3])
            }
            SpectrumTexture::Dots {
                mapping,
                dot,
                background,
            } => {
                if inside_polka_dot(mapping.map(tc)) {
                    self.spectrum(*dot, tc)
                } else {
                    self.spectrum(*background, tc)
                }
            }
            SpectrumTexture::Marble {
                mapping,
                octaves,
                omega,
                scale,
                variation,
            } => marble(mapping.map(tc), *octaves, *omega, *scale, *variation),
            SpectrumTexture::DirectionMix { tex1, tex2, dir } => {
                let a = tc.n.dot(*dir).abs();
                a * self.spectrum(*tex1, tc) + (1.0 - a) * self.spectrum(*tex2, tc)
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::{Transform, Vec2, Vec3};
    use crate::texture::UvMapping;

    fn at(uv: Vec2, p: Vec3, n: Vec3) -> TexCoord {
        TexCoord {
            uv,
            p,
            n,
            ..TexCoord::default()
        }
    }

    #[test]
    fn float_textures_follow_pbrt_v4s_formulas() {
        let floats = vec![
            // 0: bilerp v00 0.05, v01 1, v10 0.05, v11 1 (procedural.pbrt's "fade").
            FloatTexture::Bilerp {
                mapping: Mapping2D::default(),
                v: [0.05, 1.0, 0.05, 1.0],
            },
            // 1: 3D checkerboard of 0.2-unit cells.
            FloatTexture::Checkerboard3D {
                mapping: Mapping3D {
                    texture_from_world: Transform::scale(Vec3::splat(0.2)).unwrap().inverse(),
                },
                tex1: FloatTex::Const(1.0),
                tex2: FloatTex::Const(0.0),
            },
            // 2: directionmix along +y of 1 and 0.
            FloatTexture::DirectionMix {
                tex1: FloatTex::Const(1.0),
                tex2: FloatTex::Const(0.0),
                dir: Vec3::Y,
            },
            // 3: scale of texture 0 by 0: 0 without looking at it.
            FloatTexture::Scale {
                tex: FloatTex::Tex(0),
                scale: FloatTex::Const(0.0),
            },
            // 4: 2D checker with uscale 4.
            FloatTexture::Checkerboard {
                mapping: UvMapping {
                    su: 4.0,
                    ..UvMapping::default()
                }
                .into(),
                tex1: FloatTex::Const(0.25),
                tex2: FloatTex::Const(0.75),
            },
        ];
        let ev = TextureEval {
            floats: &floats,
            spectra: &[],
        };
        let f = |i, tc: &TexCoord| ev.float(FloatTex::Tex(i), tc);
        // Bilerp at (s, t) = (0.3, 0.5): 0.05 + 0.5·0.95 = 0.525.
        let tc = at(Vec2::new(0.3, 0.5), Vec3::ZERO, Vec3::Z);
        assert!((f(0, &tc) - 0.525).abs() < 1e-6);
        // (0.1, 0.1, 0.1) is cell (0, 0, 0): even; (0.3, 0.1, 0.1) is cell (1, 0, 0): odd;
        // (−0.1, −0.1, 0.1) is (−1, −1, 0): even.
        for (p, want) in [
            (Vec3::splat(0.1), 1.0),
            (Vec3::new(0.3, 0.1, 0.1), 0.0),
            (Vec3::new(-0.1, -0.1, 0.1), 1.0),
        ] {
            assert_eq!(f(1, &at(Vec2::ZERO, p, Vec3::Z)), want, "{p}");
        }
        // |n·dir| = cos 60° = ½ → ½·1 + ½·0.
        let n = Vec3::new(0.0, 0.5, 0.75f32.sqrt());
        assert!((f(2, &at(Vec2::ZERO, Vec3::ZERO, n)) - 0.5).abs() < 1e-6);
        assert_eq!(f(3, &tc), 0.0);
        // u = 0.3 → s = 1.2: odd column.
        assert_eq!(f(4, &tc), 0.75);
    }

    #[test]
    fn spectrum_dots_draw_the_dot_value_inside() {
        let spectra = vec![SpectrumTexture::Dots {
            mapping: Mapping2D::default(),
            dot: SpectrumTex::Const(Rgb::X),
            background: SpectrumTex::Const(Rgb::Y),
        }];
        let ev = TextureEval {
            floats: &[],
            spectra: &spectra,
        };
        let c = |u: f32, v: f32| {
            ev.spectrum(
                SpectrumTex::Tex(0),
                &at(Vec2::new(u, v), Vec3::ZERO, Vec3::Z),
            )
        };
        // Cell corners are always between the dots.
        assert_eq!(c(0.5, 0.5), Rgb::Y);
        let cells: Vec<Rgb> = (0..16).map(|i| c(i as f32, 0.0)).collect();
        assert!(cells.contains(&Rgb::X) && cells.contains(&Rgb::Y));
    }
}

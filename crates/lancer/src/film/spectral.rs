//! pbrt-v4's `spectral` film: besides the colour channels, the radiance in `nbuckets` equal
//! wavelength buckets over [lambdamin, lambdamax], written as OpenEXR channels laid out as
//! "An OpenEXR Layout for Spectral Images" (Fichet et al. 2021) proposes.
//!
//! As pbrt-v4's `SpectralFilm`:
//! - the wavelengths of a camera sample are drawn uniformly over [lambdamin, lambdamax]
//!   (`SampleUniform`) instead of by the visible-light density;
//! - each sample adds its colour to the RGB sums as an `rgb` film does, and each of its four
//!   radiance values L(λᵢ) (scaled down so that its largest is at most `maxcomponentvalue`)
//!   adds w·L(λᵢ) to the sum of the bucket λᵢ falls in, and w to that bucket's weight.
//!   pbrt-v4 adds w·L(λᵢ)·∫ȳ (`CIE_Y_integral`, 106.857) to undo its lights' photometric
//!   normalisation; lancer's radiance already is pbrt-v4's times ∫ȳ (its lights are
//!   normalised against the film's 1/∫ȳ instead: [`crate::spectrum::sampled`]), so the sums
//!   are the same numbers. L is not divided by the wavelength density: that density is
//!   uniform and the buckets equally wide;
//! - a bucket's value is its sum over its weight (0 where no sample fell), not multiplied by
//!   the film's imaging ratio (pbrt-v4 applies that in the sensor's RGB only);
//! - channel i is named `S0.<λc>nm`, λc = lerp((i + ½)/n, min, max) with three decimals and
//!   its '.' written ',' (a '.' separates layers in OpenEXR): `S0.374,688nm`; the header has
//!   `spectralLayoutVersion` "1.0" and `emissiveUnits` "W.m^-2.sr^-1"; half floats by default
//!   (`savefp16`), values clamped to 65504 there.
//!
//! The sums are fixed point like the colour sums ([`super::to_fixed`]), so tiles merge
//! exactly in any order.

use super::{PixelBounds, from_fixed, to_fixed};
use crate::math::SampledSpectrum;
use crate::spectrum::sampled::{N_SPECTRUM_SAMPLES, SampledWavelengths};

/// What a `spectral` film asks for: its buckets.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SpectralDesc {
    /// Number of buckets (`nbuckets`, 16 by default).
    pub nbuckets: u32,
    /// Shortest wavelength in nm (`lambdamin`, 360 by default).
    pub lambda_min: f32,
    /// Longest wavelength in nm (`lambdamax`, 830 by default).
    pub lambda_max: f32,
}

impl Default for SpectralDesc {
    /// pbrt-v4's defaults: 16 buckets over 360–830 nm.
    fn default() -> Self {
        SpectralDesc {
            nbuckets: 16,
            lambda_min: 360.0,
            lambda_max: 830.0,
        }
    }
}

impl SpectralDesc {
    /// The bucket of wavelength `lambda`, as pbrt-v4's `LambdaToBucket`:
    /// b = ⌊n·(λ − min)/(max − min)⌋ clamped to [0, n − 1].
    #[inline]
    pub fn bucket(&self, lambda: f32) -> usize {
        let n = self.nbuckets as f32;
        let b = (n * (lambda - self.lambda_min) / (self.lambda_max - self.lambda_min)) as i64;
        b.clamp(0, self.nbuckets as i64 - 1) as usize
    }

    /// The camera sample's wavelengths from one uniform number (pbrt-v4's
    /// `SpectralFilm::SampleWavelengths`).
    #[inline]
    pub fn sample_wavelengths(&self, u: f32) -> SampledWavelengths {
        SampledWavelengths::sample_uniform(u, self.lambda_min, self.lambda_max)
    }

    /// The names of the bucket channels, in order: `S0.<centre>nm` with the centre
    /// lerp((i + ½)/n, min, max) printed with three decimals and ',' for '.'.
    pub fn channel_names(&self) -> Vec<String> {
        (0..self.nbuckets)
            .map(|i| {
                let t = (i as f32 + 0.5) / self.nbuckets as f32;
                let centre = (1.0 - t) * self.lambda_min + t * self.lambda_max;
                format!("S0.{}nm", format!("{centre:.3}").replace('.', ","))
            })
            .collect()
    }
}

/// The bucket sums of a spectral film (or of one tile): per pixel, `nbuckets` sums of
/// w·L then `nbuckets` sums of w, fixed point.
#[derive(Clone, Debug, PartialEq)]
pub struct SpectralSums {
    /// The buckets.
    pub desc: SpectralDesc,
    /// Row-major pixels, 2·nbuckets values each.
    pub sums: Vec<i64>,
}

impl SpectralSums {
    /// Zero sums for `pixels` pixels.
    pub fn new(desc: SpectralDesc, pixels: usize) -> SpectralSums {
        SpectralSums {
            desc,
            sums: vec![0; pixels * 2 * desc.nbuckets as usize],
        }
    }

    /// The sums of pixel `i`: (bucket sums, weight sums).
    fn pixel_mut(&mut self, i: usize) -> (&mut [i64], &mut [i64]) {
        let n = self.desc.nbuckets as usize;
        self.sums[2 * n * i..2 * n * (i + 1)].split_at_mut(n)
    }

    /// Adds a camera sample of pixel `i`: radiance `l` at `lambda`, filter weight `w`, scaled
    /// down to `max_component` when its largest value is above it (pbrt-v4's
    /// `SpectralFilm::AddSample`). A sample whose radiance is not finite adds only its weight
    /// (as the colour sums count it black).
    pub fn add(
        &mut self,
        i: usize,
        l: SampledSpectrum,
        lambda: &SampledWavelengths,
        w: f32,
        max_component: f32,
    ) {
        let l = if l.is_finite() {
            l
        } else {
            SampledSpectrum::ZERO
        };
        let m = l.max_element();
        let l = if m > max_component {
            l * (max_component / m)
        } else {
            l
        };
        let l = l * w;
        let desc = self.desc;
        let (sums, weights) = self.pixel_mut(i);
        for k in 0..N_SPECTRUM_SAMPLES {
            let b = desc.bucket(lambda.lambda[k]);
            sums[b] = sums[b].saturating_add(to_fixed(l[k]));
            weights[b] = weights[b].saturating_add(to_fixed(w));
        }
    }

    /// Adds a tile's sums (its pixels row-major over `tile`) to these, which cover `bounds`.
    pub fn merge_tile(&mut self, bounds: &PixelBounds, tile: &PixelBounds, o: &SpectralSums) {
        let n2 = 2 * self.desc.nbuckets as usize;
        let t = tile.intersect(bounds);
        let (tw, bw) = (tile.width() as usize, bounds.width() as usize);
        for y in t.y0..t.y1 {
            for x in t.x0..t.x1 {
                let s = ((y - tile.y0) as usize * tw + (x - tile.x0) as usize) * n2;
                let d = ((y - bounds.y0) as usize * bw + (x - bounds.x0) as usize) * n2;
                for (a, b) in self.sums[d..d + n2].iter_mut().zip(&o.sums[s..s + n2]) {
                    *a = a.saturating_add(*b);
                }
            }
        }
    }

    /// The bucket values of pixel `i`: Σ w·L / Σ w per bucket, 0 where no weight fell.
    pub fn values(&self, i: usize) -> Vec<f32> {
        let n = self.desc.nbuckets as usize;
        let (sums, weights) = self.sums[2 * n * i..2 * n * (i + 1)].split_at(n);
        sums.iter()
            .zip(weights)
            .map(|(&s, &w)| {
                if w > 0 {
                    (from_fixed(s) / from_fixed(w)) as f32
                } else {
                    0.0
                }
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn channel_names_are_pbrt_v4_bucket_centres() {
        let names = SpectralDesc::default().channel_names();
        assert_eq!(names.len(), 16);
        // (0.5/16)·470 + 360 = 374.6875 → "374.688" with three decimals.
        assert_eq!(names[0], "S0.374,688nm");
        assert_eq!(names[15], "S0.815,312nm");
        let d = SpectralDesc {
            nbuckets: 2,
            lambda_min: 400.0,
            lambda_max: 700.0,
        };
        assert_eq!(d.channel_names(), ["S0.475,000nm", "S0.625,000nm"]);
    }

    #[test]
    fn buckets_split_the_range_evenly_and_clamp() {
        let d = SpectralDesc {
            nbuckets: 4,
            lambda_min: 400.0,
            lambda_max: 800.0,
        };
        assert_eq!(d.bucket(400.0), 0);
        assert_eq!(d.bucket(499.9), 0);
        assert_eq!(d.bucket(500.0), 1);
        assert_eq!(d.bucket(799.0), 3);
        assert_eq!(d.bucket(800.0), 3);
        assert_eq!(d.bucket(300.0), 0);
    }

    #[test]
    fn uniform_wavelengths_fall_one_per_quarter() {
        let d = SpectralDesc::default();
        let w = d.sample_wavelengths(0.1);
        // λ₀ = 360 + 0.1·470 = 407, then steps of 117.5 nm.
        let expect = [407.0, 524.5, 642.0, 759.5];
        for (k, e) in expect.iter().enumerate() {
            assert!((w.lambda[k] - e).abs() < 1e-3, "{:?}", w.lambda);
            assert!((w.pdf[k] - 1.0 / 470.0).abs() < 1e-9);
        }
        // Past the top they wrap to the bottom: u = 0.9 gives 783, then 430.5, 548, 665.5.
        let w = d.sample_wavelengths(0.9);
        assert!((w.lambda[1] - 430.5).abs() < 1e-3, "{:?}", w.lambda);
    }

    #[test]
    fn bucket_values_are_weighted_means() {
        let d = SpectralDesc {
            nbuckets: 4,
            lambda_min: 360.0,
            lambda_max: 830.0,
        };
        let mut s = SpectralSums::new(d, 2);
        let lambda = d.sample_wavelengths(0.0); // 360, 477.5, 595, 712.5: one per bucket
        s.add(
            1,
            SampledSpectrum::new(1.0, 2.0, 3.0, 4.0),
            &lambda,
            0.5,
            f32::INFINITY,
        );
        s.add(
            1,
            SampledSpectrum::new(3.0, 2.0, 1.0, 0.0),
            &lambda,
            1.5,
            f32::INFINITY,
        );
        // Bucket 0: (0.5·1 + 1.5·3)/(0.5 + 1.5) = 2.5, bucket 3: (0.5·4 + 0)/2 = 1.
        let v = s.values(1);
        let expect = [2.5, 2.0, 1.5, 1.0];
        for (a, e) in v.iter().zip(expect) {
            assert!((a - e).abs() < 1e-6, "{v:?}");
        }
        assert_eq!(s.values(0), [0.0; 4]);
        // maxcomponentvalue scales the whole sample down: (1, 2, 3, 8) at most 4 → (½, 1, 1½, 4).
        let mut c = SpectralSums::new(d, 1);
        c.add(
            0,
            SampledSpectrum::new(1.0, 2.0, 3.0, 8.0),
            &lambda,
            1.0,
            4.0,
        );
        assert!((c.values(0)[0] - 0.5).abs() < 1e-6);
        // A non-finite sample counts as black.
        c.add(0, SampledSpectrum::splat(f32::NAN), &lambda, 1.0, 4.0);
        assert!((c.values(0)[3] - 2.0).abs() < 1e-6);
    }

    #[test]
    fn tiles_merge_into_place() {
        let d = SpectralDesc {
            nbuckets: 1,
            lambda_min: 360.0,
            lambda_max: 830.0,
        };
        let film = PixelBounds {
            x0: 0,
            x1: 3,
            y0: 0,
            y1: 2,
        };
        let tile = PixelBounds {
            x0: 1,
            x1: 3,
            y0: 1,
            y1: 2,
        };
        let mut t = SpectralSums::new(d, 2);
        let lambda = d.sample_wavelengths(0.5);
        t.add(1, SampledSpectrum::ONE, &lambda, 1.0, f32::INFINITY);
        let mut f = SpectralSums::new(d, 6);
        f.merge_tile(&film, &tile, &t);
        f.merge_tile(&film, &tile, &t);
        // Tile pixel 1 is (2, 1): film pixel 5.
        assert!((f.values(5)[0] - 1.0).abs() < 1e-6);
        assert_eq!(f.sums[2 * 5 + 1], 2 * 4 * to_fixed(1.0));
        assert_eq!(f.values(4), [0.0]);
    }
}

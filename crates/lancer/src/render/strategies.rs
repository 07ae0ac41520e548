//! bdpt's strategy images (pbrt-v4's `visualizestrategies` and `visualizeweights`): one image
//! per connection strategy (s, t) of each depth d = s + t − 2 ≤ `maxdepth`, holding what that
//! strategy alone brings to the rendered image, without its MIS weight
//! (`visualizestrategies`: each one an estimate of the light of depth d by that strategy
//! alone) or with it (`visualizeweights`: then the images sum to the rendered image).
//!
//! Each strategy lands where the rendered image puts it: a strategy with t ≥ 2 in its camera
//! sample's pixel, with the sample's filter weight, over that pixel's filter weight sum Σw
//! (as the image's Σw·L/Σw); a t = 1 strategy through the film's filter at its film point,
//! over the samples per pixel n (as the image's splats S/n). pbrt-v4 puts both in the pixel
//! that holds their film point (a box filter, the camera ray reprojected) and divides both by
//! n; here the weighted images add up to the rendered image, to rounding (the t = 1 ones to
//! the bit: the same fixed-point splats). The sums are fixed-point integers, as the film's,
//! so the images do not depend on the thread count. Colours are the film's (the scene's
//! sensor, or CIE in spectral mode); `maxcomponentvalue` does not clamp them.

use super::{SampleAt, SampleIntegrator, Splats, scene_film_rgb};
use crate::film::splat::{AtomicSplats, SplatPlane};
use crate::film::tile::{FilmKind, FilmSplats};
use crate::film::{Film, PixelBounds, from_fixed};
use crate::filter::Filter;
use crate::integrator::bdpt::{self, BdptOptions};
use crate::math::{Rgb, SampledSpectrum, Vec2};
use crate::ray::Ray;
use crate::sampling::Sampler;
use crate::scene::Scene;
use crate::spectrum::sampled::SampledWavelengths;

/// One connection strategy: s light subpath vertices joined to t camera subpath vertices.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub struct Strategy {
    /// Light subpath vertices.
    pub s: usize,
    /// Camera subpath vertices.
    pub t: usize,
}

impl Strategy {
    /// The depth of the paths it makes: s + t − 2 bounces.
    pub fn depth(&self) -> usize {
        self.s + self.t - 2
    }

    /// pbrt-v4's name for its image: `bdpt_d{depth:02}_s{s:02}_t{t:02}.exr`.
    pub fn file_name(&self) -> String {
        format!(
            "bdpt_d{:02}_s{:02}_t{:02}.exr",
            self.depth(),
            self.s,
            self.t
        )
    }
}

/// The strategies bdpt runs for paths of at most `max_depth` bounces, by depth and then s
/// (pbrt-v4's: t ≥ 1, and not s = t = 1).
pub fn strategies(max_depth: u32) -> Vec<Strategy> {
    let mut out = Vec::new();
    for depth in 0..=max_depth as usize {
        for s in 0..=depth + 2 {
            let t = depth + 2 - s;
            if t == 0 || (s == 1 && t == 1) {
                continue;
            }
            out.push(Strategy { s, t });
        }
    }
    out
}

/// The strategy images of a render as the threads add to them: a fixed-point plane per
/// strategy (its colour sums).
#[derive(Debug)]
pub struct StrategyImages {
    /// Weighted (`visualizeweights`) rather than unweighted (`visualizestrategies`).
    weighted: bool,
    /// The strategies, in [`strategies`]' order.
    strategies: Vec<Strategy>,
    /// Their sums, in the same order, over the render's pixels.
    planes: Vec<AtomicSplats>,
}

impl StrategyImages {
    /// Empty images of bdpt's strategies up to `max_depth` over `bounds` (the render's
    /// pixels), `weighted` or not.
    pub fn new(max_depth: u32, weighted: bool, bounds: PixelBounds) -> StrategyImages {
        let strategies = strategies(max_depth);
        let planes = strategies
            .iter()
            .map(|_| AtomicSplats::new(bounds, 3))
            .collect();
        StrategyImages {
            weighted,
            strategies,
            planes,
        }
    }

    /// The plane of strategy (s, t), if it is one of the images'.
    fn plane(&self, s: usize, t: usize) -> Option<&AtomicSplats> {
        let i = self.strategies.iter().position(|x| x.s == s && x.t == t)?;
        self.planes.get(i)
    }

    /// The images over `film`'s pixels (row-major over its bounds) once the render that
    /// filled them has added its samples to `film`, times `scale` (the film's): a t ≥ 2
    /// strategy's sums over each pixel's filter weight sum Σw, a t = 1 strategy's over the
    /// samples per pixel n.
    pub fn images(self, film: &Film, scale: f32) -> Vec<(Strategy, Vec<Rgb>)> {
        let n = film
            .pixels
            .iter()
            .map(|p| p.samples)
            .max()
            .unwrap_or(0)
            .max(1) as f64;
        let b = film.bounds;
        self.strategies
            .into_iter()
            .zip(self.planes)
            .map(|(st, plane)| {
                let plane: SplatPlane = plane.into_plane();
                let pixels = film
                    .pixels
                    .iter()
                    .enumerate()
                    .map(|(i, p)| {
                        let (x, y) = (
                            b.x0 + (i as u32 % b.width()) as i32,
                            b.y0 + (i as u32 / b.width()) as i32,
                        );
                        let divisor = if st.t == 1 { n } else { from_fixed(p.weight) };
                        if divisor == 0.0 {
                            return Rgb::ZERO;
                        }
                        let c = |k: usize| (plane.value(x, y, k) / divisor) as f32 * scale;
                        Rgb::new(c(0), c(1), c(2))
                    })
                    .collect();
                (st, pixels)
            })
            .collect()
    }
}

/// bdpt rendering the image as [`crate::integrator::Integrator::Bdpt`] does, bit for bit, and
/// adding each strategy's contribution to `images` as it goes.
pub struct ObservedBdpt<'a> {
    /// bdpt's settings.
    pub options: BdptOptions,
    /// Where the strategies go.
    pub images: &'a StrategyImages,
    /// The film's filter (t = 1 strategies spread as the image's splats).
    pub filter: &'a Filter,
}

impl ObservedBdpt<'_> {
    /// Adds one strategy's `contribution` (MIS-weighted, with MIS weight `w`) to its image: at
    /// film point `p` through the filter (t = 1), else to the sample's pixel `at`.
    #[allow(clippy::too_many_arguments)] // the observer's arguments and the sample's
    fn observe(
        &self,
        scene: &Scene,
        lambda: Option<&SampledWavelengths>,
        at: Option<SampleAt>,
        (s, t): (usize, usize),
        p: Option<Vec2>,
        contribution: SampledSpectrum,
        w: f32,
    ) {
        let Some(plane) = self.images.plane(s, t) else {
            return;
        };
        let v = if self.images.weighted {
            contribution
        } else {
            contribution / w
        };
        if !v.is_finite() {
            return;
        }
        let rgb = scene_film_rgb(scene, lambda, v);
        match (p, at) {
            (Some(p), _) => {
                FilmSplats::new(plane, self.filter, FilmKind::Rgb).add_splat(p, rgb, None)
            }
            (None, Some(at)) => {
                let c = rgb * at.weight;
                plane.add(at.x, at.y, &[c.x, c.y, c.z]);
            }
            (None, None) => {}
        }
    }

    /// bdpt's radiance for the camera ray `ray`, splatting into `splats`, each strategy
    /// observed for the sample `at` (`None`: the t ≥ 2 strategies have no pixel to go to).
    fn li_observed(
        &self,
        scene: &Scene,
        ray: &Ray,
        sampler: &mut Sampler,
        lambda: Option<&SampledWavelengths>,
        splats: &Splats<'_>,
        at: Option<SampleAt>,
    ) -> SampledSpectrum {
        let mut observe = |s, t, p, c, w| self.observe(scene, lambda, at, (s, t), p, c, w);
        bdpt::li(
            scene,
            ray,
            sampler,
            lambda,
            self.options,
            &mut |p, l| splats.add_splat(p, l, lambda),
            Some(&mut observe),
        )
    }
}

impl SampleIntegrator for ObservedBdpt<'_> {
    fn splats(&self) -> bool {
        true
    }

    fn computes_radiance(&self) -> bool {
        true
    }

    fn li(
        &self,
        scene: &Scene,
        ray: &Ray,
        sampler: &mut Sampler,
        lambda: Option<&SampledWavelengths>,
        splats: &Splats<'_>,
    ) -> SampledSpectrum {
        self.li_observed(scene, ray, sampler, lambda, splats, None)
    }

    fn li_at(
        &self,
        scene: &Scene,
        ray: &Ray,
        sampler: &mut Sampler,
        lambda: Option<&SampledWavelengths>,
        splats: &Splats<'_>,
        at: SampleAt,
    ) -> SampledSpectrum {
        self.li_observed(scene, ray, sampler, lambda, splats, Some(at))
    }
}

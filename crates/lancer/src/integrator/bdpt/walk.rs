//! The two subpaths of a bidirectional sample (pbrt-v4's `GenerateCameraSubpath`,
//! `GenerateLightSubpath` and `RandomWalk`): each vertex records its throughput and the
//! densities, per unit area, with which its own subpath reached it (`pdf_fwd`) and with which
//! the other direction would have (`pdf_rev`, filled in as the next vertex is sampled).
//!
//! Through a medium the walk samples distances by delta tracking against the majorant, at
//! the hero lane's coefficients (pbrt-v4's `RandomWalk`): at each tentative collision the
//! path is absorbed, scatters (a medium vertex, then a direction from the phase function) or
//! goes on (a null collision), with probabilities σ_a/σ_maj, σ_s/σ_maj and the rest.

use super::super::volpath::{Collision, collision, hero_lane, medium_after, seeded_rng};
use super::super::{bsdf_at, keep_hero_only};
use super::vertex::{Kind, Vertex, infinite_light_density};
use crate::material::TransportMode;
use crate::math::{SampledSpectrum, Vec3, normalize};
use crate::medium::{MediumProperties, sample_t_maj};
use crate::ray::Ray;
use crate::sampling::SampleSource;
use crate::scene::Scene;
use crate::spectrum::hero::HERO_ONLY;
use crate::spectrum::sampled::SampledWavelengths;

thread_local! {
    /// The subpaths' vertices, kept from one sample to the next on each thread (no
    /// allocation per sample once they have grown).
    pub(super) static PATHS: std::cell::RefCell<(Vec<Vertex>, Vec<Vertex>)> =
        const { std::cell::RefCell::new((Vec::new(), Vec::new())) };
}

/// What both subpaths share as they are traced.
pub(super) struct Walk<'a> {
    /// The scene.
    pub scene: &'a Scene,
    /// The sample's wavelengths (spectral mode), which a dispersive surface terminates (every
    /// contribution is then weighted by [`HERO_ONLY`]).
    pub lambda: Option<SampledWavelengths>,
    /// Roughen near-specular lobes after a non-specular bounce (pbrt's `regularize`).
    pub regularize: bool,
    /// The lane whose coefficients sample distances in media (0 in spectral mode, one of the
    /// four per camera sample in RGB mode: `volpath`'s `hero_lane`).
    pub hero: usize,
}

/// What became of a ray crossing a medium up to the next surface.
enum Crossing {
    /// It reached the surface (or infinity).
    Passed,
    /// It scattered: the walk goes on along this ray.
    Scattered(Ray),
    /// The walk ends (absorbed, out of vertices, no throughput left).
    Ended,
}

impl<'a> Walk<'a> {
    /// The walk of the camera sample whose camera ray is `ray`: its hero lane is `volpath`'s
    /// for that ray, or 0 in a scene without media (which has no use for it, and then no
    /// hash per sample).
    pub fn new(
        scene: &'a Scene,
        ray: &Ray,
        lambda: Option<&SampledWavelengths>,
        regularize: bool,
    ) -> Self {
        Walk {
            scene,
            lambda: lambda.copied(),
            regularize,
            hero: if scene.media().is_empty() {
                0
            } else {
                hero_lane(ray, lambda)
            },
        }
    }

    /// The camera subpath of at most `max_vertices` vertices for camera ray `ray`, into `path`
    /// (cleared first): the lens, then the surfaces the path meets.
    pub fn camera_subpath<S: SampleSource + ?Sized>(
        &mut self,
        ray: &Ray,
        sampler: &mut S,
        max_vertices: usize,
        path: &mut Vec<Vertex>,
    ) {
        path.clear();
        if max_vertices == 0 {
            return;
        }
        let beta = SampledSpectrum::ONE;
        let mut v = Vertex::endpoint(Kind::Camera, ray.o, Vec3::ZERO, Vec3::ZERO, beta);
        v.medium = self.scene.camera_medium();
        path.push(v);
        let (_, pdf_dir) = self.scene.camera().pdf_we(ray.o, ray.d);
        self.random_walk(
            *ray,
            sampler,
            beta,
            pdf_dir,
            max_vertices - 1,
            TransportMode::Radiance,
            path,
        );
    }

    /// The light subpath of at most `max_vertices` vertices into `path` (cleared first): a
    /// light chosen by power, a ray leaving it, the surfaces that ray meets.
    pub fn light_subpath<S: SampleSource + ?Sized>(
        &mut self,
        sampler: &mut S,
        max_vertices: usize,
        path: &mut Vec<Vertex>,
    ) {
        path.clear();
        if max_vertices == 0 {
            return;
        }
        let scene = self.scene;
        let Some((light, p_choice)) = scene.light_distribution().sample(sampler.get_1d()) else {
            return;
        };
        let (u1, u2) = (sampler.get_2d(), sampler.get_2d());
        let Some(les) = scene.lights()[light].sample_le(u1, u2, scene.shapes(), scene.meshes())
        else {
            return;
        };
        crate::counters::count_light_path();
        let le = scene.light_radiance(light, self.lambda.as_ref(), les.l, les.factor, -les.w);
        if le == SampledSpectrum::ZERO {
            return;
        }
        // The first vertex: density p_l·p_pos of its position.
        let p = p_choice * les.pdf_pos;
        let ray = les.ray();
        let mut v = Vertex::endpoint(Kind::Light(light as u32), les.p, les.p_error, les.n, le);
        v.pdf_fwd = p;
        v.medium = scene.light_medium(light, les.n, ray.d);
        path.push(v);
        // β = Le·|cos θ| / (p_l·p_pos·p_dir).
        let beta = le * (les.abs_cos() / (p * les.pdf_dir));
        let n_walk = self.random_walk(
            ray,
            sampler,
            beta,
            les.pdf_dir,
            max_vertices - 1,
            TransportMode::Importance,
            path,
        );
        // A light at infinity: its rays' origins are spread over the scene's disk, so the
        // second vertex's density is p_pos (per unit area of the disk, projected onto the
        // surface), and the first's is the density of the direction.
        if path[0].is_infinite_light(scene) {
            if n_walk > 0 {
                let v1 = &mut path[1];
                v1.pdf_fwd = les.pdf_pos;
                if v1.is_on_surface() {
                    v1.pdf_fwd *= ray.d.dot(v1.ng).abs();
                }
            }
            path[0].pdf_fwd = infinite_light_density(scene, ray.d);
        }
    }

    /// Extends `path` (whose last vertex the ray leaves) by at most `max_vertices` vertices;
    /// `pdf` is the density per unit solid angle of the ray's direction. The ray starts in
    /// the last vertex's medium on its side. Returns how many vertices were added. No Russian
    /// roulette, as in pbrt-v4's bdpt.
    #[allow(clippy::too_many_arguments)]
    fn random_walk<S: SampleSource + ?Sized>(
        &mut self,
        mut ray: Ray,
        sampler: &mut S,
        mut beta: SampledSpectrum,
        pdf: f32,
        max_vertices: usize,
        mode: TransportMode,
        path: &mut Vec<Vertex>,
    ) -> usize {
        if max_vertices == 0 {
            return 0;
        }
        let scene = self.scene;
        let mut bounces = 0;
        let mut any_non_specular = false;
        let mut pdf_fwd = pdf;
        let mut r = path.last().map_or(SampledSpectrum::ONE, |v| v.r);
        let mut medium = path.last().and_then(|v| v.medium_towards(scene, ray.d));
        loop {
            if beta == SampledSpectrum::ZERO || !beta.is_finite() {
                break;
            }
            let hit = scene.intersect(&ray);
            if let Some(m) = medium {
                let t_max = hit.as_ref().map_or(f32::INFINITY, |h| h.si.t);
                let mut w = WalkState {
                    beta: &mut beta,
                    r: &mut r,
                    pdf_fwd: &mut pdf_fwd,
                    bounces: &mut bounces,
                };
                match self.cross_medium(&ray, t_max, m, sampler, &mut w, max_vertices, path) {
                    Crossing::Ended => break,
                    Crossing::Scattered(next) => {
                        ray = next;
                        any_non_specular = true;
                        continue;
                    }
                    Crossing::Passed => {}
                }
            }
            let Some(hit) = hit else {
                // Left the scene: the camera subpath ends on the environment.
                if mode == TransportMode::Radiance {
                    let mut v =
                        Vertex::endpoint(Kind::Escaped, ray.o + ray.d, Vec3::ZERO, -ray.d, beta);
                    v.pdf_fwd = pdf_fwd;
                    v.r = r;
                    path.push(v);
                    bounces += 1;
                }
                break;
            };
            let si = &hit.si;
            let Some((mut bsdf, disperses)) = bsdf_at(scene, &hit, self.lambda.as_ref()) else {
                // An interface between media: the ray goes on, perhaps in another medium.
                medium = medium_after(scene, &hit, ray.d, medium);
                ray = si.spawn_ray(ray.d);
                continue;
            };
            keep_hero_only(&mut self.lambda, disperses);
            if self.regularize && any_non_specular {
                bsdf.bxdf.regularize();
            }
            let prev = *path.last().expect("a subpath starts at its endpoint");
            let mut v = Vertex {
                kind: Kind::Surface,
                p: si.p,
                p_error: si.p_error,
                ng: si.n,
                ns: si.shading.n,
                wo: si.wo,
                uv: si.uv,
                prim: hit.prim,
                bsdf: Some(bsdf),
                phase: crate::medium::HgPhaseFunction { g: 0.0 },
                medium,
                beta,
                r,
                delta: false,
                pdf_fwd: 0.0,
                pdf_rev: 0.0,
            };
            v.pdf_fwd = prev.convert_density(pdf_fwd, &v, scene);
            path.push(v);
            bounces += 1;
            if bounces >= max_vertices {
                break;
            }
            let uc = sampler.get_1d();
            let Some(bs) = bsdf.sample_f(si.wo, uc, sampler.get_2d(), mode) else {
                break;
            };
            pdf_fwd = if bs.pdf_is_proportional {
                bsdf.pdf(si.wo, bs.wi, mode)
            } else {
                bs.pdf
            };
            any_non_specular |= !bs.is_specular();
            beta *= bs.f * (bs.wi.dot(si.shading.n).abs() / bs.pdf);
            medium = medium_after(scene, &hit, bs.wi, medium);
            ray = si.spawn_ray(bs.wi);
            // The density of the reverse direction, turned into one per unit area at the
            // previous vertex.
            let mut pdf_rev = bsdf.pdf(bs.wi, si.wo, mode.flip());
            let n = path.len();
            if bs.is_specular() {
                path[n - 1].delta = true;
                pdf_rev = 0.0;
                pdf_fwd = 0.0;
            }
            let (head, tail) = path.split_at_mut(n - 1);
            head[n - 2].pdf_rev = tail[0].convert_density(pdf_rev, &head[n - 2], scene);
        }
        bounces
    }

    /// Delta tracking along `ray` in `medium` up to `t_max` (pbrt-v4's `RandomWalk` in a
    /// medium), at the hero lane h: a scattering collision adds a medium vertex with
    /// β ← β·T_maj·σ_s / (T_maj[h]·σ_s[h]) and samples the phase function; a null collision
    /// weights β by T_maj·σ_n / (T_maj[h]·σ_n[h]); reaching the end, by T_maj / T_maj[h].
    /// The lane ratios `r` take the same factors (each is a lane's density over the hero's).
    #[allow(clippy::too_many_arguments)]
    fn cross_medium<S: SampleSource + ?Sized>(
        &self,
        ray: &Ray,
        t_max: f32,
        medium: u32,
        sampler: &mut S,
        w: &mut WalkState<'_>,
        max_vertices: usize,
        path: &mut Vec<Vertex>,
    ) -> Crossing {
        let scene = self.scene;
        let h = self.hero;
        let mut rng = seeded_rng(sampler.get_1d(), sampler.get_1d());
        let u = sampler.get_1d();
        let mut ended = false;
        let mut scattered = None;
        let wo = -normalize(ray.d);
        let t_maj = sample_t_maj(
            scene.medium(medium),
            ray.o,
            ray.d,
            t_max,
            u,
            &mut rng,
            self.lambda.as_ref(),
            h,
            |p, mp: &MediumProperties, sigma_maj, t_maj, rng| {
                match collision(mp, sigma_maj, h, rng.uniform()) {
                    Collision::Absorb => {
                        ended = true;
                        false
                    }
                    Collision::Scatter => {
                        let weight = t_maj * mp.sigma_s / (t_maj[h] * mp.sigma_s[h]);
                        *w.beta *= weight;
                        *w.r *= weight;
                        let prev = path.last().expect("a subpath starts at its endpoint");
                        let mut v =
                            Vertex::endpoint(Kind::Medium, p, Vec3::ZERO, Vec3::ZERO, *w.beta);
                        v.wo = wo;
                        v.phase = mp.phase;
                        v.medium = Some(medium);
                        v.r = *w.r;
                        v.pdf_fwd = prev.convert_density(*w.pdf_fwd, &v, scene);
                        path.push(v);
                        *w.bounces += 1;
                        if *w.bounces >= max_vertices || !w.beta.is_finite() {
                            ended = true;
                            return false;
                        }
                        let Some(ps) = mp.phase.sample(wo, sampler.get_2d()) else {
                            ended = true;
                            return false;
                        };
                        *w.pdf_fwd = ps.pdf;
                        *w.beta *= ps.p / ps.pdf;
                        // The phase function is symmetric: the reverse direction's density is
                        // the same, turned into one per unit area at the previous vertex.
                        let n = path.len();
                        let (head, tail) = path.split_at_mut(n - 1);
                        head[n - 2].pdf_rev = tail[0].convert_density(ps.pdf, &head[n - 2], scene);
                        scattered = Some(Ray::new(p, ps.wi).at_time(ray.time));
                        false
                    }
                    Collision::Null => {
                        let sigma_n =
                            (sigma_maj - mp.sigma_a - mp.sigma_s).max(SampledSpectrum::ZERO);
                        let pdf = t_maj[h] * sigma_n[h];
                        if pdf == 0.0 {
                            *w.beta = SampledSpectrum::ZERO;
                        } else {
                            *w.beta *= t_maj * sigma_n / pdf;
                            *w.r *= t_maj * sigma_n / pdf;
                        }
                        *w.beta != SampledSpectrum::ZERO && w.beta.is_finite()
                    }
                }
            },
        );
        if let Some(next) = scattered {
            return Crossing::Scattered(next);
        }
        if ended || *w.beta == SampledSpectrum::ZERO {
            return Crossing::Ended;
        }
        // T_maj / T_maj[h]: the hero's transmittance was the probability of getting here.
        let weight = t_maj / t_maj[h];
        *w.beta *= weight;
        *w.r *= weight;
        if w.beta.is_finite() && w.r.is_finite() {
            Crossing::Passed
        } else {
            Crossing::Ended
        }
    }

    /// The weight of every contribution: [`HERO_ONLY`] once a dispersive surface kept only
    /// the hero wavelength, else 1.
    pub fn spectral_weight(&self) -> SampledSpectrum {
        if self.lambda.is_some_and(|w| w.secondary_terminated()) {
            HERO_ONLY
        } else {
            SampledSpectrum::ONE
        }
    }
}

/// The running state of a walk that a medium crossing updates.
struct WalkState<'a> {
    /// The throughput.
    beta: &'a mut SampledSpectrum,
    /// The lanes' density ratios ([`Vertex::r`]).
    r: &'a mut SampledSpectrum,
    /// Density per unit solid angle of the current ray's direction.
    pdf_fwd: &'a mut f32,
    /// Vertices added so far.
    bounces: &'a mut usize,
}

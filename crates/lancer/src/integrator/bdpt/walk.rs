//! The two subpaths of a bidirectional sample (pbrt-v4's `GenerateCameraSubpath`,
//! `GenerateLightSubpath` and `RandomWalk`): each vertex records its throughput and the
//! densities, per unit area, with which its own subpath reached it (`pdf_fwd`) and with which
//! the other direction would have (`pdf_rev`, filled in as the next vertex is sampled).

use super::super::{bsdf_at, keep_hero_only};
use super::vertex::{Kind, Vertex, infinite_light_density};
use crate::material::TransportMode;
use crate::math::{SampledSpectrum, Vec3};
use crate::ray::Ray;
use crate::sampling::SampleSource;
use crate::scene::Scene;
use crate::spectrum::hero::HERO_ONLY;
use crate::spectrum::sampled::SampledWavelengths;

/// What both subpaths share as they are traced.
pub(super) struct Walk<'a> {
    /// The scene.
    pub scene: &'a Scene,
    /// The sample's wavelengths (spectral mode), which a dispersive surface terminates (every
    /// contribution is then weighted by [`HERO_ONLY`]).
    pub lambda: Option<SampledWavelengths>,
    /// Roughen near-specular lobes after a non-specular bounce (pbrt's `regularize`).
    pub regularize: bool,
}

impl Walk<'_> {
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
        path.push(Vertex::endpoint(
            Kind::Camera,
            ray.o,
            Vec3::ZERO,
            Vec3::ZERO,
            beta,
        ));
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
        let le = scene.light_radiance(light, self.lambda.as_ref(), les.l, les.factor, -les.w);
        if le == SampledSpectrum::ZERO {
            return;
        }
        // The first vertex: density p_l·p_pos of its position.
        let p = p_choice * les.pdf_pos;
        let mut v = Vertex::endpoint(Kind::Light(light as u32), les.p, les.p_error, les.n, le);
        v.pdf_fwd = p;
        path.push(v);
        // β = Le·|cos θ| / (p_l·p_pos·p_dir).
        let beta = le * (les.abs_cos() / (p * les.pdf_dir));
        let ray = les.ray();
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
    /// `pdf` is the density per unit solid angle of the ray's direction. Returns how many
    /// were added. No Russian roulette, as in pbrt-v4's bdpt.
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
        loop {
            if beta == SampledSpectrum::ZERO || !beta.is_finite() {
                break;
            }
            let Some(hit) = scene.intersect(&ray) else {
                // Left the scene: the camera subpath ends on the environment.
                if mode == TransportMode::Radiance {
                    let mut v =
                        Vertex::endpoint(Kind::Escaped, ray.o + ray.d, Vec3::ZERO, -ray.d, beta);
                    v.pdf_fwd = pdf_fwd;
                    path.push(v);
                    bounces += 1;
                }
                break;
            };
            let si = &hit.si;
            let Some((mut bsdf, disperses)) = bsdf_at(scene, &hit, self.lambda.as_ref()) else {
                // An interface between media: the ray goes on.
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
                beta,
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

//! pbrt-v4's `gbuffer` film: besides colour, per-pixel auxiliary channels of the surface first
//! seen through each pixel (a denoiser's inputs).
//!
//! The channels, as pbrt-v4 names them: `R G B`, `Albedo.{R,G,B}`, `P.{X,Y,Z}`, `dzdx`,
//! `dzdy`, `N.{X,Y,Z}`, `Ns.{X,Y,Z}`, `u`, `v`, `Variance.{R,G,B}`,
//! `RelativeVariance.{R,G,B}`; positions and normals in camera space unless the film's
//! `"string coordinatesystem"` is `"world"`.
//!
//! As pbrt-v4's `GBufferFilm::AddSample`: each camera sample whose ray meets a surface (the
//! first one with a BSDF: `interface` surfaces are passed through) adds, with its filter
//! weight w, w·P, w·N, w·Ns, w·uv, w·∂z/∂x, w·∂z/∂y and w·albedo to its pixel, and its colour
//! to a per-channel running variance (Welford, unweighted). When written, P, uv and the depth
//! slopes are divided by the weight of those samples, the albedo by the weight of every
//! sample (as pbrt-v4 does), the normals are normalised, and the slopes are written as
//! absolute values. The surface data is gathered by tracing the camera ray once more, apart
//! from the integrator, and draws no sampler dimension, so the colour channels are the very
//! ones an `rgb` film gets; the ordinary render loop never sees any of this.

use crate::film::PixelBounds;
use crate::integrator::bsdf_at;
use crate::material::TransportMode;
use crate::math::{Rgb, SampledSpectrum, Transform, Vec2, Vec3, lanes_rgb};
use crate::ray::Ray;
use crate::scene::Scene;

pub mod write;
pub use write::{GbufferHeader, encode_gbuffer_exr, write_gbuffer_exr};

/// What a `gbuffer` film asks for beyond colour.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct GbufferDesc {
    /// Positions and normals in world space (`"world"`) rather than camera space (`"camera"`,
    /// pbrt-v4's default).
    pub world_space: bool,
}

/// The channel names pbrt-v4's g-buffer film writes, in its order.
pub const CHANNELS: [&str; 25] = [
    "R",
    "G",
    "B",
    "Albedo.R",
    "Albedo.G",
    "Albedo.B",
    "P.X",
    "P.Y",
    "P.Z",
    "dzdx",
    "dzdy",
    "N.X",
    "N.Y",
    "N.Z",
    "Ns.X",
    "Ns.Y",
    "Ns.Z",
    "u",
    "v",
    "Variance.R",
    "Variance.G",
    "Variance.B",
    "RelativeVariance.R",
    "RelativeVariance.G",
    "RelativeVariance.B",
];

/// The first surface seen by a camera ray, as pbrt-v4's `VisibleSurface`: world space.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct VisibleSurface {
    /// The point.
    pub p: Vec3,
    /// Geometric normal, turned towards the camera.
    pub n: Vec3,
    /// Shading normal, turned towards the camera.
    pub ns: Vec3,
    /// Surface parameterisation.
    pub uv: Vec2,
    /// Change of `p` for one pixel step in x (the camera ray's differentials, scaled as
    /// pbrt-v4 scales them: by max(1/8, 1/√spp)).
    pub dpdx: Vec3,
    /// Change of `p` for one pixel step in y.
    pub dpdy: Vec3,
    /// The BSDF's directional albedo towards the camera (linear RGB).
    pub albedo: Rgb,
}

/// pbrt-v4's fixed sample pattern for a BSDF's albedo (`PathIntegrator::Li`, 16 samples).
const RHO_UC: [f32; 16] = [
    0.757_416_4,
    0.378_708_2,
    0.708_348_7,
    0.189_354_1,
    0.914_936_3,
    0.354_174_35,
    0.599_085_8,
    0.094_677_03,
    0.857_872_5,
    0.457_468_12,
    0.686_759,
    0.177_087_16,
    0.967_451_8,
    0.299_542_9,
    0.508_320_1,
    0.047_338_516,
];
/// The 2D half of pbrt-v4's albedo sample pattern.
const RHO_U: [[f32; 2]; 16] = [
    [0.855985, 0.570367],
    [0.381823, 0.851844],
    [0.285328, 0.764262],
    [0.733380, 0.114073],
    [0.542663, 0.344465],
    [0.127274, 0.414848],
    [0.964700, 0.947162],
    [0.594089, 0.643463],
    [0.095109, 0.170369],
    [0.825444, 0.263359],
    [0.429467, 0.454469],
    [0.244460, 0.816459],
    [0.756135, 0.731258],
    [0.516165, 0.152852],
    [0.180888, 0.214174],
    [0.898579, 0.503897],
];

/// The camera's rays one pixel to the right and one pixel down of a camera sample, for the
/// visible surface's footprint.
#[derive(Clone, Copy, Debug)]
pub struct RayDifferentials {
    /// The ray through the film point one pixel to the right.
    pub rx: Ray,
    /// The ray through the film point one pixel down.
    pub ry: Ray,
}

impl RayDifferentials {
    /// The offset rays of `ray` (through `p_film`, lens point `p_lens`), moved towards it by
    /// `scale` as pbrt-v4's `ScaleDifferentials` does: o' = o + (oₓ − o)·s, d' = d + (dₓ − d)·s.
    pub fn of(
        scene: &Scene,
        ray: &Ray,
        p_film: Vec2,
        p_lens: Vec2,
        scale: f32,
    ) -> Option<RayDifferentials> {
        let shifted = |dp: Vec2| {
            let r = scene.camera.generate_ray(p_film + dp, p_lens)?.ray;
            Some(Ray::new(
                ray.o + (r.o - ray.o) * scale,
                ray.d + (r.d - ray.d) * scale,
            ))
        };
        Some(RayDifferentials {
            rx: shifted(Vec2::new(1.0, 0.0))?,
            ry: shifted(Vec2::new(0.0, 1.0))?,
        })
    }
}

/// pbrt-v4's scale of camera ray differentials: max(1/8, 1/√spp).
pub fn differential_scale(spp: u32) -> f32 {
    (1.0 / (spp.max(1) as f32).sqrt()).max(0.125)
}

/// Where a ray meets the plane through `p` with normal `n`, minus `p` (pbrt-v4's
/// `ComputeDifferentials`: t = (n·p − n·o) / (n·d)); zero when the ray runs along the plane.
fn plane_offset(p: Vec3, n: Vec3, r: &Ray) -> Vec3 {
    let nd = n.dot(r.d);
    if nd == 0.0 {
        return Vec3::ZERO;
    }
    let t = (n.dot(p) - n.dot(r.o)) / nd;
    if !t.is_finite() {
        return Vec3::ZERO;
    }
    r.o + r.d * t - p
}

/// The first surface `ray` meets that has a BSDF (pbrt-v4 skips `interface` surfaces), with
/// its footprint from `diff` and its albedo, or `None` if the ray escapes.
pub fn visible_surface(
    scene: &Scene,
    ray: &Ray,
    diff: Option<&RayDifferentials>,
) -> Option<VisibleSurface> {
    let mut r = *ray;
    // A bounded number of pass-through surfaces, as a guard against a ray stuck in place.
    for _ in 0..256 {
        let hit = scene.intersect(&r)?;
        let si = &hit.si;
        let Some((bsdf, _)) = bsdf_at(scene, &hit, None) else {
            r = si.spawn_ray(r.d);
            continue;
        };
        // albedo ≈ (1/16) Σ f(wo, wᵢ)·|cos θᵢ| / pdf(wᵢ) over pbrt-v4's fixed samples.
        let mut rho = SampledSpectrum::ZERO;
        for (uc, u) in RHO_UC.iter().zip(RHO_U) {
            if let Some(s) =
                bsdf.sample_f(si.wo, *uc, Vec2::new(u[0], u[1]), TransportMode::Radiance)
                && s.pdf > 0.0
            {
                rho += s.f * (s.wi.dot(si.shading.n).abs() / s.pdf);
            }
        }
        let face = |n: Vec3| if n.dot(si.wo) < 0.0 { -n } else { n };
        let (dpdx, dpdy) = match diff {
            Some(d) => (
                plane_offset(si.p, si.n, &d.rx),
                plane_offset(si.p, si.n, &d.ry),
            ),
            None => (Vec3::ZERO, Vec3::ZERO),
        };
        return Some(VisibleSurface {
            p: si.p,
            n: face(si.n),
            ns: face(si.shading.n),
            uv: si.uv,
            dpdx,
            dpdy,
            albedo: lanes_rgb(rho * (1.0 / RHO_UC.len() as f32)),
        });
    }
    None
}

/// A running mean and sum of squared deviations (Welford's update, as pbrt-v4's
/// `VarianceEstimator`).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Variance {
    /// Values added.
    pub n: u64,
    /// Their mean.
    pub mean: f64,
    /// Σ (x − mean)².
    pub s: f64,
}

impl Variance {
    /// Adds x: δ = x − mean, mean += δ/n, S += δ·(x − mean').
    pub fn add(&mut self, x: f64) {
        self.n += 1;
        let d = x - self.mean;
        self.mean += d / self.n as f64;
        self.s += d * (x - self.mean);
    }

    /// Adds another estimator's values (Chan et al.'s pairwise update, as pbrt-v4's `Merge`).
    pub fn merge(&mut self, o: &Variance) {
        if o.n == 0 {
            return;
        }
        let (n, m) = (self.n as f64, o.n as f64);
        self.s += o.s + (o.mean - self.mean).powi(2) * n * m / (n + m);
        self.mean = (n * self.mean + m * o.mean) / (n + m);
        self.n += o.n;
    }

    /// The sample variance S / (n − 1) (0 for fewer than two values).
    pub fn variance(&self) -> f64 {
        if self.n > 1 {
            self.s / (self.n - 1) as f64
        } else {
            0.0
        }
    }

    /// Variance / mean (0 with no value or a zero mean).
    pub fn relative(&self) -> f64 {
        if self.n < 1 || self.mean == 0.0 {
            0.0
        } else {
            self.variance() / self.mean
        }
    }
}

/// One pixel's g-buffer sums (the colour itself stays in [`crate::film::PixelSum`]).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct GPixel {
    /// Σ w over every sample (the albedo's divisor, as in pbrt-v4).
    pub weight: f64,
    /// Σ w over the samples that saw a surface.
    pub g_weight: f64,
    /// Σ w·P.
    pub p: [f64; 3],
    /// Σ w·N.
    pub n: [f64; 3],
    /// Σ w·Ns.
    pub ns: [f64; 3],
    /// Σ w·(u, v).
    pub uv: [f64; 2],
    /// Σ w·∂z/∂x, Σ w·∂z/∂y.
    pub dz: [f64; 2],
    /// Σ w·albedo.
    pub albedo: [f64; 3],
    /// Running variance of each colour channel over the samples that saw a surface.
    pub variance: [Variance; 3],
}

impl GPixel {
    /// Adds a sample of film colour `rgb` (after the NaN and `maxcomponentvalue` rules), filter
    /// weight `w`, and its visible surface, already in output space.
    pub fn add(&mut self, rgb: Rgb, w: f32, vs: Option<&VisibleSurface>) {
        let w = w as f64;
        self.weight += w;
        let Some(v) = vs else { return };
        self.g_weight += w;
        for c in 0..3 {
            self.variance[c].add(rgb[c] as f64);
            self.p[c] += w * v.p[c] as f64;
            self.n[c] += w * v.n[c] as f64;
            self.ns[c] += w * v.ns[c] as f64;
            self.albedo[c] += w * v.albedo[c] as f64;
        }
        self.uv[0] += w * v.uv.x as f64;
        self.uv[1] += w * v.uv.y as f64;
        self.dz[0] += w * v.dpdx.z as f64;
        self.dz[1] += w * v.dpdy.z as f64;
    }

    /// Adds another pixel's sums.
    pub fn merge(&mut self, o: &GPixel) {
        self.weight += o.weight;
        self.g_weight += o.g_weight;
        for c in 0..3 {
            self.p[c] += o.p[c];
            self.n[c] += o.n[c];
            self.ns[c] += o.ns[c];
            self.albedo[c] += o.albedo[c];
            self.variance[c].merge(&o.variance[c]);
        }
        for i in 0..2 {
            self.uv[i] += o.uv[i];
            self.dz[i] += o.dz[i];
        }
    }

    /// The auxiliary channels of [`CHANNELS`] after R, G, B (22 values, in order).
    pub fn channels(&self) -> [f32; 22] {
        let div = |s: f64, w: f64| if w != 0.0 { (s / w) as f32 } else { 0.0 };
        let unit = |v: [f64; 3]| {
            let l = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
            if l > 0.0 {
                v.map(|x| (x / l) as f32)
            } else {
                [0.0; 3]
            }
        };
        let (n, ns) = (unit(self.n), unit(self.ns));
        let g = self.g_weight;
        let var = self.variance.map(|v| v.variance() as f32);
        let rel = self.variance.map(|v| v.relative() as f32);
        [
            div(self.albedo[0], self.weight),
            div(self.albedo[1], self.weight),
            div(self.albedo[2], self.weight),
            div(self.p[0], g),
            div(self.p[1], g),
            div(self.p[2], g),
            div(self.dz[0], g).abs(),
            div(self.dz[1], g).abs(),
            n[0],
            n[1],
            n[2],
            ns[0],
            ns[1],
            ns[2],
            div(self.uv[0], g),
            div(self.uv[1], g),
            var[0],
            var[1],
            var[2],
            rel[0],
            rel[1],
            rel[2],
        ]
    }
}

/// How a render fills a g-buffer: the space its positions and normals are written in.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GbufferConfig {
    /// World space → output space (camera space by default, else the identity).
    pub output_from_world: Transform,
    /// Samples per pixel of the whole render (the ray differentials' scale depends on it).
    pub spp: u32,
}

impl GbufferConfig {
    /// The configuration `desc` asks for, with `camera_from_world` the camera's transform.
    pub fn new(desc: GbufferDesc, camera_from_world: Transform, spp: u32) -> GbufferConfig {
        GbufferConfig {
            output_from_world: if desc.world_space {
                Transform::IDENTITY
            } else {
                camera_from_world
            },
            spp,
        }
    }

    /// `v` moved to output space.
    pub fn to_output(&self, v: &VisibleSurface) -> VisibleSurface {
        let t = &self.output_from_world;
        VisibleSurface {
            p: t.point(v.p),
            n: t.normal(v.n),
            ns: t.normal(v.ns),
            dpdx: t.vector(v.dpdx),
            dpdy: t.vector(v.dpdy),
            ..*v
        }
    }
}

/// A film's g-buffer: the configuration and one [`GPixel`] per pixel of the film's bounds.
#[derive(Clone, Debug, PartialEq)]
pub struct GbufferFilm {
    /// How it is filled.
    pub config: GbufferConfig,
    /// Sums, row-major over the film's bounds.
    pub pixels: Vec<GPixel>,
}

impl GbufferFilm {
    /// An empty g-buffer over `bounds`.
    pub fn new(config: GbufferConfig, bounds: &PixelBounds) -> GbufferFilm {
        GbufferFilm {
            config,
            pixels: vec![GPixel::default(); bounds.area() as usize],
        }
    }

    /// Adds a tile's sums (pixels of `tile`, row-major) into the g-buffer over `bounds`.
    pub fn merge_tile(&mut self, bounds: &PixelBounds, tile: &PixelBounds, sums: &[GPixel]) {
        let w = tile.width() as usize;
        let fw = bounds.width() as usize;
        let t = tile.intersect(bounds);
        for y in t.y0..t.y1 {
            for x in t.x0..t.x1 {
                let s = &sums[(y - tile.y0) as usize * w + (x - tile.x0) as usize];
                let i = (y - bounds.y0) as usize * fw + (x - bounds.x0) as usize;
                self.pixels[i].merge(s);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn variance_matches_the_sample_variance_and_merges_exactly_enough() {
        // 1, 2, 4, 7: mean 3.5, Σ(x − 3.5)² = 6.25 + 2.25 + 0.25 + 12.25 = 21, variance 7.
        let mut a = Variance::default();
        for x in [1.0, 2.0, 4.0, 7.0] {
            a.add(x);
        }
        assert_eq!((a.n, a.mean), (4, 3.5));
        assert!((a.variance() - 7.0).abs() < 1e-12);
        assert!((a.relative() - 2.0).abs() < 1e-12);
        let (mut b, mut c) = (Variance::default(), Variance::default());
        b.add(1.0);
        b.add(2.0);
        c.add(4.0);
        c.add(7.0);
        b.merge(&c);
        assert!((b.mean - 3.5).abs() < 1e-12 && (b.variance() - 7.0).abs() < 1e-12);
        // One value: no variance; a zero mean: no relative variance.
        let mut one = Variance::default();
        one.add(5.0);
        assert_eq!((one.variance(), Variance::default().relative()), (0.0, 0.0));
    }

    #[test]
    fn pixel_channels_average_with_filter_weights() {
        let vs = |z: f32, n: Vec3, u: f32| VisibleSurface {
            p: Vec3::new(0.0, 0.0, z),
            n,
            ns: n,
            uv: Vec2::new(u, 0.5),
            dpdx: Vec3::new(0.0, 0.0, -0.5),
            dpdy: Vec3::ZERO,
            albedo: Rgb::splat(0.6),
        };
        let mut p = GPixel::default();
        // Weights 3 and 1: P.Z = (3·2 + 1·6)/4 = 3, u = (3·0 + 1·1)/4 = 0.25.
        p.add(Rgb::ONE, 3.0, Some(&vs(2.0, Vec3::Z, 0.0)));
        p.add(Rgb::ONE, 1.0, Some(&vs(6.0, Vec3::X, 1.0)));
        // A sample that saw nothing: only the albedo's divisor grows.
        p.add(Rgb::ZERO, 2.0, None);
        let c = p.channels();
        // Albedo: Σw·a / Σw over every sample = 0.6·4/6.
        assert!((c[0] - 0.4).abs() < 1e-6);
        assert_eq!((c[3], c[4], c[5]), (0.0, 0.0, 3.0));
        // |Σw·∂z/∂x| / Σw = 0.5, written as an absolute value.
        assert_eq!((c[6], c[7]), (0.5, 0.0));
        // N = normalise(3·z + 1·x) = (1, 0, 3)/√10.
        let s = 10f32.sqrt();
        assert!((c[8] - 1.0 / s).abs() < 1e-6 && c[9] == 0.0 && (c[10] - 3.0 / s).abs() < 1e-6);
        assert_eq!((c[14], c[15]), (0.25, 0.5));
        // Two colours of 1, unweighted: no variance.
        assert_eq!((c[16], c[19]), (0.0, 0.0));
    }

    #[test]
    fn differentials_scale_as_pbrt() {
        assert_eq!(differential_scale(16), 0.25);
        assert_eq!(differential_scale(1024), 0.125);
        assert_eq!(differential_scale(1), 1.0);
        // A ray from the origin along (0.1, 0, 1) meets the plane z = 2 at x = 0.2.
        let r = Ray::new(Vec3::ZERO, Vec3::new(0.1, 0.0, 1.0));
        let d = plane_offset(Vec3::new(0.0, 0.0, 2.0), -Vec3::Z, &r);
        assert!((d - Vec3::new(0.2, 0.0, 0.0)).length() < 1e-6);
        // Parallel to the plane: no offset.
        let r = Ray::new(Vec3::ZERO, Vec3::X);
        assert_eq!(
            plane_offset(Vec3::new(0.0, 0.0, 2.0), Vec3::Z, &r),
            Vec3::ZERO
        );
    }
}

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
//! in the sensor's RGB ([`variance_rgb`]: XYZ for the default CIE 1931 sensor, not the output
//! RGB) to a per-channel running variance (Welford, unweighted). When written, P, uv and the depth
//! slopes are divided by the weight of those samples, the albedo by the weight of every
//! sample (as pbrt-v4 does), the normals are normalised, and the slopes are written as
//! absolute values. The surface data is gathered by tracing the camera ray once more, apart
//! from the integrator, and draws no sampler dimension, so the colour channels are the very
//! ones an `rgb` film gets; the ordinary render loop never sees any of this.

pub use crate::film::gsums::{
    CHANNELS, GPixel, GbufferConfig, GbufferDesc, GbufferFilm, Variance, VisibleSurface,
};
use crate::integrator::bsdf_at;
use crate::material::TransportMode;
use crate::math::{Rgb, SampledSpectrum, Vec2, Vec3, lanes_rgb};
use crate::ray::Ray;
use crate::scene::Scene;

pub mod write;
pub use write::{GbufferHeader, encode_gbuffer_exr, write_gbuffer_exr};

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
            let r = scene.camera().generate_ray(p_film + dp, p_lens)?.ray;
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

/// The colour whose variance pbrt-v4's `GBufferFilm` keeps: a sample's sensor RGB
/// (`PixelSensor::ToSensorRGB`; XYZ for the default CIE 1931 sensor), not its output RGB, with
/// `maxcomponentvalue` applied there (the colour scaled so that its largest component is at
/// most `max_component_value`). `output` is the sample's output colour before lancer's own
/// clamp, which it takes back to the sensor's space by the inverse of pbrt-v4's
/// `outputRGBFromSensorRGB`; a colour that is not finite counts as black (as in the sums).
pub fn variance_rgb(scene: &Scene, output: Rgb, max_component_value: f32) -> Rgb {
    if !output.is_finite() {
        return Rgb::ZERO;
    }
    let sensor = match scene.film_response() {
        Some(r) => r.sensor_rgb(output),
        None => {
            // The plain CIE 1931 film into sRGB: the sensor's RGB is XYZ.
            static XYZ_FROM_SRGB: std::sync::OnceLock<glam::Mat3> = std::sync::OnceLock::new();
            let m = XYZ_FROM_SRGB
                .get_or_init(|| crate::spectrum::ColorSpace::Srgb.rgb_to_xyz().as_mat3());
            (*m * glam::Vec3::from(output)).into()
        }
    };
    let m = sensor.max_element();
    if m > max_component_value {
        sensor * (max_component_value / m)
    } else {
        sensor
    }
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

/// Perfectly specular bounces the denoiser's visible surface follows before it gives up.
const MAX_SPECULAR_BOUNCES: usize = 16;

/// The first surface `ray` meets that has a BSDF (pbrt-v4 skips `interface` surfaces), with
/// its footprint from `diff` and its albedo, or `None` if the ray escapes.
///
/// With `follow_specular` (the denoiser's auxiliary images, as Open Image Denoise's
/// documentation asks), a perfectly specular surface (mirror, smooth glass or metal) is
/// passed through along its sampled direction (transmission preferred: u = 0.999), and the
/// surface found after it is returned, its albedo times the specular bounces' throughput
/// f·|cos θ|/pdf (each clamped to [0, 1]).
pub fn visible_surface(
    scene: &Scene,
    ray: &Ray,
    diff: Option<&RayDifferentials>,
    follow_specular: bool,
) -> Option<VisibleSurface> {
    let mut r = *ray;
    let mut throughput = SampledSpectrum::ONE;
    let mut specular = 0;
    // A bounded number of pass-through surfaces, as a guard against a ray stuck in place.
    for _ in 0..256 {
        let hit = scene.intersect(&r)?;
        let si = &hit.si;
        let Some((bsdf, _)) = bsdf_at(scene, &hit, None) else {
            r = si.spawn_ray(r.d);
            continue;
        };
        if follow_specular && !bsdf.flags().is_non_specular() && specular < MAX_SPECULAR_BOUNCES {
            let s = bsdf.sample_f(si.wo, 0.999, Vec2::new(0.5, 0.5), TransportMode::Radiance)?;
            if s.pdf <= 0.0 {
                return None;
            }
            let t = s.f * (s.wi.dot(si.shading.n).abs() / s.pdf);
            throughput *= t.clamp(SampledSpectrum::ZERO, SampledSpectrum::ONE);
            r = si.spawn_ray(s.wi);
            specular += 1;
            continue;
        }
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
            albedo: lanes_rgb(rho * throughput * (1.0 / RHO_UC.len() as f32)),
        });
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::camera::footprint::differential_scale;
    use crate::math::Rgb;

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

    /// pbrt-v4's variance is of the sensor's RGB, for the plain film XYZ: sRGB red is
    /// XYZ (0.4125, 0.2127, 0.0193), `maxcomponentvalue` scales it there, and a colour that
    /// is not finite is black.
    #[test]
    fn variance_is_of_the_sensors_rgb() {
        let scene = Scene::build(&crate::scene::desc::SceneDesc::default()).expect("a scene");
        assert!(scene.film_response().is_none());
        let xyz = variance_rgb(&scene, Rgb::X, f32::INFINITY);
        let want = Rgb::new(0.412_456_4, 0.212_672_9, 0.019_333_9);
        assert!((xyz - want).abs().max_element() < 1e-5, "{xyz}");
        let clamped = variance_rgb(&scene, Rgb::X, 0.2);
        assert!((clamped - want * (0.2 / want.x)).abs().max_element() < 1e-6);
        assert_eq!(
            variance_rgb(&scene, Rgb::new(f32::NAN, 0.0, 1.0), 1.0),
            Rgb::ZERO
        );
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

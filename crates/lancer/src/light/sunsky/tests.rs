use super::*;
use crate::math::Frame;
use crate::sampling::{hash_u64, u32_to_unit_f32};

fn rand2(i: u64, seed: u64) -> Vec2 {
    let h = hash_u64(&[i, seed]);
    Vec2::new(u32_to_unit_f32(h as u32), u32_to_unit_f32((h >> 32) as u32))
}

/// The reference scene's light: `Rotate -90 1 0 0` (light +z → world +y), sun (−0.45, 0.6,
/// 0.65) in light space, turbidity 3, albedo 0.3.
fn light(params: SunskyParams) -> SunskyLight {
    let t = Transform::rotate(-90.0, Vec3::X).expect("a rotation");
    let scene = SceneSphere {
        centre: Vec3::ZERO,
        radius: 10.0,
    };
    SunskyLight::new(t, &params, scene)
}

fn reference() -> SunskyLight {
    light(SunskyParams::new(Vec3::new(-0.45, 0.6, 0.65)))
}

fn ctx(n: Vec3) -> LightSampleContext {
    LightSampleContext {
        p: Vec3::ZERO,
        n,
        ns: n,
    }
}

/// The world direction of the sun, its disk's edge, and the zenith.
#[test]
fn sun_and_horizon_are_where_the_transform_puts_them() {
    let l = reference();
    let sun_world = crate::math::normalize(Vec3::new(-0.45, 0.65, -0.6));
    assert!(l.le(sun_world).x > 10_000.0, "{}", l.le(sun_world));
    // The disk's rim (half-angle 0.2679°) within 1 %: 1.01 of it off the sun's centre, sky
    // only; 0.99 of it, the sun.
    let rim = model::SUN_HALF_APERTURE as f32;
    let off = |a: f32| Frame::from_z(sun_world).from_local(Vec3::new(a.sin(), 0.0, a.cos()));
    let sky = l.le(off(1.01 * rim));
    assert!(sky.x > 0.0 && sky.x < 100.0, "{sky}");
    assert!(l.le(off(0.99 * rim)).x > 10_000.0);
    // Below the horizon (world −y): nothing.
    assert_eq!(l.le(Vec3::new(0.3, -0.2, 0.5)), Rgb::ZERO);
    assert_eq!(
        l.le_spectral(Vec3::new(0.3, -0.2, 0.5), &wavelengths()),
        SampledSpectrum::ZERO
    );
}

fn wavelengths() -> SampledWavelengths {
    SampledWavelengths::sample_uniform(0.1, 300.0, 800.0)
}

/// Spectral radiance: the model's channels interpolated at each wavelength, zero outside
/// 320–720 nm, the sun added inside its disk and scaled by `sunscale`, the sky by `skyscale`.
#[test]
fn spectral_radiance_interpolates_the_channels() {
    let params = SunskyParams {
        sky_scale: 2.0,
        sun_scale: 0.5,
        scale: 3.0,
        ..SunskyParams::new(Vec3::new(-0.45, 0.6, 0.65))
    };
    let l = light(params);
    let lambda = wavelengths(); // 350, 475, 600, 725 nm
    let zenith = Vec3::Y;
    let got = l.le_spectral(zenith, &lambda);
    let gamma = l.sun_angle(Vec3::Z);
    let sky = |c: usize| model::sky_radiance(&l.sky_spectral[c], 1.0, gamma, gamma.cos()) * 6.0;
    let want = [
        0.25 * sky(0) + 0.75 * sky(1),
        0.125 * sky(3) + 0.875 * sky(4),
        sky(7),
        0.0,
    ];
    for k in 0..4 {
        assert!(
            (got[k] - want[k]).abs() <= 1e-5 * want[k],
            "{k}: {got} vs {want:?}"
        );
    }
    let sun_world = crate::math::normalize(Vec3::new(-0.45, 0.65, -0.6));
    let with_sun = l.le_spectral(sun_world, &lambda);
    let e = model::sun_irradiance(3.0, std::f32::consts::FRAC_PI_2 - l.sun.z.acos());
    let sun_600 = e[7] as f64 * 1.5 / l.sun_solid_angle;
    let sky_600 = model::sky_radiance(&l.sky_spectral[7], l.sun.z, 0.0, 1.0) * 6.0;
    assert!((with_sun[2] as f64 - sun_600 - sky_600 as f64).abs() < 1e-5 * sun_600);
    assert_eq!(with_sun[3], 0.0);
}

/// Every sample's density is the one `pdf_li` gives its direction, and the densities integrate
/// to 1 over the sphere (the sky's part by quadrature, the sun's by its disk).
#[test]
fn densities_agree_and_integrate_to_one() {
    let l = reference();
    let c = ctx(Vec3::Y);
    let mut suns = 0;
    for i in 0..4000 {
        let s = l.sample_li(&c, rand2(i, 1)).expect("a sample");
        let p = l.pdf_li(s.wi);
        assert!((s.pdf - p).abs() <= 1e-5 * p, "{} vs {p}", s.pdf);
        assert_eq!(s.l, l.le(s.wi));
        suns += (s.l.x > 1000.0) as u32;
    }
    // The sun's share of the samples.
    let share = suns as f32 / 4000.0;
    assert!((share - l.p_sun).abs() < 0.03, "{share} vs {}", l.p_sun);
    // Quadrature of the sky's density over the upper hemisphere (the sun's disk is far
    // smaller than a cell): 1 − p_sun.
    let n = 400;
    let mut sum = 0.0f64;
    for iz in 0..n {
        for ip in 0..n {
            let uv = Vec2::new((ip as f32 + 0.5) / n as f32, (iz as f32 + 0.5) / n as f32);
            sum += l.sky_pdf(uv_to_dir(uv)) as f64;
        }
    }
    let sky = sum * 2.0 * std::f64::consts::PI / (n * n) as f64 * (1.0 - l.p_sun as f64);
    assert!(
        (sky + l.p_sun as f64 - 1.0).abs() < 1e-3,
        "{sky} + {}",
        l.p_sun
    );
}

/// Irradiance on an upward patch: light sampling's estimate (Σ L cos θ / p) against
/// quadrature of the sky plus the sun's irradiance E·cos θ_sun, within 1 %.
#[test]
fn sampling_estimates_the_irradiance() {
    let l = reference();
    let n_up = Vec3::Y; // world zenith
    let c = ctx(n_up);
    let n = 100_000;
    let mut est = Rgb::ZERO;
    for i in 0..n {
        if let Some(s) = l.sample_li(&c, rand2(i, 7)) {
            est += s.l * (s.wi.dot(n_up).max(0.0) / s.pdf);
        }
    }
    est /= n as f32;
    let m = 1000;
    let mut sky = Rgb::ZERO;
    for iz in 0..m {
        for ip in 0..m {
            let w = uv_to_dir(Vec2::new(
                (ip as f32 + 0.5) / m as f32,
                (iz as f32 + 0.5) / m as f32,
            ));
            sky += l.sky_rgb_at(w) * w.z;
        }
    }
    let sky = sky * (2.0 * PI / (m * m) as f32);
    let sun = l.sun_rgb * (l.sun_solid_angle as f32 * l.sun.z);
    let want = sky + sun;
    for k in 0..3 {
        assert!(
            (est[k] - want[k]).abs() < 0.01 * want[k],
            "{est} vs {want} (sky {sky})"
        );
    }
}

/// A sun below the horizon leaves the light black (as Mitsuba): no radiance, no samples, no
/// power.
/// Rays leaving the light (`sample_le`) carry its power, `pdf_le` gives each ray's densities,
/// and the directions' density integrates over the sphere to the sky's share (uniform
/// directions miss the sun's tiny disk, which holds the rest, `p_sun`).
#[test]
fn emitted_rays_carry_the_power() {
    use crate::light::testing::{le_dir_integral, le_pdfs_agree, le_power};
    let l = reference();
    let phi = le_power(&l, &[], &[], 1 << 16);
    let want = l.power();
    assert!((phi - want).abs() < 0.02 * want, "{phi} vs {want}");
    le_pdfs_agree(&l, &[], &[], 256, 1e-4);
    let sky = le_dir_integral(&l, Vec3::ZERO, Vec3::ZERO, 1 << 16);
    assert!(
        (sky - (1.0 - l.p_sun)).abs() < 0.02,
        "{sky} vs {}",
        1.0 - l.p_sun
    );
    // Below the horizon nothing leaves.
    let dark = light(SunskyParams::new(Vec3::new(0.3, 0.2, -0.1)));
    assert!(
        dark.sample_le(Vec2::splat(0.5), Vec2::splat(0.5), &[], &[])
            .is_none()
    );
}

#[test]
fn a_sun_below_the_horizon_is_black() {
    let l = light(SunskyParams::new(Vec3::new(0.3, 0.2, -0.1)));
    assert!(l.is_black());
    assert_eq!(l.le(Vec3::Y), Rgb::ZERO);
    assert!(l.sample_li(&ctx(Vec3::Y), Vec2::new(0.3, 0.6)).is_none());
    assert_eq!(l.power(), 0.0);
}

/// The parameters' ranges.
#[test]
fn out_of_range_parameters_are_named() {
    let p = SunskyParams::new(Vec3::Z);
    assert!(p.check().is_none());
    assert!(
        SunskyParams {
            turbidity: 0.5,
            ..p
        }
        .check()
        .unwrap()
        .contains("turbidity")
    );
    assert!(
        SunskyParams { albedo: 1.5, ..p }
            .check()
            .unwrap()
            .contains("albedo")
    );
    assert!(
        SunskyParams {
            sky_scale: -1.0,
            ..p
        }
        .check()
        .unwrap()
        .contains("skyscale")
    );
    assert!(
        SunskyParams {
            sun_direction: Vec3::ZERO,
            ..p
        }
        .check()
        .unwrap()
        .contains("sun")
    );
}

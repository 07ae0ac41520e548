//! The measured BRDF (RGL `.bsdf` files, pbrt-v4's `MeasuredBxDF`) on files written from
//! analytic BRDFs (`common::bsdf_file`): the reader's fields, values against the BRDF a file
//! was made from, chi-square of its sampling, and the white furnace.

use crate::common::bsdf_file::{bsdf_file, ggx_d, ggx_g1};
use crate::common::chi2::*;
use lancer::material::measured::tensor::Tensor;
use lancer::material::{BxDF, MeasuredBxdf, MeasuredData, MeasuredFile, TransportMode};
use lancer::math::{INV_PI, SampledSpectrum, Vec2, Vec3, normalize};
use lancer::sampling::Pcg32;
use lancer::spectrum::sampled::SampledWavelengths;

const RADIANCE: TransportMode = TransportMode::Radiance;
const ALPHA: f32 = 0.5;
const N: usize = 48;
const WAVELENGTHS: [f32; 6] = [360.0, 450.0, 540.0, 630.0, 720.0, 830.0];

/// Number of chi-square tests here, for the Šidák correction.
const N_CHI2_TESTS: usize = 4;

fn theta_nodes() -> Vec<f32> {
    [0.0f32, 10.0, 20.0, 30.0, 40.0, 50.0, 60.0, 70.0, 80.0, 87.0]
        .map(f32::to_radians)
        .to_vec()
}

/// Normal-incidence reflectance, linear in λ (so the file's wavelength nodes represent it
/// exactly): 0.2 at 360 nm to 0.8 at 830 nm.
fn f0(lambda: f32) -> f32 {
    0.2 + 0.6 * (lambda - 360.0) / 470.0
}

/// The analytic GGX conductor: Schlick's F(ωo·ωm) · G₁(ωo) G₁(ωi) D(ωm) / (4 cos θo cos θi).
fn ggx(wo: Vec3, wi: Vec3, lambda: f32) -> f32 {
    if wo.z <= 0.0 || wi.z <= 0.0 {
        return 0.0;
    }
    let wm = normalize(wo + wi);
    let f = f0(lambda) + (1.0 - f0(lambda)) * (1.0 - wo.dot(wm).clamp(0.0, 1.0)).powi(5);
    f * ggx_g1(ALPHA, wo) * ggx_g1(ALPHA, wi) * ggx_d(ALPHA, wm) / (4.0 * wo.z * wi.z)
}

fn ggx_data() -> &'static MeasuredData {
    let bytes = bsdf_file(ALPHA, ggx, N, &theta_nodes(), &WAVELENGTHS);
    MeasuredData::shared(&MeasuredFile::from_bytes(&bytes, "ggx.bsdf").unwrap())
}

/// Lambert with albedo 0.9 (grey), tabulated with GGX(0.5)'s parameterisation.
fn lambert_data() -> &'static MeasuredData {
    let f = |_: Vec3, wi: Vec3, _: f32| if wi.z > 0.0 { 0.9 * INV_PI } else { 0.0 };
    let bytes = bsdf_file(ALPHA, f, N, &theta_nodes(), &WAVELENGTHS);
    MeasuredData::shared(&MeasuredFile::from_bytes(&bytes, "lambert.bsdf").unwrap())
}

fn wavelengths() -> SampledWavelengths {
    let mut l = SampledWavelengths::sample_visible(0.5);
    l.lambda = glam::Vec4::new(400.0, 500.0, 600.0, 700.0);
    l
}

fn spectral(d: &'static MeasuredData) -> BxDF {
    BxDF::Measured(MeasuredBxdf::new(d, Some(&wavelengths())))
}

fn at(theta_deg: f32, phi: f32) -> Vec3 {
    let t = theta_deg.to_radians();
    Vec3::new(t.sin() * phi.cos(), t.sin() * phi.sin(), t.cos())
}

fn random_upper(rng: &mut Pcg32) -> Vec3 {
    let z = rng.uniform();
    let phi = 2.0 * std::f32::consts::PI * rng.uniform();
    let s = (1.0 - z * z).sqrt();
    Vec3::new(s * phi.cos(), s * phi.sin(), z)
}

#[test]
fn the_reader_finds_every_field() {
    let bytes = bsdf_file(ALPHA, ggx, 8, &theta_nodes(), &WAVELENGTHS);
    let t = Tensor::parse(&bytes).unwrap();
    let shape = |n: &str| t.fields[n].shape.clone();
    assert_eq!(shape("vndf"), [1, 10, 8, 8]);
    assert_eq!(shape("spectra"), [1, 10, 6, 8, 8]);
    assert_eq!(shape("ndf"), [8, 8]);
    assert_eq!(t.fields["wavelengths"].to_f32().unwrap(), WAVELENGTHS);
    let d = MeasuredFile::from_bytes(&bytes, "g.bsdf").unwrap();
    assert!(d.isotropic);
    assert_eq!(d.wavelengths, WAVELENGTHS);
    assert_eq!(d.description, "generated");
    assert_eq!(d.name, "g.bsdf");
    assert_eq!(d.vndf.shape, [1, 10, 8, 8]);
    // The same bytes are the same shared description while it is held, and the same built
    // tables; other bytes are others.
    let a = MeasuredFile::shared(&bytes, "a").unwrap();
    assert!(std::sync::Arc::ptr_eq(
        &a,
        &MeasuredFile::shared(&bytes, "b").unwrap()
    ));
    let other =
        MeasuredFile::shared(&bsdf_file(0.3, ggx, 8, &theta_nodes(), &WAVELENGTHS), "a").unwrap();
    assert!(!std::sync::Arc::ptr_eq(&a, &other));
    let built = MeasuredData::shared(&a);
    assert!(std::ptr::eq(built, MeasuredData::shared(&d)));
    assert!(!std::ptr::eq(built, MeasuredData::shared(&other)));
    assert_eq!(built.name, "a");
}

/// Relative errors of f against `want` over random (wo at the θ nodes, wi) pairs: returns
/// the median and the 95th percentile.
fn errors(b: &BxDF, want: impl Fn(Vec3, Vec3) -> SampledSpectrum) -> (f32, f32) {
    let mut rng = Pcg32::new(3, 0);
    let mut e = Vec::new();
    for theta in [10.0, 30.0, 50.0, 70.0] {
        for _ in 0..500 {
            let wo = at(theta, 2.0 * std::f32::consts::PI * rng.uniform());
            let wi = random_upper(&mut rng);
            let (got, w) = (b.f(wo, wi, RADIANCE), want(wo, wi));
            if w.max_element() < 1e-3 {
                continue;
            }
            e.push(((got - w).abs() / w).max_element());
        }
    }
    e.sort_by(f32::total_cmp);
    (e[e.len() / 2], e[e.len() * 95 / 100])
}

#[test]
fn values_match_the_brdf_the_file_was_made_from() {
    let l = wavelengths().lambda.to_array();
    let (med, p95) = errors(&spectral(ggx_data()), |wo, wi| {
        SampledSpectrum::from_array(l.map(|l| ggx(wo, wi, l)))
    });
    println!("GGX: median {med}, 95th percentile {p95}");
    assert!(med < 0.01 && p95 < 0.05, "GGX: median {med}, 95 % {p95}");
    let (med, p95) = errors(&spectral(lambert_data()), |_, _| {
        SampledSpectrum::splat(0.9 * INV_PI)
    });
    println!("Lambert: median {med}, 95th percentile {p95}");
    assert!(
        med < 0.01 && p95 < 0.05,
        "Lambert: median {med}, 95 % {p95}"
    );
    // RGB mode: a grey spectrum reduces to grey.
    let rgb = BxDF::Measured(MeasuredBxdf::new(lambert_data(), None));
    let (med, p95) = errors(&rgb, |_, _| SampledSpectrum::splat(0.9 * INV_PI));
    assert!(
        med < 0.01 && p95 < 0.05,
        "Lambert in RGB: median {med}, 95 % {p95}"
    );
    // Nothing below the surface; wo below is mirrored.
    let b = spectral(ggx_data());
    let (wo, wi) = (at(30.0, 0.3), at(50.0, 2.0));
    assert_eq!(b.f(wo, -wi, RADIANCE), SampledSpectrum::ZERO);
    assert_eq!(b.f(-wo, -wi, RADIANCE), b.f(wo, wi, RADIANCE));
}

fn chi2_sampling(name: &str, b: &BxDF, wo: Vec3, n: usize) {
    let mut rng = Pcg32::new(11, 0);
    let mut obs = vec![0.0; N_BINS];
    let mut ok = 0usize;
    for _ in 0..n {
        let u = Vec2::new(rng.uniform(), rng.uniform());
        if let Some(s) = b.sample_f(wo, rng.uniform(), u, RADIANCE) {
            // The sample's value and density are f and pdf there.
            let (f, pdf) = (b.f(wo, s.wi, RADIANCE), b.pdf(wo, s.wi, RADIANCE));
            assert!(
                ((s.f - f).abs().max_element()) <= 1e-2 * f.max_element().max(1e-2),
                "{name}: sampled f {} vs f {f}",
                s.f
            );
            // Equal up to rounding: recomputing the half vector from wi and inverting the
            // warps is ill-conditioned only where θm → 0 (u_θ = √(2θ/π) and φm degenerate).
            let wm = normalize(wo + s.wi);
            let err = (s.pdf - pdf).abs() / pdf.max(1e-2);
            assert!(
                err < 1e-3 || (err < 0.03 && wm.z > 0.9998),
                "{name}: sampled pdf {} vs pdf {pdf} at ωm {wm}",
                s.pdf
            );
            obs[bin_of(s.wi)] += 1.0;
            ok += 1;
        }
    }
    let integral = integrate_bins(8, |wi| b.pdf(wo, wi, RADIANCE) as f64);
    let total: f64 = integral.iter().sum();
    assert!(total <= 1.0 + 2e-3, "{name}: ∫pdf = {total} > 1");
    let rate = ok as f64 / n as f64;
    assert!(
        (rate - total).abs() < 5.0 * (total * (1.0 - total) / n as f64).sqrt() + 3e-3,
        "{name}: {rate} of samples succeed but ∫pdf = {total}"
    );
    let exp: Vec<f64> = integral.iter().map(|p| p * n as f64).collect();
    let (chi2, dof) = pooled_chi2(&obs, &exp).unwrap_or_else(|e| panic!("{name}: {e}"));
    let p = chi2_survival(chi2, dof);
    println!("{name}: χ² = {chi2:.1}, {dof} dof, p = {p:.3}; ∫pdf = {total:.4}");
    assert!(
        p > sidak(N_CHI2_TESTS),
        "{name}: χ² = {chi2:.1}, {dof} dof, p = {p:.2e}"
    );
}

#[test]
fn sampling_follows_the_density_chi_square() {
    let b = spectral(ggx_data());
    // On a θ node, between two, near grazing; and the Lambert file.
    chi2_sampling("ggx 30°", &b, at(30.0, 0.4), 200_000);
    chi2_sampling("ggx 45°", &b, at(45.0, -2.0), 200_000);
    chi2_sampling("ggx 83°", &b, at(83.0, 1.0), 200_000);
    chi2_sampling(
        "lambert 60°",
        &spectral(lambert_data()),
        at(60.0, 2.5),
        200_000,
    );
}

/// ∫ f cos θi dωi by quadrature over the bins, per lane.
fn albedo(b: &BxDF, wo: Vec3) -> SampledSpectrum {
    let mut a = SampledSpectrum::ZERO;
    for k in 0..4 {
        let per_bin = integrate_bins(6, |wi| (b.f(wo, wi, RADIANCE)[k] * wi.z.abs()) as f64);
        a[k] = per_bin.iter().sum::<f64>() as f32;
    }
    a
}

#[test]
fn white_furnace_never_gains_energy() {
    // A white GGX (F = 1) loses what single-scattering Smith loses; Lambert 0.9 keeps 0.9.
    let white = |wo: Vec3, wi: Vec3, _: f32| {
        if wo.z <= 0.0 || wi.z <= 0.0 {
            return 0.0;
        }
        let wm = normalize(wo + wi);
        ggx_g1(ALPHA, wo) * ggx_g1(ALPHA, wi) * ggx_d(ALPHA, wm) / (4.0 * wo.z * wi.z)
    };
    let bytes = bsdf_file(ALPHA, white, N, &theta_nodes(), &WAVELENGTHS);
    let b = spectral(MeasuredData::shared(
        &MeasuredFile::from_bytes(&bytes, "white.bsdf").unwrap(),
    ));
    let lambert = spectral(lambert_data());
    for theta in [0.0, 20.0, 45.0, 70.0, 85.0] {
        let wo = at(theta, 0.7);
        let a = albedo(&b, wo).max_element();
        let want: f64 = integrate_bins(6, |wi| (white(wo, wi, 0.0) * wi.z.max(0.0)) as f64)
            .iter()
            .sum();
        println!("θo = {theta}°: white GGX albedo {a} (analytic {want})");
        assert!(a <= 1.0, "θo = {theta}°: albedo {a}");
        assert!(
            (a as f64 - want).abs() < 0.03,
            "θo = {theta}°: {a} vs {want}"
        );
        let l = albedo(&lambert, wo);
        assert!(
            l.max_element() <= 1.0 && (l - 0.9).abs().max_element() < 0.03,
            "{l}"
        );
    }
}

/// Writes the generated files (`ggx.bsdf`: the spectral GGX conductor above; `lambert.bsdf`:
/// Lambert 0.9) into the folder `$LANCER_BSDF_OUT`, for trying them in scenes:
/// `LANCER_BSDF_OUT=/tmp/bsdf cargo test -p lancer --test it measured::write -- --ignored`.
#[test]
#[ignore]
fn write_generated_files() {
    let out = std::path::PathBuf::from(std::env::var("LANCER_BSDF_OUT").expect("LANCER_BSDF_OUT"));
    std::fs::create_dir_all(&out).unwrap();
    let lambert = |_: Vec3, wi: Vec3, _: f32| if wi.z > 0.0 { 0.9 * INV_PI } else { 0.0 };
    std::fs::write(
        out.join("ggx.bsdf"),
        bsdf_file(ALPHA, ggx, N, &theta_nodes(), &WAVELENGTHS),
    )
    .unwrap();
    std::fs::write(
        out.join("lambert.bsdf"),
        bsdf_file(ALPHA, lambert, N, &theta_nodes(), &WAVELENGTHS),
    )
    .unwrap();
}

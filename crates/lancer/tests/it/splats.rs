//! Splats through the film interface: a fake light-tracing integrator that puts light on
//! pixels anywhere in the image gives the same film bits whatever the thread count, and split
//! parts (by samples or by tiles, through part files too) merge into the whole render's film.

use crate::common::units::render_units_on;
use lancer::Scene;
use lancer::film::part::{PartMeta, read_part, write_part};
use lancer::film::spectral::{SpectralDesc, SpectralSums};
use lancer::film::{Film, PixelBounds};
use lancer::math::{SampledSpectrum, Vec2};
use lancer::ray::Ray;
use lancer::render::{RenderSettings, RenderStats, SampleIntegrator, Splats, work_units};
use lancer::sampling::Sampler;
use lancer::scene::desc::{FilterDesc, SceneDesc};
use lancer::spectrum::sampled::SampledWavelengths;

const W: u32 = 24;
const H: u32 = 16;
const SPP: u32 = 8;
/// The radiance each splat carries.
const SPLAT: f32 = 0.75;

/// Splats `SPLAT` at a uniformly drawn point of the image (and one outside it), as a light
/// tracer's light paths land anywhere; its camera rays bring back a little radiance too.
struct FakeLightTracer;

impl SampleIntegrator for FakeLightTracer {
    fn splats(&self) -> bool {
        true
    }

    fn computes_radiance(&self) -> bool {
        true
    }

    fn li(
        &self,
        _scene: &Scene,
        ray: &Ray,
        sampler: &mut Sampler,
        lambda: Option<&SampledWavelengths>,
        splats: &Splats<'_>,
    ) -> SampledSpectrum {
        let u = sampler.get_2d();
        let p = Vec2::new(u.x * W as f32, u.y * H as f32);
        splats.add_splat(p, SampledSpectrum::splat(SPLAT), lambda);
        // Off the film: dropped.
        splats.add_splat(Vec2::new(-5.0, 3.0), SampledSpectrum::splat(1.0), lambda);
        SampledSpectrum::splat(0.1 * ray.d.z.abs())
    }
}

fn desc() -> SceneDesc {
    let mut d = SceneDesc {
        filter: FilterDesc::Box { radius: [0.5, 0.5] },
        ..SceneDesc::default()
    };
    d.film.xresolution = W;
    d.film.yresolution = H;
    d.sampler.spp = SPP;
    d
}

/// The whole image.
fn full() -> PixelBounds {
    desc().film.render_bounds()
}

/// Renders `bounds` × `samples` with the fake integrator on `threads` threads into a fresh
/// film over `bounds`, in units of 8-pixel tiles and 3-sample passes.
fn render(
    scene: &Scene,
    d: &SceneDesc,
    bounds: PixelBounds,
    samples: std::ops::Range<u32>,
    threads: usize,
) -> (Film, RenderStats) {
    render_into(scene, d, Film::new(W, H, bounds), samples, threads)
}

/// [`render`] into `film` (over the pixels it holds; spectral mode for a spectral film).
fn render_into(
    scene: &Scene,
    d: &SceneDesc,
    mut film: Film,
    samples: std::ops::Range<u32>,
    threads: usize,
) -> (Film, RenderStats) {
    let bounds = film.bounds;
    let settings = RenderSettings {
        bounds,
        samples: samples.clone(),
        spectral: film.spectral.is_some(),
        ..RenderSettings::from_desc(d)
    };
    let units = work_units(&bounds, 8, samples, 3);
    let stats = render_units_on(
        threads,
        scene,
        &settings,
        &FakeLightTracer,
        &mut film,
        &units,
    );
    (film, stats)
}

#[test]
fn splatting_render_is_exact_across_threads_and_splits() {
    let d = desc();
    let scene = Scene::build(&d).unwrap();
    let (whole, stats) = render(&scene, &d, full(), 0..SPP, 1);
    assert_eq!(stats.samples, full().area() * SPP as u64);
    let splats = whole.splats.as_ref().expect("the film has a splat plane");
    assert_eq!(splats.bounds, full());
    assert!(splats.sums.iter().any(|&s| s != 0));

    // Any thread count: the same bits.
    let (two, _) = render(&scene, &d, full(), 0..SPP, 2);
    assert_eq!(two, whole);
    assert_eq!(two.image(1.0), whole.image(1.0));

    // Split by samples: parts merged equal the whole.
    let mut merged = Film::new(W, H, full());
    for r in [0..3, 3..5, 5..SPP] {
        let (part, _) = render(&scene, &d, full(), r, 2);
        merged.merge_film(&part);
    }
    assert_eq!(merged, whole);

    // Split by tiles, each part through its part file: each part's splats land anywhere in the
    // render, and the parts still add up to the whole.
    let dir = lancer_testing::ScratchDir::new("splat-parts");
    let mut merged = Film::new(W, H, full());
    for (k, rows) in [0..5, 5..H as i32].into_iter().enumerate() {
        let b = PixelBounds {
            y0: rows.start,
            y1: rows.end,
            ..full()
        };
        let (part, _) = render(&scene, &d, b, 0..SPP, 2);
        assert_eq!(part.splats.as_ref().unwrap().bounds, full());
        let meta = PartMeta {
            scene_hash: 7,
            seed: 0,
            spp: SPP,
            samples: 0..SPP,
            render_bounds: full(),
            scale: 1.0,
        };
        let path = dir.join(format!("part{k}.exr"));
        write_part(&path, &part, &meta).unwrap();
        let (read, m) = read_part(&path).unwrap();
        assert_eq!(read, part);
        assert_eq!(m, meta);
        merged.merge_film(&read);
    }
    assert_eq!(merged, whole);
}

/// pbrt-v4's splat scale: a pixel adds its splat sum over the samples per pixel. With a box
/// filter of radius ½ each splat lands on one pixel with weight 1/∫f = 1; every camera
/// sample splats `SPLAT` once inside the image, so the splats' mean over the image is `SPLAT`.
#[test]
fn splats_add_their_sum_over_the_samples_per_pixel() {
    let d = desc();
    let scene = Scene::build(&d).unwrap();
    let (film, _) = render(&scene, &d, full(), 0..SPP, 2);
    let mut without = film.clone();
    without.splats = None;
    let (with, plain) = (film.image(1.0), without.image(1.0));
    let n = with.len() as f64;
    let mean: f64 = with
        .iter()
        .zip(&plain)
        .map(|(a, b)| (a.x - b.x) as f64)
        .sum::<f64>()
        / n;
    assert!((mean - SPLAT as f64).abs() < 1e-4, "mean splat {mean}");
    // The samples' own radiance is untouched by the splats: Σw·L/Σw as before.
    assert!(plain.iter().all(|p| p.x > 0.0 && p.x <= 0.1));
}

/// A spectral film's buckets take splats as its colour does: each splat of radiance L adds
/// L(λₖ)/(pdf(λₖ)·Δλ·4) to the bucket of each of its four wavelengths, so that S/n is in
/// the units of a bucket's sample value. The fake splats a constant `SPLAT` once per camera
/// sample, so the buckets' splats average exactly `SPLAT` over the image (the four
/// wavelengths of a sample fall one in each quarter of the range), and so does each bucket's,
/// up to which bucket of its quarter each wavelength falls in. 64 samples a pixel spread
/// them evenly (the sampler stratifies; with 8 a bucket was 7.6 % off, and independent draws
/// would be about 1 % off), and a bucket that got no share or twice its share (a wrong
/// bucket index) fails the 5 % bound.
#[test]
fn a_spectral_films_buckets_take_splats_in_their_units() {
    const SPECTRAL_SPP: u32 = 64;
    let mut d = desc();
    d.sampler.spp = SPECTRAL_SPP;
    let scene = Scene::build(&d).unwrap();
    let buckets = SpectralDesc::default();
    let mut film = Film::new(W, H, full());
    film.spectral = Some(Box::new(SpectralSums::new(buckets, full().area() as usize)));
    let (film, _) = render_into(&scene, &d, film, 0..SPECTRAL_SPP, 2);
    let splats = film.splats.as_ref().expect("the film has a splat plane");
    assert_eq!(splats.channels, 3 + buckets.nbuckets as usize);
    let divisor = film.splat_divisor();
    let nb = buckets.nbuckets as usize;
    let mut mean = vec![0.0f64; nb];
    for i in 0..film.pixels.len() {
        let (with, without) = (film.bucket_values(i, divisor), film.bucket_values(i, None));
        assert_eq!(with.len(), nb);
        for b in 0..nb {
            mean[b] += (with[b] - without[b]) as f64 / film.pixels.len() as f64;
        }
    }
    let overall = mean.iter().sum::<f64>() / nb as f64;
    assert!(
        (overall - SPLAT as f64).abs() < 1e-3,
        "mean bucket splat {overall}"
    );
    for (b, m) in mean.iter().enumerate() {
        assert!(
            (m - SPLAT as f64).abs() < 0.05 * SPLAT as f64,
            "bucket {b}: mean splat {m} (all: {mean:?})"
        );
    }
}

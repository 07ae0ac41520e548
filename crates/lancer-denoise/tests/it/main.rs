//! The denoiser end to end: OIDN's own output on a small image (stored, as OIDN is not
//! here), tiling seams, and that it removes noise.

mod oidn;

use lancer_denoise::{Options, denoise, denoise_with, tile_plan};
use lancer_testing::uniform;

/// A clean synthetic image: two flat regions split by a slanted edge, a soft gradient over
/// them; its albedo (the regions' colours) and normal (one per region).
/// `tools/oidn_golden.py` makes the same floats.
fn scene(w: usize, h: usize) -> (Vec<f32>, Vec<f32>, Vec<f32>) {
    let mut clean = Vec::with_capacity(w * h * 3);
    let mut albedo = Vec::with_capacity(w * h * 3);
    let mut normal = Vec::with_capacity(w * h * 3);
    for y in 0..h {
        for x in 0..w {
            let (a, n) = if 3 * x + y < 2 * w {
                ([0.8, 0.3, 0.2], [0.0, 0.0, -1.0])
            } else {
                ([0.2, 0.5, 0.8], [0.6, 0.0, -0.8])
            };
            let light = 0.5 + 0.5 * y as f32 / h as f32;
            clean.extend(a.map(|c| c * light));
            albedo.extend(a);
            normal.extend(n);
        }
    }
    (clean, albedo, normal)
}

/// Monte Carlo-like noise: each pixel is its clean value times 3u² (mean 1), one u per
/// pixel, so colour stays and brightness is noisy.
fn noisy(clean: &[f32], seed: u64) -> Vec<f32> {
    let u = uniform(clean.len() / 3, seed);
    clean
        .chunks_exact(3)
        .zip(u)
        .flat_map(|(c, u)| {
            let k = 3.0 * u * u;
            [c[0] * k, c[1] * k, c[2] * k]
        })
        .collect()
}

/// Relative MSE, mean of (a − b)² / (b² + 0.01).
fn relmse(a: &[f32], b: &[f32]) -> f64 {
    let s: f64 = a
        .iter()
        .zip(b)
        .map(|(&a, &b)| ((a - b) as f64).powi(2) / ((b as f64).powi(2) + 0.01))
        .sum();
    s / a.len() as f64
}

#[test]
fn the_denoiser_removes_most_of_the_noise() {
    let (w, h) = (96, 80);
    let (clean, albedo, normal) = scene(w, h);
    let input = noisy(&clean, 7);
    let before = relmse(&input, &clean);
    for (name, out) in [
        ("colour", denoise(&input, None, None, w, h).unwrap()),
        (
            "colour + albedo",
            denoise(&input, Some(&albedo), None, w, h).unwrap(),
        ),
        (
            "colour + albedo + normal",
            denoise(&input, Some(&albedo), Some(&normal), w, h).unwrap(),
        ),
    ] {
        let after = relmse(&out, &clean);
        assert!(
            out.iter().all(|v| v.is_finite() && *v >= 0.0),
            "{name}: bad values"
        );
        assert!(after < 0.2 * before, "{name}: relmse {before} → {after}");
        // the mean brightness is kept (within 5 %)
        let (m_in, m_out) = (mean(&input), mean(&out));
        assert!(
            (m_out / m_in - 1.0).abs() < 0.05,
            "{name}: mean {m_in} → {m_out}"
        );
    }
}

fn mean(v: &[f32]) -> f64 {
    v.iter().map(|&x| x as f64).sum::<f64>() / v.len() as f64
}

#[test]
fn a_tiled_image_equals_the_untiled_one() {
    let (w, h) = (480, 160);
    let (clean, albedo, _) = scene(w, h);
    let input = noisy(&clean, 11);
    // tiles are at least 4 overlaps (384) wide: two tiles across
    let small = Options {
        max_tile_pixels: 400 * 160,
        min_tile_dim: 0,
    };
    assert_eq!(tile_plan(w, h, &small), (160, 384, 1, 2));
    assert_eq!(tile_plan(w, h, &Options::default()), (160, 480, 1, 1));
    let whole = denoise(&input, Some(&albedo), None, w, h).unwrap();
    let tiled = denoise_with(&small, &input, Some(&albedo), None, w, h).unwrap();
    // The overlap (96 pixels) covers all but the faintest tail of the network's reach: the
    // seams are invisible, the images equal up to rounding-sized differences.
    let worst = whole
        .iter()
        .zip(&tiled)
        .map(|(a, b)| (a - b).abs() / (a.abs() + 0.01))
        .fold(0.0f32, f32::max);
    assert!(
        worst < 2e-3,
        "largest relative difference at a seam {worst}"
    );
    assert!(relmse(&tiled, &whole) < 1e-8);
}

#[test]
fn tiles_cover_each_pixel_once_as_oidn_cuts_them() {
    // OIDN keeps 1280x720 whole and cuts big images into tiles of at most the limit
    let o = Options::default();
    assert_eq!(tile_plan(1280, 720, &o), (720, 1280, 1, 1));
    assert_eq!(tile_plan(1000, 7, &o), (16, 1008, 1, 1));
    for &(w, h) in &[(4000, 3000), (1500, 5000), (16384, 16384)] {
        let (th, tw, nh, nw) = tile_plan(w, h, &o);
        assert!(th * tw <= o.max_tile_pixels, "{w}x{h}: tile {tw}x{th}");
        assert!(th % 16 == 0 && tw % 16 == 0);
        // the written rows of the tiles: [i·(th − 192) + begin, … + out) partition 0..h
        for (size, tile, n) in [(h, th, nh), (w, tw, nw)] {
            let mut next = 0;
            for i in 0..n {
                let src = i * (tile - 192);
                let begin = if i > 0 { 96 } else { 0 };
                let end = if i + 1 < n { 96 } else { 0 };
                let len = (size - src).min(tile);
                assert_eq!(src + begin, next, "{w}x{h}: tile {i} of {n}");
                next = src + len - end;
            }
            assert_eq!(next, size, "{w}x{h}");
        }
    }
}

#[test]
fn bad_inputs_are_refused() {
    let img = vec![0.5; 4 * 4 * 3];
    assert!(denoise(&img, None, Some(&img), 4, 4).is_err());
    assert!(denoise(&img[..5], None, None, 4, 4).is_err());
    assert!(denoise(&[], None, None, 0, 0).is_err());
    // tiny and odd sizes work (the tile is padded to 16)
    let out = denoise(&[0.5; 3 * 5 * 3], None, None, 3, 5).unwrap();
    assert_eq!(out.len(), 3 * 5 * 3);
}

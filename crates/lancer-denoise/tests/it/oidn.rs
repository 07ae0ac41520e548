//! lancer's denoiser against Intel Open Image Denoise's own output on the same input: the
//! 40×36 image of [`super::scene`] with its noise, denoised by OIDN 2.5.1 ("rt" filter, HDR,
//! quality "high") with each of the three input combinations, stored in
//! `tests/data/oidn_40x36.f32` by `tools/oidn_golden.py`. The same network with the same
//! weights differs from OIDN only by float rounding (its convolutions sum in another order);
//! a wrong network (a skip connection swapped, a layer's channels in the wrong order, the
//! image placed elsewhere in its tile, an autoexposure a few per cent off) changes whole
//! regions by far more than the tolerance.

use super::{noisy, scene};
use lancer_denoise::denoise;

const W: usize = 40;
const H: usize = 36;

/// OIDN's three outputs: colour; colour + albedo; colour + albedo + normal.
fn oidn_outputs() -> Vec<Vec<f32>> {
    let bytes = include_bytes!("../data/oidn_40x36.f32");
    let floats: Vec<f32> = bytes
        .chunks_exact(4)
        .map(|b| f32::from_le_bytes(b.try_into().unwrap()))
        .collect();
    assert_eq!(floats.len(), 3 * W * H * 3);
    floats
        .chunks_exact(W * H * 3)
        .map(<[f32]>::to_vec)
        .collect()
}

#[test]
fn each_network_gives_oidns_output() {
    let (clean, albedo, normal) = scene(W, H);
    let input = noisy(&clean, 7);
    let cases = [
        ("colour", None, None),
        ("colour + albedo", Some(&albedo[..]), None),
        (
            "colour + albedo + normal",
            Some(&albedo[..]),
            Some(&normal[..]),
        ),
    ];
    for ((name, a, n), want) in cases.into_iter().zip(oidn_outputs()) {
        let got = denoise(&input, a, n, W, H).unwrap();
        // worst difference relative to the pixel's value, and the normalised RMS error
        let worst = got
            .iter()
            .zip(&want)
            .map(|(g, e)| (g - e).abs() / (e.abs() + 0.01))
            .fold(0.0f32, f32::max);
        let (se, ss) = got
            .iter()
            .zip(&want)
            .fold((0.0f64, 0.0f64), |(se, ss), (g, e)| {
                (se + ((g - e) as f64).powi(2), ss + (*e as f64).powi(2))
            });
        let nrmse = (se / ss).sqrt();
        assert!(
            worst < 1e-3 && nrmse < 1e-4,
            "{name}: worst relative difference {worst}, nrmse {nrmse}"
        );
    }
}

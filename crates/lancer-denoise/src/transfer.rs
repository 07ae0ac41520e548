//! The network's input and output transfer in HDR mode (OIDN's `core/color.h`,
//! `cpu_autoexposure`, `cpu_input_process`, `cpu_output_process`).
//!
//! Colour is scaled by the autoexposure's factor s, sanitised (NaN → 0, clamped to
//! [0, f32::MAX]) and mapped by the perceptually uniform curve PU, normalised so that
//! PU(65504) = 1: x = PU(s·y) / PU(65504). The network's output goes back by
//! y = PU⁻¹(x·PU(65504)) / s. Albedo is clamped to [0, 1]; a normal n to [-1, 1] and mapped
//! to n/2 + 1/2.

use rayon::prelude::*;

/// PU's fitted constants (OIDN's `TransferFunction::PU`), written as OIDN writes them (each
/// rounds to the f32 OIDN uses).
#[allow(clippy::excessive_precision)]
mod pu {
    pub const A: f32 = 1.412_837_65e+03;
    pub const B: f32 = 1.645_931_72e+00;
    pub const C: f32 = 4.313_849_81e-01;
    pub const D: f32 = -2.941_396_09e-03;
    pub const E: f32 = 1.926_532_54e-01;
    pub const F: f32 = 6.260_260_94e-03;
    pub const G: f32 = 9.986_201_52e-01;
    pub const Y0: f32 = 1.579_457_60e-06;
    pub const Y1: f32 = 3.220_876_31e-02;
    pub const X0: f32 = 2.231_517_11e-03;
    pub const X1: f32 = 3.709_747_49e-01;
}

/// The largest HDR value PU is normalised by (the largest binary16).
pub const Y_MAX: f32 = 65504.0;

/// PU(y): a·y below y0, b·y^c + d below y1, e·ln(y + f) + g above.
pub fn pu_forward(y: f32) -> f32 {
    use pu::*;
    if y <= Y0 {
        A * y
    } else if y <= Y1 {
        B * y.powf(C) + D
    } else {
        E * (y + F).ln() + G
    }
}

/// PU⁻¹(x): x/a below x0, ((x − d)/b)^(1/c) below x1, exp((x − g)/e) − f above.
pub fn pu_inverse(x: f32) -> f32 {
    use pu::*;
    if x <= X0 {
        x / A
    } else if x <= X1 {
        ((x - D) / B).powf(1.0 / C)
    } else {
        ((x - G) / E).exp() - F
    }
}

/// The HDR transfer: PU scaled so that `Y_MAX` maps to 1, with the autoexposure's scale.
#[derive(Clone, Copy, Debug)]
pub struct Transfer {
    /// s, multiplied into the colour before PU.
    pub input_scale: f32,
    /// 1/s (0 when s is 0), multiplied into the output after PU⁻¹.
    pub output_scale: f32,
    /// 1/PU(65504).
    pub norm_scale: f32,
    /// PU(65504).
    pub rcp_norm_scale: f32,
}

impl Transfer {
    /// The transfer for an input scale s.
    pub fn new(input_scale: f32) -> Self {
        let x_max = pu_forward(Y_MAX);
        Self {
            input_scale,
            output_scale: if input_scale != 0.0 {
                1.0 / input_scale
            } else {
                0.0
            },
            // OIDN computes 1./xMax in double precision.
            norm_scale: (1.0 / x_max as f64) as f32,
            rcp_norm_scale: x_max,
        }
    }

    /// A colour channel as the network sees it: PU(clamp(s·y)) / PU(65504).
    #[inline]
    pub fn forward(&self, y: f32) -> f32 {
        pu_forward(sanitize(y * self.input_scale, 0.0, f32::MAX)) * self.norm_scale
    }

    /// A network output channel back to colour: PU⁻¹(clamp(x)·PU(65504)) / s.
    #[inline]
    pub fn inverse(&self, x: f32) -> f32 {
        pu_inverse(sanitize(x, 0.0, f32::MAX) * self.rcp_norm_scale) * self.output_scale
    }
}

/// NaN → 0, then clamped to [lo, hi].
#[inline]
pub fn sanitize(v: f32, lo: f32, hi: f32) -> f32 {
    if v.is_nan() { 0.0 } else { v.clamp(lo, hi) }
}

/// An albedo channel as the network sees it: clamped to [0, 1].
#[inline]
pub fn albedo_in(v: f32) -> f32 {
    sanitize(v, 0.0, 1.0)
}

/// A normal channel as the network sees it: clamped to [-1, 1], then n/2 + 1/2.
#[inline]
pub fn normal_in(v: f32) -> f32 {
    sanitize(v, -1.0, 1.0) * 0.5 + 0.5
}

/// Luminance of linear RGB (OIDN's weights: 0.212671, 0.715160, 0.072169).
#[inline]
fn luminance(r: f32, g: f32, b: f32) -> f32 {
    0.212_671 * r + 0.715_160 * g + 0.072_169 * b
}

/// The bins' edge: bin i of n over `len` pixels starts at ⌊i·len/n⌋.
fn bin_edge(i: usize, len: usize, n: usize) -> usize {
    i * len / n
}

/// OIDN's autoexposure of an RGB image (`width`×`height`, interleaved): the image is cut
/// into bins of at most 16×16 pixels; L̄ = mean luminance of each bin (colour sanitised to
/// [0, f32::MAX]); over the bins with L̄ > 1e-8, s = 0.18 / 2^(mean log₂ L̄); s = 1 if none.
pub fn autoexposure(rgb: &[f32], width: usize, height: usize) -> f32 {
    const MAX_BIN: usize = 16;
    const KEY: f32 = 0.18;
    const EPS: f32 = 1e-8;
    let nh = height.div_ceil(MAX_BIN);
    let nw = width.div_ceil(MAX_BIN);
    let per_row: Vec<(f32, usize)> = (0..nh)
        .into_par_iter()
        .map(|i| {
            let (h0, h1) = (bin_edge(i, height, nh), bin_edge(i + 1, height, nh));
            let mut sum = 0.0f32;
            let mut count = 0;
            for j in 0..nw {
                let (w0, w1) = (bin_edge(j, width, nw), bin_edge(j + 1, width, nw));
                let mut l = 0.0f32;
                for y in h0..h1 {
                    for x in w0..w1 {
                        let p = &rgb[3 * (y * width + x)..][..3];
                        let c = |v: f32| sanitize(v, 0.0, f32::MAX);
                        l += luminance(c(p[0]), c(p[1]), c(p[2]));
                    }
                }
                let l = l / ((h1 - h0) * (w1 - w0)) as f32;
                if l > EPS {
                    sum += l.log2();
                    count += 1;
                }
            }
            (sum, count)
        })
        .collect();
    let (sum, count) = per_row
        .iter()
        .fold((0.0f32, 0usize), |a, b| (a.0 + b.0, a.1 + b.1));
    if count > 0 {
        KEY / (sum / count as f32).exp2()
    } else {
        1.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pu_inverse_undoes_forward_on_each_piece() {
        for &y in &[
            0.0, 1e-7, 1.5e-6, 1e-4, 0.01, 0.0322, 0.05, 0.5, 1.0, 7.0, 300.0, 65504.0,
        ] {
            let x = pu_forward(y);
            let back = pu_inverse(x);
            assert!(
                (back - y).abs() <= 1e-4 * y.max(1e-6),
                "y {y} → {x} → {back}"
            );
        }
        // continuity at the pieces' joins and monotonicity
        let mut prev = -1.0;
        for i in 0..2000 {
            let y = 10f32.powf(-8.0 + i as f32 * 0.0065);
            let x = pu_forward(y);
            assert!(x > prev, "PU not increasing at {y}");
            prev = x;
        }
        assert!((pu_forward(pu::Y0) - pu::X0).abs() < 1e-6);
        assert!((pu_forward(pu::Y1) - pu::X1).abs() < 1e-5);
    }

    #[test]
    fn transfer_maps_65504_to_one_and_back() {
        let t = Transfer::new(1.0);
        assert!((t.forward(65504.0) - 1.0).abs() < 1e-6);
        let t = Transfer::new(2.5);
        for &y in &[0.0, 0.001, 0.2, 3.0, 100.0] {
            let back = t.inverse(t.forward(y));
            assert!((back - y).abs() <= 2e-4 * y.max(1e-3), "{y} → {back}");
        }
        assert_eq!(t.forward(f32::NAN), 0.0);
        assert_eq!(t.forward(-3.0), 0.0);
        assert_eq!(t.inverse(-1.0), 0.0);
        assert_eq!(normal_in(-2.0), 0.0);
        assert_eq!(normal_in(0.0), 0.5);
        assert_eq!(albedo_in(1.5), 1.0);
    }

    #[test]
    fn autoexposure_of_a_constant_image_is_key_over_luminance() {
        let (w, h) = (37, 20);
        let img: Vec<f32> = (0..w * h).flat_map(|_| [0.5, 0.5, 0.5]).collect();
        let s = autoexposure(&img, w, h);
        assert!((s - 0.18 / 0.5).abs() < 1e-5, "{s}");
        assert_eq!(autoexposure(&vec![0.0; w * h * 3], w, h), 1.0);
        // a geometric mean over bins: half the bins at 2, half at 8 → 4
        let img: Vec<f32> = (0..32 * 16)
            .flat_map(|i| if i % 32 < 16 { [2.0; 3] } else { [8.0; 3] })
            .collect();
        let s = autoexposure(&img, 32, 16);
        assert!((s - 0.18 / 4.0).abs() < 1e-6, "{s}");
    }
}

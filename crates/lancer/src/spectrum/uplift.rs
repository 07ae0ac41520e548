//! RGB → spectrum: the sigmoid-polynomial spectra of Jakob & Hanika 2019 ("A Low-Dimensional
//! Function Space for Efficient Spectral Upsampling", Computer Graphics Forum 38(2)), as
//! pbrt-v4 uses them for its spectral rendering.
//!
//! A colour becomes the smooth spectrum
//!
//! s(λ) = S(c₀t² + c₁t + c₂),  t = (λ − 360 nm)/(830 nm − 360 nm),  S(x) = ½ + x/(2√(1 + x²)),
//!
//! whose values lie in (0, 1). The three coefficients are fitted by Gauss–Newton so that the
//! spectrum, seen under D65 (the white of sRGB) and reduced to linear sRGB by the same rules as
//! [`super::spectrum_to_rgb`] with [`super::SpectrumKind::Albedo`], reproduces the colour:
//!
//! rgb(s) = M_XYZ→sRGB · Σ_λ s(λ)·D65(λ)·(x̄, ȳ, z̄)(λ) / Σ_λ D65(λ)·ȳ(λ)  (1 nm steps).
//!
//! [`fit_albedo`] fits one colour exactly (about 0.1 ms). Rendering instead looks colours up in
//! a [`CoefficientTable`], as pbrt-v4 does: coefficients fitted once per process on a
//! 3 × 40³ grid over the colour cube and interpolated trilinearly, so that image textures and
//! environment maps with many distinct texel colours cost a lookup each rather than a fit. The
//! table is built, in parallel, the first time spectral mode meets a colour that is not grey
//! (RGB mode never builds it); its fits are warm-started from their neighbours, as in
//! rgb2spec_opt, and take about 0.3 s on two cores. Interpolated colours come back within
//! 2·10⁻³ of the input in [0, 1]³ (about 5·10⁻⁴ on average; up to 3·10⁻³ in the corner of
//! near-whites, all components above 0.85 and one within 2 % of 1), against about 10⁻⁷ for an
//! exact fit; the grid's spacing and the interpolation's measure along the brightest
//! component are chosen for that (see [`CoefficientTable`]). Lookups are pure functions of the
//! colour, so renders depend on neither threads nor the order colours are met.
//!
//! Three uses, as pbrt-v4's `RGBAlbedoSpectrum`, `RGBUnboundedSpectrum` and
//! `RGBIlluminantSpectrum`:
//!
//! - a reflectance, clamped to [0, 1], is uplifted as it is;
//! - an unbounded value with largest component m is written 2m · s(λ), s uplifted from rgb/(2m)
//!   (whose components are at most ½, comfortably inside what a sigmoid spectrum can reach);
//! - an illuminant is the unbounded spectrum times D65(λ), divided by Σ D65·ȳ / Σ ȳ so that
//!   RGB (1, 1, 1) has luminance 1 on the film (lancer's light normalisation, pbrt-v4's for RGB
//!   lights): see [`super::sampled`].

use std::sync::OnceLock;

use glam::{DMat3, DVec3};

use super::{INTEGRATION_RANGE, cie, weights, xyz_to_srgb_f64};
use crate::math::Rgb;

/// A spectrum s(λ) = S(c₀t² + c₁t + c₂) of the Jakob–Hanika family, or one of its limits.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum SigmoidSpectrum {
    /// The same value everywhere (greys, including black and white, are fitted exactly so).
    Constant(f32),
    /// Coefficients `[c₀, c₁, c₂]` of the polynomial in t = (λ − 360)/470.
    Poly([f32; 3]),
}

/// Wavelength (nm) → the fit's normalised t ∈ [0, 1].
#[inline]
fn normalised(lambda: f64) -> f64 {
    (lambda - cie::LAMBDA_MIN) / (cie::LAMBDA_MAX - cie::LAMBDA_MIN)
}

impl SigmoidSpectrum {
    /// The value at `lambda` (nm), in [0, 1].
    #[inline]
    pub fn eval(&self, lambda: f32) -> f32 {
        match *self {
            SigmoidSpectrum::Constant(v) => v,
            SigmoidSpectrum::Poly([c0, c1, c2]) => {
                // Single precision is plenty here (the fit's tolerance is far coarser).
                let t = (lambda - cie::LAMBDA_MIN as f32)
                    * (1.0 / (cie::LAMBDA_MAX - cie::LAMBDA_MIN) as f32);
                // Horner: (c₀t + c₁)t + c₂.
                let x = (c0 * t + c1) * t + c2;
                if x.is_infinite() {
                    return if x > 0.0 { 1.0 } else { 0.0 };
                }
                0.5 + x / (2.0 * (1.0 + x * x).sqrt())
            }
        }
    }

    /// The spectrum's colour: linear sRGB of s seen under D65 (the reduction the fit inverts).
    pub fn to_rgb(&self) -> Rgb {
        match *self {
            SigmoidSpectrum::Constant(v) => Rgb::splat(v),
            SigmoidSpectrum::Poly(c) => reduce(c.map(f64::from), false).0.as_vec3a(),
        }
    }
}

/// Lanes of the fit's inner loop: wavelengths are processed four at a time (one AVX2
/// register of f64), each lane with its own partial sums.
const LANES: usize = 4;

/// The fit's integration weights, by groups of [`LANES`] wavelengths (the last group padded
/// with zero weights): t(λ), and the rows of M_XYZ→sRGB · D65(λ)(x̄, ȳ, z̄)(λ) / Σ D65·ȳ, so
/// that rgb(s) = Σ_λ s(λ) · w(λ) directly.
struct FitWeights {
    t: Vec<[f64; LANES]>,
    w: [Vec<[f64; LANES]>; 3],
}

fn fit_weights() -> &'static FitWeights {
    static FIT_WEIGHTS: OnceLock<FitWeights> = OnceLock::new();
    FIT_WEIGHTS.get_or_init(|| {
        let w = weights();
        let groups = w.d65_cmf.len().div_ceil(LANES);
        let mut fw = FitWeights {
            t: vec![[0.0; LANES]; groups],
            w: std::array::from_fn(|_| vec![[0.0; LANES]; groups]),
        };
        for (n, (l, wc)) in INTEGRATION_RANGE.zip(&w.d65_cmf).enumerate() {
            let (g, lane) = (n / LANES, n % LANES);
            fw.t[g][lane] = normalised(l as f64);
            let rgb = xyz_to_srgb_f64(DVec3::from(*wc) / w.d65_y);
            for k in 0..3 {
                fw.w[k][g][lane] = rgb[k];
            }
        }
        fw
    })
}

/// rgb(s) for coefficients `c` (see the module documentation) and, when `JACOBIAN`, its
/// derivatives with respect to c₀, c₁, c₂ (the matrix's columns):
///
/// rgb = Σ_λ S(x)·w(λ),  ∂rgb/∂cₖ = Σ_λ S'(x)·t^{2−k}·w(λ),  x = (c₀t + c₁)t + c₂,
///
/// with S(x) = ½ + ½·x·r and S'(x) = ½·r³ for r = 1/√(1 + x²) (one square root and one
/// division per wavelength). This is the inner loop of every fit, written lane-wise so that
/// it vectorises.
fn reduce_lanes<const JACOBIAN: bool>(c: [f64; 3]) -> (DVec3, DMat3) {
    use lanes::F4;
    let fw = fit_weights();
    let zero = F4::splat(0.0);
    let (one, half) = (F4::splat(1.0), F4::splat(0.5));
    let c = c.map(F4::splat);
    let mut rgb = [zero; 3];
    let mut d = [zero; 9];
    let groups = fw.t.iter().zip(&fw.w[0]).zip(&fw.w[1]).zip(&fw.w[2]);
    for (((t, w0), w1), w2) in groups {
        let t = F4::load(t);
        let x = c[0].mul(t).add(c[1]).mul(t).add(c[2]);
        let r = one.div(one.add(x.mul(x)).sqrt());
        let s = half.add(half.mul(x).mul(r));
        let w = [F4::load(w0), F4::load(w1), F4::load(w2)];
        for k in 0..3 {
            rgb[k] = rgb[k].add(s.mul(w[k]));
        }
        if JACOBIAN {
            let ds = half.mul(r).mul(r).mul(r);
            let t2 = t.mul(t);
            for k in 0..3 {
                let dw = ds.mul(w[k]);
                d[k] = d[k].add(dw.mul(t2));
                d[3 + k] = d[3 + k].add(dw.mul(t));
                d[6 + k] = d[6 + k].add(dw);
            }
        }
    }
    let sum = |v: F4| {
        let v = v.to_array();
        (v[0] + v[1]) + (v[2] + v[3])
    };
    let vec = |a: usize| DVec3::new(sum(d[a]), sum(d[a + 1]), sum(d[a + 2]));
    (
        DVec3::new(sum(rgb[0]), sum(rgb[1]), sum(rgb[2])),
        DMat3::from_cols(vec(0), vec(3), vec(6)),
    )
}

/// Four `f64` lanes for [`reduce_lanes`]: one AVX register on x86-64 (lancer is built for
/// x86-64-v3), a plain array elsewhere. Every operation is the IEEE one of scalar code (no
/// fusing), so both give the same bits.
mod lanes {
    #[cfg(all(target_arch = "x86_64", target_feature = "avx"))]
    mod imp {
        //! SAFETY (every `unsafe` block below): the intrinsics need AVX, which the `cfg` of
        //! this module guarantees the build enables; loads and stores are unaligned.
        use std::arch::x86_64::*;

        /// Four doubles.
        #[derive(Clone, Copy)]
        pub struct F4(__m256d);

        impl F4 {
            #[inline(always)]
            pub fn splat(v: f64) -> F4 {
                F4(unsafe { _mm256_set1_pd(v) })
            }
            #[inline(always)]
            pub fn load(a: &[f64; 4]) -> F4 {
                // SAFETY: `a` is four readable doubles.
                F4(unsafe { _mm256_loadu_pd(a.as_ptr()) })
            }
            #[inline(always)]
            pub fn to_array(self) -> [f64; 4] {
                let mut out = [0.0; 4];
                // SAFETY: `out` is four writable doubles.
                unsafe { _mm256_storeu_pd(out.as_mut_ptr(), self.0) };
                out
            }
            #[inline(always)]
            pub fn add(self, o: F4) -> F4 {
                F4(unsafe { _mm256_add_pd(self.0, o.0) })
            }
            #[inline(always)]
            pub fn mul(self, o: F4) -> F4 {
                F4(unsafe { _mm256_mul_pd(self.0, o.0) })
            }
            #[inline(always)]
            pub fn div(self, o: F4) -> F4 {
                F4(unsafe { _mm256_div_pd(self.0, o.0) })
            }
            #[inline(always)]
            pub fn sqrt(self) -> F4 {
                F4(unsafe { _mm256_sqrt_pd(self.0) })
            }
        }
    }

    #[cfg(not(all(target_arch = "x86_64", target_feature = "avx")))]
    mod imp {
        /// Four doubles.
        #[derive(Clone, Copy)]
        pub struct F4([f64; 4]);

        impl F4 {
            #[inline(always)]
            pub fn splat(v: f64) -> F4 {
                F4([v; 4])
            }
            #[inline(always)]
            pub fn load(a: &[f64; 4]) -> F4 {
                F4(*a)
            }
            #[inline(always)]
            pub fn to_array(self) -> [f64; 4] {
                self.0
            }
            #[inline(always)]
            pub fn add(self, o: F4) -> F4 {
                F4(std::array::from_fn(|i| self.0[i] + o.0[i]))
            }
            #[inline(always)]
            pub fn mul(self, o: F4) -> F4 {
                F4(std::array::from_fn(|i| self.0[i] * o.0[i]))
            }
            #[inline(always)]
            pub fn div(self, o: F4) -> F4 {
                F4(std::array::from_fn(|i| self.0[i] / o.0[i]))
            }
            #[inline(always)]
            pub fn sqrt(self) -> F4 {
                F4(self.0.map(f64::sqrt))
            }
        }
    }

    pub use imp::F4;
}

/// [`reduce_lanes`] with or without the Jacobian.
fn reduce(c: [f64; 3], jacobian: bool) -> (DVec3, DMat3) {
    if jacobian {
        reduce_lanes::<true>(c)
    } else {
        reduce_lanes::<false>(c)
    }
}

/// The inverse of S: S(x) = v for v ∈ (0, 1) at x = (v − ½)/√(v(1 − v)).
fn sigmoid_inverse(v: f64) -> f64 {
    (v - 0.5) / (v * (1.0 - v)).sqrt()
}

/// Fits coefficients to a target colour in [0, 1]³ (not all equal): Gauss–Newton on
/// ‖rgb(s) − target‖², walking from the grey of the same mean to the target in a few steps
/// (each solution starts the next fit, as pbrt-v4's table is filled outwards from grey), with
/// step halving whenever a step would not reduce the residual. Colours a sigmoid spectrum
/// cannot reach exactly (on the edge of the gamut) end at the nearest point found.
fn fit(target: DVec3) -> [f64; 3] {
    let mean = ((target.x + target.y + target.z) / 3.0).clamp(0.02, 0.98);
    let grey = DVec3::splat(mean);
    let mut c = [0.0, 0.0, sigmoid_inverse(mean)];
    const STEPS: u32 = 4;
    for step in 1..=STEPS {
        let goal = grey + (target - grey) * (step as f64 / STEPS as f64);
        c = gauss_newton(c, goal);
    }
    c
}

/// Coefficients with their colour and its Jacobian (which do not depend on the goal of a fit,
/// so a solution starts the next fit without reducing again).
#[derive(Clone, Copy)]
struct Solution {
    c: [f64; 3],
    rgb: DVec3,
    jac: DMat3,
}

impl Solution {
    fn at(c: [f64; 3]) -> Solution {
        let (rgb, jac) = reduce(c, true);
        Solution { c, rgb, jac }
    }
}

/// Gauss–Newton from coefficients `c` towards rgb(s) = `goal` (see [`gauss_newton_from`]).
fn gauss_newton(c: [f64; 3], goal: DVec3) -> [f64; 3] {
    gauss_newton_from(Solution::at(c), goal, 1e-14).c
}

/// Gauss–Newton from `start` towards rgb(s) = `goal`, at most `max_iterations` steps: each
/// step solves J·δ = −r (r = rgb(s) − goal, J its Jacobian) and is halved up to 12 times
/// until ‖r‖² decreases; stops when ‖r‖² < 10⁻¹⁴ or no step helps. A pure function of its
/// arguments.
fn gauss_newton_from(start: Solution, goal: DVec3, tolerance: f64) -> Solution {
    let max_iterations = 30;
    let mut sol = start;
    for _ in 0..max_iterations {
        let r = sol.rgb - goal;
        let err = r.length_squared();
        if err < tolerance {
            break;
        }
        if sol.jac.determinant().abs() < 1e-300 {
            break;
        }
        let delta = sol.jac.inverse() * -r;
        if !delta.is_finite() {
            break;
        }
        let mut scale = 1.0;
        let mut improved = false;
        for _ in 0..12 {
            let trial = Solution::at([
                sol.c[0] + scale * delta.x,
                sol.c[1] + scale * delta.y,
                sol.c[2] + scale * delta.z,
            ]);
            if (trial.rgb - goal).length_squared() < err {
                sol = trial;
                improved = true;
                break;
            }
            scale *= 0.5;
        }
        if !improved {
            break;
        }
    }
    sol
}

/// The sigmoid spectrum of a reflectance (clamped to [0, 1] first, as pbrt-v4's
/// `RGBAlbedoSpectrum` requires; NaN as 0). Greys, black and white are constant spectra.
pub fn fit_albedo(rgb: Rgb) -> SigmoidSpectrum {
    let rgb = clamp_albedo(rgb);
    if rgb.x == rgb.y && rgb.y == rgb.z {
        return SigmoidSpectrum::Constant(rgb.x);
    }
    SigmoidSpectrum::Poly(fit(rgb.as_dvec3()).map(|v| v as f32))
}

/// Grid points per axis of the coefficient table ([`CoefficientTable`]): 3 × 40³ fits, about
/// 0.3 s on two cores. On uniform random colours the worst error is 1.6·10⁻³ and the mean
/// 4.8·10⁻⁴ (at 32: 1.7·10⁻³ and 7.7·10⁻⁴; at 48, 0.5 s: 9·10⁻⁴ and 3.2·10⁻⁴).
pub const TABLE_RES: usize = 40;

/// ‖r‖² at which the table's fits stop: |r| < 10⁻⁶, far below the interpolation's error.
const TABLE_TOLERANCE: f64 = 1e-12;

/// Index along z of the slice each column of the table starts from (as rgb2spec_opt, a fifth
/// of the way up): fits walk from it to both ends.
const TABLE_START: usize = TABLE_RES / 5;

/// Range of the table's z (the largest component): black and white themselves would need
/// infinite coefficients; lookups clamp z into it (an error of at most 10⁻⁷).
const Z_MIN: f64 = 1e-7;
const Z_MAX: f64 = 1.0 - 1e-7;

/// The grid's x_i (and y_i) = smoothstep(i/(n−1)): denser near 0 (a component much smaller
/// than the largest: saturated colours) and near 1 (near-greys, and near-whites), where the
/// coefficients change fastest.
fn ratio_grid(i: usize) -> f64 {
    smoothstep(i as f64 / (TABLE_RES - 1) as f64)
}

/// φ(z) = S⁻¹(z) = (z − ½)/√(z(1 − z)) in single precision, for the table's z_k and its
/// lookups alike (so that a lookup at z_k has a fraction of exactly 0 or 1).
#[inline]
fn phi_f32(z: f32) -> f32 {
    (z - 0.5) / (z * (1.0 - z)).sqrt()
}

/// smoothstep(x) = x²(3 − 2x).
#[inline]
fn smoothstep(x: f64) -> f64 {
    x * x * (3.0 - 2.0 * x)
}

/// Coefficients of the sigmoid spectra of a grid over the colour cube, interpolated to uplift
/// any colour without a fit, after pbrt-v4's `RGBToSpectrumTable`.
///
/// A colour with largest component z = rgb[l] (l ∈ {0, 1, 2}) is placed at (l, z, x, y) with
/// x = rgb[(l+1) mod 3]/z and y = rgb[(l+2) mod 3]/z in [0, 1]. Each of the three blocks l has
/// n = [`TABLE_RES`] grid points per axis, denser where the coefficients change fastest:
///
/// - z_k = smoothstep(smoothstep(k/(n−1))) (pbrt-v4's spacing), kept inside
///   [10⁻⁷, 1 − 10⁻⁷], where colours near black and near white need large coefficients;
/// - x_i = smoothstep(i/(n−1)), likewise y_j (pbrt-v4 spaces them uniformly): near 0 lie
///   saturated colours, near 1 near-greys and near-whites. With uniform spacing the error
///   reaches 1.7·10⁻² near white at this resolution, and 3·10⁻³ at 64.
///
/// Each point holds the coefficients fitted to its colour. A lookup interpolates them
/// trilinearly, linearly in x and y, and along z linearly in φ(z) = S⁻¹(z) =
/// (z − ½)/√(z(1 − z)) rather than in z: φ(z) is exactly c₂ for a grey, and it follows the
/// growth of the coefficients towards black and white.
pub struct CoefficientTable {
    /// z_k, ascending from 0 to 1.
    z: [f32; TABLE_RES],
    /// φ(z_k).
    phi: [f32; TABLE_RES],
    /// x_i (and y_i), ascending from 0 to 1.
    ratio: [f32; TABLE_RES],
    /// Coefficients, at index ((l·n + k)·n + j)·n + i for z_k, x_i, y_j.
    coeffs: Vec<[f32; 3]>,
}

impl CoefficientTable {
    /// The grid's colour at (l, k, i, j): rgb[l] = z_k, rgb[(l+1) mod 3] = x_i·z_k,
    /// rgb[(l+2) mod 3] = y_j·z_k.
    fn grid_colour(z: f64, l: usize, i: usize, j: usize) -> DVec3 {
        let mut c = DVec3::ZERO;
        c[l] = z;
        c[(l + 1) % 3] = ratio_grid(i) * z;
        c[(l + 2) % 3] = ratio_grid(j) * z;
        c
    }

    /// Fits every grid point, in parallel over the 3n rows (l, j) of the grid.
    ///
    /// A row is filled by chains of warm-started Gauss–Newton fits (two or three iterations
    /// each, as in rgb2spec_opt): on the starting slice z_s (s = n/5) along x from x = 1 (the
    /// grey side, where the exact [`fit`]'s walk from grey starts the row) down to 0, and from
    /// each of those along z up to the last slice and down to the first. A fit stops at
    /// ‖r‖ < 10⁻⁶, far below the interpolation's error. Every entry is a pure function of its
    /// row, so the table is the same bit for bit whatever the number of threads.
    pub fn build() -> CoefficientTable {
        use rayon::prelude::*;
        let n = TABLE_RES;
        let z: [f64; TABLE_RES] = std::array::from_fn(|k| {
            smoothstep(smoothstep(k as f64 / (n - 1) as f64)).clamp(Z_MIN, Z_MAX)
        });
        // Each row (l, j): n² coefficient triples, indexed k·n + i.
        let rows: Vec<Vec<[f32; 3]>> = (0..3 * n)
            .into_par_iter()
            .map(|row| {
                let (l, j) = (row / n, row % n);
                let mut out = vec![[0.0f32; 3]; n * n];
                let mut start: Option<Solution> = None;
                let store = |s: &Solution| s.c.map(|v| v as f32);
                for i in (0..n).rev() {
                    let target = |k: usize| Self::grid_colour(z[k], l, i, j);
                    let s0 = match start {
                        None => Solution::at(fit(target(TABLE_START))),
                        Some(s) => gauss_newton_from(s, target(TABLE_START), TABLE_TOLERANCE),
                    };
                    start = Some(s0);
                    out[TABLE_START * n + i] = store(&s0);
                    let mut s = s0;
                    for k in TABLE_START + 1..n {
                        s = gauss_newton_from(s, target(k), TABLE_TOLERANCE);
                        out[k * n + i] = store(&s);
                    }
                    let mut s = s0;
                    for k in (0..TABLE_START).rev() {
                        s = gauss_newton_from(s, target(k), TABLE_TOLERANCE);
                        out[k * n + i] = store(&s);
                    }
                }
                out
            })
            .collect();
        let mut coeffs = vec![[0.0f32; 3]; 3 * n * n * n];
        for (row, values) in rows.iter().enumerate() {
            let (l, j) = (row / n, row % n);
            for k in 0..n {
                for i in 0..n {
                    coeffs[((l * n + k) * n + j) * n + i] = values[k * n + i];
                }
            }
        }
        CoefficientTable {
            z: z.map(|v| v as f32),
            phi: z.map(|v| phi_f32(v as f32)),
            ratio: std::array::from_fn(|i| ratio_grid(i) as f32),
            coeffs,
        }
    }

    /// The table of the process, built on first use (see [`CoefficientTable::build`]).
    pub fn get() -> &'static CoefficientTable {
        static TABLE: OnceLock<CoefficientTable> = OnceLock::new();
        TABLE.get_or_init(CoefficientTable::build)
    }

    /// The interpolated coefficients of a colour in [0, 1]³ that is not grey (so its largest
    /// component is positive).
    pub fn lookup(&self, rgb: Rgb) -> [f32; 3] {
        let n = TABLE_RES;
        let c = rgb.to_array();
        // The largest component, ties to the later one (as pbrt-v4).
        let l = if c[0] > c[1] {
            if c[0] > c[2] { 0 } else { 2 }
        } else if c[1] > c[2] {
            1
        } else {
            2
        };
        let z = c[l];
        let x = c[(l + 1) % 3] / z;
        let y = c[(l + 2) % 3] / z;
        // Cell and fraction along x or y: v between x_i and x_{i+1}.
        let cell = |v: f32| {
            let i = self.ratio.partition_point(|&r| r <= v).clamp(1, n - 1) - 1;
            (i, (v - self.ratio[i]) / (self.ratio[i + 1] - self.ratio[i]))
        };
        let (i, fx) = cell(x);
        let (j, fy) = cell(y);
        // Along z, the fraction is measured in φ(z) = S⁻¹(z) (exact for greys, whose
        // coefficients are (0, 0, φ(z)), and tame where φ grows without bound near 0 and 1).
        let z = z.clamp(Z_MIN as f32, Z_MAX as f32);
        let k = self.z.partition_point(|&zk| zk <= z).clamp(1, n - 1) - 1;
        let fz = (phi_f32(z) - self.phi[k]) / (self.phi[k + 1] - self.phi[k]);
        let at = |dk: usize, dj: usize, di: usize| {
            self.coeffs[((l * n + k + dk) * n + j + dj) * n + i + di]
        };
        let lerp =
            |a: [f32; 3], b: [f32; 3], t: f32| std::array::from_fn(|m| a[m] + (b[m] - a[m]) * t);
        let plane = |dk: usize| {
            lerp(
                lerp(at(dk, 0, 0), at(dk, 0, 1), fx),
                lerp(at(dk, 1, 0), at(dk, 1, 1), fx),
                fy,
            )
        };
        lerp(plane(0), plane(1), fz)
    }
}

/// A colour clamped to [0, 1], NaN taken as 0.
fn clamp_albedo(rgb: Rgb) -> Rgb {
    Rgb::from_array(
        rgb.to_array()
            .map(|v| if v.is_nan() { 0.0 } else { v.clamp(0.0, 1.0) }),
    )
}

/// The sigmoid spectrum of a reflectance for rendering: clamped to [0, 1] first (NaN as 0);
/// greys, black and white are constant spectra, every other colour is looked up in the
/// process's [`CoefficientTable`] (built on the first such colour).
pub fn albedo_spectrum(rgb: Rgb) -> SigmoidSpectrum {
    let rgb = clamp_albedo(rgb);
    if rgb.x == rgb.y && rgb.y == rgb.z {
        return SigmoidSpectrum::Constant(rgb.x);
    }
    SigmoidSpectrum::Poly(CoefficientTable::get().lookup(rgb))
}

/// An unbounded colour (components ≥ 0, negatives clamped) as pbrt-v4's
/// `RGBUnboundedSpectrum`: a scale 2m, m the largest component, and the albedo spectrum of
/// rgb/(2m). Evaluate as `scale · spectrum.eval(λ)`; black is scale 0.
pub fn unbounded_spectrum(rgb: Rgb) -> (f32, SigmoidSpectrum) {
    let rgb = rgb.max(Rgb::ZERO);
    let m = rgb.max_element();
    if m.is_nan() || m <= 0.0 || m.is_infinite() {
        return (0.0, SigmoidSpectrum::Constant(0.0));
    }
    let scale = 2.0 * m;
    (scale, albedo_spectrum(rgb / scale))
}

#[cfg(test)]
mod tests {
    use super::super::{Spectrum, SpectrumKind, spectrum_to_rgb};
    use super::*;

    /// The spectrum tabulated every 1 nm, reduced by the independent code of
    /// [`spectrum_to_rgb`] (this also checks `eval` with the f32 coefficients), and its
    /// extreme values.
    fn reduce_independently(s: &SigmoidSpectrum) -> (Rgb, f32, f32) {
        let lambda: Vec<f32> = (360..=830).map(|l| l as f32).collect();
        let values: Vec<f32> = lambda.iter().map(|&l| s.eval(l)).collect();
        let (lo, hi) = values
            .iter()
            .fold((f32::INFINITY, f32::NEG_INFINITY), |(a, b), &v| {
                (a.min(v), b.max(v))
            });
        let rgb = spectrum_to_rgb(
            &Spectrum::PiecewiseLinear { lambda, values },
            SpectrumKind::Unbounded,
        );
        (rgb, lo, hi)
    }

    #[test]
    fn albedo_spectra_reproduce_in_gamut_colours() {
        let grid = [0.05f32, 0.2, 0.35, 0.5, 0.65, 0.8, 0.95];
        let mut worst = 0.0f32;
        for &r in &grid {
            for &g in &grid {
                for &b in &grid {
                    let c = Rgb::new(r, g, b);
                    let s = fit_albedo(c);
                    let (back, lo, hi) = reduce_independently(&s);
                    let err = (back - c).abs().max_element();
                    worst = worst.max(err);
                    assert!(err <= 2e-3, "{c} came back as {back} ({s:?})");
                    assert!((0.0..=1.0).contains(&lo) && hi <= 1.0, "{c}: {lo}..{hi}");
                    // The fit's own reduction agrees with the independent one (greys are
                    // constants, whose independent reduction carries the ~1e-4 mismatch
                    // between the tabulated D65 white and the sRGB matrix's).
                    let d = (s.to_rgb() - back).abs().max_element();
                    assert!(d < 3e-4, "{c}: {} vs {back}", s.to_rgb());
                }
            }
        }
        println!("worst round-trip error {worst:.2e}");
    }

    #[test]
    fn saturated_colours_come_back_closely() {
        // The bitterli-coffee scene's orange plastic, and strong primaries and secondaries.
        for c in [
            Rgb::new(1.0, 0.379, 0.013),
            Rgb::new(0.9, 0.05, 0.05),
            Rgb::new(0.05, 0.8, 0.1),
            Rgb::new(0.05, 0.1, 0.9),
            Rgb::new(0.95, 0.9, 0.05),
        ] {
            let (back, lo, hi) = reduce_independently(&fit_albedo(c));
            assert!(
                (back - c).abs().max_element() <= 5e-3,
                "{c} came back as {back}"
            );
            assert!(lo >= 0.0 && hi <= 1.0);
        }
    }

    #[test]
    fn greys_are_constant_and_albedos_are_clamped() {
        assert_eq!(fit_albedo(Rgb::ZERO), SigmoidSpectrum::Constant(0.0));
        assert_eq!(fit_albedo(Rgb::ONE), SigmoidSpectrum::Constant(1.0));
        assert_eq!(fit_albedo(Rgb::splat(0.3)), SigmoidSpectrum::Constant(0.3));
        // Above 1 and below 0 are clamped first (pbrt's albedo spectra live in [0, 1]).
        assert_eq!(fit_albedo(Rgb::splat(1.7)), SigmoidSpectrum::Constant(1.0));
        assert_eq!(
            albedo_spectrum(Rgb::splat(-0.5)),
            SigmoidSpectrum::Constant(0.0)
        );
        assert_eq!(
            albedo_spectrum(Rgb::new(1.5, -0.2, f32::NAN)),
            albedo_spectrum(Rgb::new(1.0, 0.0, 0.0))
        );
        // Other colours come from the table.
        let c = Rgb::new(0.3, 0.6, 0.2);
        assert_eq!(
            albedo_spectrum(c),
            SigmoidSpectrum::Poly(CoefficientTable::get().lookup(c))
        );
    }

    /// A deterministic stream of numbers in [0, 1) (a 64-bit LCG's top 24 bits).
    fn uniforms(seed: u64) -> impl FnMut() -> f32 {
        let mut s = seed;
        move || {
            s = s
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            (s >> 40) as f32 / (1u64 << 24) as f32
        }
    }

    #[test]
    fn table_lookups_reproduce_colours_across_the_cube() {
        // Every colour of [0, 1]³ is within reach of a sigmoid spectrum to ~10⁻⁷ (exact fits of
        // this same set come back so), so the whole cube is the test set: uniform colours,
        // plus colours near the faces, edges and corners, where the coefficients grow fastest.
        let mut u = uniforms(7);
        let mut near_end = uniforms(11);
        let table = CoefficientTable::get();
        let (mut worst, mut sum, count) = (0.0f32, 0.0f64, 20_000);
        for n in 0..count {
            let mut c = Rgb::new(u(), u(), u());
            if n % 4 == 0 {
                // Push one or two components within 2 % of 0 or 1.
                for k in 0..(1 + n / 4 % 2) {
                    let v = 0.02 * near_end();
                    c[(n / 8 + k) % 3] = if near_end() < 0.5 { v } else { 1.0 - v };
                }
            }
            if c.x == c.y && c.y == c.z {
                continue;
            }
            let s = SigmoidSpectrum::Poly(table.lookup(c));
            let (back, lo, hi) = reduce_independently(&s);
            let err = (back - c).abs().max_element();
            // Near white (all components near 1) the coefficients grow like the inverse
            // square root of the distance to 1, and linear interpolation loses accuracy: a
            // looser bound in that corner only.
            let near_white = c.min_element() >= 0.85 && c.max_element() >= 0.98;
            let bound = if near_white { 4e-3 } else { 2e-3 };
            assert!(err <= bound, "{c} came back as {back} ({s:?})");
            assert!((0.0..=1.0).contains(&lo) && hi <= 1.0, "{c}: {lo}..{hi}");
            worst = worst.max(err);
            sum += err as f64;
        }
        let mean = sum / count as f64;
        // A table whose fits or interpolation had gone wrong anywhere would show here.
        assert!(mean < 8e-4, "mean error {mean:.2e}");
        println!("worst {worst:.2e}, mean {mean:.2e}");
        // Colours on the faces of the cube (a component exactly 0 or 1, as in 8-bit
        // textures), not all reachable exactly: the table gives what an exact fit gives.
        for c in [
            Rgb::new(1.0, 0.0, 0.0),
            Rgb::new(0.0, 1.0, 1.0),
            Rgb::new(1.0, 0.5, 0.2),
            Rgb::new(0.3, 1.0, 0.0),
            Rgb::new(0.0, 0.0, 0.4),
            Rgb::new(1.0, 1.0, 0.7),
            Rgb::new(0.9, 0.0, 1.0),
        ] {
            let table_rgb = SigmoidSpectrum::Poly(table.lookup(c)).to_rgb();
            let exact = fit_albedo(c).to_rgb();
            assert!(
                (table_rgb - exact).abs().max_element() <= 2e-3,
                "{c}: table {table_rgb}, exact fit {exact}"
            );
        }
        // The grid's own colours come back as closely as their fits.
        for (l, k, i, j) in [
            (0, 10, 3, 30),
            (1, 25, 39, 0),
            (2, 39, 20, 21),
            (0, 1, 5, 5),
        ] {
            let z = table.z[k] as f64;
            let c = CoefficientTable::grid_colour(z, l, i, j).as_vec3a();
            let back = SigmoidSpectrum::Poly(table.lookup(c)).to_rgb();
            assert!(
                (back - c).abs().max_element() < 1e-5,
                "{c} came back as {back}"
            );
        }
    }

    #[test]
    fn table_is_the_same_whatever_the_thread_count() {
        let build = |threads: usize| {
            rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap()
                .install(CoefficientTable::build)
        };
        let bits = |t: &CoefficientTable| -> Vec<u32> {
            t.coeffs.iter().flatten().map(|v| v.to_bits()).collect()
        };
        let one = bits(&build(1));
        assert_eq!(one.len(), 3 * 3 * TABLE_RES.pow(3));
        assert!(one == bits(&build(3)), "1 and 3 threads differ");
        assert!(
            one == bits(CoefficientTable::get()),
            "1 thread and the process's differ"
        );
    }

    #[test]
    fn unbounded_spectra_scale_by_twice_the_largest_component() {
        assert_eq!(unbounded_spectrum(Rgb::ZERO).0, 0.0);
        assert_eq!(unbounded_spectrum(Rgb::new(-1.0, f32::NAN, 0.0)).0, 0.0);
        for c in [
            Rgb::new(3.0, 1.5, 0.2),
            Rgb::new(0.2, 0.9, 1.1),
            Rgb::splat(2.5),
        ] {
            let (scale, s) = unbounded_spectrum(c);
            assert_eq!(scale, 2.0 * c.max_element());
            let (back, _, hi) = reduce_independently(&s);
            assert!(hi <= 1.0);
            let back = back * scale;
            assert!(
                (back - c).abs().max_element() <= 2e-3 * scale,
                "{c} came back as {back}"
            );
        }
    }
}

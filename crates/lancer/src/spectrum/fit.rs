//! Fitting sigmoid-polynomial spectra to colours (Jakob & Hanika 2019), one at a time or over
//! the grid of the RGB → spectrum coefficient table.
//!
//! A colour becomes the smooth spectrum
//!
//! s(λ) = S(c₀t² + c₁t + c₂),  t = (λ − 360 nm)/(830 nm − 360 nm),  S(x) = ½ + x/(2√(1 + x²)),
//!
//! whose three coefficients are fitted by Gauss–Newton so that the spectrum, seen under D65 and
//! reduced to linear sRGB as a reflectance is, reproduces the colour:
//!
//! rgb(s) = M_XYZ→sRGB · Σ_λ s(λ)·D65(λ)·(x̄, ȳ, z̄)(λ) / Σ_λ D65(λ)·ȳ(λ)  (1 nm steps).
//!
//! This file uses nothing but `std` and [`super::cie`]: the crate's build script includes both
//! to fit the table at compile time ([`fit_table`]), and the library uses the same code for
//! exact fits and to check the shipped table. Every step is plain IEEE arithmetic in a fixed
//! order (no fused operations, no dependence on threads), so a fit gives the same bits wherever
//! and however it is compiled.

use super::cie;

/// Three numbers: a colour, coefficients, or a column of a matrix.
pub type V3 = [f64; 3];
/// A 3×3 matrix as its three columns.
type M3 = [V3; 3];

fn sub(a: V3, b: V3) -> V3 {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

/// a · b, summed left to right.
fn dot(a: V3, b: V3) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// a × b = (a_y b_z − b_y a_z, a_z b_x − b_z a_x, a_x b_y − b_x a_y).
fn cross(a: V3, b: V3) -> V3 {
    [
        a[1] * b[2] - b[1] * a[2],
        a[2] * b[0] - b[2] * a[0],
        a[0] * b[1] - b[0] * a[1],
    ]
}

/// det M = m₀ · (m₁ × m₂) for columns m₀, m₁, m₂.
fn determinant(m: &M3) -> f64 {
    dot(m[0], cross(m[1], m[2]))
}

/// M⁻¹ v by the adjugate: row k of M⁻¹ is (m_{k+1} × m_{k+2}) / (m₀ · (m₁ × m₂)).
fn solve(m: &M3, v: V3) -> V3 {
    let rows = [cross(m[1], m[2]), cross(m[2], m[0]), cross(m[0], m[1])];
    let inv_det = 1.0 / dot(m[0], rows[0]);
    rows.map(|r| dot(r.map(|x| x * inv_det), v))
}

/// Lanes of the fit's inner loop: wavelengths are processed four at a time (one AVX2
/// register of f64), each lane with its own partial sums.
const LANES: usize = 4;

/// Groups of [`LANES`] wavelengths covering [`cie::INTEGRATION_RANGE`] (471 of them).
const GROUPS: usize = (830 - 360 + 1usize).div_ceil(LANES);

/// The fit's integration weights, by groups of [`LANES`] wavelengths (the last group padded
/// with zero weights): t(λ), and the rows of M_XYZ→sRGB · D65(λ)(x̄, ȳ, z̄)(λ) / Σ D65·ȳ, so
/// that rgb(s) = Σ_λ s(λ) · w(λ) directly.
struct FitWeights {
    t: [[f64; LANES]; GROUPS],
    w: [[[f64; LANES]; GROUPS]; 3],
}

impl FitWeights {
    /// The weights of the fit into the RGB space whose XYZ → RGB matrix has rows
    /// `xyz_to_rgb` (each component m₀·x + m₁·y + m₂·z, summed left to right, as
    /// [`cie::xyz_to_srgb`]).
    fn new(xyz_to_rgb: &[[f64; 3]; 3]) -> FitWeights {
        let lambdas = || cie::INTEGRATION_RANGE.map(f64::from);
        let d65_cmf: Vec<V3> = lambdas()
            .map(|l| cie::cmf(l).map(|v| v * cie::d65(l)))
            .collect();
        let d65_y = d65_cmf.iter().map(|c| c[1]).sum::<f64>();
        let mut fw = FitWeights {
            t: [[0.0; LANES]; GROUPS],
            w: [[[0.0; LANES]; GROUPS]; 3],
        };
        for (n, (l, wc)) in lambdas().zip(&d65_cmf).enumerate() {
            let (g, lane) = (n / LANES, n % LANES);
            fw.t[g][lane] = (l - cie::LAMBDA_MIN) / (cie::LAMBDA_MAX - cie::LAMBDA_MIN);
            let xyz = wc.map(|v| v / d65_y);
            let rgb = xyz_to_rgb.map(|m| m[0] * xyz[0] + m[1] * xyz[1] + m[2] * xyz[2]);
            for (w, v) in fw.w.iter_mut().zip(rgb) {
                w[g][lane] = v;
            }
        }
        fw
    }
}

/// rgb(s) for coefficients `c` (see the module documentation) and, when `JACOBIAN`, its
/// derivatives with respect to c₀, c₁, c₂ (the matrix's columns):
///
/// rgb = Σ_λ S(x)·w(λ),  ∂rgb/∂cₖ = Σ_λ S'(x)·t^{2−k}·w(λ),  x = (c₀t + c₁)t + c₂,
///
/// with S(x) = ½ + ½·x·r and S'(x) = ½·r³ for r = 1/√(1 + x²) (one square root and one
/// division per wavelength). This is the inner loop of every fit, written lane-wise so that
/// it vectorises.
fn reduce_lanes<const JACOBIAN: bool>(fw: &FitWeights, c: V3) -> (V3, M3) {
    use lanes::F4;
    let zero = F4::splat(0.0);
    let (one, half) = (F4::splat(1.0), F4::splat(0.5));
    let c = c.map(F4::splat);
    let mut rgb = [zero; 3];
    let mut d = [zero; 9];
    for g in 0..GROUPS {
        let t = F4::load(&fw.t[g]);
        let x = c[0].mul(t).add(c[1]).mul(t).add(c[2]);
        let r = one.div(one.add(x.mul(x)).sqrt());
        let s = half.add(half.mul(x).mul(r));
        let w = [
            F4::load(&fw.w[0][g]),
            F4::load(&fw.w[1][g]),
            F4::load(&fw.w[2][g]),
        ];
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
    let col = |a: usize| [sum(d[a]), sum(d[a + 1]), sum(d[a + 2])];
    (rgb.map(sum), [col(0), col(3), col(6)])
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
                F4([
                    self.0[0] + o.0[0],
                    self.0[1] + o.0[1],
                    self.0[2] + o.0[2],
                    self.0[3] + o.0[3],
                ])
            }
            #[inline(always)]
            pub fn mul(self, o: F4) -> F4 {
                F4([
                    self.0[0] * o.0[0],
                    self.0[1] * o.0[1],
                    self.0[2] * o.0[2],
                    self.0[3] * o.0[3],
                ])
            }
            #[inline(always)]
            pub fn div(self, o: F4) -> F4 {
                F4([
                    self.0[0] / o.0[0],
                    self.0[1] / o.0[1],
                    self.0[2] / o.0[2],
                    self.0[3] / o.0[3],
                ])
            }
            #[inline(always)]
            pub fn sqrt(self) -> F4 {
                F4(self.0.map(f64::sqrt))
            }
        }
    }

    pub use imp::F4;
}

/// Fits colours: the integration weights, computed once per fitter.
pub struct Fitter {
    weights: Box<FitWeights>,
}

/// Coefficients with their colour and its Jacobian (which do not depend on the goal of a fit,
/// so a solution starts the next fit without reducing again).
#[derive(Clone, Copy)]
struct Solution {
    c: V3,
    rgb: V3,
    jac: M3,
}

/// The inverse of S: S(x) = v for v ∈ (0, 1) at x = (v − ½)/√(v(1 − v)).
fn sigmoid_inverse(v: f64) -> f64 {
    (v - 0.5) / (v * (1.0 - v)).sqrt()
}

impl Default for Fitter {
    fn default() -> Fitter {
        Fitter::new()
    }
}

impl Fitter {
    /// A fitter into linear sRGB with its weights (a few microseconds).
    pub fn new() -> Fitter {
        Fitter::for_space(&cie::XYZ_TO_SRGB)
    }

    /// A fitter into the RGB space whose XYZ → RGB matrix has rows `xyz_to_rgb` (the colour
    /// still seen under D65).
    pub fn for_space(xyz_to_rgb: &[[f64; 3]; 3]) -> Fitter {
        Fitter {
            weights: Box::new(FitWeights::new(xyz_to_rgb)),
        }
    }

    /// rgb(s) of coefficients `c`: linear sRGB of the spectrum seen under D65.
    pub fn colour(&self, c: V3) -> V3 {
        reduce_lanes::<false>(&self.weights, c).0
    }

    fn at(&self, c: V3) -> Solution {
        let (rgb, jac) = reduce_lanes::<true>(&self.weights, c);
        Solution { c, rgb, jac }
    }

    /// Fits coefficients to a target colour in [0, 1]³ (not all equal): Gauss–Newton on
    /// ‖rgb(s) − target‖², walking from the grey of the same mean to the target in a few steps
    /// (each solution starts the next fit, as pbrt-v4's table is filled outwards from grey),
    /// with step halving whenever a step would not reduce the residual. Colours a sigmoid
    /// spectrum cannot reach exactly (on the edge of the gamut) end at the nearest point found.
    pub fn fit(&self, target: V3) -> V3 {
        let mean = ((target[0] + target[1] + target[2]) / 3.0).clamp(0.02, 0.98);
        let mut c = [0.0, 0.0, sigmoid_inverse(mean)];
        const STEPS: u32 = 4;
        for step in 1..=STEPS {
            let f = step as f64 / STEPS as f64;
            // goal = grey + (target − grey)·f.
            let goal = target.map(|t| mean + (t - mean) * f);
            c = self.gauss_newton(self.at(c), goal, 1e-14).c;
        }
        c
    }

    /// Gauss–Newton from `start` towards rgb(s) = `goal`, at most 30 steps: each step solves
    /// J·δ = −r (r = rgb(s) − goal, J its Jacobian) and is halved up to 12 times until ‖r‖²
    /// decreases; stops when ‖r‖² < `tolerance` or no step helps. A pure function of its
    /// arguments.
    fn gauss_newton(&self, start: Solution, goal: V3, tolerance: f64) -> Solution {
        let mut sol = start;
        for _ in 0..30 {
            let r = sub(sol.rgb, goal);
            let err = dot(r, r);
            if err < tolerance || determinant(&sol.jac).abs() < 1e-300 {
                break;
            }
            let delta = solve(&sol.jac, r.map(|v| -v));
            if !delta.iter().all(|v| v.is_finite()) {
                break;
            }
            let mut scale = 1.0;
            let mut improved = false;
            for _ in 0..12 {
                let trial = self.at(std::array::from_fn(|k| sol.c[k] + scale * delta[k]));
                let rt = sub(trial.rgb, goal);
                if dot(rt, rt) < err {
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
}

/// Grid points per axis of the coefficient table: 3 × 40³ fits. On uniform random colours
/// the worst error of the interpolated table is 1.6·10⁻³ and the mean 4.8·10⁻⁴ (at 32:
/// 1.7·10⁻³ and 7.7·10⁻⁴; at 48: 9·10⁻⁴ and 3.2·10⁻⁴).
pub const TABLE_RES: usize = 40;

/// Entries of the table: 3 blocks of [`TABLE_RES`]³ coefficient triples.
pub const TABLE_LEN: usize = 3 * TABLE_RES * TABLE_RES * TABLE_RES;

/// ‖r‖² at which the table's fits stop: |r| < 10⁻⁶, far below the interpolation's error.
const TABLE_TOLERANCE: f64 = 1e-12;

/// Index along z of the slice each row of the table starts from (as rgb2spec_opt, a fifth
/// of the way up): fits walk from it to both ends.
const TABLE_START: usize = TABLE_RES / 5;

/// Range of the table's z (the largest component): black and white themselves would need
/// infinite coefficients; lookups clamp z into it (an error of at most 10⁻⁷).
pub const Z_MIN: f64 = 1e-7;
/// See [`Z_MIN`].
pub const Z_MAX: f64 = 1.0 - 1e-7;

/// smoothstep(x) = x²(3 − 2x).
fn smoothstep(x: f64) -> f64 {
    x * x * (3.0 - 2.0 * x)
}

/// The table's x_i (and y_i) = smoothstep(i/(n−1)): denser near 0 (a component much smaller
/// than the largest: saturated colours) and near 1 (near-greys and near-whites), where the
/// coefficients change fastest.
pub fn ratio_grid(i: usize) -> f64 {
    smoothstep(i as f64 / (TABLE_RES - 1) as f64)
}

/// The table's z_k = smoothstep(smoothstep(k/(n−1))) (pbrt-v4's spacing), clamped to
/// [[`Z_MIN`], [`Z_MAX`]].
pub fn z_grid(k: usize) -> f64 {
    smoothstep(smoothstep(k as f64 / (TABLE_RES - 1) as f64)).clamp(Z_MIN, Z_MAX)
}

/// The grid's colour at (l, k, i, j): rgb[l] = z_k, rgb[(l+1) mod 3] = x_i·z_k,
/// rgb[(l+2) mod 3] = y_j·z_k.
pub fn grid_colour(l: usize, k: usize, i: usize, j: usize) -> V3 {
    let z = z_grid(k);
    let mut c = [0.0; 3];
    c[l] = z;
    c[(l + 1) % 3] = ratio_grid(i) * z;
    c[(l + 2) % 3] = ratio_grid(j) * z;
    c
}

/// Index of grid point (l, k, i, j) in the table: ((l·n + k)·n + j)·n + i.
pub fn table_index(l: usize, k: usize, i: usize, j: usize) -> usize {
    ((l * TABLE_RES + k) * TABLE_RES + j) * TABLE_RES + i
}

impl Fitter {
    /// The coefficients of row `row` = l·n + j of the table (all k and i, at index k·n + i).
    ///
    /// A row is filled by chains of warm-started Gauss–Newton fits (two or three iterations
    /// each, as in rgb2spec_opt): on the starting slice z_s (s = n/5) along x from x = 1 (the
    /// grey side, where the exact [`Fitter::fit`]'s walk from grey starts the row) down to 0,
    /// and from each of those along z up to the last slice and down to the first. A fit stops
    /// at ‖r‖ < 10⁻⁶. Every entry is a pure function of its row.
    pub fn table_row(&self, row: usize) -> Vec<[f32; 3]> {
        let n = TABLE_RES;
        let (l, j) = (row / n, row % n);
        let mut out = vec![[0.0f32; 3]; n * n];
        let mut start: Option<Solution> = None;
        let store = |s: &Solution| s.c.map(|v| v as f32);
        for i in (0..n).rev() {
            let target = |k: usize| grid_colour(l, k, i, j);
            let s0 = match start {
                None => self.at(self.fit(target(TABLE_START))),
                Some(s) => self.gauss_newton(s, target(TABLE_START), TABLE_TOLERANCE),
            };
            start = Some(s0);
            out[TABLE_START * n + i] = store(&s0);
            let mut s = s0;
            for k in TABLE_START + 1..n {
                s = self.gauss_newton(s, target(k), TABLE_TOLERANCE);
                out[k * n + i] = store(&s);
            }
            let mut s = s0;
            for k in (0..TABLE_START).rev() {
                s = self.gauss_newton(s, target(k), TABLE_TOLERANCE);
                out[k * n + i] = store(&s);
            }
        }
        out
    }
}

/// Fits the whole table on `threads` threads (rows dealt out in turn; the result does not
/// depend on the count): [`TABLE_LEN`] coefficient triples at [`table_index`], for the RGB
/// space whose XYZ → RGB matrix has rows `xyz_to_rgb` (D65 white).
pub fn fit_table(threads: usize, xyz_to_rgb: &[[f64; 3]; 3]) -> Vec<[f32; 3]> {
    let n = TABLE_RES;
    let rows = 3 * n;
    let threads = threads.clamp(1, rows);
    let fitted: Vec<(usize, Vec<[f32; 3]>)> = std::thread::scope(|scope| {
        let workers: Vec<_> = (0..threads)
            .map(|t| {
                scope.spawn(move || {
                    let fitter = Fitter::for_space(xyz_to_rgb);
                    (t..rows)
                        .step_by(threads)
                        .map(|row| (row, fitter.table_row(row)))
                        .collect::<Vec<_>>()
                })
            })
            .collect();
        workers
            .into_iter()
            .flat_map(|w| w.join().expect("a table-fitting thread panicked"))
            .collect()
    });
    let mut coeffs = vec![[0.0f32; 3]; TABLE_LEN];
    for (row, values) in fitted {
        let (l, j) = (row / n, row % n);
        for k in 0..n {
            for i in 0..n {
                coeffs[table_index(l, k, i, j)] = values[k * n + i];
            }
        }
    }
    coeffs
}

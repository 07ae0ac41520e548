//! Piecewise-bilinear densities over [0, 1]², optionally depending on extra parameters (as
//! pbrt-v4's `PiecewiseLinear2D`, after Jakob's implementation for Dupuy & Jakob 2018, "An
//! adaptive parameterization for efficient material acquisition and rendering").
//!
//! A table holds values v at the nodes of an n_x × n_y grid over [0, 1]² (node (i, j) at
//! (i/(n_x − 1), j/(n_y − 1))), one such slice per combination of the parameters' node
//! values. Between nodes the function is bilinear; between parameter nodes the slices are
//! blended linearly (outside the parameter range, clamped to the end slices).
//!
//! A *sampled* table is normalised, per slice, so that the bilinear function integrates to 1
//! over [0, 1]²; sampling it first picks a row from the marginal density (linear in y within a
//! row of patches, inverted in closed form: with r₀, r₁ the integrals over x of the rows at
//! the patch's two ends and s the remaining sample, t solves r₀t + (r₁ − r₀)t²/2 = s), then a
//! column from the conditional density at that y (linear in x within a patch, inverted the
//! same way). [`Linear2D::invert`] undoes [`Linear2D::sample`]. A *plain* table is only
//! interpolated ([`Linear2D::eval`] gives the raw values).

/// The slices blended at one set of parameter values: up to 2^D slices and their
/// weights (D ≤ 3 here: 8 corners).
#[derive(Clone, Copy, Debug)]
struct Corners {
    n: usize,
    slice: [usize; 8],
    weight: [f32; 8],
}

/// Parameters a table may depend on, at most.
pub const MAX_PARAMS: usize = 3;

/// A piecewise-bilinear function or density over [0, 1]² (see the module documentation).
#[derive(Clone, Debug, PartialEq)]
pub struct Linear2D {
    nx: usize,
    ny: usize,
    /// Node values of each parameter, outermost first (the slices are stored row-major in
    /// that order, the last parameter varying fastest).
    params: Vec<Vec<f32>>,
    /// Slice index stride of each parameter (0 for a parameter with a single node).
    strides: Vec<usize>,
    /// Node values, per slice (normalised for a sampled table).
    data: Vec<f32>,
    /// Per slice: the running integral over rows, `ny` entries (sampled tables only).
    marginal: Vec<f32>,
    /// Per slice and row: the running integral along x, `nx` entries a row (sampled only).
    conditional: Vec<f32>,
    /// What [`Linear2D::eval`] multiplies the bilinear value by: (n_x − 1)(n_y − 1) for a
    /// sampled table (its density over [0, 1]²), 1 for a plain one.
    scale: f32,
}

/// pbrt-v4's `FindInterval`: the largest i in [0, n − 2] with `pred(i)` true, for a `pred`
/// true up to some index and false after it (0 when it is false everywhere).
#[inline]
fn find_interval(n: usize, pred: impl Fn(usize) -> bool) -> usize {
    let (mut first, mut size) = (1usize, n.saturating_sub(2));
    while size > 0 {
        let half = size >> 1;
        let middle = first + half;
        if pred(middle) {
            first = middle + 1;
            size -= half + 1;
        } else {
            size = half;
        }
    }
    first.saturating_sub(1).min(n.saturating_sub(2))
}

/// The t ∈ [0, 1] with r₀t + (r₁ − r₀)t²/2 = s: the inverse of the running integral of a
/// density linear from r₀ to r₁ over [0, 1] (2s/(r₀ + r₁) when it is nearly constant).
#[inline]
fn invert_linear(r0: f32, r1: f32, s: f32) -> f32 {
    if (r0 - r1).abs() < 1e-4 * (r0 + r1) {
        2.0 * s / (r0 + r1)
    } else {
        (r0 - (r0 * r0 - 2.0 * s * (r0 - r1)).max(0.0).sqrt()) / (r0 - r1)
    }
}

impl Linear2D {
    /// A table of `nx` × `ny` node values per slice (x fastest), one slice per combination of
    /// `params`' node values (row-major, the last parameter fastest). `sampled` normalises
    /// each slice to a density and prepares sampling; otherwise values are kept as given.
    /// The caller checks the sizes (n_x, n_y ≥ 2; `data` holds every slice; each parameter's
    /// nodes ascend); a slice that is zero everywhere is sampled uniformly.
    pub fn new(data: &[f32], nx: usize, ny: usize, params: Vec<Vec<f32>>, sampled: bool) -> Self {
        assert!(nx >= 2 && ny >= 2 && params.len() <= MAX_PARAMS);
        let mut strides = vec![0; params.len()];
        let mut slices = 1;
        for (d, p) in params.iter().enumerate().rev() {
            strides[d] = if p.len() > 1 { slices } else { 0 };
            slices *= p.len();
        }
        let n = nx * ny;
        assert_eq!(data.len(), slices * n);
        let mut t = Linear2D {
            nx,
            ny,
            params,
            strides,
            data: data.to_vec(),
            marginal: Vec::new(),
            conditional: Vec::new(),
            scale: 1.0,
        };
        if !sampled {
            return t;
        }
        t.scale = ((nx - 1) * (ny - 1)) as f32;
        t.marginal = vec![0.0; slices * ny];
        t.conditional = vec![0.0; slices * n];
        for s in 0..slices {
            let v = &mut t.data[s * n..(s + 1) * n];
            let cond = &mut t.conditional[s * n..(s + 1) * n];
            let marg = &mut t.marginal[s * ny..(s + 1) * ny];
            // Trapezoids: the exact integrals of the piecewise-linear rows (in units of one
            // patch), then of the row integrals over y.
            let fill = |v: &[f32], cond: &mut [f32], marg: &mut [f32]| {
                for y in 0..ny {
                    let mut sum = 0.0f64;
                    cond[y * nx] = 0.0;
                    for x in 0..nx - 1 {
                        sum += 0.5 * (v[y * nx + x] as f64 + v[y * nx + x + 1] as f64);
                        cond[y * nx + x + 1] = sum as f32;
                    }
                }
                let mut sum = 0.0f64;
                marg[0] = 0.0;
                for y in 0..ny - 1 {
                    sum +=
                        0.5 * (cond[y * nx + nx - 1] as f64 + cond[(y + 1) * nx + nx - 1] as f64);
                    marg[y + 1] = sum as f32;
                }
                sum
            };
            let mut total = fill(v, cond, marg);
            if !(total > 0.0 && total.is_finite()) {
                v.fill(1.0);
                total = fill(v, cond, marg);
            }
            let k = (1.0 / total) as f32;
            v.iter_mut().for_each(|x| *x *= k);
            cond.iter_mut().for_each(|x| *x *= k);
            marg.iter_mut().for_each(|x| *x *= k);
        }
        t
    }

    /// Number of parameters the table depends on.
    pub fn n_params(&self) -> usize {
        self.params.len()
    }

    /// Bytes of the tables.
    pub fn memory_bytes(&self) -> usize {
        4 * (self.data.len()
            + self.marginal.len()
            + self.conditional.len()
            + self.params.iter().map(Vec::len).sum::<usize>())
    }

    /// The slices to blend at parameter values `param` and their weights.
    #[inline]
    fn corners(&self, param: &[f32]) -> Corners {
        let mut c = Corners {
            n: 1,
            slice: [0; 8],
            weight: [1.0; 8],
        };
        for (d, nodes) in self.params.iter().enumerate() {
            if nodes.len() == 1 {
                continue;
            }
            let x = param[d];
            let i = find_interval(nodes.len(), |k| nodes[k] <= x);
            let (p0, p1) = (nodes[i], nodes[i + 1]);
            let w1 = ((x - p0) / (p1 - p0)).clamp(0.0, 1.0);
            let base = self.strides[d] * i;
            let n = c.n;
            for k in 0..n {
                c.slice[n + k] = c.slice[k] + base + self.strides[d];
                c.weight[n + k] = c.weight[k] * w1;
                c.slice[k] += base;
                c.weight[k] *= 1.0 - w1;
            }
            c.n *= 2;
        }
        c
    }

    /// Entry `i` of a per-slice table of `per_slice` entries, blended over the corners.
    #[inline]
    fn at(table: &[f32], per_slice: usize, c: &Corners, i: usize) -> f32 {
        let mut v = 0.0;
        for k in 0..c.n {
            v += c.weight[k] * table[c.slice[k] * per_slice + i];
        }
        v
    }

    /// The value at `pos` ∈ [0, 1]² for parameter values `param` (one per parameter): the
    /// bilinear interpolant of the blended slices; for a sampled table, the density.
    pub fn eval(&self, pos: [f32; 2], param: &[f32]) -> f32 {
        let c = self.corners(param);
        let (nx, ny) = (self.nx, self.ny);
        let fx = pos[0].clamp(0.0, 1.0) * (nx - 1) as f32;
        let fy = pos[1].clamp(0.0, 1.0) * (ny - 1) as f32;
        let (ix, iy) = ((fx as usize).min(nx - 2), (fy as usize).min(ny - 2));
        let (wx, wy) = (fx - ix as f32, fy - iy as f32);
        let n = nx * ny;
        let i = iy * nx + ix;
        let d = |o: usize| Self::at(&self.data, n, &c, i + o);
        let (v00, v10, v01, v11) = (d(0), d(1), d(nx), d(nx + 1));
        ((1.0 - wy) * ((1.0 - wx) * v00 + wx * v10) + wy * ((1.0 - wx) * v01 + wx * v11))
            * self.scale
    }

    /// Warps a uniform `u` ∈ [0, 1)² to a point distributed as the (sampled) table at
    /// `param`; returns it and its density.
    pub fn sample(&self, u: [f32; 2], param: &[f32]) -> ([f32; 2], f32) {
        let c = self.corners(param);
        let (nx, ny) = (self.nx, self.ny);
        let n = nx * ny;
        let lo = f32::EPSILON / 2.0;
        let (ux, mut uy) = (u[0].clamp(lo, 1.0 - lo), u[1].clamp(lo, 1.0 - lo));
        // Row: the marginal's interval holding uy, then t within it.
        let marg = |j: usize| Self::at(&self.marginal, ny, &c, j);
        let row = find_interval(ny, |j| marg(j) < uy);
        uy -= marg(row);
        let cond = |i: usize| Self::at(&self.conditional, n, &c, i);
        let r0 = cond(row * nx + nx - 1);
        let r1 = cond((row + 1) * nx + nx - 1);
        let ty = invert_linear(r0, r1, uy);
        // Column: the conditional at y = row + ty, then s within the patch.
        let mut sx = ux * ((1.0 - ty) * r0 + ty * r1);
        let cond_at = |i: usize| (1.0 - ty) * cond(row * nx + i) + ty * cond((row + 1) * nx + i);
        let col = find_interval(nx, |i| cond_at(i) < sx);
        sx -= cond_at(col);
        let i = row * nx + col;
        let d = |o: usize| Self::at(&self.data, n, &c, i + o);
        let c0 = (1.0 - ty) * d(0) + ty * d(nx);
        let c1 = (1.0 - ty) * d(1) + ty * d(nx + 1);
        let tx = invert_linear(c0, c1, sx);
        let p = [
            (col as f32 + tx) / (nx - 1) as f32,
            (row as f32 + ty) / (ny - 1) as f32,
        ];
        (p, ((1.0 - tx) * c0 + tx * c1) * self.scale)
    }

    /// The inverse of [`Linear2D::sample`]: the uniform point that warps to `p`, and the
    /// density at `p`.
    pub fn invert(&self, p: [f32; 2], param: &[f32]) -> ([f32; 2], f32) {
        let c = self.corners(param);
        let (nx, ny) = (self.nx, self.ny);
        let n = nx * ny;
        let fx = p[0].clamp(0.0, 1.0) * (nx - 1) as f32;
        let fy = p[1].clamp(0.0, 1.0) * (ny - 1) as f32;
        let (col, row) = ((fx as usize).min(nx - 2), (fy as usize).min(ny - 2));
        let (tx, ty) = (fx - col as f32, fy - row as f32);
        let i = row * nx + col;
        let d = |o: usize| Self::at(&self.data, n, &c, i + o);
        let c0 = (1.0 - ty) * d(0) + ty * d(nx);
        let c1 = (1.0 - ty) * d(1) + ty * d(nx + 1);
        let pdf = ((1.0 - tx) * c0 + tx * c1) * self.scale;
        let cond = |i: usize| Self::at(&self.conditional, n, &c, i);
        // x: the running integral up to the patch, plus the part of the patch up to tx.
        let mut ux = tx * (c0 + 0.5 * tx * (c1 - c0));
        ux += (1.0 - ty) * cond(i) + ty * cond(i + nx);
        let r0 = cond(row * nx + nx - 1);
        let r1 = cond((row + 1) * nx + nx - 1);
        ux /= (1.0 - ty) * r0 + ty * r1;
        let uy = ty * (r0 + 0.5 * ty * (r1 - r0)) + Self::at(&self.marginal, ny, &c, row);
        ([ux, uy], pdf)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::Pcg32;

    /// A 3 × 2 table f(x, y) = 1 + 2x + y (bilinear, so represented exactly), and a second
    /// slice 2 − x, blended by one parameter with nodes 0 and 1.
    fn table() -> Linear2D {
        let f = |x: f32, y: f32| 1.0 + 2.0 * x + y;
        let g = |x: f32, _y: f32| 2.0 - x;
        let mut data = Vec::new();
        for h in [f, g] {
            for y in [0.0, 1.0] {
                for x in [0.0, 0.5, 1.0] {
                    data.push(h(x, y));
                }
            }
        }
        Linear2D::new(&data, 3, 2, vec![vec![0.0, 1.0]], true)
    }

    #[test]
    fn densities_are_the_normalised_functions_blended() {
        let t = table();
        // ∫f = 1 + 1 + 0.5 = 2.5, ∫g = 1.5.
        assert!((t.eval([0.3, 0.7], &[0.0]) - (1.0 + 0.6 + 0.7) / 2.5).abs() < 1e-6);
        assert!((t.eval([0.3, 0.7], &[1.0]) - 1.7 / 1.5).abs() < 1e-6);
        // Halfway: the average of the two densities; clamped outside [0, 1].
        let mid = 0.5 * (2.3 / 2.5 + 1.7 / 1.5);
        assert!((t.eval([0.3, 0.7], &[0.5]) - mid).abs() < 1e-6);
        assert_eq!(t.eval([0.3, 0.7], &[7.0]), t.eval([0.3, 0.7], &[1.0]));
        let plain = Linear2D::new(&[1.0, 3.0, 5.0, 7.0], 2, 2, vec![], false);
        // Rows 1 → 3 and 5 → 7: 1.5 and 5.5 at x = 0.25, halfway 3.5.
        assert!((plain.eval([0.25, 0.5], &[]) - 3.5).abs() < 1e-6);
    }

    #[test]
    fn sampling_inverts_and_matches_the_density() {
        let t = table();
        let mut rng = Pcg32::new(7, 0);
        // Histogram over a 4 × 4 grid against the density's cell integrals.
        for param in [0.0, 0.3, 1.0] {
            let n = 200_000;
            let mut hist = [0.0f64; 16];
            for _ in 0..n {
                let u = [rng.uniform(), rng.uniform()];
                let (p, pdf) = t.sample(u, &[param]);
                assert!((pdf - t.eval(p, &[param])).abs() < 1e-4 * pdf.max(1.0));
                let (back, pdf2) = t.invert(p, &[param]);
                assert!((back[0] - u[0]).abs() < 1e-3 && (back[1] - u[1]).abs() < 1e-3);
                assert!((pdf - pdf2).abs() < 1e-4);
                let (i, j) = ((p[0] * 4.0) as usize, (p[1] * 4.0) as usize);
                hist[j.min(3) * 4 + i.min(3)] += 1.0;
            }
            for (k, h) in hist.iter().enumerate() {
                let (i, j) = ((k % 4) as f32, (k / 4) as f32);
                // Midpoint rule on 8 × 8 sub-cells: exact enough for a bilinear density.
                let mut e = 0.0;
                for a in 0..8 {
                    for b in 0..8 {
                        let x = (i + (a as f32 + 0.5) / 8.0) / 4.0;
                        let y = (j + (b as f32 + 0.5) / 8.0) / 4.0;
                        e += t.eval([x, y], &[param]) as f64 / (64.0 * 16.0);
                    }
                }
                let expect = e * n as f64;
                assert!(
                    (h - expect).abs() < 5.0 * expect.sqrt(),
                    "{param} {k}: {h} vs {expect}"
                );
            }
        }
    }

    #[test]
    fn intervals_are_found_as_pbrt_finds_them() {
        let v = [0.0, 1.0, 2.0, 3.0];
        assert_eq!(find_interval(4, |i| v[i] <= -1.0), 0);
        assert_eq!(find_interval(4, |i| v[i] <= 1.5), 1);
        assert_eq!(find_interval(4, |i| v[i] <= 3.0), 2);
        assert_eq!(find_interval(4, |i| v[i] <= 9.0), 2);
        assert_eq!(find_interval(2, |_| true), 0);
    }
}

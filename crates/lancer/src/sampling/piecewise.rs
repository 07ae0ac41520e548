//! Piecewise-constant distributions in 1D and 2D: sampling in proportion to a tabulated
//! function, as environment lights sample their image.
//!
//! In 1D, over [0, 1] cut into n equal cells of values f₀ … fₙ₋₁ (absolute values), the
//! density is p(x) = f_i / I where x lies in cell i and I = Σ f_i / n; sampling inverts the
//! running sums (the CDF, linear inside each cell). In 2D, over [0, 1]² with n_u × n_v cells,
//! p(u, v) = f(u, v) / I = p(v) · p(u | v): a marginal distribution over rows (each row weighted
//! by its integral) and one conditional distribution per row.
//!
//! A function that is zero everywhere gives the uniform distribution, so sampling never fails.

/// A piecewise-constant density over [0, 1].
#[derive(Clone, Debug, PartialEq)]
pub struct PiecewiseConstant1D {
    /// |f_i|.
    func: Vec<f32>,
    /// cdf[0] = 0, cdf[i + 1] = cdf[i] + f_i / (n·I), cdf[n] = 1.
    cdf: Vec<f32>,
    /// I = Σ f_i / n (0 for a zero function, which is then sampled uniformly).
    integral: f32,
}

impl PiecewiseConstant1D {
    /// Bytes of the tables (capacity included).
    pub fn memory_bytes(&self) -> usize {
        (self.func.capacity() + self.cdf.capacity()) * std::mem::size_of::<f32>()
    }

    /// The distribution proportional to |f| (uniform when f is zero or empty of finite mass).
    pub fn new(f: &[f32]) -> PiecewiseConstant1D {
        let n = f.len().max(1);
        let func: Vec<f32> = if f.is_empty() {
            vec![0.0]
        } else {
            f.iter()
                .map(|v| if v.is_finite() { v.abs() } else { 0.0 })
                .collect()
        };
        let mut cdf = Vec::with_capacity(n + 1);
        cdf.push(0.0f32);
        let mut sum = 0.0f64;
        let mut sums = Vec::with_capacity(n);
        for &v in &func {
            sum += v as f64 / n as f64;
            sums.push(sum);
        }
        let integral = sum;
        if integral > 0.0 {
            cdf.extend(sums.iter().map(|&s| (s / integral) as f32));
        } else {
            cdf.extend((1..=n).map(|i| i as f32 / n as f32));
        }
        cdf[n] = 1.0;
        PiecewiseConstant1D {
            func,
            cdf,
            integral: integral as f32,
        }
    }

    /// Number of cells.
    #[inline]
    pub fn len(&self) -> usize {
        self.func.len()
    }

    /// Always false: there is at least one cell.
    #[inline]
    pub fn is_empty(&self) -> bool {
        self.func.is_empty()
    }

    /// I = ∫₀¹ |f|.
    #[inline]
    pub fn integral(&self) -> f32 {
        self.integral
    }

    /// Density at `x` ∈ [0, 1]: f_i / I (1 for a zero function, sampled uniformly).
    #[inline]
    pub fn pdf(&self, x: f32) -> f32 {
        let i = ((x * self.len() as f32) as usize).min(self.len() - 1);
        self.cell_pdf(i)
    }

    #[inline]
    fn cell_pdf(&self, i: usize) -> f32 {
        if self.integral > 0.0 {
            self.func[i] / self.integral
        } else {
            1.0
        }
    }

    /// Samples x ∈ [0, 1) for `u` ∈ [0, 1): the cell i with cdf[i] ≤ u < cdf[i + 1], then
    /// x = (i + (u − cdf[i]) / (cdf[i + 1] − cdf[i])) / n. Returns x, its density and i.
    #[inline]
    pub fn sample(&self, u: f32) -> (f32, f32, usize) {
        let n = self.len();
        // Last i with cdf[i] ≤ u, among 0..n; cells of zero mass (cdf[i] = cdf[i + 1]) are
        // skipped since the search lands on the last of equal values.
        let i = (self.cdf.partition_point(|&c| c <= u).max(1) - 1).min(n - 1);
        let width = self.cdf[i + 1] - self.cdf[i];
        let du = if width > 0.0 {
            ((u - self.cdf[i]) / width).clamp(0.0, 1.0)
        } else {
            0.0
        };
        // Keep x inside the cell (and below 1) despite rounding.
        let x =
            ((i as f32 + du) / n as f32).min((i as f32 + 1.0) / n as f32 * (1.0 - f32::EPSILON));
        (x, self.cell_pdf(i), i)
    }
}

/// A piecewise-constant density over [0, 1]², from an `nu × nv` table in row-major order
/// (`f[v·nu + u]`, rows along v).
#[derive(Clone, Debug, PartialEq)]
pub struct PiecewiseConstant2D {
    /// p(u | v), one per row.
    conditional: Vec<PiecewiseConstant1D>,
    /// p(v), from the rows' integrals.
    marginal: PiecewiseConstant1D,
}

impl PiecewiseConstant2D {
    /// Bytes of the tables (capacity included).
    pub fn memory_bytes(&self) -> usize {
        self.conditional.capacity() * std::mem::size_of::<PiecewiseConstant1D>()
            + self
                .conditional
                .iter()
                .map(PiecewiseConstant1D::memory_bytes)
                .sum::<usize>()
            + self.marginal.memory_bytes()
    }

    /// The distribution proportional to |f| over an `nu × nv` grid; `None` when the table's
    /// length is not `nu·nv` or a side is 0.
    pub fn new(f: &[f32], nu: usize, nv: usize) -> Option<PiecewiseConstant2D> {
        if nu == 0 || nv == 0 || f.len() != nu * nv {
            return None;
        }
        let conditional: Vec<PiecewiseConstant1D> =
            f.chunks_exact(nu).map(PiecewiseConstant1D::new).collect();
        let rows: Vec<f32> = conditional.iter().map(|c| c.integral()).collect();
        Some(PiecewiseConstant2D {
            conditional,
            marginal: PiecewiseConstant1D::new(&rows),
        })
    }

    /// I = ∫∫ |f| du dv.
    #[inline]
    pub fn integral(&self) -> f32 {
        self.marginal.integral()
    }

    /// Samples (u, v) ∈ [0, 1)² from two uniform numbers: v from the marginal with `u.y`, then
    /// u from that row's conditional with `u.x`. Returns the point and its density.
    #[inline]
    pub fn sample(&self, u: crate::math::Vec2) -> (crate::math::Vec2, f32) {
        let (v, pdf_v, row) = self.marginal.sample(u.y);
        let (x, pdf_u, _) = self.conditional[row].sample(u.x);
        (crate::math::Vec2::new(x, v), pdf_u * pdf_v)
    }

    /// Density at (u, v) ∈ [0, 1]²: f(u, v) / I.
    #[inline]
    pub fn pdf(&self, p: crate::math::Vec2) -> f32 {
        let nv = self.conditional.len();
        let row = ((p.y * nv as f32) as usize).min(nv - 1);
        self.marginal.cell_pdf(row) * self.conditional[row].pdf(p.x)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::Vec2;
    use crate::sampling::hash::{hash_u64, u32_to_unit_f32};

    fn rand2(i: u64) -> Vec2 {
        let h = hash_u64(&[i]);
        Vec2::new(u32_to_unit_f32(h as u32), u32_to_unit_f32((h >> 32) as u32))
    }

    #[test]
    fn one_d_inverts_its_cdf() {
        let d = PiecewiseConstant1D::new(&[1.0, 0.0, 3.0]);
        assert!((d.integral() - 4.0 / 3.0).abs() < 1e-6);
        // Cell 0 holds a quarter of the mass, cell 1 none, cell 2 three quarters.
        let (x, pdf, i) = d.sample(0.125);
        assert_eq!(i, 0);
        assert!((x - 1.0 / 6.0).abs() < 1e-6 && (pdf - 0.75).abs() < 1e-6);
        let (x, pdf, i) = d.sample(0.25);
        assert_eq!(i, 2, "the empty cell is skipped");
        assert!((x - 2.0 / 3.0).abs() < 1e-6 && (pdf - 2.25).abs() < 1e-6);
        let (x, _, i) = d.sample(0.999_999_9);
        assert!(i == 2 && x < 1.0);
        assert_eq!(d.pdf(0.5), 0.0);
        // A zero function is uniform.
        let z = PiecewiseConstant1D::new(&[0.0, 0.0]);
        assert_eq!(z.pdf(0.3), 1.0);
        assert!((z.sample(0.75).0 - 0.75).abs() < 1e-6);
    }

    #[test]
    fn two_d_samples_follow_the_table() {
        // A 6 × 4 table with a zero cell, a bright cell and a zero row.
        let (nu, nv) = (6usize, 4usize);
        let mut f: Vec<f32> = (0..nu * nv).map(|i| 1.0 + (i % 5) as f32).collect();
        f[3] = 0.0;
        f[8] = 40.0;
        for u in 0..nu {
            f[2 * nu + u] = 0.0;
        }
        let d = PiecewiseConstant2D::new(&f, nu, nv).unwrap();
        let total: f32 = f.iter().sum();
        assert!((d.integral() - total / (nu * nv) as f32).abs() < 1e-4);
        let n = 200_000u64;
        let mut counts = vec![0.0f64; nu * nv];
        for i in 0..n {
            let (p, pdf) = d.sample(rand2(i));
            assert!(
                (0.0..1.0).contains(&p.x) && (0.0..1.0).contains(&p.y),
                "{p}"
            );
            let cell = (p.y * nv as f32) as usize * nu + (p.x * nu as f32) as usize;
            assert!(f[cell] > 0.0, "sampled an empty cell");
            // The density returned matches pdf() and f / I.
            assert!((pdf - d.pdf(p)).abs() <= 1e-5 * pdf);
            assert!((pdf - f[cell] / d.integral()).abs() <= 1e-4 * pdf);
            counts[cell] += 1.0;
        }
        // The density integrates to 1.
        // (A midpoint sum on a grid finer than the cells and aligned with them.)
        let (mu, mv) = (10 * nu, 10 * nv);
        let integral: f32 = (0..mu * mv)
            .map(|k| {
                let p = Vec2::new(
                    ((k % mu) as f32 + 0.5) / mu as f32,
                    ((k / mu) as f32 + 0.5) / mv as f32,
                );
                d.pdf(p)
            })
            .sum::<f32>()
            / (mu * mv) as f32;
        assert!((integral - 1.0).abs() < 1e-3, "{integral}");
        assert!(PiecewiseConstant2D::new(&f, 5, 4).is_none());
    }
}

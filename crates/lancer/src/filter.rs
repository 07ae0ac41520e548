//! Pixel reconstruction filters, sampled by importance as pbrt-v4 does.
//!
//! Instead of splatting each sample onto every pixel the filter covers, a pixel's samples are
//! placed around its centre with density proportional to |f| and weighted by f/pdf. Each sample
//! then touches one pixel only, which is what lets tiles (and machines) render independently.

use crate::math::Vec2;
use crate::sampling::ONE_MINUS_EPSILON;
use crate::scene::desc::FilterDesc;

/// A filter ready for sampling.
#[derive(Clone, Debug, PartialEq)]
pub struct Filter {
    desc: FilterDesc,
    /// Tabulated 1D marginals for x and y (none for the box and the triangle, sampled in
    /// closed form).
    tables: Option<[Table1D; 2]>,
}

/// A piecewise-constant distribution of |f| on [−r, r].
#[derive(Clone, Debug, PartialEq)]
struct Table1D {
    radius: f32,
    /// Function values at bin centres (signed).
    f: Vec<f32>,
    /// Cumulative distribution of |f| at bin edges, cdf[0] = 0, cdf[n] = 1.
    cdf: Vec<f32>,
    /// ∫|f| over [−r, r].
    integral: f32,
    /// ∫f over [−r, r] (midpoint rule over the bins; differs from `integral` only where f < 0).
    signed_integral: f32,
}

impl Table1D {
    fn new(radius: f32, f: impl Fn(f32) -> f32) -> Table1D {
        let n = ((64.0 * radius).ceil() as usize).clamp(8, 4096);
        let dx = 2.0 * radius / n as f32;
        let vals: Vec<f32> = (0..n).map(|i| f(-radius + (i as f32 + 0.5) * dx)).collect();
        let mut cdf = Vec::with_capacity(n + 1);
        cdf.push(0.0f32);
        let mut acc = 0.0f64;
        for v in &vals {
            acc += v.abs() as f64 * dx as f64;
            cdf.push(acc as f32);
        }
        let integral = acc as f32;
        let signed_integral = (vals.iter().map(|&v| v as f64).sum::<f64>() * dx as f64) as f32;
        if integral > 0.0 {
            for c in &mut cdf {
                *c /= integral;
            }
        } else {
            for (i, c) in cdf.iter_mut().enumerate() {
                *c = i as f32 / n as f32;
            }
        }
        Table1D {
            radius,
            f: vals,
            cdf,
            integral,
            signed_integral,
        }
    }

    /// Samples x with density |f(x)|/∫|f| (piecewise constant); returns (x, f(x)/pdf(x)).
    fn sample(&self, u: f32) -> (f32, f32) {
        let n = self.f.len();
        let i = self.cdf.partition_point(|&c| c <= u).clamp(1, n) - 1;
        let (c0, c1) = (self.cdf[i], self.cdf[i + 1]);
        let du = if c1 > c0 { (u - c0) / (c1 - c0) } else { 0.5 };
        let dx = 2.0 * self.radius / n as f32;
        let x = -self.radius + (i as f32 + du) * dx;
        let pdf = (c1 - c0) / dx;
        let w = if pdf > 0.0 { self.f[i] / pdf } else { 0.0 };
        (x, w)
    }
}

/// A sample of the tent 1 − |x| on [−1, 1] from u in [0, 1), as pbrt-v4's `SampleTent(u, 1)`:
/// u < ½ picks the left half and is stretched to u' = 2u, which x = −1 + √u' maps by the
/// inverse of the CDF x ↦ x² of density 2x on [0, 1] (pbrt's `SampleLinear(u', 0, 1)`,
/// u'/(0 + √u')); otherwise u' = 2u − 1 and x = u'/(1 + √(1 − u')) (`SampleLinear(u', 1, 0)`,
/// density 2(1 − x)). Exact, so a sample's weight f/pdf is 1.
fn sample_tent(u: f32) -> f32 {
    if u < 0.5 {
        let u = (u / 0.5).min(ONE_MINUS_EPSILON);
        let x = if u == 0.0 { 0.0 } else { u / u.sqrt() };
        -1.0 + x.min(ONE_MINUS_EPSILON)
    } else {
        let u = ((u - 0.5) / 0.5).min(ONE_MINUS_EPSILON);
        (u / (1.0 + (1.0 - u).sqrt())).min(ONE_MINUS_EPSILON)
    }
}

fn gaussian(x: f32, sigma: f32) -> f32 {
    (-x * x / (2.0 * sigma * sigma)).exp() / ((2.0 * std::f32::consts::PI).sqrt() * sigma)
}

fn mitchell_1d(x: f32, b: f32, c: f32) -> f32 {
    let x = x.abs();
    if x <= 1.0 {
        ((12.0 - 9.0 * b - 6.0 * c) * x * x * x
            + (-18.0 + 12.0 * b + 6.0 * c) * x * x
            + (6.0 - 2.0 * b))
            / 6.0
    } else if x <= 2.0 {
        ((-b - 6.0 * c) * x * x * x
            + (6.0 * b + 30.0 * c) * x * x
            + (-12.0 * b - 48.0 * c) * x
            + (8.0 * b + 24.0 * c))
            / 6.0
    } else {
        0.0
    }
}

/// The filter's profile along one axis of half-width `r`, f(x) for |x| ≤ r (its 2D value
/// is f(x)·f(y)), as pbrt-v4's filters evaluate it: 1 (box), r − |x| (triangle),
/// g(x) − g(r) for the normal density g of deviation σ (gaussian), Mitchell–Netravali's
/// cubic at 2x/r, and sinc(x)·sinc(x/τ) (lanczos). What the sampling tables hold and what
/// splats are spread by.
#[inline]
fn profile(desc: FilterDesc, x: f32, r: f32) -> f32 {
    match desc {
        FilterDesc::Box { .. } => 1.0,
        FilterDesc::Triangle { .. } => (r - x.abs()).max(0.0),
        FilterDesc::Gaussian { sigma, .. } => (gaussian(x, sigma) - gaussian(r, sigma)).max(0.0),
        FilterDesc::Mitchell { b, c, .. } => mitchell_1d(2.0 * x / r, b, c),
        FilterDesc::Lanczos { tau, .. } => sinc(x) * sinc(x / tau),
    }
}

fn sinc(x: f32) -> f32 {
    if x.abs() < 1e-5 {
        1.0
    } else {
        let px = std::f32::consts::PI * x;
        px.sin() / px
    }
}

impl Filter {
    /// A filter from its description.
    pub fn new(desc: FilterDesc) -> Filter {
        let tables = match desc {
            // Sampled in closed form (pbrt-v4 does the same for both).
            FilterDesc::Box { .. } | FilterDesc::Triangle { .. } => None,
            _ => {
                let r = desc.radius();
                let table = |r: f32| Table1D::new(r.max(1e-3), |x| profile(desc, x, r));
                Some([table(r.x), table(r.y)])
            }
        };
        Filter { desc, tables }
    }

    /// The description.
    pub fn desc(&self) -> FilterDesc {
        self.desc
    }

    /// Samples an offset from the pixel centre and its weight f/pdf.
    #[inline]
    pub fn sample(&self, u: Vec2) -> (Vec2, f32) {
        match (&self.tables, self.desc) {
            (None, FilterDesc::Box { radius }) => (
                Vec2::new((2.0 * u.x - 1.0) * radius[0], (2.0 * u.y - 1.0) * radius[1]),
                1.0,
            ),
            (Some([tx, ty]), _) => {
                let (x, wx) = tx.sample(u.x);
                let (y, wy) = ty.sample(u.y);
                // f/pdf = ±∫|f| per axis; dividing by ∫|f| gives ±1, so positive filters weigh
                // every sample equally and only the sign of a negative lobe survives.
                (
                    Vec2::new(x, y),
                    (wx / tx.integral.max(1e-12)) * (wy / ty.integral.max(1e-12)),
                )
            }
            (None, FilterDesc::Triangle { radius }) => (
                Vec2::new(radius[0] * sample_tent(u.x), radius[1] * sample_tent(u.y)),
                1.0,
            ),
            _ => (Vec2::ZERO, 1.0),
        }
    }

    /// The filter's half-widths (pbrt-v4's `Filter::Radius`).
    #[inline]
    pub fn radius(&self) -> Vec2 {
        self.desc.radius()
    }

    /// The filter's value at offset `p` from a pixel centre (pbrt-v4's `Filter::Evaluate`):
    /// the product f(x)·f(y) of its 1D profiles, zero outside the radius.
    pub fn evaluate(&self, p: Vec2) -> f32 {
        let r = self.radius();
        if p.x.abs() > r.x || p.y.abs() > r.y {
            return 0.0;
        }
        profile(self.desc, p.x, r.x) * profile(self.desc, p.y, r.y)
    }

    /// ∫∫ f(x, y) dx dy over the filter's support (pbrt-v4's `Filter::Integral`, which splats
    /// are divided by): 4·rx·ry for the box, else the product of the 1D profiles' integrals
    /// (midpoint rule over the sampling tables' bins).
    pub fn integral(&self) -> f32 {
        match &self.tables {
            Some([tx, ty]) => tx.signed_integral * ty.signed_integral,
            None => {
                let r = self.radius();
                match self.desc {
                    // ∫ (r − |x|) dx over [−r, r] = r², per axis.
                    FilterDesc::Triangle { .. } => r.x * r.x * r.y * r.y,
                    _ => 4.0 * r.x * r.y,
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn positive_filters_give_constant_weights_and_stay_in_radius() {
        for d in [
            FilterDesc::Box { radius: [0.5, 0.5] },
            FilterDesc::Triangle { radius: [1.0, 1.0] },
            FilterDesc::Gaussian {
                radius: [1.5, 1.5],
                sigma: 0.5,
            },
        ] {
            let f = Filter::new(d);
            for i in 0..100 {
                let u = Vec2::new(
                    (i as f32 + 0.5) / 100.0,
                    ((i * 37) % 100) as f32 / 100.0 + 0.005,
                );
                let (p, w) = f.sample(u);
                assert!(p.x.abs() <= 1.5 && p.y.abs() <= 1.5);
                assert!((w - 1.0).abs() < 1e-3, "{d:?}: weight {w}");
            }
        }
    }

    /// Splats are spread by `evaluate` and divided by `integral`: the integral must be that of
    /// `evaluate` over the support (a midpoint sum on a fine grid), negative lobes included,
    /// and pbrt-v4's closed forms where it has them: 4·rx·ry (box), rx²·ry² (triangle),
    /// rx·ry/4 (Mitchell).
    #[test]
    fn integral_is_that_of_evaluate() {
        let third = 1.0 / 3.0;
        let cases = [
            (FilterDesc::Box { radius: [0.5, 1.5] }, Some(3.0)),
            (FilterDesc::Triangle { radius: [1.0, 2.0] }, Some(4.0)),
            (
                FilterDesc::Gaussian {
                    radius: [1.5, 1.5],
                    sigma: 0.5,
                },
                None,
            ),
            (
                FilterDesc::Mitchell {
                    radius: [2.0, 1.0],
                    b: third,
                    c: third,
                },
                Some(0.5),
            ),
            (
                FilterDesc::Lanczos {
                    radius: [2.0, 2.0],
                    tau: 2.0,
                },
                None,
            ),
        ];
        for (d, closed) in cases {
            let f = Filter::new(d);
            let r = f.radius();
            let n = 500;
            let (dx, dy) = (2.0 * r.x as f64 / n as f64, 2.0 * r.y as f64 / n as f64);
            let mut sum = 0.0f64;
            for i in 0..n {
                for j in 0..n {
                    let p = Vec2::new(
                        (-r.x as f64 + (i as f64 + 0.5) * dx) as f32,
                        (-r.y as f64 + (j as f64 + 0.5) * dy) as f32,
                    );
                    sum += f.evaluate(p) as f64;
                }
            }
            let numeric = sum * dx * dy;
            let got = f.integral() as f64;
            assert!(
                (got - numeric).abs() < 1e-3 * numeric.abs(),
                "{d:?}: integral {got}, ∫∫evaluate {numeric}"
            );
            if let Some(c) = closed {
                assert!(
                    (got - c).abs() < 1e-3 * c,
                    "{d:?}: integral {got}, want {c}"
                );
            }
            // Nothing outside the radius.
            assert_eq!(f.evaluate(Vec2::new(r.x * 1.01, 0.0)), 0.0);
        }
    }

    #[test]
    fn the_triangle_filter_samples_its_tent_exactly() {
        // The fraction of samples left of x is the tent's CDF: (1 + x)²/2 for x ≤ 0,
        // 1 − (1 − x)²/2 above (radius 1; the radius only scales the offsets).
        let f = Filter::new(FilterDesc::Triangle { radius: [1.0, 2.0] });
        let n = 4096;
        let xs: Vec<f32> = (0..n)
            .map(|i| {
                let u = Vec2::new((i as f32 + 0.5) / n as f32, 0.25);
                let (p, w) = f.sample(u);
                assert_eq!(w, 1.0);
                assert!(p.x.abs() < 1.0 && p.y.abs() < 2.0);
                p.x
            })
            .collect();
        assert!(xs.windows(2).all(|w| w[0] <= w[1]), "monotone in u");
        for x in [-0.9f32, -0.5, -0.1, 0.0, 0.3, 0.75] {
            let frac = xs.iter().filter(|&&s| s < x).count() as f32 / n as f32;
            let cdf = if x <= 0.0 {
                (1.0 + x).powi(2) / 2.0
            } else {
                1.0 - (1.0 - x).powi(2) / 2.0
            };
            assert!(
                (frac - cdf).abs() < 1.0 / n as f32 + 1e-4,
                "x {x}: {frac} vs {cdf}"
            );
        }
        assert_eq!(sample_tent(0.0), -1.0);
        assert_eq!(sample_tent(0.5), 0.0);
    }

    #[test]
    fn mitchell_has_negative_lobes() {
        let f = Filter::new(FilterDesc::Mitchell {
            radius: [2.0, 2.0],
            b: 1.0 / 3.0,
            c: 1.0 / 3.0,
        });
        let neg = (0..1000)
            .filter(|i| f.sample(Vec2::new((*i as f32 + 0.5) / 1000.0, 0.5)).1 < 0.0)
            .count();
        assert!(neg > 0);
    }
}

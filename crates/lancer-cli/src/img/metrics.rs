//! Statistics of an image and error metrics between two images of the same size, the second
//! taken as the reference. Sums are kept in `f64`, in pixel order, so the same images always
//! give the same figures.
//!
//! A sample is one channel of one pixel. The metrics are means over the samples that are finite
//! in both images; the others are counted apart (see [`DiffMetrics`]).

use lancer::math::Rgb;

/// ε of the relative MSE: `(a − b)² / (b² + ε)` (Rousselle et al. 2011's relMSE, ε = 0.01).
pub const RELMSE_EPSILON: f64 = 0.01;

/// ε of pbrt-v4's MRSE (its `Image::MRSE`, imgtool's `--metric MRSE`): `(a − b)² / (b + ε)²`.
pub const MRSE_EPSILON: f64 = 0.01;

/// Floor of a reference channel mean in the relative error of the means (as the project's
/// acceptance scripts do), so that a black reference does not divide by zero.
pub const MRE_FLOOR: f64 = 1e-4;

/// Statistics of one channel: over its finite values, and how many values are not finite.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ChannelStats {
    /// Mean of the finite values (NaN when there is none).
    pub mean: f64,
    /// Smallest finite value (NaN when there is none).
    pub min: f64,
    /// Largest finite value (NaN when there is none).
    pub max: f64,
    /// How many values are NaN.
    pub nan: u64,
    /// How many values are +∞ or −∞.
    pub inf: u64,
}

/// Statistics of a sequence of values: mean, min and max of the finite ones (as pbrt-v4's
/// `imgtool info` computes them), NaN and infinity counts.
pub fn channel_stats(values: impl Iterator<Item = f32>) -> ChannelStats {
    let (mut sum, mut n, mut nan, mut inf) = (0.0f64, 0u64, 0u64, 0u64);
    let (mut min, mut max) = (f64::INFINITY, f64::NEG_INFINITY);
    for v in values {
        if v.is_nan() {
            nan += 1;
        } else if v.is_infinite() {
            inf += 1;
        } else {
            let v = v as f64;
            sum += v;
            n += 1;
            min = min.min(v);
            max = max.max(v);
        }
    }
    if n == 0 {
        (min, max) = (f64::NAN, f64::NAN);
    }
    ChannelStats {
        mean: sum / n as f64,
        min,
        max,
        nan,
        inf,
    }
}

/// Statistics of each of the R, G, B channels of `pixels`.
pub fn rgb_stats(pixels: &[Rgb]) -> [ChannelStats; 3] {
    [0, 1, 2].map(|c| channel_stats(pixels.iter().map(|p| p[c])))
}

/// How far image A is from the reference B. All means are over the samples finite in both
/// images, `a` being A's value and `b` B's.
#[derive(Clone, Debug, PartialEq)]
pub struct DiffMetrics {
    /// Channel means of A (over its finite values).
    pub means_a: [f64; 3],
    /// Channel means of B (over its finite values).
    pub means_b: [f64; 3],
    /// Relative MSE: mean of `(a − b)² / (b² + ε)`, ε = [`RELMSE_EPSILON`].
    pub relmse: f64,
    /// pbrt-v4's MRSE: mean of `(a − b)² / (b + ε)²`, ε = [`MRSE_EPSILON`].
    pub mrse: f64,
    /// Mean squared error: mean of `(a − b)²`.
    pub mse: f64,
    /// Root mean squared error: `√mse`.
    pub rmse: f64,
    /// Mean absolute error: mean of `|a − b|`.
    pub mae: f64,
    /// Relative error of each channel mean: `|mean_A − mean_B| / max(mean_B, 10⁻⁴)`.
    pub mre_channels: [f64; 3],
    /// The largest of [`DiffMetrics::mre_channels`].
    pub mre: f64,
    /// Samples compared (finite in both images).
    pub compared: u64,
    /// Samples left out because one of the two values is not finite.
    pub skipped: u64,
    /// Of the skipped samples, those where the two values differ (NaN against a number, +∞
    /// against −∞ or a number): the images disagree there, whatever the metrics say.
    pub nonfinite_mismatches: u64,
}

/// True when two values are the same for a comparison: equal numbers, both NaN, or the same
/// infinity.
fn same(a: f32, b: f32) -> bool {
    a == b || (a.is_nan() && b.is_nan())
}

/// Compares image `a` with the reference `b` (same size, same pixel order).
pub fn diff_metrics(a: &[Rgb], b: &[Rgb]) -> DiffMetrics {
    debug_assert_eq!(a.len(), b.len());
    let (sa, sb) = (rgb_stats(a), rgb_stats(b));
    let means_a = sa.map(|s| s.mean);
    let means_b = sb.map(|s| s.mean);
    let (mut relmse, mut mrse, mut mse, mut mae) = (0.0f64, 0.0f64, 0.0f64, 0.0f64);
    let (mut compared, mut skipped, mut mismatches) = (0u64, 0u64, 0u64);
    for (pa, pb) in a.iter().zip(b) {
        for c in 0..3 {
            let (x, y) = (pa[c], pb[c]);
            if !(x.is_finite() && y.is_finite()) {
                skipped += 1;
                mismatches += u64::from(!same(x, y));
                continue;
            }
            let (x, y) = (x as f64, y as f64);
            let d2 = (x - y) * (x - y);
            relmse += d2 / (y * y + RELMSE_EPSILON);
            mrse += d2 / ((y + MRSE_EPSILON) * (y + MRSE_EPSILON));
            mse += d2;
            mae += (x - y).abs();
            compared += 1;
        }
    }
    // With no sample finite in both images there is nothing to average: 0 (the images can
    // then differ only where one is not finite, which `nonfinite_mismatches` counts).
    let n = (compared as f64).max(1.0);
    let (relmse, mrse, mse, mae) = (relmse / n, mrse / n, mse / n, mae / n);
    let mre_channels = [0, 1, 2].map(|c| {
        let (ma, mb) = (means_a[c], means_b[c]);
        if ma.is_nan() && mb.is_nan() {
            0.0 // no finite value in either image's channel
        } else {
            (ma - mb).abs() / mb.max(MRE_FLOOR)
        }
    });
    DiffMetrics {
        means_a,
        means_b,
        relmse,
        mrse,
        mse,
        rmse: mse.sqrt(),
        mae,
        mre: mre_channels.iter().copied().fold(0.0, f64::max),
        mre_channels,
        compared,
        skipped,
        nonfinite_mismatches: mismatches,
    }
}

/// The difference image: `|a − b|` per channel, 0 where the two values are the same (also
/// both NaN or the same infinity), NaN or ∞ where one value is not finite and the other differs.
pub fn difference_image(a: &[Rgb], b: &[Rgb]) -> Vec<Rgb> {
    a.iter()
        .zip(b)
        .map(|(pa, pb)| {
            let mut d = Rgb::ZERO;
            for c in 0..3 {
                d[c] = if same(pa[c], pb[c]) {
                    0.0
                } else {
                    (pa[c] - pb[c]).abs()
                };
            }
            d
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn stats_skip_non_finite_values_and_count_them() {
        let s =
            channel_stats([1.0, f32::NAN, 3.0, f32::INFINITY, -2.0, f32::NEG_INFINITY].into_iter());
        assert_eq!(
            (s.mean, s.min, s.max, s.nan, s.inf),
            (2.0 / 3.0, -2.0, 3.0, 1, 2)
        );
        let empty = channel_stats([f32::NAN].into_iter());
        assert!(empty.mean.is_nan() && empty.min.is_nan() && empty.max.is_nan());
    }

    #[test]
    fn metrics_by_hand() {
        // A = (1, 0.5, 0), (3, 0.5, 0.25); B = (1, 1, 0), (2, 0.5, 0.5).
        // Differences: 0, −0.5, 0 | 1, 0, −0.25 → squares 0, 0.25, 0, 1, 0, 0.0625.
        let a = [Rgb::new(1.0, 0.5, 0.0), Rgb::new(3.0, 0.5, 0.25)];
        let b = [Rgb::new(1.0, 1.0, 0.0), Rgb::new(2.0, 0.5, 0.5)];
        let m = diff_metrics(&a, &b);
        assert_eq!(m.mse, 1.3125 / 6.0);
        assert_eq!(m.mae, 1.75 / 6.0);
        // relmse: 0.25/(1+0.01) + 1/(4+0.01) + 0.0625/(0.25+0.01), over 6.
        let relmse = (0.25 / 1.01 + 1.0 / 4.01 + 0.0625 / 0.26) / 6.0;
        assert!(
            (m.relmse - relmse).abs() < 1e-15,
            "{} vs {relmse}",
            m.relmse
        );
        // pbrt's MRSE: 0.25/1.01² + 1/2.01² + 0.0625/0.51², over 6.
        let mrse = (0.25 / (1.01 * 1.01) + 1.0 / (2.01 * 2.01) + 0.0625 / (0.51 * 0.51)) / 6.0;
        assert!((m.mrse - mrse).abs() < 1e-15, "{} vs {mrse}", m.mrse);
        // Means: A (2, 0.5, 0.125), B (1.5, 0.75, 0.25): errors 1/3, 1/3, 1/2.
        assert_eq!(m.means_a, [2.0, 0.5, 0.125]);
        assert_eq!(m.mre_channels, [0.5 / 1.5, 0.25 / 0.75, 0.5]);
        assert_eq!(m.mre, 0.5);
        assert_eq!((m.compared, m.skipped, m.nonfinite_mismatches), (6, 0, 0));
    }

    #[test]
    fn non_finite_samples_are_left_out_and_mismatches_counted() {
        let a = [
            Rgb::new(f32::NAN, f32::INFINITY, 1.0),
            Rgb::new(2.0, f32::NAN, 1.0),
        ];
        let b = [
            Rgb::new(f32::NAN, f32::INFINITY, 1.0),
            Rgb::new(2.0, 5.0, 1.0),
        ];
        let m = diff_metrics(&a, &b);
        assert_eq!((m.compared, m.skipped, m.nonfinite_mismatches), (3, 3, 1));
        assert_eq!((m.mse, m.relmse), (0.0, 0.0));
        // Nothing finite in either image, the same non-finite values: no difference.
        let nan = [Rgb::splat(f32::NAN)];
        let m = diff_metrics(&nan, &nan);
        assert_eq!(
            (m.relmse, m.mse, m.mre, m.nonfinite_mismatches),
            (0.0, 0.0, 0.0, 0)
        );
        let d = difference_image(&a, &b);
        assert_eq!(d[0], Rgb::ZERO);
        assert!(d[1][1].is_nan() && d[1][0] == 0.0);
    }
}

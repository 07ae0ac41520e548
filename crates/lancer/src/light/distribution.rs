//! Choosing a light: with probability proportional to its power (pbrt's `power` light
//! sampler), so that bright lights get the shadow rays.

/// A discrete distribution over the scene's lights.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct LightDistribution {
    /// Probability of each light.
    pmf: Vec<f32>,
    /// Running sums of `pmf`, the last one 1.
    cdf: Vec<f32>,
}

impl LightDistribution {
    /// Bytes of the tables (capacity included).
    pub fn memory_bytes(&self) -> usize {
        (self.pmf.capacity() + self.cdf.capacity()) * std::mem::size_of::<f32>()
    }

    /// The distribution proportional to `powers` (uniform when they are all zero or some is
    /// not finite).
    pub fn new(powers: &[f32]) -> LightDistribution {
        let valid = powers.iter().all(|p| p.is_finite() && *p >= 0.0);
        let total: f64 = powers.iter().map(|&p| p as f64).sum();
        let pmf: Vec<f32> = if valid && total > 0.0 {
            powers.iter().map(|&p| (p as f64 / total) as f32).collect()
        } else {
            vec![1.0 / powers.len().max(1) as f32; powers.len()]
        };
        let mut cdf = Vec::with_capacity(pmf.len());
        let mut sum = 0.0f64;
        for &p in &pmf {
            sum += p as f64;
            cdf.push(sum as f32);
        }
        if let Some(last) = cdf.last_mut() {
            *last = 1.0;
        }
        LightDistribution { pmf, cdf }
    }

    /// Probability of light `i`.
    #[inline]
    pub fn pmf(&self, i: usize) -> f32 {
        self.pmf.get(i).copied().unwrap_or(0.0)
    }

    /// The light whose slice of [0, 1) holds `u`, and its probability; `None` without lights.
    #[inline]
    pub fn sample(&self, u: f32) -> Option<(usize, f32)> {
        if self.cdf.is_empty() {
            return None;
        }
        // First index whose running sum exceeds u; lights of zero probability are never
        // picked since their running sum equals their predecessor's.
        let i = self
            .cdf
            .partition_point(|&c| c <= u)
            .min(self.cdf.len() - 1);
        Some((i, self.pmf[i]))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn picks_in_proportion_to_power() {
        let d = LightDistribution::new(&[1.0, 0.0, 3.0]);
        assert_eq!(d.pmf(0), 0.25);
        assert_eq!(d.pmf(1), 0.0);
        assert_eq!(d.pmf(2), 0.75);
        let mut counts = [0usize; 3];
        let n = 10_000;
        for k in 0..n {
            let (i, p) = d.sample((k as f32 + 0.5) / n as f32).unwrap();
            assert_eq!(p, d.pmf(i));
            counts[i] += 1;
        }
        assert_eq!(counts, [2500, 0, 7500]);
        assert_eq!(LightDistribution::new(&[]).sample(0.5), None);
        let u = LightDistribution::new(&[0.0, 0.0]);
        assert_eq!((u.pmf(0), u.pmf(1)), (0.5, 0.5));
    }
}

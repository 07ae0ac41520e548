//! The primary-sample-space sampler of Metropolis light transport (Kelemen et al. 2002;
//! pbrt-v4's `MLTSampler`): a path is a function of a vector X of numbers in [0, 1), and a
//! Markov chain mutates X. A large step draws every coordinate afresh; a small step moves each
//! by a normal perturbation of deviation σ, wrapped into [0, 1). Coordinates are made lazily,
//! as the path asks for them: one last changed k iterations ago has missed k small steps,
//! which add up to one of deviation σ·√k, and one last changed before the latest accepted
//! large step takes a fresh value first. A rejected proposal puts back every coordinate the
//! proposal changed.
//!
//! X interleaves `STREAMS` streams (camera subpath, light subpath, connection): coordinate i
//! of stream s is X[s + STREAMS·i], so that a subpath that asks for more or fewer numbers does
//! not shift the others'.

use crate::math::{PI, Vec2};
use crate::sampling::ONE_MINUS_EPSILON;
use crate::sampling::{Pcg32, SampleSource};

/// Streams in the vector: camera subpath, light subpath, connection.
pub const STREAMS: usize = 3;

/// One coordinate of the vector, with what a rejection restores.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
struct PrimarySample {
    /// The value, in [0, 1).
    value: f32,
    /// Iteration of its last change.
    modified: u64,
    /// Value before the current iteration changed it.
    value_backup: f32,
    /// `modified` before the current iteration changed it.
    modified_backup: u64,
}

/// A primary-sample vector and its mutations (see the module's documentation).
#[derive(Clone, Debug)]
pub struct PssSampler {
    rng: Pcg32,
    sigma: f32,
    large_step_probability: f32,
    x: Vec<PrimarySample>,
    /// Current iteration (0: the initial state, drawn as a large step).
    iteration: u64,
    /// The current iteration is a large step.
    large_step: bool,
    /// Iteration of the last accepted large step.
    last_large_step: u64,
    stream: usize,
    index: usize,
}

impl PssSampler {
    /// A vector whose numbers come from `rng`, mutated by small steps of deviation `sigma`
    /// and large steps with probability `large_step_probability`; its first state is a
    /// large step (every coordinate uniform).
    pub fn new(rng: Pcg32, sigma: f32, large_step_probability: f32) -> PssSampler {
        PssSampler {
            rng,
            sigma,
            large_step_probability,
            x: Vec::new(),
            iteration: 0,
            large_step: true,
            last_large_step: 0,
            stream: 0,
            index: 0,
        }
    }

    /// Starts a proposal: the next iteration, a large step with its probability.
    pub fn start_iteration(&mut self) {
        self.iteration += 1;
        self.large_step = self.rng.uniform() < self.large_step_probability;
    }

    /// True when the current proposal is a large step.
    pub fn is_large_step(&self) -> bool {
        self.large_step
    }

    /// Makes the next values come from stream `s` (< [`STREAMS`]), from its first coordinate.
    pub fn start_stream(&mut self, s: usize) {
        debug_assert!(s < STREAMS);
        self.stream = s;
        self.index = 0;
    }

    /// Keeps the proposal.
    pub fn accept(&mut self) {
        if self.large_step {
            self.last_large_step = self.iteration;
        }
    }

    /// Drops the proposal: every coordinate it changed gets its value back, and the
    /// iteration count goes back one (the next proposal is made from the kept state).
    pub fn reject(&mut self) {
        for xi in &mut self.x {
            if xi.modified == self.iteration {
                xi.value = xi.value_backup;
                xi.modified = xi.modified_backup;
            }
        }
        self.iteration -= 1;
    }

    /// A normal deviate of deviation `sigma` (Box–Muller from two uniform numbers:
    /// √(−2 ln u₁)·cos 2πu₂, with u₁ ∈ (0, 1]).
    fn normal(&mut self, sigma: f32) -> f32 {
        let u1 = 1.0 - self.rng.uniform();
        let u2 = self.rng.uniform();
        sigma * (-2.0 * u1.ln()).sqrt() * (2.0 * PI * u2).cos()
    }

    /// Brings coordinate `i` up to the current iteration (see the module's documentation).
    fn ensure_ready(&mut self, i: usize) -> f32 {
        if i >= self.x.len() {
            self.x.resize(i + 1, PrimarySample::default());
        }
        let (iteration, last_large, large) =
            (self.iteration, self.last_large_step, self.large_step);
        // Reset if a large step was accepted since it last changed.
        if self.x[i].modified < last_large {
            let v = self.rng.uniform();
            let xi = &mut self.x[i];
            xi.value = v;
            xi.modified = last_large;
        }
        {
            let xi = &mut self.x[i];
            xi.value_backup = xi.value;
            xi.modified_backup = xi.modified;
        }
        let value = if large {
            self.rng.uniform()
        } else {
            // k missed small steps: one normal step of deviation σ·√k, wrapped into [0, 1).
            let k = iteration - self.x[i].modified;
            let v = self.x[i].value + self.normal(self.sigma * (k as f32).sqrt());
            let v = v - v.floor();
            // −tiny wraps to 1 − tiny, which may round to 1.
            if v < 1.0 { v } else { ONE_MINUS_EPSILON }
        };
        let xi = &mut self.x[i];
        xi.value = if value.is_finite() { value } else { 0.0 };
        xi.modified = iteration;
        xi.value
    }
}

impl SampleSource for PssSampler {
    fn get_1d(&mut self) -> f32 {
        let i = self.stream + STREAMS * self.index;
        self.index += 1;
        self.ensure_ready(i)
    }

    fn get_2d(&mut self) -> Vec2 {
        let a = self.get_1d();
        Vec2::new(a, self.get_1d())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The first `n` values of stream `s` of the current iteration.
    fn values(x: &mut PssSampler, s: usize, n: usize) -> Vec<f32> {
        x.start_stream(s);
        (0..n).map(|_| x.get_1d()).collect()
    }

    /// Distance between two points of the circle [0, 1).
    fn wrapped(a: f32, b: f32) -> f32 {
        let d = (a - b).abs();
        d.min(1.0 - d)
    }

    /// Runs iterations until one is a small (`large` false) or large step.
    fn start_kind(x: &mut PssSampler, large: bool) {
        loop {
            x.start_iteration();
            if x.is_large_step() == large {
                return;
            }
            x.reject();
        }
    }

    #[test]
    fn small_steps_stay_in_the_unit_interval_and_move_by_about_sigma() {
        // σ = 0.3 wraps often; every value stays in [0, 1).
        let mut x = PssSampler::new(Pcg32::new(1, 0), 0.3, 0.0);
        values(&mut x, 0, 4);
        for _ in 0..10_000 {
            x.start_iteration();
            for v in values(&mut x, 0, 4) {
                assert!((0.0..1.0).contains(&v), "{v}");
            }
            x.accept();
        }
        // A value right at the edge wraps around rather than leaving [0, 1).
        let mut x = PssSampler::new(Pcg32::new(2, 0), 1e-3, 0.0);
        x.x = vec![PrimarySample {
            value: 0.0,
            ..Default::default()
        }];
        let (mut below, mut above) = (0, 0);
        for _ in 0..1000 {
            x.start_iteration();
            let v = values(&mut x, 0, 1)[0];
            assert!((0.0..1.0).contains(&v), "{v}");
            if v > 0.5 {
                above += 1
            } else {
                below += 1
            }
            x.reject();
        }
        // From 0, half the steps go below it and wrap to just under 1.
        assert!(above > 400 && below > 400, "{above} {below}");
        // Small steps of σ = 0.01: mean |Δ| = σ·√(2/π) ≈ 0.008.
        let mut x = PssSampler::new(Pcg32::new(3, 0), 0.01, 0.0);
        x.x = vec![PrimarySample {
            value: 0.5,
            ..Default::default()
        }];
        let mut sum = 0.0;
        for _ in 0..20_000 {
            x.start_iteration();
            sum += (values(&mut x, 0, 1)[0] - 0.5).abs() as f64;
            x.reject();
        }
        let mean = sum / 20_000.0;
        assert!(
            (mean - 0.01 * (2.0 / std::f64::consts::PI).sqrt()).abs() < 3e-4,
            "{mean}"
        );
    }

    #[test]
    fn coordinates_missed_by_small_steps_catch_up_by_sigma_sqrt_k() {
        // Coordinate 1 (stream 0, index 0 then 1) is asked for only every 16th iteration:
        // its step then has deviation σ·√16 = 4σ.
        let sigma = 0.001;
        let mut x = PssSampler::new(Pcg32::new(4, 0), sigma, 0.0);
        values(&mut x, 0, 2);
        let mut sum2 = 0.0;
        let n = 4000;
        for _ in 0..n {
            for _ in 0..15 {
                x.start_iteration();
                values(&mut x, 0, 1);
                x.accept();
            }
            x.start_iteration();
            let before = x.x[STREAMS].value;
            let d = values(&mut x, 0, 2)[1] - before;
            // No wrap at this scale unless it sits at an edge; skip those.
            if d.abs() < 0.5 {
                sum2 += (d as f64).powi(2);
            }
            x.accept();
        }
        let dev = (sum2 / n as f64).sqrt();
        assert!((dev / (4.0 * sigma as f64) - 1.0).abs() < 0.08, "{dev}");
    }

    #[test]
    fn a_large_step_redraws_lazily_and_a_rejection_restores() {
        let mut x = PssSampler::new(Pcg32::new(5, 0), 0.01, 0.5);
        let a0 = values(&mut x, 0, 3);
        let b0 = values(&mut x, 1, 2);
        // Streams interleave: stream 1's first value is coordinate 1.
        assert_eq!(x.x[1].value, b0[0]);
        assert_eq!(x.x[STREAMS].value, a0[1]);
        // A rejected small step changes nothing.
        start_kind(&mut x, false);
        let a1 = values(&mut x, 0, 3);
        assert_ne!(a1, a0);
        assert!(a1.iter().zip(&a0).all(|(a, b)| wrapped(*a, *b) < 0.1));
        x.reject();
        let state = |x: &PssSampler| -> Vec<(f32, u64)> {
            x.x.iter().map(|p| (p.value, p.modified)).collect()
        };
        let saved = state(&x);
        let values_now: Vec<f32> = saved.iter().map(|s| s.0).collect();
        let stream0: Vec<f32> = (0..3).map(|i| values_now[STREAMS * i]).collect();
        let stream1: Vec<f32> = (0..2).map(|i| values_now[1 + STREAMS * i]).collect();
        assert_eq!((stream0, stream1), (a0.clone(), b0.clone()));
        // A rejected large step restores every coordinate it drew.
        start_kind(&mut x, true);
        let a2 = values(&mut x, 0, 3);
        assert_ne!(a2, a0);
        x.reject();
        assert_eq!(state(&x), saved);
        // An accepted large step: the coordinates it drew keep its values; one it did not
        // reach (stream 1) is drawn afresh when next asked for, then small steps go on from
        // there.
        start_kind(&mut x, true);
        let a3 = values(&mut x, 0, 3);
        x.accept();
        assert_eq!(x.last_large_step, x.iteration);
        start_kind(&mut x, false);
        let a4 = values(&mut x, 0, 3);
        assert!(a4.iter().zip(&a3).all(|(a, b)| wrapped(*a, *b) < 0.1));
        let b4 = values(&mut x, 1, 2);
        // Stream 1 was last drawn before the accepted large step: fresh values, not steps
        // from b0 (which a small step would leave within a few σ).
        assert!(b4.iter().zip(&b0).any(|(a, b)| (a - b).abs() > 0.05));
        // Rejecting now puts stream 1 back to what it was before this iteration, which is
        // not b0 either (the reset belongs to the accepted large step) but the state a later
        // proposal builds on; doing the same proposal again yields the same reset values.
        let reset: Vec<f32> = x.x.iter().map(|p| p.value_backup).collect();
        x.reject();
        assert_eq!(x.x[1].value, reset[1]);
        assert_eq!(x.x[1].modified, x.last_large_step);
    }
}

//! How a low-discrepancy point set is randomised (pbrt-v4's `"string randomization"`): a leaf
//! module shared by the samplers and the sequences they draw from.

/// A randomisation of a base-b point set that keeps its stratification.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Randomization {
    /// The points as they are (every pixel sees the same ones, up to the sampler's own
    /// shuffling).
    None,
    /// A random permutation of the digit values at each digit position (in base 2, an XOR).
    PermuteDigits,
    /// Owen scrambling with a cheap hash (Burley 2020); base 2 only.
    #[default]
    FastOwen,
    /// Owen scrambling: each digit permuted by a hash of the digits before it.
    Owen,
}

impl Randomization {
    /// The randomisation named `name` in pbrt-v4 (`none`, `permutedigits`, `fastowen`,
    /// `owen`).
    pub fn from_pbrt(name: &str) -> Option<Randomization> {
        Some(match name {
            "none" => Randomization::None,
            "permutedigits" => Randomization::PermuteDigits,
            "fastowen" => Randomization::FastOwen,
            "owen" => Randomization::Owen,
            _ => return None,
        })
    }

    /// pbrt-v4's name for it.
    pub fn pbrt_name(self) -> &'static str {
        match self {
            Randomization::None => "none",
            Randomization::PermuteDigits => "permutedigits",
            Randomization::FastOwen => "fastowen",
            Randomization::Owen => "owen",
        }
    }
}

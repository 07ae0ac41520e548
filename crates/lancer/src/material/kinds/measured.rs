//! The `measured` material: a tabulated BRDF read from an RGL `.bsdf` file
//! ([`crate::material::MeasuredBxdf`]); the data is read once by the reader and shared.

use super::{MaterialDescKind, MaterialKind};
use crate::material::at_hit::HitLookup;
use crate::material::{BxDF, MeasuredBxdf, MeasuredData};

impl MaterialDescKind for &'static MeasuredData {
    type Built = &'static MeasuredData;
    const PBRT_NAME: &'static str = "measured";
    fn build(&self) -> &'static MeasuredData {
        self
    }
}

impl MaterialKind for &'static MeasuredData {
    #[inline(always)]
    fn bxdf(&self, at: &HitLookup) -> Option<BxDF> {
        Some(BxDF::Measured(MeasuredBxdf::new(self, at.lambda())))
    }
}

//! The `measured` material: a tabulated BRDF read from an RGL `.bsdf` file
//! ([`crate::material::MeasuredBxdf`]). Its description is the file's tables as read
//! ([`MeasuredFile`], shared by the materials that name one file); the build makes their
//! sampling tables ([`MeasuredData`]), once per distinct file ([`MeasuredData::shared`]).

use super::{MaterialDescKind, MaterialKind};
use crate::material::at_hit::HitLookup;
use crate::material::{BxDF, MeasuredBxdf, MeasuredData, MeasuredFile};
use std::sync::Arc;

impl MaterialDescKind for Arc<MeasuredFile> {
    type Built = &'static MeasuredData;
    const PBRT_NAME: &'static str = "measured";
    fn build(&self) -> &'static MeasuredData {
        MeasuredData::shared(self)
    }
}

impl MaterialKind for &'static MeasuredData {
    /// Never specular.
    #[inline(always)]
    fn may_be_specular(&self) -> bool {
        false
    }

    #[inline(always)]
    fn bxdf(&self, at: &HitLookup) -> Option<BxDF> {
        Some(BxDF::Measured(MeasuredBxdf::new(self, at.lambda())))
    }
}

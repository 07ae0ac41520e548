//! lancer's `Shape "sdf"`: a signed-distance expression (`"string expr"`), optionally clipped to
//! an object-space box (`"point3 min"`, `"point3 max"`, required when the expression is
//! unbounded: planes, endless repetition).
//!
//! Expression errors point into the scene file: the line of the string, and its column plus
//! the error's offset in the expression (exact unless escape sequences such as `\"` come
//! before the error in the string).

use super::params::{ParamList, ParamType};
use crate::error::{Location, SceneError};
use lancer::math::Vec3;
use lancer::scene::desc::Geometry;
use lancer::shape::{SdfDesc, SdfFunction};
use std::sync::Arc;

/// The geometry of `Shape "sdf"` from its parameters.
pub fn sdf_geometry(p: &ParamList) -> Result<Geometry, SceneError> {
    let Some(param) = p.find("expr", &[ParamType::String])? else {
        return Err(SceneError::general(
            "an \"sdf\" shape needs its expression, \"string expr\" \"…\" (for example \
             \"sphere(1)\")",
        ));
    };
    let src = p.string("expr")?.unwrap_or_default();
    let function = SdfFunction::parse(&src).map_err(|e| {
        // The value's token starts at its opening quote: the text starts one column later.
        let loc = Location {
            col: param.value_loc.col + 1 + e.offset as u32,
            ..param.value_loc.clone()
        };
        SceneError::at(loc, format!("in the sdf expression: {}", e.message))
    })?;
    let bounds = match (p.has("min"), p.has("max")) {
        (false, false) => None,
        (true, true) => {
            let (min, max) = (p.point3("min", Vec3::ZERO)?, p.point3("max", Vec3::ZERO)?);
            if !min.cmplt(max).all() {
                return Err(p.error_at(
                    "max",
                    format!(
                        "the sdf's \"min\" {min} must be below its \"max\" {max} on every axis"
                    ),
                ));
            }
            Some((min, max))
        }
        _ => {
            let name = if p.has("min") { "min" } else { "max" };
            return Err(p.error_at(
                name,
                "an sdf's box needs both \"point3 min\" and \"point3 max\"",
            ));
        }
    };
    // Whether the solid is bounded is lancer's rule, checked with the other shapes' rules.
    Ok(Geometry::Sdf(SdfDesc {
        function: Arc::new(function),
        bounds,
    }))
}

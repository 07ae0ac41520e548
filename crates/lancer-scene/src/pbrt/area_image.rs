//! pbrt-v4's image area light: `AreaLightSource "diffuse" "string filename" "x.png"`, whose
//! radiance is the image looked up by the hit's uv (see [`lancer::light::AreaImage`]).
//!
//! As pbrt-v4's `DiffuseAreaLight::Create`: `L` may not be given with `filename`; the image
//! must hold no infinite or NaN value; its texels are multiplied by `scale` (RGB passes
//! through: the light's normalisation is the colour space's illuminant, as for `"rgb L"`);
//! `"float power"` Φ multiplies that by Φ / (π · sides · A · k), k the image's mean
//! luminance — this reader divides by k, the scene build by π · sides · A per primitive.
//! The image is read like an `imagemap` texture's (8-bit PNGs as sRGB unless `encoding`
//! says otherwise) and kept as a spectrum texture of the scene, which the light reads.

use super::convert::Reader;
use crate::error::{Location, SceneError};
use lancer::image::WrapMode;
use lancer::math::{Rgb, luminance};
use lancer::scene::desc::AreaLightDesc;
use lancer::texture::{ImageFilter, ImageTextureDesc, Mapping2D, SpectrumTextureDesc, UvMapping};

/// The image texture of area light `a` when its parameters name a `filename` (`None`
/// otherwise), with `a.l` turned into the factor of its texels.
pub fn area_light_image(
    r: &Reader,
    a: &mut AreaLightDesc,
    loc: &Location,
) -> Result<Option<SpectrumTextureDesc>, SceneError> {
    let params = r.params;
    if !params.has("filename") {
        return Ok(None);
    }
    let at = |message: String| SceneError::at(loc.clone(), message);
    if params.has("L") {
        return Err(params.error_at(
            "L",
            "a \"diffuse\" area light takes either \"L\" or \"filename\", not both (as in \
             pbrt-v4)",
        ));
    }
    let (path, encoding) = r.image_file("a \"diffuse\" area light")?;
    let image = r
        .images
        .rgb(&path, encoding)
        .map_err(|e| at(e.to_string()))?;
    if image.texels.iter().any(|&t| !Rgb::from(t).is_finite()) {
        return Err(at(format!(
            "{}: the image holds infinite or NaN values and cannot be a light",
            path.display()
        )));
    }
    if a.power.is_some() {
        // k = mean luminance of the texels (pbrt-v4's k_e before π · sides · A).
        let k = image
            .texels
            .iter()
            .map(|&t| luminance(Rgb::from(t)) as f64)
            .sum::<f64>()
            / image.texels.len() as f64;
        if k > 0.0 {
            a.l /= k as f32;
        }
    }
    Ok(Some(SpectrumTextureDesc::Image(ImageTextureDesc {
        image,
        to_srgb: None,
        mip: false,
        mapping: Mapping2D::Uv(UvMapping::default()),
        wrap: WrapMode::Clamp,
        scale: 1.0,
        invert: false,
        filter: ImageFilter::Bilinear,
    })))
}

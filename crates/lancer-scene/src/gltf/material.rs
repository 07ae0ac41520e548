//! glTF's metallic-roughness materials as lancer materials.
//!
//! The glTF BRDF is a mix, by `metallic`, of a metal whose normal-incidence reflectance is the
//! base colour and of a dielectric (index 1.5) over a diffuse base of the base colour, both
//! with the GGX microfacet distribution of α = roughness². lancer builds the same from its own
//! materials:
//! - dielectric part: `coateddiffuse` (reflectance = base colour, η = 1.5, α = roughness²),
//! - metal part: `conductor` with `reflectance` = base colour, α = roughness²,
//! - `mix` of the two with amount = metallic (only when metallic is neither 0 nor 1 everywhere).
//!
//! Factors multiply their textures and are baked into the texels when the images are loaded:
//! base colour = `baseColorFactor` × `baseColorTexture` (sRGB), metallic = `metallicFactor` ×
//! B of `metallicRoughnessTexture`, α = (`roughnessFactor` × G)² (linear). Emission
//! (`emissiveFactor` × `KHR_materials_emissive_strength`, × the mean of `emissiveTexture`,
//! since lancer's area lights are uniform) makes the shape an area light. `alphaMode` MASK
//! becomes a 0/1 alpha cut-out at `alphaCutoff`, BLEND lancer's stochastic alpha.

use super::loader::{GltfLoader, MaterialInfo};
use crate::image_read::{DecodedImage, Encoding, decode_image};
use ::gltf::material::AlphaMode;
use ::gltf::texture::{MagFilter, WrappingMode};
use lancer::image::Image;
use lancer::material::MaterialDesc;
use lancer::material::{CoatedDiffuseMaterial, ConductorMaterial, DiffuseMaterial, MixMaterial};
use lancer::math::Rgb;
use lancer::texture::{
    FloatTex, FloatTextureDesc, ImageFilter, ImageTextureDesc, SpectrumTex, SpectrumTextureDesc,
    UvMapping, WrapMode,
};
use std::path::PathBuf;
use std::sync::Arc;

/// Index of refraction of glTF's dielectric layer (the spec's fixed 1.5, F0 = 4 %).
pub const DIELECTRIC_ETA: f32 = 1.5;
/// Thickness of the coating of `coateddiffuse` (pbrt-v4's default).
const COAT_THICKNESS: f32 = 0.01;

/// How a texture is sampled.
struct Sampling {
    wrap: WrapMode,
    nearest: bool,
    mapping: UvMapping,
}

/// `KHR_texture_transform`'s offset (du, dv) and scale (su, sv) in lancer's (u, v), where
/// v_lancer = 1 − v_glTF: glTF looks up v' = sv·v + dv, so lancer must look up
/// 1 − v' = sv·v_lancer + (1 − sv − dv).
pub fn uv_mapping(offset: [f32; 2], scale: [f32; 2]) -> UvMapping {
    UvMapping {
        su: scale[0],
        sv: scale[1],
        du: offset[0],
        dv: 1.0 - scale[1] - offset[1],
    }
}

fn wrap_mode(w: WrappingMode) -> WrapMode {
    match w {
        WrappingMode::ClampToEdge => WrapMode::Clamp,
        WrappingMode::MirroredRepeat => WrapMode::Mirror,
        WrappingMode::Repeat => WrapMode::Repeat,
    }
}

fn image_texture(image: Image, s: &Sampling) -> ImageTextureDesc {
    ImageTextureDesc {
        // Read without MIP filtering (as before footprints existed), point or bilinear as
        // the sampler asks.
        image: Arc::new(image),
        to_srgb: None,
        mip: false,
        mapping: s.mapping.into(),
        wrap: s.wrap,
        scale: 1.0,
        invert: false,
        filter: if s.nearest {
            ImageFilter::Point
        } else {
            ImageFilter::Bilinear
        },
    }
}

/// The same image with every texel replaced by `f(rgb, alpha)`.
fn map_texels(d: &DecodedImage, f: impl Fn(Rgb, f32) -> Rgb) -> Image {
    let texels = d
        .rgb
        .texels
        .iter()
        .enumerate()
        .map(|(i, &c)| f(c.into(), d.alpha.as_ref().map_or(1.0, |a| a[i])).into())
        .collect();
    Image::new(d.rgb.width, d.rgb.height, texels).expect("same size as the decoded image")
}

impl GltfLoader<'_> {
    /// Decodes image `index` with `encoding` (each pair decoded once).
    fn image(&mut self, index: usize, encoding: Encoding) -> Result<Arc<DecodedImage>, String> {
        let key = (index, encoding == Encoding::Srgb);
        if let Some(d) = self.images.get(&key) {
            return Ok(d.clone());
        }
        // The image's JSON, read directly: the `gltf` crate's `Image::source` unwraps a
        // missing `uri` or `mimeType` (a panic found by fuzzing), and the format is told by
        // the bytes anyway.
        let img = self
            .doc
            .as_json()
            .images
            .get(index)
            .ok_or_else(|| format!("image {index} does not exist"))?;
        let (bytes, name) = match (&img.buffer_view, &img.uri) {
            (Some(view), _) => {
                let view = self.doc.views().nth(view.value()).ok_or_else(|| {
                    format!("image {index}: buffer view {} does not exist", view.value())
                })?;
                (
                    super::data::view_bytes(&self.buffers, &view)?.to_vec(),
                    PathBuf::from(format!("{} (image {index})", self.name)),
                )
            }
            (None, Some(uri)) => {
                let bytes = super::data::read_uri(uri, &self.dir)
                    .map_err(|e| format!("image {index}: {e}"))?;
                let name = if uri.starts_with("data:") {
                    PathBuf::from(format!("{} (image {index})", self.name))
                } else {
                    self.dir.join(uri)
                };
                (bytes, name)
            }
            (None, None) => {
                return Err(format!("image {index} has neither a uri nor a bufferView"));
            }
        };
        let decoded = Arc::new(decode_image(&name, &bytes, encoding).map_err(|e| e.to_string())?);
        self.images.insert(key, decoded.clone());
        Ok(decoded)
    }

    /// The decoded image and sampling of a texture reference, warning about what is not used.
    fn texture(
        &mut self,
        info: &::gltf::texture::Info,
        what: &str,
        encoding: Encoding,
    ) -> Result<(Arc<DecodedImage>, Sampling), String> {
        if info.tex_coord() != 0 {
            self.warn(format!(
                "{what} uses TEXCOORD_{}; lancer reads TEXCOORD_0 only and uses it instead",
                info.tex_coord()
            ));
        }
        let mut mapping = UvMapping::default();
        if let Some(t) = info.texture_transform() {
            if t.rotation() != 0.0 {
                self.warn(format!(
                    "{what}: KHR_texture_transform's rotation is not supported; only its offset and scale are used"
                ));
            }
            if t.tex_coord().is_some_and(|c| c != 0) {
                self.warn(format!(
                    "{what}: KHR_texture_transform's texCoord is not supported; TEXCOORD_0 is used"
                ));
            }
            mapping = uv_mapping(t.offset(), t.scale());
        }
        let tex = info.texture();
        let sampler = tex.sampler();
        let sampling = Sampling {
            wrap: wrap_mode(sampler.wrap_s()),
            nearest: sampler.mag_filter() == Some(MagFilter::Nearest),
            mapping,
        };
        if sampler.wrap_s() != sampler.wrap_t() {
            self.warn(format!(
                "{what}: different wrap modes in s and t; the s mode is used for both"
            ));
        }
        Ok((self.image(tex.source().index(), encoding)?, sampling))
    }

    /// The lancer material for glTF material `index` (`None`: the primitive has none, and gets
    /// the light grey of bare meshes), made on first use.
    pub(super) fn material(&mut self, index: Option<usize>) -> Result<MaterialInfo, String> {
        if let Some(info) = self.material_cache.get(&index) {
            return Ok(*info);
        }
        let info = match index.and_then(|i| self.doc.materials().nth(i)) {
            None => MaterialInfo {
                material: self.grey_material(),
                alpha: None,
                emission: None,
                double_sided: false,
            },
            Some(m) => self.convert_material(&m)?,
        };
        self.material_cache.insert(index, info);
        Ok(info)
    }

    fn grey_material(&mut self) -> u32 {
        self.materials.push(MaterialDesc::Diffuse(DiffuseMaterial {
            reflectance: SpectrumTex::Const(Rgb::splat(crate::mesh_scene::defaults::ALBEDO)),
        }));
        (self.materials.len() - 1) as u32
    }

    fn push_spectrum(&mut self, t: SpectrumTextureDesc) -> SpectrumTex {
        self.spectrum_textures.push(t);
        SpectrumTex::Tex((self.spectrum_textures.len() - 1) as u32)
    }

    fn push_float(&mut self, t: FloatTextureDesc) -> FloatTex {
        self.float_textures.push(t);
        FloatTex::Tex((self.float_textures.len() - 1) as u32)
    }

    fn convert_material(&mut self, m: &::gltf::Material) -> Result<MaterialInfo, String> {
        let label = match m.name() {
            Some(n) => format!("material {} '{n}'", m.index().unwrap_or(0)),
            None => format!("material {}", m.index().unwrap_or(0)),
        };
        let pbr = m.pbr_metallic_roughness();
        let [r, g, b, a] = pbr.base_color_factor();
        let factor = Rgb::new(r, g, b);

        // Base colour (sRGB texture × factor) and, for MASK/BLEND, alpha (linear).
        let (base, alpha) = match pbr.base_color_texture() {
            Some(info) => {
                let what = format!("{label} baseColorTexture");
                let (img, s) = self.texture(&info, &what, Encoding::Srgb)?;
                let base = map_texels(&img, |c, _| c * factor);
                let base = self.push_spectrum(SpectrumTextureDesc::Image(image_texture(base, &s)));
                let alpha = match m.alpha_mode() {
                    AlphaMode::Opaque => None,
                    mode => {
                        // Alpha is linear in glTF: decode once more without the sRGB curve.
                        let (lin, s) = self.texture(&info, &what, Encoding::Linear)?;
                        let cutoff = m.alpha_cutoff().unwrap_or(0.5);
                        let img = map_texels(&lin, |_, alpha| {
                            let v = alpha * a;
                            Rgb::splat(match mode {
                                AlphaMode::Mask => (v >= cutoff) as u8 as f32,
                                _ => v,
                            })
                        });
                        Some(self.push_float(FloatTextureDesc::Image(image_texture(img, &s))))
                    }
                };
                (base, alpha)
            }
            None => {
                let alpha = match m.alpha_mode() {
                    AlphaMode::Opaque => None,
                    AlphaMode::Mask => Some(FloatTex::Const(
                        (a >= m.alpha_cutoff().unwrap_or(0.5)) as u8 as f32,
                    )),
                    AlphaMode::Blend => Some(FloatTex::Const(a)),
                };
                (SpectrumTex::Const(factor.clamp(Rgb::ZERO, Rgb::ONE)), alpha)
            }
        };

        // Metallic and α = roughness².
        let (mf, rf) = (pbr.metallic_factor(), pbr.roughness_factor());
        let (metallic, alpha_r, metal_range) = match pbr.metallic_roughness_texture() {
            Some(info) => {
                let what = format!("{label} metallicRoughnessTexture");
                let (img, s) = self.texture(&info, &what, Encoding::Linear)?;
                let metal = map_texels(&img, |c, _| Rgb::splat(c.z * mf));
                let (lo, hi) = metal
                    .texels
                    .iter()
                    .fold((f32::INFINITY, f32::NEG_INFINITY), |(lo, hi), c| {
                        (lo.min(c.x), hi.max(c.x))
                    });
                let rough = map_texels(&img, |c, _| Rgb::splat((c.y * rf).powi(2)));
                let metallic = self.push_float(FloatTextureDesc::Image(image_texture(metal, &s)));
                let alpha_r = self.push_float(FloatTextureDesc::Image(image_texture(rough, &s)));
                (metallic, alpha_r, (lo, hi))
            }
            None => (FloatTex::Const(mf), FloatTex::Const(rf * rf), (mf, mf)),
        };

        if m.normal_texture().is_some() {
            self.warn(format!(
                "{label}: normalTexture is not supported yet (no tangent-space normal mapping); the mesh normals are used"
            ));
        }

        let dielectric = MaterialDesc::CoatedDiffuse(CoatedDiffuseMaterial {
            reflectance: base,
            uroughness: alpha_r,
            vroughness: alpha_r,
            thickness: FloatTex::Const(COAT_THICKNESS),
            eta: lancer::spectrum::Ior::Constant(DIELECTRIC_ETA),
            albedo: SpectrumTex::Const(Rgb::ZERO),
            g: FloatTex::Const(0.0),
            max_depth: 10,
            n_samples: 1,
            remap_roughness: false,
        });
        let metal = MaterialDesc::Conductor(ConductorMaterial {
            eta: SpectrumTex::Const(Rgb::ONE),
            k: SpectrumTex::Const(Rgb::ZERO),
            reflectance: Some(base),
            uroughness: alpha_r,
            vroughness: alpha_r,
            remap_roughness: false,
        });
        let material = if metal_range.1 <= 0.0 {
            self.materials.push(dielectric);
            self.materials.len() - 1
        } else if metal_range.0 >= 1.0 {
            self.materials.push(metal);
            self.materials.len() - 1
        } else {
            self.materials.push(dielectric);
            self.materials.push(metal);
            let n = self.materials.len() as u32;
            // Mix: the second material with probability `amount` = metallic.
            self.materials.push(MaterialDesc::Mix(MixMaterial {
                materials: [n - 2, n - 1],
                amount: metallic,
            }));
            self.materials.len() - 1
        } as u32;

        // Emission: factor × strength × mean of the texture.
        let strength = m.emissive_strength().unwrap_or(1.0);
        let mut emission = Rgb::from(m.emissive_factor()) * strength;
        if let Some(info) = m.emissive_texture()
            && emission.max_element() > 0.0
        {
            let what = format!("{label} emissiveTexture");
            let (img, _) = self.texture(&info, &what, Encoding::Srgb)?;
            let n = img.rgb.texels.len().max(1) as f32;
            let mean = img
                .rgb
                .texels
                .iter()
                .fold(Rgb::ZERO, |s, &c| s + Rgb::from(c))
                / n;
            emission *= mean;
            self.warn(format!(
                "{what}: lancer's area lights are uniform; the texture's mean colour is used"
            ));
        }
        Ok(MaterialInfo {
            material,
            alpha,
            emission: (emission.max_element() > 0.0 && emission.is_finite()).then_some(emission),
            double_sided: m.double_sided(),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use lancer::math::Vec2;

    #[test]
    fn texture_transform_composes_with_the_v_flip() {
        // glTF looks up (su·u + du, sv·v + dv); lancer holds v_l = 1 − v and its image's v
        // runs upwards, so its lookup must land on 1 − (sv·v + dv).
        let (offset, scale) = ([0.25, 0.5], [2.0, 0.5]);
        let m = uv_mapping(offset, scale);
        for (u, v) in [(0.0, 0.0), (0.3, 0.7), (1.0, 0.2)] {
            let got = m.map(Vec2::new(u, 1.0 - v));
            let want = Vec2::new(scale[0] * u + offset[0], 1.0 - (scale[1] * v + offset[1]));
            assert!((got - want).length() < 1e-6, "{got} {want}");
        }
    }
}

//! From a directive's type and parameters to lancer's plain data: materials, textures, shapes,
//! lights and the rendering options, with pbrt-v4's defaults.
//!
//! Each function reads the parameters it knows; the caller then reports the others as unused.
//! Something lancer does not support yet comes back as `Unsupported` with what it does instead,
//! for the caller to turn into a warning.

use super::params::{ColorParam, FloatParam, ParamList};
use super::parser::SearchPath;
use crate::error::{Location, SceneError};
use crate::image_read::{Encoding, ImageCache};
use crate::obj::read_obj;
use crate::ply::read_ply;
use crate::vox::{default_palette, linear_palette, read_vox};
use lancer::material::Material;
use lancer::math::{Rgb, Vec3};
use lancer::sampling::SamplerKind;
use lancer::scene::desc::{FilterDesc, Geometry, Integrator};
use lancer::shape::{BilinearMesh, CurveBasis, CurveDesc, CurveType, TriangleMesh};
use lancer::spectrum::{SpectrumKind, named_spectrum, spectrum_to_rgb};
use lancer::texture::{
    FloatTex, FloatTexture, ImageTexture, SpectrumTex, SpectrumTexture, UvMapping, WrapMode,
};
use std::collections::HashMap;
use std::sync::Arc;

/// Largest image side accepted (a film of 65536² pixels would already need ~100 GiB).
pub const MAX_RESOLUTION: i32 = 1 << 16;

/// Named textures defined so far, by kind.
#[derive(Default)]
pub struct TextureNames {
    /// Float textures: name → index in the scene's list.
    pub floats: HashMap<String, u32>,
    /// Spectrum textures: name → index.
    pub spectra: HashMap<String, u32>,
}

impl TextureNames {
    fn float(&self, name: &str, loc: &Location) -> Result<FloatTex, SceneError> {
        self.floats
            .get(name)
            .map(|&i| FloatTex::Tex(i))
            .ok_or_else(|| {
                let hint = if self.spectra.contains_key(name) {
                    " (there is a spectrum texture of that name)"
                } else {
                    ""
                };
                SceneError::at(
                    loc.clone(),
                    format!("no float texture named \"{name}\"{hint}"),
                )
            })
    }

    fn spectrum(&self, name: &str, loc: &Location) -> Result<SpectrumTex, SceneError> {
        self.spectra
            .get(name)
            .map(|&i| SpectrumTex::Tex(i))
            .ok_or_else(|| {
                let hint = if self.floats.contains_key(name) {
                    " (there is a float texture of that name)"
                } else {
                    ""
                };
                SceneError::at(
                    loc.clone(),
                    format!("no spectrum texture named \"{name}\"{hint}"),
                )
            })
    }
}

/// What a conversion gives: the thing, or what lancer does instead of an unsupported one.
pub enum Converted<T> {
    /// Done.
    Done(T),
    /// Not supported: a warning (what lancer does instead) and the stand-in, if any.
    Unsupported(String, Option<T>),
}

/// A material, with the names a `mix` refers to (and where they are written), to resolve once
/// every named material is known.
pub type MaterialWithNames = (Material, Option<(Vec<String>, Location)>);

/// Reads parameters against the scene's textures and the directive's folder.
pub struct Reader<'a> {
    /// The parameters.
    pub params: &'a ParamList,
    /// Textures defined so far.
    pub textures: &'a TextureNames,
    /// The folder of the file holding the directive.
    pub dir: &'a SearchPath,
    /// Images decoded so far in this scene.
    pub images: &'a ImageCache,
}

impl Reader<'_> {
    fn spectrum_tex(
        &self,
        name: &str,
        default: Rgb,
        kind: SpectrumKind,
    ) -> Result<SpectrumTex, SceneError> {
        Ok(match self.params.color_or_texture(name, kind, self.dir)? {
            None => SpectrumTex::Const(default),
            Some(ColorParam::Const(c)) => SpectrumTex::Const(c),
            Some(ColorParam::Texture(t, loc)) => self.textures.spectrum(&t, &loc)?,
        })
    }

    fn opt_spectrum_tex(
        &self,
        name: &str,
        kind: SpectrumKind,
    ) -> Result<Option<SpectrumTex>, SceneError> {
        if self.params.has(name) {
            self.spectrum_tex(name, Rgb::ZERO, kind).map(Some)
        } else {
            Ok(None)
        }
    }

    fn float_tex(&self, name: &str, default: f32) -> Result<FloatTex, SceneError> {
        Ok(match self.params.float_or_texture(name)? {
            None => FloatTex::Const(default),
            Some(FloatParam::Const(v)) => FloatTex::Const(v),
            Some(FloatParam::Texture(t, loc)) => self.textures.float(&t, &loc)?,
        })
    }

    /// `uroughness`/`vroughness`, each defaulting to `roughness` (prefixed by `prefix`, as in
    /// `interface.` for the coated materials).
    fn roughness(&self, prefix: &str) -> Result<(FloatTex, FloatTex), SceneError> {
        let r = self.float_tex(&format!("{prefix}roughness"), 0.0)?;
        let u = self.params.has(&format!("{prefix}uroughness"));
        let v = self.params.has(&format!("{prefix}vroughness"));
        Ok((
            if u {
                self.float_tex(&format!("{prefix}uroughness"), 0.0)?
            } else {
                r
            },
            if v {
                self.float_tex(&format!("{prefix}vroughness"), 0.0)?
            } else {
                r
            },
        ))
    }

    fn named_rgb(name: &str) -> Rgb {
        named_spectrum(name)
            .map(|s| spectrum_to_rgb(&s, SpectrumKind::Unbounded))
            .expect("pbrt's named metal spectra are built in")
    }

    /// A material of pbrt-v4's `ty`. `Mix` comes back with placeholder indices: its material
    /// names are returned beside it for the caller to resolve.
    pub fn material(&self, ty: &str) -> Result<Converted<MaterialWithNames>, SceneError> {
        use SpectrumKind::{Albedo, Unbounded};
        let p = self.params;
        let remap = || p.bool("remaproughness", true);
        let m = match ty {
            "diffuse" => Material::Diffuse {
                reflectance: self.spectrum_tex("reflectance", Rgb::splat(0.5), Albedo)?,
            },
            "conductor" => {
                let (uroughness, vroughness) = self.roughness("")?;
                Material::Conductor {
                    eta: self.spectrum_tex("eta", Self::named_rgb("metal-Cu-eta"), Unbounded)?,
                    k: self.spectrum_tex("k", Self::named_rgb("metal-Cu-k"), Unbounded)?,
                    reflectance: self.opt_spectrum_tex("reflectance", Albedo)?,
                    uroughness,
                    vroughness,
                    remap_roughness: remap()?,
                }
            }
            "dielectric" => {
                let (uroughness, vroughness) = self.roughness("")?;
                Material::Dielectric {
                    eta: p.ior("eta", 1.5, self.dir)?,
                    uroughness,
                    vroughness,
                    remap_roughness: remap()?,
                }
            }
            "thindielectric" => Material::ThinDielectric {
                eta: p.ior("eta", 1.5, self.dir)?,
            },
            "diffusetransmission" => Material::DiffuseTransmission {
                reflectance: self.spectrum_tex("reflectance", Rgb::splat(0.25), Albedo)?,
                transmittance: self.spectrum_tex("transmittance", Rgb::splat(0.25), Albedo)?,
                scale: p.float("scale", 1.0)?,
            },
            "coateddiffuse" => {
                let (uroughness, vroughness) = self.roughness("")?;
                Material::CoatedDiffuse {
                    reflectance: self.spectrum_tex("reflectance", Rgb::splat(0.5), Albedo)?,
                    uroughness,
                    vroughness,
                    thickness: self.float_tex("thickness", 0.01)?,
                    eta: p.ior("eta", 1.5, self.dir)?,
                    albedo: self.spectrum_tex("albedo", Rgb::ZERO, Albedo)?,
                    g: self.float_tex("g", 0.0)?,
                    max_depth: p.int_in("maxdepth", 10, 0..=1000)? as u32,
                    n_samples: p.int_in("nsamples", 1, 1..=1000)? as u32,
                    remap_roughness: remap()?,
                }
            }
            "coatedconductor" => {
                let (interface_uroughness, interface_vroughness) = self.roughness("interface.")?;
                let (conductor_uroughness, conductor_vroughness) = self.roughness("conductor.")?;
                Material::CoatedConductor {
                    interface_uroughness,
                    interface_vroughness,
                    interface_eta: p.ior("interface.eta", 1.5, self.dir)?,
                    conductor_eta: self.spectrum_tex(
                        "conductor.eta",
                        Self::named_rgb("metal-Cu-eta"),
                        Unbounded,
                    )?,
                    k: self.spectrum_tex(
                        "conductor.k",
                        Self::named_rgb("metal-Cu-k"),
                        Unbounded,
                    )?,
                    reflectance: self.opt_spectrum_tex("reflectance", Albedo)?,
                    conductor_uroughness,
                    conductor_vroughness,
                    thickness: self.float_tex("thickness", 0.01)?,
                    albedo: self.spectrum_tex("albedo", Rgb::ZERO, Albedo)?,
                    g: self.float_tex("g", 0.0)?,
                    max_depth: p.int_in("maxdepth", 10, 0..=1000)? as u32,
                    n_samples: p.int_in("nsamples", 1, 1..=1000)? as u32,
                    remap_roughness: remap()?,
                }
            }
            "mix" => {
                let Some((names, loc)) = p.strings("materials")? else {
                    return Err(SceneError::general(
                        "material \"mix\" needs \"string materials\" [\"a\" \"b\"]",
                    ));
                };
                if names.len() != 2 {
                    return Err(SceneError::at(
                        loc,
                        format!(
                            "\"string materials\" of a mix names 2 materials, not {}",
                            names.len()
                        ),
                    ));
                }
                let m = Material::Mix {
                    materials: [0, 0],
                    amount: self.float_tex("amount", 0.5)?,
                };
                return Ok(Converted::Done((m, Some((names, loc)))));
            }
            "interface" | "" | "none" => Material::Interface,
            "measured" | "hair" | "subsurface" => {
                let m = Material::Diffuse {
                    reflectance: self.spectrum_tex("reflectance", Rgb::splat(0.5), Albedo)?,
                };
                return Ok(Converted::Unsupported(
                    format!(
                        "material \"{ty}\" is not supported yet; lancer renders it as \"diffuse\""
                    ),
                    Some((m, None)),
                ));
            }
            _ => {
                return Ok(Converted::Unsupported(
                    format!("unknown material \"{ty}\"; lancer renders it as \"diffuse\""),
                    Some((Material::default(), None)),
                ));
            }
        };
        Ok(Converted::Done((m, None)))
    }

    fn mapping(&self) -> Result<Option<String>, SceneError> {
        let p = self.params;
        let kind = p.string("mapping")?.unwrap_or_else(|| "uv".to_string());
        Ok((kind != "uv").then(|| {
            format!("texture mapping \"{kind}\" is not supported yet; lancer uses \"uv\"")
        }))
    }

    fn uv_mapping(&self) -> Result<UvMapping, SceneError> {
        let p = self.params;
        Ok(UvMapping {
            su: p.float("uscale", 1.0)?,
            sv: p.float("vscale", 1.0)?,
            du: p.float("udelta", 0.0)?,
            dv: p.float("vdelta", 0.0)?,
        })
    }

    /// An error at the place of parameter `name` (or without a place).
    fn param_error(&self, name: &str, message: String) -> SceneError {
        match self.params.location(name) {
            Some(l) => SceneError::at(l.clone(), message),
            None => SceneError::general(message),
        }
    }

    /// The image file named by `filename`, resolved against the directive's folders, and the
    /// `encoding` its 8- and 16-bit values go through (pbrt-v4's default: sRGB for `.png`,
    /// linear otherwise; JPEG is sRGB whatever it says, as in pbrt-v4).
    pub fn image_file(&self, what: &str) -> Result<(std::path::PathBuf, Encoding), SceneError> {
        let p = self.params;
        let Some(name) = p.string("filename")? else {
            return Err(SceneError::general(format!(
                "{what} needs the name of its image, \"string filename\""
            )));
        };
        let path = self.dir.resolve(&name);
        let is_png = path
            .extension()
            .and_then(|e| e.to_str())
            .is_some_and(|e| e.eq_ignore_ascii_case("png"));
        let encoding = match p.string("encoding")? {
            None if is_png => Encoding::Srgb,
            None => Encoding::Linear,
            Some(e) => Encoding::parse(&e).ok_or_else(|| {
                self.param_error(
                    "encoding",
                    format!(
                        "unknown encoding \"{e}\" (expected \"sRGB\", \"linear\" or \"gamma G\")"
                    ),
                )
            })?,
        };
        Ok((path, encoding))
    }

    /// pbrt-v4's `imagemap`: the image, its wrap mode and filter, `scale`, `invert` and the
    /// (u, v) mapping. Float textures read the value pbrt-v4's MIPMap gives (see
    /// [`crate::image_read::DecodedImage::float_image`]).
    fn image_texture(&self, float: bool) -> Result<Converted<ImageTexture>, SceneError> {
        let p = self.params;
        let mut notes = Vec::new();
        let (path, encoding) = self.image_file("an \"imagemap\" texture")?;
        let wrap = match p.string("wrap")?.as_deref().unwrap_or("repeat") {
            "repeat" => WrapMode::Repeat,
            "black" => WrapMode::Black,
            "clamp" => WrapMode::Clamp,
            "octahedralsphere" => WrapMode::OctahedralSphere,
            other => {
                return Err(self.param_error(
                    "wrap",
                    format!(
                        "unknown wrap mode \"{other}\" (expected \"repeat\", \"black\", \"clamp\" or \"octahedralsphere\")"
                    ),
                ));
            }
        };
        let nearest = match p.string("filter")?.as_deref().unwrap_or("bilinear") {
            "bilinear" => false,
            "point" => true,
            f @ ("trilinear" | "ewa" | "EWA") => {
                notes.push(format!(
                    "texture filter \"{f}\" is not supported yet (lancer has no ray differentials); lancer uses \"bilinear\""
                ));
                false
            }
            other => {
                notes.push(format!(
                    "unknown texture filter \"{other}\"; lancer uses \"bilinear\""
                ));
                false
            }
        };
        // Only matters for the EWA filter.
        p.float("maxanisotropy", 8.0)?;
        let image = if float {
            self.images.float(&path, encoding, nearest)
        } else {
            self.images.rgb(&path, encoding)
        }
        .map_err(|e| SceneError::general(e.to_string()))?;
        if let Some(w) = self.mapping()? {
            notes.push(w);
        }
        let t = ImageTexture {
            image,
            mapping: self.uv_mapping()?,
            wrap,
            scale: p.float("scale", 1.0)?,
            invert: p.bool("invert", false)?,
            nearest,
        };
        Ok(if notes.is_empty() {
            Converted::Done(t)
        } else {
            Converted::Unsupported(notes.join("; "), Some(t))
        })
    }

    /// A float texture of class `class`.
    pub fn float_texture(&self, class: &str) -> Result<Converted<FloatTexture>, SceneError> {
        let p = self.params;
        let t = match class {
            "constant" => FloatTexture::Constant(p.float("value", 1.0)?),
            "scale" => FloatTexture::Scale {
                tex: self.float_tex("tex", 1.0)?,
                scale: self.float_tex("scale", 1.0)?,
            },
            "mix" => FloatTexture::Mix {
                tex1: self.float_tex("tex1", 0.0)?,
                tex2: self.float_tex("tex2", 1.0)?,
                amount: self.float_tex("amount", 0.5)?,
            },
            "checkerboard" => {
                let t = FloatTexture::Checkerboard {
                    mapping: self.uv_mapping()?,
                    tex1: self.float_tex("tex1", 1.0)?,
                    tex2: self.float_tex("tex2", 0.0)?,
                };
                if let Some(w) = self.checkerboard_warning()? {
                    return Ok(Converted::Unsupported(w, Some(t)));
                }
                t
            }
            "imagemap" => {
                return Ok(match self.image_texture(true)? {
                    Converted::Done(t) => Converted::Done(FloatTexture::Image(t)),
                    Converted::Unsupported(w, t) => {
                        Converted::Unsupported(w, t.map(FloatTexture::Image))
                    }
                });
            }
            _ => {
                return Ok(Converted::Unsupported(
                    format!(
                        "float texture \"{class}\" is not supported yet; lancer uses the constant 1"
                    ),
                    Some(FloatTexture::Constant(1.0)),
                ));
            }
        };
        Ok(Converted::Done(t))
    }

    fn checkerboard_warning(&self) -> Result<Option<String>, SceneError> {
        let dim = self.params.int("dimension", 2)?;
        if dim != 2 {
            return Ok(Some(format!(
                "a {dim}D checkerboard is not supported yet; lancer uses the 2D one"
            )));
        }
        self.mapping()
    }

    /// A spectrum texture of class `class`.
    pub fn spectrum_texture(&self, class: &str) -> Result<Converted<SpectrumTexture>, SceneError> {
        use SpectrumKind::Albedo;
        let t = match class {
            "constant" => SpectrumTexture::Constant(
                self.params
                    .color("value", Albedo, self.dir)?
                    .unwrap_or(Rgb::ONE),
            ),
            "scale" => SpectrumTexture::Scale {
                tex: self.spectrum_tex("tex", Rgb::ONE, Albedo)?,
                scale: self.float_tex("scale", 1.0)?,
            },
            "mix" => SpectrumTexture::Mix {
                tex1: self.spectrum_tex("tex1", Rgb::ZERO, Albedo)?,
                tex2: self.spectrum_tex("tex2", Rgb::ONE, Albedo)?,
                amount: self.float_tex("amount", 0.5)?,
            },
            "checkerboard" => {
                let t = SpectrumTexture::Checkerboard {
                    mapping: self.uv_mapping()?,
                    tex1: self.spectrum_tex("tex1", Rgb::ONE, Albedo)?,
                    tex2: self.spectrum_tex("tex2", Rgb::ZERO, Albedo)?,
                };
                if let Some(w) = self.checkerboard_warning()? {
                    return Ok(Converted::Unsupported(w, Some(t)));
                }
                t
            }
            "imagemap" => {
                return Ok(match self.image_texture(false)? {
                    Converted::Done(t) => Converted::Done(SpectrumTexture::Image(t)),
                    Converted::Unsupported(w, t) => {
                        Converted::Unsupported(w, t.map(SpectrumTexture::Image))
                    }
                });
            }
            _ => {
                return Ok(Converted::Unsupported(
                    format!(
                        "spectrum texture \"{class}\" is not supported yet; lancer uses a constant grey 0.5"
                    ),
                    Some(SpectrumTexture::Constant(Rgb::splat(0.5))),
                ));
            }
        };
        Ok(Converted::Done(t))
    }

    /// A shape's geometry (object space) and its `alpha`.
    pub fn shape(&self, ty: &str) -> Result<Converted<(Geometry, Option<FloatTex>)>, SceneError> {
        let p = self.params;
        let positive = |v: f32| v > 0.0;
        // pbrt's sweep angle, in degrees, for every quadric.
        let phi_max = || p.float_checked("phimax", 360.0, "in (0, 360]", |v| v > 0.0 && v <= 360.0);
        // What lancer left out of a shape it still makes.
        let mut note = None;
        // A mesh read from a file; `None` when it is skipped (with its warning).
        let mut mesh = |c: Converted<TriangleMesh>| match c {
            Converted::Done(m) => Some(Geometry::TriangleMesh(Arc::new(m))),
            Converted::Unsupported(w, m) => {
                note = Some(w);
                m.map(|m| Geometry::TriangleMesh(Arc::new(m)))
            }
        };
        let geometry = match ty {
            "sphere" => {
                let radius = p.float_checked("radius", 1.0, "positive", positive)?;
                Geometry::Sphere {
                    radius,
                    z_min: p.float("zmin", -radius)?,
                    z_max: p.float("zmax", radius)?,
                    phi_max: phi_max()?,
                }
            }
            "disk" => {
                let radius = p.float_checked("radius", 1.0, "positive", positive)?;
                Geometry::Disk {
                    height: p.float("height", 0.0)?,
                    radius,
                    inner_radius: p.float_checked(
                        "innerradius",
                        0.0,
                        "at least 0 and less than the radius",
                        |v| (0.0..radius).contains(&v),
                    )?,
                    phi_max: phi_max()?,
                }
            }
            "cylinder" => Geometry::Cylinder {
                radius: p.float_checked("radius", 1.0, "positive", positive)?,
                z_min: p.float("zmin", -1.0)?,
                z_max: p.float("zmax", 1.0)?,
                phi_max: phi_max()?,
            },
            "cone" => Geometry::Cone {
                radius: p.float_checked("radius", 1.0, "positive", positive)?,
                height: p.float_checked("height", 1.0, "positive", positive)?,
                phi_max: phi_max()?,
            },
            "paraboloid" => {
                let z_max = p.float_checked("zmax", 1.0, "positive", positive)?;
                Geometry::Paraboloid {
                    radius: p.float_checked("radius", 1.0, "positive", positive)?,
                    z_min: p.float_checked("zmin", 0.0, "at least 0 and less than zmax", |v| {
                        (0.0..z_max).contains(&v)
                    })?,
                    z_max,
                    phi_max: phi_max()?,
                }
            }
            "hyperboloid" => {
                let p1 = p.point3("p1", Vec3::ZERO)?;
                let p2 = p.point3("p2", Vec3::ONE)?;
                if p1.z == p2.z {
                    let msg = format!(
                        "the hyperboloid's \"p1\" {p1} and \"p2\" {p2} are at the same height; \
                         the swept segment would be a flat annulus (use a disk)"
                    );
                    let loc = p.location("p2").or(p.location("p1")).cloned();
                    return Err(match loc {
                        Some(l) => SceneError::at(l, msg),
                        None => SceneError::general(msg),
                    });
                }
                Geometry::Hyperboloid {
                    p1,
                    p2,
                    phi_max: phi_max()?,
                }
            }
            // lancer extension: an axis-aligned box in object space.
            "box" => {
                let min = p.point3("min", Vec3::splat(-1.0))?;
                let max = p.point3("max", Vec3::ONE)?;
                if !min.cmplt(max).all() {
                    let msg = format!(
                        "the box's \"min\" {min} must be below its \"max\" {max} on every axis"
                    );
                    let loc = p.location("max").or(p.location("min")).cloned();
                    return Err(match loc {
                        Some(l) => SceneError::at(l, msg),
                        None => SceneError::general(msg),
                    });
                }
                Geometry::Box { min, max }
            }
            "plane" => {
                let n = p.normal("n", Vec3::Z)?;
                // Too short to normalise (components so small their squares underflow) counts
                // as zero.
                if n.try_normalize().is_none() {
                    let loc = p.location("n").cloned();
                    return Err(match loc {
                        Some(l) => SceneError::at(l, "the plane's normal \"n\" is zero"),
                        None => SceneError::general("the plane's normal \"n\" is zero"),
                    });
                }
                Geometry::Plane {
                    p: p.point3("p", Vec3::ZERO)?,
                    n,
                }
            }
            // lancer extension: a signed-distance object, sphere-traced.
            "sdf" => super::sdf::sdf_geometry(p)?,
            "trianglemesh" => Geometry::TriangleMesh(Arc::new(self.triangle_mesh(ty)?)),
            // pbrt's subdivision surface: the control mesh refined `levels` times (default 3)
            // and moved to the limit surface.
            "loopsubdiv" => {
                let levels = p.int_in("levels", 3, 0..=8)? as u32;
                let control = self.triangle_mesh(ty)?;
                Geometry::TriangleMesh(Arc::new(lancer::shape::loop_subdivide(&control, levels)))
            }
            "plymesh" | "objmesh" => {
                let read = if ty == "plymesh" {
                    self.ply_mesh()?
                } else {
                    self.obj_mesh()?
                };
                match mesh(read) {
                    Some(g) => g,
                    None => {
                        let warning = note.take().unwrap_or_default();
                        return Ok(Converted::Unsupported(warning, None));
                    }
                }
            }
            // lancer extension: a voxel grid, from a MagicaVoxel file or inline.
            "voxels" => {
                let (grid, warnings) = self.voxel_grid()?;
                if !warnings.is_empty() {
                    note = Some(warnings.join("; "));
                }
                Geometry::Voxels(Arc::new(grid))
            }
            "curve" => {
                let (desc, ignored_normals) = self.curve()?;
                if ignored_normals {
                    note = Some(
                        "curve normals \"N\" are only used by \"ribbon\" curves; ignored".into(),
                    );
                }
                Geometry::Curve(Arc::new(desc))
            }
            "bilinearmesh" => Geometry::BilinearMesh(Arc::new(self.bilinear_mesh()?)),
            _ => {
                return Ok(Converted::Unsupported(
                    format!("unknown shape \"{ty}\"; skipped"),
                    None,
                ));
            }
        };
        let alpha = match p.float_or_texture("alpha")? {
            None | Some(FloatParam::Const(1.0)) => None,
            Some(FloatParam::Const(a)) => Some(FloatTex::Const(a)),
            Some(FloatParam::Texture(t, loc)) => Some(self.textures.float(&t, &loc)?),
        };
        Ok(match note {
            None => Converted::Done((geometry, alpha)),
            Some(warning) => Converted::Unsupported(warning, Some((geometry, alpha))),
        })
    }

    /// lancer's `voxels`: the first model of the MagicaVoxel file `filename`, or the inline
    /// grid `integer dims` [nx ny nz] with `integer indices` (nx·ny·nz palette indices, x
    /// fastest, 0 = empty) and an optional `float palette` (linear r, g, b of indices 1, 2, …;
    /// indices it does not reach keep MagicaVoxel's default palette; `float` because pbrt's
    /// `rgb` holds one colour).
    fn voxel_grid(&self) -> Result<(lancer::shape::VoxelGrid, Vec<String>), SceneError> {
        let p = self.params;
        if let Some(name) = p.string("filename")? {
            let path = self.dir.resolve(&name);
            let model = read_vox(&path).map_err(|e| SceneError::general(e.to_string()))?;
            let warnings = model
                .warnings
                .iter()
                .map(|w| format!("{}: {w}", path.display()))
                .collect();
            return Ok((model.grid, warnings));
        }
        let err = |name: &str, msg: String| match p.location(name).cloned() {
            Some(l) => SceneError::at(l, msg),
            None => SceneError::general(msg),
        };
        let Some((dims, dloc)) = p.ints("dims")? else {
            return Err(SceneError::general(
                "a \"voxels\" shape needs \"string filename\" or \"integer dims\" with \"integer indices\"",
            ));
        };
        if dims.len() != 3 || dims.iter().any(|&d| d <= 0) {
            return Err(SceneError::at(
                dloc,
                format!("\"integer dims\" must be three positive values, got {dims:?}"),
            ));
        }
        let dims = [dims[0] as u32, dims[1] as u32, dims[2] as u32];
        let Some((indices, iloc)) = p.ints("indices")? else {
            return Err(err(
                "dims",
                "a \"voxels\" shape with \"integer dims\" needs \"integer indices\"".into(),
            ));
        };
        let count = dims.iter().map(|&d| d as u64).product::<u64>();
        if indices.len() as u64 != count {
            return Err(SceneError::at(
                iloc,
                format!(
                    "\"integer indices\" holds {} values for {}×{}×{} = {count} cells",
                    indices.len(),
                    dims[0],
                    dims[1],
                    dims[2]
                ),
            ));
        }
        if let Some(bad) = indices.iter().find(|&&i| !(0..=255).contains(&i)) {
            return Err(SceneError::at(
                iloc,
                format!("palette index {bad} in \"integer indices\" is not in 0..=255"),
            ));
        }
        let cells = indices.iter().map(|&i| i as u8).collect();
        let mut palette = linear_palette(&default_palette());
        if let Some(values) = p.floats("palette")? {
            if values.len() % 3 != 0 || values.len() > 3 * 255 {
                return Err(err(
                    "palette",
                    format!(
                        "\"float palette\" holds {} values: it needs 3 (r, g, b) per colour, at most 255 colours",
                        values.len()
                    ),
                ));
            }
            for (i, c) in values.chunks_exact(3).enumerate() {
                palette[i + 1] = Rgb::new(c[0], c[1], c[2]);
            }
        }
        let grid =
            lancer::shape::VoxelGrid::new(dims, cells, palette).map_err(|m| err("dims", m))?;
        Ok((grid, Vec::new()))
    }

    /// pbrt-v4's `objmesh`: every triangle of the OBJ file `filename` in one mesh (objects,
    /// groups and materials merged; the file's materials are not used, the shape takes the
    /// current pbrt material as any other shape does).
    fn obj_mesh(&self) -> Result<Converted<TriangleMesh>, SceneError> {
        let p = self.params;
        let Some(name) = p.string("filename")? else {
            return Err(SceneError::general(
                "an \"objmesh\" needs the name of its OBJ file, \"string filename\"",
            ));
        };
        let path = self.dir.resolve(&name);
        let obj = read_obj(&path).map_err(|e| SceneError::general(e.to_string()))?;
        let mesh = obj.merged_mesh();
        mesh.validate()
            .map_err(|e| SceneError::general(format!("{}: {e}", path.display())))?;
        if mesh.triangle_count() == 0 {
            return Ok(Converted::Unsupported(
                format!("{} has no faces; the shape is skipped", path.display()),
                None,
            ));
        }
        Ok(if obj.skipped_faces > 0 {
            Converted::Unsupported(
                format!(
                    "{}: {} faces with fewer than 3 vertices skipped",
                    path.display(),
                    obj.skipped_faces
                ),
                Some(mesh),
            )
        } else {
            Converted::Done(mesh)
        })
    }

    /// pbrt's `plymesh`: the triangles of the PLY file `filename` (gzipped when it ends in
    /// `.gz`). Displacement is not supported: the mesh is used as it is, with a warning.
    fn ply_mesh(&self) -> Result<Converted<TriangleMesh>, SceneError> {
        let p = self.params;
        let Some(name) = p.string("filename")? else {
            return Err(SceneError::general(
                "a \"plymesh\" needs the name of its PLY file, \"string filename\"",
            ));
        };
        let path = self.dir.resolve(&name);
        let ply = read_ply(&path).map_err(|e| SceneError::general(e.to_string()))?;
        if ply.mesh.triangle_count() == 0 {
            return Ok(Converted::Unsupported(
                format!("{} has no faces; the shape is skipped", path.display()),
                None,
            ));
        }
        let mut notes = Vec::new();
        if ply.skipped_faces > 0 {
            notes.push(format!(
                "{}: {} faces with fewer than 3 vertices skipped",
                path.display(),
                ply.skipped_faces
            ));
        }
        // Read (so that they are not also reported as unused) but not applied.
        let displaced = p.float_or_texture("displacement")?.is_some();
        let edge_length = p.has("edgelength");
        p.float("edgelength", 1.0)?;
        if displaced {
            notes.push(
                "displacement of a \"plymesh\" is not supported yet; the mesh is used undisplaced"
                    .into(),
            );
        } else if edge_length {
            notes.push(
                "\"edgelength\" only matters with \"displacement\", which lancer does not support yet; ignored"
                    .into(),
            );
        }
        Ok(if notes.is_empty() {
            Converted::Done(ply.mesh)
        } else {
            Converted::Unsupported(notes.join("; "), Some(ply.mesh))
        })
    }

    /// pbrt's `trianglemesh`: `P`, `indices` (optional for a single triangle), `N`, `uv`.
    fn triangle_mesh(&self, what: &str) -> Result<TriangleMesh, SceneError> {
        let p = self.params;
        let Some(positions) = p.point3s("P")? else {
            return Err(SceneError::general(format!(
                "a \"{what}\" needs vertex positions \"point3 P\""
            )));
        };
        let p_loc = p.location("P").cloned().expect("given");
        let indices: Vec<u32> = match p.ints("indices")? {
            Some((idx, loc)) => face_indices(idx, loc, 3, positions.len())?,
            None if positions.len() == 3 => vec![0, 1, 2],
            None => {
                return Err(SceneError::at(
                    p_loc,
                    format!("a \"{what}\" with more than 3 vertices needs \"integer indices\""),
                ));
            }
        };
        let per_vertex = |name: &str, n: usize| -> Result<(), SceneError> {
            if n != positions.len() {
                let loc = p.location(name).cloned().expect("given");
                return Err(SceneError::at(
                    loc,
                    format!(
                        "\"{name}\" has {n} entries for {} vertices",
                        positions.len()
                    ),
                ));
            }
            Ok(())
        };
        let normals = p.normals("N")?.unwrap_or_default();
        if !normals.is_empty() {
            per_vertex("N", normals.len())?;
        }
        let uv_name = if p.has("uv") { "uv" } else { "st" };
        let uvs = p.point2s(uv_name)?.unwrap_or_default();
        if !uvs.is_empty() {
            per_vertex(uv_name, uvs.len())?;
        }
        Ok(TriangleMesh {
            positions,
            normals,
            uvs,
            indices,
            flip_normal: false,
        })
    }

    /// pbrt-v4's `curve`: `P`, `basis` (`bezier` | `bspline`), `degree` (2 | 3), `type`
    /// (`flat` | `ribbon` | `cylinder`), `width` / `width0` / `width1`, `N` (ribbons: one per
    /// segment boundary), `splitdepth` (default 3). Also says whether `N` was given to a curve
    /// that does not use it.
    fn curve(&self) -> Result<(CurveDesc, bool), SceneError> {
        let p = self.params;
        let Some(points) = p.point3s("P")? else {
            return Err(SceneError::general(
                "a \"curve\" needs control points \"point3 P\"",
            ));
        };
        let non_negative = |v: f32| v >= 0.0 && v.is_finite();
        let width = p.float_checked("width", 1.0, "at least 0", non_negative)?;
        let width0 = p.float_checked("width0", width, "at least 0", non_negative)?;
        let width1 = p.float_checked("width1", width, "at least 0", non_negative)?;
        let degree = p.int_in("degree", 3, 2..=3)? as u32;
        let basis = match p.string("basis")?.as_deref() {
            None | Some("bezier") => CurveBasis::Bezier,
            Some("bspline") => CurveBasis::BSpline,
            Some(other) => {
                return Err(self.param_error(
                    "basis",
                    format!("unknown curve basis \"{other}\" (expected \"bezier\" or \"bspline\")"),
                ));
            }
        };
        let kind = match p.string("type")?.as_deref() {
            None | Some("flat") => CurveType::Flat,
            Some("ribbon") => CurveType::Ribbon,
            Some("cylinder") => CurveType::Cylinder,
            Some(other) => {
                return Err(self.param_error(
                    "type",
                    format!(
                        "unknown curve type \"{other}\" (expected \"flat\", \"ribbon\" or \"cylinder\")"
                    ),
                ));
            }
        };
        let split_depth = p.int_in("splitdepth", 3, 0..=10)? as u32;
        let mut normals = p.normals("N")?.unwrap_or_default();
        let ignored_normals = kind != CurveType::Ribbon && !normals.is_empty();
        if ignored_normals {
            normals.clear();
        }
        let desc = CurveDesc {
            points,
            basis,
            degree,
            kind,
            width0,
            width1,
            normals,
            split_depth,
        };
        desc.segment_count().map_err(|e| self.param_error("P", e))?;
        desc.validate().map_err(|e| {
            let at = if kind == CurveType::Ribbon && p.has("N") {
                "N"
            } else {
                "P"
            };
            self.param_error(at, e)
        })?;
        Ok((desc, ignored_normals))
    }

    /// pbrt-v4's `bilinearmesh`: `P`, `indices` (four per patch: p₀₀, p₁₀, p₀₁, p₁₁;
    /// optional for a single patch), `uv`, `N`.
    fn bilinear_mesh(&self) -> Result<BilinearMesh, SceneError> {
        let p = self.params;
        let Some(positions) = p.point3s("P")? else {
            return Err(SceneError::general(
                "a \"bilinearmesh\" needs vertex positions \"point3 P\"",
            ));
        };
        let indices: Vec<u32> = match p.ints("indices")? {
            Some((idx, loc)) if idx.is_empty() => {
                return Err(SceneError::at(loc, "\"integer indices\" is empty"));
            }
            Some((idx, loc)) => face_indices(idx, loc, 4, positions.len())?,
            None if positions.len() == 4 => vec![0, 1, 2, 3],
            None => {
                return Err(self.param_error(
                    "P",
                    "a \"bilinearmesh\" with other than 4 vertices needs \"integer indices\""
                        .into(),
                ));
            }
        };
        if positions.iter().any(|v| !v.is_finite()) {
            return Err(self.param_error("P", "vertex positions must be finite".into()));
        }
        let per_vertex = |name: &str, n: usize| -> Result<(), SceneError> {
            if n != positions.len() {
                return Err(self.param_error(
                    name,
                    format!(
                        "\"{name}\" has {n} entries for {} vertices",
                        positions.len()
                    ),
                ));
            }
            Ok(())
        };
        let normals = p.normals("N")?.unwrap_or_default();
        if !normals.is_empty() {
            per_vertex("N", normals.len())?;
        }
        let uvs = p.point2s("uv")?.unwrap_or_default();
        if !uvs.is_empty() {
            per_vertex("uv", uvs.len())?;
        }
        Ok(BilinearMesh {
            positions,
            normals,
            uvs,
            indices,
            flip_normal: false,
        })
    }

    /// The integrator, with pbrt-v4's defaults (`maxdepth` 5).
    pub fn integrator(&self, ty: &str) -> Result<Converted<Integrator>, SceneError> {
        let p = self.params;
        let max_depth = p.int_in("maxdepth", 5, 0..=100_000)? as u32;
        let path = || -> Result<Integrator, SceneError> {
            Ok(Integrator::Path {
                max_depth,
                regularize: p.bool("regularize", false)?,
            })
        };
        let i = match ty {
            "whitted" => Integrator::Whitted { max_depth },
            "path" | "volpath" => {
                // The light sampler is lancer's own; pbrt's choice needs no warning.
                let _ = p.string("lightsampler")?;
                path()?
            }
            "ambientocclusion" => Integrator::AmbientOcclusion {
                cos_sample: p.bool("cossample", true)?,
                max_distance: p.float("maxdistance", f32::INFINITY)?,
            },
            "normals" => Integrator::Normals,
            "depth" => Integrator::Depth,
            "bdpt" | "mlt" | "sppm" | "lightpath" | "randomwalk" | "simplepath"
            | "simplevolpath" | "aov" => {
                return Ok(Converted::Unsupported(
                    format!(
                        "integrator \"{ty}\" is not supported yet; lancer uses \"path\" with maxdepth {max_depth}"
                    ),
                    Some(path()?),
                ));
            }
            _ => {
                return Ok(Converted::Unsupported(
                    format!("unknown integrator \"{ty}\"; lancer uses \"path\""),
                    Some(path()?),
                ));
            }
        };
        Ok(Converted::Done(i))
    }

    /// The sampler: its point set and samples per pixel (the seed is read by the caller).
    pub fn sampler(&self, ty: &str) -> Result<Converted<(SamplerKind, u32)>, SceneError> {
        let p = self.params;
        let spp =
            || -> Result<u32, SceneError> { Ok(p.int_in("pixelsamples", 16, 1..=1 << 24)? as u32) };
        let s = match ty {
            "independent" => (SamplerKind::Independent, spp()?),
            "stratified" => {
                let x = p.int_in("xsamples", 4, 1..=4096)? as u32;
                let y = p.int_in("ysamples", 4, 1..=4096)? as u32;
                let jitter = p.bool("jitter", true)?;
                (
                    SamplerKind::Stratified {
                        xsamples: x,
                        ysamples: y,
                        jitter,
                    },
                    x * y,
                )
            }
            "sobol" | "zsobol" | "paddedsobol" => {
                let _ = p.string("randomization")?;
                (SamplerKind::Sobol, spp()?)
            }
            "halton" | "pmj02bn" => {
                let _ = p.string("randomization")?;
                return Ok(Converted::Unsupported(
                    format!("sampler \"{ty}\" is not supported yet; lancer uses \"zsobol\""),
                    Some((SamplerKind::Sobol, spp()?)),
                ));
            }
            _ => {
                return Ok(Converted::Unsupported(
                    format!("unknown sampler \"{ty}\"; lancer uses \"zsobol\""),
                    Some((SamplerKind::Sobol, spp()?)),
                ));
            }
        };
        Ok(Converted::Done(s))
    }

    /// The pixel filter, with pbrt-v4's default radii.
    pub fn filter(&self, ty: &str) -> Result<Converted<FilterDesc>, SceneError> {
        let p = self.params;
        let radius = |d: f32| -> Result<[f32; 2], SceneError> {
            let ok = |v: f32| v > 0.0 && v <= 64.0;
            Ok([
                p.float_checked("xradius", d, "in (0, 64]", ok)?,
                p.float_checked("yradius", d, "in (0, 64]", ok)?,
            ])
        };
        let f = match ty {
            "box" => FilterDesc::Box {
                radius: radius(0.5)?,
            },
            "gaussian" => FilterDesc::Gaussian {
                radius: radius(1.5)?,
                sigma: p.float_checked("sigma", 0.5, "positive", |v| v > 0.0)?,
            },
            "triangle" => FilterDesc::Triangle {
                radius: radius(2.0)?,
            },
            "mitchell" => FilterDesc::Mitchell {
                radius: radius(2.0)?,
                b: p.float("B", 1.0 / 3.0)?,
                c: p.float("C", 1.0 / 3.0)?,
            },
            "sinc" | "lanczos" => FilterDesc::Lanczos {
                radius: radius(4.0)?,
                tau: p.float_checked("tau", 3.0, "positive", |v| v > 0.0)?,
            },
            _ => {
                return Ok(Converted::Unsupported(
                    format!("unknown pixel filter \"{ty}\"; lancer uses \"gaussian\""),
                    Some(FilterDesc::default()),
                ));
            }
        };
        Ok(Converted::Done(f))
    }
}

/// A mesh's `"integer indices"`: `corners` per face, each naming one of `vertices` vertices.
fn face_indices(
    idx: Vec<i32>,
    loc: Location,
    corners: usize,
    vertices: usize,
) -> Result<Vec<u32>, SceneError> {
    if !idx.len().is_multiple_of(corners) {
        return Err(SceneError::at(
            loc,
            format!(
                "\"integer indices\" holds {} values, not a multiple of {corners}",
                idx.len()
            ),
        ));
    }
    if let Some(bad) = idx.iter().find(|&&i| i < 0 || i as usize >= vertices) {
        return Err(SceneError::at(
            loc,
            format!("index {bad} in \"integer indices\" is out of range for {vertices} vertices"),
        ));
    }
    Ok(idx.into_iter().map(|i| i as u32).collect())
}

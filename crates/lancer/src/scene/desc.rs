//! [`SceneDesc`]: a scene as plain data, the meeting point of every input format and the
//! renderer.
//!
//! Readers (pbrt, glTF, OBJ, PLY, or a program using the library) fill it in; [`crate::Scene`]
//! is built from it. Colours are already linear RGB (spectra are converted by the readers, with
//! pbrt's light normalisation applied); meshes are in object space with their transforms.

pub use crate::camera::desc::{CameraDesc, Projection};
use crate::film::PixelBounds;
use crate::integrator::Integrator;
/// Lights are described where their kinds live, in [`crate::light`].
pub use crate::light::{AreaLightDesc, LightDesc};
use crate::material::MaterialDesc;
use crate::math::{AnimatedTransform, Transform};
pub use crate::shape::Geometry;
use crate::shape::RuleError;
use crate::texture::{FloatTex, FloatTextureDesc, SpectrumTextureDesc};

/// A whole scene: what to render and how.
#[derive(Clone, Debug, Default)]
pub struct SceneDesc {
    /// The camera.
    pub camera: CameraDesc,
    /// The image.
    pub film: FilmDesc,
    /// How pixel samples are drawn.
    pub sampler: SamplerDesc,
    /// How samples are weighted into pixels.
    pub filter: FilterDesc,
    /// How light transport is computed.
    pub integrator: Integrator,
    /// Materials; shapes refer to them by index.
    pub materials: Vec<MaterialDesc>,
    /// Float textures; material parameters refer to them by index.
    pub float_textures: Vec<FloatTextureDesc>,
    /// Colour textures; material parameters refer to them by index.
    pub spectrum_textures: Vec<SpectrumTextureDesc>,
    /// Shapes placed in the world.
    pub shapes: Vec<ShapeDesc>,
    /// Light sources other than area lights (those belong to their shapes).
    pub lights: Vec<LightDesc>,
    /// Per light of `lights` (missing at the end: none): the spectrum its colour is a multiple
    /// of, when the scene gave one (spectral mode emits it).
    pub light_spectra: Vec<Option<crate::spectrum::dense::Measured>>,
    /// Per light of `lights` (missing at the end: vacuum): the medium it sits in (pbrt-v4's
    /// current outside medium at `LightSource`), where its light paths start.
    pub light_media: Vec<Option<u32>>,
    /// Object definitions (pbrt's `ObjectBegin`/`ObjectEnd`), for instancing.
    pub objects: Vec<ObjectDesc>,
    /// Placements of objects (pbrt's `ObjectInstance`).
    pub instances: Vec<InstanceDesc>,
    /// Participating media; shapes and the camera refer to them by index.
    pub media: Vec<crate::medium::MediumDesc>,
    /// The medium the camera sits in (`None`: vacuum).
    pub camera_medium: Option<u32>,
    /// What moves during the shutter interval (motion blur).
    pub motion: MotionDesc,
}

/// The film: the image's size, the part of it rendered, its exposure and where it goes.
#[derive(Clone, Debug, PartialEq)]
pub struct FilmDesc {
    /// Full image width in pixels.
    pub xresolution: u32,
    /// Full image height in pixels.
    pub yresolution: u32,
    /// Output file named in the scene (`filename`); the command line may override it.
    pub filename: Option<String>,
    /// Crop window in NDC (x_min, x_max, y_min, y_max), pbrt's `cropwindow`.
    pub crop_window: [f32; 4],
    /// Pixel bounds (x0, x1, y0, y1), half-open, pbrt's `pixelbounds`; overrides the crop
    /// window when set.
    pub pixel_bounds: Option<[i32; 4]>,
    /// Multiplies every pixel: `exposure time × iso / 100` in pbrt-v4 terms (1 by default).
    pub scale: f32,
    /// Largest sample value kept (pbrt's `maxcomponentvalue`), per component.
    pub max_component_value: f32,
    /// Write EXR as half floats (pbrt's `savefp16`; lancer defaults to full float).
    pub save_fp16: bool,
    /// The sensor's diagonal in millimetres (pbrt's `diagonal`, 35 by default): the realistic
    /// camera's film size.
    pub diagonal: f32,
    /// The sensor (pbrt's `sensor`; CIE 1931 by default).
    pub sensor: crate::spectrum::Sensor,
    /// White balance temperature in kelvin (pbrt's `whitebalance`; 0: none).
    pub white_balance: f32,
    /// The output colour space (pbrt's film `colorspace`, or a `ColorSpace` before `Film`).
    pub color_space: crate::spectrum::ColorSpace,
    /// What the film writes besides colour (pbrt's `gbuffer` film).
    pub gbuffer: Option<crate::film::gsums::GbufferDesc>,
    /// The wavelength buckets a `spectral` film writes besides colour.
    pub spectral: Option<crate::film::spectral::SpectralDesc>,
}

impl FilmDesc {
    /// The pixels to render: pbrt's `pixelbounds`, else its crop window rounded as pbrt-v4
    /// rounds it (⌈res·min⌉ to ⌈res·max⌉), clipped to the image.
    pub fn render_bounds(&self) -> PixelBounds {
        let (w, h) = (self.xresolution as i32, self.yresolution as i32);
        let full = PixelBounds {
            x0: 0,
            x1: w,
            y0: 0,
            y1: h,
        };
        if let Some([x0, x1, y0, y1]) = self.pixel_bounds {
            return PixelBounds { x0, x1, y0, y1 }.intersect(&full);
        }
        let [cx0, cx1, cy0, cy1] = self.crop_window;
        PixelBounds {
            x0: (w as f32 * cx0).ceil() as i32,
            x1: (w as f32 * cx1).ceil() as i32,
            y0: (h as f32 * cy0).ceil() as i32,
            y1: (h as f32 * cy1).ceil() as i32,
        }
        .intersect(&full)
    }
}

impl Default for FilmDesc {
    /// pbrt's default film: 1280 × 720.
    fn default() -> Self {
        FilmDesc {
            xresolution: 1280,
            yresolution: 720,
            filename: None,
            crop_window: [0.0, 1.0, 0.0, 1.0],
            pixel_bounds: None,
            scale: 1.0,
            max_component_value: f32::INFINITY,
            save_fp16: false,
            diagonal: crate::camera::desc::DEFAULT_DIAGONAL,
            sensor: crate::spectrum::Sensor::Cie1931,
            white_balance: 0.0,
            color_space: crate::spectrum::ColorSpace::Srgb,
            gbuffer: None,
            spectral: None,
        }
    }
}

/// Which sampler, how many samples, which seed.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SamplerDesc {
    /// The point set.
    pub kind: crate::sampling::SamplerKind,
    /// Samples per pixel.
    pub spp: u32,
    /// Seed (pbrt's `seed` parameter, or `--seed`).
    pub seed: u64,
    /// How next-event estimation chooses a light (pbrt's integrator `lightsampler`; `bvh`
    /// by default, as pbrt-v4).
    pub light_sampler: crate::light::LightSamplerKind,
}

impl Default for SamplerDesc {
    /// pbrt's default is `zsobol` with 16 samples; lancer's Owen-scrambled Sobol stands in.
    fn default() -> Self {
        SamplerDesc {
            kind: crate::sampling::SamplerKind::ZSobol {
                randomization: crate::sampling::Randomization::FastOwen,
            },
            spp: 16,
            seed: 0,
            light_sampler: crate::light::LightSamplerKind::Bvh,
        }
    }
}

/// Pixel reconstruction filter (sampled by importance, as pbrt-v4 does).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum FilterDesc {
    /// Box of the given radius (x, y).
    Box {
        /// Radius.
        radius: [f32; 2],
    },
    /// Gaussian with `sigma`, cut at `radius`.
    Gaussian {
        /// Radius.
        radius: [f32; 2],
        /// Standard deviation.
        sigma: f32,
    },
    /// Tent.
    Triangle {
        /// Radius.
        radius: [f32; 2],
    },
    /// Mitchell–Netravali with parameters B and C.
    Mitchell {
        /// Radius.
        radius: [f32; 2],
        /// B.
        b: f32,
        /// C.
        c: f32,
    },
    /// Windowed sinc.
    Lanczos {
        /// Radius.
        radius: [f32; 2],
        /// Number of sinc lobes in the window.
        tau: f32,
    },
}

impl FilterDesc {
    /// The filter's radius (x, y) in pixels: beyond it, its weight is zero.
    pub fn radius(&self) -> crate::math::Vec2 {
        let r = match self {
            FilterDesc::Box { radius }
            | FilterDesc::Gaussian { radius, .. }
            | FilterDesc::Triangle { radius }
            | FilterDesc::Mitchell { radius, .. }
            | FilterDesc::Lanczos { radius, .. } => *radius,
        };
        crate::math::Vec2::new(r[0], r[1])
    }
}

impl Default for FilterDesc {
    /// pbrt's default: Gaussian, radius 1.5, σ 0.5.
    fn default() -> Self {
        FilterDesc::Gaussian {
            radius: [1.5, 1.5],
            sigma: 0.5,
        }
    }
}

/// A shape placed in the world with its material and optional emission.
#[derive(Clone, Debug, PartialEq)]
pub struct ShapeDesc {
    /// The geometry, object space.
    pub geometry: Geometry,
    /// Object space → world space.
    pub object_to_world: Transform,
    /// pbrt's `ReverseOrientation`: flips the normal (and the emitting side).
    pub reverse_orientation: bool,
    /// Index into [`SceneDesc::materials`].
    pub material: u32,
    /// Emission, when the shape is an area light.
    pub area_light: Option<AreaLightDesc>,
    /// Alpha cut-out: where it is 0 the surface is absent.
    pub alpha: Option<FloatTex>,
    /// The media inside and outside the shape, when it bounds any (indices into
    /// [`SceneDesc::media`]).
    pub medium_interface: Option<crate::medium::MediumInterface>,
}

impl ShapeDesc {
    /// `geometry` placed as it is (object space = world space) with material `material`: no
    /// emission, alpha, media or reversed orientation.
    pub fn new(geometry: Geometry, material: u32) -> ShapeDesc {
        ShapeDesc {
            geometry,
            object_to_world: Transform::IDENTITY,
            reverse_orientation: false,
            material,
            area_light: None,
            alpha: None,
            medium_interface: None,
        }
    }

    /// [`Geometry::validate`], then, when the shape emits, [`Geometry::validate_emitter`].
    pub fn validate(&self) -> Result<(), RuleError> {
        self.geometry.validate()?;
        match self.area_light {
            Some(_) => self.geometry.validate_emitter(),
            None => Ok(()),
        }
    }
}

/// A named object definition (instancing).
#[derive(Clone, Debug, PartialEq)]
pub struct ObjectDesc {
    /// Its name in the scene file.
    pub name: String,
    /// Its shapes, in the object's own space.
    pub shapes: Vec<ShapeDesc>,
}

/// One placement of an object.
#[derive(Clone, Debug, PartialEq)]
pub struct InstanceDesc {
    /// Index into [`SceneDesc::objects`].
    pub object: u32,
    /// Object space → world space.
    pub object_to_world: Transform,
}

// What moves while the shutter is open (pbrt's `ActiveTransform` and `TransformTimes`): the
// camera, shapes and object instances whose transformation differs between the two times.
// Everything else in the [`SceneDesc`] stands still.

/// The moving parts of a scene; empty (the default) for a still scene.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct MotionDesc {
    /// Camera space → world space over time, when the camera moves (pbrt-v4 interpolates the
    /// camera-to-world transformation, the inverse of the CTM at `Camera`). Its start is the
    /// inverse of [`CameraDesc::camera_from_world`].
    pub camera: Option<AnimatedTransform>,
    /// Shapes that move.
    pub shapes: Vec<MovingShapeDesc>,
    /// Object instances that move.
    pub instances: Vec<MovingInstanceDesc>,
}

impl MotionDesc {
    /// True when nothing moves.
    pub fn is_empty(&self) -> bool {
        self.camera.is_none() && self.shapes.is_empty() && self.instances.is_empty()
    }
}

/// A shape whose placement changes over time.
#[derive(Clone, Debug, PartialEq)]
pub struct MovingShapeDesc {
    /// The shape; its `object_to_world` applies first (identity from the pbrt reader).
    pub shape: ShapeDesc,
    /// Then this moving transformation into the world.
    pub world_from_object: AnimatedTransform,
}

/// A placement of an object that changes over time.
#[derive(Clone, Debug, PartialEq)]
pub struct MovingInstanceDesc {
    /// Index into [`SceneDesc::objects`].
    pub object: u32,
    /// Object space → world space over time.
    pub object_to_world: AnimatedTransform,
}

#[cfg(test)]
mod tests;

//! The meaning of pbrt's directives: the current transformation matrix (the course's "repère du
//! monde"), the graphics state saved and restored by `AttributeBegin`/`AttributeEnd`, named
//! materials, textures, coordinate systems and objects, and the [`SceneDesc`] they build.

use super::area_image::area_light_image;
use super::cameras::{camera, frame_window};
use super::convert::{Fallback, Reader, TextureNames};
use super::light_spectra;
use super::lights::{area_light, light};
use super::materials::{MaterialWithNames, material};
use super::media::{CurrentMedia, Media};
use super::options::{film, filter, imaging_ratio, integrator, light_sampler, sampler, seed};
use super::params::{Param, ParamList};
use super::parser::{Directive, Located};
use super::search_path::SearchPath;
use super::shapes::{ShapeGeometry, shape};
use super::singular::{flatten, is_singular, unplaced};
use super::textures::{
    float_texture, needs_unbounded_variant, spectrum_texture, spectrum_texture_as,
};
use crate::LoadOptions;
use crate::error::{Location, SceneError, Warning};
use crate::image_read::ImageCache;
use lancer::material::MaterialDesc;
use lancer::material::MixMaterial;
use lancer::math::{AnimatedTransform, Transform};
use lancer::scene::desc::{
    AreaLightDesc, Geometry, InstanceDesc, MovingInstanceDesc, MovingShapeDesc, SceneDesc,
    ShapeDesc,
};
use lancer::spectrum::ColorSpace;
use lancer::spectrum::SpectrumKind::Unbounded;
use lancer::texture::FloatTex;
use std::collections::{HashMap, HashSet};

/// The material a shape gets: one already in the list, or a name resolved at the end (pbrt-v4
/// lets `NamedMaterial` come before `MakeNamedMaterial`).
#[derive(Clone, Debug)]
enum MaterialRef {
    Index(u32),
    Named(String, Location),
}

/// The deepest nesting of attribute, transform and object blocks accepted: far beyond any real
/// scene, and a bound on the memory the saved graphics states take.
pub const MAX_NESTING: usize = 10_000;

mod blocks;
mod built;
mod displaced;
pub mod entry;
mod integrator;
mod object_motion;
mod transforms;
mod volpath;

pub use built::Built;

/// What `AttributeBegin` saves.
#[derive(Clone, Debug)]
struct GraphicsState {
    ctm: Transform,
    /// The CTM at the shutter's end time (pbrt keeps two; they differ for moving things).
    ctm_end: Transform,
    /// Which of the two the transformation directives change (`ActiveTransform`).
    active: Active,
    /// The times of the two CTMs (`TransformTimes`; 0 and 1 by default).
    times: [f32; 2],
    reverse_orientation: bool,
    material: MaterialRef,
    area_light: Option<AreaLightDesc>,
    /// pbrt-v4's `Attribute "shape" …` defaults, by target.
    defaults: HashMap<String, Vec<Param>>,
    media: CurrentMedia,
    /// The colour space of `rgb` values (`ColorSpace`; it persists through `WorldBegin`).
    color_space: ColorSpace,
}

/// `ActiveTransform StartTime`, `EndTime` or `All`: which CTMs change.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct Active {
    start: bool,
    end: bool,
}

impl Active {
    const ALL: Active = Active {
        start: true,
        end: true,
    };
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Block {
    Attribute,
    Transform,
    Object,
    /// An imported file: it starts from a copy of the graphics state, which its end restores.
    Import,
}

impl Block {
    fn names(self) -> (&'static str, &'static str) {
        match self {
            Block::Attribute => ("AttributeBegin", "AttributeEnd"),
            Block::Transform => ("TransformBegin", "TransformEnd"),
            Block::Object => ("ObjectBegin", "ObjectEnd"),
            Block::Import => ("Import", "the end of the imported file"),
        }
    }
}

/// Where a material name must be written once every name is known.
enum Slot {
    Shape(usize),
    ObjectShape(u32, usize),
    MovingShape(usize),
    ObjectMovingShape(usize),
    Mix(u32, usize),
}

/// Builds a [`SceneDesc`] from a stream of directives.
pub struct Builder {
    desc: SceneDesc,
    gs: GraphicsState,
    stack: Vec<(Block, GraphicsState, Location)>,
    /// Named coordinate systems: both CTMs, as pbrt-v4 keeps them.
    named_coords: HashMap<String, (Transform, Transform)>,
    named_materials: HashMap<String, u32>,
    textures: TextureNames,
    media: Media,
    /// Images decoded so far, shared by the textures and lights that name the same file.
    images: ImageCache,
    object_names: HashMap<String, u32>,
    current_object: Option<u32>,
    in_world: bool,
    pending_materials: Vec<(Slot, String, Location)>,
    pending_instances: Vec<(String, AnimatedTransform, Location)>,
    /// Shapes moving inside object definitions, by object (see `object_motion`).
    object_moving: Vec<(u32, MovingShapeDesc)>,
    warnings: Vec<Warning>,
    warned: HashSet<&'static str>,
    frame_aspect: Option<f32>,
    iso: f32,
    option_seed: Option<u64>,
    sampler_seed: Option<u64>,
    displacer: displaced::Displacer,
}

impl Builder {
    fn new(options: &LoadOptions) -> Builder {
        let desc = SceneDesc {
            materials: vec![MaterialDesc::default()],
            ..SceneDesc::default()
        };
        Builder {
            desc,
            gs: GraphicsState {
                ctm: Transform::IDENTITY,
                ctm_end: Transform::IDENTITY,
                active: Active::ALL,
                times: [0.0, 1.0],
                reverse_orientation: false,
                material: MaterialRef::Index(0),
                area_light: None,
                defaults: HashMap::new(),
                media: CurrentMedia::default(),
                color_space: ColorSpace::Srgb,
            },
            stack: Vec::new(),
            named_coords: HashMap::new(),
            named_materials: HashMap::new(),
            textures: TextureNames::default(),
            media: Media::default(),
            images: ImageCache::default(),
            object_names: HashMap::new(),
            current_object: None,
            in_world: false,
            pending_materials: Vec::new(),
            pending_instances: Vec::new(),
            object_moving: Vec::new(),
            warnings: Vec::new(),
            warned: HashSet::new(),
            frame_aspect: None,
            iso: 100.0,
            option_seed: None,
            sampler_seed: None,
            displacer: displaced::Displacer::new(options),
        }
    }

    fn warn(&mut self, loc: &Location, message: impl Into<String>) {
        self.warnings.push(Warning {
            location: loc.clone(),
            message: message.into(),
        });
    }

    /// Warns once per `key` for the whole scene.
    fn warn_once(&mut self, key: &'static str, loc: &Location, message: impl Into<String>) {
        if self.warned.insert(key) {
            self.warn(loc, message);
        }
    }

    /// What a conversion gives, after passing on its warnings.
    fn accept<T>(&mut self, converted: Fallback<T>, loc: &Location) -> T {
        for w in converted.warnings {
            self.warn(loc, w);
        }
        converted.value
    }

    fn unused(&mut self, params: &ParamList, what: String) {
        params.report_unused(&what, &mut self.warnings);
    }

    /// Options (camera, film, …) belong before `WorldBegin`; shapes and lights after.
    fn require_options(&self, name: &str, loc: &Location) -> Result<(), SceneError> {
        if self.in_world {
            return Err(SceneError::at(
                loc.clone(),
                format!("{name} must come before WorldBegin"),
            ));
        }
        Ok(())
    }

    fn require_world(&self, name: &str, loc: &Location) -> Result<(), SceneError> {
        if !self.in_world {
            return Err(SceneError::at(
                loc.clone(),
                format!("{name} is only allowed after WorldBegin"),
            ));
        }
        Ok(())
    }

    fn defaults(&self, target: &str, params: ParamList) -> ParamList {
        match self.gs.defaults.get(target) {
            Some(d) => params.with_defaults(d),
            None => params,
        }
    }

    /// The frame of a directive with parameters: an option must come before `WorldBegin`; a
    /// world directive after it, with the `Attribute` defaults of its category filling in what
    /// it does not say. The parameters `body` leaves unread are warned about as parameters of
    /// `directive "label"`.
    fn with_params(
        &mut self,
        directive: &str,
        label: &str,
        params: ParamList,
        loc: &Location,
        body: impl FnOnce(&mut Self, &ParamList) -> Result<(), SceneError>,
    ) -> Result<(), SceneError> {
        let category = match directive {
            "Material" | "MakeNamedMaterial" => "material",
            "Texture" => "texture",
            "LightSource" | "AreaLightSource" => "light",
            "Shape" => "shape",
            _ => "",
        };
        let params = if category.is_empty() {
            self.require_options(directive, loc)?;
            params
        } else {
            self.require_world(directive, loc)?;
            self.defaults(category, params)
        };
        let params = params.in_color_space(self.gs.color_space);
        body(self, &params)?;
        self.unused(&params, format!("{directive} \"{label}\""));
        Ok(())
    }

    fn reader<'a>(&'a self, params: &'a ParamList, dir: &'a SearchPath) -> Reader<'a> {
        Reader {
            params,
            textures: &self.textures,
            dir,
            images: &self.images,
        }
    }

    /// One directive: the transformation and block directives change the graphics state,
    /// the others convert their parameters through the file of their kind.
    fn directive(&mut self, d: Located) -> Result<(), SceneError> {
        let Located {
            directive,
            loc,
            dir,
        } = d;
        use Directive as D;
        let loc = &loc;
        match directive {
            D::AttributeBegin => self.begin_block(Block::Attribute, loc),
            D::AttributeEnd => self.end_block(Block::Attribute, loc),
            D::TransformBegin => self.begin_block(Block::Transform, loc),
            D::TransformEnd => self.end_block(Block::Transform, loc),
            D::ObjectBegin(name) => self.object_begin(name, loc),
            D::ObjectEnd => self.end_block(Block::Object, loc),
            D::ObjectInstance(name) => self.object_instance(name, loc),
            D::ImportBegin(_) => {
                self.require_world("Import", loc)?;
                self.begin_block(Block::Import, loc)
            }
            D::ImportEnd => self.end_block(Block::Import, loc),
            D::Attribute(target, params) => self.attribute(target, params, loc),
            D::WorldBegin => self.world_begin(loc),
            // A tuning hint for pbrt's own structures: lancer always builds its BVH.
            D::WorldEnd | D::Accelerator(..) => Ok(()),
            D::Option(..)
            | D::ColorSpace(..)
            | D::Camera(..)
            | D::Film(..)
            | D::Sampler(..)
            | D::PixelFilter(..)
            | D::Integrator(..) => self.rendering_option(directive, &dir, loc),
            D::MakeNamedMedium(..)
            | D::MediumInterface(..)
            | D::Material(..)
            | D::MakeNamedMaterial(..)
            | D::NamedMaterial(..)
            | D::Texture(..)
            | D::LightSource(..)
            | D::AreaLightSource(..)
            | D::Shape(..) => self.world_content(directive, &dir, loc),
            transform => self.transform(transform, loc),
        }
    }

    /// The rendering options, each converted by [`super::options`] or [`super::cameras`].
    fn rendering_option(
        &mut self,
        d: Directive,
        dir: &SearchPath,
        loc: &Location,
    ) -> Result<(), SceneError> {
        use Directive as D;
        match d {
            D::Option(params) => {
                if let Some(s) = seed(&params)? {
                    self.option_seed = Some(s);
                }
                self.unused(&params, "Option".to_string());
                Ok(())
            }
            D::ColorSpace(name) => {
                self.gs.color_space = ColorSpace::from_name(&name).ok_or_else(|| {
                    SceneError::at(
                        loc.clone(),
                        format!(
                            "unknown colour space \"{name}\" (pbrt-v4 knows srgb, rec2020, \
                             aces2065-1 and dci-p3)"
                        ),
                    )
                })?;
                Ok(())
            }
            D::Camera(ty, params) => self.with_params("Camera", &ty, params, loc, |b, p| {
                if is_singular(&b.gs.ctm) || is_singular(&b.gs.ctm_end) {
                    let m = "the camera's transformation is singular (it flattens space)";
                    return Err(SceneError::at(loc.clone(), m));
                }
                let c = b.accept(camera(&b.reader(p, dir), &ty, b.gs.ctm, loc)?, loc);
                (b.desc.camera, b.frame_aspect) = (c.camera, c.frame_aspect);
                b.media.set_camera(&b.gs.media, loc);
                // pbrt-v4 interpolates camera → world, the inverse of the CTM.
                let [t0, t1] = b.gs.times;
                let (start, end) = (b.gs.ctm.inverse(), b.gs.ctm_end.inverse());
                let moving = AnimatedTransform::new(start, t0, end, t1);
                b.desc.motion.camera = moving.is_animated().then_some(moving);
                b.named_coords.insert("camera".to_string(), (start, end));
                Ok(())
            }),
            D::Film(ty, params) => self.with_params("Film", &ty, params, loc, |b, p| {
                let f = b.accept(film(p, &ty, b.desc.film.clone())?, loc);
                (b.desc.film, b.iso) = (f.film, f.iso);
                // The film writes in the colour space current at `Film`.
                b.desc.film.color_space = b.gs.color_space;
                Ok(())
            }),
            D::Sampler(ty, params) => self.with_params("Sampler", &ty, params, loc, |b, p| {
                let s = b.accept(sampler(p, &ty)?, loc);
                (b.desc.sampler.kind, b.desc.sampler.spp) = (s.kind, s.spp);
                b.sampler_seed = s.seed.or(b.sampler_seed);
                Ok(())
            }),
            D::PixelFilter(ty, params) => {
                self.with_params("PixelFilter", &ty, params, loc, |b, p| {
                    b.desc.filter = b.accept(filter(p, &ty)?, loc);
                    Ok(())
                })
            }
            D::Integrator(ty, params) => {
                self.with_params("Integrator", &ty, params, loc, |b, p| {
                    b.desc.integrator = b.accept(integrator(p, &ty)?, loc);
                    b.desc.sampler.light_sampler = b.accept(light_sampler(p, &ty)?, loc);
                    Ok(())
                })
            }
            other => unreachable!("not a rendering option: {other:?}"),
        }
    }

    /// Media, materials, textures, lights and shapes, each converted by the file of its kind.
    fn world_content(
        &mut self,
        d: Directive,
        dir: &SearchPath,
        loc: &Location,
    ) -> Result<(), SceneError> {
        use Directive as D;
        match d {
            D::MakeNamedMedium(name, params) => {
                let (p, ctm) = (self.defaults("medium", params), self.gs.ctm);
                let (desc, warnings) = (&mut self.desc, &mut self.warnings);
                self.media.define(&name, &p, ctm, dir, desc, warnings, loc)
            }
            D::MediumInterface(inside, outside) => self.gs.media.set(inside, outside),
            D::Material(ty, params) => self.with_params("Material", &ty, params, loc, |b, p| {
                b.gs.material = MaterialRef::Index(b.material(&ty, p, dir, loc)?);
                Ok(())
            }),
            D::MakeNamedMaterial(name, params) => {
                self.with_params("MakeNamedMaterial", &name, params, loc, |b, p| {
                    b.named_material(&name, p, dir, loc)
                })
            }
            D::NamedMaterial(name) => {
                self.require_world("NamedMaterial", loc)?;
                self.gs.material = MaterialRef::Named(name, loc.clone());
                Ok(())
            }
            D::Texture(name, ty, class, params) => {
                self.with_params("Texture", &class, params, loc, |b, p| {
                    b.texture(name, &ty, &class, p, dir, loc)
                })
            }
            D::LightSource(ty, params) => {
                self.with_params("LightSource", &ty, params, loc, |b, p| {
                    if is_singular(&b.gs.ctm) {
                        p.mark_all_used();
                        b.warn(loc, unplaced(&format!("LightSource \"{ty}\"")));
                        return Ok(());
                    }
                    if b.gs.ctm.m != b.gs.ctm_end.m {
                        b.warn_once(
                            "moving-light",
                            loc,
                            "a light's transformation changes during the shutter: pbrt-v4 \
                             keeps lights at their start pose, and so does lancer",
                        );
                    }
                    if matches!(
                        b.desc.integrator,
                        lancer::integrator::Integrator::SimpleVolPath { .. }
                    ) && matches!(
                        ty.as_str(),
                        "point" | "spot" | "goniometric" | "projection" | "distant"
                    ) {
                        // pbrt-v4's SimpleVolPathIntegrator refuses them too: no walk can
                        // hit a light at a point or in one direction.
                        return Err(SceneError::at(
                            loc.clone(),
                            format!(
                                "integrator \"simplevolpath\" supports only area and infinite \
                                 lights, not a \"{ty}\" light"
                            ),
                        ));
                    }
                    let l = light(&b.reader(p, dir), &ty, b.gs.ctm, loc)?;
                    if let Some(l) = b.accept(l, loc) {
                        let spectrum = light_spectra::light_spectrum(&l, p, dir)?;
                        let medium = b.media.outside(&b.gs.media, loc)?;
                        b.desc.lights.push(l);
                        light_spectra::record(&mut b.desc, spectrum);
                        if let Some(m) = medium {
                            // Vacuum for the lights before it (the list may be shorter).
                            let i = b.desc.lights.len() - 1;
                            b.desc.light_media.resize(i, None);
                            b.desc.light_media.push(Some(m));
                        }
                    }
                    Ok(())
                })
            }
            D::AreaLightSource(ty, params) => {
                self.with_params("AreaLightSource", &ty, params, loc, |b, p| {
                    let mut a = area_light(p, &ty, dir, loc)?;
                    a.spectrum = light_spectra::emission_spectrum(p, "L", dir)?;
                    if let Some(t) = area_light_image(&b.reader(p, dir), &mut a, loc)? {
                        a.image = Some(b.desc.spectrum_textures.len() as u32);
                        b.desc.spectrum_textures.push(t);
                    }
                    b.gs.area_light = Some(a);
                    Ok(())
                })
            }
            D::Shape(ty, params) => {
                self.with_params("Shape", &ty, params, loc, |b, p| b.shape(&ty, p, dir, loc))
            }
            other => unreachable!("not a world directive: {other:?}"),
        }
    }

    /// Adds a material; a `mix` has its two names resolved at the end.
    fn material(
        &mut self,
        ty: &str,
        params: &ParamList,
        dir: &SearchPath,
        loc: &Location,
    ) -> Result<u32, SceneError> {
        let converted = material(&self.reader(params, dir), ty, loc)?;
        let MaterialWithNames {
            material,
            mix,
            bump,
        } = self.accept(converted, loc);
        let index = self.desc.materials.len() as u32;
        self.desc.materials.push(material);
        if let Some((names, nloc)) = mix {
            for (k, n) in names.into_iter().enumerate() {
                self.pending_materials
                    .push((Slot::Mix(index, k), n, nloc.clone()));
            }
        }
        Ok(bump.map_or(index, |b| b.push_around(index, &mut self.desc)))
    }

    /// `MakeNamedMaterial "name" "string type" …`.
    fn named_material(
        &mut self,
        name: &str,
        params: &ParamList,
        dir: &SearchPath,
        loc: &Location,
    ) -> Result<(), SceneError> {
        let Some(ty) = params.string("type")? else {
            return Err(SceneError::at(
                loc.clone(),
                format!("MakeNamedMaterial \"{name}\" needs a \"string type\""),
            ));
        };
        let index = self.material(&ty, params, dir, loc)?;
        if self
            .named_materials
            .insert(name.to_string(), index)
            .is_some()
        {
            self.warn(loc, format!("named material \"{name}\" redefined"));
        }
        Ok(())
    }

    fn texture(
        &mut self,
        name: String,
        ty: &str,
        class: &str,
        params: &ParamList,
        dir: &SearchPath,
        loc: &Location,
    ) -> Result<(), SceneError> {
        match ty {
            "float" => {
                let converted = float_texture(&self.reader(params, dir), class, &self.gs.ctm, loc)?;
                let t = self.accept(converted, loc);
                self.desc.float_textures.push(t);
                let index = self.desc.float_textures.len() as u32 - 1;
                self.textures.floats.insert(name, index);
            }
            "spectrum" | "color" | "rgb" => {
                let converted =
                    spectrum_texture(&self.reader(params, dir), class, &self.gs.ctm, loc)?;
                let t = self.accept(converted, loc);
                self.desc.spectrum_textures.push(t);
                let index = self.desc.spectrum_textures.len() as u32 - 1;
                // Its unbounded variant, when that differs (its warnings are the ones above).
                self.textures.unbounded.remove(&name);
                if needs_unbounded_variant(params, &self.textures) {
                    let reader = self.reader(params, dir);
                    let u = spectrum_texture_as(&reader, class, &self.gs.ctm, loc, Unbounded)?;
                    self.desc.spectrum_textures.push(u.value);
                    let u_index = self.desc.spectrum_textures.len() as u32 - 1;
                    self.textures.unbounded.insert(name.clone(), u_index);
                }
                self.textures.spectra.insert(name, index);
            }
            _ => {
                return Err(SceneError::at(
                    loc.clone(),
                    format!(
                        "texture type \"{ty}\" is unknown (expected \"float\" or \"spectrum\")"
                    ),
                ));
            }
        }
        Ok(())
    }

    fn shape(
        &mut self,
        ty: &str,
        params: &ParamList,
        dir: &SearchPath,
        loc: &Location,
    ) -> Result<(), SceneError> {
        let emits = self.gs.area_light.is_some();
        let converted = shape(&self.reader(params, dir), ty, emits, loc)?;
        let Some(ShapeGeometry {
            geometry,
            also,
            alpha,
            displacement,
        }) = self.accept(converted, loc)
        else {
            // Skipped whole: its warning says so; its parameters need no warnings of their own.
            params.mark_all_used();
            return Ok(());
        };
        // Moving, flattened by a singular transformation, or placed by the CTM: decided (and
        // warned about) once for the directive, whose two geometries (a plymesh's triangles
        // and quads) share their attributes and vertices.
        let geometry = match displacement {
            Some(d) => self.displaced(geometry, d, loc)?,
            None => geometry,
        };
        let moving = self.moving_shape(emits, alpha.is_some(), loc)?;
        let singular = moving.is_none() && is_singular(&self.gs.ctm);
        for (k, geometry) in std::iter::once(geometry).chain(also).enumerate() {
            let (geometry, object_to_world) = if moving.is_some() {
                (geometry, Transform::IDENTITY)
            } else if singular {
                let flat = flatten(geometry, ty, &self.gs.ctm);
                let flat = if k == 0 {
                    self.accept(flat, loc)
                } else {
                    flat.value
                };
                match flat {
                    Some(g) => (g, Transform::IDENTITY),
                    None => continue,
                }
            } else {
                (geometry, self.gs.ctm)
            };
            self.place_shape(geometry, object_to_world, moving, alpha, loc)?;
        }
        Ok(())
    }

    /// One geometry of a `Shape` directive, placed by `object_to_world` (or moving by
    /// `moving`), under the current attributes, in the world or the object being defined.
    fn place_shape(
        &mut self,
        geometry: Geometry,
        object_to_world: Transform,
        moving: Option<AnimatedTransform>,
        alpha: Option<FloatTex>,
        loc: &Location,
    ) -> Result<(), SceneError> {
        let (material, pending) = match &self.gs.material {
            MaterialRef::Index(i) => (*i, None),
            MaterialRef::Named(name, nloc) => match self.named_materials.get(name) {
                Some(&i) => (i, None),
                None => (0, Some((name.clone(), nloc.clone()))),
            },
        };
        let mut area_light = self.gs.area_light;
        if area_light.is_some() && self.current_object.is_some() {
            self.warn_once(
                "instanced-area-light",
                loc,
                "area lights inside object definitions are not supported; those shapes do not emit",
            );
            area_light = None;
        }
        let sd = ShapeDesc {
            medium_interface: self.media.interface(&self.gs.media, loc)?,
            geometry,
            object_to_world,
            reverse_orientation: self.gs.reverse_orientation,
            material,
            area_light,
            alpha,
        };
        let slot = match (self.current_object, moving) {
            (Some(o), Some(world_from_object)) => {
                self.object_moving.push((
                    o,
                    MovingShapeDesc {
                        shape: sd,
                        world_from_object,
                    },
                ));
                Slot::ObjectMovingShape(self.object_moving.len() - 1)
            }
            (None, Some(world_from_object)) => {
                let moving = &mut self.desc.motion.shapes;
                moving.push(MovingShapeDesc {
                    shape: sd,
                    world_from_object,
                });
                Slot::MovingShape(moving.len() - 1)
            }
            (Some(o), None) => {
                let shapes = &mut self.desc.objects[o as usize].shapes;
                shapes.push(sd);
                Slot::ObjectShape(o, shapes.len() - 1)
            }
            (None, None) => {
                self.desc.shapes.push(sd);
                Slot::Shape(self.desc.shapes.len() - 1)
            }
        };
        if let Some((name, nloc)) = pending {
            self.pending_materials.push((slot, name, nloc));
        }
        Ok(())
    }

    /// Resolves what could be named before its definition, checks every block is closed, and
    /// applies the options that depend on several directives.
    fn finish(mut self, end: Location) -> Result<Built, SceneError> {
        if let Some((b, _, open)) = self.stack.last() {
            let (begin, end) = b.names();
            return Err(SceneError::at(
                open.clone(),
                format!("this {begin} is never closed by {end}"),
            ));
        }
        if !self.in_world {
            return Err(SceneError::at(
                end,
                "the scene ends before WorldBegin: there is nothing to render",
            ));
        }
        for (slot, name, loc) in std::mem::take(&mut self.pending_materials) {
            let Some(&index) = self.named_materials.get(&name) else {
                return Err(SceneError::at(
                    loc,
                    format!("no material named \"{name}\" (MakeNamedMaterial defines one)"),
                ));
            };
            match slot {
                Slot::Shape(i) => self.desc.shapes[i].material = index,
                Slot::MovingShape(i) => self.desc.motion.shapes[i].shape.material = index,
                Slot::ObjectMovingShape(i) => self.object_moving[i].1.shape.material = index,
                Slot::ObjectShape(o, i) => self.desc.objects[o as usize].shapes[i].material = index,
                Slot::Mix(m, k) => {
                    if let MaterialDesc::Mix(MixMaterial { materials, .. }) =
                        &mut self.desc.materials[m as usize]
                    {
                        materials[k] = index;
                    }
                }
            }
        }
        for (name, ctm, loc) in std::mem::take(&mut self.pending_instances) {
            let Some(&object) = self.object_names.get(&name) else {
                return Err(SceneError::at(
                    loc,
                    format!("no object named \"{name}\" (ObjectBegin defines one)"),
                ));
            };
            self.place_moving_object_shapes(object, &ctm, &loc);
            if ctm.is_animated() {
                self.desc.motion.instances.push(MovingInstanceDesc {
                    object,
                    object_to_world: ctm,
                });
            } else {
                self.desc.instances.push(InstanceDesc {
                    object,
                    object_to_world: *ctm.start(),
                });
            }
        }
        self.desc.camera_medium = self.media.camera_medium()?;
        self.sppm_writes_rgb(&end);
        self.volumes_need_volpath(&end);
        let camera = &mut self.desc.camera;
        camera.screen_window = camera.screen_window.or(self.frame_aspect.map(frame_window));
        self.desc.film.scale = imaging_ratio(camera.shutter, self.iso);
        self.desc.sampler.seed = self.sampler_seed.or(self.option_seed).unwrap_or(0);
        Ok(Built {
            desc: self.desc,
            warnings: self.warnings,
            notes: self.displacer.notes,
        })
    }
}

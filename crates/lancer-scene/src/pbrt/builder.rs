//! The meaning of pbrt's directives: the current transformation matrix (the course's "repère du
//! monde"), the graphics state saved and restored by `AttributeBegin`/`AttributeEnd`, named
//! materials, textures, coordinate systems and objects, and the [`SceneDesc`] they build.

use super::convert::{Converted, MAX_RESOLUTION, Reader, TextureNames};
use super::params::{Param, ParamList};
use super::parser::SearchPath;
use super::parser::{Directive, Located, Parser};
use crate::error::{Location, SceneError, Warning};
use crate::image_read::{Encoding, ImageCache};
use lancer::light::EnvMapping;
use lancer::material::Material;
use lancer::math::{Mat4, Rgb, Transform, Vec3};
use lancer::scene::desc::{
    AreaLightDesc, CameraDesc, InstanceDesc, LightDesc, ObjectDesc, Projection, SceneDesc,
    ShapeDesc,
};
use lancer::spectrum::SpectrumKind;
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

/// What `AttributeBegin` saves.
#[derive(Clone, Debug)]
struct GraphicsState {
    ctm: Transform,
    reverse_orientation: bool,
    material: MaterialRef,
    area_light: Option<AreaLightDesc>,
    /// pbrt-v4's `Attribute "shape" …` defaults, by target.
    defaults: HashMap<String, Vec<Param>>,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Block {
    Attribute,
    Transform,
    Object,
}

impl Block {
    fn names(self) -> (&'static str, &'static str) {
        match self {
            Block::Attribute => ("AttributeBegin", "AttributeEnd"),
            Block::Transform => ("TransformBegin", "TransformEnd"),
            Block::Object => ("ObjectBegin", "ObjectEnd"),
        }
    }
}

/// Where a material name must be written once every name is known.
enum Slot {
    Shape(usize),
    ObjectShape(u32, usize),
    Mix(u32, usize),
}

/// Builds a [`SceneDesc`] from a stream of directives.
pub struct Builder {
    desc: SceneDesc,
    gs: GraphicsState,
    stack: Vec<(Block, GraphicsState, Location)>,
    named_coords: HashMap<String, Transform>,
    named_materials: HashMap<String, u32>,
    textures: TextureNames,
    /// Images decoded so far, shared by the textures and lights that name the same file.
    images: ImageCache,
    object_names: HashMap<String, u32>,
    current_object: Option<u32>,
    in_world: bool,
    pending_materials: Vec<(Slot, String, Location)>,
    pending_instances: Vec<(String, Transform, Location)>,
    warnings: Vec<Warning>,
    warned: HashSet<&'static str>,
    /// Transforms apply to the shutter's start (`ActiveTransform StartTime`/`All`).
    start_active: bool,
    frame_aspect: Option<f32>,
    iso: f32,
    option_seed: Option<u64>,
    sampler_seed: Option<u64>,
}

/// Gives an error without a place the place of the directive it came from.
fn locate(mut e: SceneError, loc: &Location) -> SceneError {
    if e.location.is_none() {
        e.location = Some(loc.clone());
    }
    e
}

impl Builder {
    fn new() -> Builder {
        let desc = SceneDesc {
            materials: vec![Material::default()],
            ..SceneDesc::default()
        };
        Builder {
            desc,
            gs: GraphicsState {
                ctm: Transform::IDENTITY,
                reverse_orientation: false,
                material: MaterialRef::Index(0),
                area_light: None,
                defaults: HashMap::new(),
            },
            stack: Vec::new(),
            named_coords: HashMap::new(),
            named_materials: HashMap::new(),
            textures: TextureNames::default(),
            images: ImageCache::default(),
            object_names: HashMap::new(),
            current_object: None,
            in_world: false,
            pending_materials: Vec::new(),
            pending_instances: Vec::new(),
            warnings: Vec::new(),
            warned: HashSet::new(),
            start_active: true,
            frame_aspect: None,
            iso: 100.0,
            option_seed: None,
            sampler_seed: None,
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

    /// What a conversion gives, after warning about an unsupported one; `None` when lancer
    /// skips it.
    fn accept<T>(&mut self, converted: Converted<T>, loc: &Location) -> Option<T> {
        match converted {
            Converted::Done(t) => Some(t),
            Converted::Unsupported(warning, t) => {
                self.warn(loc, warning);
                t
            }
        }
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

    /// `ctm ← ctm · t`, as pbrt post-multiplies every transformation.
    fn concat(
        &mut self,
        t: Option<Transform>,
        what: &str,
        loc: &Location,
    ) -> Result<(), SceneError> {
        let t = t.ok_or_else(|| {
            SceneError::at(
                loc.clone(),
                format!(
                    "{what} gives a singular transformation (it flattens space and cannot be inverted)"
                ),
            )
        })?;
        if self.start_active {
            self.gs.ctm = self.gs.ctm * t;
        }
        Ok(())
    }

    fn defaults(&self, target: &str, params: ParamList) -> ParamList {
        match self.gs.defaults.get(target) {
            Some(d) => params.with_defaults(d),
            None => params,
        }
    }

    /// The frame of a world directive with parameters: it must come after `WorldBegin`, the
    /// `Attribute` defaults of `category` fill in what it does not say, and the parameters
    /// `body` leaves unread are warned about as parameters of `what`.
    fn world_directive(
        &mut self,
        directive: &str,
        category: &str,
        params: ParamList,
        loc: &Location,
        what: String,
        body: impl FnOnce(&mut Self, &ParamList) -> Result<(), SceneError>,
    ) -> Result<(), SceneError> {
        self.require_world(directive, loc)?;
        let params = self.defaults(category, params);
        body(self, &params)?;
        self.unused(&params, what);
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

    fn directive(&mut self, d: Located) -> Result<(), SceneError> {
        let Located {
            directive,
            loc,
            dir,
        } = d;
        use Directive as D;
        match directive {
            D::Identity => {
                if self.start_active {
                    self.gs.ctm = Transform::IDENTITY;
                }
            }
            D::Translate([x, y, z]) => {
                self.concat(Some(Transform::translate(Vec3::new(x, y, z))), "Translate", &loc)?
            }
            D::Scale([x, y, z]) => {
                self.concat(Transform::scale(Vec3::new(x, y, z)), "Scale", &loc)?
            }
            D::Rotate([a, x, y, z]) => {
                let r = Transform::rotate(a, Vec3::new(x, y, z));
                if r.is_none() {
                    return Err(SceneError::at(loc, "Rotate about a zero axis"));
                }
                self.concat(r, "Rotate", &loc)?
            }
            D::LookAt(v) => {
                let t = Transform::look_at(
                    Vec3::new(v[0], v[1], v[2]),
                    Vec3::new(v[3], v[4], v[5]),
                    Vec3::new(v[6], v[7], v[8]),
                );
                if t.is_none() {
                    return Err(SceneError::at(
                        loc,
                        "LookAt: the eye and the point looked at coincide, or 'up' is parallel \
                         to the viewing direction",
                    ));
                }
                self.concat(t, "LookAt", &loc)?
            }
            D::Transform(m) => {
                // pbrt's 16 numbers are the matrix column by column.
                let t = Transform::from_matrix(Mat4::from_cols_array(&m));
                if self.start_active {
                    self.gs.ctm = Transform::IDENTITY;
                }
                self.concat(t, "Transform", &loc)?
            }
            D::ConcatTransform(m) => {
                let t = Transform::from_matrix(Mat4::from_cols_array(&m));
                self.concat(t, "ConcatTransform", &loc)?
            }
            D::CoordinateSystem(name) => {
                self.named_coords.insert(name, self.gs.ctm);
            }
            D::CoordSysTransform(name) => match self.named_coords.get(&name) {
                Some(t) => self.gs.ctm = *t,
                None => self.warn(
                    &loc,
                    format!("no coordinate system named \"{name}\"; CoordSysTransform ignored"),
                ),
            },
            D::ActiveTransform(which) => {
                self.start_active = which != "EndTime";
                if which != "StartTime" {
                    self.warn_once(
                        "motion",
                        &loc,
                        "motion blur is not supported yet: lancer uses the transformations at the shutter's opening",
                    );
                }
            }
            D::TransformTimes(_) => self.warn_once(
                "motion",
                &loc,
                "motion blur is not supported yet: lancer uses the transformations at the shutter's opening",
            ),
            D::ReverseOrientation => self.gs.reverse_orientation ^= true,
            D::AttributeBegin => self.begin_block(Block::Attribute, loc)?,
            D::TransformBegin => self.begin_block(Block::Transform, loc)?,
            D::AttributeEnd => self.end_block(Block::Attribute, &loc)?,
            D::TransformEnd => self.end_block(Block::Transform, &loc)?,
            D::Attribute(target, params) => {
                if !matches!(
                    target.as_str(),
                    "shape" | "light" | "material" | "medium" | "texture"
                ) {
                    return Err(SceneError::at(
                        loc,
                        format!(
                            "Attribute target \"{target}\" is unknown (expected shape, light, \
                             material, medium or texture)"
                        ),
                    ));
                }
                self.gs
                    .defaults
                    .entry(target)
                    .or_default()
                    .extend(params.iter().cloned());
            }
            D::WorldBegin => {
                self.require_options("WorldBegin", &loc)?;
                if let Some((b, _, open)) = self.stack.last() {
                    return Err(SceneError::at(
                        loc,
                        format!("WorldBegin inside the {} at line {}", b.names().0, open.line),
                    ));
                }
                self.in_world = true;
                self.gs.ctm = Transform::IDENTITY;
                self.named_coords
                    .insert("world".to_string(), Transform::IDENTITY);
            }
            D::WorldEnd => {}
            D::Option(params) => {
                if params.has("seed") {
                    self.option_seed = Some(params.int("seed", 0)? as u32 as u64);
                }
                self.unused(&params, "Option".to_string());
            }
            D::ColorSpace(name) => {
                if name != "srgb" {
                    self.warn(
                        &loc,
                        format!("colour space \"{name}\" is not supported yet; lancer uses srgb"),
                    );
                }
            }
            D::Camera(ty, params) => {
                self.require_options("Camera", &loc)?;
                self.camera(&ty, &params, &loc)?;
                self.unused(&params, format!("Camera \"{ty}\""));
            }
            D::Film(ty, params) => {
                self.require_options("Film", &loc)?;
                self.film(&ty, &params, &loc)?;
                self.unused(&params, format!("Film \"{ty}\""));
            }
            D::Sampler(ty, params) => {
                self.require_options("Sampler", &loc)?;
                let (kind, spp) = self.accept(self.reader(&params, &dir).sampler(&ty)?, &loc).expect("samplers always fall back");
                self.desc.sampler.kind = kind;
                self.desc.sampler.spp = spp;
                if params.has("seed") {
                    self.sampler_seed = Some(params.int("seed", 0)? as u32 as u64);
                }
                self.unused(&params, format!("Sampler \"{ty}\""));
            }
            D::PixelFilter(ty, params) => {
                self.require_options("PixelFilter", &loc)?;
                self.desc.filter = self.accept(self.reader(&params, &dir).filter(&ty)?, &loc).expect("filters always fall back");
                self.unused(&params, format!("PixelFilter \"{ty}\""));
            }
            D::Integrator(ty, params) => {
                self.require_options("Integrator", &loc)?;
                self.desc.integrator = self.accept(self.reader(&params, &dir).integrator(&ty)?, &loc).expect("integrators always fall back");
                self.unused(&params, format!("Integrator \"{ty}\""));
            }
            D::Accelerator(..) => {
                // A tuning hint for pbrt's own structures: lancer always builds its BVH.
            }
            D::MakeNamedMedium(..) | D::MediumInterface(..) => self.warn_once(
                "media",
                &loc,
                "participating media are not supported yet; media are ignored",
            ),
            D::Material(ty, params) => {
                self.require_world("Material", &loc)?;
                let params = self.defaults("material", params);
                let index = self.material(&ty, &params, &dir, &loc)?;
                self.gs.material = MaterialRef::Index(index);
                self.unused(&params, format!("Material \"{ty}\""));
            }
            D::MakeNamedMaterial(name, params) => {
                self.require_world("MakeNamedMaterial", &loc)?;
                let params = self.defaults("material", params);
                let Some(ty) = params.string("type")? else {
                    return Err(SceneError::at(
                        loc,
                        format!("MakeNamedMaterial \"{name}\" needs a \"string type\""),
                    ));
                };
                let index = self.material(&ty, &params, &dir, &loc)?;
                if self.named_materials.insert(name.clone(), index).is_some() {
                    self.warn(&loc, format!("named material \"{name}\" redefined"));
                }
                self.unused(&params, format!("MakeNamedMaterial \"{name}\""));
            }
            D::NamedMaterial(name) => {
                self.require_world("NamedMaterial", &loc)?;
                self.gs.material = MaterialRef::Named(name, loc);
            }
            D::Texture(name, ty, class, params) => {
                let what = format!("Texture \"{class}\"");
                self.world_directive("Texture", "texture", params, &loc, what, |b, p| {
                    b.texture(name, &ty, &class, p, &dir, &loc)
                })?;
            }
            D::LightSource(ty, params) => {
                let what = format!("LightSource \"{ty}\"");
                self.world_directive("LightSource", "light", params, &loc, what, |b, p| {
                    b.light(&ty, p, &dir, &loc)
                })?;
            }
            D::AreaLightSource(ty, params) => {
                let what = format!("AreaLightSource \"{ty}\"");
                self.world_directive("AreaLightSource", "light", params, &loc, what, |b, p| {
                    b.area_light(&ty, p, &dir, &loc)
                })?;
            }
            D::Shape(ty, params) => {
                let what = format!("Shape \"{ty}\"");
                self.world_directive("Shape", "shape", params, &loc, what, |b, p| {
                    b.shape(&ty, p, &dir, &loc)
                })?;
            }
            D::ObjectBegin(name) => {
                self.require_world("ObjectBegin", &loc)?;
                if let Some(open) = self.current_object {
                    let open = &self.desc.objects[open as usize].name;
                    return Err(SceneError::at(
                        loc,
                        format!("ObjectBegin \"{name}\" inside the definition of \"{open}\""),
                    ));
                }
                // pbrt-v4's ObjectBegin also begins an attribute block.
                self.stack.push((Block::Object, self.gs.clone(), loc.clone()));
                let index = self.desc.objects.len() as u32;
                self.desc.objects.push(ObjectDesc {
                    name: name.clone(),
                    shapes: Vec::new(),
                });
                if self.object_names.insert(name.clone(), index).is_some() {
                    self.warn(&loc, format!("object \"{name}\" redefined"));
                }
                self.current_object = Some(index);
            }
            D::ObjectEnd => {
                self.end_block(Block::Object, &loc)?;
                self.current_object = None;
            }
            D::ObjectInstance(name) => {
                self.require_world("ObjectInstance", &loc)?;
                if self.current_object.is_some() {
                    return Err(SceneError::at(
                        loc,
                        "ObjectInstance inside an object definition",
                    ));
                }
                self.pending_instances.push((name, self.gs.ctm, loc));
            }
        }
        Ok(())
    }

    /// Saves the graphics state at the opening of a block, refusing nesting deeper than
    /// [`MAX_NESTING`] (each level holds a copy of the state).
    fn begin_block(&mut self, block: Block, loc: Location) -> Result<(), SceneError> {
        if self.stack.len() >= MAX_NESTING {
            let (open, _) = block.names();
            return Err(SceneError::at(
                loc,
                format!("{open} nested more than {MAX_NESTING} blocks deep"),
            ));
        }
        self.stack.push((block, self.gs.clone(), loc));
        Ok(())
    }

    fn end_block(&mut self, block: Block, loc: &Location) -> Result<(), SceneError> {
        let (begin, end) = block.names();
        match self.stack.pop() {
            None => Err(SceneError::at(
                loc.clone(),
                format!("{end} without a matching {begin}"),
            )),
            Some((b, _, open)) if b != block => Err(SceneError::at(
                loc.clone(),
                format!("{end} closes the {} at line {}", b.names().0, open.line),
            )),
            Some((_, saved_gs, _)) => {
                if block == Block::Transform {
                    self.gs.ctm = saved_gs.ctm;
                } else {
                    self.gs = saved_gs;
                }
                Ok(())
            }
        }
    }

    fn camera(&mut self, ty: &str, params: &ParamList, loc: &Location) -> Result<(), SceneError> {
        let projection = match ty {
            "perspective" => Projection::Perspective {
                fov: params.float_checked("fov", 90.0, "in (0, 180)", |v| v > 0.0 && v < 180.0)?,
            },
            "orthographic" => Projection::Orthographic,
            _ => {
                self.warn(
                    loc,
                    format!(
                        "camera \"{ty}\" is not supported yet; lancer uses a perspective camera \
                         with fov 90"
                    ),
                );
                Projection::Perspective { fov: 90.0 }
            }
        };
        let screen_window = match params.floats("screenwindow")? {
            None => None,
            Some(w) if w.len() == 4 && w[0] < w[1] && w[2] < w[3] => Some([w[0], w[1], w[2], w[3]]),
            Some(_) => {
                return Err(SceneError::at(
                    params.location("screenwindow").cloned().expect("given"),
                    "\"float screenwindow\" needs 4 numbers: xmin xmax ymin ymax, with min < max",
                ));
            }
        };
        self.frame_aspect = if params.has("frameaspectratio") {
            Some(params.float_checked("frameaspectratio", 1.0, "positive", |v| v > 0.0)?)
        } else {
            None
        };
        let shutter_open = params.float("shutteropen", 0.0)?;
        let shutter_close = params.float("shutterclose", 1.0)?;
        if shutter_close < shutter_open {
            return Err(SceneError::at(
                params
                    .location("shutterclose")
                    .cloned()
                    .unwrap_or(loc.clone()),
                "the shutter closes before it opens",
            ));
        }
        self.desc.camera = CameraDesc {
            projection,
            camera_from_world: self.gs.ctm,
            screen_window,
            lens_radius: params.float_checked("lensradius", 0.0, "at least 0", |v| v >= 0.0)?,
            focal_distance: params.float_checked("focaldistance", 1e6, "positive", |v| v > 0.0)?,
            shutter: [shutter_open, shutter_close],
        };
        self.named_coords
            .insert("camera".to_string(), self.gs.ctm.inverse());
        Ok(())
    }

    fn film(&mut self, ty: &str, params: &ParamList, loc: &Location) -> Result<(), SceneError> {
        if ty != "rgb" {
            self.warn(
                loc,
                format!("film \"{ty}\" is not supported yet; lancer uses an \"rgb\" film"),
            );
        }
        let film = &mut self.desc.film;
        film.xresolution = params.int_in("xresolution", 1280, 1..=MAX_RESOLUTION)? as u32;
        film.yresolution = params.int_in("yresolution", 720, 1..=MAX_RESOLUTION)? as u32;
        film.filename = params.string("filename")?;
        if let Some(c) = params.floats("cropwindow")? {
            let ok = c.len() == 4
                && c.iter().all(|v| (0.0..=1.0).contains(v))
                && c[0] < c[1]
                && c[2] < c[3];
            if !ok {
                return Err(SceneError::at(
                    params.location("cropwindow").cloned().expect("given"),
                    "\"float cropwindow\" needs 4 numbers in [0, 1]: xmin xmax ymin ymax, with min < max",
                ));
            }
            film.crop_window = [c[0], c[1], c[2], c[3]];
        }
        if let Some((b, bloc)) = params.ints("pixelbounds")? {
            if b.len() != 4 || b[0] >= b[1] || b[2] >= b[3] {
                return Err(SceneError::at(
                    bloc,
                    "\"integer pixelbounds\" needs 4 numbers: x0 x1 y0 y1, with x0 < x1 and y0 < y1",
                ));
            }
            film.pixel_bounds = Some([b[0], b[1], b[2], b[3]]);
        }
        self.iso = params.float_checked("iso", 100.0, "positive", |v| v > 0.0)?;
        film.max_component_value =
            params.float_checked("maxcomponentvalue", f32::INFINITY, "positive", |v| v > 0.0)?;
        film.save_fp16 = params.bool("savefp16", false)?;
        // Only the realistic camera uses the sensor's diagonal.
        let _ = params.float("diagonal", 35.0)?;
        let sensor = params.string("sensor")?.unwrap_or_else(|| "cie1931".into());
        let white_balance = params.float("whitebalance", 0.0)?;
        if sensor != "cie1931" || white_balance != 0.0 {
            self.warn(
                loc,
                "camera sensors and white balance are not supported yet; lancer uses the CIE 1931 observer without white balance",
            );
        }
        Ok(())
    }

    /// Adds a material; a `mix` has its two names resolved at the end.
    fn material(
        &mut self,
        ty: &str,
        params: &ParamList,
        dir: &SearchPath,
        loc: &Location,
    ) -> Result<u32, SceneError> {
        let converted = self
            .reader(params, dir)
            .material(ty)
            .map_err(|e| locate(e, loc))?;
        let (m, mix) = self
            .accept(converted, loc)
            .expect("materials always fall back");
        let index = self.desc.materials.len() as u32;
        self.desc.materials.push(m);
        if let Some((names, nloc)) = mix {
            for (k, n) in names.into_iter().enumerate() {
                self.pending_materials
                    .push((Slot::Mix(index, k), n, nloc.clone()));
            }
        }
        Ok(index)
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
                let converted = self
                    .reader(params, dir)
                    .float_texture(class)
                    .map_err(|e| locate(e, loc))?;
                let t = self
                    .accept(converted, loc)
                    .expect("textures always fall back");
                let index = self.desc.float_textures.len() as u32;
                self.desc.float_textures.push(t);
                self.textures.floats.insert(name, index);
            }
            "spectrum" | "color" | "rgb" => {
                let converted = self
                    .reader(params, dir)
                    .spectrum_texture(class)
                    .map_err(|e| locate(e, loc))?;
                let t = self
                    .accept(converted, loc)
                    .expect("textures always fall back");
                let index = self.desc.spectrum_textures.len() as u32;
                self.desc.spectrum_textures.push(t);
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

    /// A light's emission: its colour (RGB passes through; spectra are normalised to luminance
    /// 1, as pbrt-v4 divides `scale` by the spectrum's photometric value) times `scale`.
    fn emission(params: &ParamList, name: &str, dir: &SearchPath) -> Result<Rgb, SceneError> {
        let c = params
            .color(name, SpectrumKind::Illuminant, dir)?
            .unwrap_or(Rgb::ONE);
        Ok(c * params.float("scale", 1.0)?)
    }

    fn light(
        &mut self,
        ty: &str,
        params: &ParamList,
        dir: &SearchPath,
        loc: &Location,
    ) -> Result<(), SceneError> {
        let ctm = self.gs.ctm;
        let power = params.float("power", -1.0)?;
        let light = match ty {
            "point" => {
                let mut i = Self::emission(params, "I", dir)?;
                if power > 0.0 {
                    // Φ = 4π·I for an isotropic point light.
                    i *= power / (4.0 * std::f32::consts::PI);
                }
                LightDesc::Point {
                    from: ctm.point(params.point3("from", Vec3::ZERO)?),
                    intensity: i,
                }
            }
            "spot" => {
                let mut i = Self::emission(params, "I", dir)?;
                let cone_angle = params
                    .float_checked("coneangle", 30.0, "in (0, 180]", |v| v > 0.0 && v <= 180.0)?;
                let cone_delta_angle = params.float_checked(
                    "conedeltaangle",
                    5.0,
                    "between 0 and the cone angle",
                    |v| (0.0..=cone_angle).contains(&v),
                )?;
                if power > 0.0 {
                    // Φ = 2π·I·((1 − cos θ_start) + (cos θ_start − cos θ_end)/2): the
                    // smoothstep falloff integrates to half its width.
                    let c_end = cone_angle.to_radians().cos();
                    let c_start = (cone_angle - cone_delta_angle).to_radians().cos();
                    let k =
                        2.0 * std::f32::consts::PI * ((1.0 - c_start) + (c_start - c_end) / 2.0);
                    i *= power / k;
                }
                let from = ctm.point(params.point3("from", Vec3::ZERO)?);
                let to = ctm.point(params.point3("to", Vec3::Z)?);
                if from == to {
                    return Err(SceneError::at(
                        loc.clone(),
                        "spot light with \"from\" equal to \"to\"",
                    ));
                }
                LightDesc::Spot {
                    from,
                    to,
                    intensity: i,
                    cone_angle,
                    cone_delta_angle,
                }
            }
            "distant" => {
                let mut l = Self::emission(params, "L", dir)?;
                let w = params.point3("from", Vec3::ZERO)? - params.point3("to", Vec3::Z)?;
                let illuminance = params.float("illuminance", -1.0)?;
                if illuminance > 0.0 {
                    // pbrt-v4 measures illuminance on an upward-facing patch.
                    let k = w.normalize_or_zero().y;
                    if k > 0.0 {
                        l *= illuminance / k;
                    }
                }
                let direction = ctm.vector(w);
                if direction == Vec3::ZERO {
                    return Err(SceneError::at(
                        loc.clone(),
                        "distant light with \"from\" equal to \"to\"",
                    ));
                }
                LightDesc::Distant { direction, l }
            }
            "infinite" => self.infinite_light(ctm, params, dir, loc)?,
            "goniometric" | "projection" => {
                self.warn(loc, format!("light \"{ty}\" is not supported yet; skipped"));
                return Ok(());
            }
            _ => {
                return Err(SceneError::at(
                    loc.clone(),
                    format!(
                        "unknown light \"{ty}\" (expected point, spot, distant, infinite, goniometric or projection)"
                    ),
                ));
            }
        };
        self.desc.lights.push(light);
        Ok(())
    }

    /// pbrt-v4's `infinite` light: a uniform sky of radiance `L`, or the image `filename`
    /// (equal-area octahedral, or, as a lancer extension, 2:1 latitude-longitude) times
    /// `scale`. With `illuminance` E, a sky is scaled so that an upward patch receives E
    /// (L·π = E); an image is scaled by E over the illuminance pbrt-v4 computes for it, which
    /// is half the physical one (see `EnvMapping::pbrt_illuminance`), so that lancer matches
    /// pbrt-v4's images.
    fn infinite_light(
        &mut self,
        ctm: Transform,
        params: &ParamList,
        dir: &SearchPath,
        loc: &Location,
    ) -> Result<LightDesc, SceneError> {
        let illuminance = params.float("illuminance", -1.0)?;
        if !params.has("filename") {
            let mut l = Self::emission(params, "L", dir)?;
            if illuminance > 0.0 {
                // A uniform sky of radiance L gives an illuminance of π·L.
                l *= illuminance / std::f32::consts::PI;
            }
            return Ok(LightDesc::Infinite {
                light_to_world: ctm,
                l,
                image: None,
            });
        }
        if params.has("L") {
            return Err(SceneError::at(
                loc.clone(),
                "an \"infinite\" light takes either \"L\" or \"filename\", not both",
            ));
        }
        let mut scale = params.float("scale", 1.0)?;
        // pbrt-v4 reads environment images with their default encoding (sRGB for PNG).
        let (path, _) = self
            .reader(params, dir)
            .image_file("an \"infinite\" light with an image")
            .map_err(|e| locate(e, loc))?;
        let image = self
            .images
            .rgb(&path, Encoding::Srgb)
            .map_err(|e| SceneError::at(loc.clone(), e.to_string()))?;
        let mapping = EnvMapping::of_size(image.width, image.height).ok_or_else(|| {
            SceneError::at(
                loc.clone(),
                format!(
                    "{}: an environment image must be square (pbrt-v4's equal-area octahedral layout) or twice as wide as high (latitude-longitude), not {}×{}",
                    path.display(),
                    image.width,
                    image.height
                ),
            )
        })?;
        if image.texels.iter().any(|c| !c.is_finite()) {
            return Err(SceneError::at(
                loc.clone(),
                format!(
                    "{}: the image has infinite or NaN values and cannot be a light",
                    path.display()
                ),
            ));
        }
        if illuminance > 0.0 {
            let e = mapping.pbrt_illuminance(&image);
            if e > 0.0 {
                scale *= illuminance / e;
            } else {
                self.warn(
                    loc,
                    format!(
                        "{} is black above the horizon, so \"illuminance\" cannot scale it; ignored",
                        path.display()
                    ),
                );
            }
        }
        if params.point3s("portal")?.is_some() {
            self.warn(
                loc,
                "infinite light portals are not supported yet; lancer samples the whole image",
            );
        }
        Ok(LightDesc::Infinite {
            light_to_world: ctm,
            l: Rgb::splat(scale),
            image: Some(image),
        })
    }

    fn area_light(
        &mut self,
        ty: &str,
        params: &ParamList,
        dir: &SearchPath,
        loc: &Location,
    ) -> Result<(), SceneError> {
        if ty != "diffuse" {
            return Err(SceneError::at(
                loc.clone(),
                format!("unknown area light \"{ty}\" (expected \"diffuse\")"),
            ));
        }
        let l = Self::emission(params, "L", dir)?;
        let two_sided = params.bool("twosided", false)?;
        self.gs.area_light = Some(AreaLightDesc { l, two_sided });
        Ok(())
    }

    fn shape(
        &mut self,
        ty: &str,
        params: &ParamList,
        dir: &SearchPath,
        loc: &Location,
    ) -> Result<(), SceneError> {
        let converted = self
            .reader(params, dir)
            .shape(ty)
            .map_err(|e| locate(e, loc))?;
        let Some((geometry, alpha)) = self.accept(converted, loc) else {
            // Skipped whole: its warning says so; its parameters need no warnings of their own.
            params.mark_all_used();
            return Ok(());
        };
        let (material, pending) = match &self.gs.material {
            MaterialRef::Index(i) => (*i, None),
            MaterialRef::Named(name, nloc) => match self.named_materials.get(name) {
                Some(&i) => (i, None),
                None => (0, Some((name.clone(), nloc.clone()))),
            },
        };
        if self.gs.area_light.is_some()
            && matches!(geometry, lancer::scene::desc::Geometry::Curve(_))
        {
            return Err(SceneError::at(
                loc.clone(),
                "a curve cannot be an area light (pbrt-v4 cannot sample curves either)",
            ));
        }
        let mut area_light = self.gs.area_light;
        if area_light.is_some() && matches!(geometry, lancer::scene::desc::Geometry::Voxels(_)) {
            return Err(SceneError::at(
                loc.clone(),
                "a \"voxels\" shape cannot be an area light (AttributeBegin/AttributeEnd around the AreaLightSource keeps it from the voxels)",
            ));
        }
        if area_light.is_some() && self.current_object.is_some() {
            self.warn_once(
                "instanced-area-light",
                loc,
                "area lights inside object definitions are not supported; those shapes do not emit",
            );
            area_light = None;
        }
        let sd = ShapeDesc {
            geometry,
            object_to_world: self.gs.ctm,
            reverse_orientation: self.gs.reverse_orientation,
            material,
            area_light,
            alpha,
        };
        let slot = match self.current_object {
            Some(o) => {
                let shapes = &mut self.desc.objects[o as usize].shapes;
                shapes.push(sd);
                Slot::ObjectShape(o, shapes.len() - 1)
            }
            None => {
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
    fn finish(mut self, end: Location) -> Result<(SceneDesc, Vec<Warning>), SceneError> {
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
                Slot::ObjectShape(o, i) => self.desc.objects[o as usize].shapes[i].material = index,
                Slot::Mix(m, k) => {
                    if let Material::Mix { materials, .. } = &mut self.desc.materials[m as usize] {
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
            self.desc.instances.push(InstanceDesc {
                object,
                object_to_world: ctm,
            });
        }
        if self.desc.camera.screen_window.is_none()
            && let Some(frame) = self.frame_aspect
        {
            self.desc.camera.screen_window = Some(if frame > 1.0 {
                [-frame, frame, -1.0, 1.0]
            } else {
                [-1.0, 1.0, -1.0 / frame, 1.0 / frame]
            });
        }
        // pbrt-v4's imaging ratio: exposure time × ISO / 100.
        let [open, close] = self.desc.camera.shutter;
        self.desc.film.scale = (close - open) * self.iso / 100.0;
        self.desc.sampler.seed = self.sampler_seed.or(self.option_seed).unwrap_or(0);
        Ok((self.desc, self.warnings))
    }
}

/// Reads every directive of `parser` into a scene description and its warnings.
pub fn build(parser: &mut Parser) -> Result<(SceneDesc, Vec<Warning>), SceneError> {
    let mut b = Builder::new();
    let mut last = None;
    while let Some(d) = parser.next_directive()? {
        last = Some(d.loc.clone());
        b.directive(d)?;
    }
    let end = last.unwrap_or_else(|| parser.start_location());
    b.finish(end)
}

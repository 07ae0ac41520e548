//! The built scene: immutable, shared by all render threads.

pub mod desc;
pub mod instance;

use crate::accel::{Bvh, Tri4};
use crate::camera::Camera;
use crate::light::{Light, LightDistribution};
use crate::material::Material;
use crate::math::{Bounds3, PackedRgb, PackedVec3, Rgb, Vec3};
use crate::ray::Ray;
use crate::shape::{
    Cone, Cuboid, Cylinder, Disk, Hyperboloid, Paraboloid, Placement, Plane, Sdf, Shape, Sphere,
    SurfaceInteraction, Triangle, TriangleMesh, TriangleRay, is_degenerate,
};
use crate::texture::{FloatTex, FloatTexture, SpectrumTexture, TexCoord, TextureEval};
use desc::{Geometry, LightDesc, SceneDesc, ShapeDesc};

/// What a primitive is made of, beside its shape.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PrimInfo {
    /// Index into [`Scene::materials`].
    pub material: u32,
    /// Emitted radiance when the primitive is an area light.
    pub emission: Option<AreaEmission>,
    /// Alpha cut-out: where it is below 1 the surface is (partly) absent.
    pub alpha: Option<FloatTex>,
}

/// A primitive's emission.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AreaEmission {
    /// Radiance (packed, so that [`PrimInfo`], one per primitive, stays 32 bytes).
    pub l: PackedRgb,
    /// Emits from both sides.
    pub two_sided: bool,
    /// Index of the light in [`Scene::lights`].
    pub light: u32,
}

/// A ray's nearest hit in the scene.
#[derive(Clone, Copy, Debug)]
pub struct SceneHit {
    /// The surface.
    pub si: SurfaceInteraction,
    /// Index of the primitive hit.
    pub prim: u32,
    /// Reflectance given by the shape itself (a voxel's palette colour), which a `diffuse`
    /// material uses instead of its own.
    pub albedo: Option<Rgb>,
}

/// Why a scene description could not be built.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum BuildError {
    /// A mesh with bad indices or mismatched arrays.
    #[error("shape {shape}: {message}")]
    BadMesh {
        /// Index of the shape in the description.
        shape: usize,
        /// What is wrong.
        message: String,
    },
    /// A material index out of range.
    #[error("shape {shape}: material {material} does not exist")]
    BadMaterial {
        /// Index of the shape.
        shape: usize,
        /// The index given.
        material: u32,
    },
    /// The camera's parameters give no valid projection.
    #[error("the camera's parameters give no valid projection")]
    BadCamera,
    /// A zero or non-finite parameter that makes a shape or light meaningless.
    #[error("{0}")]
    Invalid(String),
}

/// A scene ready to render: primitives in a BVH, lights, materials, textures, camera.
#[derive(Debug)]
pub struct Scene {
    /// Every primitive's shape.
    pub shapes: Vec<Shape>,
    /// Every primitive's material and emission, same indices as `shapes`.
    pub prims: Vec<PrimInfo>,
    /// Triangle meshes, world space.
    pub meshes: Vec<TriangleMesh>,
    /// Lights, area lights included.
    pub lights: Vec<Light>,
    /// How next-event estimation picks a light: in proportion to power.
    pub light_distribution: LightDistribution,
    /// Indices of the lights that rays escaping the scene see (environment lights).
    pub infinite_lights: Vec<u32>,
    /// Materials.
    pub materials: Vec<Material>,
    /// Float textures.
    pub float_textures: Vec<FloatTexture>,
    /// Colour textures.
    pub spectrum_textures: Vec<SpectrumTexture>,
    /// The camera.
    pub camera: Camera,
    bvh: Bvh,
    /// Per leaf of `bvh`: its triangles as a packet, or an empty packet when the leaf holds
    /// other shapes or alpha-tested triangles (those go through [`Shape::intersect_with`]).
    packets: Vec<Tri4>,
    /// Instanced objects and their placements (the two-level part of the scene).
    pub instances: instance::Instances,
    /// Primitives without finite bounds (infinite planes), tested on every ray.
    unbounded: Vec<u32>,
    bounds: Bounds3,
}

fn shapes_of(
    sd: &ShapeDesc,
    index: usize,
    meshes: &mut Vec<TriangleMesh>,
    out: &mut Vec<Shape>,
) -> Result<(), BuildError> {
    let placement = Placement::new(sd.object_to_world, sd.reverse_orientation);
    let positive = |v: f32, what: &str| {
        if v.is_finite() && v > 0.0 {
            Ok(v)
        } else {
            Err(BuildError::Invalid(format!(
                "shape {index}: {what} must be positive, got {v}"
            )))
        }
    };
    match &sd.geometry {
        Geometry::Sphere {
            radius,
            z_min,
            z_max,
            phi_max,
        } => out.push(Shape::Sphere(Box::new(Sphere::new(
            placement,
            positive(*radius, "radius")?,
            *z_min,
            *z_max,
            *phi_max,
        )))),
        Geometry::Disk {
            height,
            radius,
            inner_radius,
            phi_max,
        } => out.push(Shape::Disk(Box::new(Disk::new(
            placement,
            *height,
            positive(*radius, "radius")?,
            *inner_radius,
            *phi_max,
        )))),
        Geometry::Cylinder {
            radius,
            z_min,
            z_max,
            phi_max,
        } => out.push(Shape::Cylinder(Box::new(Cylinder::new(
            placement,
            positive(*radius, "radius")?,
            *z_min,
            *z_max,
            *phi_max,
        )))),
        Geometry::Cone {
            radius,
            height,
            phi_max,
        } => out.push(Shape::Cone(Box::new(Cone::new(
            placement,
            positive(*radius, "radius")?,
            positive(*height, "height")?,
            *phi_max,
        )))),
        Geometry::Paraboloid {
            radius,
            z_min,
            z_max,
            phi_max,
        } => out.push(Shape::Paraboloid(Box::new(Paraboloid::new(
            placement,
            positive(*radius, "radius")?,
            *z_min,
            positive(z_min.max(*z_max), "zmax")?,
            *phi_max,
        )))),
        Geometry::Hyperboloid { p1, p2, phi_max } => {
            let h = Hyperboloid::new(placement, *p1, *p2, *phi_max).ok_or_else(|| {
                BuildError::Invalid(format!(
                    "shape {index}: hyperboloid p1 {p1} and p2 {p2} must be finite and at different heights"
                ))
            })?;
            out.push(Shape::Hyperboloid(Box::new(h)));
        }
        Geometry::Box { min, max } => {
            if !(min.cmplt(*max).all() && min.is_finite() && max.is_finite()) {
                return Err(BuildError::Invalid(format!(
                    "shape {index}: box min {min} must be below max {max} on every axis"
                )));
            }
            out.push(Shape::Box(Box::new(Cuboid::new(placement, *min, *max))));
        }
        Geometry::Plane { p, n } => {
            let t = &sd.object_to_world;
            let mut n = t.normal(*n);
            if sd.reverse_orientation {
                n = -n;
            }
            let plane = Plane::new(t.point(*p), n).ok_or_else(|| {
                BuildError::Invalid(format!("shape {index}: plane normal is zero"))
            })?;
            out.push(Shape::Plane(Box::new(plane)));
        }
        Geometry::Sdf { function, bounds } => {
            if sd.area_light.is_some() {
                return Err(BuildError::Invalid(format!(
                    "shape {index}: an sdf shape cannot be an area light (its area has no closed form)"
                )));
            }
            let sdf = Sdf::new(placement, function.clone(), *bounds)
                .map_err(|e| BuildError::Invalid(format!("shape {index}: {e}")))?;
            out.push(Shape::Sdf(Box::new(sdf)));
        }
        Geometry::Curve(c) => {
            if sd.area_light.is_some() {
                return Err(BuildError::Invalid(format!(
                    "shape {index}: a curve cannot be an area light (pbrt-v4 cannot sample curves either)"
                )));
            }
            let curves = c
                .curves(&sd.object_to_world, sd.reverse_orientation)
                .map_err(|e| BuildError::Invalid(format!("shape {index}: {e}")))?;
            out.extend(curves.into_iter().map(Shape::Curve));
        }
        Geometry::BilinearMesh(m) => {
            m.validate().map_err(|message| BuildError::BadMesh {
                shape: index,
                message,
            })?;
            let world =
                std::sync::Arc::new(m.transformed(&sd.object_to_world, sd.reverse_orientation));
            out.extend(
                crate::shape::BilinearMesh::patches(&world)
                    .into_iter()
                    .map(|p| Shape::Bilinear(Box::new(p))),
            );
        }
        Geometry::TriangleMesh(m) => {
            m.validate().map_err(|message| BuildError::BadMesh {
                shape: index,
                message,
            })?;
            let world = m.transformed(&sd.object_to_world, sd.reverse_orientation);
            let mesh_index = meshes.len() as u32;
            for i in 0..world.triangle_count() as u32 {
                let v = world.vertices(i);
                let p = [
                    world.positions[v[0]],
                    world.positions[v[1]],
                    world.positions[v[2]],
                ];
                // A triangle of zero area can never be hit: leave it out.
                let [a, b, c] = p.map(Vec3::from);
                if !is_degenerate(a, b, c) {
                    out.push(Shape::Triangle(Triangle {
                        p,
                        mesh: mesh_index,
                        index: i,
                    }));
                }
            }
            meshes.push(world);
        }
        Geometry::Voxels(grid) => {
            if sd.area_light.is_some() {
                return Err(BuildError::Invalid(format!(
                    "shape {index}: a voxel grid cannot be an area light"
                )));
            }
            // An empty grid has nothing to hit: no primitive.
            if let Some(v) = crate::shape::Voxels::new(placement, grid.clone()) {
                out.push(Shape::Voxels(Box::new(v)));
            }
        }
    }
    Ok(())
}

/// The world centre and radius of a shape that is a whole sphere (no cut, full sweep).
fn whole_sphere(shape: &Shape) -> Option<(PackedVec3, f32)> {
    let Shape::Sphere(s) = shape else { return None };
    let whole =
        s.z_min <= -s.radius && s.z_max >= s.radius && s.phi_max >= 2.0 * std::f32::consts::PI;
    let t = &s.placement.to_world;
    let scale = glam::Mat3::from_mat4(t.m).determinant().abs().cbrt();
    whole.then(|| (t.point(Vec3::ZERO).into(), s.radius * scale))
}

impl Scene {
    /// Builds a scene: shapes moved to world space and put in a BVH, lights gathered, the
    /// camera set up for an `xres × yres` image.
    pub fn build(desc: &SceneDesc) -> Result<Scene, BuildError> {
        let mut shapes = Vec::new();
        let mut prims = Vec::new();
        let mut meshes = Vec::new();
        let mut all: Vec<(usize, &ShapeDesc, crate::math::Transform)> = desc
            .shapes
            .iter()
            .enumerate()
            .map(|(i, s)| (i, s, crate::math::Transform::IDENTITY))
            .collect();
        let mut materials = desc.materials.clone();
        if materials.is_empty() {
            materials.push(Material::default());
        }
        // Objects of plain triangle meshes get a BVH of their own, shared by their instances;
        // the others (emitting, alpha-tested or non-mesh shapes) are flattened: each copy
        // becomes shapes of its own. Their PrimInfo entries come after the shapes' ones.
        let mut object_slot: Vec<Option<u32>> = vec![None; desc.objects.len()];
        let mut objects = Vec::new();
        let mut placements = Vec::new();
        let mut object_prims = Vec::new();
        for inst in &desc.instances {
            let obj = desc.objects.get(inst.object as usize).ok_or_else(|| {
                BuildError::Invalid(format!("instance of unknown object {}", inst.object))
            })?;
            let slot = &mut object_slot[inst.object as usize];
            if slot.is_none()
                && let Some(acc) =
                    instance::ObjectAccel::build(obj, &mut object_prims, materials.len())?
            {
                *slot = Some(objects.len() as u32);
                objects.push(acc);
            }
            if let Some(object) = *slot {
                placements.push(instance::Instance {
                    object,
                    to_world: inst.object_to_world,
                });
                continue;
            }
            for s in &obj.shapes {
                all.push((desc.shapes.len(), s, inst.object_to_world));
            }
        }
        let instances = instance::Instances::new(objects, placements);
        for (index, sd, instance_xf) in all {
            if sd.material as usize >= materials.len() {
                return Err(BuildError::BadMaterial {
                    shape: index,
                    material: sd.material,
                });
            }
            let placed;
            let sd = if instance_xf.is_identity() {
                sd
            } else {
                placed = ShapeDesc {
                    object_to_world: instance_xf * sd.object_to_world,
                    ..sd.clone()
                };
                &placed
            };
            let first = shapes.len();
            shapes_of(sd, index, &mut meshes, &mut shapes)?;
            let info = PrimInfo {
                material: sd.material,
                emission: sd.area_light.map(|a| AreaEmission {
                    l: a.l.into(),
                    two_sided: a.two_sided,
                    light: 0,
                }),
                // A constant alpha of 1 (pbrt's default) cuts nothing: no test needed.
                alpha: sd.alpha.filter(|a| *a != FloatTex::Const(1.0)),
            };
            prims.extend(std::iter::repeat_n(info, shapes.len() - first));
        }
        let (mut bounded, mut unbounded) = (Vec::new(), Vec::new());
        for (i, s) in shapes.iter().enumerate() {
            if s.is_unbounded() {
                unbounded.push(i as u32);
            } else {
                bounded.push(i as u32);
            }
        }
        let bounds_list: Vec<Bounds3> = bounded
            .iter()
            .map(|&i| shapes[i as usize].bounds())
            .collect();
        let mut bvh = Bvh::build(&bounds_list);
        // Lay the primitives out in the tree's leaf order (unbounded ones last), so that the
        // primitives of a leaf are neighbours in memory and the leaf's indices are its slots.
        let order: Vec<u32> = bvh
            .indices
            .iter()
            .map(|&k| bounded[k as usize])
            .chain(unbounded.iter().copied())
            .collect();
        let mut slots: Vec<Option<Shape>> = shapes.into_iter().map(Some).collect();
        let shapes: Vec<Shape> = order
            .iter()
            .map(|&i| slots[i as usize].take().expect("each primitive once"))
            .collect();
        let mut prims: Vec<PrimInfo> = order.iter().map(|&i| prims[i as usize]).collect();
        let n_bounded = bvh.indices.len() as u32;
        for (k, idx) in bvh.indices.iter_mut().enumerate() {
            *idx = k as u32;
        }
        let unbounded: Vec<u32> = (n_bounded..shapes.len() as u32).collect();
        let packets = (0..bvh.leaf_count() as u32)
            .map(|leaf| {
                let mut lanes = Vec::with_capacity(4);
                for k in bvh.leaf_range(leaf) {
                    let i = bvh.indices[k];
                    match &shapes[i as usize] {
                        Shape::Triangle(t) if prims[i as usize].alpha.is_none() => {
                            lanes.push((t.p, i))
                        }
                        _ => return Tri4::EMPTY,
                    }
                }
                Tri4::new(&lanes)
            })
            .collect();
        let mut bounds = bvh.bounds().union(&instances.bounds());
        if bounds.is_empty() {
            bounds = Bounds3::from_point(Vec3::ZERO);
        }
        let (_, scene_radius) = bounds.bounding_sphere();

        let mut lights = Vec::new();
        for l in &desc.lights {
            lights.push(match l {
                LightDesc::Point { from, intensity } => Light::Point {
                    p: *from,
                    intensity: *intensity,
                },
                LightDesc::Spot {
                    from,
                    to,
                    intensity,
                    cone_angle,
                    cone_delta_angle,
                } => {
                    let axis = (*to - *from).try_normalize().ok_or_else(|| {
                        BuildError::Invalid("spot light with from == to".to_string())
                    })?;
                    Light::Spot {
                        p: *from,
                        axis,
                        intensity: *intensity,
                        cos_falloff_end: cone_angle.to_radians().cos(),
                        cos_falloff_start: (cone_angle - cone_delta_angle).to_radians().cos(),
                    }
                }
                LightDesc::Distant { direction, l } => Light::Distant {
                    w: direction.try_normalize().ok_or_else(|| {
                        BuildError::Invalid("distant light with from == to".to_string())
                    })?,
                    l: *l,
                    scene_radius,
                },
                LightDesc::Infinite { l, image: None, .. } => Light::UniformInfinite {
                    l: *l,
                    scene_radius,
                },
                LightDesc::Infinite {
                    light_to_world,
                    l,
                    image: Some(image),
                } => Light::ImageInfinite(Box::new(
                    crate::light::ImageInfiniteLight::new(
                        *light_to_world,
                        image.clone(),
                        *l,
                        scene_radius,
                    )
                    .map_err(BuildError::Invalid)?,
                )),
            });
        }

        // Every emitting primitive is a light of its own (a mesh light: one per triangle).
        for (i, (shape, info)) in shapes.iter().zip(prims.iter_mut()).enumerate() {
            let Some(e) = info.emission.as_mut() else {
                continue;
            };
            let area = shape.area();
            if !(area > 0.0 && area.is_finite()) || e.l == PackedRgb::ZERO {
                continue;
            }
            e.light = lights.len() as u32;
            lights.push(Light::Area {
                prim: i as u32,
                l: e.l,
                two_sided: e.two_sided,
                area,
                sphere: whole_sphere(shape),
            });
        }
        let powers: Vec<f32> = lights.iter().map(Light::power).collect();
        let light_distribution = LightDistribution::new(&powers);
        // The instanced meshes' entries, renumbered to follow the shapes'.
        let base = prims.len() as u32;
        prims.extend(object_prims);
        let mut instances = instances;
        for o in &mut instances.objects {
            o.offset_prims(base);
        }
        let infinite_lights = (0..lights.len() as u32)
            .filter(|&i| lights[i as usize].is_infinite())
            .collect();

        let camera = Camera::from_desc(&desc.camera, desc.film.xresolution, desc.film.yresolution)
            .ok_or(BuildError::BadCamera)?;
        Ok(Scene {
            shapes,
            prims,
            meshes,
            lights,
            light_distribution,
            infinite_lights,
            materials,
            float_textures: desc.float_textures.clone(),
            spectrum_textures: desc.spectrum_textures.clone(),
            camera,
            bvh,
            packets,
            instances,
            unbounded,
            bounds,
        })
    }

    /// Bounds of the bounded geometry.
    pub fn bounds(&self) -> Bounds3 {
        self.bounds
    }

    /// The acceleration structure over the primitives (for statistics).
    pub fn bvh(&self) -> &Bvh {
        &self.bvh
    }

    /// The course's "keep the nearest valid hit": the smallest t with 0 < t < t_max over all
    /// primitives, found through the BVH.
    pub fn intersect(&self, ray: &Ray) -> Option<SceneHit> {
        crate::counters::count_ray();
        let mut best: Option<(crate::shape::ShapeHit, u32)> = None;
        let mut r = *ray;
        let pre = TriangleRay::new(ray);
        for &i in &self.unbounded {
            if let Some(h) = self.hit(i, &r, &pre) {
                r.t_max = h.t;
                best = Some((h, i));
            }
        }
        self.bvh.intersect_leaves(&r, |leaf, r| {
            let p = &self.packets[leaf as usize];
            if !p.is_empty() {
                let (lane, h) = p.intersect(r, &pre)?;
                best = Some((h, p.ids[lane]));
                return Some(h.t);
            }
            self.bvh.leaf_nearest(leaf, r, &mut |i, r| {
                let h = self.hit(i, r, &pre)?;
                best = Some((h, i));
                Some(h.t)
            })
        });
        if !self.instances.is_empty() {
            if let Some(b) = best {
                r.t_max = b.0.t;
            }
            if let Some(ih) = self.instances.intersect(&r) {
                let (si, prim) = self.instances.interaction(ray, &ih);
                // Instanced objects are triangle meshes, which carry no colour of their own.
                return Some(SceneHit {
                    si,
                    prim,
                    albedo: None,
                });
            }
        }
        let (h, prim) = best?;
        let shape = &self.shapes[prim as usize];
        let si = shape.interaction(ray, &h, &self.meshes);
        let albedo = shape.hit_albedo(&h);
        Some(SceneHit { si, prim, albedo })
    }

    /// Primitive `i`'s hit by `ray`, unless its alpha cuts the surface away there.
    #[inline(always)]
    fn hit(&self, i: u32, ray: &Ray, pre: &TriangleRay) -> Option<crate::shape::ShapeHit> {
        let h = self.shapes[i as usize].intersect_with(ray, pre)?;
        match self.prims[i as usize].alpha {
            None => Some(h),
            Some(alpha) => self.alpha_test(i, ray, h, alpha),
        }
    }

    /// The alpha test, out of the hot loop: alpha 0 is a hole, alpha 1 solid, and in between
    /// the surface is there for a fraction alpha of the rays, chosen by a hash of the ray
    /// (pbrt-v4's stochastic alpha).
    #[cold]
    #[inline(never)]
    fn alpha_test(
        &self,
        i: u32,
        ray: &Ray,
        h: crate::shape::ShapeHit,
        alpha: FloatTex,
    ) -> Option<crate::shape::ShapeHit> {
        let si = self.shapes[i as usize].interaction(ray, &h, &self.meshes);
        let a = self.textures().float(alpha, &Scene::tex_coord(&si));
        if a >= 1.0 {
            return Some(h);
        }
        if a <= 0.0 {
            return None;
        }
        let u = crate::sampling::u32_to_unit_f32(crate::sampling::hash_u64(&[
            ray.o.x.to_bits() as u64 | (ray.o.y.to_bits() as u64) << 32,
            ray.o.z.to_bits() as u64 | (ray.d.x.to_bits() as u64) << 32,
            ray.d.y.to_bits() as u64 | (ray.d.z.to_bits() as u64) << 32,
        ]) as u32);
        (u < a).then_some(h)
    }

    /// True if anything blocks the ray before `t_max` (shadow rays).
    pub fn intersect_p(&self, ray: &Ray) -> bool {
        crate::counters::count_ray();
        let pre = TriangleRay::new(ray);
        self.unbounded
            .iter()
            .any(|&i| self.hit(i, ray, &pre).is_some())
            || self.bvh.intersect_any_leaves(ray, |leaf, r| {
                let p = &self.packets[leaf as usize];
                if !p.is_empty() {
                    return p.intersect_any(r, &pre);
                }
                self.bvh
                    .leaf_any(leaf, r, &mut |i, r| self.hit(i, r, &pre).is_some())
            })
            || (!self.instances.is_empty() && self.instances.intersect_any(ray))
    }

    /// Texture evaluation against this scene's textures.
    pub fn textures(&self) -> TextureEval<'_> {
        TextureEval {
            floats: &self.float_textures,
            spectra: &self.spectrum_textures,
        }
    }

    /// Where textures are looked up for a hit.
    pub fn tex_coord(si: &SurfaceInteraction) -> TexCoord {
        TexCoord { uv: si.uv, p: si.p }
    }
}

//! [`Scene::build`], phase by phase: flatten the instances that cannot share a tree, make the
//! primitives (meshes become triangles), lay them out in BVH order, pack the leaves' triangles,
//! gather the lights, set up the camera. Each phase is a function of what the previous ones
//! made; the order of every list (and so every render) is the order these phases give.

use super::Scene;
use super::desc::{AreaLightDesc, Geometry, SceneDesc, ShapeDesc};
use super::instance::{Instance, Instances, ObjectAccel};
use super::power::power_radiance;
use super::prim::{
    AreaEmission, BuildError, IMAGE_EMISSION, NO_SPECTRUM, PrimInfo, check_media, check_shape,
    prim_media,
};
use super::tris::SceneTrisBuilder;
use crate::accel::{Bvh, Tri4};
use crate::camera::Camera;
use crate::camera::footprint::Footprints;
use crate::light::{AreaImage, AreaLight, Light, LightDistribution, LightSampler, SceneSphere};
use crate::material::{Material, MaterialDesc};
use crate::math::{Bounds3, Transform, Vec3};
use crate::shape::{Placing, Shape, TriangleMesh};
use crate::spectrum::dense::Measured;
use crate::texture::{
    FloatTex, FloatTexture, ImageTexture, Pyramids, SpectrumTex, SpectrumTexture,
};

impl Scene {
    /// Builds a scene: shapes moved to world space and put in a BVH, lights gathered, the
    /// camera set up for an `xres × yres` image. The phases, each a function of
    /// `scene/build.rs`: `flatten_instances`, `primitives` (meshes → triangles), `bvh_order`,
    /// `packets`, `lights`, then the camera.
    pub fn build(desc: &SceneDesc) -> Result<Scene, BuildError> {
        let materials = materials(desc);
        let textures = textures(desc);
        check_media(desc)?;
        let flat = flatten_instances(desc, materials.len())?;
        let made = primitives(&flat.shapes, materials.len())?;
        let meshes = made.meshes;
        let mut tris = made.tris.build();
        let (shapes, mut prims, bvh, unbounded) = bvh_order(made.shapes, made.prims);
        let packets = packets(&bvh, &shapes, &prims);
        let frames = super::triangle_frames(&shapes);
        let mut instances = flat.instances;
        let mut moving_prims = Vec::new();
        let mut motion =
            super::motion::Motion::build(desc, materials.len(), &mut moving_prims, shapes_of)?;
        let mut bounds = bvh
            .bounds()
            .union(&tris.bounds())
            .union(&instances.bounds());
        if let Some(m) = &motion {
            bounds = bounds.union(&m.bounds());
        }
        if bounds.is_empty() {
            bounds = Bounds3::from_point(Vec3::ZERO);
        }
        let (centre, radius) = bounds.bounding_sphere();
        let lights = lights(
            desc,
            &SceneSphere { centre, radius },
            &shapes,
            &meshes,
            &mut prims,
            &made.area_spectra,
            &textures.spectra,
        )?;
        // The plain meshes' entries, then the instanced meshes', renumbered to follow the
        // shapes'.
        tris.offset_prims(prims.len() as u32);
        prims.extend(made.tri_prims);
        let base = prims.len() as u32;
        prims.extend(flat.object_prims);
        for o in &mut instances.objects {
            o.offset_prims(base);
        }
        // The moving primitives' entries after those.
        if let Some(m) = &mut motion {
            m.offset_prims(prims.len() as u32);
            prims.extend(moving_prims);
        }
        let mut camera = Camera::from_desc(
            &desc.camera,
            (desc.film.xresolution, desc.film.yresolution),
            desc.film.diagonal,
        )
        .map_err(BuildError::BadCamera)?;
        camera.set_motion(desc.motion.camera);
        if desc.integrator.splats() {
            camera.light_path_support().map_err(|e| {
                BuildError::BadCamera(format!(
                    "the \"{}\" integrator traces light paths: {e}",
                    desc.integrator.pbrt_name()
                ))
            })?;
        }
        // Light paths reach the raster points the film reconstructs (its bounds grown by
        // the filter's radius).
        let b = desc.film.render_bounds();
        camera.set_film_extent(
            [b.x0, b.x1, b.y0, b.y1],
            desc.film.xresolution as f32 * desc.film.yresolution as f32,
            desc.filter.radius(),
        );
        let extents: Vec<_> = lights
            .lights
            .iter()
            .map(|l| l.extent(&shapes, &meshes))
            .collect();
        let light_sampler =
            LightSampler::new(desc.sampler.light_sampler, &extents, &lights.distribution);
        let footprints = footprints_for(desc, &textures, &camera);
        let reads_footprints = materials.iter().map(reads_footprints).collect();
        Ok(Scene {
            footprints,
            reads_footprints,
            light_sampler,
            shapes,
            prims,
            meshes,
            tris,
            lights: lights.lights,
            light_spectra: lights.spectra,
            light_distribution: lights.distribution,
            infinite_lights: lights.infinite,
            materials,
            float_textures: textures.floats,
            spectrum_textures: textures.spectra,
            camera,
            media: desc
                .media
                .iter()
                .map(crate::medium::Medium::from_desc)
                .collect(),
            camera_medium: desc.camera_medium,
            light_media: desc.light_media.clone(),
            bvh,
            packets,
            frames,
            instances,
            motion: motion.map(Box::new),
            unbounded,
            bounds,
            spectra: std::sync::OnceLock::new(),
            casters: std::sync::OnceLock::new(),
            film_response: crate::spectrum::FilmResponse::new(
                desc.film.sensor,
                desc.film.white_balance,
                desc.film.color_space,
            ),
        })
    }
}

/// The scene's textures as the renderer reads them.
struct Textures {
    floats: Vec<FloatTexture>,
    spectra: Vec<SpectrumTexture>,
}

/// The description's textures built: image textures get their MIP pyramids, one per distinct
/// image and pyramid settings, shared by every texture that names them.
fn textures(desc: &SceneDesc) -> Textures {
    let mut pyramids = Pyramids::default();
    Textures {
        floats: desc
            .float_textures
            .iter()
            .map(|t| t.build(&mut pyramids))
            .collect(),
        spectra: desc
            .spectrum_textures
            .iter()
            .map(|t| t.build(&mut pyramids))
            .collect(),
    }
}

/// The footprints for the scene `desc` (its textures built, `textures`) seen by `camera`, if
/// anything in it uses them: an image texture with a MIP pyramid, or a material's bump map
/// (its finite-difference step is half the footprint in (u, v)). Scenes without either skip
/// the work at every hit.
fn footprints_for(desc: &SceneDesc, textures: &Textures, camera: &Camera) -> Option<Footprints> {
    let filtered = |it: &ImageTexture| it.mipmap.levels() > 1;
    let wanted = textures.floats.iter().any(|t| match t {
        FloatTexture::Image(it) => filtered(it),
        _ => false,
    }) || textures.spectra.iter().any(|t| match t {
        SpectrumTexture::Image(it) => filtered(it),
        _ => false,
    }) || desc
        .materials
        .iter()
        .any(|m| matches!(m, MaterialDesc::Bumped(b) if b.displacement.is_some()));
    wanted.then(|| {
        Footprints::new(
            camera,
            (desc.film.xresolution, desc.film.yresolution),
            desc.sampler.spp,
        )
    })
}

/// Whether a hit on material `m` may use its footprint: to filter a texture, to step a bump
/// map, or to carry ray differentials through a specular bounce. Only the plain kinds are told
/// apart: a `diffuse` of constant reflectance, a `conductor` of constant parameters that is
/// never smooth enough to be specular; every other material may.
fn reads_footprints(m: &Material) -> bool {
    let textured = |t: &SpectrumTex| matches!(t, SpectrumTex::Tex(_));
    match m {
        Material::Diffuse(d) => textured(&d.reflectance),
        Material::Conductor(c) => {
            m.may_be_specular()
                || textured(&c.eta)
                || textured(&c.k)
                || c.reflectance.as_ref().is_some_and(textured)
                || matches!(c.uroughness, FloatTex::Tex(_))
                || matches!(c.vroughness, FloatTex::Tex(_))
        }
        _ => true,
    }
}

/// The description's materials, or one default material when it has none.
fn materials(desc: &SceneDesc) -> Vec<Material> {
    let mut materials: Vec<Material> = desc.materials.iter().map(MaterialDesc::build).collect();
    if materials.is_empty() {
        materials.push(MaterialDesc::default().build());
    }
    materials
}

/// A shape to make primitives from: its index in error messages, its description, and the
/// placement of the instance it is a copy of (identity for the world's own shapes).
type Placed<'a> = (usize, &'a ShapeDesc, Transform);

/// What flattening the instances leaves.
struct Flattened<'a> {
    /// The world's shapes, then the shapes of every copy of the objects that cannot be
    /// instanced.
    shapes: Vec<Placed<'a>>,
    /// The objects that can, and their placements.
    instances: Instances,
    /// One entry per mesh of those objects, appended to the scene's list after the shapes'.
    object_prims: Vec<PrimInfo>,
}

/// Phase 1. Objects of plain triangle meshes get a BVH of their own, shared by their instances;
/// the others (emitting, alpha-tested or non-mesh shapes) are flattened: each copy becomes
/// shapes of its own, reported with the index one past the world's shapes.
fn flatten_instances(desc: &SceneDesc, n_materials: usize) -> Result<Flattened<'_>, BuildError> {
    let mut shapes: Vec<Placed<'_>> = desc
        .shapes
        .iter()
        .enumerate()
        .map(|(i, s)| (i, s, Transform::IDENTITY))
        .collect();
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
            && let Some(acc) = ObjectAccel::build(obj, &mut object_prims, n_materials)?
        {
            *slot = Some(objects.len() as u32);
            objects.push(acc);
        }
        if let Some(object) = *slot {
            placements.push(Instance {
                object,
                to_world: inst.object_to_world,
            });
            continue;
        }
        for s in &obj.shapes {
            shapes.push((desc.shapes.len(), s, inst.object_to_world));
        }
    }
    Ok(Flattened {
        shapes,
        instances: Instances::new(objects, placements),
        object_prims,
    })
}

/// The primitives made from the shapes, before the BVH orders them.
struct Primitives {
    /// Every primitive's shape.
    shapes: Vec<Shape>,
    /// Its material, emission and alpha.
    prims: Vec<PrimInfo>,
    /// The triangle meshes whose triangles are primitives of their own (emitting or
    /// alpha-tested), world space.
    meshes: Vec<TriangleMesh>,
    /// The distinct spectra of the area lights ([`AreaEmission::spectrum`] indexes them).
    area_spectra: Vec<Measured>,
    /// The other triangle meshes: no record per triangle.
    tris: SceneTrisBuilder,
    /// One record per mesh in `tris`.
    tri_prims: Vec<PrimInfo>,
}

/// Below this many triangles in plain meshes (neither emitting nor alpha-tested), a scene keeps
/// them as primitives of their own in the one BVH: their memory is small, and a second tree
/// with indexed leaves costs every ray a second traversal (on the Cornell box, 23 % of the
/// render time). From this many on, they go to [`SceneTrisBuilder`] (no record per triangle).
pub(super) const SHARED_VERTEX_MIN_TRIANGLES: usize = 4096;

/// Whether a placed shape is a plain triangle mesh: no emission, no alpha cut-out.
fn is_plain_mesh(sd: &ShapeDesc) -> bool {
    matches!(sd.geometry, Geometry::TriangleMesh(_))
        && sd.area_light.is_none()
        && sd.alpha.filter(|a| *a != FloatTex::Const(1.0)).is_none()
}

/// Phase 2. Each shape checked and moved to world space: meshes become their triangles, a
/// curve its pieces, a bilinear mesh its patches, any other shape one primitive.
fn primitives(list: &[Placed<'_>], n_materials: usize) -> Result<Primitives, BuildError> {
    let plain_triangles: usize = list
        .iter()
        .filter(|(_, sd, _)| is_plain_mesh(sd))
        .map(|(_, sd, _)| match &sd.geometry {
            Geometry::TriangleMesh(m) => m.face_count(),
            _ => 0,
        })
        .sum();
    let share_vertices = plain_triangles >= SHARED_VERTEX_MIN_TRIANGLES;
    let mut out = Primitives {
        shapes: Vec::new(),
        prims: Vec::new(),
        meshes: Vec::new(),
        area_spectra: Vec::new(),
        tris: SceneTrisBuilder::default(),
        tri_prims: Vec::new(),
    };
    for &(index, sd, instance_xf) in list {
        check_shape(sd, index, n_materials)?;
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
        let info = PrimInfo {
            material: sd.material,
            emission: sd.area_light.map(|a| match a.image {
                // Until phase 5 makes the light, `light` holds the image's texture index.
                Some(tex) => AreaEmission {
                    l: a.l.into(),
                    two_sided: a.two_sided,
                    spectrum: IMAGE_EMISSION,
                    light: tex,
                },
                None => AreaEmission {
                    l: a.l.into(),
                    two_sided: a.two_sided,
                    spectrum: a
                        .spectrum
                        .map_or(NO_SPECTRUM, |m| spectrum_index(&mut out.area_spectra, m)),
                    light: 0,
                },
            }),
            // A constant alpha of 1 (pbrt's default) cuts nothing: no test needed.
            alpha: sd.alpha.filter(|a| *a != FloatTex::Const(1.0)),
            media: prim_media(sd),
        };
        if share_vertices
            && let Geometry::TriangleMesh(m) = &sd.geometry
            && info.emission.is_none()
            && info.alpha.is_none()
        {
            // A plain mesh: its triangles share one record.
            let world = m.transformed(&sd.object_to_world, sd.reverse_orientation);
            out.tris.add(world, out.tri_prims.len() as u32);
            out.tri_prims.push(info);
            continue;
        }
        let first = out.shapes.len();
        shapes_of(sd, index, &mut out.meshes, &mut out.shapes)?;
        match (sd.area_light, info.emission) {
            // Given by power: each primitive emits Φ on its own, as in pbrt-v4.
            (
                Some(
                    a @ AreaLightDesc {
                        power: Some(phi), ..
                    },
                ),
                Some(e),
            ) => out.prims.extend(out.shapes[first..].iter().map(|s| {
                let l = power_radiance(a.l, phi, a.two_sided, s.emission_area());
                PrimInfo {
                    emission: Some(AreaEmission { l: l.into(), ..e }),
                    ..info
                }
            })),
            _ => out
                .prims
                .extend(std::iter::repeat_n(info, out.shapes.len() - first)),
        }
    }
    Ok(out)
}

/// The world-space primitives of a shape already checked by [`check_shape`], appended to `out`
/// (a triangle mesh's to `meshes` too): its kind's build ([`Geometry::build`]). Errors left are
/// those only the constructors find.
fn shapes_of(
    sd: &ShapeDesc,
    index: usize,
    meshes: &mut Vec<TriangleMesh>,
    out: &mut Vec<Shape>,
) -> Result<(), BuildError> {
    let mut at = Placing {
        to_world: sd.object_to_world,
        reverse_orientation: sd.reverse_orientation,
        meshes,
    };
    sd.geometry
        .build(&mut at, out)
        .map_err(|e| BuildError::Invalid(format!("shape {index}: {e}")))
}

/// Phase 3. The BVH over the bounded primitives, and the primitives laid out in its leaf order
/// (unbounded ones last), so that the primitives of a leaf are neighbours in memory and the
/// leaf's indices are its slots. Returns the shapes, their records, the tree and the indices
/// of the unbounded primitives (infinite planes, tested on every ray).
fn bvh_order(
    shapes: Vec<Shape>,
    prims: Vec<PrimInfo>,
) -> (Vec<Shape>, Vec<PrimInfo>, Bvh, Vec<u32>) {
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
    let prims: Vec<PrimInfo> = order.iter().map(|&i| prims[i as usize]).collect();
    let n_bounded = bvh.indices.len() as u32;
    for (k, idx) in bvh.indices.iter_mut().enumerate() {
        *idx = k as u32;
    }
    let unbounded: Vec<u32> = (n_bounded..shapes.len() as u32).collect();
    (shapes, prims, bvh, unbounded)
}

/// Phase 4. Per leaf of `bvh`: its triangles as a packet, or an empty packet when the leaf
/// holds other shapes or alpha-tested triangles (those go through [`Shape::intersect_with`]).
fn packets(bvh: &Bvh, shapes: &[Shape], prims: &[PrimInfo]) -> Vec<Tri4> {
    (0..bvh.leaf_count() as u32)
        .map(|leaf| {
            let mut lanes = Vec::with_capacity(4);
            for k in bvh.leaf_range(leaf) {
                let i = bvh.indices[k];
                match &shapes[i as usize] {
                    Shape::Triangle(t) if prims[i as usize].alpha.is_none() => lanes.push((t.p, i)),
                    _ => return Tri4::EMPTY,
                }
            }
            Tri4::new(&lanes)
        })
        .collect()
}

/// The scene's lights and how next-event estimation picks them.
struct Lights {
    /// The description's lights, then one per emitting primitive.
    lights: Vec<Light>,
    /// Per light: the spectrum its colour is a multiple of, if the scene gave one.
    spectra: Vec<Option<Measured>>,
    /// In proportion to power.
    distribution: LightDistribution,
    /// Indices of the environment lights.
    infinite: Vec<u32>,
}

/// Phase 5. The description's lights (checked by [`crate::light::LightDesc::validate`]),
/// then every emitting primitive as a light of its own (a mesh light: one per triangle), whose
/// index is written in its record; an image area light reads its image from the built
/// `spectrum_textures`.
fn lights(
    desc: &SceneDesc,
    scene: &SceneSphere,
    shapes: &[Shape],
    meshes: &[TriangleMesh],
    prims: &mut [PrimInfo],
    area_spectra: &[Measured],
    spectrum_textures: &[SpectrumTexture],
) -> Result<Lights, BuildError> {
    let mut lights = desc
        .lights
        .iter()
        .map(|l| l.build(scene).map_err(BuildError::Invalid))
        .collect::<Result<Vec<Light>, BuildError>>()?;
    let mut spectra: Vec<Option<Measured>> = (0..lights.len())
        .map(|i| desc.light_spectra.get(i).copied().flatten())
        .collect();
    for (i, (shape, info)) in shapes.iter().zip(prims.iter_mut()).enumerate() {
        let Some(e) = info.emission.as_mut() else {
            continue;
        };
        // Until now `light` holds the image's texture index.
        let image = (e.spectrum == IMAGE_EMISSION)
            .then(|| AreaImage::from_texture(spectrum_textures.get(e.light as usize), e.l.into()))
            .flatten();
        let Some(light) = AreaLight::new(i as u32, shape, meshes, e.l, e.two_sided, image) else {
            continue;
        };
        e.light = lights.len() as u32;
        lights.push(Light::Area(light));
        spectra.push(area_spectra.get(e.spectrum as usize).copied());
    }
    let powers: Vec<f32> = lights.iter().map(Light::power).collect();
    let distribution = LightDistribution::new(&powers);
    let infinite = (0..lights.len() as u32)
        .filter(|&i| lights[i as usize].is_infinite())
        .collect();
    Ok(Lights {
        lights,
        spectra,
        distribution,
        infinite,
    })
}

/// The index of `m` in `list` (appended when new; shared tables compare by address). Past
/// 65535 distinct spectra the emission falls back to its RGB colour.
fn spectrum_index(list: &mut Vec<Measured>, m: Measured) -> u16 {
    let same = |o: &Measured| o.rgb == m.rgb && std::ptr::eq(o.spectrum, m.spectrum);
    match list.iter().position(same) {
        Some(i) => i as u16,
        None if list.len() < IMAGE_EMISSION as usize => {
            list.push(m);
            (list.len() - 1) as u16
        }
        None => NO_SPECTRUM,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::PackedVec3;
    use crate::scene::desc::{InstanceDesc, ObjectDesc};
    use crate::shape::{PlaneDesc, SphereDesc};
    use std::sync::Arc;

    /// Footprints are skipped only where nothing can read them: a constant diffuse, a
    /// constant rough conductor. A texture, a conductor smooth enough to be specular (its ray
    /// differentials go on to the next hit), any other kind keep them.
    #[test]
    fn only_plain_surfaces_skip_their_footprints() {
        use crate::material::{ConductorMaterial, DiffuseMaterial, DiffuseTransmissionMaterial};
        use crate::math::Rgb;
        let diffuse = |reflectance| Material::Diffuse(DiffuseMaterial { reflectance });
        let conductor = |roughness, eta| {
            Material::Conductor(ConductorMaterial {
                eta,
                k: SpectrumTex::Const(Rgb::splat(3.0)),
                reflectance: None,
                uroughness: roughness,
                vroughness: roughness,
                remap_roughness: true,
            })
        };
        let grey = SpectrumTex::Const(Rgb::splat(0.5));
        assert!(!reads_footprints(&diffuse(grey)));
        assert!(reads_footprints(&diffuse(SpectrumTex::Tex(0))));
        assert!(!reads_footprints(&conductor(FloatTex::Const(0.002), grey)));
        assert!(reads_footprints(&conductor(FloatTex::Const(0.0), grey)));
        assert!(reads_footprints(&conductor(FloatTex::Tex(0), grey)));
        assert!(reads_footprints(&conductor(
            FloatTex::Const(0.3),
            SpectrumTex::Tex(1)
        )));
        // Another kind, even of constant colours.
        assert!(reads_footprints(&Material::DiffuseTransmission(
            DiffuseTransmissionMaterial {
                reflectance: grey,
                transmittance: grey,
                scale: 1.0,
            }
        )));
    }

    fn shape(geometry: Geometry) -> ShapeDesc {
        ShapeDesc {
            medium_interface: None,
            geometry,
            object_to_world: Transform::IDENTITY,
            reverse_orientation: false,
            material: 0,
            area_light: None,
            alpha: None,
        }
    }

    fn bad_mesh() -> Geometry {
        let mut m = TriangleMesh::default();
        m.positions.push(PackedVec3::ZERO);
        m.indices.extend([0, 0, 1]);
        Geometry::TriangleMesh(Arc::new(m))
    }

    #[test]
    fn build_reports_the_rule_broken_with_the_shape() {
        let sphere = Geometry::Sphere(SphereDesc {
            radius: 0.0,
            z_min: -1.0,
            z_max: 1.0,
            phi_max: 360.0,
        });
        let desc = SceneDesc {
            shapes: vec![
                shape(Geometry::Plane(PlaneDesc {
                    p: Vec3::ZERO,
                    n: Vec3::Z,
                })),
                shape(sphere),
            ],
            ..SceneDesc::default()
        };
        let e = Scene::build(&desc).unwrap_err();
        assert_eq!(e.to_string(), "shape 1: radius must be positive, got 0");
        let desc = SceneDesc {
            shapes: vec![shape(bad_mesh())],
            ..SceneDesc::default()
        };
        assert_eq!(
            Scene::build(&desc).unwrap_err(),
            BuildError::BadMesh {
                shape: 0,
                message: "index 1 out of range for 1 vertices".into()
            }
        );
        // The same rule inside an instanced object names the object.
        let desc = SceneDesc {
            objects: vec![ObjectDesc {
                name: "o".into(),
                shapes: vec![shape(bad_mesh())],
            }],
            instances: vec![InstanceDesc {
                object: 0,
                object_to_world: Transform::IDENTITY,
            }],
            ..SceneDesc::default()
        };
        assert_eq!(
            Scene::build(&desc).unwrap_err().to_string(),
            "shape 0: object \"o\": index 1 out of range for 1 vertices"
        );
        let desc = SceneDesc {
            lights: vec![crate::light::LightDesc::Distant(
                crate::light::DistantDesc {
                    direction: Vec3::ZERO,
                    l: crate::math::Rgb::ONE,
                },
            )],
            ..SceneDesc::default()
        };
        assert_eq!(
            Scene::build(&desc).unwrap_err().to_string(),
            "distant light with \"from\" equal to \"to\""
        );
    }
}

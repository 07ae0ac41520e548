//! [`Scene::memory`]: where a built scene's memory goes, buffer by buffer (what each array
//! holds, its capacity included, and what its boxes and shared images hold, each shared
//! buffer once).

use super::Scene;
use super::instance::Instances;
use super::prim::{PrimInfo, mesh_bytes, vec_bytes};
use crate::accel::Tri4;
use crate::light::Light;
use crate::material::Material;
use crate::shape::Shape;
use crate::texture::{FloatTexture, SpectrumTexture};
use std::collections::HashSet;
use std::sync::Arc;

/// A built scene's memory, in bytes, by kind of data.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct SceneMemory {
    /// World-space meshes: positions, normals, uvs, indices (the triangle meshes, the plain
    /// meshes' shared vertex arrays, triangles' vertex indices and per-mesh records, and the
    /// bilinear meshes that patches share, each once).
    pub meshes: usize,
    /// Primitive records: one shape (with what its box holds: a voxel grid's cells, a curve's
    /// shared segment) and one material/emission record per primitive (a plain mesh has one
    /// record for all its triangles, and no shape record), and the list of unbounded
    /// primitives. An emitting or alpha-tested triangle's shape record holds its three
    /// world-space vertices.
    pub primitives: usize,
    /// The BVH over the primitives and its leaves' triangle packets, and the plain meshes'
    /// BVH.
    pub bvh: usize,
    /// Instancing: the objects' trees, meshes and tables, the placements and their tree.
    pub instances: usize,
    /// Images: textures' and lights' (environment, projection), each shared image once.
    pub images: usize,
    /// Texture records.
    pub textures: usize,
    /// Lights (an environment light's sampling tables included, its image is in `images`),
    /// the light distribution and the list of environment lights.
    pub lights: usize,
    /// Materials.
    pub materials: usize,
    /// Participating media: their records and what their grids hold (density, majorants).
    pub media: usize,
}

impl SceneMemory {
    /// Every byte counted.
    pub fn total(&self) -> usize {
        self.meshes
            + self.primitives
            + self.bvh
            + self.instances
            + self.images
            + self.textures
            + self.lights
            + self.materials
            + self.media
    }
}

impl Scene {
    /// Where this scene's memory goes (see [`SceneMemory`]).
    pub fn memory(&self) -> SceneMemory {
        let mut seen = HashSet::new();
        let mut meshes: usize = self.meshes.iter().map(mesh_bytes).sum();
        let mut boxed = 0;
        for s in &self.shapes {
            let held = s.held_bytes(&mut seen);
            boxed += held.primitive;
            meshes += held.meshes;
        }
        let primitives = vec_bytes::<Shape>(self.shapes.capacity())
            + boxed
            + vec_bytes::<PrimInfo>(self.prims.capacity())
            + vec_bytes::<crate::shape::TriangleFrame>(self.frames.capacity())
            + vec_bytes::<u32>(self.unbounded.capacity());
        // Texture and environment images, each shared image once.
        let mut images = 0;
        let texture_images = self
            .float_textures
            .iter()
            .filter_map(|t| match t {
                FloatTexture::Image(i) => Some(i.mipmap.images()),
                _ => None,
            })
            .chain(self.spectrum_textures.iter().filter_map(|t| match t {
                SpectrumTexture::Image(i) => Some(i.mipmap.images()),
                _ => None,
            }))
            .flatten()
            .chain(self.lights.iter().filter_map(Light::image));
        for img in texture_images {
            if seen.insert(Arc::as_ptr(img) as usize) {
                images += img.memory_bytes();
            }
        }
        // The byte forms of the pyramids' levels that have them, each shared pyramid once.
        let mipmaps = self
            .float_textures
            .iter()
            .filter_map(|t| match t {
                FloatTexture::Image(i) => Some(&i.mipmap),
                _ => None,
            })
            .chain(self.spectrum_textures.iter().filter_map(|t| match t {
                SpectrumTexture::Image(i) => Some(&i.mipmap),
                _ => None,
            }));
        for m in mipmaps {
            if seen.insert(Arc::as_ptr(m) as usize) {
                images += m.palette_bytes();
            }
        }
        let lights = vec_bytes::<Light>(self.lights.capacity())
            + self.lights.iter().map(Light::heap_bytes).sum::<usize>()
            + self.light_distribution.memory_bytes()
            + self.light_sampler.memory_bytes()
            + vec_bytes::<u32>(self.infinite_lights.capacity());
        SceneMemory {
            meshes: meshes
                + vec_bytes::<crate::shape::TriangleMesh>(self.meshes.capacity())
                + self.tris.mesh_bytes(),
            primitives,
            bvh: self.bvh.memory_bytes()
                + vec_bytes::<Tri4>(self.packets.capacity())
                + self.tris.tree_bytes(),
            instances: Instances::memory_bytes(&self.instances),
            images,
            textures: vec_bytes::<FloatTexture>(self.float_textures.capacity())
                + vec_bytes::<SpectrumTexture>(self.spectrum_textures.capacity()),
            lights,
            materials: vec_bytes::<Material>(self.materials.capacity()),
            media: vec_bytes::<crate::medium::Medium>(self.media.capacity())
                + self.media.iter().map(|m| m.heap_bytes()).sum::<usize>(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::image::{Image, WrapMode};
    use crate::math::{PackedRgb, PackedVec3, Transform, Vec3};
    use crate::scene::desc::{Geometry, InstanceDesc, ObjectDesc, SceneDesc, ShapeDesc};
    use crate::shape::TriangleMesh;
    use crate::texture::{
        FloatTextureDesc, ImageFilter, ImageTextureDesc, SpectrumTextureDesc, UvMapping,
    };

    /// `n` separate unit triangles along x, none degenerate.
    fn strip(n: u32) -> Arc<TriangleMesh> {
        let mut m = TriangleMesh::default();
        for i in 0..n {
            let x = 2.0 * i as f32;
            m.positions
                .extend([[x, 0.0, 0.0], [x + 1.0, 0.0, 0.0], [x, 1.0, 0.0]].map(PackedVec3::from));
            m.indices.extend([3 * i, 3 * i + 1, 3 * i + 2]);
        }
        Arc::new(m)
    }

    fn shape(m: &Arc<TriangleMesh>) -> ShapeDesc {
        ShapeDesc {
            medium_interface: None,
            geometry: Geometry::TriangleMesh(m.clone()),
            object_to_world: Transform::translate(Vec3::new(0.0, 0.0, 5.0)),
            reverse_orientation: false,
            material: 0,
            area_light: None,
            alpha: None,
        }
    }

    fn mesh_scene(n: u32) -> Scene {
        let desc = SceneDesc {
            shapes: vec![shape(&strip(n))],
            ..SceneDesc::default()
        };
        Scene::build(&desc).unwrap()
    }

    #[test]
    fn memory_grows_with_triangles() {
        // Below the shared-vertex threshold a plain mesh's triangles are shapes of their own.
        assert_eq!(mesh_scene(10).shapes.len(), 10);
        let n0 = super::super::build::SHARED_VERTEX_MIN_TRIANGLES;
        // The strip's tree is a full 8-ary one of 585 nodes up to 4·4096 triangles (one to
        // four in each leaf): eight times the triangles needs more nodes.
        let (small, large) = (mesh_scene(n0 as u32), mesh_scene(8 * n0 as u32));
        // From it on, a plain mesh: no shape record, one PrimInfo for all its triangles (in a
        // vector that grew to capacity 4), nothing unbounded.
        for (n, scene) in [(n0, &small), (8 * n0, &large)] {
            let m = scene.memory();
            assert!(scene.shapes.is_empty());
            assert_eq!(scene.tris.len(), n);
            assert_eq!(m.primitives, 4 * size_of::<PrimInfo>());
            // 3 positions of 12 bytes and 3 indices of 4 bytes per triangle, one padding
            // position after them (the packets' 16-byte loads), and one mesh record of 20 bytes.
            assert_eq!(m.meshes, n * 3 * (12 + 4) + 12 + 20, "{m:?}");
            // No instance: the empty top-level tree only.
            assert!(scene.instances.objects.is_empty());
            assert_eq!(m.instances, scene.instances.memory_bytes());
        }
        let (small, large) = (small.memory(), large.memory());
        assert!(large.meshes > small.meshes && large.bvh > small.bvh);
        // The default material, pushed into an empty vector: capacity 4.
        assert_eq!(large.materials, 4 * size_of::<Material>());
        assert_eq!(
            large.total(),
            large.meshes
                + large.primitives
                + large.bvh
                + large.instances
                + large.images
                + large.textures
                + large.lights
                + large.materials
                + large.media
        );
    }

    #[test]
    fn instances_are_counted_and_geometry_once() {
        let m = strip(50);
        let scene = |copies: usize| {
            let desc = SceneDesc {
                objects: vec![ObjectDesc {
                    name: "strip".into(),
                    shapes: vec![shape(&m)],
                }],
                instances: (0..copies)
                    .map(|k| InstanceDesc {
                        object: 0,
                        object_to_world: Transform::translate(Vec3::new(0.0, k as f32, 0.0)),
                    })
                    .collect(),
                ..SceneDesc::default()
            };
            Scene::build(&desc).unwrap()
        };
        let (one, ten) = (scene(1), scene(10));
        let (a, b) = (one.memory(), ten.memory());
        // Instanced meshes are no flattened primitive: no shape, no world mesh, only the
        // object's one PrimInfo record (in a vector of capacity 4); the rest is in `instances`.
        assert!(one.shapes.is_empty() && ten.shapes.is_empty());
        let p = size_of::<PrimInfo>();
        assert_eq!((a.primitives, a.meshes, b.primitives), (4 * p, 0, 4 * p));
        assert_eq!(a.instances, one.instances.memory_bytes());
        // The object's 50 triangles at least: 3 positions and 3 indices each.
        assert!(a.instances > 50 * 3 * 16, "{a:?}");
        // Nine more placements: their transforms and a bigger top-level tree, not 9 copies.
        assert!(b.instances > a.instances && b.instances < a.instances + 9 * 1024);
    }

    #[test]
    fn a_shared_image_is_counted_once() {
        let image = Arc::new(Image {
            width: 4,
            height: 2,
            texels: vec![PackedRgb::ONE; 8],
        });
        let tex = ImageTextureDesc {
            image: image.clone(),
            to_srgb: None,
            mip: false,
            mapping: UvMapping::default().into(),
            wrap: WrapMode::Repeat,
            scale: 1.0,
            invert: false,
            filter: ImageFilter::Bilinear,
        };
        let desc = SceneDesc {
            float_textures: vec![FloatTextureDesc::Image(tex.clone())],
            spectrum_textures: vec![SpectrumTextureDesc::Image(tex)],
            ..SceneDesc::default()
        };
        let m = Scene::build(&desc).unwrap().memory();
        // The texels, and once their byte form: 8 one-bit indices (a byte) into a table of
        // one texel.
        assert_eq!(m.images, 8 * 12 + 1 + 12);
        assert_eq!(
            m.textures,
            size_of::<FloatTexture>() + size_of::<SpectrumTexture>()
        );
    }

    /// An image texture description of `image` with these pyramid settings.
    fn image_tex(image: &Arc<Image>, wrap: WrapMode, mip: bool) -> SpectrumTextureDesc {
        SpectrumTextureDesc::Image(ImageTextureDesc {
            image: image.clone(),
            to_srgb: None,
            mip,
            mapping: UvMapping::default().into(),
            wrap,
            scale: 1.0,
            invert: false,
            filter: ImageFilter::Bilinear,
        })
    }

    /// The pyramid of a built spectrum texture.
    fn pyramid(t: &SpectrumTexture) -> &Arc<crate::texture::MipMap> {
        match t {
            SpectrumTexture::Image(i) => &i.mipmap,
            _ => panic!("not an image texture"),
        }
    }

    #[test]
    fn textures_of_one_image_share_one_pyramid() {
        // 3×2 texels: resampled to 4×2 (what lies beyond the edges, the wrap mode, matters),
        // then 2×1 and 1×1.
        let odd = Arc::new(Image {
            width: 3,
            height: 2,
            texels: (0..6).map(|i| PackedRgb::splat(i as f32)).collect(),
        });
        let build = |textures: Vec<SpectrumTextureDesc>| {
            Scene::build(&SceneDesc {
                spectrum_textures: textures,
                ..SceneDesc::default()
            })
            .unwrap()
        };
        let scene = build(vec![
            image_tex(&odd, WrapMode::Repeat, true),
            image_tex(&odd, WrapMode::Repeat, true),
            image_tex(&odd, WrapMode::Clamp, true),
            image_tex(&odd, WrapMode::Repeat, false),
        ]);
        let p: Vec<_> = scene.spectrum_textures.iter().map(pyramid).collect();
        assert!(Arc::ptr_eq(p[0], p[1]));
        assert!(!Arc::ptr_eq(p[0], p[2]));
        assert_eq!((p[0].levels(), p[0].level(0).width), (3, 4));
        // Without a pyramid, the image itself.
        assert_eq!(p[3].levels(), 1);
        assert!(std::ptr::eq(p[3].level(0), &*odd));
        // A hundred textures of the image cost what one does.
        let one = build(vec![image_tex(&odd, WrapMode::Repeat, true)]).memory();
        let hundred = build(vec![image_tex(&odd, WrapMode::Repeat, true); 100]).memory();
        assert_eq!(one.images, hundred.images);
        assert!(one.images >= (8 + 2 + 1) * 12, "{one:?}");
        // A power-of-two image is not resampled: one pyramid whatever the wrap modes.
        let square = Arc::new(Image {
            width: 2,
            height: 2,
            texels: (0..4).map(|i| PackedRgb::splat(i as f32)).collect(),
        });
        let scene = build(vec![
            image_tex(&square, WrapMode::Repeat, true),
            image_tex(&square, WrapMode::Clamp, true),
        ]);
        let (a, b) = (
            pyramid(&scene.spectrum_textures[0]),
            pyramid(&scene.spectrum_textures[1]),
        );
        assert!(Arc::ptr_eq(a, b) && std::ptr::eq(a.level(0), &*square));
    }
}

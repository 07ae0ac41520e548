//! The built scene: immutable, shared by all render threads.

mod build;
mod casters;
mod counts;
pub mod desc;
pub mod instance;
pub mod memory;
pub mod motion;
pub mod power;
mod prim;
mod spectra;
mod tris;

pub use casters::Casters;
pub use counts::DescCounts;
pub use prim::{AreaEmission, BuildError, IMAGE_EMISSION, PrimInfo};
pub(crate) use spectra::SceneSpectra;
pub use tris::SceneTris;

use crate::accel::packet::{self, LANES, PacketHits, RayPacket};
use crate::accel::{Bvh, Packet, Tri4};
use crate::camera::Camera;
use crate::light::{Light, LightDistribution, LightSampler};
use crate::material::Material;
use crate::math::{Bounds3, Rgb, SampledSpectrum, Vec3, rgb_lanes};
use crate::ray::Ray;
use crate::shape::{
    ShadingDerivatives, Shape, ShapeHit, SurfaceInteraction, TriangleFrame, TriangleMesh,
    TriangleRay,
};
use crate::spectrum::sampled::SampledWavelengths;
use crate::texture::{FloatTex, FloatTexture, SpectrumTexture, TexCoord, TextureEval};

/// How many times one ray's search on one alpha-tested primitive goes on past a cut-out
/// ([`Scene::alpha_test`]): a quadric needs two, any real surface a few.
const MAX_ALPHA_PASSES: usize = 64;

/// A ray's nearest hit in the scene.
#[derive(Clone, Copy, Debug)]
pub struct SceneHit {
    /// The surface.
    pub si: SurfaceInteraction,
    /// Index of the primitive hit.
    pub prim: u32,
    /// Reflectance given by the shape itself (a voxel's palette colour), which a `diffuse`
    /// material uses instead of its own, when `has_albedo` ([`SceneHit::albedo`]).
    albedo: Rgb,
    /// Whether `albedo` holds a colour. A flag rather than an `Option<Rgb>`: `Option<SceneHit>`
    /// took its niche from that option's 16 bytes, which `intersect` wrote as two 8-byte stores
    /// and its callers read as one 16-byte load: a failed store forward, a stall per ray. The
    /// flag's niche is one byte, written and read as one.
    has_albedo: bool,
    /// The hit's footprint ∂p/∂x, ∂p/∂y (zero when the scene's textures need none; see
    /// [`Scene::tex_coord_with_footprint`]).
    pub footprint: [Vec3; 2],
}

/// A ray's nearest hit in the BVH of primitives and the plain meshes', as
/// [`Scene::intersect_packet`] finds it and [`Scene::intersect_from`] completes it.
#[derive(Clone, Copy, Debug, Default)]
pub struct Nearest {
    /// Where the ray ends: its nearest hit's t, or its own end.
    t_max: f32,
    /// The nearest hit on the primitives (hit, primitive).
    best: Option<(ShapeHit, u32)>,
    /// The nearest plain-mesh hit (slot, hit).
    best_tri: Option<(u32, ShapeHit)>,
}

impl SceneHit {
    /// A hit on primitive `prim` at `si`, its footprint zero.
    #[inline(always)]
    fn new(si: SurfaceInteraction, prim: u32, albedo: Option<Rgb>) -> SceneHit {
        SceneHit {
            si,
            prim,
            albedo: albedo.unwrap_or(Rgb::ZERO),
            has_albedo: albedo.is_some(),
            footprint: [Vec3::ZERO; 2],
        }
    }

    /// Reflectance given by the shape itself (a voxel's palette colour), which a `diffuse`
    /// material uses instead of its own.
    #[inline(always)]
    pub fn albedo(&self) -> Option<Rgb> {
        self.has_albedo.then_some(self.albedo)
    }
}

/// A scene ready to render: primitives in a BVH, lights, materials, textures, camera.
#[derive(Debug)]
pub struct Scene {
    /// Every primitive's shape.
    shapes: Vec<Shape>,
    /// Every primitive's material and emission, same indices as `shapes`.
    prims: Vec<PrimInfo>,
    /// Triangle meshes whose triangles are primitives of their own (emitting or alpha-tested
    /// ones), world space.
    meshes: Vec<TriangleMesh>,
    /// The other triangle meshes, with one record per mesh rather than per triangle.
    tris: SceneTris,
    /// Lights, area lights included.
    lights: Vec<Light>,
    /// The lights in proportion to power (pbrt's `power` light sampler).
    light_distribution: LightDistribution,
    /// How next-event estimation picks a light (the integrator's `lightsampler`).
    light_sampler: LightSampler,
    /// Indices of the lights that rays escaping the scene see (environment lights).
    infinite_lights: Vec<u32>,
    /// Materials.
    materials: Vec<Material>,
    /// Float textures.
    float_textures: Vec<FloatTexture>,
    /// Colour textures.
    spectrum_textures: Vec<SpectrumTexture>,
    /// The camera.
    camera: Camera,
    /// Participating media ([`crate::medium`]); primitives and the camera refer to them by
    /// index.
    media: Vec<crate::medium::Medium>,
    /// The medium the camera sits in (`None`: vacuum).
    camera_medium: Option<u32>,
    /// Per light of the description (the first of [`Scene::lights`]; missing at the end:
    /// vacuum): the medium it sits in.
    light_media: Vec<Option<u32>>,
    bvh: Bvh,
    /// Per leaf of `bvh`: its triangles as a packet, or an empty packet when the leaf holds
    /// other shapes or alpha-tested triangles (those go through [`Shape::intersect_with`]).
    packets: Vec<Tri4>,
    /// Per primitive: its [`TriangleFrame`] if it is a triangle (a zero one otherwise), made
    /// at build so that a hit's record costs no square root or division of its own.
    frames: Vec<TriangleFrame>,
    /// Instanced objects and their placements (the two-level part of the scene).
    instances: instance::Instances,
    /// What moves during the shutter (motion blur); `None` for a still scene.
    motion: Option<Box<motion::Motion>>,
    /// Primitives without finite bounds (infinite planes), tested on every ray.
    unbounded: Vec<u32>,
    bounds: Bounds3,
    /// Per light of `lights`: the spectrum its colour is a multiple of, when the scene gave
    /// one ([`SceneDesc::light_spectra`](desc::SceneDesc::light_spectra),
    /// [`AreaLightDesc::spectrum`](desc::AreaLightDesc::spectrum)).
    light_spectra: Vec<Option<crate::spectrum::dense::Measured>>,
    /// Spectral mode's constant colours as spectra, made on first use.
    spectra: std::sync::OnceLock<SceneSpectra>,
    /// Where the surfaces that may scatter specularly are, found when first asked
    /// ([`Scene::caustic_casters`]).
    casters: std::sync::OnceLock<casters::Casters>,
    /// What gives texture lookups their footprints, when a texture filters over them (an
    /// image texture with a MIP pyramid) or a bump map steps by them; `None` otherwise.
    footprints: Option<crate::camera::footprint::Footprints>,
    /// Per material: whether a hit on it may read its footprint (when the scene has
    /// footprints, they are computed for those hits only).
    reads_footprints: Vec<bool>,
    /// The film's sensor, white balance and output space, unless it is the plain CIE 1931
    /// observer into sRGB.
    film_response: Option<crate::spectrum::FilmResponse>,
}

impl Scene {
    /// The camera.
    #[inline]
    pub fn camera(&self) -> &Camera {
        &self.camera
    }

    /// The medium the camera sits in (`None`: vacuum).
    #[inline]
    pub fn camera_medium(&self) -> Option<u32> {
        self.camera_medium
    }

    /// The medium a ray leaving primitive `prim` (geometric normal `n`) in direction `w`
    /// travels in: the side of its interface `w` points to when crossing it changes medium,
    /// else `current`, the medium the ray was already in.
    #[inline]
    pub fn medium_past(&self, prim: u32, n: Vec3, w: Vec3, current: Option<u32>) -> Option<u32> {
        match self.prim(prim).media {
            Some(mi) if mi.is_transition() => mi.towards(n, w),
            _ => current,
        }
    }

    /// The medium a ray leaving light `i` from a point with geometric normal `n` in direction
    /// `w` starts in: for an area light, the side of its shape's interface `w` points to; for
    /// the others, the medium they sit in (`None`: vacuum).
    pub fn light_medium(&self, i: usize, n: Vec3, w: Vec3) -> Option<u32> {
        match self.lights[i].as_area() {
            Some(a) => self.prim(a.prim).media.and_then(|mi| mi.towards(n, w)),
            None => self.light_media.get(i).copied().flatten(),
        }
    }

    /// Lights, area lights included; a light's index here is its id everywhere else
    /// ([`AreaEmission::light`], [`Scene::infinite_lights`], [`Scene::light_sampler`]).
    #[inline]
    pub fn lights(&self) -> &[Light] {
        &self.lights
    }

    /// How next-event estimation picks a light (the integrator's `lightsampler`).
    #[inline]
    pub fn light_sampler(&self) -> &LightSampler {
        &self.light_sampler
    }

    /// The lights in proportion to power (pbrt's `power` light sampler).
    #[inline]
    pub fn light_distribution(&self) -> &LightDistribution {
        &self.light_distribution
    }

    /// Indices of the lights that rays escaping the scene see (environment lights).
    #[inline]
    pub fn infinite_lights(&self) -> &[u32] {
        &self.infinite_lights
    }

    /// The incident radiance at `ctx` from `light`, one of [`Scene::lights`], for sample `u`
    /// (an area light samples its shape among this scene's).
    #[inline]
    pub fn sample_li(
        &self,
        light: &Light,
        ctx: &crate::light::LightSampleContext,
        u: crate::math::Vec2,
    ) -> Option<crate::light::LightLiSample> {
        light.sample_li(ctx, u, &self.shapes, &self.meshes)
    }

    /// What primitive `prim` (a [`SceneHit::prim`]) is made of: material, emission, alpha,
    /// media.
    #[inline]
    pub fn prim(&self, prim: u32) -> &PrimInfo {
        &self.prims[prim as usize]
    }

    /// Every primitive's shape, same indices as [`Scene::prim`].
    #[inline]
    pub fn shapes(&self) -> &[Shape] {
        &self.shapes
    }

    /// Triangle meshes whose triangles are primitives of their own (emitting or
    /// alpha-tested ones), world space.
    #[inline]
    pub fn meshes(&self) -> &[TriangleMesh] {
        &self.meshes
    }

    /// The other triangle meshes, with one record per mesh rather than per triangle.
    #[inline]
    pub fn tris(&self) -> &SceneTris {
        &self.tris
    }

    /// Material `id` (a [`PrimInfo::material`]).
    #[inline]
    pub fn material(&self, id: u32) -> &Material {
        &self.materials[id as usize]
    }

    /// Participating medium `id` (a [`crate::medium::MediumInterface`] side, the camera's).
    #[inline]
    pub fn medium(&self, id: u32) -> &crate::medium::Medium {
        &self.media[id as usize]
    }

    /// Every participating medium, indexed by id (empty: a scene without media).
    #[inline]
    pub fn media(&self) -> &[crate::medium::Medium] {
        &self.media
    }

    /// What moves during the shutter (motion blur); `None` for a still scene.
    #[inline]
    pub fn motion(&self) -> Option<&motion::Motion> {
        self.motion.as_deref()
    }

    /// What gives texture lookups their footprints, when a texture filters over them or a
    /// bump map steps by them; `None` otherwise.
    #[inline]
    pub fn footprints(&self) -> Option<&crate::camera::footprint::Footprints> {
        self.footprints.as_ref()
    }

    /// The film's sensor, white balance and output space, unless it is the plain CIE 1931
    /// observer into sRGB (`None`).
    #[inline]
    pub fn film_response(&self) -> Option<&crate::spectrum::FilmResponse> {
        self.film_response.as_ref()
    }

    /// Where the surfaces that may scatter specularly are ([`casters::find`]), found when
    /// first asked (`path` with `caustics` aims its light paths at them).
    pub fn caustic_casters(&self) -> Casters {
        *self.casters.get_or_init(|| {
            casters::find(
                &self.shapes,
                &self.prims,
                &self.tris,
                &self.materials,
                !self.instances.is_empty() || self.motion.is_some(),
            )
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

    /// Triangles the scene holds: those of the plain meshes and those that are primitives of
    /// their own (degenerate ones, which no ray can hit, are not kept).
    pub fn triangle_count(&self) -> usize {
        self.tris.len()
            + self
                .shapes
                .iter()
                .filter(|s| matches!(s, Shape::Triangle(_)))
                .count()
    }

    /// Primitives the scene holds: those of the primitives' tree and one per triangle of the
    /// plain meshes.
    pub fn primitive_count(&self) -> usize {
        self.shapes.len() + self.tris.len()
    }

    /// Nodes of the acceleration structures (the primitives' tree and the plain meshes').
    pub fn bvh_node_count(&self) -> usize {
        self.bvh.node_count() + self.tris.node_count()
    }

    /// The course's "keep the nearest valid hit": the smallest t with 0 < t < t_max over all
    /// primitives, found through the BVH. The interaction takes the ray's time, which the rays
    /// spawned from it inherit.
    ///
    /// The time is written where each record is built (a triangle's record by the triangle,
    /// the others' by [`Scene::finish_hit`]): setting it on the returned record unwrapped and
    /// rewrapped the `Option`, a copy of the whole record read back right after its piecewise
    /// stores (a failed store forward per ray).
    #[inline]
    pub fn intersect(&self, ray: &Ray) -> Option<SceneHit> {
        crate::counters::count_ray();
        let mut best: Option<(crate::shape::ShapeHit, u32)> = None;
        // The ray is read in place and its end kept apart: a copy of a ray its caller has
        // just written field by field costs a stall per ray (store forwarding).
        let mut t_max = ray.t_max;
        let pre = TriangleRay::new(ray);
        if !self.unbounded.is_empty()
            && let Some((h, i)) = self.nearest_unbounded(ray, &pre)
        {
            t_max = h.t;
            best = Some((h, i));
        }
        self.bvh.traverse(ray, t_max, |leaf, t_max| {
            let p = &self.packets[leaf.id as usize];
            if !p.is_empty() {
                let (lane, h) = p.intersect_to(ray, t_max, &pre)?;
                best = Some((h, p.ids[lane]));
                return Some(h.t);
            }
            self.bvh.leaf_nearest(leaf, ray, t_max, &mut |i, r| {
                let h = self.hit(i, r, &pre)?;
                best = Some((h, i));
                Some(h.t)
            })
        });
        if let Some(b) = best {
            t_max = b.0.t;
        }
        // The plain meshes (shared vertices), the moving things, then the instances: each
        // searched below the nearest hit so far, so the last one found is the nearest.
        let best_tri = if self.tris.is_empty() {
            None
        } else {
            self.tris.intersect(ray, t_max, &pre)
        };
        if let Some((_, h)) = best_tri {
            t_max = h.t;
        }
        self.nearest_rest(ray, t_max, best, best_tri)
    }

    /// [`Scene::intersect`]'s nearest hits of `ray` after the BVH of primitives and the plain
    /// meshes: `best` (primitive hit, its index) and `best_tri` (plain-mesh slot, hit), the ray
    /// ending at `t_max`; then the moving things and the instances, and the nearest hit's
    /// record.
    #[inline(always)]
    fn nearest_rest(
        &self,
        ray: &Ray,
        mut t_max: f32,
        best: Option<(crate::shape::ShapeHit, u32)>,
        best_tri: Option<(u32, crate::shape::ShapeHit)>,
    ) -> Option<SceneHit> {
        let mut moving = None;
        if let Some(m) = &self.motion {
            moving = m.intersect(&Ray { t_max, ..*ray }, ray.time);
            if let Some(mh) = &moving {
                t_max = mh.hit.t;
            }
        }
        if !self.instances.is_empty()
            && let Some(ih) = self.instances.intersect(&Ray { t_max, ..*ray })
        {
            let (si, prim) = self.instances.interaction(ray, &ih);
            // Instanced objects are triangle meshes, which carry no colour of their own.
            let hit = SceneHit::new(si, prim, None);
            return Some(
                self.finish_hit(ray, hit, |_| self.instances.shading_derivatives(ray, &ih)),
            );
        }
        if let (Some(m), Some(mh)) = (&self.motion, moving) {
            let (si, prim, albedo) = m.interaction(ray, &mh);
            let hit = SceneHit::new(si, prim, albedo);
            return Some(self.finish_hit(ray, hit, |_| m.shading_derivatives(ray, &mh)));
        }
        if let Some((slot, h)) = best_tri {
            let (si, prim) = self.tris.interaction(ray, slot, &h);
            let hit = SceneHit::new(si, prim, None);
            return Some(self.finish_hit(ray, hit, |si| self.tris.shading_derivatives(slot, si)));
        }
        let (h, prim) = best?;
        let shape = &self.shapes[prim as usize];
        if let Shape::Triangle(t) = shape
            && !self.finishes(prim)
        {
            // Built where it is returned: a record built aside and then copied was read back
            // right after being written piece by piece, which stalled every hit. (Written out
            // again in the match below on purpose: one closure for both made the whole path
            // 1.5 % more instructions on the Cornell box.)
            return Some(SceneHit::new(
                t.interaction_framed(
                    ray,
                    &h,
                    &self.meshes[t.mesh as usize],
                    &self.frames[prim as usize],
                ),
                prim,
                None,
            ));
        }
        let hit = match shape {
            // The common case first, without the dispatch over every shape.
            Shape::Triangle(t) => SceneHit::new(
                t.interaction_framed(
                    ray,
                    &h,
                    &self.meshes[t.mesh as usize],
                    &self.frames[prim as usize],
                ),
                prim,
                None,
            ),
            _ => SceneHit::new(
                shape.interaction(ray, &h, &self.meshes),
                prim,
                shape.hit_albedo(&h),
            ),
        };
        Some(self.finish_hit(ray, hit, |si| {
            shape.shading_derivatives(ray, &h, &self.meshes, si)
        }))
    }

    /// The first part of [`Scene::intersect`] for the rays of lanes `active` of `rays`,
    /// traced as one packet through the BVH of primitives and the plain meshes' (what comes
    /// before, the unbounded primitives, one ray at a time): each lane's nearest hit there,
    /// which [`Scene::intersect_from`] completes into the ray's hit. Each ray finds what it
    /// finds alone, the nearest hit being the same; of hits at exactly the same t on different
    /// surfaces (two walls' common edge), the packet may keep another than the single ray: it
    /// visits the leaves in their order along `order`, the same for every lane whichever share
    /// the packet ([`crate::accel::Bvh::traverse_packet`]). For rays that cross the same
    /// boxes, such as the camera rays of one pixel's samples.
    pub fn intersect_packet(
        &self,
        rays: &[Ray; LANES],
        active: u32,
        order: Vec3,
    ) -> [Nearest; LANES] {
        let mut out = [Nearest::default(); LANES];
        if active == 0 {
            return out;
        }
        for _ in 0..active.count_ones() {
            crate::counters::count_ray();
        }
        let rp = RayPacket::new(rays, active, order);
        let mut hits = PacketHits::new(rays.each_ref().map(|r| r.t_max));
        let lanes = |mut m: u32| {
            std::iter::from_fn(move || {
                (m != 0).then(|| {
                    let k = m.trailing_zeros() as usize;
                    m &= m - 1;
                    k
                })
            })
        };
        if !self.unbounded.is_empty() {
            for k in lanes(active) {
                if let Some((h, i)) = self.nearest_unbounded(&rp.rays[k], &rp.pre[k]) {
                    hits.set(k, i, h);
                }
            }
        }
        self.bvh.traverse_packet(&rp, &mut hits, |leaf, m, hits| {
            let p = &self.packets[leaf.id as usize];
            if !p.is_empty() {
                packet::leaf_nearest(p, &rp, m, hits, |j| p.ids[j]);
                return;
            }
            for k in lanes(m) {
                let mut found = None;
                self.bvh
                    .leaf_nearest(leaf, &rp.rays[k], hits.t.lane(k), &mut |i, r| {
                        let h = self.hit(i, r, &rp.pre[k])?;
                        found = Some((i, h));
                        Some(h.t)
                    });
                if let Some((i, h)) = found {
                    hits.set(k, i, h);
                }
            }
        });
        let mut tri_hits = PacketHits::new(hits.t.to_array());
        if !self.tris.is_empty() {
            self.tris.intersect_packet(&rp, &mut tri_hits);
        }
        let (t, bu, bv) = (hits.t.to_array(), hits.u.to_array(), hits.v.to_array());
        let (tt, tu, tv) = (
            tri_hits.t.to_array(),
            tri_hits.u.to_array(),
            tri_hits.v.to_array(),
        );
        for k in lanes(active) {
            let hit = |t: f32, u: f32, v: f32| ShapeHit { t, u, v };
            out[k] = Nearest {
                t_max: tt[k],
                best: (hits.id[k] != u32::MAX).then(|| (hit(t[k], bu[k], bv[k]), hits.id[k])),
                best_tri: (tri_hits.id[k] != u32::MAX)
                    .then(|| (tri_hits.id[k], hit(tt[k], tu[k], tv[k]))),
            };
        }
        out
    }

    /// The nearest hit of `ray`, completed from `n`, its nearest hit in the BVH of primitives
    /// and the plain meshes' ([`Scene::intersect_packet`]): what [`Scene::intersect`] returns.
    #[inline(always)]
    pub fn intersect_from(&self, ray: &Ray, n: &Nearest) -> Option<SceneHit> {
        self.nearest_rest(ray, n.t_max, n.best, n.best_tri)
    }

    /// Whether a hit on primitive `prim` needs [`Scene::finish_hit`]: the scene's textures
    /// use footprints, or its material is a `mix` or carries a bump or normal map (what
    /// [`crate::material::mix::apply_bump`] acts on).
    #[inline(always)]
    fn finishes(&self, prim: u32) -> bool {
        self.footprints.is_some()
            || matches!(
                self.materials[self.prims[prim as usize].material as usize],
                Material::Mix(_) | Material::Bumped(_)
            )
    }

    /// Completes `hit` in place: the ray's time, its footprint, and its shading frame changed
    /// by its primitive's material's bump or normal map (for a `mix`, the picked material's), a
    /// bump map reading the shading derivatives `derivatives` gives for the hit's interaction
    /// (called only then). The interaction is not copied on the way: a copy read back the
    /// record its shape had just written piece by piece, and stalled every hit (store
    /// forwarding).
    #[inline(always)]
    fn finish_hit(
        &self,
        ray: &Ray,
        mut hit: SceneHit,
        derivatives: impl FnOnce(&SurfaceInteraction) -> ShadingDerivatives,
    ) -> SceneHit {
        hit.si.time = ray.time;
        let m = self.prims[hit.prim as usize].material;
        if let Some(f) = &self.footprints
            && self.reads_footprints[m as usize]
        {
            let (dpdx, dpdy) = f.at_hit(ray.o, hit.si.p, hit.si.n);
            hit.footprint = [dpdx, dpdy];
        }
        let footprint = hit.footprint;
        crate::material::mix::apply_bump(
            &self.materials,
            &self.textures(),
            m,
            &mut hit.si,
            |si| Scene::tex_coord_from(si, footprint),
            derivatives,
        );
        hit
    }

    /// The nearest hit of `ray` on the primitives without finite bounds (infinite planes,
    /// tested one after another, the ray shortened by each hit): (hit, primitive).
    #[inline]
    fn nearest_unbounded(
        &self,
        ray: &Ray,
        pre: &TriangleRay,
    ) -> Option<(crate::shape::ShapeHit, u32)> {
        let mut r = *ray;
        let mut best = None;
        for &i in &self.unbounded {
            if let Some(h) = self.hit(i, &r, pre) {
                r.t_max = h.t;
                best = Some((h, i));
            }
        }
        best
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
    ///
    /// Where the surface is cut away the search goes on past the cut on this primitive alone,
    /// as pbrt-v4's `GeometricPrimitive::Intersect` does: a ray spawned from the cut-away point
    /// in the same direction, up to what is left of `t_max`, meets the primitive again (a
    /// quadric's far side, seen through a hole in its near side), and that hit is tested in
    /// turn. The hit kept is given as one of `ray` ([`Shape::hit_after`]).
    #[cold]
    #[inline(never)]
    fn alpha_test(
        &self,
        i: u32,
        ray: &Ray,
        h: crate::shape::ShapeHit,
        alpha: FloatTex,
    ) -> Option<crate::shape::ShapeHit> {
        let shape = &self.shapes[i as usize];
        // The ray tested, its hit, and where that ray starts on `ray` (`None`: it is `ray`).
        let (mut r, mut hit, mut before) = (*ray, h, None);
        // A bound on the searches past cuts, which only a surface folded on itself many
        // times over along one ray could reach.
        for _ in 0..MAX_ALPHA_PASSES {
            let si = shape.interaction(&r, &hit, &self.meshes);
            let on_ray = match &before {
                None => hit,
                Some(b) => shape.hit_after(b, &hit),
            };
            if self.alpha_keeps(alpha, &r, &si) {
                return Some(on_ray);
            }
            let mut next = si.spawn_ray(r.d).at_time(ray.time);
            next.t_max = r.t_max - hit.t;
            hit = shape.intersect_with(&next, &TriangleRay::new(&next))?;
            (r, before) = (next, Some(on_ray));
        }
        None
    }

    /// Whether the surface is there at `si`, met by `ray`: alpha a = 1 keeps it, a = 0 cuts it
    /// away, and in between it is kept when a hash of the ray, uniform in [0, 1), is below a.
    #[inline]
    fn alpha_keeps(&self, alpha: FloatTex, ray: &Ray, si: &SurfaceInteraction) -> bool {
        let a = self.textures().float(alpha, &Scene::tex_coord(si));
        if a >= 1.0 {
            return true;
        }
        if a <= 0.0 {
            return false;
        }
        let u = crate::sampling::u32_to_unit_f32(crate::sampling::hash_u64(&[
            ray.o.x.to_bits() as u64 | (ray.o.y.to_bits() as u64) << 32,
            ray.o.z.to_bits() as u64 | (ray.d.x.to_bits() as u64) << 32,
            ray.d.y.to_bits() as u64 | (ray.d.z.to_bits() as u64) << 32,
        ]) as u32);
        u < a
    }

    /// True if anything blocks the ray before `t_max` (shadow rays).
    pub fn intersect_p(&self, ray: &Ray) -> bool {
        crate::counters::count_ray();
        let pre = TriangleRay::new(ray);
        self.unbounded
            .iter()
            .any(|&i| self.hit(i, ray, &pre).is_some())
            || self.bvh.intersect_any_leaves(ray, |leaf, r| {
                let p = &self.packets[leaf.id as usize];
                if !p.is_empty() {
                    return p.intersect_any(r, &pre);
                }
                self.bvh
                    .leaf_any(leaf, r, &mut |i, r| self.hit(i, r, &pre).is_some())
            })
            || (!self.tris.is_empty() && self.tris.intersect_any(ray, &pre))
            || (!self.instances.is_empty() && self.instances.intersect_any(ray))
            || self
                .motion
                .as_ref()
                .is_some_and(|m| m.intersect_any(ray, ray.time))
    }

    /// Texture evaluation against this scene's textures.
    pub fn textures(&self) -> TextureEval<'_> {
        TextureEval {
            floats: &self.float_textures,
            spectra: &self.spectrum_textures,
        }
    }

    /// Where textures are looked up for a hit, without a footprint.
    pub fn tex_coord(si: &SurfaceInteraction) -> TexCoord {
        TexCoord::at(si)
    }

    /// Where textures are looked up for `si` with footprint ∂p/∂x, ∂p/∂y, and the (u, v)
    /// derivatives that gives ([`TexCoord::with_footprint`]).
    #[inline]
    fn tex_coord_from(si: &SurfaceInteraction, footprint: [Vec3; 2]) -> TexCoord {
        let tc = Scene::tex_coord(si);
        if footprint == [Vec3::ZERO; 2] {
            return tc;
        }
        tc.with_footprint(si.dpdu, si.dpdv, footprint[0], footprint[1])
    }

    /// Where textures are looked up for a hit, with its footprint.
    #[inline]
    pub fn tex_coord_with_footprint(hit: &SceneHit) -> TexCoord {
        Scene::tex_coord_from(&hit.si, hit.footprint)
    }
}

/// Per shape: its [`TriangleFrame`] if it is a triangle, a zero one otherwise (see
/// [`Scene`]'s `frames`).
fn triangle_frames(shapes: &[Shape]) -> Vec<TriangleFrame> {
    let zero = TriangleFrame {
        n: crate::math::PackedVec3::ZERO,
        s: crate::math::PackedVec3::ZERO,
    };
    shapes
        .iter()
        .map(|s| match s {
            Shape::Triangle(t) => TriangleFrame::new(t.vertices()),
            _ => zero,
        })
        .collect()
}

impl Scene {
    /// The scene's constant colours as spectra, prepared on the first call.
    pub(crate) fn spectra(&self) -> &SceneSpectra {
        self.spectra
            .get_or_init(|| SceneSpectra::new(&self.lights, &self.light_spectra, &self.materials))
    }

    /// Spectral mode's view of material `m` (a [`PrimInfo::material`]) on a path of
    /// wavelengths `lambda`: its constant colours prepared by position, which only its kind
    /// reads back ([`crate::material::MaterialKind::colours`]).
    #[inline(always)]
    pub fn spectral_colours<'a>(
        &'a self,
        m: u32,
        lambda: &'a SampledWavelengths,
    ) -> crate::material::SpectralColours<'a> {
        crate::material::SpectralColours {
            lambda,
            consts: &self.spectra().materials[m as usize],
        }
    }

    /// Emission `l` of light `i`, which is its constant colour times `factor` (see
    /// [`crate::light::LightLiSample::factor`]), arriving along direction `wi` (towards the
    /// light), as transport lanes: in spectral mode the light's prepared spectrum as an
    /// illuminant, times `factor` (lights without a constant colour uplift `l` itself, but the
    /// sun and sky, spectral by nature, give their spectrum along `wi`); in RGB mode `l`'s
    /// lanes (r, g, b, b).
    #[inline]
    pub fn light_radiance(
        &self,
        i: usize,
        lambda: Option<&SampledWavelengths>,
        l: Rgb,
        factor: f32,
        wi: Vec3,
    ) -> SampledSpectrum {
        match lambda {
            None => rgb_lanes(l),
            Some(w) => match &self.spectra().lights[i] {
                Some(sp) => w.sample_prepared_illuminant(sp) * factor,
                None => self.lights[i]
                    .le_spectral(wi, w)
                    .unwrap_or_else(|| w.illuminant(l)),
            },
        }
    }

    /// Radiance of environment light `i` (one of [`Scene::infinite_lights`]) arriving along a
    /// ray that leaves the scene in direction `d` (need not be unit), as transport lanes; zero
    /// where it gives none. [`Light::le`] through [`Scene::light_radiance`], except in
    /// spectral mode for a light spectral by nature ([`Light::le_spectral`]), whose colour
    /// would be thrown away.
    #[inline]
    pub fn environment_radiance(
        &self,
        i: usize,
        lambda: Option<&SampledWavelengths>,
        d: Vec3,
    ) -> SampledSpectrum {
        if let Some(s) = lambda.and_then(|w| self.lights[i].le_spectral(d, w)) {
            return s;
        }
        let le = self.lights[i].le(d);
        if le == Rgb::ZERO {
            return SampledSpectrum::ZERO;
        }
        self.light_radiance(i, lambda, le, 1.0, d)
    }
}

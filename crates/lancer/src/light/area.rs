//! Diffuse area lights (pbrt-v4's `diffuse` `AreaLightSource`): a primitive of the scene that
//! emits radiance L from its surface, one light per primitive ([`AreaLight`]); the surface a
//! light samples points on, prepared once at scene build ([`Emitter`]); the sampling of
//! incident light from it ([`sample_area_li`], [`area_pdf_li`]) and of light leaving it.
//!
//! A triangle of an emitting mesh keeps its three vertices and its oriented unit normal, so
//! that a light sample reads one record: no lookup through the shape list or the mesh's index
//! buffer, no cross product, no normalisation. The point is b₀p₀ + b₁p₁ + b₂p₂ and the normal
//! the one [`Shape::sample_area`] would give, bit for bit.
//!
//! Power: a diffuse emitter of radiance L and area A emits Φ = π·A·L per emitting side.

use super::area_image::{AreaImage, sampled_radiance};
use super::bounds::{DirectionCone, LightBounds, LightExtent};
use super::kind::{LightKind, LightLePdf, LightLeSample, LightType, point_error};
use super::sample::{LightLiSample, LightSampleContext};
use crate::math::{Frame, PackedRgb, PackedVec3, Rgb, Vec2, Vec3, cross};
use crate::sampling::ONE_MINUS_EPSILON;
use crate::sampling::{cosine_hemisphere_pdf, sample_cosine_hemisphere, sample_uniform_triangle};
use crate::shape::{Shape, ShapeSample, TriangleMesh};
use std::f32::consts::PI;

/// A diffuse area light attached to a shape, as a scene describes it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AreaLightDesc {
    /// Emitted radiance (already scaled and normalised as pbrt does).
    pub l: Rgb,
    /// Emits from both sides (otherwise only the side the normal faces).
    pub two_sided: bool,
    /// The spectrum `l` is a multiple of, when the scene gave one (spectral mode emits it).
    pub spectrum: Option<crate::spectrum::dense::Measured>,
    /// pbrt-v4's `power` Φ in watts, when given: each primitive the shape becomes (a mesh's
    /// every triangle, as in pbrt-v4) then emits `l · Φ / (π · sides · area)`, sides 2 when
    /// two-sided, area the primitive's own (see `crate::scene::power::emission_area`).
    pub power: Option<f32>,
    /// pbrt-v4's `filename`: the index of an image texture among the scene description's
    /// `spectrum_textures` the radiance is read from by uv; `l` is then the factor its
    /// texels are multiplied by (grey).
    pub image: Option<u32>,
}

/// A diffuse area light: a primitive of the scene that emits radiance L from its surface.
/// There is one per emitting primitive, so its colour is packed; a triangle's vertices and
/// normal are not ([`Emitter::Triangle`]: read on every light sample).
#[derive(Clone, Debug, PartialEq)]
pub struct AreaLight {
    /// Index of the primitive in the scene's shapes.
    pub prim: u32,
    /// Emitted radiance.
    pub l: PackedRgb,
    /// Emits from both sides (otherwise only from the side its normal faces).
    pub two_sided: bool,
    /// Surface area, world space.
    pub area: f32,
    /// Its surface, prepared for sampling (a whole sphere is sampled by the cone of
    /// directions it subtends rather than by area).
    pub emitter: Emitter,
    /// The image the radiance comes from (pbrt-v4's `filename`; `l` is then its mean times
    /// its scale).
    pub image: Option<Box<AreaImage>>,
}

impl AreaLight {
    /// The light of primitive `prim`, `shape` (of the scene whose meshes are `meshes`),
    /// emitting `l` (on both sides when `two_sided`), or read from `image`; `None` when it
    /// emits nothing (no area, or black).
    pub fn new(
        prim: u32,
        shape: &Shape,
        meshes: &[TriangleMesh],
        l: PackedRgb,
        two_sided: bool,
        image: Option<Box<AreaImage>>,
    ) -> Option<AreaLight> {
        let area = shape.area();
        if !(area > 0.0 && area.is_finite()) || l == PackedRgb::ZERO {
            return None;
        }
        Some(AreaLight {
            prim,
            // With an image: its mean times its factor, for the power and the light bounds
            // (pbrt-v4's `Phi` and `Bounds`).
            l: image.as_ref().map_or(l, |im| (im.mean() * im.scale).into()),
            two_sided,
            area,
            emitter: Emitter::new(shape, meshes, shape.whole_sphere()),
            image,
        })
    }

    /// Its triangle's vertices and oriented normal when it is a triangle of constant
    /// radiance: the commonest light, sampled inline where lights are sampled
    /// ([`sample_triangle_li`]).
    #[inline(always)]
    pub fn plain_triangle(&self) -> Option<(&[Vec3; 3], &Vec3)> {
        match (&self.emitter, &self.image) {
            (Emitter::Triangle { p, n }, None) => Some((p, n)),
            _ => None,
        }
    }
}

impl LightKind for AreaLight {
    fn light_type(&self) -> LightType {
        LightType::Area
    }

    fn sample_li(
        &self,
        ctx: &LightSampleContext,
        u: Vec2,
        shapes: &[Shape],
        meshes: &[TriangleMesh],
    ) -> Option<LightLiSample> {
        let mut s = sample_area_li(
            self.prim,
            self.l,
            self.two_sided,
            self.area,
            &self.emitter,
            ctx,
            u,
            shapes,
            meshes,
        )?;
        if self.image.is_some() {
            s.l = sampled_radiance(
                &self.image,
                self.l,
                shapes,
                self.prim,
                meshes,
                ctx.p,
                s.p_light,
            );
        }
        Some(s)
    }

    fn pdf_li(&self, ctx: &LightSampleContext, wi: Vec3, hit: Option<(Vec3, Vec3)>) -> f32 {
        area_pdf_li(self.area, &self.emitter, ctx, wi, hit)
    }

    /// Φ = π·A·L per emitting side.
    fn power(&self) -> f32 {
        let l = Rgb::from(self.l);
        PI * self.area * ((l.x + l.y + l.z) / 3.0) * if self.two_sided { 2.0 } else { 1.0 }
    }

    /// φ = π·A·max(L), its normals' cone, emission over a hemisphere.
    fn extent(&self, shapes: &[Shape], meshes: &[TriangleMesh]) -> LightExtent {
        let shape = &shapes[self.prim as usize];
        let normals = match shape {
            // Flat shapes: one normal, as the shape orients it.
            Shape::Triangle(_) | Shape::Disk(_) => shape
                .sample_area(Vec2::splat(1.0 / 3.0), meshes)
                .map(|s| DirectionCone {
                    w: s.n,
                    cos_theta: 1.0,
                })
                .unwrap_or(DirectionCone::ENTIRE_SPHERE),
            _ => DirectionCone::ENTIRE_SPHERE,
        };
        let bounds = shape.bounds();
        if bounds.is_empty() || !bounds.diagonal().is_finite() {
            return LightExtent::Dark;
        }
        let l = Rgb::from(self.l);
        LightBounds {
            bounds,
            phi: l.x.max(l.y).max(l.z) * self.area * PI,
            normals,
            cos_theta_e: (PI / 2.0).cos(),
            two_sided: self.two_sided,
        }
        .extent()
    }

    fn constant_colour(&self) -> Option<Rgb> {
        match self.image {
            None => Some(self.l.into()),
            Some(_) => None,
        }
    }

    /// pbrt-v4's: a point uniform on the surface from `u1` (p_pos = 1/A, as
    /// [`sample_area_li`] assumes), a direction cosine-weighted about its normal from `u2`
    /// (p_dir = cos θ/π); two-sided, `u2.x` first picks the side (p_dir = |cos θ|/2π).
    fn sample_le(
        &self,
        u1: Vec2,
        u2: Vec2,
        shapes: &[Shape],
        meshes: &[TriangleMesh],
    ) -> Option<LightLeSample> {
        let shape = &shapes[self.prim as usize];
        let ss = match &self.emitter {
            Emitter::Triangle { p, n } => triangle_point(p, n, u1),
            _ => shape.sample_area(u1, meshes)?,
        };
        let (local, pdf_dir) = if self.two_sided {
            let back = u2.x >= 0.5;
            let ux = if back { (u2.x - 0.5) * 2.0 } else { u2.x * 2.0 };
            let mut w = sample_cosine_hemisphere(Vec2::new(ux.min(ONE_MINUS_EPSILON), u2.y));
            if back {
                w.z = -w.z;
            }
            (w, cosine_hemisphere_pdf(w.z.abs()) / 2.0)
        } else {
            let w = sample_cosine_hemisphere(u2);
            (w, cosine_hemisphere_pdf(w.z))
        };
        if pdf_dir == 0.0 || ss.n == Vec3::ZERO {
            return None;
        }
        let l = match &self.image {
            None => self.l.into(),
            // Its uv found by a ray from just off the surface back to the point.
            Some(img) => {
                let off = 1e-3 * shape.bounds().diagonal().length();
                img.le_towards(shape, meshes, ss.p + ss.n * off, ss.p, self.l.into())
            }
        };
        Some(LightLeSample {
            l,
            factor: 1.0,
            p: ss.p,
            p_error: point_error(ss.p),
            w: Frame::from_z(ss.n).from_local(local),
            n: ss.n,
            pdf_pos: 1.0 / self.area,
            pdf_dir,
        })
    }

    /// p_pos = 1/A; p_dir = cos θ/π about the emitting side's normal `n`, |cos θ|/2π when
    /// two-sided.
    fn pdf_le(&self, _: Vec3, n: Vec3, w: Vec3) -> LightLePdf {
        let cos = n.dot(w);
        LightLePdf {
            pos: 1.0 / self.area,
            dir: if self.two_sided {
                cosine_hemisphere_pdf(cos.abs()) / 2.0
            } else {
                cosine_hemisphere_pdf(cos)
            },
        }
    }
}

/// The surface of an area light, as its samples need it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Emitter {
    /// A whole sphere (centre and world radius), sampled by the cone of directions it
    /// subtends from points outside it; by area from inside.
    Sphere {
        /// Centre, world space.
        centre: PackedVec3,
        /// Radius, world space.
        radius: f32,
        /// Normals point inwards (ReverseOrientation).
        flip: bool,
    },
    /// A triangle whose emitting side is the same all over it: sampled uniformly by area.
    /// Its vectors are aligned, not packed: packed ones were read 16 bytes at a time, past
    /// each field, and the light sample stalled on them.
    Triangle {
        /// Vertices, world space.
        p: [Vec3; 3],
        /// Unit geometric normal, oriented as [`Shape::sample_area`] orients it.
        n: Vec3,
    },
    /// Any other shape, sampled through [`Shape::sample_area`].
    Shape,
}

/// The smallest |n·nᵢ|/|nᵢ| of a vertex normal nᵢ for which a triangle's side is taken to be
/// the same all over it: the interpolated normal's dot with n is then a sum of terms of one
/// sign, far larger than its rounding (a few 1e-7), so every sample orients n the same way.
const ONE_SIDE_MIN_COS: f32 = 1e-3;

impl Emitter {
    /// The emitter for `shape` (a primitive of the scene, whose meshes are `meshes`);
    /// `whole_sphere` is its centre and world radius when it is a whole sphere.
    pub fn new(
        shape: &Shape,
        meshes: &[TriangleMesh],
        whole_sphere: Option<(PackedVec3, f32)>,
    ) -> Emitter {
        if let Some((centre, radius)) = whole_sphere {
            let flip = matches!(shape, Shape::Sphere(s) if s.placement.flip_normal);
            return Emitter::Sphere {
                centre,
                radius,
                flip,
            };
        }
        let Shape::Triangle(t) = shape else {
            return Emitter::Shape;
        };
        let Some(mesh) = meshes.get(t.mesh as usize) else {
            return Emitter::Shape;
        };
        // Shape::sample_area's rule: n = (p₀ − p₂) × (p₁ − p₂) normalised, turned towards
        // the interpolated shading normal when the mesh has normals, else flipped by
        // ReverseOrientation.
        let [p0, p1, p2] = t.vertices();
        let mut n = cross(p0 - p2, p1 - p2).normalize_or_zero();
        if !mesh.normals.is_empty() {
            // cos of the angle between n and each vertex normal.
            let cos = mesh.vertices(t.index).map(|v| {
                let nv = mesh.normal(v);
                n.dot(nv) / nv.length()
            });
            if cos.iter().all(|&c| c <= -ONE_SIDE_MIN_COS) {
                n = -n;
            } else if !cos.iter().all(|&c| c >= ONE_SIDE_MIN_COS) {
                // Vertex normals on both sides of the face, nearly in it, or not numbers: the
                // side depends on the point.
                return Emitter::Shape;
            }
        } else if mesh.flip_normal {
            n = -n;
        }
        Emitter::Triangle {
            p: t.p.map(Vec3::from),
            n,
        }
    }
}

/// Samples incident light at `ctx` from the area light on primitive `prim` (radiance `l`,
/// emitting on both sides when `two_sided`, world area `area`, surface `emitter`).
#[allow(clippy::too_many_arguments)]
pub(super) fn sample_area_li(
    prim: u32,
    l: PackedRgb,
    two_sided: bool,
    area: f32,
    emitter: &Emitter,
    ctx: &LightSampleContext,
    u: Vec2,
    shapes: &[Shape],
    meshes: &[TriangleMesh],
) -> Option<LightLiSample> {
    let ss = match emitter {
        Emitter::Triangle { p, n } => triangle_point(p, n, u),
        &Emitter::Sphere {
            centre,
            radius,
            flip,
        } => {
            let c = Vec3::from(centre);
            if let Some(cone) = SphereCone::new(ctx.p, c, radius) {
                return sample_sphere_cone(&cone, flip, l, two_sided, ctx, u, c, radius);
            }
            // From inside: by area.
            shapes[prim as usize].sample_area(u, meshes)?
        }
        Emitter::Shape => shapes[prim as usize].sample_area(u, meshes)?,
    };
    li_from_point(&ss, l, two_sided, area, ctx)
}

/// [`sample_area_li`] for a triangle of vertices `p` and oriented normal `n` (small enough to
/// be inlined where lights are sampled).
#[inline(always)]
pub(super) fn sample_triangle_li(
    p: &[Vec3; 3],
    n: &Vec3,
    l: PackedRgb,
    two_sided: bool,
    area: f32,
    ctx: &LightSampleContext,
    u: Vec2,
) -> Option<LightLiSample> {
    li_from_point(&triangle_point(p, n, u), l, two_sided, area, ctx)
}

/// A point uniform on the triangle of vertices `p` (b₀p₀ + b₁p₁ + b₂p₂, as
/// [`Shape::sample_area`] computes it) and its normal `n`. The vertices are read in place: a
/// copy of the record to the stack, reloaded at other offsets, stalled on store forwarding.
#[inline(always)]
fn triangle_point(p: &[Vec3; 3], n: &Vec3, u: Vec2) -> ShapeSample {
    let [b0, b1, b2] = sample_uniform_triangle(u);
    ShapeSample {
        p: b0 * p[0] + b1 * p[1] + b2 * p[2],
        n: *n,
    }
}

/// Light arriving at `ctx` from the point `ss` of an area light, sampled uniformly by area:
/// its density per solid angle is p_ω = p_A · d² / |cos θ_light| with p_A = 1/A.
///
/// With d = p_light − p and cos θ_light = −n·d/|d|, p_ω = |d|²·|d| / (|n·d| · A): n·d and |d|²
/// side by side, then one √ and one division, rather than waiting on the unit direction for
/// the cosine (the same value up to rounding).
#[inline(always)]
fn li_from_point(
    ss: &ShapeSample,
    l: PackedRgb,
    two_sided: bool,
    area: f32,
    ctx: &LightSampleContext,
) -> Option<LightLiSample> {
    let d = ss.p - ctx.p;
    let d2 = d.length_squared();
    // −|d| cos θ_light.
    let nd = ss.n.dot(d);
    if d2 == 0.0 || nd == 0.0 || (!two_sided && nd > 0.0) {
        return None;
    }
    let len = d2.sqrt();
    let wi = d / len;
    let pdf = d2 * len / (nd.abs() * area);
    pdf.is_finite().then_some(LightLiSample {
        l: l.into(),
        factor: 1.0,
        wi,
        pdf,
        p_light: ss.p,
    })
}

/// Light from a whole sphere (centre `c`, radius `r`, normals inwards when `flip`) seen from
/// outside, as pbrt-v4's `Sphere::Sample` takes it: a direction uniform in the cone the sphere
/// fills (half-angle θmax, sin θmax = r/d), turned straight into the point it meets. With θ
/// the sampled angle from the axis, cos θ = 1 − u₀(1 − cos θmax), the point's angle α from
/// the centre's axis seen from the sphere's centre is cos α = sin²θ/sin θmax +
/// cos θ·√(1 − sin²θ/sin²θmax), and the point is c + r·n with n = −(sin α cos φ, sin α sin φ,
/// cos α) in the frame whose z points from the shading point to the centre (φ = 2πu₁). All in
/// single precision: no ray is traced against the sphere.
#[allow(clippy::too_many_arguments)]
fn sample_sphere_cone(
    cone: &SphereCone,
    flip: bool,
    l: PackedRgb,
    two_sided: bool,
    ctx: &LightSampleContext,
    u: Vec2,
    c: Vec3,
    r: f32,
) -> Option<LightLiSample> {
    let (sin2_theta, cos_theta) = if cone.sin2_theta_max < SMALL_CONE_SIN2 {
        // Small cones: sin²θ ≈ u₀ sin²θmax (the Taylor expansion pbrt-v4 takes).
        let sin2 = cone.sin2_theta_max * u.x;
        (sin2, (1.0 - sin2).sqrt())
    } else {
        let cos = (cone.cos_theta_max - 1.0) * u.x + 1.0;
        (1.0 - cos * cos, cos)
    };
    let cos_alpha = sin2_theta / cone.sin_theta_max
        + cos_theta * (1.0 - sin2_theta / cone.sin2_theta_max).max(0.0).sqrt();
    let sin_alpha = (1.0 - cos_alpha * cos_alpha).max(0.0).sqrt();
    let w = crate::sampling::spherical_direction_turn(sin_alpha, cos_alpha, u.y);
    let outward = -cone.frame.from_local(w);
    let p = c + r * outward;
    let wi = crate::math::normalize(p - ctx.p);
    let n = if flip { -outward } else { outward };
    if !two_sided && n.dot(wi) >= 0.0 {
        return None;
    }
    Some(LightLiSample {
        l: l.into(),
        factor: 1.0,
        wi,
        pdf: cone.pdf(),
        p_light: p,
    })
}

/// Density with which [`sample_area_li`] picks direction `wi` at `ctx` from an area light of
/// world area `area` and surface `emitter`; `hit` is where `wi` meets the light and the
/// geometric normal there.
#[inline]
pub(super) fn area_pdf_li(
    area: f32,
    emitter: &Emitter,
    ctx: &LightSampleContext,
    wi: Vec3,
    hit: Option<(Vec3, Vec3)>,
) -> f32 {
    if let Emitter::Sphere { centre, radius, .. } = *emitter
        && let Some(cone) = SphereCone::new(ctx.p, centre.into(), radius)
    {
        return cone.pdf();
    }
    let Some((p, n)) = hit else { return 0.0 };
    let d2 = (p - ctx.p).length_squared();
    let cos_light = n.dot(wi).abs();
    if cos_light == 0.0 {
        0.0
    } else {
        d2 / (cos_light * area)
    }
}

/// sin²(1.5°): below it, the cone's 1 − cos θmax and its samples are taken by their Taylor
/// expansions (pbrt-v4's threshold), where 1 − √(1 − sin²θmax) would lose its digits.
const SMALL_CONE_SIN2: f32 = 0.000_685_23;

/// The cone of directions in which a sphere is seen from a point outside it.
struct SphereCone {
    /// Frame whose z points at the centre.
    frame: Frame,
    /// sin θmax = r/d, its square, and cos θmax.
    sin_theta_max: f32,
    sin2_theta_max: f32,
    cos_theta_max: f32,
}

impl SphereCone {
    /// `None` when `p` is inside the sphere (or so close that the cone is the hemisphere).
    fn new(p: Vec3, c: Vec3, r: f32) -> Option<SphereCone> {
        let d2 = (c - p).length_squared();
        let r2 = r * r;
        if d2 <= r2 * 1.0001 {
            return None;
        }
        let d = d2.sqrt();
        let sin_theta_max = r / d;
        let sin2_theta_max = sin_theta_max * sin_theta_max;
        Some(SphereCone {
            frame: Frame::from_z((c - p) / d),
            sin_theta_max,
            sin2_theta_max,
            cos_theta_max: (1.0 - sin2_theta_max).max(0.0).sqrt(),
        })
    }

    /// The density of a direction uniform in the cone, 1/(2π(1 − cos θmax)), with
    /// 1 − cos θmax ≈ sin²θmax/2 for small cones.
    fn pdf(&self) -> f32 {
        let one_minus_cos = if self.sin2_theta_max < SMALL_CONE_SIN2 {
            self.sin2_theta_max / 2.0
        } else {
            1.0 - self.cos_theta_max
        };
        1.0 / (2.0 * PI * one_minus_cos)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::shape::Triangle;
    use std::f32::consts::PI;

    /// The triangle (0, 0, 0), (2, 0, 0), (0, 2, 0) of a mesh with these vertex normals (none
    /// when empty) and orientation; its geometric normal (p₀ − p₂) × (p₁ − p₂) is +z.
    fn triangle(normals: &[[f32; 3]], flip: bool) -> (Shape, TriangleMesh) {
        let p = [
            PackedVec3::ZERO,
            PackedVec3::new(2.0, 0.0, 0.0),
            PackedVec3::new(0.0, 2.0, 0.0),
        ];
        let mesh = TriangleMesh {
            positions: p.to_vec(),
            normals: normals.iter().map(|&n| PackedVec3::from(n)).collect(),
            indices: vec![0, 1, 2],
            flip_normal: flip,
            ..Default::default()
        };
        let tri = Shape::Triangle(Triangle {
            p,
            mesh: 0,
            index: 0,
        });
        (tri, mesh)
    }

    /// Light samples of the emitter prepared for `shape` and of the generic path through
    /// `Shape::sample_area`, from points on both sides, for a grid of u.
    fn samples_of_both(shape: &Shape, mesh: &TriangleMesh, two_sided: bool) -> usize {
        let meshes = std::slice::from_ref(mesh);
        let shapes = std::slice::from_ref(shape);
        let prepared = Emitter::new(shape, meshes, None);
        let l = PackedRgb::new(1.0, 2.0, 3.0);
        let mut some = 0;
        for p in [Vec3::new(0.3, 0.4, 1.5), Vec3::new(0.5, -0.2, -2.0)] {
            let ctx = LightSampleContext {
                p,
                n: Vec3::Z,
                ns: Vec3::Z,
            };
            for i in 0..16 {
                for j in 0..16 {
                    let u = Vec2::new((i as f32 + 0.3) / 16.0, (j as f32 + 0.7) / 16.0);
                    let sample = |e: &Emitter| {
                        sample_area_li(0, l, two_sided, 2.0, e, &ctx, u, shapes, meshes)
                            .map(|s| (s.l, s.wi, s.pdf.to_bits(), s.p_light))
                    };
                    let (got, want) = (sample(&prepared), sample(&Emitter::Shape));
                    assert_eq!(got, want, "u {u:?} from {p:?}");
                    some += usize::from(got.is_some());
                }
            }
        }
        some
    }

    #[test]
    fn prepared_triangles_sample_the_bits_of_the_shape() {
        // No vertex normals: +z, or −z when the mesh is reversed; the light is seen from the
        // point above, or below.
        for flip in [false, true] {
            let (tri, mesh) = triangle(&[], flip);
            let e = Emitter::new(&tri, std::slice::from_ref(&mesh), None);
            let want = if flip { -Vec3::Z } else { Vec3::Z };
            assert!(
                matches!(e, Emitter::Triangle { n, .. } if n == want),
                "{e:?}"
            );
            assert_eq!(samples_of_both(&tri, &mesh, false), 256);
            assert_eq!(samples_of_both(&tri, &mesh, true), 512);
        }
        // Vertex normals all on the −z side turn the normal over; ReverseOrientation is then
        // ignored, as Triangle::interaction ignores it.
        let down = [[0.1, 0.0, -1.0], [0.0, 0.2, -1.0], [0.0, 0.0, -3.0]];
        for flip in [false, true] {
            let (tri, mesh) = triangle(&down, flip);
            let e = Emitter::new(&tri, std::slice::from_ref(&mesh), None);
            assert!(matches!(e, Emitter::Triangle { n, .. } if n == -Vec3::Z));
            assert_eq!(samples_of_both(&tri, &mesh, false), 256);
        }
    }

    #[test]
    fn triangle_samples_have_the_solid_angle_density_of_their_point() {
        // The triangle of area 2 in z = 0 facing +z, lit from (0.3, 0.4, 1.5): each sample's
        // pdf is d²/(|cos θ_light|·A) and wi the unit vector to its point, worked out here
        // from the point the sample reports; from below, a one-sided light gives nothing.
        let (tri, mesh) = triangle(&[], false);
        let e = Emitter::new(&tri, std::slice::from_ref(&mesh), None);
        let p = Vec3::new(0.3, 0.4, 1.5);
        let ctx = LightSampleContext {
            p,
            n: -Vec3::Z,
            ns: -Vec3::Z,
        };
        let below = LightSampleContext { p: -p, ..ctx };
        let l = PackedRgb::ONE;
        for (a, b) in [(0.1, 0.2), (0.5, 0.5), (0.9, 0.05), (0.33, 0.77)] {
            let u = Vec2::new(a, b);
            let s = sample_area_li(0, l, false, 2.0, &e, &ctx, u, &[], &[]).expect("lit");
            let d = Vec3::from(s.p_light) - p;
            assert!(Vec3::from(s.p_light).z == 0.0);
            let cos = (d.z / d.length()).abs() as f64;
            let want = d.length_squared() as f64 / (cos * 2.0);
            assert!(
                (s.pdf as f64 - want).abs() < 1e-6 * want,
                "{} vs {want}",
                s.pdf
            );
            assert!((s.wi - d / d.length()).length() < 1e-6);
            assert!(sample_area_li(0, l, false, 2.0, &e, &below, u, &[], &[]).is_none());
            assert!(sample_area_li(0, l, true, 2.0, &e, &below, u, &[], &[]).is_some());
        }
    }

    #[test]
    fn triangles_whose_side_varies_keep_the_generic_path() {
        // One vertex normal below the face, two above: the side depends on the point, so the
        // sample goes through the mesh (and lights from both sides, part of the triangle each).
        let mixed = [[0.0, 0.0, 1.0], [0.0, 0.0, 1.0], [0.0, 0.0, -1.0]];
        let (tri, mesh) = triangle(&mixed, false);
        assert_eq!(
            Emitter::new(&tri, std::slice::from_ref(&mesh), None),
            Emitter::Shape
        );
        let lit = samples_of_both(&tri, &mesh, false);
        assert!(lit > 256 - 64 && lit < 256 + 64, "{lit}");
        // A vertex normal in the plane of the face: not trusted either.
        let flat = [[0.0, 0.0, 1.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]];
        let (tri, mesh) = triangle(&flat, false);
        assert_eq!(
            Emitter::new(&tri, std::slice::from_ref(&mesh), None),
            Emitter::Shape
        );
    }

    #[test]
    fn a_reversed_sphere_lights_only_its_inside_unless_two_sided() {
        use crate::math::Transform;
        use crate::shape::{Placement, Sphere};
        let c = Vec3::new(0.0, 0.0, 5.0);
        let ctx = LightSampleContext {
            p: Vec3::ZERO,
            n: Vec3::Z,
            ns: Vec3::Z,
        };
        for reverse in [false, true] {
            let placement = Placement::new(Transform::translate(c), reverse);
            let sphere = Shape::Sphere(Box::new(Sphere::new(placement, 1.0, -1.0, 1.0, 360.0)));
            let e = Emitter::new(&sphere, &[], Some((c.into(), 1.0)));
            assert!(matches!(e, Emitter::Sphere { flip, .. } if flip == reverse));
            let shapes = std::slice::from_ref(&sphere);
            let l = PackedRgb::ONE;
            for two_sided in [false, true] {
                let s = sample_area_li(
                    0,
                    l,
                    two_sided,
                    4.0 * PI,
                    &e,
                    &ctx,
                    Vec2::new(0.3, 0.6),
                    shapes,
                    &[],
                );
                // Seen from outside, the cone of the sphere (sin θmax = 1/5) is sampled.
                assert_eq!(s.is_some(), two_sided || !reverse, "{reverse} {two_sided}");
                if let Some(s) = s {
                    let cos_max = (1.0f32 - 1.0 / 25.0).sqrt();
                    assert!((s.pdf - 1.0 / (2.0 * PI * (1.0 - cos_max))).abs() < 1e-3 * s.pdf);
                    assert!(((Vec3::from(s.p_light) - c).length() - 1.0).abs() < 1e-5);
                }
            }
        }
    }

    #[test]
    fn whole_spheres_and_other_shapes() {
        let (tri, mesh) = triangle(&[], false);
        let c = PackedVec3::new(1.0, 2.0, 3.0);
        assert_eq!(
            Emitter::new(&tri, std::slice::from_ref(&mesh), Some((c, 0.5))),
            Emitter::Sphere {
                centre: c,
                radius: 0.5,
                flip: false
            }
        );
        // A triangle whose mesh is missing is sampled through the shape.
        assert_eq!(Emitter::new(&tri, &[], None), Emitter::Shape);
    }

    #[test]
    fn emitted_rays_carry_the_power_from_either_side() {
        use crate::light::testing::{le_dir_integral, le_pdfs_agree, le_power};
        use crate::math::Transform;
        use crate::shape::{Disk, Placement, Sphere};
        let (tri, mesh) = triangle(&[], true);
        let meshes = std::slice::from_ref(&mesh);
        let sphere = |reverse| {
            let placement = Placement::new(Transform::translate(Vec3::new(0.0, 1.0, 5.0)), reverse);
            Shape::Sphere(Box::new(Sphere::new(placement, 0.5, -0.5, 0.5, 360.0)))
        };
        let disk = Shape::Disk(Box::new(Disk::new(
            Placement::new(Transform::rotate(30.0, Vec3::X).unwrap(), false),
            0.5,
            2.0,
            0.5,
            360.0,
        )));
        let l = PackedRgb::new(1.0, 2.0, 0.5);
        for (name, shape) in [
            ("triangle", tri),
            ("sphere", sphere(false)),
            ("reversed sphere", sphere(true)),
            ("disk", disk),
        ] {
            let shapes = std::slice::from_ref(&shape);
            for two_sided in [false, true] {
                let light = AreaLight::new(0, &shape, meshes, l, two_sided, None).unwrap();
                let phi = le_power(&light, shapes, meshes, 1 << 14);
                let want = light.power();
                assert!(
                    (phi - want).abs() < 0.01 * want,
                    "{name} {two_sided}: {phi} vs {want}"
                );
                le_pdfs_agree(&light, shapes, meshes, 256, 1e-3);
                let s = light
                    .sample_le(Vec2::new(0.3, 0.7), Vec2::new(0.6, 0.2), shapes, meshes)
                    .unwrap();
                let total = le_dir_integral(&light, s.p, s.n, 1 << 16);
                assert!((total - 1.0).abs() < 0.02, "{name} {two_sided}: {total}");
                // One-sided, rays leave on the side the normal faces.
                for i in 0..64 {
                    let u = Vec2::new((i % 8) as f32 / 8.0 + 0.05, (i / 8) as f32 / 8.0 + 0.05);
                    let s = light
                        .sample_le(u, Vec2::new(u.y, u.x), shapes, meshes)
                        .unwrap();
                    assert!(two_sided || s.n.dot(s.w) > 0.0, "{name}: {s:?}");
                }
            }
        }
    }

    #[test]
    fn an_image_light_emits_the_texel_where_its_ray_starts() {
        use crate::image::Image;
        use crate::math::Transform;
        use crate::shape::{Disk, Placement};
        use crate::texture::MipMap;
        use std::sync::Arc;
        // A unit disk: u = φ/2π, v = 1 − r; left half of the image (u < ½) red, right blue.
        let disk = Shape::Disk(Box::new(Disk::new(
            Placement::new(Transform::IDENTITY, false),
            0.0,
            1.0,
            0.0,
            360.0,
        )));
        let img = Image::new(
            2,
            1,
            vec![PackedRgb::new(1.0, 0.0, 0.0), PackedRgb::new(0.0, 0.0, 3.0)],
        )
        .unwrap();
        let image = Box::new(AreaImage {
            mipmap: Arc::new(MipMap::single(Arc::new(img))),
            scale: 2.0,
        });
        let shapes = std::slice::from_ref(&disk);
        let light =
            AreaLight::new(0, &disk, &[], PackedRgb::ONE, false, Some(image.clone())).unwrap();
        assert_eq!(light.constant_colour(), None);
        for i in 0..32 {
            let u = Vec2::new((i as f32 + 0.5) / 32.0, 0.37);
            let s = light
                .sample_le(u, Vec2::new(0.5, 0.5), shapes, &[])
                .unwrap();
            let phi = s.p.y.atan2(s.p.x).rem_euclid(2.0 * PI);
            let uv = Vec2::new(phi / (2.0 * PI), 1.0 - s.p.truncate().length());
            let want = image.le(uv);
            assert!(
                (s.l - want).abs().max_element() < 1e-3,
                "{:?}: {} vs {want}",
                s.p,
                s.l
            );
        }
    }
}

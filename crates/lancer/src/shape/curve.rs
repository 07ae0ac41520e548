//! pbrt-v4's `curve`: cubic Bézier curves with a width, for hair, fur and grass.
//!
//! A curve is a thin surface swept along a cubic Bézier spine p(u), u ∈ [0, 1], its width
//! varying linearly from `width0` to `width1`. Three kinds, as in pbrt:
//! - **flat**: a ribbon that always faces the ray (a billboard);
//! - **ribbon**: a ribbon whose orientation is given by a normal at each end, interpolated by
//!   spherical linear interpolation;
//! - **cylinder**: a flat curve whose normal turns across the width, so that it shades like a
//!   round tube without being one.
//!
//! Intersection follows pbrt (Nakamaru and Ohno's recursive subdivision): the curve is moved
//! to a space where the ray starts at the origin and runs along +z, then split in halves until
//! each piece is close enough to a line segment (the depth comes from the control polygon's
//! second differences), and each segment is tested in the xy plane: is the origin within half
//! the width of the segment, and between the perpendiculars at its ends?
//!
//! Each Bézier segment of a curve is split into 2^`splitdepth` pieces, each a primitive of its
//! own in the BVH, whose bounds are those of the piece's own control points.
//!
//! lancer keeps curves in world space (control points, normals and widths moved once when the
//! scene is built; widths scaled by the transform's mean scale |det M|^(1/3)); this is pbrt's
//! object-space curve exactly for similarity transforms.

use super::hit::{Shading, ShapeHit, ShapeSample, SurfaceInteraction};
use super::kind::{GeometryKind, HeldBytes, Placing, ShapeKind};
use super::mesh::{RuleError, TriangleMesh};
use super::triangle_ray::TriangleRay;
use crate::math::{Bounds3, PackedVec3, Transform, Vec2, Vec3, cross, lerp, normalize};
use crate::ray::Ray;
use std::collections::HashSet;
use std::sync::Arc;

/// How a curve presents itself to rays (pbrt's `type`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CurveType {
    /// A ribbon always facing the ray.
    Flat,
    /// A ribbon oriented by the normals `N` at its ends.
    Ribbon,
    /// A flat curve shaded as a round tube.
    Cylinder,
}

/// The spline basis of a curve's control points (pbrt's `basis`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CurveBasis {
    /// Bézier: degree + 1 points for the first segment, `degree` more for each next one.
    Bezier,
    /// Uniform B-spline: one segment for each run of degree + 1 consecutive points.
    BSpline,
}

/// A curve as a scene describes it, in object space, before it is split into primitives.
#[derive(Clone, Debug, PartialEq)]
pub struct CurveDesc {
    /// Control points (`P`), packed.
    pub points: Vec<PackedVec3>,
    /// Their basis.
    pub basis: CurveBasis,
    /// Polynomial degree: 2 or 3.
    pub degree: u32,
    /// Flat, ribbon or cylinder.
    pub kind: CurveType,
    /// Width at the start of the curve.
    pub width0: f32,
    /// Width at its end.
    pub width1: f32,
    /// Ribbon normals, one per segment boundary (segments + 1); empty for other types.
    pub normals: Vec<PackedVec3>,
    /// Each segment is split into 2^`split_depth` primitives.
    pub split_depth: u32,
}

impl CurveDesc {
    /// The number of spline segments the control points make, or why they make none:
    /// Bézier needs degree + 1 + n·degree points, a B-spline at least degree + 1.
    pub fn segment_count(&self) -> Result<usize, String> {
        let d = self.degree as usize;
        if d != 2 && d != 3 {
            return Err(format!(
                "curve degree {} is not supported (only 2 and 3)",
                self.degree
            ));
        }
        let n = self.points.len();
        match self.basis {
            CurveBasis::Bezier => {
                if n < d + 1 || !(n - 1 - d).is_multiple_of(d) {
                    return Err(format!(
                        "{n} control points for a degree-{d} Bézier curve: {} + k·{d} are required \
                         (k ≥ 0)",
                        d + 1
                    ));
                }
                Ok((n - 1) / d)
            }
            CurveBasis::BSpline => {
                if n < d + 1 {
                    return Err(format!(
                        "{n} control points for a degree-{d} B-spline curve: at least {} are \
                         required",
                        d + 1
                    ));
                }
                Ok(n - d)
            }
        }
    }

    /// Checks the description: point count ([`CurveDesc::segment_count`]), finite values,
    /// non-negative widths, and for ribbons one non-zero normal per segment boundary; the first
    /// rule broken, with the fields it is about. The one place these rules are checked.
    pub fn validate(&self) -> Result<(), RuleError> {
        let segments = self
            .segment_count()
            .map_err(|m| RuleError::on(&["points"], m))?;
        if self.points.iter().any(|p| !p.is_finite()) {
            return Err(RuleError::on(
                &["points"],
                "curve control points must be finite",
            ));
        }
        let ok = |w: f32| w >= 0.0 && w.is_finite();
        let bad_width = if !ok(self.width0) {
            Some(&["width0"])
        } else if !ok(self.width1) {
            Some(&["width1"])
        } else {
            None
        };
        if let Some(field) = bad_width {
            return Err(RuleError::on(
                field,
                format!(
                    "curve widths must be finite and at least 0, got {} and {}",
                    self.width0, self.width1
                ),
            ));
        }
        if self.kind == CurveType::Ribbon {
            if self.normals.len() != segments + 1 {
                return Err(RuleError::on(
                    &["points", "normals"],
                    format!(
                        "a ribbon curve of {segments} segment(s) needs {} normals \"N\", got {}",
                        segments + 1,
                        self.normals.len()
                    ),
                ));
            }
            if self.normals.iter().any(|n| n.try_normalize().is_none()) {
                return Err(RuleError::on(
                    &["normals"],
                    "a ribbon curve's normals \"N\" must be non-zero",
                ));
            }
        }
        Ok(())
    }

    /// The cubic Bézier control points of every segment: quadratics are degree-elevated,
    /// B-splines converted to the Bézier form of the same polynomial pieces.
    pub fn bezier_segments(&self) -> Result<Vec<[Vec3; 4]>, String> {
        let n = self.segment_count()?;
        let d = self.degree as usize;
        let p = |i: usize| Vec3::from(self.points[i]);
        let mut out = Vec::with_capacity(n);
        for seg in 0..n {
            let cubic = match (self.basis, d) {
                (CurveBasis::Bezier, 3) => {
                    let b = 3 * seg;
                    [p(b), p(b + 1), p(b + 2), p(b + 3)]
                }
                (CurveBasis::Bezier, _) => {
                    let b = 2 * seg;
                    elevate([p(b), p(b + 1), p(b + 2)])
                }
                // Uniform cubic B-spline B₀..B₃ → Bézier:
                // P₀ = (B₀ + 4B₁ + B₂)/6, P₁ = (2B₁ + B₂)/3, P₂ = (B₁ + 2B₂)/3,
                // P₃ = (B₁ + 4B₂ + B₃)/6.
                (CurveBasis::BSpline, 3) => {
                    let [b0, b1, b2, b3] = [p(seg), p(seg + 1), p(seg + 2), p(seg + 3)];
                    [
                        (b0 + 4.0 * b1 + b2) / 6.0,
                        (2.0 * b1 + b2) / 3.0,
                        (b1 + 2.0 * b2) / 3.0,
                        (b1 + 4.0 * b2 + b3) / 6.0,
                    ]
                }
                // Uniform quadratic B-spline B₀..B₂ → Bézier:
                // Q₀ = (B₀ + B₁)/2, Q₁ = B₁, Q₂ = (B₁ + B₂)/2; then elevated.
                (CurveBasis::BSpline, _) => {
                    let [b0, b1, b2] = [p(seg), p(seg + 1), p(seg + 2)];
                    elevate([(b0 + b1) * 0.5, b1, (b1 + b2) * 0.5])
                }
            };
            out.push(cubic);
        }
        Ok(out)
    }

    /// The curve's primitives in world space: each segment split into 2^`split_depth` pieces.
    /// Segment i of n spans widths lerp(i/n, w₀, w₁) to lerp((i + 1)/n, w₀, w₁), as in pbrt.
    pub fn curves(
        &self,
        to_world: &Transform,
        reverse_orientation: bool,
    ) -> Result<Vec<Curve>, String> {
        self.validate()?;
        let segments = self.bezier_segments()?;
        let n = segments.len();
        let scale = glam::Mat3::from_mat4(to_world.m).determinant().abs().cbrt();
        let pieces = 1u32 << self.split_depth.min(16);
        let mut out = Vec::with_capacity(n * pieces as usize);
        for (seg, cp) in segments.iter().enumerate() {
            let w = [
                lerp(seg as f32 / n as f32, self.width0, self.width1) * scale,
                lerp((seg + 1) as f32 / n as f32, self.width0, self.width1) * scale,
            ];
            let normals = if self.kind == CurveType::Ribbon {
                Some([
                    to_world.normal(self.normals[seg].into()),
                    to_world.normal(self.normals[seg + 1].into()),
                ])
            } else {
                None
            };
            let common = Arc::new(CurveCommon::new(
                self.kind,
                cp.map(|p| to_world.point(p)),
                w,
                normals,
                reverse_orientation ^ to_world.swaps_handedness(),
            ));
            for i in 0..pieces {
                out.push(Curve {
                    common: common.clone(),
                    u_min: i as f32 / pieces as f32,
                    u_max: (i + 1) as f32 / pieces as f32,
                });
            }
        }
        Ok(out)
    }
}

/// A quadratic Bézier raised to a cubic with the same curve:
/// (Q₀, Q₁, Q₂) → (Q₀, (Q₀ + 2Q₁)/3, (2Q₁ + Q₂)/3, Q₂).
fn elevate(q: [Vec3; 3]) -> [Vec3; 4] {
    [
        q[0],
        (q[0] + 2.0 * q[1]) / 3.0,
        (2.0 * q[1] + q[2]) / 3.0,
        q[2],
    ]
}

/// What the pieces of one Bézier segment share.
#[derive(Clone, Debug, PartialEq)]
pub struct CurveCommon {
    /// Flat, ribbon or cylinder.
    pub kind: CurveType,
    /// The segment's cubic Bézier control points, world space (packed; see [`CurveCommon::cp`]).
    pub cp: [PackedVec3; 4],
    /// Width at u = 0 and u = 1 (world units).
    pub width: [f32; 2],
    /// Ribbon normals at u = 0 and u = 1, unit length (unused by the other types), packed.
    pub n: [PackedVec3; 2],
    /// Angle between the two ribbon normals.
    normal_angle: f32,
    /// 1 / sin(normal_angle).
    inv_sin_normal_angle: f32,
    /// Normals flipped: reverse orientation xor a handedness-swapping transform.
    pub flip_normal: bool,
}

impl CurveCommon {
    /// A segment from world-space control points, widths and (for ribbons) end normals.
    pub fn new(
        kind: CurveType,
        cp: [Vec3; 4],
        width: [f32; 2],
        normals: Option<[Vec3; 2]>,
        flip_normal: bool,
    ) -> CurveCommon {
        let n = normals
            .map(|[a, b]| [a.normalize_or_zero(), b.normalize_or_zero()])
            .unwrap_or([Vec3::Z, Vec3::Z]);
        // The angle between unit vectors, computed without acos' loss near 0 and π:
        // θ = 2·asin(|a − b|/2) (or π − 2·asin(|a + b|/2) past π/2).
        let normal_angle = if n[0].dot(n[1]) < 0.0 {
            std::f32::consts::PI - 2.0 * ((n[0] + n[1]).length() / 2.0).clamp(-1.0, 1.0).asin()
        } else {
            2.0 * ((n[1] - n[0]).length() / 2.0).clamp(-1.0, 1.0).asin()
        };
        CurveCommon {
            kind,
            cp: cp.map(PackedVec3::from),
            width,
            n: n.map(PackedVec3::from),
            normal_angle,
            inv_sin_normal_angle: 1.0 / normal_angle.sin(),
            flip_normal,
        }
    }

    /// The control points, unpacked for computing.
    #[inline]
    pub fn cp(&self) -> [Vec3; 4] {
        self.cp.map(Vec3::from)
    }

    /// Width at u: w(u) = (1 − u)·w₀ + u·w₁.
    #[inline]
    fn width_at(&self, u: f32) -> f32 {
        lerp(u, self.width[0], self.width[1])
    }

    /// The ribbon normal at u by spherical linear interpolation:
    /// n(u) = (sin((1 − u)θ)·n₀ + sin(uθ)·n₁) / sin θ, θ the angle between n₀ and n₁.
    #[inline]
    fn ribbon_normal(&self, u: f32) -> Vec3 {
        if self.normal_angle == 0.0 {
            return self.n[0].into();
        }
        let s0 = ((1.0 - u) * self.normal_angle).sin() * self.inv_sin_normal_angle;
        let s1 = (u * self.normal_angle).sin() * self.inv_sin_normal_angle;
        s0 * Vec3::from(self.n[0]) + s1 * Vec3::from(self.n[1])
    }
}

/// One piece of a curve segment: the part with `u_min ≤ u ≤ u_max`, a primitive of its own.
#[derive(Clone, Debug, PartialEq)]
pub struct Curve {
    /// The segment it is a piece of.
    pub common: Arc<CurveCommon>,
    /// Start of the piece in the segment's u.
    pub u_min: f32,
    /// End of the piece.
    pub u_max: f32,
}

/// Blossom of a cubic Bézier: de Casteljau with a different parameter at each level;
/// B(u, u, u) = p(u), and B(u₀, u₀, u₀), B(u₀, u₀, u₁), B(u₀, u₁, u₁), B(u₁, u₁, u₁) are the
/// control points of the piece between u₀ and u₁.
fn blossom(cp: &[Vec3; 4], u0: f32, u1: f32, u2: f32) -> Vec3 {
    let a = [
        cp[0].lerp(cp[1], u0),
        cp[1].lerp(cp[2], u0),
        cp[2].lerp(cp[3], u0),
    ];
    let b = [a[0].lerp(a[1], u1), a[1].lerp(a[2], u1)];
    b[0].lerp(b[1], u2)
}

/// The control points of the part of a cubic Bézier between `u0` and `u1`.
pub fn bezier_piece(cp: &[Vec3; 4], u0: f32, u1: f32) -> [Vec3; 4] {
    [
        blossom(cp, u0, u0, u0),
        blossom(cp, u0, u0, u1),
        blossom(cp, u0, u1, u1),
        blossom(cp, u1, u1, u1),
    ]
}

/// A cubic Bézier split at u = ½ (de Casteljau): the seven control points of both halves,
/// the middle one shared.
fn split_half(cp: &[Vec3; 4]) -> [Vec3; 7] {
    let m01 = (cp[0] + cp[1]) * 0.5;
    let m12 = (cp[1] + cp[2]) * 0.5;
    let m23 = (cp[2] + cp[3]) * 0.5;
    let a = (m01 + m12) * 0.5;
    let b = (m12 + m23) * 0.5;
    [cp[0], m01, a, (a + b) * 0.5, b, m23, cp[3]]
}

/// p(u) and p′(u) of a cubic Bézier. p′(u) = 3(b₁ − b₀) with b₀, b₁ the last de Casteljau
/// pair; where that vanishes (coincident control points) the chord p₃ − p₀ stands in.
pub fn bezier_eval(cp: &[Vec3; 4], u: f32) -> (Vec3, Vec3) {
    let a = [
        cp[0].lerp(cp[1], u),
        cp[1].lerp(cp[2], u),
        cp[2].lerp(cp[3], u),
    ];
    let b = [a[0].lerp(a[1], u), a[1].lerp(a[2], u)];
    let d = b[1] - b[0];
    let deriv = if d.length_squared() > 0.0 {
        3.0 * d
    } else {
        cp[3] - cp[0]
    };
    (b[0].lerp(b[1], u), deriv)
}

/// Does the box of `cp` grown by `half_width` overlap the ray's box from (0, 0, 0) to
/// (0, 0, z_max) in ray space?
#[inline]
fn overlaps_ray(cp: &[Vec3], half_width: f32, z_max: f32) -> bool {
    let lo = cp[0].min(cp[1]).min(cp[2]).min(cp[3]) - Vec3::splat(half_width);
    let hi = cp[0].max(cp[1]).max(cp[2]).max(cp[3]) + Vec3::splat(half_width);
    lo.x <= 0.0 && hi.x >= 0.0 && lo.y <= 0.0 && hi.y >= 0.0 && lo.z <= z_max && hi.z >= 0.0
}

/// The nearest hit found so far during the recursion, in ray-space depth.
struct Best {
    z: f32,
    u: f32,
    v: f32,
}

impl Curve {
    /// World-space bounds: the piece's control points (the convex hull property) grown by
    /// half its largest width.
    pub fn bounds(&self) -> Bounds3 {
        let c = &self.common;
        let cp = bezier_piece(&c.cp(), self.u_min, self.u_max);
        let half = 0.5 * c.width_at(self.u_min).max(c.width_at(self.u_max));
        let b = Bounds3::from_point(cp[0])
            .union_point(cp[1])
            .union_point(cp[2])
            .union_point(cp[3]);
        Bounds3::new(b.min - Vec3::splat(half), b.max + Vec3::splat(half))
    }

    /// Approximate area, as pbrt computes it: the length of the piece's control polygon times
    /// its mean width.
    pub fn area(&self) -> f32 {
        let c = &self.common;
        let cp = bezier_piece(&c.cp(), self.u_min, self.u_max);
        let length: f32 = (0..3).map(|i| cp[i].distance(cp[i + 1])).sum();
        length * 0.5 * (c.width_at(self.u_min) + c.width_at(self.u_max))
    }

    /// Nearest hit: the piece moved to ray space (origin at the ray's origin, z along the ray,
    /// y along d × (p₃ − p₀) so that the piece's chord lies along x), then pbrt's recursive
    /// subdivision. The hit's u and v are the surface parameters; t = z/|d|.
    pub fn intersect(&self, ray: &Ray) -> Option<ShapeHit> {
        let c = &*self.common;
        let len = ray.d.length();
        if len == 0.0 || !len.is_finite() {
            return None;
        }
        let max_width = c.width_at(self.u_min).max(c.width_at(self.u_max));
        if max_width <= 0.0 {
            return None;
        }
        let cp_world = bezier_piece(&c.cp(), self.u_min, self.u_max);
        let z = ray.d / len;
        let (x, y) = match cross(ray.d, cp_world[3] - cp_world[0]).try_normalize() {
            Some(y) => (cross(y, z), y),
            None => {
                let f = crate::math::Frame::from_z(z);
                (f.x, f.y)
            }
        };
        let to_ray = |p: Vec3| {
            let q = p - ray.o;
            Vec3::new(q.dot(x), q.dot(y), q.dot(z))
        };
        let cp = cp_world.map(to_ray);
        let z_max = len * ray.t_max;
        if !overlaps_ray(&cp, 0.5 * max_width, z_max) {
            return None;
        }
        // Subdivision depth (pbrt): a cubic's distance to its chord after r halvings is
        // bounded by √2·6·L₀ / (8·4^r), L₀ the largest second difference of the control
        // points; r is chosen to bring it below ε = w/20.
        let mut l0 = 0.0f32;
        for i in 0..2 {
            let dd = (cp[i] - 2.0 * cp[i + 1] + cp[i + 2]).abs();
            l0 = l0.max(dd.max_element());
        }
        let mut depth = 0;
        if l0 > 0.0 {
            let eps = c.width[0].max(c.width[1]) * 0.05;
            let r = std::f32::consts::SQRT_2 * 6.0 * l0 / (8.0 * eps);
            let log2 = if r >= 1.0 { r.log2().floor() as i32 } else { 0 };
            depth = (log2 / 2).clamp(0, 10);
        }
        let mut best = Best {
            z: z_max,
            u: 0.0,
            v: 0.0,
        };
        let mut found = false;
        self.recurse(&cp, self.u_min, self.u_max, depth, z, &mut best, &mut found);
        found.then(|| ShapeHit {
            t: best.z / len,
            u: best.u,
            v: best.v,
        })
    }

    /// Halves `cp` (spanning `u0..u1`) `depth` more times, skipping halves whose boxes miss
    /// the ray, then tests the ray against the remaining near-straight pieces.
    #[allow(clippy::too_many_arguments)]
    fn recurse(
        &self,
        cp: &[Vec3; 4],
        u0: f32,
        u1: f32,
        depth: i32,
        dir: Vec3,
        best: &mut Best,
        found: &mut bool,
    ) {
        let c = &*self.common;
        if depth > 0 {
            let split = split_half(cp);
            let um = 0.5 * (u0 + u1);
            let us = [u0, um, u1];
            for seg in 0..2 {
                let part = [
                    split[3 * seg],
                    split[3 * seg + 1],
                    split[3 * seg + 2],
                    split[3 * seg + 3],
                ];
                let half = 0.5 * c.width_at(us[seg]).max(c.width_at(us[seg + 1]));
                if overlaps_ray(&part, half, best.z) {
                    self.recurse(&part, us[seg], us[seg + 1], depth - 1, dir, best, found);
                }
            }
            return;
        }
        // The ray (the origin of the xy plane) must lie past the perpendicular to the tangent
        // at the start, (p₁ − p₀)·(−p₀) ≥ 0, and before the one at the end, (p₂ − p₃)·(−p₃) ≥ 0.
        let xy = |p: Vec3| Vec2::new(p.x, p.y);
        let (p0, p1, p2, p3) = (xy(cp[0]), xy(cp[1]), xy(cp[2]), xy(cp[3]));
        if (p1 - p0).dot(-p0) < 0.0 || (p2 - p3).dot(-p3) < 0.0 {
            return;
        }
        // The segment's parameter w of the point closest to the origin:
        // w = (−p₀)·(p₃ − p₀) / |p₃ − p₀|².
        let chord = p3 - p0;
        let denom = chord.length_squared();
        if denom == 0.0 {
            return;
        }
        let w = (-p0).dot(chord) / denom;
        let u = lerp(w, u0, u1).clamp(u0, u1);
        let mut hit_width = c.width_at(u);
        if c.kind == CurveType::Ribbon {
            // A ribbon seen at an angle looks narrower: w·|n(u)·d̂|.
            hit_width *= c.ribbon_normal(u).dot(dir).abs();
        }
        let (pc, dpcdw) = bezier_eval(cp, w.clamp(0.0, 1.0));
        let dist2 = pc.x * pc.x + pc.y * pc.y;
        if dist2 > hit_width * hit_width * 0.25 {
            return;
        }
        if pc.z <= 0.0 || pc.z >= best.z {
            return;
        }
        // v = ½ ± distance/width, the sign given by the side of the curve the ray passes:
        // the 2D cross product p′ × (−pc).
        let dist = dist2.sqrt();
        let edge = dpcdw.x * -pc.y + pc.x * dpcdw.y;
        let v = if edge > 0.0 {
            0.5 + dist / hit_width
        } else {
            0.5 - dist / hit_width
        };
        *best = Best { z: pc.z, u, v };
        *found = true;
    }

    /// Full interaction: p on the ray, ∂p/∂u = p′(u) of the segment, and ∂p/∂v across the
    /// width: for ribbons normalize(n(u) × ∂p/∂u)·w; for flat curves the direction in the plane
    /// facing the ray, normalize(d̂ × ∂p/∂u)·w; for cylinders that direction turned by
    /// −θ = −lerp(v, −90°, 90°) about ∂p/∂u (Rodrigues: a·cos φ + (k × a)·sin φ, a ⟂ k), which
    /// makes the normal n = normalize(∂p/∂u × ∂p/∂v) sweep half a turn across the curve.
    /// The error bound is pbrt's: the width, on every axis.
    pub fn interaction(&self, ray: &Ray, hit: &ShapeHit) -> SurfaceInteraction {
        let c = &*self.common;
        let (u, v) = (hit.u, hit.v);
        let dir = normalize(ray.d);
        let (_, dpdu) = bezier_eval(&c.cp(), u);
        let mut hit_width = c.width_at(u);
        let dpdv = if c.kind == CurveType::Ribbon {
            let n = c.ribbon_normal(u);
            hit_width *= n.dot(dir).abs();
            cross(n, dpdu).normalize_or_zero() * hit_width
        } else {
            let plane = cross(dir, dpdu).normalize_or_zero() * hit_width;
            if c.kind == CurveType::Cylinder {
                let phi = -lerp(v, -90.0f32, 90.0).to_radians();
                let k = dpdu.normalize_or_zero();
                plane * phi.cos() + cross(k, plane) * phi.sin()
            } else {
                plane
            }
        };
        let mut n = cross(dpdu, dpdv).normalize_or_zero();
        if c.flip_normal {
            n = -n;
        }
        SurfaceInteraction {
            p: ray.at(hit.t),
            p_error: Vec3::splat(hit_width),
            n,
            uv: Vec2::new(u, v),
            dpdu,
            dpdv,
            shading: Shading { n, dpdu, dpdv },
            wo: -dir,
            t: hit.t,
            time: 0.0,
        }
    }
}

/// pbrt's `curve` as a scene gives it, shared by its copies.
impl GeometryKind for Arc<CurveDesc> {
    type Prim = Curve;

    fn pbrt_name(&self) -> &'static str {
        "curve"
    }

    /// [`CurveDesc::validate`].
    fn validate(&self) -> Result<(), RuleError> {
        CurveDesc::validate(self)
    }

    fn emitter_refusal(&self) -> Option<&'static str> {
        Some("a curve cannot be an area light (pbrt-v4 cannot sample curves either)")
    }

    /// Its pieces ([`CurveDesc::curves`]).
    fn build(&self, at: &mut Placing<'_>, out: &mut impl Extend<Curve>) -> Result<(), String> {
        out.extend(self.curves(&at.to_world, at.reverse_orientation)?);
        Ok(())
    }
}

/// A piece of a curve: pbrt's approximate area, but no area sampling (pbrt-v4 has none), so
/// it cannot emit.
impl ShapeKind for Curve {
    fn bounds(&self) -> Bounds3 {
        Curve::bounds(self)
    }

    #[inline]
    fn intersect(&self, ray: &Ray, _: &TriangleRay) -> Option<ShapeHit> {
        Curve::intersect(self, ray)
    }

    fn interaction(&self, ray: &Ray, hit: &ShapeHit, _: &[TriangleMesh]) -> SurfaceInteraction {
        Curve::interaction(self, ray, hit)
    }

    fn area(&self) -> f32 {
        Curve::area(self)
    }

    fn sample_area(&self, _: Vec2, _: &[TriangleMesh]) -> Option<ShapeSample> {
        None
    }

    /// The segment its pieces share, once.
    fn held_bytes(&self, seen: &mut HashSet<usize>) -> HeldBytes {
        let common = Arc::as_ptr(&self.common) as usize;
        HeldBytes {
            primitive: if seen.insert(common) {
                size_of_val(&*self.common)
            } else {
                0
            },
            meshes: 0,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn desc(points: Vec<Vec3>, basis: CurveBasis, degree: u32) -> CurveDesc {
        CurveDesc {
            points: points.into_iter().map(PackedVec3::from).collect(),
            basis,
            degree,
            kind: CurveType::Flat,
            width0: 0.1,
            width1: 0.1,
            normals: vec![],
            split_depth: 3,
        }
    }

    #[test]
    fn control_point_counts() {
        let pts = |n: usize| (0..n).map(|i| Vec3::splat(i as f32)).collect::<Vec<_>>();
        assert_eq!(desc(pts(4), CurveBasis::Bezier, 3).segment_count(), Ok(1));
        assert_eq!(desc(pts(7), CurveBasis::Bezier, 3).segment_count(), Ok(2));
        assert!(desc(pts(5), CurveBasis::Bezier, 3).segment_count().is_err());
        assert!(desc(pts(3), CurveBasis::Bezier, 3).segment_count().is_err());
        assert_eq!(desc(pts(5), CurveBasis::Bezier, 2).segment_count(), Ok(2));
        assert_eq!(desc(pts(6), CurveBasis::BSpline, 3).segment_count(), Ok(3));
        assert!(
            desc(pts(3), CurveBasis::BSpline, 3)
                .segment_count()
                .is_err()
        );
        assert!(desc(pts(4), CurveBasis::Bezier, 4).segment_count().is_err());
        let mut ribbon = desc(pts(7), CurveBasis::Bezier, 3);
        ribbon.kind = CurveType::Ribbon;
        assert!(ribbon.validate().is_err());
        ribbon.normals = vec![PackedVec3::Z; 3];
        assert!(ribbon.validate().is_ok());
    }

    /// The Bézier pieces a B-spline or a quadratic turns into trace the same curve as the
    /// spline evaluated from its own basis functions.
    #[test]
    fn basis_conversion_keeps_the_curve() {
        let pts = vec![
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(1.0, 2.0, 0.5),
            Vec3::new(2.0, -1.0, 1.0),
            Vec3::new(3.0, 1.0, -1.0),
            Vec3::new(4.5, 0.0, 0.2),
        ];
        // Uniform cubic B-spline basis on segment s, t ∈ [0, 1].
        let bspline3 = |s: usize, t: f32| {
            let b = [
                (1.0 - t).powi(3) / 6.0,
                (3.0 * t.powi(3) - 6.0 * t * t + 4.0) / 6.0,
                (-3.0 * t.powi(3) + 3.0 * t * t + 3.0 * t + 1.0) / 6.0,
                t.powi(3) / 6.0,
            ];
            (0..4).map(|i| b[i] * pts[s + i]).sum::<Vec3>()
        };
        let segs = desc(pts.clone(), CurveBasis::BSpline, 3)
            .bezier_segments()
            .unwrap();
        assert_eq!(segs.len(), 2);
        for (s, cp) in segs.iter().enumerate() {
            for k in 0..=10 {
                let t = k as f32 / 10.0;
                let (p, _) = bezier_eval(cp, t);
                assert!((p - bspline3(s, t)).length() < 1e-5, "segment {s} t {t}");
            }
        }
        // Quadratic B-spline: ½(1 − t)², ½(−2t² + 2t + 1), ½t².
        let bspline2 = |s: usize, t: f32| {
            0.5 * (1.0 - t).powi(2) * pts[s]
                + 0.5 * (-2.0 * t * t + 2.0 * t + 1.0) * pts[s + 1]
                + 0.5 * t * t * pts[s + 2]
        };
        let segs = desc(pts.clone(), CurveBasis::BSpline, 2)
            .bezier_segments()
            .unwrap();
        assert_eq!(segs.len(), 3);
        for (s, cp) in segs.iter().enumerate() {
            for k in 0..=10 {
                let t = k as f32 / 10.0;
                assert!((bezier_eval(cp, t).0 - bspline2(s, t)).length() < 1e-5);
            }
        }
        // Quadratic Bézier: (1 − t)²Q₀ + 2t(1 − t)Q₁ + t²Q₂.
        let segs = desc(pts.clone(), CurveBasis::Bezier, 2)
            .bezier_segments()
            .unwrap();
        for (s, cp) in segs.iter().enumerate() {
            let q = &pts[2 * s..2 * s + 3];
            for k in 0..=10 {
                let t = k as f32 / 10.0;
                let want = (1.0 - t).powi(2) * q[0] + 2.0 * t * (1.0 - t) * q[1] + t * t * q[2];
                assert!((bezier_eval(cp, t).0 - want).length() < 1e-5);
            }
        }
    }

    #[test]
    fn pieces_and_halves_follow_the_curve() {
        let cp = [
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(1.0, 3.0, 0.0),
            Vec3::new(2.0, -2.0, 1.0),
            Vec3::new(3.0, 0.5, 0.0),
        ];
        let piece = bezier_piece(&cp, 0.25, 0.75);
        let halves = split_half(&cp);
        let (left, right) = (
            [halves[0], halves[1], halves[2], halves[3]],
            [halves[3], halves[4], halves[5], halves[6]],
        );
        for k in 0..=8 {
            let s = k as f32 / 8.0;
            let p = bezier_eval(&cp, 0.25 + 0.5 * s).0;
            assert!((bezier_eval(&piece, s).0 - p).length() < 1e-5);
            assert!((bezier_eval(&left, s).0 - bezier_eval(&cp, 0.5 * s).0).length() < 1e-5);
            assert!((bezier_eval(&right, s).0 - bezier_eval(&cp, 0.5 + 0.5 * s).0).length() < 1e-5);
        }
        // p′ against a central difference.
        let (_, d) = bezier_eval(&cp, 0.3);
        let fd = (bezier_eval(&cp, 0.301).0 - bezier_eval(&cp, 0.299).0) / 0.002;
        assert!((d - fd).length() < 1e-2 * d.length());
    }

    /// A straight flat curve along x from 0 to 3, 0.2 wide (control points evenly spaced, so
    /// p(u) = (3u, 0, 0) and p′(u) = (3, 0, 0)).
    fn straight() -> Curve {
        let cp = [0.0, 1.0, 2.0, 3.0].map(|x| Vec3::new(x, 0.0, 0.0));
        Curve {
            common: Arc::new(CurveCommon::new(
                CurveType::Flat,
                cp,
                [0.2, 0.2],
                None,
                false,
            )),
            u_min: 0.0,
            u_max: 1.0,
        }
    }

    #[test]
    fn a_flat_curve_is_hit_within_half_its_width() {
        // From (1.5, 0.05, 5) down: the curve point nearest the ray is u = ½, 0.05 off the
        // axis (< 0.1), 5 along the ray. In ray space (x, y, z) = (+x, −y, −z) the ray passes
        // on the side where p′ × (−pc) = 3·(−0.05) < 0: v = ½ − 0.05/0.2 = ¼.
        let c = straight();
        let ray = Ray::new(Vec3::new(1.5, 0.05, 5.0), -Vec3::Z);
        let h = c.intersect(&ray).unwrap();
        assert!((h.t - 5.0).abs() < 1e-5, "t {}", h.t);
        assert!(
            (h.u - 0.5).abs() < 1e-5 && (h.v - 0.25).abs() < 1e-5,
            "{h:?}"
        );
        let si = c.interaction(&ray, &h);
        assert!((si.p - Vec3::new(1.5, 0.05, 0.0)).length() < 1e-5);
        // ∂p/∂v = normalize(d̂ × p′)·w = (0, −0.2, 0), and n ∝ p′ × (d̂ × p′) = |p′|²·d̂ (as
        // p′ ⟂ d̂): a flat curve's normal runs along the ray, (0, 0, −1) here.
        assert!((si.dpdu - Vec3::new(3.0, 0.0, 0.0)).length() < 1e-5);
        assert!((si.dpdv - Vec3::new(0.0, -0.2, 0.0)).length() < 1e-6);
        assert!((si.n + Vec3::Z).length() < 1e-6, "{}", si.n);
        // 0.15 off the axis is beyond half the width; past the end (x = 3.2) too.
        assert!(
            c.intersect(&Ray::new(Vec3::new(1.5, 0.15, 5.0), -Vec3::Z))
                .is_none()
        );
        assert!(
            c.intersect(&Ray::new(Vec3::new(3.2, 0.0, 5.0), -Vec3::Z))
                .is_none()
        );
        // pbrt's area: control polygon length 3 × width 0.2.
        assert!((c.area() - 0.6).abs() < 1e-6);
    }
}

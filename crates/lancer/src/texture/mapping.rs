//! Texture mappings: where on a texture a surface point lands, as pbrt-v4's `TextureMapping2D`
//! (`uv`, `spherical`, `cylindrical`, `planar`) and `TextureMapping3D` (the point in texture
//! space). Texture space is the coordinate system current at the `Texture` directive: the
//! mappings hold `texture_from_world`, the inverse of that transformation.

use super::mipmap::StFootprint;
use crate::math::{INV_2PI, INV_PI, PI, Transform, Vec2, Vec3, safe_acos};

/// Where a texture is looked up.
#[derive(Clone, Copy, Debug, Default)]
pub struct TexCoord {
    /// Surface (u, v).
    pub uv: Vec2,
    /// World-space position.
    pub p: Vec3,
    /// Geometric normal, world space (for `directionmix`).
    pub n: Vec3,
    /// The footprint: ∂p/∂x and ∂p/∂y, the change of the point from one pixel to the next
    /// (zero when unknown: filters then read the finest texels).
    pub dpdx: Vec3,
    /// ∂p/∂y.
    pub dpdy: Vec3,
    /// ∂u/∂x.
    pub dudx: f32,
    /// ∂u/∂y.
    pub dudy: f32,
    /// ∂v/∂x.
    pub dvdx: f32,
    /// ∂v/∂y.
    pub dvdy: f32,
}

impl TexCoord {
    /// Where textures are looked up at a surface point, without a footprint: its (u, v),
    /// position and geometric normal.
    pub fn at(si: &crate::shape::SurfaceInteraction) -> TexCoord {
        TexCoord {
            uv: si.uv,
            p: si.p,
            n: si.n,
            ..TexCoord::default()
        }
    }

    /// This point with the footprint ∂p/∂x, ∂p/∂y and the (u, v) derivatives it gives on a
    /// surface with tangents ∂p/∂u, ∂p/∂v (pbrt-v4's `ComputeDifferentials`): ∂p/∂x ≈
    /// ∂p/∂u·∂u/∂x + ∂p/∂v·∂v/∂x solved in the least-squares sense,
    /// (AᵀA)⁻¹Aᵀ·∂p/∂x with A = [∂p/∂u ∂p/∂v]; each derivative clamped to ±10⁸, 0 when the
    /// system is singular.
    pub fn with_footprint(self, dpdu: Vec3, dpdv: Vec3, dpdx: Vec3, dpdy: Vec3) -> TexCoord {
        let (a00, a01, a11) = (dpdu.dot(dpdu), dpdu.dot(dpdv), dpdv.dot(dpdv));
        let inv_det = 1.0 / (a00 * a11 - a01 * a01);
        let inv_det = if inv_det.is_finite() { inv_det } else { 0.0 };
        let (b0x, b1x) = (dpdu.dot(dpdx), dpdv.dot(dpdx));
        let (b0y, b1y) = (dpdu.dot(dpdy), dpdv.dot(dpdy));
        let fix = |v: f32| {
            if v.is_finite() {
                v.clamp(-1e8, 1e8)
            } else {
                0.0
            }
        };
        TexCoord {
            dpdx,
            dpdy,
            dudx: fix((a11 * b0x - a01 * b1x) * inv_det),
            dvdx: fix((a00 * b1x - a01 * b0x) * inv_det),
            dudy: fix((a11 * b0y - a01 * b1y) * inv_det),
            dvdy: fix((a00 * b1y - a01 * b0y) * inv_det),
            ..self
        }
    }
}

/// The (u, v) mapping of pbrt's textures: `(su·u + du, sv·v + dv)`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct UvMapping {
    /// Scale of u (`uscale`).
    pub su: f32,
    /// Scale of v (`vscale`).
    pub sv: f32,
    /// Offset of u (`udelta`).
    pub du: f32,
    /// Offset of v (`vdelta`).
    pub dv: f32,
}

impl Default for UvMapping {
    fn default() -> Self {
        UvMapping {
            su: 1.0,
            sv: 1.0,
            du: 0.0,
            dv: 0.0,
        }
    }
}

impl UvMapping {
    /// The mapped texture coordinates.
    #[inline]
    pub fn map(&self, uv: Vec2) -> Vec2 {
        Vec2::new(self.su * uv.x + self.du, self.sv * uv.y + self.dv)
    }
}

/// A 2D texture mapping: surface point → texture coordinates (s, t).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Mapping2D {
    /// The surface's own (u, v), scaled and offset.
    Uv(UvMapping),
    /// Around texture space's origin: `s = θ/π` (θ from texture +z), `t = φ/2π`, of the
    /// direction from the origin to the point.
    Spherical {
        /// World → texture space.
        texture_from_world: Transform,
    },
    /// Around texture space's z axis: `s = (π + atan2(y, x))/2π`, `t = z`.
    Cylindrical {
        /// World → texture space.
        texture_from_world: Transform,
    },
    /// Projection on two vectors: `s = ds + p·vs`, `t = dt + p·vt` (p in texture space).
    Planar {
        /// World → texture space.
        texture_from_world: Transform,
        /// `v1`.
        vs: Vec3,
        /// `v2`.
        vt: Vec3,
        /// `udelta`.
        ds: f32,
        /// `vdelta`.
        dt: f32,
    },
}

impl Default for Mapping2D {
    fn default() -> Self {
        Mapping2D::Uv(UvMapping::default())
    }
}

impl From<UvMapping> for Mapping2D {
    fn from(m: UvMapping) -> Self {
        Mapping2D::Uv(m)
    }
}

impl Mapping2D {
    /// The texture coordinates (s, t) of `tc`.
    #[inline]
    pub fn map(&self, tc: &TexCoord) -> Vec2 {
        match self {
            Mapping2D::Uv(m) => m.map(tc.uv),
            Mapping2D::Spherical { texture_from_world } => {
                let v = texture_from_world.point(tc.p).normalize_or_zero();
                let phi = v.y.atan2(v.x);
                let phi = if phi < 0.0 { phi + 2.0 * PI } else { phi };
                Vec2::new(safe_acos(v.z) * INV_PI, phi * INV_2PI)
            }
            Mapping2D::Cylindrical { texture_from_world } => {
                let p = texture_from_world.point(tc.p);
                Vec2::new((PI + p.y.atan2(p.x)) * INV_2PI, p.z)
            }
            Mapping2D::Planar {
                texture_from_world,
                vs,
                vt,
                ds,
                dt,
            } => {
                let p = texture_from_world.point(tc.p);
                Vec2::new(ds + p.dot(*vs), dt + p.dot(*vt))
            }
        }
    }
}

impl Mapping2D {
    /// The texture coordinates of `tc` with their screen-space derivatives, by the chain rule
    /// through the mapping (pbrt-v4's `TextureMapping2D::Map`): `uv` scales ∂u, ∂v by su, sv;
    /// the others take `∂s/∂x = ∇s · ∂p/∂x` with ∂p/∂x in texture space.
    #[inline]
    pub fn map_footprint(&self, tc: &TexCoord) -> StFootprint {
        let st = self.map(tc);
        let grads = |tfw: &Transform, ds: Vec3, dt: Vec3| {
            let (dpdx, dpdy) = (tfw.vector(tc.dpdx), tfw.vector(tc.dpdy));
            StFootprint {
                st,
                dsdx: ds.dot(dpdx),
                dsdy: ds.dot(dpdy),
                dtdx: dt.dot(dpdx),
                dtdy: dt.dot(dpdy),
            }
        };
        let c = match self {
            Mapping2D::Uv(m) => StFootprint {
                st,
                dsdx: m.su * tc.dudx,
                dsdy: m.su * tc.dudy,
                dtdx: m.sv * tc.dvdx,
                dtdy: m.sv * tc.dvdy,
            },
            Mapping2D::Spherical { texture_from_world } => {
                let p = texture_from_world.point(tc.p);
                // ∇(φ/2π) = (−y, x, 0)/(2π(x² + y²)) and
                // ∇(θ/π) = (xz/r, yz/r, −r)/(π(r² + z²)), r = √(x² + y²). pbrt-v4 pairs the
                // first with s and the second with t although s = θ/π, t = φ/2π; lancer
                // follows it, so that the filters see the same footprints.
                let x2y2 = p.x * p.x + p.y * p.y;
                let r = x2y2.sqrt();
                let ds = Vec3::new(-p.y, p.x, 0.0) / (2.0 * PI * x2y2);
                let dt = Vec3::new(p.x * p.z / r, p.y * p.z / r, -r) / (PI * (x2y2 + p.z * p.z));
                grads(texture_from_world, ds, dt)
            }
            Mapping2D::Cylindrical { texture_from_world } => {
                // s = (π + atan2(y, x))/2π: ∇s = (−y, x, 0)/(2π(x² + y²)); t = z: ∇t = ẑ.
                let p = texture_from_world.point(tc.p);
                let ds = Vec3::new(-p.y, p.x, 0.0) / (2.0 * PI * (p.x * p.x + p.y * p.y));
                grads(texture_from_world, ds, Vec3::Z)
            }
            Mapping2D::Planar {
                texture_from_world,
                vs,
                vt,
                ..
            } => grads(texture_from_world, *vs, *vt),
        };
        // Degenerate points (the axis of a spherical or cylindrical mapping) give no
        // footprint rather than NaNs.
        let finite = |v: f32| if v.is_finite() { v } else { 0.0 };
        StFootprint {
            st: c.st,
            dsdx: finite(c.dsdx),
            dsdy: finite(c.dsdy),
            dtdx: finite(c.dtdx),
            dtdy: finite(c.dtdy),
        }
    }
}

/// pbrt-v4's 3D mapping (`PointTransformMapping`): the point in texture space.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct Mapping3D {
    /// World → texture space.
    pub texture_from_world: Transform,
}

impl Mapping3D {
    /// The texture-space point of `tc`.
    #[inline]
    pub fn map(&self, tc: &TexCoord) -> Vec3 {
        self.texture_from_world.point(tc.p)
    }

    /// The texture-space point of `tc` with its footprint ∂p/∂x, ∂p/∂y in texture space
    /// (pbrt-v4's `TexCoord3D`).
    #[inline]
    pub fn map_footprint(&self, tc: &TexCoord) -> (Vec3, Vec3, Vec3) {
        let t = &self.texture_from_world;
        (t.point(tc.p), t.vector(tc.dpdx), t.vector(tc.dpdy))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn at(p: Vec3) -> TexCoord {
        TexCoord {
            p,
            ..TexCoord::default()
        }
    }

    fn close(a: Vec2, b: Vec2) -> bool {
        (a - b).abs().max_element() < 1e-5
    }

    #[test]
    fn uv_scales_then_offsets() {
        let m = Mapping2D::Uv(UvMapping {
            su: 2.0,
            sv: 1.5,
            du: 0.25,
            dv: -0.1,
        });
        let tc = TexCoord {
            uv: Vec2::new(0.5, 0.2),
            ..TexCoord::default()
        };
        // (2·0.5 + 0.25, 1.5·0.2 − 0.1) = (1.25, 0.2).
        assert!(close(m.map(&tc), Vec2::new(1.25, 0.2)));
    }

    #[test]
    fn spherical_measures_theta_from_texture_z() {
        let m = Mapping2D::Spherical {
            texture_from_world: Transform::IDENTITY,
        };
        // +z: θ = 0; +x: θ = π/2, φ = 0; +y: φ = π/2 → t = 1/4; −y: φ = 3π/2 → t = 3/4.
        assert!(close(m.map(&at(Vec3::Z * 3.0)), Vec2::new(0.0, 0.0)));
        assert!(close(m.map(&at(Vec3::X)), Vec2::new(0.5, 0.0)));
        assert!(close(m.map(&at(Vec3::Y)), Vec2::new(0.5, 0.25)));
        assert!(close(m.map(&at(-Vec3::Y - Vec3::Z)), Vec2::new(0.75, 0.75)));
        // Texture space moved to (0, 0, 5) by the CTM: the world point (1, 0, 5) is texture +x.
        let moved = Mapping2D::Spherical {
            texture_from_world: Transform::translate(Vec3::new(0.0, 0.0, 5.0)).inverse(),
        };
        assert!(close(
            moved.map(&at(Vec3::new(1.0, 0.0, 5.0))),
            Vec2::new(0.5, 0.0)
        ));
    }

    #[test]
    fn cylindrical_starts_s_at_minus_x_and_t_is_height() {
        let m = Mapping2D::Cylindrical {
            texture_from_world: Transform::scale(Vec3::new(1.0, 1.0, 0.5))
                .unwrap()
                .inverse(),
        };
        // (π + atan2(0, 1))/2π = 1/2 at +x; atan2(1, 0) = π/2 → 3/4 at +y; z = 0.3 / 0.5.
        assert!(close(
            m.map(&at(Vec3::new(1.0, 0.0, 0.3))),
            Vec2::new(0.5, 0.6)
        ));
        assert!(close(
            m.map(&at(Vec3::new(0.0, 2.0, 0.0))),
            Vec2::new(0.75, 0.0)
        ));
        assert!(close(
            m.map(&at(Vec3::new(-1.0, -1e-7, 0.0))),
            Vec2::new(0.0, 0.0)
        ));
    }

    #[test]
    fn planar_projects_on_v1_and_v2() {
        let m = Mapping2D::Planar {
            texture_from_world: Transform::translate(Vec3::new(0.0, 0.5, 0.0)).inverse(),
            vs: Vec3::new(0.9, 0.35, 0.0),
            vt: Vec3::new(-0.35, 0.9, 0.0),
            ds: 0.5,
            dt: 0.4,
        };
        // Texture point (0.2, 0.1, 0): s = 0.5 + 0.18 + 0.035, t = 0.4 − 0.07 + 0.09.
        let st = m.map(&at(Vec3::new(0.2, 0.6, 7.0)));
        assert!(close(st, Vec2::new(0.715, 0.42)), "{st}");
    }

    /// A lookup at `p` with footprint `dpdx`, `dpdy` and (u, v) derivatives.
    fn moving(p: Vec3, dpdx: Vec3, dpdy: Vec3) -> TexCoord {
        TexCoord {
            p,
            dpdx,
            dpdy,
            dudx: 0.1,
            dudy: -0.2,
            dvdx: 0.3,
            dvdy: 0.4,
            ..TexCoord::default()
        }
    }

    #[test]
    fn footprints_follow_the_chain_rule() {
        let tc = moving(
            Vec3::new(1.0, 0.0, 0.3),
            Vec3::new(0.0, 0.01, 0.0),
            Vec3::new(0.0, 0.0, 0.02),
        );
        // uv: ∂s/∂x = su·∂u/∂x …
        let uv = Mapping2D::Uv(UvMapping {
            su: 2.0,
            sv: 3.0,
            du: 0.5,
            dv: 0.0,
        })
        .map_footprint(&tc);
        assert_eq!(
            (uv.dsdx, uv.dsdy, uv.dtdx, uv.dtdy),
            (0.2, -0.4, 0.90000004, 1.2)
        );
        // planar: ∂s/∂x = v1·∂p/∂x, ∂p/∂x taken into texture space (scaled by ½ here).
        let planar = Mapping2D::Planar {
            texture_from_world: Transform::scale(Vec3::splat(2.0)).unwrap().inverse(),
            vs: Vec3::new(0.0, 1.0, 0.0),
            vt: Vec3::new(0.0, 0.0, 1.0),
            ds: 0.0,
            dt: 0.0,
        }
        .map_footprint(&tc);
        let close = |a: f32, b: f32| (a - b).abs() < 1e-7;
        assert!(close(planar.dsdx, 0.005) && close(planar.dtdy, 0.01) && planar.dsdy == 0.0);
        // cylindrical at (1, 0, z): moving 0.01 along y turns by 0.01 rad, s by 0.01/2π; t
        // is z.
        let cyl = Mapping2D::Cylindrical {
            texture_from_world: Transform::IDENTITY,
        }
        .map_footprint(&tc);
        assert!(
            close(cyl.dsdx, 0.01 / (2.0 * PI)) && close(cyl.dtdy, 0.02),
            "{cyl:?}"
        );
        assert!(close(cyl.dtdx, 0.0) && close(cyl.dsdy, 0.0));
        // The same finite difference through `map`.
        let m = Mapping2D::Cylindrical {
            texture_from_world: Transform::IDENTITY,
        };
        let ahead = m.map(&at(tc.p + tc.dpdx)).x - m.map(&at(tc.p)).x;
        assert!((ahead - cyl.dsdx).abs() < 1e-5);
        // spherical at (1, 0, 0): ∇(φ/2π) = (0, 1, 0)/2π goes to s (as pbrt-v4 pairs them),
        // ∇(θ/π) = (0, 0, −1)/π to t.
        let sph = Mapping2D::Spherical {
            texture_from_world: Transform::IDENTITY,
        }
        .map_footprint(&moving(
            Vec3::X,
            Vec3::new(0.0, 0.01, 0.0),
            Vec3::new(0.0, 0.0, 0.02),
        ));
        assert!(
            close(sph.dsdx, 0.01 / (2.0 * PI)) && close(sph.dtdy, -0.02 / PI),
            "{sph:?}"
        );
        // On the axis the gradient is undefined: no footprint rather than NaN.
        let pole = Mapping2D::Spherical {
            texture_from_world: Transform::IDENTITY,
        }
        .map_footprint(&moving(Vec3::Z, Vec3::X, Vec3::Y));
        assert!(pole.dsdx == 0.0 && pole.dtdx == 0.0 && pole.dsdy == 0.0);
    }

    #[test]
    fn uv_derivatives_are_the_least_squares_solution() {
        // ∂p/∂u = (2, 0, 0), ∂p/∂v = (1, 3, 0): ∂p/∂x = 0.1·∂p/∂u + 0.2·∂p/∂v exactly, and
        // ∂p/∂y has a component off the surface (along z) that least squares ignores.
        let (dpdu, dpdv) = (Vec3::new(2.0, 0.0, 0.0), Vec3::new(1.0, 3.0, 0.0));
        let dpdx = 0.1 * dpdu + 0.2 * dpdv;
        let dpdy = -0.05 * dpdu + 0.3 * dpdv + Vec3::new(0.0, 0.0, 0.7);
        let tc = TexCoord::default().with_footprint(dpdu, dpdv, dpdx, dpdy);
        for (got, want) in [
            (tc.dudx, 0.1),
            (tc.dvdx, 0.2),
            (tc.dudy, -0.05),
            (tc.dvdy, 0.3),
        ] {
            assert!((got - want).abs() < 1e-6, "{got} vs {want}");
        }
        assert_eq!((tc.dpdx, tc.dpdy), (dpdx, dpdy));
        // Parallel tangents: no (u, v) footprint.
        let tc = TexCoord::default().with_footprint(dpdu, dpdu, dpdx, dpdy);
        assert_eq!((tc.dudx, tc.dvdx, tc.dudy, tc.dvdy), (0.0, 0.0, 0.0, 0.0));
    }

    #[test]
    fn the_3d_mapping_moves_the_point_into_texture_space() {
        let m = Mapping3D {
            texture_from_world: Transform::scale(Vec3::splat(0.2)).unwrap().inverse(),
        };
        assert!(
            (m.map(&at(Vec3::new(0.2, 0.4, -0.6))) - Vec3::new(1.0, 2.0, -3.0)).length() < 1e-5
        );
    }
}

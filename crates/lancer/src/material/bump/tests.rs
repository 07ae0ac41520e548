//! Bump and normal mapping: the shading frame a height or normal texture gives.

use super::*;
use crate::math::Rgb;
use crate::texture::{
    BilerpTexture, CheckerboardTexture, FloatTexture, Mapping2D, SpectrumTexture,
};

/// A hit on the plane z = 0 at (u, v) = (x, y), ∂p/∂u = x̂, ∂p/∂v = ŷ, n = ẑ.
pub(crate) fn flat(x: f32, y: f32) -> SurfaceInteraction {
    SurfaceInteraction {
        p: Vec3::new(x, y, 0.0),
        p_error: Vec3::ZERO,
        n: Vec3::Z,
        uv: Vec2::new(x, y),
        dpdu: Vec3::X,
        dpdv: Vec3::Y,
        shading: Shading {
            n: Vec3::Z,
            dpdu: Vec3::X,
            dpdv: Vec3::Y,
        },
        wo: Vec3::Z,
        t: 1.0,
        time: 0.0,
    }
}

/// One `bilerp` float texture over (u, v) with corner values `v` (as [`BilerpTexture`] takes
/// them): a height whose slope is the same everywhere.
pub(crate) fn bilerp(v: [f32; 4]) -> Vec<FloatTexture> {
    vec![FloatTexture::Bilerp(BilerpTexture {
        mapping: Mapping2D::default(),
        v,
    })]
}

/// The lookups of the float textures `floats`, with no spectrum textures.
pub(crate) fn floats_only(floats: &[FloatTexture]) -> TextureEval<'_> {
    TextureEval {
        floats,
        spectra: &[],
    }
}

/// The bump frame at `si` with no footprint (steps of [`DELTA`]).
fn bump(tex: &TextureEval, d: FloatTex, si: &SurfaceInteraction) -> Shading {
    let tc = TexCoord {
        uv: si.uv,
        p: si.p,
        n: si.n,
        ..TexCoord::default()
    };
    bump_shading(tex, d, si, &tc, &ShadingDerivatives::flat(si)).unwrap()
}

#[test]
fn the_step_is_half_the_footprint_in_u_and_v() {
    // Height h = 100·u² (bilerp cannot: use a checkerboard of 0 and 1 with cells of
    // 0.01 in u): at u = 0.004 a step of 0.0005 stays in the cell (flat), a footprint with
    // |∂u/∂x| + |∂u/∂y| = 0.016 steps 0.008 into the next cell (a slope of 1/0.008).
    let floats = vec![FloatTexture::Checkerboard(CheckerboardTexture {
        mapping: crate::texture::UvMapping {
            su: 100.0,
            sv: 1.0,
            du: 0.0,
            dv: 0.0,
        }
        .into(),
        tex1: FloatTex::Const(0.0),
        tex2: FloatTex::Const(1.0),
    })];
    let tex = floats_only(&floats);
    let si = flat(0.004, 0.5);
    assert_eq!(bump(&tex, FloatTex::Tex(0), &si).dpdu, Vec3::X);
    let tc = TexCoord {
        uv: si.uv,
        p: si.p,
        n: si.n,
        dudx: 0.01,
        dudy: -0.006,
        ..TexCoord::default()
    };
    let sh = bump_shading(
        &tex,
        FloatTex::Tex(0),
        &si,
        &tc,
        &ShadingDerivatives::flat(&si),
    )
    .unwrap();
    assert!(
        (sh.dpdu - Vec3::new(1.0, 0.0, 125.0)).length() < 1e-3,
        "{}",
        sh.dpdu
    );
    // v had no footprint: its step is still 0.0005, inside the cell.
    assert_eq!(sh.dpdv, Vec3::Y);
}

#[test]
fn bumps_tilt_the_normal_against_the_height_gradient() {
    // Height h(u, v) = 0.1·u + 0.2·v (bilerp 0, 0.2, 0.1, 0.3): the displaced surface
    // (u, v, h) has normal ∝ (−0.1, −0.2, 1).
    let floats = bilerp([0.0, 0.2, 0.1, 0.3]);
    let tex = floats_only(&floats);
    let sh = bump(&tex, FloatTex::Tex(0), &flat(0.3, 0.6));
    let want = normalize(Vec3::new(-0.1, -0.2, 1.0));
    assert!((sh.n - want).length() < 2e-3, "{} vs {want}", sh.n);
    assert!((sh.dpdu - Vec3::new(1.0, 0.0, 0.1)).length() < 2e-3);
    // A constant height leaves the frame as it was.
    let sh = bump(&tex, FloatTex::Const(0.7), &flat(0.3, 0.6));
    assert_eq!((sh.n, sh.dpdu, sh.dpdv), (Vec3::Z, Vec3::X, Vec3::Y));
}

#[test]
fn a_constant_height_moves_the_surface_along_its_turning_normal() {
    // On a sphere of radius 2 (n = p/2, so ∂n/∂u = ∂p/∂u/2), a constant height d = 0.5 makes
    // the sphere of radius 2.5: pbrt-v4's d·∂n/∂u term scales ∂p/∂u by 1 + d/r and leaves
    // the normal alone; a height gradient still tilts it as on a plane.
    let si = flat(0.3, 0.6);
    let tc = TexCoord {
        uv: si.uv,
        p: si.p,
        n: si.n,
        ..TexCoord::default()
    };
    let sd = ShadingDerivatives {
        dpdu: Vec3::X,
        dpdv: Vec3::Y,
        dndu: Vec3::X * 0.5,
        dndv: Vec3::Y * 0.5,
    };
    let tex = floats_only(&[]);
    let sh = bump_shading(&tex, FloatTex::Const(0.5), &si, &tc, &sd).unwrap();
    assert_eq!(
        (sh.dpdu, sh.dpdv, sh.n),
        (Vec3::X * 1.25, Vec3::Y * 1.25, Vec3::Z)
    );
    // The new tangents start from the derivatives' ∂p/∂u, ∂p/∂v, not the interaction's: with
    // ∂p/∂u = 2x̂ and h = 0.1·u, ∂p/∂u' = 2x̂ + 0.1·ẑ.
    let floats = bilerp([0.0, 0.0, 0.1, 0.1]);
    let tex = floats_only(&floats);
    let sd = ShadingDerivatives {
        dpdu: Vec3::X * 2.0,
        dpdv: Vec3::Y,
        dndu: Vec3::ZERO,
        dndv: Vec3::ZERO,
    };
    let sh = bump_shading(&tex, FloatTex::Tex(0), &si, &tc, &sd).unwrap();
    assert!(
        (sh.dpdu - Vec3::new(2.0, 0.0, 0.1)).length() < 2e-3,
        "{}",
        sh.dpdu
    );
}

#[test]
fn bumped_normals_stay_on_the_geometric_side() {
    // The same slope seen from a surface whose normal is −z: ns is flipped to −z's side.
    let floats = bilerp([0.0, 0.0, 0.5, 0.5]);
    let tex = floats_only(&floats);
    let mut si = flat(0.5, 0.5);
    si.n = -Vec3::Z;
    si.shading.n = -Vec3::Z;
    let sh = bump(&tex, FloatTex::Tex(0), &si);
    assert!(sh.n.z < 0.0, "{}", sh.n);
    // dpdu' = x̂ + 0.5·(−ẑ): the slope follows the shading normal.
    assert!(
        (sh.dpdu - Vec3::new(1.0, 0.0, -0.5)).length() < 2e-3,
        "{}",
        sh.dpdu
    );
}

#[test]
fn a_flat_normal_map_keeps_the_frame_and_a_tilted_one_tilts_it() {
    let tilted = normalize(Vec3::new(0.6, 0.0, 0.8));
    let spectra = vec![
        SpectrumTexture::Constant(Rgb::new(0.5, 0.5, 1.0)),
        SpectrumTexture::Constant((tilted + Vec3::ONE) * 0.5),
    ];
    let tex = TextureEval {
        floats: &[],
        spectra: &spectra,
    };
    let mut si = flat(0.2, 0.2);
    si.shading.dpdu = Vec3::X * 2.0;
    si.shading.dpdv = Vec3::Y * 3.0;
    let sh = normal_map_shading(&tex, 0, &si).unwrap();
    assert!((sh.n - Vec3::Z).length() < 1e-6);
    // Lengths of ∂p/∂u and ∂p/∂v are kept.
    assert!((sh.dpdu - Vec3::X * 2.0).length() < 1e-5);
    assert!((sh.dpdv - Vec3::Y * 3.0).length() < 1e-5);
    let sh = normal_map_shading(&tex, 1, &si).unwrap();
    assert!((sh.n - tilted).length() < 1e-5, "{}", sh.n);
    assert!(sh.dpdu.dot(sh.n).abs() < 1e-5 && (sh.dpdu.length() - 2.0).abs() < 1e-5);
}

//! Mix materials: the bump of the material a mix picks.

use super::*;
use crate::material::DiffuseMaterial;
use crate::material::bump::tests::{bilerp, flat, floats_only};
use crate::math::{Rgb, normalize};
use crate::texture::{FloatTex, SpectrumTex};

/// Materials: 0 diffuse, 1 diffuse bumped by h(u, v) = 0.1·u + 0.2·v (normal
/// ∝ (−0.1, −0.2, 1)), 2 a mix of 0 and 1 with `amount`, 3 a mix of 2 and 2.
fn scene(amount: f32) -> Vec<Material> {
    vec![
        Material::Diffuse(DiffuseMaterial {
            reflectance: SpectrumTex::Const(Rgb::splat(0.5)),
        }),
        Material::Bumped(BumpedMaterial {
            base: 0,
            displacement: Some(FloatTex::Tex(0)),
            normal_map: None,
        }),
        Material::Mix(MixMaterial {
            materials: [0, 1],
            amount: FloatTex::Const(amount),
        }),
        Material::Mix(MixMaterial {
            materials: [2, 2],
            amount: FloatTex::Const(0.5),
        }),
    ]
}

#[test]
fn a_mix_applies_the_bump_of_the_material_it_picks() {
    let floats = bilerp([0.0, 0.2, 0.1, 0.3]);
    let tex = floats_only(&floats);
    let bumped_n = normalize(Vec3::new(-0.1, -0.2, 1.0));
    // Amount 1: always the bumped side, directly and under a mix of mixes.
    for m in [1, 2, 3] {
        let mut si = flat(0.3, 0.6);
        apply_bump(&scene(1.0), &tex, m, &mut si, TexCoord::at, |si| {
            ShadingDerivatives::flat(si)
        });
        assert!(
            (si.shading.n - bumped_n).length() < 2e-3,
            "{m}: {}",
            si.shading.n
        );
    }
    // Amount 0: always the plain side, whose frame stays.
    let mut si = flat(0.3, 0.6);
    apply_bump(&scene(0.0), &tex, 2, &mut si, TexCoord::at, |si| {
        ShadingDerivatives::flat(si)
    });
    assert_eq!(si.shading.n, Vec3::Z);
    // Amount 0.3: per point, the bump is there exactly when the mix picks material 1
    // (the choice the BSDF set-up makes with `mix_pick`), about 30 % of the points.
    let mats = scene(0.3);
    let mut picked = 0;
    let n = 2000;
    for i in 0..n {
        let (x, y) = ((i % 50) as f32 / 50.0 + 0.01, (i / 50) as f32 / 40.0 + 0.01);
        let mut si = flat(x, y);
        apply_bump(&mats, &tex, 2, &mut si, TexCoord::at, |si| {
            ShadingDerivatives::flat(si)
        });
        let tc = TexCoord::at(&si);
        let m = resolve_mix(&mats, &tex, &tc, 2);
        assert_eq!(m, mix_pick([0, 1], 0.3, si.p));
        if m == 1 {
            picked += 1;
            assert!((si.shading.n - bumped_n).length() < 2e-3);
        } else {
            assert_eq!(m, 0);
            assert_eq!(si.shading.n, Vec3::Z);
        }
    }
    // Binomial(2000, 0.3): σ ≈ 20.5; 5σ bounds.
    assert!((picked as f32 - 600.0).abs() < 103.0, "{picked}");
}

//! Resolving `mix` materials: the per-hit choice between a mix's two materials, shared by the
//! bump step at the hit ([`apply_bump`]) and the BSDF set-up, so that both see the same
//! material — and the material a mix picks has its own bump or normal map applied, as pbrt-v4
//! applies the chosen material's displacement after `MixMaterial::ChooseMaterial`.

use super::{BumpedMaterial, Material, MixMaterial, bump_shading, normal_map_shading};
use crate::math::Vec3;
use crate::shape::{ShadingDerivatives, SurfaceInteraction};
use crate::texture::{TexCoord, TextureEval};

/// The uniform number that picks a `mix` material's side at `p`: a hash of the point. Out of
/// line, so that it is computed only for mixes (hoisted into a caller's entry, it cost every
/// hit a hash).
#[cold]
#[inline(never)]
pub fn mix_choice(p: Vec3) -> f32 {
    crate::sampling::u32_to_unit_f32(crate::sampling::hash_u64(&[
        p.x.to_bits() as u64,
        p.y.to_bits() as u64,
        p.z.to_bits() as u64,
    ]) as u32)
}

/// The side of the mix `materials`/`amount` taken at a hit at `p` with texture coordinates
/// `tc`: the second when u < a (u = [`mix_choice`]`(p)`, a the amount there), always the first
/// for a ≤ 0 and always the second for a ≥ 1.
#[inline]
pub fn mix_pick(materials: [u32; 2], amount: f32, p: Vec3) -> u32 {
    if amount <= 0.0 {
        materials[0]
    } else if amount >= 1.0 || mix_choice(p) < amount {
        materials[1]
    } else {
        materials[0]
    }
}

/// Follows `mix` materials from `m` down to the material they choose at the hit (at most 16
/// levels deep, as the BSDF set-up does); a non-mix `m` is returned as it is.
#[inline]
pub fn resolve_mix(materials: &[Material], tex: &TextureEval, tc: &TexCoord, mut m: u32) -> u32 {
    for _ in 0..16 {
        match materials[m as usize] {
            Material::Mix(MixMaterial {
                materials: pair,
                amount,
            }) => m = mix_pick(pair, tex.float(amount, tc), tc.p),
            _ => return m,
        }
    }
    m
}

/// Changes `si`'s shading frame as material `m`'s bump or normal map asks (pbrt-v4 does it
/// in `SurfaceInteraction::GetBSDF`, before the BSDF and everything that uses the shading
/// normal); for a `mix`, the map of the material it chooses at this hit ([`resolve_mix`], the
/// same choice the BSDF set-up makes). Other materials leave it alone. `tex_coord` gives the
/// hit's texture lookup point with its footprint, `derivatives` pbrt-v4's shading derivatives
/// of the hit (asked only by a bump map, so that other hits never compute them).
#[inline]
pub fn apply_bump(
    materials: &[Material],
    tex: &TextureEval,
    mut m: u32,
    si: &mut SurfaceInteraction,
    tex_coord: impl Fn(&SurfaceInteraction) -> TexCoord,
    derivatives: impl FnOnce(&SurfaceInteraction) -> ShadingDerivatives,
) {
    if let Material::Mix(_) = materials[m as usize] {
        m = resolve_mix(materials, tex, &tex_coord(si), m);
    }
    if let Material::Bumped(BumpedMaterial {
        displacement,
        normal_map,
        ..
    }) = materials[m as usize]
    {
        let shading = match (normal_map, displacement) {
            (Some(nm), _) => normal_map_shading(tex, nm, si),
            (None, Some(d)) => bump_shading(tex, d, si, &tex_coord(si), &derivatives(si)),
            (None, None) => None,
        };
        if let Some(sh) = shading {
            si.shading = sh;
        }
    }
}

#[cfg(test)]
mod tests;

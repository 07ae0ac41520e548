//! bdpt and light tracing against the path tracer on a small diffuse room, the MIS weights of
//! every strategy of a path summing to 1, and a white furnace.

use super::connect::mis_weight;
use super::vertex::{Kind, Vertex};
use super::walk::Walk;
use super::*;
use crate::integrator::test_scenes::{self, diffuse};
use crate::integrator::{Integrator, bsdf_at};
use crate::light::{PointDesc, UniformInfiniteDesc};
use crate::material::{BxdfFlags, ConductorMaterial, DielectricMaterial, MaterialDesc};
use crate::math::{Rgb, Vec3, normalize};
use crate::sampling::SamplerKind;
use crate::scene::desc::{AreaLightDesc, Geometry, LightDesc, SceneDesc, ShapeDesc};
use crate::shape::{PlaneDesc, SphereDesc};
use crate::spectrum::Ior;
use crate::texture::{FloatTex, SpectrumTex};

pub(super) use crate::integrator::test_scenes::{H, W};

/// [`test_scenes::quad`], emitting `light` (one-sided) when given.
fn quad(p: [[f32; 3]; 4], material: u32, light: Option<f32>) -> ShapeDesc {
    ShapeDesc {
        area_light: light.map(|l| AreaLightDesc {
            l: Rgb::splat(l),
            two_sided: false,
            spectrum: None,
            power: None,
            image: None,
        }),
        ..test_scenes::quad(p, material)
    }
}

/// [`test_scenes::view`] with the y axis up.
fn view(eye: Vec3, target: Vec3, fov: f32, integrator: Integrator) -> SceneDesc {
    test_scenes::view(eye, target, Vec3::Y, fov, integrator)
}

/// A room open towards the camera: grey floor, back wall and ceiling, a red left wall, a
/// green right wall, lit by a small quad under the ceiling facing down (`area`) or a point
/// light (`!area`), which the camera does not see directly.
pub(super) fn room(area: bool, integrator: Integrator) -> Scene {
    Scene::build(&room_desc(area, integrator)).unwrap()
}

/// The description of [`room`].
pub(crate) fn room_desc(area: bool, integrator: Integrator) -> SceneDesc {
    let mut shapes = vec![
        quad(
            [
                [-1.0, 0.0, 1.0],
                [1.0, 0.0, 1.0],
                [1.0, 0.0, -1.0],
                [-1.0, 0.0, -1.0],
            ],
            0,
            None,
        ),
        quad(
            [
                [-1.0, 0.0, -1.0],
                [1.0, 0.0, -1.0],
                [1.0, 2.0, -1.0],
                [-1.0, 2.0, -1.0],
            ],
            0,
            None,
        ),
        quad(
            [
                [-1.0, 2.0, -1.0],
                [1.0, 2.0, -1.0],
                [1.0, 2.0, 1.0],
                [-1.0, 2.0, 1.0],
            ],
            0,
            None,
        ),
        quad(
            [
                [-1.0, 0.0, 1.0],
                [-1.0, 0.0, -1.0],
                [-1.0, 2.0, -1.0],
                [-1.0, 2.0, 1.0],
            ],
            1,
            None,
        ),
        quad(
            [
                [1.0, 0.0, -1.0],
                [1.0, 0.0, 1.0],
                [1.0, 2.0, 1.0],
                [1.0, 2.0, -1.0],
            ],
            2,
            None,
        ),
    ];
    let mut lights = vec![];
    if area {
        let (a, h) = (0.3, 1.98);
        shapes.push(quad(
            [[-a, h, -a], [a, h, -a], [a, h, a], [-a, h, a]],
            0,
            Some(6.0),
        ));
    } else {
        lights.push(LightDesc::Point(PointDesc {
            from: Vec3::new(0.2, 1.7, 0.1),
            intensity: Rgb::splat(2.0),
        }));
    }
    SceneDesc {
        materials: vec![
            diffuse(Rgb::splat(0.7)),
            diffuse(Rgb::new(0.7, 0.15, 0.1)),
            diffuse(Rgb::new(0.15, 0.6, 0.15)),
        ],
        shapes,
        lights,
        // The image's top edge at 14° − 2.7° above the horizontal, below the light.
        ..view(
            Vec3::new(0.0, 1.0, 4.2),
            Vec3::new(0.0, 0.8, 0.0),
            28.0,
            integrator,
        )
    }
}

/// Renders `scene` with `integrator` at `spp` samples per pixel (box filter, RGB mode):
/// camera samples and splats into the pixel they land in, over `spp`. `per_strategy` also
/// gathers each (s, t) strategy's unweighted contributions into images of their own.
pub(super) fn render(
    scene: &Scene,
    integrator: Integrator,
    spp: u32,
    seed: u64,
    mut per_strategy: Option<&mut std::collections::BTreeMap<(usize, usize), Vec<Rgb>>>,
) -> Vec<Rgb> {
    let n = (W * H) as usize;
    let mut img = vec![Rgb::ZERO; n];
    let mut sampler = Sampler::new(SamplerKind::Independent, spp, seed);
    let pixel = |p: Vec2| {
        let (x, y) = (p.x.floor() as i32, p.y.floor() as i32);
        (x >= 0 && y >= 0 && x < W as i32 && y < H as i32)
            .then(|| (y as u32 * W + x as u32) as usize)
    };
    let rgb = |l: SampledSpectrum| Rgb::new(l[0], l[1], l[2]);
    for y in 0..H as i32 {
        for x in 0..W as i32 {
            let i = (y as u32 * W + x as u32) as usize;
            for s in 0..spp {
                sampler.start_pixel_sample(x, y, s as u64);
                let u = sampler.get_pixel_2d();
                let p_film = Vec2::new(x as f32 + u.x, y as f32 + u.y);
                let ray = scene
                    .camera()
                    .generate_ray(p_film, sampler.get_2d())
                    .unwrap()
                    .ray;
                let mut splats = Vec::new();
                let l = match (integrator, per_strategy.as_deref_mut()) {
                    (
                        Integrator::Bdpt {
                            max_depth,
                            regularize,
                            ..
                        },
                        Some(images),
                    ) => {
                        let mut observe = |s: usize, t: usize, p: Option<Vec2>, v, w| {
                            let img = images.entry((s, t)).or_insert_with(|| vec![Rgb::ZERO; n]);
                            if let Some(j) = p.map_or(Some(i), pixel) {
                                img[j] += rgb(v) / w;
                            }
                        };
                        super::li(
                            scene,
                            &ray,
                            &mut sampler,
                            None,
                            BdptOptions {
                                max_depth,
                                regularize,
                            },
                            &mut |p, v| splats.push((p, v)),
                            Some(&mut observe),
                        )
                    }
                    _ => integrator.li_splatting(scene, &ray, &mut sampler, None, &mut |p, v| {
                        splats.push((p, v))
                    }),
                };
                img[i] += rgb(l);
                for (p, v) in splats {
                    if let Some(j) = pixel(p) {
                        img[j] += rgb(v);
                    }
                }
            }
        }
    }
    for v in img.iter_mut() {
        *v /= spp as f32;
    }
    if let Some(images) = per_strategy {
        for img in images.values_mut() {
            for v in img.iter_mut() {
                *v /= spp as f32;
            }
        }
    }
    img
}

/// Means over 6 × 6-pixel blocks (4 × 3 of them), channel by channel.
pub(crate) fn blocks(img: &[Rgb]) -> Vec<Rgb> {
    let mut out = vec![Rgb::ZERO; 12];
    for y in 0..H {
        for x in 0..W {
            out[((y / 6) * 4 + x / 6) as usize] += img[(y * W + x) as usize] / 36.0;
        }
    }
    out
}

/// Relative difference of block means, |a − b| / max(b, m/4) with m the mean of `b` over the
/// image (dim blocks are compared against a quarter of it), worst block and channel; and the
/// ratio of the images' means.
pub(crate) fn compare(a: &[Rgb], b: &[Rgb]) -> (f32, f32) {
    let (ba, bb) = (blocks(a), blocks(b));
    let mean = |v: &[Rgb]| v.iter().map(|c| c.x + c.y + c.z).sum::<f32>() / (3 * v.len()) as f32;
    let m = mean(&bb);
    let worst = ba
        .iter()
        .zip(&bb)
        .flat_map(|(x, y)| (0..3).map(move |c| (x[c] - y[c]).abs() / y[c].max(m / 4.0)))
        .fold(0.0f32, f32::max);
    (worst, mean(&ba) / m)
}

pub(crate) fn bdpt(max_depth: u32) -> Integrator {
    Integrator::Bdpt {
        max_depth,
        regularize: false,
        visualize_strategies: false,
        visualize_weights: false,
    }
}

pub(crate) fn path(max_depth: u32) -> Integrator {
    Integrator::Path {
        max_depth,
        regularize: false,
    }
}

#[test]
fn bdpt_and_light_tracing_agree_with_path_tracing() {
    for area in [true, false] {
        let scene = room(area, bdpt(3));
        let reference = render(&scene, path(3), 256, 1, None);
        let b = render(&scene, bdpt(3), 64, 2, None);
        let (worst, ratio) = compare(&b, &reference);
        assert!(
            worst < 0.07 && (ratio - 1.0).abs() < 0.015,
            "bdpt, area {area}: worst block {worst}, mean ratio {ratio}"
        );
        let lp = render(&scene, Integrator::LightPath { max_depth: 3 }, 64, 3, None);
        let (worst, ratio) = compare(&lp, &reference);
        assert!(
            worst < 0.12 && (ratio - 1.0).abs() < 0.02,
            "lightpath, area {area}: worst block {worst}, mean ratio {ratio}"
        );
        // An image 10 % too dark is caught by the mean, a wrong distribution by the blocks.
        let dim: Vec<Rgb> = reference.iter().map(|c| *c * 0.9).collect();
        assert!((compare(&dim, &reference).1 - 1.0).abs() > 0.05);
    }
}

#[test]
fn each_strategy_alone_gives_the_image_of_its_depth() {
    // Paths of one bounce (depth 1: light → surface → camera) are made by the strategies
    // (0, 3), (1, 2) and (2, 1); each alone (unweighted) converges to the path tracer's
    // image at maxdepth 1 (the camera does not see the light, so that is depth 1 only).
    let scene = room(true, bdpt(1));
    let reference = render(&scene, path(1), 256, 4, None);
    let mut images = std::collections::BTreeMap::new();
    let full = render(&scene, bdpt(1), 128, 5, Some(&mut images));
    assert_eq!(
        images.keys().copied().collect::<Vec<_>>(),
        [(0, 3), (1, 2), (2, 1)]
    );
    let (worst, ratio) = compare(&full, &reference);
    assert!(
        worst < 0.06 && (ratio - 1.0).abs() < 0.02,
        "full: {worst} {ratio}"
    );
    for (st, img) in &images {
        let (worst, ratio) = compare(img, &reference);
        // (0, 3) hits the small light by chance only: noisier.
        let (bound, mean_bound) = if *st == (0, 3) {
            (0.3, 0.03)
        } else {
            (0.12, 0.015)
        };
        assert!(
            worst < bound && (ratio - 1.0).abs() < mean_bound,
            "strategy {st:?}: worst block {worst}, mean ratio {ratio}"
        );
    }
}

#[test]
fn mis_weights_sum_to_one_through_glossy_and_specular_vertices() {
    // Bitterli's veach-bidir: a rough conductor of α = 0.25 (the lamps, whose densities are
    // not symmetric in their two directions) and smooth glass (the egg: delta vertices).
    // Here the back wall is the conductor and the right wall the glass, and the paths bounce
    // on the floor, the glass and the back wall in every order.
    let mut desc = room_desc(true, bdpt(5));
    desc.materials
        .push(MaterialDesc::Conductor(ConductorMaterial {
            eta: SpectrumTex::Const(Rgb::new(2.865601, 2.119182, 1.940077)),
            k: SpectrumTex::Const(Rgb::new(3.032326, 2.056108, 1.616293)),
            reflectance: None,
            uroughness: FloatTex::Const(0.25),
            vroughness: FloatTex::Const(0.25),
            remap_roughness: false,
        }));
    desc.materials
        .push(MaterialDesc::Dielectric(DielectricMaterial {
            eta: Ior::Constant(1.5),
            uroughness: FloatTex::Const(0.0),
            vroughness: FloatTex::Const(0.0),
            remap_roughness: false,
        }));
    desc.shapes[1].material = 3;
    desc.shapes[4].material = 4;
    for area in [true, false] {
        let mut d = desc.clone();
        if !area {
            d.shapes.pop();
            d.lights.push(LightDesc::Point(PointDesc {
                from: Vec3::new(0.2, 1.7, 0.1),
                intensity: Rgb::splat(2.0),
            }));
        }
        let scene = Scene::build(&d).unwrap();
        let c = Vec3::new(0.0, 1.0, 0.0);
        let floor = surface_vertex(&scene, c, Vec3::new(0.3, 0.0, 0.2));
        let metal = surface_vertex(&scene, c, Vec3::new(-0.5, 0.6, -1.0));
        let glass = surface_vertex(&scene, c, Vec3::new(1.0, 1.2, 0.3));
        assert!(metal.bsdf.unwrap().flags().has(BxdfFlags::GLOSSY));
        assert!(glass.bsdf.unwrap().flags().is_specular());
        for order in [
            [floor, metal, glass],
            [metal, glass, floor],
            [glass, floor, metal],
            [floor, glass, metal],
        ] {
            assert_mis_weights_sum_to_one(&scene, area, &order, "glossy and specular");
        }
        // And the walks through them store the densities the weights recompute.
        let mut checks = DensityChecks::default();
        check_walk_densities(
            &scene,
            &mut |w, got, want| checks.check(w, got, want),
            "glossy and specular",
        );
        checks.assert_agree(300);
    }
}

/// A surface vertex where the ray from `from` towards `to` first meets the room.
pub(super) fn surface_vertex(scene: &Scene, from: Vec3, to: Vec3) -> Vertex {
    let hit = scene
        .intersect(&Ray::new(from, normalize(to - from)))
        .unwrap();
    let (bsdf, _) = bsdf_at(scene, &hit, None).unwrap();
    Vertex {
        kind: Kind::Surface,
        p: hit.si.p,
        p_error: hit.si.p_error,
        ng: hit.si.n,
        ns: hit.si.shading.n,
        wo: hit.si.wo,
        uv: hit.si.uv,
        prim: hit.prim,
        bsdf: Some(bsdf),
        phase: crate::medium::HgPhaseFunction { g: 0.0 },
        medium: None,
        beta: SampledSpectrum::ONE,
        r: SampledSpectrum::ONE,
        delta: false,
        pdf_fwd: 0.0,
        pdf_rev: 0.0,
    }
}

/// The subpaths strategy s makes of the path `x` (light end first, camera last): the light
/// subpath's first s vertices and the camera subpath's first t, with their densities as the
/// random walks compute them.
pub(super) fn subpaths(
    scene: &Scene,
    x: &[Vertex],
    light_vertex: Vertex,
    s: usize,
) -> (Vec<Vertex>, Vec<Vertex>) {
    let n = x.len();
    let mut light: Vec<Vertex> = x[..s].to_vec();
    if s > 0 {
        light[0] = light_vertex;
    }
    let mut camera: Vec<Vertex> = x[s..].iter().rev().copied().collect();
    for path in [&mut light, &mut camera] {
        for i in 1..path.len() {
            let prev = (i >= 2).then(|| path[i - 2]);
            path[i].pdf_fwd = path[i - 1].pdf(scene, prev.as_ref(), &path[i]);
        }
        for i in 0..path.len().saturating_sub(2) {
            let next_next = path.get(i + 2).copied();
            path[i].pdf_rev = path[i + 1].pdf(scene, next_next.as_ref(), &path[i]);
        }
    }
    if s > 0 {
        light[0].pdf_fwd = light[0].pdf_light_origin(scene, &x[1]);
    }
    assert_eq!(light.len() + camera.len(), n);
    (light, camera)
}

#[test]
fn mis_weights_of_all_strategies_of_a_path_sum_to_one() {
    for (area, cropped) in [(true, false), (false, false), (true, true), (false, true)] {
        // Cropped: the pixels x < 18, y ≥ 3 (which hold the path's last bounce), so that the
        // light paths are fewer than the full image's samples (splat scale 432/270 = 1.6).
        let mut desc = room_desc(area, bdpt(5));
        if cropped {
            desc.film.pixel_bounds = Some([0, 18, 3, 18]);
        }
        let scene = Scene::build(&desc).unwrap();
        assert_eq!(
            scene.camera().splat_scale(),
            if cropped { 1.6 } else { 1.0 }
        );
        let c = Vec3::new(0.0, 1.0, 0.0);
        let bounces = [
            surface_vertex(&scene, c, Vec3::new(0.3, 0.0, 0.2)),
            surface_vertex(&scene, c, Vec3::new(-0.5, 0.6, -1.0)),
            surface_vertex(&scene, c, Vec3::new(-1.0, 1.2, 0.3)),
        ];
        assert_mis_weights_sum_to_one(&scene, area, &bounces, &format!("cropped {cropped}"));
    }
}

/// Checks that every strategy's MIS weight is in (0, 1] and that they sum to 1 over each
/// path light → `bounces[..d]` → camera, d = 1 … `bounces.len()`, in the room of [`room`]:
/// the light's end a point on the quad (a surface vertex for the camera side, a light vertex
/// for the light side) when `area`, else the point light. A bounce on a specular surface is
/// a delta vertex, as the walks mark it: the strategies that would connect at it make
/// nothing, and the others' weights sum to 1.
pub(super) fn assert_mis_weights_sum_to_one(
    scene: &Scene,
    area: bool,
    bounces: &[Vertex],
    what: &str,
) {
    let c = Vec3::new(0.0, 1.0, 0.0);
    let eye = scene.camera().world_from_camera.point(Vec3::ZERO);
    let (on_light, light_vertex) = if area {
        let v = surface_vertex(scene, c, Vec3::new(0.1, 2.0, 0.05));
        let i = scene.prim(v.prim).emission.unwrap().light;
        let lv = Vertex::endpoint(Kind::Light(i), v.p, v.p_error, v.ng, SampledSpectrum::ONE);
        (v, lv)
    } else {
        let p = Vec3::new(0.2, 1.7, 0.1);
        let v = Vertex::endpoint(
            Kind::Light(0),
            p,
            Vec3::ZERO,
            Vec3::ZERO,
            SampledSpectrum::ONE,
        );
        (v, v)
    };
    let camera_vertex = Vertex::endpoint(
        Kind::Camera,
        eye,
        Vec3::ZERO,
        Vec3::ZERO,
        SampledSpectrum::ONE,
    );
    for depth in 1..=bounces.len() {
        let mut x = vec![on_light];
        x.extend_from_slice(&bounces[..depth]);
        x.push(camera_vertex);
        let n = x.len();
        let mut weights = vec![];
        // A point light cannot be hit: no s = 0.
        for s in usize::from(!area)..n {
            let t = n - s;
            let (mut light, mut camera) = subpaths(scene, &x, light_vertex, s);
            // The walks mark a specular bounce delta (the densities out of it, which
            // `Vertex::pdf` gives as 0, they store as 0 too).
            for v in light.iter_mut().chain(camera.iter_mut()) {
                v.delta = v.bsdf.is_some_and(|b| b.flags().is_specular());
            }
            if (s > 0 && light[s - 1].delta) || (t > 0 && camera[t - 1].delta) {
                continue;
            }
            // s = 1 and t = 1 connect to a vertex sampled for the purpose: the light's or the
            // lens' (with the lens' normal, as the camera samples it).
            let sampled = if s == 1 {
                Some(light[0])
            } else if t == 1 {
                let mut v = camera[0];
                v.ng = normalize(scene.camera().world_from_camera.vector(Vec3::Z));
                v.ns = v.ng;
                Some(v)
            } else {
                None
            };
            let w = mis_weight(scene, &mut light, &mut camera, sampled.as_ref(), s, t);
            assert!(
                w > 0.0 && w <= 1.0,
                "{what}, area {area} depth {depth} s {s}: {w}"
            );
            weights.push(w);
        }
        // A point light seen by the camera through one delta vertex: no strategy makes it.
        if weights.is_empty()
            && !area
            && depth == 1
            && bounces[0].bsdf.is_some_and(|b| b.flags().is_specular())
        {
            continue;
        }
        let sum: f32 = weights.iter().sum();
        assert!(
            (sum - 1.0).abs() < 1e-4,
            "{what}, area {area} depth {depth}: weights {weights:?} sum to {sum}"
        );
    }
}

/// The densities the walks of `scene` stored against the ones [`Vertex::pdf`] recomputes, 64
/// camera and light subpaths of up to 7 and 6 vertices: `check(what, stored, recomputed)`
/// for each. Returns how many vertices of each kind the subpaths held (surface, medium).
pub(super) fn check_walk_densities(
    scene: &Scene,
    check: &mut dyn FnMut(String, f32, f32),
    what: &str,
) -> (usize, usize) {
    let mut sampler = Sampler::new(SamplerKind::Independent, 64, 11);
    let (mut camera, mut light) = (Vec::new(), Vec::new());
    let mut kinds = (0, 0);
    for k in 0..64 {
        sampler.start_pixel_sample(5 + (k % 14) as i32, 3 + (k % 11) as i32, k);
        let p = Vec2::new(5.5 + (k % 14) as f32, 3.5 + (k % 11) as f32);
        let ray = scene.camera().generate_ray(p, Vec2::ZERO).unwrap().ray;
        let mut walk = Walk {
            scene,
            lambda: None,
            regularize: false,
            hero: (k % 4) as usize,
        };
        walk.camera_subpath(&ray, &mut sampler, 7, &mut camera);
        walk.light_subpath(&mut sampler, 6, &mut light);
        for (name, path) in [("camera", &camera), ("light", &light)] {
            for v in path.iter() {
                match v.kind {
                    Kind::Surface => kinds.0 += 1,
                    Kind::Medium => kinds.1 += 1,
                    _ => {}
                }
            }
            for i in 1..path.len() {
                let at = format!("{what}, {name} subpath {k}, vertex {i}");
                let prev2 = (i >= 2).then(|| path[i - 2]);
                let want = path[i - 1].pdf(scene, prev2.as_ref(), &path[i]);
                check(format!("{at}: pdf_fwd"), path[i].pdf_fwd, want);
                // pdf_rev is known once the vertex after next has been reached.
                if i + 2 < path.len() {
                    let want = path[i + 1].pdf(scene, Some(&path[i + 2]), &path[i]);
                    check(format!("{at}: pdf_rev"), path[i].pdf_rev, want);
                }
            }
        }
        // The light's own vertex: the density of its position (a point light's is a delta,
        // which no other strategy can reach).
        if light.len() > 1 && light[0].is_on_surface() {
            let want = light[0].pdf_light_origin(scene, &light[1]);
            check(
                format!("{what}, light subpath {k}: origin"),
                light[0].pdf_fwd,
                want,
            );
        }
    }
    kinds
}

/// Collects [`check_walk_densities`]'s comparisons: how many, how many off by more than
/// 10⁻⁴, and those off by more than 2 %.
#[derive(Default)]
pub(super) struct DensityChecks {
    pub checked: usize,
    pub loose: usize,
    pub off: Vec<String>,
}

impl DensityChecks {
    /// Records one comparison.
    pub fn check(&mut self, what: String, got: f32, want: f32) {
        let rel = (got - want).abs() / want.abs().max(1e-6);
        self.checked += 1;
        self.loose += usize::from(rel > 1e-4);
        if rel > 2e-2 {
            self.off.push(format!("{what}: {got} vs {want}"));
        }
    }

    /// All within 2 %, and 99 % within 10⁻⁴, of at least `min` checked.
    pub fn assert_agree(&self, min: usize) {
        assert!(
            self.checked > min,
            "only {} densities checked",
            self.checked
        );
        assert!(
            self.off.is_empty(),
            "densities that disagree:\n{}",
            self.off.join("\n")
        );
        assert!(
            self.loose * 100 <= self.checked,
            "{} of {} densities differ by more than 1e-4",
            self.loose,
            self.checked
        );
    }
}

#[test]
fn the_walks_store_the_densities_the_weights_recompute() {
    // The MIS weights mix the densities the random walks stored (pdf_fwd as each vertex was
    // sampled, pdf_rev as the next vertex would have sampled it back) with the ones
    // `Vertex::pdf` recomputes at the connection: a path's weights sum to 1 only if the two
    // agree. Traced subpaths of the room, every vertex checked. They agree to rounding but
    // where rays leave a surface at a grazing angle or land very close (the rays' offsets
    // then shift the direction or distance measurably: up to 0.7 % seen), so: all within
    // 2 %, and 99 % within 10⁻⁴. A wrong measure or a missing cosine is off by far more,
    // and a systematic error of 0.1 % on every vertex fails the second bound.
    let mut checks = DensityChecks::default();
    for area in [true, false] {
        let scene = room(area, bdpt(5));
        let what = format!("area {area}");
        check_walk_densities(
            &scene,
            &mut |w, got, want| checks.check(w, got, want),
            &what,
        );
    }
    checks.assert_agree(1000);
}

/// A white furnace: a diffuse sphere of albedo 0.8 under a uniform white sky. A convex
/// object reflects the sky once, so the image is 0.8 on the sphere and 1 around it, whatever
/// the strategies.
pub(crate) fn furnace_desc(integrator: Integrator) -> SceneDesc {
    SceneDesc {
        materials: vec![diffuse(Rgb::splat(0.8))],
        shapes: vec![ShapeDesc::new(
            Geometry::Sphere(SphereDesc {
                radius: 1.0,
                z_min: -1.0,
                z_max: 1.0,
                phi_max: 360.0,
            }),
            0,
        )],
        lights: vec![LightDesc::UniformInfinite(UniformInfiniteDesc {
            l: Rgb::ONE,
        })],
        ..view(Vec3::new(0.0, 0.0, 4.0), Vec3::ZERO, 40.0, integrator)
    }
}

/// Asserts that `img`, a render of [`furnace_desc`], is 0.8 on its centre block (all sphere)
/// and 1 in its corner (all sky).
#[track_caller]
pub(crate) fn assert_furnace(img: &[Rgb]) {
    let centre: Rgb = [(11, 8), (12, 8), (11, 9), (12, 9)]
        .iter()
        .map(|&(x, y)| img[(y * W + x) as usize])
        .fold(Rgb::ZERO, |a, b| a + b)
        / 4.0;
    let corner = img[0];
    for c in 0..3 {
        assert!((centre[c] - 0.8).abs() < 0.03, "sphere {centre}");
        assert!((corner[c] - 1.0).abs() < 0.02, "sky {corner}");
    }
}

#[test]
fn white_furnace() {
    let scene = Scene::build(&furnace_desc(bdpt(5))).unwrap();
    assert_furnace(&render(&scene, bdpt(5), 64, 9, None));
}

/// A grey sphere of radius ½ on lancer's infinite plane under a white sky, seen towards the
/// horizon: most of the image is the plane far past the scene's bounds (the sphere's), where
/// no light subpath from the sky's disk arrives.
pub(crate) fn plane_under_sky(integrator: Integrator) -> SceneDesc {
    SceneDesc {
        materials: vec![diffuse(Rgb::splat(0.5))],
        shapes: vec![
            ShapeDesc::new(
                Geometry::Sphere(SphereDesc {
                    radius: 0.5,
                    z_min: -0.5,
                    z_max: 0.5,
                    phi_max: 360.0,
                }),
                0,
            ),
            ShapeDesc::new(
                Geometry::Plane(PlaneDesc {
                    p: Vec3::new(0.0, -0.5, 0.0),
                    n: Vec3::Y,
                }),
                0,
            ),
        ],
        lights: vec![LightDesc::UniformInfinite(UniformInfiniteDesc {
            l: Rgb::ONE,
        })],
        ..view(
            Vec3::new(0.0, 0.3, 4.0),
            Vec3::new(0.0, 0.0, -20.0),
            40.0,
            integrator,
        )
    }
}

#[test]
fn an_infinite_plane_is_lit_by_the_sky_beyond_the_scene_bounds() {
    // There a point's light sampling must weigh all (it weighed almost nothing against the
    // impossible light paths: a black horizon).
    let scene = Scene::build(&plane_under_sky(bdpt(3))).unwrap();
    let reference = render(&scene, path(3), 64, 3, None);
    let b = render(&scene, bdpt(3), 64, 4, None);
    let (worst, ratio) = compare(&b, &reference);
    assert!(
        worst < 0.1 && (ratio - 1.0).abs() < 0.02,
        "worst block {worst}, mean ratio {ratio}"
    );
}

#[test]
fn the_simple_integrators_agree_with_path_tracing() {
    let scene = room(true, path(3));
    let reference = render(&scene, path(3), 256, 1, None);
    for (integrator, spp, bound) in [
        (
            Integrator::SimplePath {
                max_depth: 3,
                sample_lights: true,
                sample_bsdf: true,
            },
            128,
            0.08,
        ),
        (
            Integrator::SimplePath {
                max_depth: 3,
                sample_lights: true,
                sample_bsdf: false,
            },
            128,
            0.1,
        ),
        // Hitting the small light by chance: much noisier.
        (Integrator::RandomWalk { max_depth: 3 }, 512, 0.35),
    ] {
        let img = render(&scene, integrator, spp, 7, None);
        let (worst, ratio) = compare(&img, &reference);
        assert!(
            worst < bound && (ratio - 1.0).abs() < bound / 4.0,
            "{integrator:?}: worst block {worst}, mean ratio {ratio}"
        );
    }
}

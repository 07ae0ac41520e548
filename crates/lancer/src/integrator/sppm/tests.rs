//! sppm's pieces: the progressive update and the final estimate by their formulas, the grid
//! against a brute-force search, and the photon density estimate of a diffuse plane under a
//! point light against its analytic radiance.

use super::grid::VisibleGrid;
use super::*;
use crate::integrator::bsdf_at;
use crate::integrator::test_scenes::{diffuse, quad};
use crate::light::PointDesc;
use crate::math::Rgb;
use crate::scene::desc::{LightDesc, SceneDesc};

#[test]
fn update_follows_the_progressive_formulas() {
    let mut s = PixelState::new(1.0);
    // M = 3, Φ = 3: N' = 0 + 2/3·3 = 2, R' = √(2/3), τ' = 3·R'²/R² = 2.
    s.update(3, [3.0, 1.5, 0.0]);
    assert!((s.n - 2.0).abs() < 1e-12);
    assert!((s.radius - (2.0f64 / 3.0).sqrt()).abs() < 1e-12);
    assert!((s.tau[0] - 2.0).abs() < 1e-12 && (s.tau[1] - 1.0).abs() < 1e-12);
    // No photon: nothing changes.
    let before = s;
    s.update(0, [5.0; 3]);
    assert_eq!(s, before);
    // M = 6, Φ = 6: N'' = 2 + 4 = 6, R''² = R'²·6/8, τ'' = (2 + 6)·6/8 = 6.
    s.update(6, [6.0, 0.0, 0.0]);
    assert!((s.n - 6.0).abs() < 1e-12);
    assert!((s.radius * s.radius - 2.0 / 3.0 * 0.75).abs() < 1e-12);
    assert!((s.tau[0] - 6.0).abs() < 1e-12);
    // L = Ld/iterations + τ/(N_p·π·R²), N_p = iterations · photons per iteration.
    s.ld = [4.0, 0.0, 2.0];
    let l = s.estimate(2, 10);
    let area = 20.0 * std::f64::consts::PI * (0.5);
    assert!((l[0] as f64 - (2.0 + 6.0 / area)).abs() < 1e-6, "{l:?}");
    assert!((l[2] - 1.0).abs() < 1e-6);
    assert_eq!(PixelState::new(1.0).estimate(0, 10), Rgb::ZERO);
}

/// A small deterministic generator for the tests' points.
struct Lcg(u64);

impl Lcg {
    fn next(&mut self) -> f32 {
        self.0 = self
            .0
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        (self.0 >> 40) as f32 / (1u64 << 24) as f32
    }
}

#[test]
fn grid_lists_every_point_whose_sphere_holds_the_query() {
    let mut rng = Lcg(7);
    let mut points: Vec<(Vec3, f32)> = (0..500)
        .map(|_| {
            let p = Vec3::new(rng.next() * 4.0 - 2.0, rng.next(), rng.next() * 3.0);
            (p, 0.02 + 0.2 * rng.next())
        })
        .collect();
    // Points without a visible point (radius 0) are never listed.
    points.push((Vec3::ZERO, 0.0));
    let grid = VisibleGrid::build(&points).unwrap();
    let mut found = 0;
    for _ in 0..5000 {
        let q = Vec3::new(
            rng.next() * 5.0 - 2.5,
            rng.next() * 1.4 - 0.2,
            rng.next() * 3.4 - 0.2,
        );
        let listed = grid.candidates(q);
        for (i, (p, r)) in points.iter().enumerate() {
            if *r > 0.0 && (*p - q).length_squared() <= r * r {
                found += 1;
                assert!(listed.contains(&(i as u32)), "point {i} missing at {q:?}");
            }
        }
        assert!(!listed.contains(&500));
        // Each point once: a photon meets it once.
        let mut unique = listed.to_vec();
        unique.sort_unstable();
        unique.dedup();
        assert_eq!(unique.len(), listed.len(), "a point listed twice at {q:?}");
    }
    assert!(found > 1000, "the test found too few points: {found}");
    assert!(VisibleGrid::build(&[(Vec3::ONE, 0.0)]).is_none());
    // Two points in a table of two buckets: their 27 cells each share them.
    let two = [(Vec3::ZERO, 0.5), (Vec3::new(0.4, 0.3, 0.2), 0.45)];
    let grid = VisibleGrid::build(&two).unwrap();
    assert_eq!(grid.candidates(Vec3::new(0.1, 0.1, 0.1)), &[0, 1]);
}

/// A diffuse floor of albedo `rho` (y = 0, 100 units wide) under a point light of intensity
/// `i` at height 1 above the origin.
fn lit_floor(rho: f32, i: f32) -> Scene {
    let s = 50.0;
    let desc = SceneDesc {
        materials: vec![diffuse(Rgb::splat(rho))],
        shapes: vec![quad(
            [[-s, 0.0, s], [s, 0.0, s], [s, 0.0, -s], [-s, 0.0, -s]],
            0,
        )],
        lights: vec![LightDesc::Point(PointDesc {
            from: Vec3::new(0.0, 1.0, 0.0),
            intensity: Rgb::splat(i),
        })],
        ..SceneDesc::default()
    };
    Scene::build(&desc).unwrap()
}

/// Photons deposited straight from the light (`first_deposit` 0), gathered by the progressive
/// estimate at three points of the floor, give its radiance ρ/π·E, E = I·cos θ/d²: the
/// photons' flux, the density estimate's π·R² and N_p, and the update all take part (a
/// factor π or 2 anywhere would be far outside the tolerance).
#[test]
fn photon_density_estimate_converges_to_the_analytic_radiance() {
    let (rho, intensity) = (0.5f32, 3.0f32);
    let scene = lit_floor(rho, intensity);
    let xs = [0.0f32, 0.5, 1.2];
    let vps: Vec<VisiblePoint> = xs
        .iter()
        .map(|&x| {
            let hit = scene
                .intersect(&Ray::new(Vec3::new(x, 2.0, 0.0), Vec3::new(0.0, -1.0, 0.0)))
                .unwrap();
            let (bsdf, _) = bsdf_at(&scene, &hit, None).unwrap();
            VisiblePoint {
                p: hit.si.p,
                wo: hit.si.wo,
                bsdf,
                beta: SampledSpectrum::ONE,
                hero_only: false,
            }
        })
        .collect();
    let mut state = vec![PixelState::new(0.1); vps.len()];
    let (iterations, photons) = (40u32, 20_000u64);
    let perms = DigitPermutations::for_seed(3);
    let mut u = PhotonSampler::new(perms, 3, 0);
    for k in 0..iterations {
        let points: Vec<(Vec3, f32)> = vps
            .iter()
            .zip(&state)
            .map(|(v, s)| (v.p, s.radius as f32))
            .collect();
        let grid = VisibleGrid::build(&points).unwrap();
        let mut phi = vec![[0.0f64; 3]; vps.len()];
        let mut m = vec![0u64; vps.len()];
        for i in 0..photons {
            u.start(k as u64 * photons + i);
            assert!(trace_photon(&scene, None, 1, 0, &mut u, &mut |h| {
                for &v in grid.candidates(h.p) {
                    let (p, r) = points[v as usize];
                    if (p - h.p).length_squared() <= r * r {
                        let f = photon_flux(&vps[v as usize], h);
                        m[v as usize] += 1;
                        for c in 0..3 {
                            phi[v as usize][c] += f[c] as f64;
                        }
                    }
                }
            }));
        }
        for ((s, phi), m) in state.iter_mut().zip(&phi).zip(&m) {
            s.update(*m, *phi);
        }
    }
    for (x, s) in xs.iter().zip(&state) {
        let d2 = x * x + 1.0;
        let expected = rho / std::f32::consts::PI * intensity / d2 * (1.0 / d2.sqrt());
        let l = s.estimate(iterations, photons)[0];
        assert!(
            (l - expected).abs() < 0.06 * expected,
            "x = {x}: estimate {l}, analytic {expected} (radius now {})",
            s.radius
        );
        assert!(s.radius < 0.1);
    }
}

/// The photons' random numbers are a pure function of (seed, index, dimension), and differ
/// between seeds.
#[test]
fn photon_samples_depend_only_on_seed_and_index() {
    let draw = |seed: u64, index: u64| {
        let mut u = PhotonSampler::new(DigitPermutations::for_seed(seed), seed, 0);
        u.start(index);
        let mut v: Vec<f32> = (0..PRIME_TABLE_SIZE + 3).map(|_| u.get_1d()).collect();
        v.push(u.get_2d().x);
        v
    };
    let a = draw(1, 12345);
    assert_eq!(a, draw(1, 12345));
    assert_ne!(a, draw(2, 12345));
    assert_ne!(a, draw(1, 12346));
    assert!(a.iter().all(|x| (0.0..1.0).contains(x)));
}

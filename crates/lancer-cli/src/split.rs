//! Splitting a render: `--crop`, `--samples a..b`, `--split i/N --split-by tiles|samples`, and
//! the scene hash that tells whether parts belong to the same render.

use crate::cli_error::CliError;
use lancer::SceneDesc;
use lancer::film::PixelBounds;
use lancer::film::part::PartMeta;
use std::ops::Range;

/// Tile edge in pixels of every render (tile splits are bands of whole tiles).
pub const TILE_SIZE: u32 = 16;

/// Largest sample range of one unit of work: an interrupt waits for at most one unit per
/// thread, and resumes from the last finished units.
pub const SAMPLES_PER_PASS: u32 = 16;

/// How `--split` divides the render.
#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum SplitBy {
    /// Bands of whole tile rows of the image, every sample of their pixels.
    #[default]
    Tiles,
    /// Ranges of sample indices, every pixel.
    Samples,
}

/// Part `index` of `count` (0-based), from `--split i/N`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Split {
    /// Which part, `0 ≤ index < count`.
    pub index: u32,
    /// How many parts.
    pub count: u32,
}

/// Parses `i/N`, `0 ≤ i < N`.
pub fn parse_split(s: &str) -> Result<Split, String> {
    let (i, n) = s
        .split_once('/')
        .ok_or_else(|| format!("'{s}' is not i/N (a part index, 0-based, and a count)"))?;
    let index: u32 = i
        .trim()
        .parse()
        .map_err(|_| format!("'{i}' is not a part index"))?;
    let count: u32 = n
        .trim()
        .parse()
        .map_err(|_| format!("'{n}' is not a part count"))?;
    if count == 0 || index >= count {
        return Err(format!(
            "part {index} of {count} does not exist (0 ≤ i < N)"
        ));
    }
    Ok(Split { index, count })
}

/// Parses `x0,x1,y0,y1`, fractions of the image with `0 ≤ x0 < x1 ≤ 1`, `0 ≤ y0 < y1 ≤ 1`.
pub fn parse_crop(s: &str) -> Result<[f32; 4], String> {
    let v: Vec<f32> = s
        .split(',')
        .map(|x| x.trim().parse::<f32>())
        .collect::<Result<_, _>>()
        .map_err(|_| format!("'{s}' is not four numbers x0,x1,y0,y1"))?;
    match v[..] {
        [x0, x1, y0, y1] => check_crop([x0, x1, y0, y1]).map_err(|e| format!("'{s}': {e}")),
        _ => Err(format!("'{s}' is not four numbers x0,x1,y0,y1")),
    }
}

/// Checks a crop window `[x0, x1, y0, y1]`: `0 ≤ x0 < x1 ≤ 1` and `0 ≤ y0 < y1 ≤ 1`.
pub fn check_crop(c: [f32; 4]) -> Result<[f32; 4], String> {
    let [x0, x1, y0, y1] = c;
    let unit = |v: f32| (0.0..=1.0).contains(&v);
    if unit(x0) && unit(x1) && unit(y0) && unit(y1) && x0 < x1 && y0 < y1 {
        Ok(c)
    } else {
        Err("a crop window needs 0 ≤ x0 < x1 ≤ 1 and 0 ≤ y0 < y1 ≤ 1".into())
    }
}

/// Checks pixel bounds `[x0, x1, y0, y1]` (pbrt's `pixelbounds`: the pixels `x0 ≤ x < x1`,
/// `y0 ≤ y < y1`): `0 ≤ x0 < x1` and `0 ≤ y0 < y1`.
pub fn check_pixel_bounds(b: [i32; 4]) -> Result<[i32; 4], String> {
    let [x0, x1, y0, y1] = b;
    if 0 <= x0 && x0 < x1 && 0 <= y0 && y0 < y1 {
        Ok(b)
    } else {
        Err("pixel bounds need 0 ≤ x0 < x1 and 0 ≤ y0 < y1".into())
    }
}

/// Parses a sample index range `a..b` (`a < b`).
pub fn parse_samples(s: &str) -> Result<Range<u32>, String> {
    let (a, b) = s
        .split_once("..")
        .ok_or_else(|| format!("'{s}' is not a range a..b"))?;
    let a: u32 = a
        .trim()
        .parse()
        .map_err(|_| format!("'{a}' is not a sample index"))?;
    let b: u32 = b
        .trim()
        .parse()
        .map_err(|_| format!("'{b}' is not a sample index"))?;
    if a >= b {
        return Err(format!("the sample range {a}..{b} is empty"));
    }
    Ok(a..b)
}

/// FNV-1a (64 bits) over text: `h ← (h ⊕ byte) · 1099511628211`, from `h = 14695981039346656037`.
struct Fnv1a(u64);

impl std::fmt::Write for Fnv1a {
    fn write_str(&mut self, s: &str) -> std::fmt::Result {
        for b in s.bytes() {
            self.0 = (self.0 ^ b as u64).wrapping_mul(0x0000_0100_0000_01b3);
        }
        Ok(())
    }
}

/// The scene hash: FNV-1a of the scene description as parsed, with the command line's
/// overrides applied, but without what does not change a pixel's value (the output file name)
/// or what a part records on its own (which pixels it holds: crop window, pixel bounds).
/// The description's debug form is hashed as it is printed: every number at full precision,
/// except large arrays (mesh vertices, texels, voxels), which print as a digest of their bits;
/// the path the scene was read from is not in it.
pub fn scene_hash(desc: &SceneDesc) -> u64 {
    use std::fmt::Write;
    let mut d = desc.clone();
    d.film.filename = None;
    d.film.crop_window = [0.0, 1.0, 0.0, 1.0];
    d.film.pixel_bounds = None;
    let mut h = Fnv1a(0xcbf2_9ce4_8422_2325);
    let _ = write!(h, "{d:?}");
    h.0
}

/// [`scene_hash`] of a render in RGB (`spectral` false: the same hash as before spectral mode
/// existed) or spectral mode (the mode hashed after the description), so that parts and
/// checkpoints of the two modes never merge.
pub fn scene_hash_in_mode(desc: &SceneDesc, spectral: bool) -> u64 {
    use std::fmt::Write;
    let mut h = Fnv1a(scene_hash(desc));
    if spectral {
        let _ = write!(h, "spectral");
    }
    h.0
}

/// What one process renders.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Plan {
    /// The pixels of the whole render (the crop window).
    pub render_bounds: PixelBounds,
    /// The pixels this process renders.
    pub bounds: PixelBounds,
    /// The sample indices this process takes in each of them.
    pub samples: Range<u32>,
    /// True when the result is a part to merge (with `--split` or `--samples`), not an image.
    pub is_part: bool,
}

impl Plan {
    /// What the part (or checkpoint) of this plan of the render `desc` records, in spectral
    /// mode or not: the scene hash ([`scene_hash_in_mode`]), seed, spp (for `mlt`, its
    /// chains: `Integrator::sample_indices`), this plan's sample
    /// range, the whole render's pixels and the film's scale.
    pub fn part_meta(&self, desc: &SceneDesc, spectral: bool) -> PartMeta {
        PartMeta {
            scene_hash: scene_hash_in_mode(desc, spectral),
            seed: desc.sampler.seed,
            spp: desc.integrator.sample_indices(desc.sampler.spp),
            samples: self.samples.clone(),
            render_bounds: self.render_bounds,
            scale: desc.film.scale,
        }
    }
}

/// Refuses a split of an `mlt` render by tiles: its chains splat over the whole film, so a
/// part of it is a range of chains (`--split-by samples`), never a band of pixels.
pub fn check_split(desc: &SceneDesc, split: Option<(Split, SplitBy)>) -> Result<(), CliError> {
    match (&desc.integrator, split) {
        (lancer::integrator::Integrator::Mlt(_), Some((_, SplitBy::Tiles))) => {
            Err(CliError::input(
                "integrator \"mlt\" splats every chain over the whole image: split it by chains \
                 with --split-by samples (its sample indices are its chains), not by tiles",
            ))
        }
        _ => Ok(()),
    }
}

/// Works out which pixels and samples to render: `render_bounds` × `0..spp`, narrowed by
/// `--samples` and then by `--split`. Tile parts are bands of whole tile rows: part i of N
/// gets rows `⌊R·i/N⌋ .. ⌊R·(i+1)/N⌋` of the `R` tile rows; sample parts get indices
/// `a + ⌊n·i/N⌋ .. a + ⌊n·(i+1)/N⌋` of the `n` samples of `a..b`.
pub fn plan(
    render_bounds: PixelBounds,
    spp: u32,
    samples: Option<Range<u32>>,
    split: Option<(Split, SplitBy)>,
) -> Result<Plan, CliError> {
    let base = samples.clone().unwrap_or(0..spp);
    if base.end > spp {
        return Err(CliError::input(format!(
            "--samples {}..{} goes past the {spp} samples per pixel",
            base.start, base.end
        )));
    }
    let mut p = Plan {
        render_bounds,
        bounds: render_bounds,
        samples: base.clone(),
        is_part: samples.is_some() || split.is_some(),
    };
    let Some((s, by)) = split else {
        return Ok(p);
    };
    let (i, n) = (s.index as u64, s.count as u64);
    match by {
        SplitBy::Tiles => {
            let rows = render_bounds.height().div_ceil(TILE_SIZE) as u64;
            let (r0, r1) = (rows * i / n, rows * (i + 1) / n);
            if r0 == r1 {
                return Err(CliError::input(format!(
                    "--split {}/{}: the image has only {rows} {} of {TILE_SIZE}-pixel tiles, \
                     too few for {n} parts",
                    s.index,
                    s.count,
                    if rows == 1 { "row" } else { "rows" }
                )));
            }
            let t = TILE_SIZE as i32;
            p.bounds.y0 = render_bounds.y0 + r0 as i32 * t;
            p.bounds.y1 = (render_bounds.y0 + r1 as i32 * t).min(render_bounds.y1);
        }
        SplitBy::Samples => {
            let len = base.len() as u64;
            let (a, b) = (len * i / n, len * (i + 1) / n);
            if a == b {
                return Err(CliError::input(format!(
                    "--split {}/{}: {len} samples per pixel are too few for {n} sample parts",
                    s.index, s.count
                )));
            }
            p.samples = base.start + a as u32..base.start + b as u32;
        }
    }
    Ok(p)
}

#[cfg(test)]
mod tests {
    use super::*;

    const B: PixelBounds = PixelBounds {
        x0: 0,
        x1: 50,
        y0: 3,
        y1: 70,
    };

    #[test]
    fn options_parse_and_nonsense_is_refused() {
        assert_eq!(parse_split("2/4"), Ok(Split { index: 2, count: 4 }));
        assert!(parse_split("4/4").is_err());
        assert!(parse_split("1/0").is_err());
        assert!(parse_split("x").is_err());
        assert_eq!(parse_samples("3..17"), Ok(3..17));
        assert!(parse_samples("5..5").is_err());
        assert_eq!(parse_crop("0,0.5,0.25,1"), Ok([0.0, 0.5, 0.25, 1.0]));
        assert!(parse_crop("0.5,0.2,0,1").is_err());
        assert!(parse_crop("0,1,0").is_err());
        assert_eq!(check_crop([0.0, 1.0, 0.5, 0.75]), Ok([0.0, 1.0, 0.5, 0.75]));
        assert!(check_crop([0.0, 1.5, 0.0, 1.0]).is_err());
        assert_eq!(check_pixel_bounds([0, 10, 5, 6]), Ok([0, 10, 5, 6]));
        assert!(check_pixel_bounds([3, 3, 0, 1]).is_err());
        assert!(check_pixel_bounds([-1, 3, 0, 1]).is_err());
    }

    #[test]
    fn tile_splits_are_bands_that_cover_the_image_once() {
        // 67 rows: 5 tile rows (the last one partial).
        let mut next = B.y0;
        for i in 0..3 {
            let p = plan(
                B,
                8,
                None,
                Some((Split { index: i, count: 3 }, SplitBy::Tiles)),
            )
            .unwrap();
            assert!(p.is_part);
            assert_eq!(p.samples, 0..8);
            assert_eq!((p.bounds.x0, p.bounds.x1), (0, 50));
            assert_eq!(p.bounds.y0, next);
            assert_eq!((p.bounds.y0 - B.y0) % TILE_SIZE as i32, 0);
            next = p.bounds.y1;
        }
        assert_eq!(next, B.y1);
        let s = Split { index: 0, count: 6 };
        assert!(plan(B, 8, None, Some((s, SplitBy::Tiles))).is_err());
    }

    #[test]
    fn sample_splits_partition_the_range() {
        let mut next = 4;
        for i in 0..3 {
            let s = Split { index: i, count: 3 };
            let p = plan(B, 16, Some(4..14), Some((s, SplitBy::Samples))).unwrap();
            assert_eq!(p.bounds, B);
            assert_eq!(p.samples.start, next);
            assert!(p.samples.len() == 3 || p.samples.len() == 4);
            next = p.samples.end;
        }
        assert_eq!(next, 14);
        assert!(plan(B, 8, Some(4..9), None).is_err());
        let whole = plan(B, 8, None, None).unwrap();
        assert!(!whole.is_part);
        assert_eq!(whole.samples, 0..8);
    }

    #[test]
    fn the_hash_sees_pixels_not_names() {
        let a = SceneDesc::default();
        let mut b = a.clone();
        b.film.filename = Some("elsewhere.exr".into());
        b.film.crop_window = [0.0, 0.5, 0.0, 1.0];
        assert_eq!(scene_hash(&a), scene_hash(&b));
        b.sampler.seed += 1;
        assert_ne!(scene_hash(&a), scene_hash(&b));
        let mut c = a.clone();
        c.film.scale = 2.0;
        assert_ne!(scene_hash(&a), scene_hash(&c));
        // The mode changes pixels: spectral and RGB parts must not merge; RGB keeps the hash.
        assert_eq!(scene_hash_in_mode(&a, false), scene_hash(&a));
        assert_ne!(scene_hash_in_mode(&a, true), scene_hash(&a));
        let mut e = a.clone();
        e.film.filename = Some("spectral.exr".into());
        assert_eq!(scene_hash_in_mode(&e, true), scene_hash_in_mode(&a, true));
        assert_ne!(scene_hash_in_mode(&b, true), scene_hash_in_mode(&a, true));
    }

    #[test]
    fn an_mlt_render_splits_into_ranges_of_chains_only() {
        use lancer::integrator::Integrator;
        use lancer::integrator::mlt::MltOptions;
        let mut d = SceneDesc {
            integrator: Integrator::Mlt(MltOptions {
                max_depth: 5,
                bootstrap_samples: 100,
                chains: 40,
                mutations_per_pixel: 8,
                large_step_probability: 0.3,
                sigma: 0.01,
                regularize: false,
            }),
            ..SceneDesc::default()
        };
        let split = Split { index: 1, count: 4 };
        let e = check_split(&d, Some((split, SplitBy::Tiles))).unwrap_err();
        assert!(e.message.contains("--split-by samples"), "{}", e.message);
        check_split(&d, Some((split, SplitBy::Samples))).unwrap();
        check_split(&d, None).unwrap();
        // Its sample indices are its 40 chains: part 1 of 4 takes chains 10..20, and the part
        // records 40 as its "spp", so that merging checks the chains are all there.
        let n = d.integrator.sample_indices(d.sampler.spp);
        let p = plan(B, n, None, Some((split, SplitBy::Samples))).unwrap();
        assert_eq!(p.samples, 10..20);
        assert_eq!(p.part_meta(&d, true).spp, 40);
        d.integrator = Integrator::default();
        check_split(&d, Some((split, SplitBy::Tiles))).unwrap();
    }
}

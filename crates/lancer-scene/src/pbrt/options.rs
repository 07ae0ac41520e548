//! The rendering options: `Film`, `Sampler`, `PixelFilter`, `Integrator` and `Option`, with
//! pbrt-v4's defaults. Kinds lancer does not have fall back to its nearest one, with a warning.

mod spectral_film;

use super::convert::{Fallback, MAX_RESOLUTION};
use super::params::ParamList;
use crate::error::SceneError;
use lancer::integrator::Integrator;
use lancer::integrator::sppm::SppmOptions;
use lancer::integrator::vcm::VcmOptions;
use lancer::light::LightSamplerKind;
use lancer::sampling::{Randomization, SamplerKind};
use lancer::scene::desc::{FilmDesc, FilterDesc};
use lancer::spectrum::Sensor;

/// What `Film` sets: the film, and the sensor's ISO (the imaging ratio is exposure time ×
/// ISO / 100, known once the camera's shutter is).
#[derive(Clone, Debug)]
pub struct FilmOptions {
    /// The film (its `scale` is left for the builder to set).
    pub film: FilmDesc,
    /// `iso`.
    pub iso: f32,
}

/// The film `ty`, over `film` (what earlier directives set).
pub fn film(
    params: &ParamList,
    ty: &str,
    mut film: FilmDesc,
) -> Result<Fallback<FilmOptions>, SceneError> {
    let mut warnings = Vec::new();
    film.gbuffer = None;
    film.spectral = None;
    match ty {
        "rgb" => {}
        "gbuffer" => {
            let world_space = match params.string("coordinatesystem")?.as_deref() {
                None | Some("camera") => false,
                Some("world") => true,
                Some(other) => {
                    return Err(params.error_at(
                        "coordinatesystem",
                        format!(
                            "unknown coordinate system \"{other}\" for the gbuffer film (pbrt-v4 \
                             knows \"camera\" and \"world\")"
                        ),
                    ));
                }
            };
            film.gbuffer = Some(lancer::gbuffer::GbufferDesc { world_space });
        }
        "spectral" => film.spectral = Some(spectral_film::buckets(params)?),
        _ => warnings.push(format!(
            "film \"{ty}\" is not supported yet; lancer uses an \"rgb\" film"
        )),
    }
    film.xresolution = params.int_in("xresolution", 1280, 1..=MAX_RESOLUTION)? as u32;
    film.yresolution = params.int_in("yresolution", 720, 1..=MAX_RESOLUTION)? as u32;
    film.filename = params.string("filename")?;
    if let Some(c) = params.floats("cropwindow")? {
        let ok =
            c.len() == 4 && c.iter().all(|v| (0.0..=1.0).contains(v)) && c[0] < c[1] && c[2] < c[3];
        if !ok {
            return Err(params.error_at(
                "cropwindow",
                "\"float cropwindow\" needs 4 numbers in [0, 1]: xmin xmax ymin ymax, with min < max",
            ));
        }
        film.crop_window = [c[0], c[1], c[2], c[3]];
    }
    if let Some((b, bloc)) = params.ints("pixelbounds")? {
        if b.len() != 4 || b[0] >= b[1] || b[2] >= b[3] {
            return Err(SceneError::at(
                bloc,
                "\"integer pixelbounds\" needs 4 numbers: x0 x1 y0 y1, with x0 < x1 and y0 < y1",
            ));
        }
        film.pixel_bounds = Some([b[0], b[1], b[2], b[3]]);
    }
    let iso = params.float_checked("iso", 100.0, "positive", |v| v > 0.0)?;
    film.max_component_value =
        params.float_checked("maxcomponentvalue", f32::INFINITY, "positive", |v| v > 0.0)?;
    // pbrt-v4's gbuffer and spectral films write half floats unless told otherwise.
    film.save_fp16 = params.bool(
        "savefp16",
        film.gbuffer.is_some() || film.spectral.is_some(),
    )?;
    // The sensor's diagonal in mm: the realistic camera's film size.
    film.diagonal = params.float_checked("diagonal", 35.0, "positive", |v| v > 0.0)?;
    if let Some(name) = params.string("sensor")? {
        film.sensor = Sensor::from_name(&name).ok_or_else(|| {
            let known: Vec<&str> = Sensor::names().collect();
            params.error_at(
                "sensor",
                format!(
                    "unknown sensor \"{name}\" (pbrt-v4 knows {})",
                    known.join(", ")
                ),
            )
        })?;
    }
    film.white_balance =
        params.float_checked("whitebalance", 0.0, "0 (none) or positive", |v| v >= 0.0)?;
    Ok(Fallback {
        value: FilmOptions { film, iso },
        warnings,
    })
}

/// pbrt-v4's imaging ratio, the film's scale: exposure time × ISO / 100, the exposure time
/// being the camera's `shutter` [open, close].
pub fn imaging_ratio(shutter: [f32; 2], iso: f32) -> f32 {
    let [open, close] = shutter;
    (close - open) * iso / 100.0
}

/// A `seed` (of `Option` or `Sampler`), if given; pbrt-v4 reads it as a 32-bit integer.
pub fn seed(params: &ParamList) -> Result<Option<u64>, SceneError> {
    if !params.has("seed") {
        return Ok(None);
    }
    Ok(Some(params.int("seed", 0)? as u32 as u64))
}

/// What `Sampler` sets.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SamplerOptions {
    /// The point set.
    pub kind: SamplerKind,
    /// Samples per pixel.
    pub spp: u32,
    /// `seed`, if given (it overrides `Option "seed"`).
    pub seed: Option<u64>,
}

/// The sampler `ty`: its point set, samples per pixel and seed.
pub fn sampler(params: &ParamList, ty: &str) -> Result<Fallback<SamplerOptions>, SceneError> {
    let p = params;
    let spp =
        || -> Result<u32, SceneError> { Ok(p.int_in("pixelsamples", 16, 1..=1 << 24)? as u32) };
    let zsobol = SamplerKind::ZSobol {
        randomization: Randomization::FastOwen,
    };
    let (kind, spp, warning) = match ty {
        "independent" => (SamplerKind::Independent, spp()?, None),
        "stratified" => {
            let x = p.int_in("xsamples", 4, 1..=4096)? as u32;
            let y = p.int_in("ysamples", 4, 1..=4096)? as u32;
            let jitter = p.bool("jitter", true)?;
            let kind = SamplerKind::Stratified {
                xsamples: x,
                ysamples: y,
                jitter,
            };
            (kind, x * y, None)
        }
        "zsobol" => {
            let randomization = randomization(p, Randomization::FastOwen, true)?;
            (SamplerKind::ZSobol { randomization }, spp()?, None)
        }
        "paddedsobol" => {
            let randomization = randomization(p, Randomization::FastOwen, true)?;
            (SamplerKind::PaddedSobol { randomization }, spp()?, None)
        }
        "halton" => {
            let randomization = randomization(p, Randomization::PermuteDigits, false)?;
            // The film's resolution is set when the render starts.
            let kind = SamplerKind::Halton {
                randomization,
                resolution: [1280, 720],
            };
            (kind, spp()?, None)
        }
        "sobol" => {
            let randomization = randomization(p, Randomization::FastOwen, true)?;
            let kind = SamplerKind::Sobol {
                randomization,
                resolution: [1280, 720],
            };
            (kind, spp()?, None)
        }
        // pbrt-v4's pmj02bn has no randomization parameter (its points are generated by
        // lancer, see lancer::sampling::pmj02).
        "pmj02bn" => (SamplerKind::Pmj02bn, spp()?, None),
        _ => {
            let w = format!("unknown sampler \"{ty}\"; lancer uses \"zsobol\"");
            (zsobol, spp()?, Some(w))
        }
    };
    let options = SamplerOptions {
        kind,
        spp,
        seed: seed(p)?,
    };
    Ok(match warning {
        None => Fallback::done(options),
        Some(w) => Fallback::instead(options, w),
    })
}

/// The sampler's `"string randomization"` (`default` when absent): `none`, `permutedigits`,
/// `owen`, and `fastowen` where the sequence is in base 2 (`base2`); pbrt-v4 refuses the rest.
fn randomization(
    params: &ParamList,
    default: Randomization,
    base2: bool,
) -> Result<Randomization, SceneError> {
    let Some(name) = params.string("randomization")? else {
        return Ok(default);
    };
    match Randomization::from_pbrt(&name) {
        Some(Randomization::FastOwen) if !base2 => Err(params.error_at(
            "randomization",
            "\"fastowen\" randomization is for base-2 samplers; use \"permutedigits\", \"owen\" or \"none\"",
        )),
        Some(r) => Ok(r),
        None => Err(params.error_at(
            "randomization",
            format!(
                "unknown randomization \"{name}\": expected \"none\", \"permutedigits\", \"fastowen\" or \"owen\""
            ),
        )),
    }
}

/// The pixel filter `ty`, with pbrt-v4's default radii.
pub fn filter(params: &ParamList, ty: &str) -> Result<Fallback<FilterDesc>, SceneError> {
    let p = params;
    let radius = |d: f32| -> Result<[f32; 2], SceneError> {
        let ok = |v: f32| v > 0.0 && v <= 64.0;
        Ok([
            p.float_checked("xradius", d, "in (0, 64]", ok)?,
            p.float_checked("yradius", d, "in (0, 64]", ok)?,
        ])
    };
    let f = match ty {
        "box" => FilterDesc::Box {
            radius: radius(0.5)?,
        },
        "gaussian" => FilterDesc::Gaussian {
            radius: radius(1.5)?,
            sigma: p.float_checked("sigma", 0.5, "positive", |v| v > 0.0)?,
        },
        "triangle" => FilterDesc::Triangle {
            radius: radius(2.0)?,
        },
        "mitchell" => FilterDesc::Mitchell {
            radius: radius(2.0)?,
            b: p.float("B", 1.0 / 3.0)?,
            c: p.float("C", 1.0 / 3.0)?,
        },
        "sinc" | "lanczos" => FilterDesc::Lanczos {
            radius: radius(4.0)?,
            tau: p.float_checked("tau", 3.0, "positive", |v| v > 0.0)?,
        },
        _ => {
            return Ok(Fallback::instead(
                FilterDesc::default(),
                format!("unknown pixel filter \"{ty}\"; lancer uses \"gaussian\""),
            ));
        }
    };
    Ok(Fallback::done(f))
}

/// The integrator `ty`, with pbrt-v4's defaults (`maxdepth` 5, `regularize`,
/// `visualizestrategies` and `visualizeweights` false; sppm's `photonsperiteration` −1 (one
/// per pixel), `radius` 1, `seed` the render's; lancer's `vcm`: `radius` from the scene's
/// size, `alpha` 0.75); the others fall back to `path`.
pub fn integrator(params: &ParamList, ty: &str) -> Result<Fallback<Integrator>, SceneError> {
    let p = params;
    let max_depth = p.int_in("maxdepth", 5, 0..=100_000)? as u32;
    let path = || -> Result<Integrator, SceneError> {
        Ok(Integrator::Path {
            max_depth,
            regularize: p.bool("regularize", false)?,
        })
    };
    let i = match ty {
        "whitted" => Integrator::Whitted { max_depth },
        // lancer's extension: caustics seen directly by light tracing (no regularisation).
        "path" if p.bool("caustics", false)? => {
            let i = Integrator::PathCaustics {
                max_depth,
                paths: p.float_checked(
                    "causticpaths",
                    lancer::integrator::caustics::DEFAULT_PATHS,
                    "in (0, 1]",
                    |v| v > 0.0 && v <= 1.0,
                )?,
            };
            if p.bool("regularize", false)? {
                return Ok(Fallback::instead(
                    i,
                    "\"regularize\" is ignored by \"path\" with \"caustics\"".to_string(),
                ));
            }
            i
        }
        "path" | "volpath" => {
            // Their `lightsampler` is read by [`light_sampler`].
            match (ty, path()?) {
                (
                    "volpath",
                    Integrator::Path {
                        max_depth,
                        regularize,
                    },
                ) => Integrator::VolPath {
                    max_depth,
                    regularize,
                },
                (_, i) => i,
            }
        }
        "ambientocclusion" => Integrator::AmbientOcclusion {
            cos_sample: p.bool("cossample", true)?,
            max_distance: p.float("maxdistance", f32::INFINITY)?,
        },
        "normals" => Integrator::Normals,
        "depth" => Integrator::Depth,
        "lightpath" => Integrator::LightPath { max_depth },
        "bdpt" => {
            let (visualize_strategies, visualize_weights) = (
                p.bool("visualizestrategies", false)?,
                p.bool("visualizeweights", false)?,
            );
            let visualize = visualize_strategies || visualize_weights;
            let i = Integrator::Bdpt {
                // As pbrt-v4: with the strategy images, paths of at most 5 bounces.
                max_depth: if visualize {
                    max_depth.min(5)
                } else {
                    max_depth
                },
                regularize: p.bool("regularize", false)?,
                visualize_strategies,
                visualize_weights,
            };
            if visualize && max_depth > 5 {
                return Ok(Fallback::instead(
                    i,
                    "integrator \"bdpt\": visualizestrategies/visualizeweights limit maxdepth to 5, as in pbrt-v4".to_string(),
                ));
            }
            i
        }
        "simplepath" => Integrator::SimplePath {
            max_depth,
            sample_lights: p.bool("samplelights", true)?,
            sample_bsdf: p.bool("samplebsdf", true)?,
        },
        "randomwalk" => Integrator::RandomWalk { max_depth },
        "mlt" => {
            let o = lancer::integrator::mlt::MltOptions {
                max_depth,
                bootstrap_samples: p.int_in("bootstrapsamples", 100_000, 1..=1 << 24)? as u32,
                chains: p.int_in("chains", 1000, 1..=1 << 24)? as u32,
                mutations_per_pixel: p.int_in("mutationsperpixel", 100, 1..=1 << 24)? as u32,
                large_step_probability: p.float_checked(
                    "largestepprobability",
                    0.3,
                    "in [0, 1]",
                    |v| (0.0..=1.0).contains(&v),
                )?,
                sigma: p.float_checked("sigma", 0.01, "finite and not negative", |v| {
                    v.is_finite() && v >= 0.0
                })?,
                regularize: p.bool("regularize", false)?,
            };
            // The bootstrap keeps one weight per vector: bootstrapsamples × (maxdepth + 1).
            let vectors = o.bootstrap_samples as u64 * (o.max_depth as u64 + 1);
            if vectors > 1 << 28 {
                return Err(p.error_at(
                    "bootstrapsamples",
                    format!(
                        "integrator \"mlt\": \"bootstrapsamples\" × (\"maxdepth\" + 1) = {vectors} \
                     bootstrap paths, more than the 268435456 lancer keeps"
                    ),
                ));
            }
            Integrator::Mlt(o)
        }
        "simplevolpath" => Integrator::SimpleVolPath { max_depth },
        "sppm" => Integrator::Sppm(SppmOptions {
            max_depth,
            // pbrt-v4: −1 (the default) or any value ≤ 0 means one photon per pixel.
            photons_per_iteration: Some(p.int("photonsperiteration", -1)?)
                .filter(|&n| n > 0)
                .map(|n| n as u32),
            radius: p.float_checked("radius", 1.0, "positive and finite", |r| {
                r > 0.0 && r.is_finite()
            })?,
            seed: seed(p)?,
        }),
        // lancer's extension: the first iteration's merge radius (absent: a fraction of the
        // scene's size, chosen once the scene is built) and its shrink exponent α ∈ (0, 1].
        "vcm" => Integrator::Vcm(VcmOptions {
            max_depth,
            radius: Some(
                p.float_checked("radius", f32::NAN, "positive and finite", |r| {
                    r > 0.0 && r.is_finite()
                })?,
            )
            .filter(|r| !r.is_nan()),
            alpha: p.float_checked("alpha", 0.75, "in (0, 1]", |a| a > 0.0 && a <= 1.0)?,
        }),
        "aov" => {
            return Ok(Fallback::instead(
                path()?,
                format!(
                    "integrator \"{ty}\" is not supported yet; lancer uses \"path\" with maxdepth {max_depth}"
                ),
            ));
        }
        _ => {
            return Ok(Fallback::instead(
                path()?,
                format!("unknown integrator \"{ty}\"; lancer uses \"path\""),
            ));
        }
    };
    Ok(Fallback::done(i))
}

/// The integrator `ty`'s `"string lightsampler"` (path tracers only): `uniform`, `power` or
/// `bvh`, pbrt-v4's default.
pub fn light_sampler(
    params: &ParamList,
    ty: &str,
) -> Result<Fallback<LightSamplerKind>, SceneError> {
    if !matches!(ty, "path" | "volpath") {
        return Ok(Fallback::done(LightSamplerKind::Bvh));
    }
    let Some(name) = params.string("lightsampler")? else {
        return Ok(Fallback::done(LightSamplerKind::Bvh));
    };
    match LightSamplerKind::from_pbrt(&name) {
        Some(k) => Ok(Fallback::done(k)),
        None if name == "exhaustive" => Ok(Fallback::instead(
            LightSamplerKind::Bvh,
            "light sampler \"exhaustive\" is not supported yet; lancer uses \"bvh\"".to_string(),
        )),
        None => Err(params.error_at(
            "lightsampler",
            format!("unknown light sampler \"{name}\": expected \"uniform\", \"power\" or \"bvh\""),
        )),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::pbrt::convert::testing::{err, typed, unused};

    /// Converts the one directive of `text` with `f`, and gives its unread parameters.
    fn convert<T>(
        text: &str,
        f: impl FnOnce(&ParamList, &str) -> Result<T, SceneError>,
    ) -> (Result<T, SceneError>, Vec<String>) {
        let (ty, params, _) = typed(text);
        let out = f(&params, &ty);
        (out, unused(&params))
    }

    /// Converted without warnings, every parameter read.
    #[track_caller]
    fn clean<T>(
        text: &str,
        f: impl FnOnce(&ParamList, &str) -> Result<Fallback<T>, SceneError>,
    ) -> T {
        let (out, unused) = convert(text, f);
        let out = out.unwrap_or_else(|e| panic!("{e}"));
        assert!(out.warnings.is_empty(), "{:?}", out.warnings);
        assert!(unused.is_empty(), "{unused:?}");
        out.value
    }

    /// The warnings of a conversion that succeeds.
    #[track_caller]
    fn warnings<T>(
        text: &str,
        f: impl FnOnce(&ParamList, &str) -> Result<Fallback<T>, SceneError>,
    ) -> Vec<String> {
        convert(text, f)
            .0
            .unwrap_or_else(|e| panic!("{e}"))
            .warnings
    }

    #[track_caller]
    fn error<T: std::fmt::Debug>(
        text: &str,
        f: impl FnOnce(&ParamList, &str) -> Result<T, SceneError>,
    ) -> String {
        err(convert(text, f).0)
    }

    fn new_film(p: &ParamList, ty: &str) -> Result<Fallback<FilmOptions>, SceneError> {
        film(p, ty, FilmDesc::default())
    }

    #[test]
    fn film_defaults_and_every_parameter() {
        let f = clean(r#"Film "rgb""#, new_film);
        assert_eq!((f.film, f.iso), (FilmDesc::default(), 100.0));
        let f = clean(
            r#"Film "rgb" "integer xresolution" 64 "integer yresolution" 48
               "string filename" "out.exr" "float cropwindow" [0 0.5 0.25 1]
               "integer pixelbounds" [0 10 0 20] "float iso" 200 "float maxcomponentvalue" 10
               "bool savefp16" true "float diagonal" 50 "string sensor" "cie1931"
               "float whitebalance" 0"#,
            new_film,
        );
        let expected = FilmDesc {
            xresolution: 64,
            yresolution: 48,
            filename: Some("out.exr".into()),
            crop_window: [0.0, 0.5, 0.25, 1.0],
            pixel_bounds: Some([0, 10, 0, 20]),
            scale: 1.0,
            max_component_value: 10.0,
            save_fp16: true,
            diagonal: 50.0,
            ..FilmDesc::default()
        };
        assert_eq!((f.film, f.iso), (expected, 200.0));
        // A crop window or pixel bounds a later Film does not give are kept.
        let earlier = FilmDesc {
            crop_window: [0.1, 0.2, 0.3, 0.4],
            ..FilmDesc::default()
        };
        let (out, _) = convert(r#"Film "rgb" "integer xresolution" 8"#, |p, ty| {
            film(p, ty, earlier)
        });
        let f = out.unwrap().value.film;
        assert_eq!((f.xresolution, f.crop_window), (8, [0.1, 0.2, 0.3, 0.4]));
    }

    #[test]
    fn film_fallbacks_and_errors() {
        let (f, unused) = convert(
            r#"Film "gbuffer" "string sensor" "canon_eos_100d" "float whitebalance" 5000
               "string coordinatesystem" "world" "string filename" "g.exr""#,
            new_film,
        );
        assert!(unused.is_empty(), "{unused:?}");
        let f = f.unwrap();
        // Its auxiliary channels are written (lancer::gbuffer): no warning.
        assert!(f.warnings.is_empty(), "{:?}", f.warnings);
        let f = f.value;
        assert_eq!(f.film.sensor.name(), "canon_eos_100d");
        assert_eq!(f.film.white_balance, 5000.0);
        assert_eq!(
            f.film.gbuffer,
            Some(lancer::gbuffer::GbufferDesc { world_space: true })
        );
        // pbrt-v4's gbuffer film writes half floats by default.
        assert!(f.film.save_fp16);
        assert_eq!(
            warnings(r#"Film "foo""#, new_film),
            ["film \"foo\" is not supported yet; lancer uses an \"rgb\" film"]
        );
        assert_eq!(
            error("Film \"rgb\"\n  \"string sensor\" \"leica\"", new_film)
                .split(" (")
                .next()
                .unwrap(),
            "t.pbrt:2:3: unknown sensor \"leica\""
        );
        assert_eq!(
            error(
                "Film \"gbuffer\"\n  \"string coordinatesystem\" \"screen\"",
                new_film
            ),
            "t.pbrt:2:3: unknown coordinate system \"screen\" for the gbuffer film (pbrt-v4 \
             knows \"camera\" and \"world\")"
        );
        assert_eq!(
            error("Film \"rgb\"\n  \"integer xresolution\" 0", new_film),
            "t.pbrt:2:3: \"integer xresolution\" must be between 1 and 65536, not 0"
        );
        assert_eq!(
            error("Film \"rgb\"\n  \"integer yresolution\" 65537", new_film),
            "t.pbrt:2:3: \"integer yresolution\" must be between 1 and 65536, not 65537"
        );
        assert_eq!(
            error("Film \"rgb\"\n  \"float cropwindow\" [0 2 0 1]", new_film),
            "t.pbrt:2:3: \"float cropwindow\" needs 4 numbers in [0, 1]: xmin xmax ymin ymax, with min < max"
        );
        assert_eq!(
            error(
                "Film \"rgb\"\n  \"integer pixelbounds\" [0 0 0 1]",
                new_film
            ),
            "t.pbrt:2:3: \"integer pixelbounds\" needs 4 numbers: x0 x1 y0 y1, with x0 < x1 and y0 < y1"
        );
        assert_eq!(
            error("Film \"rgb\"\n  \"float iso\" 0", new_film),
            "t.pbrt:2:3: \"float iso\" must be positive, not 0"
        );
        assert_eq!(
            error("Film \"rgb\"\n  \"float maxcomponentvalue\" -1", new_film),
            "t.pbrt:2:3: \"float maxcomponentvalue\" must be positive, not -1"
        );
    }

    #[test]
    fn the_imaging_ratio_is_exposure_time_times_iso_over_100() {
        assert_eq!(imaging_ratio([0.0, 1.0], 100.0), 1.0);
        assert_eq!(imaging_ratio([0.25, 0.75], 400.0), 2.0);
    }

    #[test]
    fn samplers() {
        let options = |kind, spp, seed| SamplerOptions { kind, spp, seed };
        let zsobol = |randomization| SamplerKind::ZSobol { randomization };
        assert_eq!(
            clean(r#"Sampler "zsobol""#, sampler),
            options(zsobol(Randomization::FastOwen), 16, None)
        );
        assert_eq!(
            clean(
                r#"Sampler "zsobol" "integer pixelsamples" 64 "string randomization" "owen" "integer seed" 9"#,
                sampler
            ),
            options(zsobol(Randomization::Owen), 64, Some(9))
        );
        assert_eq!(
            clean(
                r#"Sampler "paddedsobol" "string randomization" "permutedigits""#,
                sampler
            ),
            options(
                SamplerKind::PaddedSobol {
                    randomization: Randomization::PermuteDigits
                },
                16,
                None
            )
        );
        assert_eq!(
            clean(r#"Sampler "pmj02bn" "integer pixelsamples" 64"#, sampler),
            options(SamplerKind::Pmj02bn, 64, None)
        );
        let halton = |randomization| SamplerKind::Halton {
            randomization,
            resolution: [1280, 720],
        };
        assert_eq!(
            clean(r#"Sampler "halton" "integer pixelsamples" 8"#, sampler),
            options(halton(Randomization::PermuteDigits), 8, None)
        );
        assert_eq!(
            clean(r#"Sampler "halton" "string randomization" "none""#, sampler),
            options(halton(Randomization::None), 16, None)
        );
        assert_eq!(
            error(
                "Sampler \"halton\"\n  \"string randomization\" \"fastowen\"",
                sampler
            ),
            "t.pbrt:2:3: \"fastowen\" randomization is for base-2 samplers; use \"permutedigits\", \"owen\" or \"none\""
        );
        assert_eq!(
            error(
                "Sampler \"zsobol\"\n  \"string randomization\" \"cranleypatterson\"",
                sampler
            ),
            "t.pbrt:2:3: unknown randomization \"cranleypatterson\": expected \"none\", \"permutedigits\", \"fastowen\" or \"owen\""
        );
        assert_eq!(
            clean(r#"Sampler "independent" "integer pixelsamples" 4"#, sampler),
            options(SamplerKind::Independent, 4, None)
        );
        let strata = |xsamples, ysamples, jitter| SamplerKind::Stratified {
            xsamples,
            ysamples,
            jitter,
        };
        assert_eq!(
            clean(r#"Sampler "stratified""#, sampler),
            options(strata(4, 4, true), 16, None)
        );
        assert_eq!(
            clean(
                r#"Sampler "stratified" "integer xsamples" 2 "integer ysamples" 3 "bool jitter" false"#,
                sampler
            ),
            options(strata(2, 3, false), 6, None)
        );
        // pbrt-v4 reads the seed as a 32-bit integer.
        assert_eq!(
            clean(r#"Sampler "zsobol" "integer seed" -1"#, sampler).seed,
            Some(u32::MAX as u64)
        );
        assert_eq!(
            warnings(r#"Sampler "magic""#, sampler),
            ["unknown sampler \"magic\"; lancer uses \"zsobol\""]
        );
        assert_eq!(
            error("Sampler \"zsobol\"\n  \"integer pixelsamples\" 0", sampler),
            "t.pbrt:2:3: \"integer pixelsamples\" must be between 1 and 16777216, not 0"
        );
        assert_eq!(
            error(
                "Sampler \"stratified\"\n  \"integer xsamples\" 5000",
                sampler
            ),
            "t.pbrt:2:3: \"integer xsamples\" must be between 1 and 4096, not 5000"
        );
    }

    #[test]
    fn option_seeds() {
        let seed_of = |p: &ParamList, _: &str| seed(p);
        assert_eq!(
            convert(r#"Option "integer seed" 5"#, seed_of).0,
            Ok(Some(5))
        );
        assert_eq!(
            convert(r#"Option "bool disablepixeljitter" true"#, seed_of).0,
            Ok(None)
        );
        assert_eq!(
            error("Option\n  \"float seed\" 5", seed_of),
            "t.pbrt:2:3: parameter 'seed' must be of type integer, not float"
        );
    }

    #[test]
    fn filters() {
        assert_eq!(
            clean(r#"PixelFilter "box""#, filter),
            FilterDesc::Box { radius: [0.5, 0.5] }
        );
        assert_eq!(
            clean(r#"PixelFilter "gaussian""#, filter),
            FilterDesc::Gaussian {
                radius: [1.5, 1.5],
                sigma: 0.5
            }
        );
        assert_eq!(
            clean(r#"PixelFilter "triangle""#, filter),
            FilterDesc::Triangle { radius: [2.0, 2.0] }
        );
        assert_eq!(
            clean(r#"PixelFilter "mitchell""#, filter),
            FilterDesc::Mitchell {
                radius: [2.0, 2.0],
                b: 1.0 / 3.0,
                c: 1.0 / 3.0
            }
        );
        assert_eq!(
            clean(r#"PixelFilter "sinc""#, filter),
            FilterDesc::Lanczos {
                radius: [4.0, 4.0],
                tau: 3.0
            }
        );
        assert_eq!(
            clean(
                r#"PixelFilter "gaussian" "float xradius" 1 "float yradius" 2 "float sigma" 0.25"#,
                filter
            ),
            FilterDesc::Gaussian {
                radius: [1.0, 2.0],
                sigma: 0.25
            }
        );
        assert_eq!(
            clean(
                r#"PixelFilter "mitchell" "float B" 0.5 "float C" 0.25"#,
                filter
            ),
            FilterDesc::Mitchell {
                radius: [2.0, 2.0],
                b: 0.5,
                c: 0.25
            }
        );
        assert_eq!(
            clean(r#"PixelFilter "lanczos" "float tau" 2"#, filter),
            FilterDesc::Lanczos {
                radius: [4.0, 4.0],
                tau: 2.0
            }
        );
        let (out, _) = convert(r#"PixelFilter "cubic""#, filter);
        let f = out.unwrap();
        assert_eq!(f.value, FilterDesc::default());
        assert_eq!(
            f.warnings,
            ["unknown pixel filter \"cubic\"; lancer uses \"gaussian\""]
        );
        assert_eq!(
            error("PixelFilter \"box\"\n  \"float xradius\" 0", filter),
            "t.pbrt:2:3: \"float xradius\" must be in (0, 64], not 0"
        );
        assert_eq!(
            error("PixelFilter \"gaussian\"\n  \"float sigma\" -1", filter),
            "t.pbrt:2:3: \"float sigma\" must be positive, not -1"
        );
    }

    #[test]
    fn integrators() {
        let path = |max_depth, regularize| Integrator::Path {
            max_depth,
            regularize,
        };
        assert_eq!(clean(r#"Integrator "path""#, integrator), path(5, false));
        // lancer's caustics by light tracing.
        assert_eq!(
            clean(r#"Integrator "path" "bool caustics" true"#, integrator),
            Integrator::PathCaustics {
                max_depth: 5,
                paths: 0.125
            }
        );
        assert_eq!(
            clean(
                r#"Integrator "path" "bool caustics" false "integer maxdepth" 7"#,
                integrator
            ),
            path(7, false)
        );
        assert_eq!(
            warnings(
                r#"Integrator "path" "bool caustics" true "float causticpaths" 0.5 "bool regularize" true"#,
                integrator
            ),
            ["\"regularize\" is ignored by \"path\" with \"caustics\""]
        );
        assert_eq!(
            error(
                "Integrator \"path\" \"bool caustics\" true\n  \"float causticpaths\" 2",
                integrator
            ),
            "t.pbrt:2:3: \"float causticpaths\" must be in (0, 1], not 2"
        );
        assert_eq!(
            clean(
                r#"Integrator "volpath" "integer maxdepth" 8 "bool regularize" true"#,
                integrator
            ),
            Integrator::VolPath {
                max_depth: 8,
                regularize: true
            }
        );
        let ls = |text: &str| clean(text, light_sampler);
        assert_eq!(ls(r#"Integrator "path""#), LightSamplerKind::Bvh);
        assert_eq!(
            ls(r#"Integrator "volpath" "string lightsampler" "power""#),
            LightSamplerKind::Power
        );
        assert_eq!(
            ls(r#"Integrator "path" "string lightsampler" "uniform""#),
            LightSamplerKind::Uniform
        );
        assert_eq!(
            warnings(
                r#"Integrator "path" "string lightsampler" "exhaustive""#,
                light_sampler
            ),
            ["light sampler \"exhaustive\" is not supported yet; lancer uses \"bvh\""]
        );
        assert_eq!(
            error(
                "Integrator \"path\"\n  \"string lightsampler\" \"magic\"",
                light_sampler
            ),
            "t.pbrt:2:3: unknown light sampler \"magic\": expected \"uniform\", \"power\" or \"bvh\""
        );
        assert_eq!(
            clean(r#"Integrator "whitted" "integer maxdepth" 3"#, integrator),
            Integrator::Whitted { max_depth: 3 }
        );
        assert_eq!(
            clean(r#"Integrator "ambientocclusion""#, integrator),
            Integrator::AmbientOcclusion {
                cos_sample: true,
                max_distance: f32::INFINITY
            }
        );
        assert_eq!(
            clean(
                r#"Integrator "ambientocclusion" "bool cossample" false "float maxdistance" 2"#,
                integrator
            ),
            Integrator::AmbientOcclusion {
                cos_sample: false,
                max_distance: 2.0
            }
        );
        assert_eq!(
            clean(r#"Integrator "normals""#, integrator),
            Integrator::Normals
        );
        assert_eq!(
            clean(r#"Integrator "depth""#, integrator),
            Integrator::Depth
        );
        assert_eq!(
            clean(r#"Integrator "bdpt" "integer maxdepth" 7"#, integrator),
            Integrator::Bdpt {
                max_depth: 7,
                regularize: false,
                visualize_strategies: false,
                visualize_weights: false
            }
        );
        assert_eq!(
            clean(r#"Integrator "bdpt" "bool regularize" true"#, integrator),
            Integrator::Bdpt {
                max_depth: 5,
                regularize: true,
                visualize_strategies: false,
                visualize_weights: false
            }
        );
        assert_eq!(
            clean(
                r#"Integrator "simplepath" "bool samplebsdf" false"#,
                integrator
            ),
            Integrator::SimplePath {
                max_depth: 5,
                sample_lights: true,
                sample_bsdf: false
            }
        );
        assert_eq!(
            clean(r#"Integrator "randomwalk""#, integrator),
            Integrator::RandomWalk { max_depth: 5 }
        );
        assert_eq!(
            clean(r#"Integrator "lightpath" "integer maxdepth" 3"#, integrator),
            Integrator::LightPath { max_depth: 3 }
        );
        assert_eq!(
            clean(r#"Integrator "simplevolpath""#, integrator),
            Integrator::SimpleVolPath { max_depth: 5 }
        );
        assert_eq!(
            clean(
                r#"Integrator "simplevolpath" "integer maxdepth" 9"#,
                integrator
            ),
            Integrator::SimpleVolPath { max_depth: 9 }
        );
        // The strategy images are written; with them, paths of at most 5 bounces (pbrt-v4).
        assert_eq!(
            clean(
                r#"Integrator "bdpt" "bool visualizestrategies" true"#,
                integrator
            ),
            Integrator::Bdpt {
                max_depth: 5,
                regularize: false,
                visualize_strategies: true,
                visualize_weights: false
            }
        );
        let (out, _) = convert(
            r#"Integrator "bdpt" "bool visualizeweights" true "integer maxdepth" 9"#,
            integrator,
        );
        let f = out.unwrap();
        assert_eq!(
            f.value,
            Integrator::Bdpt {
                max_depth: 5,
                regularize: false,
                visualize_strategies: false,
                visualize_weights: true
            }
        );
        assert!(
            f.warnings[0].contains("limit maxdepth to 5"),
            "{:?}",
            f.warnings
        );
        // sppm: pbrt-v4's defaults, every parameter read, a non-positive photon count meaning
        // one per pixel, and a radius that is not positive refused where it is written.
        assert_eq!(
            clean(r#"Integrator "sppm""#, integrator),
            Integrator::Sppm(SppmOptions {
                max_depth: 5,
                photons_per_iteration: None,
                radius: 1.0,
                seed: None,
            })
        );
        assert_eq!(
            clean(
                r#"Integrator "sppm" "integer maxdepth" 8 "integer photonsperiteration" 200000 "float radius" 0.03 "integer seed" 7"#,
                integrator
            ),
            Integrator::Sppm(SppmOptions {
                max_depth: 8,
                photons_per_iteration: Some(200_000),
                radius: 0.03,
                seed: Some(7),
            })
        );
        assert_eq!(
            clean(
                r#"Integrator "sppm" "integer photonsperiteration" 0"#,
                integrator
            ),
            Integrator::Sppm(SppmOptions {
                max_depth: 5,
                photons_per_iteration: None,
                radius: 1.0,
                seed: None,
            })
        );
        assert_eq!(
            error("Integrator \"sppm\"\n  \"float radius\" 0", integrator),
            "t.pbrt:2:3: \"float radius\" must be positive and finite, not 0"
        );
        // vcm: its defaults (the radius left to the scene), every parameter read, and the
        // values that mean nothing refused where they are written.
        assert_eq!(
            clean(r#"Integrator "vcm""#, integrator),
            Integrator::Vcm(VcmOptions {
                max_depth: 5,
                radius: None,
                alpha: 0.75,
            })
        );
        assert_eq!(
            clean(
                r#"Integrator "vcm" "integer maxdepth" 9 "float radius" 0.01 "float alpha" 1"#,
                integrator
            ),
            Integrator::Vcm(VcmOptions {
                max_depth: 9,
                radius: Some(0.01),
                alpha: 1.0,
            })
        );
        assert_eq!(
            error("Integrator \"vcm\"\n  \"float radius\" -0.5", integrator),
            "t.pbrt:2:3: \"float radius\" must be positive and finite, not -0.5"
        );
        assert_eq!(
            error("Integrator \"vcm\" \"float alpha\" 0", integrator),
            "t.pbrt:1:18: \"float alpha\" must be in (0, 1], not 0"
        );
        let (out, _) = convert(r#"Integrator "aov" "integer maxdepth" 7"#, integrator);
        let f = out.unwrap();
        assert_eq!(f.value, path(7, false));
        assert_eq!(
            f.warnings,
            ["integrator \"aov\" is not supported yet; lancer uses \"path\" with maxdepth 7"]
        );
        assert_eq!(
            warnings(r#"Integrator "photonmap""#, integrator),
            ["unknown integrator \"photonmap\"; lancer uses \"path\""]
        );
        assert_eq!(
            error("Integrator \"path\"\n  \"integer maxdepth\" -1", integrator),
            "t.pbrt:2:3: \"integer maxdepth\" must be between 0 and 100000, not -1"
        );
    }

    #[test]
    fn mlt_reads_pbrts_parameters_and_defaults() {
        use lancer::integrator::mlt::MltOptions;
        assert_eq!(
            clean(r#"Integrator "mlt""#, integrator),
            Integrator::Mlt(MltOptions {
                max_depth: 5,
                bootstrap_samples: 100_000,
                chains: 1000,
                mutations_per_pixel: 100,
                large_step_probability: 0.3,
                sigma: 0.01,
                regularize: false,
            })
        );
        assert_eq!(
            clean(
                r#"Integrator "mlt" "integer maxdepth" 7 "integer bootstrapsamples" 10 "integer chains" 3 "integer mutationsperpixel" 64 "float largestepprobability" 0.5 "float sigma" 0.02 "bool regularize" true"#,
                integrator
            ),
            Integrator::Mlt(MltOptions {
                max_depth: 7,
                bootstrap_samples: 10,
                chains: 3,
                mutations_per_pixel: 64,
                large_step_probability: 0.5,
                sigma: 0.02,
                regularize: true,
            })
        );
        assert_eq!(
            error("Integrator \"mlt\"\n  \"integer chains\" 0", integrator),
            "t.pbrt:2:3: \"integer chains\" must be between 1 and 16777216, not 0"
        );
        assert_eq!(
            error(
                "Integrator \"mlt\"\n  \"float largestepprobability\" 1.5",
                integrator
            ),
            "t.pbrt:2:3: \"float largestepprobability\" must be in [0, 1], not 1.5"
        );
        assert!(
            error(
                "Integrator \"mlt\" \"integer maxdepth\" 10000\n  \"integer bootstrapsamples\" 1000000",
                integrator
            )
            .starts_with("t.pbrt:2:3: integrator \"mlt\": \"bootstrapsamples\" × (\"maxdepth\" + 1)")
        );
    }
}

//! `Film "spectral"`: pbrt-v4's `SpectralFilm` buckets (see [`lancer::film::spectral`]).

use crate::error::SceneError;
use crate::pbrt::params::ParamList;

/// The buckets of a `spectral` film, as pbrt-v4's `SpectralFilm::Create`: `nbuckets` (16),
/// `lambdamin` (360) and `lambdamax` (830), the range within 360–830 nm (pbrt-v4 refuses
/// wider ones: its wavelength tables end there).
pub(super) fn buckets(
    params: &ParamList,
) -> Result<lancer::film::spectral::SpectralDesc, SceneError> {
    let nbuckets = params.int_in("nbuckets", 16, 1..=4096)? as u32;
    let lambda_min = params.float("lambdamin", 360.0)?;
    let lambda_max = params.float("lambdamax", 830.0)?;
    let (lo, hi) = (
        lancer::spectrum::sampled::LAMBDA_MIN,
        lancer::spectrum::sampled::LAMBDA_MAX,
    );
    if !(lambda_min >= lo && lambda_max <= hi && lambda_min < lambda_max) {
        let at = if params.has("lambdamin") {
            "lambdamin"
        } else {
            "lambdamax"
        };
        return Err(params.error_at(
            at,
            format!(
                "the spectral film's wavelengths [{lambda_min}, {lambda_max}] nm must lie \
                 within [{lo}, {hi}] nm, lambdamin below lambdamax (as in pbrt-v4)"
            ),
        ));
    }
    Ok(lancer::film::spectral::SpectralDesc {
        nbuckets,
        lambda_min,
        lambda_max,
    })
}

#[cfg(test)]
mod tests {
    use crate::pbrt::convert::testing::{err, typed, unused};
    use crate::pbrt::options::film;
    use lancer::scene::desc::FilmDesc;

    #[test]
    fn spectral_film_buckets_and_errors() {
        // Converted without warnings, every parameter read.
        let clean = |text: &str| {
            let (ty, params, _) = typed(text);
            let out = film(&params, &ty, FilmDesc::default()).unwrap_or_else(|e| panic!("{e}"));
            assert!(out.warnings.is_empty(), "{:?}", out.warnings);
            assert!(unused(&params).is_empty(), "{:?}", unused(&params));
            out.value
        };
        let error = |text: &str| {
            let (ty, params, _) = typed(text);
            err(film(&params, &ty, FilmDesc::default()))
        };
        let f = clean(r#"Film "spectral""#);
        assert_eq!(
            f.film.spectral,
            Some(lancer::film::spectral::SpectralDesc::default())
        );
        // pbrt-v4's spectral film writes half floats by default.
        assert!(f.film.save_fp16);
        let f = clean(
            r#"Film "spectral" "integer nbuckets" 4 "float lambdamin" 400 "float lambdamax" 700"#,
        );
        let d = f.film.spectral.unwrap();
        assert_eq!((d.nbuckets, d.lambda_min, d.lambda_max), (4, 400.0, 700.0));
        assert_eq!(
            error("Film \"spectral\"\n  \"float lambdamin\" 300"),
            "t.pbrt:2:3: the spectral film's wavelengths [300, 830] nm must lie within \
             [360, 830] nm, lambdamin below lambdamax (as in pbrt-v4)"
        );
    }
}

//! What every conversion of a directive shares: the [`Reader`] of its parameters against the
//! scene's named textures, folders and images, and the [`Fallback`] it returns.
//!
//! The conversions themselves live beside each kind, as pbrt-v4 puts `X::Create` beside each
//! type: [`super::shapes`], [`super::materials`], [`super::textures`], [`super::lights`],
//! [`super::media`], [`super::cameras`] and [`super::options`]. Each reads the parameters it
//! knows; the builder then reports the others as unused.

use super::params::{ColorParam, FloatParam, ParamList};
use super::search_path::SearchPath;
use crate::error::{Location, SceneError};
use crate::image_read::{Encoding, ImageCache};
use lancer::math::Rgb;
use lancer::spectrum::SpectrumKind;
use lancer::texture::{FloatTex, SpectrumTex};
use std::collections::HashMap;
use std::path::PathBuf;

/// Largest image side accepted (a film of 65536² pixels would already need ~100 GiB).
pub const MAX_RESOLUTION: i32 = 1 << 16;

/// What a conversion gives: always a value (what lancer renders), and the warnings that say
/// what it does instead of what the scene asked, if anything.
#[derive(Clone, Debug, PartialEq)]
pub struct Fallback<T> {
    /// The converted thing, or its stand-in.
    pub value: T,
    /// One message per thing lancer left out or replaced, in the order met.
    pub warnings: Vec<String>,
}

impl<T> Fallback<T> {
    /// Converted as asked.
    pub fn done(value: T) -> Fallback<T> {
        Fallback {
            value,
            warnings: Vec::new(),
        }
    }

    /// `value` stands in for what the scene asked, as `warning` says.
    pub fn instead(value: T, warning: impl Into<String>) -> Fallback<T> {
        Fallback {
            value,
            warnings: vec![warning.into()],
        }
    }

    /// `value` with the notes gathered while converting it folded into one warning (joined by
    /// "; "), or none.
    pub fn noted(value: T, notes: Vec<String>) -> Fallback<T> {
        Fallback {
            value,
            warnings: if notes.is_empty() {
                Vec::new()
            } else {
                vec![notes.join("; ")]
            },
        }
    }

    /// The same warnings about another value.
    pub fn map<U>(self, f: impl FnOnce(T) -> U) -> Fallback<U> {
        Fallback {
            value: f(self.value),
            warnings: self.warnings,
        }
    }
}

/// Gives an error without a place the place of the directive it came from.
pub fn locate(mut e: SceneError, loc: &Location) -> SceneError {
    if e.location.is_none() {
        e.location = Some(loc.clone());
    }
    e
}

/// Named textures defined so far, by kind.
#[derive(Default)]
pub struct TextureNames {
    /// Float textures: name → index in the scene's list.
    pub floats: HashMap<String, u32>,
    /// Spectrum textures: name → index.
    pub spectra: HashMap<String, u32>,
    /// The spectrum textures whose unbounded variant differs (they hold a spectrum-valued
    /// parameter, or refer to such a texture): name → index of that variant. The others read
    /// the same either way.
    pub unbounded: HashMap<String, u32>,
}

impl TextureNames {
    /// The float texture `name`, referred to at `loc`.
    pub fn float(&self, name: &str, loc: &Location) -> Result<FloatTex, SceneError> {
        match self.floats.get(name) {
            Some(&i) => Ok(FloatTex::Tex(i)),
            None => Err(Self::missing("float", "spectrum", &self.spectra, name, loc)),
        }
    }

    /// The spectrum texture `name`, referred to at `loc`.
    pub fn spectrum(&self, name: &str, loc: &Location) -> Result<SpectrumTex, SceneError> {
        match self.spectra.get(name) {
            Some(&i) => Ok(SpectrumTex::Tex(i)),
            None => Err(Self::missing("spectrum", "float", &self.floats, name, loc)),
        }
    }

    /// The spectrum texture `name` read as `kind`: its unbounded variant when it has one and
    /// `kind` is unbounded (pbrt-v4's `SpectrumType::Unbounded` textures).
    pub fn spectrum_as(
        &self,
        name: &str,
        loc: &Location,
        kind: SpectrumKind,
    ) -> Result<SpectrumTex, SceneError> {
        match self.unbounded.get(name) {
            Some(&i) if kind == SpectrumKind::Unbounded => Ok(SpectrumTex::Tex(i)),
            _ => self.spectrum(name, loc),
        }
    }

    /// No `kind` texture is called `name`; says so, and whether one of the `other` kind is.
    fn missing(
        kind: &str,
        other: &str,
        others: &HashMap<String, u32>,
        name: &str,
        loc: &Location,
    ) -> SceneError {
        let hint = if others.contains_key(name) {
            format!(" (there is a {other} texture of that name)")
        } else {
            String::new()
        };
        SceneError::at(
            loc.clone(),
            format!("no {kind} texture named \"{name}\"{hint}"),
        )
    }
}

/// Reads parameters against the scene's textures and the directive's folder.
pub struct Reader<'a> {
    /// The parameters.
    pub params: &'a ParamList,
    /// Textures defined so far.
    pub textures: &'a TextureNames,
    /// The folder of the file holding the directive.
    pub dir: &'a SearchPath,
    /// Images decoded so far in this scene.
    pub images: &'a ImageCache,
}

impl Reader<'_> {
    /// A colour or spectrum texture `name`, or the constant `default`.
    pub fn spectrum_tex(
        &self,
        name: &str,
        default: Rgb,
        kind: SpectrumKind,
    ) -> Result<SpectrumTex, SceneError> {
        self.spectrum_tex_or(name, SpectrumTex::Const(default), kind)
    }

    /// A colour or spectrum texture `name`, or `default` (a spectrum, say).
    pub fn spectrum_tex_or(
        &self,
        name: &str,
        default: SpectrumTex,
        kind: SpectrumKind,
    ) -> Result<SpectrumTex, SceneError> {
        Ok(match self.params.color_or_texture(name, kind, self.dir)? {
            None => default,
            Some(ColorParam::Const(c)) => SpectrumTex::Const(c),
            Some(ColorParam::Measured(m)) => SpectrumTex::Measured(m),
            Some(ColorParam::Texture(t, loc)) => self.textures.spectrum_as(&t, &loc, kind)?,
        })
    }

    /// A colour or spectrum texture `name`, if given.
    pub fn opt_spectrum_tex(
        &self,
        name: &str,
        kind: SpectrumKind,
    ) -> Result<Option<SpectrumTex>, SceneError> {
        if self.params.has(name) {
            self.spectrum_tex(name, Rgb::ZERO, kind).map(Some)
        } else {
            Ok(None)
        }
    }

    /// A float or float texture `name`, or the constant `default`.
    pub fn float_tex(&self, name: &str, default: f32) -> Result<FloatTex, SceneError> {
        Ok(match self.params.float_or_texture(name)? {
            None => FloatTex::Const(default),
            Some(FloatParam::Const(v)) => FloatTex::Const(v),
            Some(FloatParam::Texture(t, loc)) => self.textures.float(&t, &loc)?,
        })
    }

    /// The file named by `string filename`, resolved against the directive's folders;
    /// `needs` completes the error when it is missing ("a \"plymesh\" needs the name of its
    /// PLY file").
    pub fn file(&self, needs: &str) -> Result<PathBuf, SceneError> {
        match self.params.string("filename")? {
            Some(name) => Ok(self.dir.resolve(&name)),
            None => Err(SceneError::general(format!("{needs}, \"string filename\""))),
        }
    }

    /// The image file named by `filename`, resolved against the directive's folders, and the
    /// `encoding` its 8- and 16-bit values go through (pbrt-v4's default: sRGB for `.png`,
    /// linear otherwise; JPEG is sRGB whatever it says, as in pbrt-v4).
    pub fn image_file(&self, what: &str) -> Result<(PathBuf, Encoding), SceneError> {
        let path = self.file(&format!("{what} needs the name of its image"))?;
        let is_png = path
            .extension()
            .and_then(|e| e.to_str())
            .is_some_and(|e| e.eq_ignore_ascii_case("png"));
        let encoding = match self.params.string("encoding")? {
            None if is_png => Encoding::Srgb,
            None => Encoding::Linear,
            Some(e) => Encoding::parse(&e).ok_or_else(|| {
                self.params.error_at(
                    "encoding",
                    format!(
                        "unknown encoding \"{e}\" (expected \"sRGB\", \"linear\" or \"gamma G\")"
                    ),
                )
            })?,
        };
        Ok((path, encoding))
    }
}

/// Parameter lists with locations for the unit tests of each kind: the directives of a small
/// scene text, read by the real parser.
#[cfg(test)]
pub mod testing {
    use super::super::parser::{Directive, Located, Parser};
    use super::*;
    use std::path::Path;

    /// Every directive of `text` (named `t.pbrt`, relative names against `dir`).
    pub fn directives(text: &str, dir: &Path) -> Vec<Located> {
        let mut parser = Parser::from_str(text, "t.pbrt", dir);
        let mut out = Vec::new();
        while let Some(d) = parser.next_directive().unwrap_or_else(|e| panic!("{e}")) {
            out.push(d);
        }
        out
    }

    /// The type, parameters and place of the one directive of `text` that has a type and a
    /// parameter list (`Shape "sphere" …`, `Material "diffuse" …`, …).
    pub fn typed(text: &str) -> (String, ParamList, Location) {
        typed_in(text, Path::new("."))
    }

    /// [`typed`], with relative names against `dir`.
    pub fn typed_in(text: &str, dir: &Path) -> (String, ParamList, Location) {
        let mut ds = directives(text, dir);
        assert_eq!(ds.len(), 1, "one directive in {text:?}");
        let d = ds.pop().expect("one");
        use Directive as D;
        let (ty, params) = match d.directive {
            D::Shape(t, p)
            | D::Material(t, p)
            | D::LightSource(t, p)
            | D::AreaLightSource(t, p)
            | D::Camera(t, p)
            | D::Film(t, p)
            | D::Sampler(t, p)
            | D::PixelFilter(t, p)
            | D::Integrator(t, p) => (t, p),
            D::Texture(_, _, class, p) => (class, p),
            D::Option(p) => (String::new(), p),
            other => panic!("not a typed directive: {other:?}"),
        };
        (ty, params, d.loc)
    }

    /// Reads with no named textures and images decoded afresh.
    pub fn with_reader<T>(params: &ParamList, dir: &Path, f: impl FnOnce(&Reader) -> T) -> T {
        let textures = TextureNames::default();
        with_textures(params, dir, &textures, f)
    }

    /// Reads against `textures`.
    pub fn with_textures<T>(
        params: &ParamList,
        dir: &Path,
        textures: &TextureNames,
        f: impl FnOnce(&Reader) -> T,
    ) -> T {
        let dir = SearchPath::new(dir);
        let images = ImageCache::default();
        f(&Reader {
            params,
            textures,
            dir: &dir,
            images: &images,
        })
    }

    /// The messages of the parameters nobody read.
    pub fn unused(params: &ParamList) -> Vec<String> {
        let mut w = Vec::new();
        params.report_unused("X", &mut w);
        w.into_iter().map(|w| w.to_string()).collect()
    }

    /// An error's text, with its place.
    pub fn err<T: std::fmt::Debug>(r: Result<T, SceneError>) -> String {
        r.expect_err("an error").to_string()
    }
}

#[cfg(test)]
mod tests {
    use super::testing::{err, typed, with_reader};
    use super::*;
    use std::path::Path;

    #[test]
    fn a_fallback_always_has_a_value() {
        let done = Fallback::done(1);
        assert_eq!((done.value, done.warnings.len()), (1, 0));
        let instead = Fallback::instead(2, "used 2").map(|v| v * 10);
        assert_eq!(
            instead,
            Fallback {
                value: 20,
                warnings: vec!["used 2".into()]
            }
        );
        // Notes fold into one warning, or none.
        let noted = Fallback::noted(3, vec!["a".into(), "b".into()]);
        assert_eq!(noted.warnings, ["a; b"]);
        assert!(Fallback::noted(3, Vec::new()).warnings.is_empty());
    }

    #[test]
    fn errors_get_the_directive_place_when_they_have_none() {
        let (_, _, loc) = typed("\n  Shape \"sphere\"");
        assert_eq!(
            locate(SceneError::general("bad"), &loc).to_string(),
            "t.pbrt:2:3: bad"
        );
        let own = SceneError::at(
            Location {
                line: 9,
                ..loc.clone()
            },
            "bad",
        );
        assert_eq!(locate(own, &loc).to_string(), "t.pbrt:9:3: bad");
    }

    #[test]
    fn texture_names_are_looked_up_by_kind() {
        let (_, _, loc) = typed("Shape \"sphere\"");
        let mut names = TextureNames::default();
        names.floats.insert("f".into(), 1);
        names.spectra.insert("s".into(), 2);
        assert_eq!(names.float("f", &loc), Ok(FloatTex::Tex(1)));
        assert_eq!(names.spectrum("s", &loc), Ok(SpectrumTex::Tex(2)));
        assert_eq!(
            err(names.float("s", &loc)),
            "t.pbrt:1:1: no float texture named \"s\" (there is a spectrum texture of that name)"
        );
        assert_eq!(
            err(names.spectrum("x", &loc)),
            "t.pbrt:1:1: no spectrum texture named \"x\""
        );
    }

    #[test]
    fn files_resolve_against_the_scene_folder_and_images_get_their_encoding() {
        let dir = Path::new("scenes");
        let (_, params, _) =
            typed(r#"Texture "t" "spectrum" "imagemap" "string filename" "a.png""#);
        let (path, encoding) = with_reader(&params, dir, |r| r.image_file("x")).unwrap();
        assert_eq!((path, encoding), (dir.join("a.png"), Encoding::Srgb));
        let (_, params, _) = typed(
            r#"Texture "t" "spectrum" "imagemap" "string filename" "a.png" "string encoding" "linear""#,
        );
        let (_, encoding) = with_reader(&params, dir, |r| r.image_file("x")).unwrap();
        assert_eq!(encoding, Encoding::Linear);
        let (_, params, _) =
            typed(r#"Texture "t" "spectrum" "imagemap" "string filename" "a.exr""#);
        let (_, encoding) = with_reader(&params, dir, |r| r.image_file("x")).unwrap();
        assert_eq!(encoding, Encoding::Linear);
        let (_, params, _) = typed(r#"Shape "plymesh""#);
        assert_eq!(
            err(with_reader(&params, dir, |r| r.file("a \"plymesh\" needs a file"))),
            "a \"plymesh\" needs a file, \"string filename\""
        );
    }
}

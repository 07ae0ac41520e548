//! The pbrt parser: tokens → directives, one at a time, with `Include` and `Import` followed
//! into the named files (gzip-compressed or not). Relative file names are looked up as pbrt-v4
//! does, in the folder of the scene file given on the command line, and then in the folder of
//! the file that names them ([`SearchPath`]).
//!
//! As in pbrt-v4, an `Include`d file is only more tokens: when it ends, its last directive may
//! go on with the parameters that follow the `Include` line. An `Import`ed file is a stream of
//! its own, framed by [`Directive::ImportBegin`] and [`Directive::ImportEnd`] so that the
//! builder can give it a copy of the graphics state.
//!
//! The parser knows every directive of pbrt-v4 (and pbrt-v3's `TransformBegin`/`End`,
//! `WorldEnd`) and the shape of its arguments; what the directives *mean* is the builder's
//! business ([`super::builder`]).

use super::lexer::{Lexer, Token, TokenKind, decode_utf8};
use super::params::{Param, ParamList, RawValue};
use super::search_path::SearchPath;
use crate::error::{Location, SceneError};
use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// Deepest chain of `Include`s accepted (a file that includes itself is caught earlier).
pub const MAX_INCLUDE_DEPTH: usize = 32;

/// A directive with its arguments.
#[derive(Debug)]
pub enum Directive {
    /// `Identity`
    Identity,
    /// `Translate dx dy dz`
    Translate([f32; 3]),
    /// `Scale sx sy sz`
    Scale([f32; 3]),
    /// `Rotate angle x y z`
    Rotate([f32; 4]),
    /// `LookAt ex ey ez lx ly lz ux uy uz`
    LookAt([f32; 9]),
    /// `Transform m00 … m33` (column-major)
    Transform([f32; 16]),
    /// `ConcatTransform m00 … m33` (column-major)
    ConcatTransform([f32; 16]),
    /// `CoordinateSystem "name"`
    CoordinateSystem(String),
    /// `CoordSysTransform "name"`
    CoordSysTransform(String),
    /// `ActiveTransform StartTime|EndTime|All`
    ActiveTransform(String),
    /// `TransformTimes start end`
    TransformTimes([f32; 2]),
    /// `ReverseOrientation`
    ReverseOrientation,
    /// `AttributeBegin`
    AttributeBegin,
    /// `AttributeEnd`
    AttributeEnd,
    /// `TransformBegin` (pbrt-v3)
    TransformBegin,
    /// `TransformEnd` (pbrt-v3)
    TransformEnd,
    /// `Attribute "target" params`
    Attribute(String, ParamList),
    /// `WorldBegin`
    WorldBegin,
    /// `WorldEnd` (pbrt-v3)
    WorldEnd,
    /// `Option params`
    Option(ParamList),
    /// `ColorSpace "name"`
    ColorSpace(String),
    /// `Camera "type" params`
    Camera(String, ParamList),
    /// `Film "type" params`
    Film(String, ParamList),
    /// `Sampler "type" params`
    Sampler(String, ParamList),
    /// `PixelFilter "type" params`
    PixelFilter(String, ParamList),
    /// `Integrator "type" params`
    Integrator(String, ParamList),
    /// `Accelerator "type" params`
    Accelerator(String, ParamList),
    /// `MakeNamedMedium "name" params`
    MakeNamedMedium(String, ParamList),
    /// `MediumInterface "inside" ["outside"]`
    MediumInterface(String, String),
    /// `Material "type" params`
    Material(String, ParamList),
    /// `MakeNamedMaterial "name" params`
    MakeNamedMaterial(String, ParamList),
    /// `NamedMaterial "name"`
    NamedMaterial(String),
    /// `Texture "name" "type" "class" params`
    Texture(String, String, String, ParamList),
    /// `LightSource "type" params`
    LightSource(String, ParamList),
    /// `AreaLightSource "type" params`
    AreaLightSource(String, ParamList),
    /// `Shape "type" params`
    Shape(String, ParamList),
    /// `ObjectBegin "name"`
    ObjectBegin(String),
    /// `ObjectEnd`
    ObjectEnd,
    /// `ObjectInstance "name"`
    ObjectInstance(String),
    /// `Import "file"`: the directives of `file` follow, then [`Directive::ImportEnd`].
    ImportBegin(String),
    /// The end of an imported file.
    ImportEnd,
}

/// A directive, where it starts, and where its relative file names point.
#[derive(Debug)]
pub struct Located {
    /// The directive.
    pub directive: Directive,
    /// Where its name starts.
    pub loc: Location,
    /// Where its relative file names are looked for.
    pub dir: SearchPath,
}

struct Source {
    lexer: Lexer,
    dir: SearchPath,
    /// Canonical path, to catch a file that includes itself.
    canonical: Option<PathBuf>,
    /// A token read ahead.
    peeked: Option<Token>,
    /// Read for an `Import`: a stream of its own, which its directives cannot leave.
    import: bool,
}

/// Reads directives from a scene file and the files it includes.
pub struct Parser {
    stack: Vec<Source>,
    /// Every file's text, by the name used in locations (for error excerpts).
    sources: HashMap<Arc<str>, Arc<str>>,
}

/// Reads a file (gunzipped when compressed) as UTF-8 text; `at` is where it was asked for (an
/// `Include`), if anywhere.
fn read_text(path: &Path, name: &Arc<str>, at: Option<&Location>) -> Result<String, SceneError> {
    let bytes = crate::files_read::read_maybe_gzipped(path).map_err(|e| {
        let what = if at.is_some() {
            "cannot read included file"
        } else {
            "cannot read scene"
        };
        let message = format!("{what} {}: {}", path.display(), io_reason(&e));
        match at {
            Some(l) => SceneError::at(l.clone(), message),
            None => SceneError::general(message),
        }
    })?;
    decode_utf8(&bytes, name)
}

/// An I/O error in a few words.
fn io_reason(e: &std::io::Error) -> String {
    match e.kind() {
        std::io::ErrorKind::NotFound => "no such file".to_string(),
        std::io::ErrorKind::PermissionDenied => "permission denied".to_string(),
        std::io::ErrorKind::IsADirectory => "it is a folder".to_string(),
        _ => e.to_string(),
    }
}

const DIRECTIVES: &[&str] = &[
    "Accelerator",
    "ActiveTransform",
    "AreaLightSource",
    "Attribute",
    "AttributeBegin",
    "AttributeEnd",
    "Camera",
    "ColorSpace",
    "ConcatTransform",
    "CoordinateSystem",
    "CoordSysTransform",
    "Film",
    "Identity",
    "Import",
    "Include",
    "Integrator",
    "LightSource",
    "LookAt",
    "MakeNamedMaterial",
    "MakeNamedMedium",
    "Material",
    "MediumInterface",
    "NamedMaterial",
    "ObjectBegin",
    "ObjectEnd",
    "ObjectInstance",
    "Option",
    "PixelFilter",
    "ReverseOrientation",
    "Rotate",
    "Sampler",
    "Scale",
    "Shape",
    "Texture",
    "Transform",
    "TransformBegin",
    "TransformEnd",
    "TransformTimes",
    "Translate",
    "WorldBegin",
    "WorldEnd",
];

/// The directive closest in spelling to `word`, for "did you mean" hints.
fn closest_directive(word: &str) -> Option<&'static str> {
    let lower = word.to_ascii_lowercase();
    DIRECTIVES
        .iter()
        .map(|d| (edit_distance(&lower, &d.to_ascii_lowercase()), *d))
        .filter(|(dist, _)| *dist <= 2)
        .min()
        .map(|(_, d)| d)
}

fn edit_distance(a: &str, b: &str) -> usize {
    let b: Vec<char> = b.chars().collect();
    let mut row: Vec<usize> = (0..=b.len()).collect();
    for (i, ca) in a.chars().enumerate() {
        let mut prev = row[0];
        row[0] = i + 1;
        for (j, cb) in b.iter().enumerate() {
            let cur = row[j + 1];
            row[j + 1] = (prev + usize::from(ca != *cb)).min(row[j] + 1).min(cur + 1);
            prev = cur;
        }
    }
    row[b.len()]
}

impl Parser {
    /// A parser over a scene file.
    pub fn from_file(path: &Path) -> Result<Parser, SceneError> {
        let name: Arc<str> = Arc::from(path.display().to_string());
        let text = read_text(path, &name, None)?;
        let mut p = Parser {
            stack: Vec::new(),
            sources: HashMap::new(),
        };
        p.push(text, name, path, false);
        Ok(p)
    }

    /// A parser over scene text held in memory, named `name` in messages, with relative file
    /// names resolved against `dir`.
    pub fn from_str(text: &str, name: &str, dir: &Path) -> Parser {
        let name: Arc<str> = Arc::from(name);
        let src: Arc<str> = Arc::from(text);
        Parser {
            stack: vec![Source {
                lexer: Lexer::new(src.clone(), name.clone()),
                dir: SearchPath::new(dir),
                canonical: None,
                peeked: None,
                import: false,
            }],
            sources: HashMap::from([(name, src)]),
        }
    }

    fn push(&mut self, text: String, name: Arc<str>, path: &Path, import: bool) {
        let src: Arc<str> = Arc::from(text);
        // A file in the working folder has the empty folder, so that the files it includes
        // are named as plainly as it is.
        let dir: Arc<Path> = Arc::from(path.parent().unwrap_or(Path::new("")));
        let scene = match self.stack.first() {
            Some(main) => main.dir.scene.clone(),
            None => dir.clone(),
        };
        self.sources.insert(name.clone(), src.clone());
        self.stack.push(Source {
            lexer: Lexer::new(src, name),
            dir: SearchPath { scene, file: dir },
            canonical: path.canonicalize().ok(),
            peeked: None,
            import,
        });
    }

    /// The text of a file read so far, by its name in locations.
    pub fn source(&self, file: &str) -> Option<&str> {
        self.sources.get(file).map(|s| &**s)
    }

    /// Reads a token ahead in the innermost file; at the end of an `Include`d file, goes on
    /// in the file that includes it, as pbrt-v4's stack of token streams does. Stops at the
    /// end of the main file and of an `Import`ed one (`false`).
    fn fill(&mut self) -> Result<bool, SceneError> {
        loop {
            let depth = self.stack.len();
            let Some(top) = self.stack.last_mut() else {
                return Ok(false);
            };
            if top.peeked.is_none() {
                top.peeked = top.lexer.next_token()?;
            }
            if top.peeked.is_some() {
                return Ok(true);
            }
            if top.import || depth == 1 {
                return Ok(false);
            }
            self.stack.pop();
        }
    }

    /// The next token, `None` at the end of the main file or of an imported one.
    fn next(&mut self) -> Result<Option<Token>, SceneError> {
        if !self.fill()? {
            return Ok(None);
        }
        Ok(self.stack.last_mut().and_then(|s| s.peeked.take()))
    }

    fn peek(&mut self) -> Result<Option<&Token>, SceneError> {
        if !self.fill()? {
            return Ok(None);
        }
        Ok(self.stack.last().and_then(|s| s.peeked.as_ref()))
    }

    /// The start of the main file (for messages about a scene as a whole).
    pub fn start_location(&self) -> Location {
        let name = self
            .stack
            .first()
            .map(|s| s.lexer.location().file)
            .or_else(|| self.sources.keys().next().cloned())
            .unwrap_or_else(|| std::sync::Arc::from("<scene>"));
        Location {
            file: name,
            line: 1,
            col: 1,
        }
    }

    fn end_location(&self) -> Location {
        self.stack
            .last()
            .map(|s| s.lexer.location())
            .expect("a file is open")
    }

    fn describe(t: &Token) -> String {
        match t.kind {
            TokenKind::Word => format!("'{}'", t.text),
            TokenKind::Str => format!("the string \"{}\"", t.text),
            TokenKind::Number => format!("the number {}", t.number),
            TokenKind::Open | TokenKind::Close => format!("'{}'", t.text),
        }
    }

    /// A quoted string argument of `directive`.
    fn string_arg(&mut self, directive: &str, what: &str) -> Result<String, SceneError> {
        match self.next()? {
            Some(t) if t.kind == TokenKind::Str => Ok(t.text),
            Some(t) => Err(SceneError::at(
                t.loc.clone(),
                format!(
                    "{directive} expects {what} in quotes, found {}",
                    Self::describe(&t)
                ),
            )),
            None => Err(SceneError::at(
                self.end_location(),
                format!("{directive} expects {what}, but the file ends"),
            )),
        }
    }

    /// `N` numbers, bare or in one pair of brackets.
    fn numbers<const N: usize>(&mut self, directive: &str) -> Result<[f32; N], SceneError> {
        let mut out = [0.0; N];
        let bracket = match self.peek()? {
            Some(t) if t.kind == TokenKind::Open => Some(self.next()?.expect("peeked").loc),
            _ => None,
        };
        for (i, v) in out.iter_mut().enumerate() {
            match self.next()? {
                Some(t) if t.kind == TokenKind::Number => *v = t.number as f32,
                Some(t) => {
                    let hint = if t.kind == TokenKind::Word
                        && matches!(
                            t.text.to_ascii_lowercase().as_str(),
                            "nan" | "inf" | "infinity"
                        ) {
                        format!("'{}' is not a finite number", t.text)
                    } else {
                        format!(
                            "{directive} expects {N} numbers, found {} after {i}",
                            Self::describe(&t)
                        )
                    };
                    return Err(SceneError::at(t.loc.clone(), hint));
                }
                None => {
                    return Err(SceneError::at(
                        self.end_location(),
                        format!("{directive} expects {N} numbers, but the file ends after {i}"),
                    ));
                }
            }
        }
        if let Some(open) = bracket {
            match self.next()? {
                Some(t) if t.kind == TokenKind::Close => {}
                Some(t) => {
                    return Err(SceneError::at(
                        t.loc.clone(),
                        format!(
                            "{directive} expects exactly {N} numbers, found {} where ']' should be",
                            Self::describe(&t)
                        ),
                    ));
                }
                None => {
                    return Err(SceneError::at(
                        open,
                        "this '[' is never closed: the file ends first",
                    ));
                }
            }
        }
        Ok(out)
    }

    /// The value(s) of a parameter: one value, or a bracketed list.
    fn param_values(
        &mut self,
        decl: &str,
        decl_loc: &Location,
    ) -> Result<Vec<(RawValue, Location)>, SceneError> {
        let raw = |t: Token| -> Result<(RawValue, Location), SceneError> {
            let v = match t.kind {
                TokenKind::Number => RawValue::Number(t.number, t.integral),
                TokenKind::Str => RawValue::Str(t.text),
                TokenKind::Word if t.text == "true" => RawValue::Bool(true),
                TokenKind::Word if t.text == "false" => RawValue::Bool(false),
                TokenKind::Word
                    if matches!(
                        t.text.to_ascii_lowercase().as_str(),
                        "nan" | "inf" | "infinity"
                    ) =>
                {
                    return Err(SceneError::at(
                        t.loc,
                        format!("'{}' is not a finite number", t.text),
                    ));
                }
                _ => {
                    return Err(SceneError::at(
                        t.loc.clone(),
                        format!(
                            "parameter \"{decl}\" expects a value, found {}",
                            Self::describe(&t)
                        ),
                    ));
                }
            };
            Ok((v, t.loc))
        };
        match self.next()? {
            Some(t) if t.kind == TokenKind::Open => {
                let open = t.loc;
                let mut out = Vec::new();
                loop {
                    match self.next()? {
                        Some(t) if t.kind == TokenKind::Close => return Ok(out),
                        Some(t) if t.kind == TokenKind::Open => {
                            return Err(SceneError::at(t.loc, "'[' inside a bracketed list"));
                        }
                        Some(t) => out.push(raw(t)?),
                        None => {
                            return Err(SceneError::at(
                                open,
                                "this '[' is never closed: the file ends first",
                            ));
                        }
                    }
                }
            }
            Some(t) => Ok(vec![raw(t)?]),
            None => Err(SceneError::at(
                decl_loc.clone(),
                format!("parameter \"{decl}\" has no value: the file ends"),
            )),
        }
    }

    /// A parameter list: `"type name" value` pairs until the next directive.
    fn params(&mut self) -> Result<ParamList, SceneError> {
        let mut params = Vec::new();
        while let Some(t) = self.peek()? {
            match t.kind {
                TokenKind::Str => {
                    let t = self.next()?.expect("peeked");
                    let values = self.param_values(&t.text, &t.loc)?;
                    params.push(Param::new(&t.text, t.loc, values)?);
                }
                TokenKind::Word => break,
                _ => {
                    let t = self.next()?.expect("peeked");
                    return Err(SceneError::at(
                        t.loc.clone(),
                        format!(
                            "expected a parameter (\"type name\" value) or a directive, found {}",
                            Self::describe(&t)
                        ),
                    ));
                }
            }
        }
        ParamList::new(params)
    }

    /// Opens the file an `Include` or `Import` names; gives its name as written.
    fn include(
        &mut self,
        loc: &Location,
        dir: &SearchPath,
        what: &str,
    ) -> Result<String, SceneError> {
        let file = self.string_arg(what, "a file name")?;
        let path = dir.resolve(&file);
        if self.stack.len() >= MAX_INCLUDE_DEPTH {
            return Err(SceneError::at(
                loc.clone(),
                format!("{what} nested more than {MAX_INCLUDE_DEPTH} files deep"),
            ));
        }
        if let Ok(c) = path.canonicalize()
            && self.stack.iter().any(|s| s.canonical.as_ref() == Some(&c))
        {
            return Err(SceneError::at(
                loc.clone(),
                format!("{what} \"{file}\" includes a file that is already being read (a cycle)"),
            ));
        }
        let name: Arc<str> = Arc::from(path.display().to_string());
        let text = read_text(&path, &name, Some(loc))?;
        self.push(text, name, &path, what == "Import");
        Ok(file)
    }

    /// The next directive, `None` when every file is read.
    pub fn next_directive(&mut self) -> Result<Option<Located>, SceneError> {
        loop {
            let Some(t) = self.next()? else {
                let Some(ended) = self.stack.pop() else {
                    return Ok(None);
                };
                if !ended.import {
                    self.stack.clear();
                    return Ok(None);
                }
                return Ok(Some(Located {
                    directive: Directive::ImportEnd,
                    loc: ended.lexer.location(),
                    dir: ended.dir,
                }));
            };
            let loc = t.loc.clone();
            let dir = self.stack.last().expect("open").dir.clone();
            if t.kind != TokenKind::Word {
                return Err(SceneError::at(
                    loc,
                    format!("expected a directive, found {}", Self::describe(&t)),
                ));
            }
            use Directive as D;
            let name = t.text.as_str();
            let directive = match name {
                "Include" => {
                    self.include(&loc, &dir, name)?;
                    continue;
                }
                "Import" => D::ImportBegin(self.include(&loc, &dir, name)?),
                "Identity" => D::Identity,
                "Translate" => D::Translate(self.numbers(name)?),
                "Scale" => D::Scale(self.numbers(name)?),
                "Rotate" => D::Rotate(self.numbers(name)?),
                "LookAt" => D::LookAt(self.numbers(name)?),
                "Transform" => D::Transform(self.numbers(name)?),
                "ConcatTransform" => D::ConcatTransform(self.numbers(name)?),
                "TransformTimes" => D::TransformTimes(self.numbers(name)?),
                "CoordinateSystem" => D::CoordinateSystem(self.string_arg(name, "a name")?),
                "CoordSysTransform" => D::CoordSysTransform(self.string_arg(name, "a name")?),
                "ActiveTransform" => match self.next()? {
                    Some(t)
                        if t.kind == TokenKind::Word
                            && matches!(t.text.as_str(), "StartTime" | "EndTime" | "All") =>
                    {
                        D::ActiveTransform(t.text)
                    }
                    Some(t) => {
                        return Err(SceneError::at(
                            t.loc.clone(),
                            format!(
                                "ActiveTransform expects StartTime, EndTime or All, found {}",
                                Self::describe(&t)
                            ),
                        ));
                    }
                    None => {
                        return Err(SceneError::at(
                            self.end_location(),
                            "ActiveTransform expects StartTime, EndTime or All, but the file ends",
                        ));
                    }
                },
                "ReverseOrientation" => D::ReverseOrientation,
                "AttributeBegin" => D::AttributeBegin,
                "AttributeEnd" => D::AttributeEnd,
                "TransformBegin" => D::TransformBegin,
                "TransformEnd" => D::TransformEnd,
                "Attribute" => D::Attribute(self.string_arg(name, "a target")?, self.params()?),
                "WorldBegin" => D::WorldBegin,
                "WorldEnd" => D::WorldEnd,
                "Option" => D::Option(self.params()?),
                "ColorSpace" => D::ColorSpace(self.string_arg(name, "a colour space name")?),
                "Camera" => D::Camera(self.string_arg(name, "a type")?, self.params()?),
                "Film" => D::Film(self.string_arg(name, "a type")?, self.params()?),
                "Sampler" => D::Sampler(self.string_arg(name, "a type")?, self.params()?),
                "PixelFilter" => D::PixelFilter(self.string_arg(name, "a type")?, self.params()?),
                "Integrator" => D::Integrator(self.string_arg(name, "a type")?, self.params()?),
                "Accelerator" => D::Accelerator(self.string_arg(name, "a type")?, self.params()?),
                "MakeNamedMedium" => {
                    D::MakeNamedMedium(self.string_arg(name, "a name")?, self.params()?)
                }
                "MediumInterface" => {
                    let inside = self.string_arg(name, "a medium name")?;
                    let outside = match self.peek()? {
                        Some(t) if t.kind == TokenKind::Str => self.next()?.expect("peeked").text,
                        _ => inside.clone(),
                    };
                    D::MediumInterface(inside, outside)
                }
                "Material" => D::Material(self.string_arg(name, "a type")?, self.params()?),
                "MakeNamedMaterial" => {
                    D::MakeNamedMaterial(self.string_arg(name, "a name")?, self.params()?)
                }
                "NamedMaterial" => D::NamedMaterial(self.string_arg(name, "a name")?),
                "Texture" => D::Texture(
                    self.string_arg(name, "a name")?,
                    self.string_arg(name, "a type (\"float\" or \"spectrum\")")?,
                    self.string_arg(name, "a class")?,
                    self.params()?,
                ),
                "LightSource" => D::LightSource(self.string_arg(name, "a type")?, self.params()?),
                "AreaLightSource" => {
                    D::AreaLightSource(self.string_arg(name, "a type")?, self.params()?)
                }
                "Shape" => D::Shape(self.string_arg(name, "a type")?, self.params()?),
                "ObjectBegin" => D::ObjectBegin(self.string_arg(name, "a name")?),
                "ObjectEnd" => D::ObjectEnd,
                "ObjectInstance" => D::ObjectInstance(self.string_arg(name, "a name")?),
                _ => {
                    let hint = closest_directive(name)
                        .map(|d| format!(" (did you mean {d}?)"))
                        .unwrap_or_default();
                    return Err(SceneError::at(
                        loc,
                        format!("unknown directive '{name}'{hint}"),
                    ));
                }
            };
            return Ok(Some(Located {
                directive,
                loc,
                dir,
            }));
        }
    }
}

#[cfg(test)]
mod tests;

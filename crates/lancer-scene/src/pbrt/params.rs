//! pbrt's typed parameter lists: `"float radius" [1]  "rgb reflectance" [0.8 0.3 0.2]`.
//!
//! Values are checked against their declared type when read (an `integer` must be a whole
//! number, an `rgb` three numbers). Directives then look parameters up by name and type; a
//! parameter found under the right name but the wrong type is an error, one never looked up is
//! reported as a warning (lancer does not use it).

use super::search_path::SearchPath;
use crate::error::{Location, SceneError, Warning};
use lancer::math::{PackedVec3, Rgb, Vec2, Vec3};
use lancer::spectrum::{ColorSpace, Ior, Spectrum, SpectrumKind, parse_spd, spectrum_to_rgb};
use std::cell::Cell;

/// The declared type of a parameter.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ParamType {
    /// `float`
    Float,
    /// `integer`
    Integer,
    /// `bool`
    Bool,
    /// `string`
    String,
    /// `texture` (the name of a texture)
    Texture,
    /// `point2`
    Point2,
    /// `vector2`
    Vector2,
    /// `point3` (pbrt-v3: `point`)
    Point3,
    /// `vector3` (pbrt-v3: `vector`)
    Vector3,
    /// `normal` or `normal3`
    Normal,
    /// `rgb` (pbrt-v3: `color`)
    Rgb,
    /// `spectrum`: wavelength–value pairs, a named spectrum or a file
    Spectrum,
    /// `blackbody`: a temperature in kelvin
    Blackbody,
}

impl ParamType {
    fn parse(s: &str) -> Option<ParamType> {
        Some(match s {
            "float" => ParamType::Float,
            "integer" => ParamType::Integer,
            "bool" => ParamType::Bool,
            "string" => ParamType::String,
            "texture" => ParamType::Texture,
            "point2" => ParamType::Point2,
            "vector2" => ParamType::Vector2,
            "point3" | "point" => ParamType::Point3,
            "vector3" | "vector" => ParamType::Vector3,
            "normal" | "normal3" => ParamType::Normal,
            "rgb" | "color" => ParamType::Rgb,
            "spectrum" => ParamType::Spectrum,
            "blackbody" => ParamType::Blackbody,
            _ => return None,
        })
    }

    /// The name pbrt-v4 uses in files.
    pub fn name(self) -> &'static str {
        match self {
            ParamType::Float => "float",
            ParamType::Integer => "integer",
            ParamType::Bool => "bool",
            ParamType::String => "string",
            ParamType::Texture => "texture",
            ParamType::Point2 => "point2",
            ParamType::Vector2 => "vector2",
            ParamType::Point3 => "point3",
            ParamType::Vector3 => "vector3",
            ParamType::Normal => "normal",
            ParamType::Rgb => "rgb",
            ParamType::Spectrum => "spectrum",
            ParamType::Blackbody => "blackbody",
        }
    }
}

/// One value as written, before the parameter's type gives it a meaning.
#[derive(Clone, Debug, PartialEq)]
pub enum RawValue {
    /// A number, and whether it is written as an integer.
    Number(f64, bool),
    /// A quoted string.
    Str(String),
    /// A bare `true` or `false`.
    Bool(bool),
}

/// A parameter's values, typed.
#[derive(Clone, Debug, PartialEq)]
pub enum Values {
    /// `float`, `point*`, `vector*`, `normal`, `rgb`, `blackbody`, numeric `spectrum`.
    Numbers(Vec<f32>),
    /// `integer`.
    Integers(Vec<i32>),
    /// `bool`.
    Bools(Vec<bool>),
    /// `string`, `texture`, named or file `spectrum`.
    Strings(Vec<String>),
}

impl Values {
    fn len(&self) -> usize {
        match self {
            Values::Numbers(v) => v.len(),
            Values::Integers(v) => v.len(),
            Values::Bools(v) => v.len(),
            Values::Strings(v) => v.len(),
        }
    }
}

/// One `"type name" value(s)` pair.
#[derive(Clone, Debug)]
pub struct Param {
    /// Declared type.
    pub ty: ParamType,
    /// Name.
    pub name: String,
    /// Where its declaration string starts.
    pub loc: Location,
    /// Where its first value starts (for a string, its opening quote).
    pub value_loc: Location,
    /// Values.
    pub values: Values,
    used: Cell<bool>,
}

impl Param {
    /// Builds a parameter from its declaration string (`"float radius"`) and raw values, checking
    /// the values against the type.
    pub fn new(
        decl: &str,
        loc: Location,
        raw: Vec<(RawValue, Location)>,
    ) -> Result<Param, SceneError> {
        let mut words = decl.split_whitespace();
        let (Some(ty_name), Some(name), None) = (words.next(), words.next(), words.next()) else {
            return Err(SceneError::at(
                loc,
                format!("\"{decl}\" is not a parameter declaration (expected \"type name\")"),
            ));
        };
        let ty = ParamType::parse(ty_name).ok_or_else(|| {
            SceneError::at(
                loc.clone(),
                format!(
                    "unknown parameter type '{ty_name}' (expected float, integer, bool, string, \
                     texture, point2, vector2, point3, vector3, normal, rgb, spectrum or blackbody)"
                ),
            )
        })?;
        if raw.is_empty() {
            return Err(SceneError::at(
                loc,
                format!("parameter \"{decl}\" has no value"),
            ));
        }
        let what = |v: &RawValue| match v {
            RawValue::Number(t, _) => format!("the number {t}"),
            RawValue::Str(s) => format!("the string \"{s}\""),
            RawValue::Bool(b) => format!("{b}"),
        };
        let wrong = |v: &RawValue, l: &Location, expected: &str| {
            SceneError::at(
                l.clone(),
                format!("parameter \"{decl}\" expects {expected}, found {}", what(v)),
            )
        };
        let numbers = |raw: &[(RawValue, Location)]| -> Result<Vec<f32>, SceneError> {
            raw.iter()
                .map(|(v, l)| match v {
                    RawValue::Number(t, _) => Ok(*t as f32),
                    _ => Err(wrong(v, l, "numbers")),
                })
                .collect()
        };
        let values = match ty {
            ParamType::Integer => Values::Integers(
                raw.iter()
                    .map(|(v, l)| match v {
                        RawValue::Number(t, true) if t.abs() <= i32::MAX as f64 => Ok(*t as i32),
                        RawValue::Number(t, _) => Err(SceneError::at(
                            l.clone(),
                            format!("parameter \"{decl}\" expects integers, found {t}"),
                        )),
                        _ => Err(wrong(v, l, "integers")),
                    })
                    .collect::<Result<_, _>>()?,
            ),
            ParamType::Bool => Values::Bools(
                raw.iter()
                    .map(|(v, l)| match v {
                        RawValue::Bool(b) => Ok(*b),
                        RawValue::Str(s) if s == "true" => Ok(true),
                        RawValue::Str(s) if s == "false" => Ok(false),
                        _ => Err(wrong(v, l, "true or false")),
                    })
                    .collect::<Result<_, _>>()?,
            ),
            ParamType::String | ParamType::Texture => Values::Strings(
                raw.iter()
                    .map(|(v, l)| match v {
                        RawValue::Str(s) => Ok(s.clone()),
                        _ => Err(wrong(v, l, "quoted strings")),
                    })
                    .collect::<Result<_, _>>()?,
            ),
            ParamType::Spectrum if matches!(raw[0].0, RawValue::Str(_)) => {
                if raw.len() != 1 {
                    return Err(SceneError::at(
                        raw[1].1.clone(),
                        format!(
                            "parameter \"{decl}\" takes one spectrum name or file, or \
                             wavelength–value pairs"
                        ),
                    ));
                }
                let RawValue::Str(s) = &raw[0].0 else {
                    unreachable!("checked above")
                };
                Values::Strings(vec![s.clone()])
            }
            _ => Values::Numbers(numbers(&raw)?),
        };
        let n = values.len();
        let arity_error = |expected: &str| {
            SceneError::at(
                loc.clone(),
                format!("parameter \"{decl}\" needs {expected}, found {n} value(s)"),
            )
        };
        match ty {
            ParamType::Point2 | ParamType::Vector2 if n % 2 != 0 => {
                return Err(arity_error("pairs of numbers"));
            }
            ParamType::Point3 | ParamType::Vector3 | ParamType::Normal if n % 3 != 0 => {
                return Err(arity_error("triples of numbers"));
            }
            // One colour, or a grid of them (pbrt-v4's `rgbgrid` medium): whole triples.
            ParamType::Rgb if n % 3 != 0 => return Err(arity_error("triples of numbers")),
            ParamType::Blackbody if n != 1 && n != 2 => {
                return Err(arity_error("a temperature in kelvin"));
            }
            ParamType::Spectrum
                if matches!(values, Values::Numbers(_)) && (n < 2 || n % 2 != 0) =>
            {
                return Err(arity_error("wavelength–value pairs"));
            }
            _ => {}
        }
        Ok(Param {
            ty,
            name: name.to_string(),
            value_loc: raw[0].1.clone(),
            loc,
            values,
            used: Cell::new(false),
        })
    }

    /// `"type name"`, as written in files.
    pub fn decl(&self) -> String {
        format!("\"{} {}\"", self.ty.name(), self.name)
    }

    fn numbers(&self) -> &[f32] {
        match &self.values {
            Values::Numbers(v) => v,
            _ => &[],
        }
    }

    fn error(&self, message: impl Into<String>) -> SceneError {
        SceneError::at(self.loc.clone(), message)
    }
}

/// The reading of a colour parameter: a constant or the name of a texture.
#[derive(Clone, Debug, PartialEq)]
pub enum ColorParam {
    /// A constant colour.
    Const(Rgb),
    /// A constant given as a spectrum (`blackbody`, pairs, a named spectrum, a file): its
    /// reduction and its table.
    Measured(lancer::spectrum::dense::Measured),
    /// `"texture name" "texname"`.
    Texture(String, Location),
}

/// The reading of a float parameter: a constant or the name of a texture.
#[derive(Clone, Debug, PartialEq)]
pub enum FloatParam {
    /// A constant.
    Const(f32),
    /// `"texture name" "texname"`.
    Texture(String, Location),
}

/// A directive's parameters.
#[derive(Clone, Debug, Default)]
pub struct ParamList {
    params: Vec<Param>,
    /// Earlier copies of a name given again, with where the copy that counts is declared.
    shadowed: Vec<(Param, Location)>,
    /// The colour space `rgb` values are in (pbrt-v4's `ColorSpace` at the directive).
    color_space: ColorSpace,
}

impl ParamList {
    /// A list of parsed parameters. A name given twice keeps its last value, as in pbrt-v4
    /// (its `ParameterDictionary` looks names up in the reversed list); the earlier copies are
    /// set aside for a warning ([`ParamList::report_unused`]).
    pub fn new(params: Vec<Param>) -> Result<ParamList, SceneError> {
        let mut kept: Vec<Param> = Vec::with_capacity(params.len());
        let mut shadowed = Vec::new();
        for p in params {
            if let Some(i) = kept.iter().position(|q| q.name == p.name) {
                let earlier = kept.remove(i);
                shadowed.push((earlier, p.loc.clone()));
            }
            kept.push(p);
        }
        Ok(ParamList {
            params: kept,
            shadowed,
            color_space: ColorSpace::Srgb,
        })
    }

    /// The same list with its `rgb` values read in `space` (pbrt-v4's `ColorSpace`).
    pub fn in_color_space(mut self, space: ColorSpace) -> ParamList {
        self.color_space = space;
        self
    }

    /// Adds `defaults` (pbrt's `Attribute` values) for the names this list does not give.
    pub fn with_defaults(mut self, defaults: &[Param]) -> ParamList {
        for d in defaults {
            if !self.params.iter().any(|p| p.name == d.name) {
                let mut d = d.clone();
                d.used = Cell::new(false);
                self.params.push(d);
            }
        }
        self
    }

    /// The parameters, in order.
    pub fn iter(&self) -> impl Iterator<Item = &Param> {
        self.params.iter()
    }

    /// The parameter called `name`, if its type is one of `types`: marks it used. A parameter of
    /// that name but another type is an error.
    pub fn find(&self, name: &str, types: &[ParamType]) -> Result<Option<&Param>, SceneError> {
        let Some(p) = self.params.iter().find(|p| p.name == name) else {
            return Ok(None);
        };
        if !types.contains(&p.ty) {
            let expected: Vec<_> = types.iter().map(|t| t.name()).collect();
            return Err(p.error(format!(
                "parameter '{name}' must be of type {}, not {}",
                expected.join(" or "),
                p.ty.name()
            )));
        }
        p.used.set(true);
        Ok(Some(p))
    }

    /// True if a parameter called `name` is given (whatever its type); does not mark it used.
    pub fn has(&self, name: &str) -> bool {
        self.params.iter().any(|p| p.name == name)
    }

    /// Where the parameter `name` is declared, if given.
    pub fn location(&self, name: &str) -> Option<&Location> {
        self.params.iter().find(|p| p.name == name).map(|p| &p.loc)
    }

    /// An error at the place of parameter `name`, or without a place when it is not given
    /// (the conversion then puts it at its directive).
    pub fn error_at(&self, name: &str, message: impl Into<String>) -> SceneError {
        match self.location(name) {
            Some(l) => SceneError::at(l.clone(), message),
            None => SceneError::general(message),
        }
    }

    fn one_number(&self, name: &str, ty: ParamType) -> Result<Option<(f32, &Param)>, SceneError> {
        let Some(p) = self.find(name, &[ty])? else {
            return Ok(None);
        };
        match p.numbers() {
            [v] => Ok(Some((*v, p))),
            vs => Err(p.error(format!(
                "parameter {} takes one value, found {}",
                p.decl(),
                vs.len()
            ))),
        }
    }

    /// A `float`, or `default`.
    pub fn float(&self, name: &str, default: f32) -> Result<f32, SceneError> {
        Ok(self
            .one_number(name, ParamType::Float)?
            .map_or(default, |v| v.0))
    }

    /// A `float` checked by `ok` (which says what is required when it fails), or `default`.
    pub fn float_checked(
        &self,
        name: &str,
        default: f32,
        requirement: &str,
        ok: impl Fn(f32) -> bool,
    ) -> Result<f32, SceneError> {
        match self.one_number(name, ParamType::Float)? {
            Some((v, _)) if ok(v) => Ok(v),
            Some((v, p)) => Err(p.error(format!("{} must be {requirement}, not {v}", p.decl()))),
            None => Ok(default),
        }
    }

    /// `float` values (any count).
    pub fn floats(&self, name: &str) -> Result<Option<Vec<f32>>, SceneError> {
        Ok(self
            .find(name, &[ParamType::Float])?
            .map(|p| p.numbers().to_vec()))
    }

    /// An `integer`, or `default`.
    pub fn int(&self, name: &str, default: i32) -> Result<i32, SceneError> {
        let Some(p) = self.find(name, &[ParamType::Integer])? else {
            return Ok(default);
        };
        match &p.values {
            Values::Integers(v) if v.len() == 1 => Ok(v[0]),
            v => Err(p.error(format!(
                "parameter {} takes one value, found {}",
                p.decl(),
                v.len()
            ))),
        }
    }

    /// An `integer` within `range`, or `default`.
    pub fn int_in(
        &self,
        name: &str,
        default: i32,
        range: std::ops::RangeInclusive<i32>,
    ) -> Result<i32, SceneError> {
        let v = self.int(name, default)?;
        if !range.contains(&v) {
            let p = self.find(name, &[ParamType::Integer])?.expect("given");
            return Err(p.error(format!(
                "{} must be between {} and {}, not {v}",
                p.decl(),
                range.start(),
                range.end()
            )));
        }
        Ok(v)
    }

    /// `integer` values (any count).
    pub fn ints(&self, name: &str) -> Result<Option<(Vec<i32>, Location)>, SceneError> {
        Ok(self
            .find(name, &[ParamType::Integer])?
            .map(|p| match &p.values {
                Values::Integers(v) => (v.clone(), p.loc.clone()),
                _ => (Vec::new(), p.loc.clone()),
            }))
    }

    /// A `bool`, or `default`.
    pub fn bool(&self, name: &str, default: bool) -> Result<bool, SceneError> {
        let Some(p) = self.find(name, &[ParamType::Bool])? else {
            return Ok(default);
        };
        match &p.values {
            Values::Bools(v) if v.len() == 1 => Ok(v[0]),
            v => Err(p.error(format!(
                "parameter {} takes one value, found {}",
                p.decl(),
                v.len()
            ))),
        }
    }

    /// A `string`, if given.
    pub fn string(&self, name: &str) -> Result<Option<String>, SceneError> {
        self.string_of(name, ParamType::String)
    }

    fn string_of(&self, name: &str, ty: ParamType) -> Result<Option<String>, SceneError> {
        let Some(p) = self.find(name, &[ty])? else {
            return Ok(None);
        };
        match &p.values {
            Values::Strings(v) if v.len() == 1 => Ok(Some(v[0].clone())),
            v => Err(p.error(format!(
                "parameter {} takes one value, found {}",
                p.decl(),
                v.len()
            ))),
        }
    }

    /// `string` values (any count), with where they are declared.
    pub fn strings(&self, name: &str) -> Result<Option<(Vec<String>, Location)>, SceneError> {
        Ok(self
            .find(name, &[ParamType::String])?
            .map(|p| match &p.values {
                Values::Strings(v) => (v.clone(), p.loc.clone()),
                _ => (Vec::new(), p.loc.clone()),
            }))
    }

    /// Triples, packed: meshes keep them as their vertex arrays.
    fn vec3s(
        &self,
        name: &str,
        types: &[ParamType],
    ) -> Result<Option<Vec<PackedVec3>>, SceneError> {
        Ok(self.find(name, types)?.map(|p| {
            p.numbers()
                .chunks_exact(3)
                .map(|c| PackedVec3::new(c[0], c[1], c[2]))
                .collect()
        }))
    }

    fn one_vec3(&self, name: &str, types: &[ParamType]) -> Result<Option<Vec3>, SceneError> {
        match self.vec3s(name, types)? {
            None => Ok(None),
            Some(v) if v.len() == 1 => Ok(Some(v[0].into())),
            Some(v) => {
                let p = self.find(name, types)?.expect("given");
                Err(p.error(format!(
                    "parameter {} takes one triple, found {}",
                    p.decl(),
                    v.len()
                )))
            }
        }
    }

    /// A `point3`, or `default`.
    pub fn point3(&self, name: &str, default: Vec3) -> Result<Vec3, SceneError> {
        Ok(self
            .one_vec3(name, &[ParamType::Point3])?
            .unwrap_or(default))
    }

    /// A `vector3`, or `default`.
    pub fn vector3(&self, name: &str, default: Vec3) -> Result<Vec3, SceneError> {
        Ok(self
            .one_vec3(name, &[ParamType::Vector3])?
            .unwrap_or(default))
    }

    /// A `normal`, or `default`.
    pub fn normal(&self, name: &str, default: Vec3) -> Result<Vec3, SceneError> {
        Ok(self
            .one_vec3(name, &[ParamType::Normal])?
            .unwrap_or(default))
    }

    /// `point3` values (packed).
    pub fn point3s(&self, name: &str) -> Result<Option<Vec<PackedVec3>>, SceneError> {
        self.vec3s(name, &[ParamType::Point3])
    }

    /// `normal` values (packed).
    pub fn normals(&self, name: &str) -> Result<Option<Vec<PackedVec3>>, SceneError> {
        self.vec3s(name, &[ParamType::Normal])
    }

    /// `point2` values (pbrt-v3 also wrote them as `float`).
    pub fn point2s(&self, name: &str) -> Result<Option<Vec<Vec2>>, SceneError> {
        let Some(p) = self.find(name, &[ParamType::Point2, ParamType::Float])? else {
            return Ok(None);
        };
        let n = p.numbers();
        if n.len() % 2 != 0 {
            return Err(p.error(format!(
                "parameter {} needs pairs of numbers, found {}",
                p.decl(),
                n.len()
            )));
        }
        Ok(Some(
            n.chunks_exact(2).map(|c| Vec2::new(c[0], c[1])).collect(),
        ))
    }

    /// Marks every parameter used: for a directive skipped as a whole, whose one warning says
    /// so, rather than one more per parameter.
    pub fn mark_all_used(&self) {
        for p in &self.params {
            p.used.set(true);
        }
    }

    /// Warnings for every parameter nobody looked up (lancer ignores them), and for every
    /// earlier copy of a parameter given twice.
    pub fn report_unused(&self, what: &str, warnings: &mut Vec<Warning>) {
        for (p, last) in &self.shadowed {
            warnings.push(Warning {
                location: p.loc.clone(),
                message: format!(
                    "parameter {} of {what} is given again at {}:{}; this earlier value is \
                     ignored (as pbrt-v4, the last one counts)",
                    p.decl(),
                    last.line,
                    last.col
                ),
            });
        }
        for p in self.params.iter().filter(|p| !p.used.get()) {
            warnings.push(Warning {
                location: p.loc.clone(),
                message: format!(
                    "parameter {} of {what} is not used by lancer; ignored",
                    p.decl()
                ),
            });
        }
    }
}

mod colors;

#[cfg(test)]
mod tests;

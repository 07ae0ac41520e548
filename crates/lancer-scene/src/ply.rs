//! PLY meshes (the Stanford polygon file format) read into a [`TriangleMesh`], as pbrt-v4's
//! `Shape "plymesh"` uses them.
//!
//! The three encodings are read (`ascii`, `binary_little_endian`, `binary_big_endian`, all
//! version 1.0), with every PLY scalar type. From the `vertex` element come `x y z`, the
//! normal `nx ny nz` and texture coordinates (`u v`, `s t`, `texture_u texture_v` or
//! `texture_s texture_t`); from `face` the `vertex_indices` (or `vertex_index`) lists:
//! triangles as they are, larger polygons as fans (a quad gives two triangles). A
//! `tristrips` element (triangle strips, `-1` restarting a strip) is read too. Other elements
//! and properties are skipped. A file whose name ends in `.gz` is gunzipped first.
//!
//! The whole file is read into memory and parsed from the slice. Nothing is allocated on the
//! header's word alone: before any element is read, the header's counts are checked against
//! the bytes that follow it.

use lancer::math::{PackedVec3, Vec2};
use lancer::shape::TriangleMesh;
use std::fmt;
use std::io::Read;
use std::path::Path;

/// Why a PLY file could not be read.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct PlyError {
    /// The file, as named to the reader.
    pub file: String,
    /// What is wrong, one line.
    pub message: String,
}

impl fmt::Display for PlyError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}: {}", self.file, self.message)
    }
}

impl std::error::Error for PlyError {}

/// A mesh read from a PLY file, and what the reader left out.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PlyMesh {
    /// The triangles, in the file's coordinates.
    pub mesh: TriangleMesh,
    /// Faces with fewer than three vertices, which make no triangle and are skipped.
    pub skipped_faces: u64,
}

/// Reads a PLY file (gunzipping it first when its name ends in `.gz`).
pub fn read_ply(path: &Path) -> Result<PlyMesh, PlyError> {
    let name = path.display().to_string();
    let fail = |message: String| PlyError {
        file: name.clone(),
        message,
    };
    crate::files_read::record(path);
    let raw = std::fs::read(path).map_err(|e| fail(format!("cannot read the file: {e}")))?;
    let gz = path
        .extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| e.eq_ignore_ascii_case("gz"));
    let data = if gz {
        let mut out = Vec::new();
        flate2::read::MultiGzDecoder::new(raw.as_slice())
            .read_to_end(&mut out)
            .map_err(|e| fail(format!("cannot decompress the file: {e}")))?;
        out
    } else {
        raw
    };
    parse_ply(&data, &name)
}

/// Reads PLY data held in memory; `name` names it in messages.
pub fn parse_ply(data: &[u8], name: &str) -> Result<PlyMesh, PlyError> {
    parse(data).map_err(|message| PlyError {
        file: name.to_string(),
        message,
    })
}

fn parse(data: &[u8]) -> Result<PlyMesh, String> {
    let header = parse_header(data)?;
    let body = &data[header.body_start..];
    check_sizes(&header, body.len())?;
    match header.format {
        Format::Ascii => read_body(&mut Ascii { data: body, pos: 0 }, &header),
        Format::Binary { big_endian } => read_body(
            &mut Binary {
                data: body,
                pos: 0,
                big: big_endian,
            },
            &header,
        ),
    }
}

/// A PLY scalar type.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Scalar {
    I8,
    U8,
    I16,
    U16,
    I32,
    U32,
    F32,
    F64,
}

impl Scalar {
    /// The type a header names, in either of PLY's spellings.
    fn parse(word: &str) -> Option<Scalar> {
        Some(match word {
            "char" | "int8" => Scalar::I8,
            "uchar" | "uint8" => Scalar::U8,
            "short" | "int16" => Scalar::I16,
            "ushort" | "uint16" => Scalar::U16,
            "int" | "int32" => Scalar::I32,
            "uint" | "uint32" => Scalar::U32,
            "float" | "float32" => Scalar::F32,
            "double" | "float64" => Scalar::F64,
            _ => return None,
        })
    }

    /// Bytes in the binary encodings.
    fn size(self) -> usize {
        match self {
            Scalar::I8 | Scalar::U8 => 1,
            Scalar::I16 | Scalar::U16 => 2,
            Scalar::I32 | Scalar::U32 | Scalar::F32 => 4,
            Scalar::F64 => 8,
        }
    }

    fn is_integer(self) -> bool {
        !matches!(self, Scalar::F32 | Scalar::F64)
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Format {
    Ascii,
    Binary { big_endian: bool },
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Kind {
    Scalar(Scalar),
    List { count: Scalar, item: Scalar },
}

#[derive(Debug)]
struct Property {
    name: String,
    kind: Kind,
}

#[derive(Debug)]
struct Element {
    name: String,
    count: u64,
    props: Vec<Property>,
}

impl Element {
    fn property(&self, name: &str) -> Option<usize> {
        self.props.iter().position(|p| p.name == name)
    }

    /// The index of the scalar property `name`, if there is one.
    fn scalar(&self, name: &str) -> Option<usize> {
        self.property(name)
            .filter(|&i| matches!(self.props[i].kind, Kind::Scalar(_)))
    }

    /// Bytes one record takes at least in `format` (a list may be empty; in ASCII every
    /// number takes a character and a separator).
    fn min_record_size(&self, format: Format) -> u64 {
        match format {
            Format::Ascii => 2 * self.props.len() as u64,
            Format::Binary { .. } => self
                .props
                .iter()
                .map(|p| match p.kind {
                    Kind::Scalar(t) => t.size() as u64,
                    Kind::List { count, .. } => count.size() as u64,
                })
                .sum(),
        }
    }
}

#[derive(Debug)]
struct Header {
    format: Format,
    elements: Vec<Element>,
    /// Where the data starts: just after the `end_header` line.
    body_start: usize,
}

fn parse_header(data: &[u8]) -> Result<Header, String> {
    let magic_ok = data.starts_with(b"ply")
        && matches!(
            data.get(3),
            Some(b'\n') | Some(b'\r') | Some(b' ') | Some(b'\t')
        );
    if !magic_ok {
        return Err("not a PLY file (it does not start with a \"ply\" line)".into());
    }
    let mut pos = 0;
    let mut line_no = 0u32;
    let mut format = None;
    let mut elements: Vec<Element> = Vec::new();
    loop {
        let Some(len) = data[pos..].iter().position(|&b| b == b'\n') else {
            return Err("the header never ends (there is no \"end_header\" line)".into());
        };
        let raw = &data[pos..pos + len];
        pos += len + 1;
        line_no += 1;
        if line_no == 1 {
            continue; // "ply"
        }
        let line = String::from_utf8_lossy(raw);
        let words: Vec<&str> = line.split_ascii_whitespace().collect();
        let at = |what: String| format!("header line {line_no}: {what}");
        match words.first().copied() {
            None | Some("comment") | Some("obj_info") => {}
            Some("format") => {
                if format.is_some() {
                    return Err(at("a second \"format\" line".into()));
                }
                let [_, name, version] = words[..] else {
                    return Err(at("expected \"format <encoding> 1.0\"".into()));
                };
                format = Some(match name {
                    "ascii" => Format::Ascii,
                    "binary_little_endian" => Format::Binary { big_endian: false },
                    "binary_big_endian" => Format::Binary { big_endian: true },
                    _ => {
                        return Err(at(format!(
                            "unknown format \"{name}\" (expected ascii, binary_little_endian or binary_big_endian)"
                        )));
                    }
                });
                if version.parse::<f64>() != Ok(1.0) {
                    return Err(at(format!(
                        "PLY version {version} (lancer reads version 1.0)"
                    )));
                }
            }
            Some("element") => {
                let [_, name, count] = words[..] else {
                    return Err(at("expected \"element <name> <count>\"".into()));
                };
                let count = count.parse::<u64>().map_err(|_| {
                    at(format!(
                        "the count of element \"{name}\" is \"{count}\", not a whole number"
                    ))
                })?;
                elements.push(Element {
                    name: name.to_string(),
                    count,
                    props: Vec::new(),
                });
            }
            Some("property") => {
                let Some(element) = elements.last_mut() else {
                    return Err(at("a property before any element".into()));
                };
                let ty = |word: &str| {
                    Scalar::parse(word).ok_or_else(|| {
                        at(format!(
                            "unknown type \"{word}\" (expected char, uchar, short, ushort, int, uint, float or double, or int8 … float64)"
                        ))
                    })
                };
                let (name, kind) = match words[..] {
                    [_, "list", count, item, name] => {
                        let count = ty(count)?;
                        if !count.is_integer() {
                            return Err(at(format!(
                                "the length of list \"{name}\" has a floating-point type"
                            )));
                        }
                        (
                            name,
                            Kind::List {
                                count,
                                item: ty(item)?,
                            },
                        )
                    }
                    [_, "list", ..] => {
                        return Err(at(
                            "expected \"property list <length type> <item type> <name>\"".into(),
                        ));
                    }
                    [_, t, name] => (name, Kind::Scalar(ty(t)?)),
                    _ => return Err(at("expected \"property <type> <name>\"".into())),
                };
                element.props.push(Property {
                    name: name.to_string(),
                    kind,
                });
            }
            Some("end_header") => break,
            Some(other) => return Err(at(format!("unknown keyword \"{other}\""))),
        }
    }
    let Some(format) = format else {
        return Err("the header has no \"format\" line".into());
    };
    Ok(Header {
        format,
        elements,
        body_start: pos,
    })
}

/// Refuses a header that announces more records than the data could hold, before anything is
/// allocated for them.
fn check_sizes(header: &Header, available: usize) -> Result<(), String> {
    // The last number of an ASCII file needs no separator after it.
    let slack = u128::from(header.format == Format::Ascii);
    let mut need: u128 = 0;
    for el in &header.elements {
        need += u128::from(el.count) * u128::from(el.min_record_size(header.format));
        if need > available as u128 + slack {
            return Err(format!(
                "the header announces {} \"{}\" elements, more than the {available} bytes of data after it can hold",
                el.count, el.name
            ));
        }
    }
    Ok(())
}

/// Why reading a value failed: the data ended, or (ASCII) a word is not a number.
enum ReadError {
    End,
    Bad(String),
}

impl ReadError {
    /// The message, naming record `i` of element `el`, which has `n` records.
    fn describe(self, el: &str, i: u64, n: u64) -> String {
        match self {
            ReadError::End => {
                format!("the data ends inside {el} {i} of {n}: the file is truncated")
            }
            ReadError::Bad(m) => format!("{el} {i}: {m}"),
        }
    }
}

/// The data after the header, in one of the encodings.
trait Body {
    /// A number of type `t`.
    fn float(&mut self, t: Scalar) -> Result<f64, ReadError>;
    /// A whole number of the integer type `t`.
    fn int(&mut self, t: Scalar) -> Result<i64, ReadError>;
    /// Skips `n` numbers of type `t`.
    fn skip(&mut self, t: Scalar, n: u64) -> Result<(), ReadError>;
    /// Skips records of fixed size: `bytes` in binary, `words` in ASCII.
    fn skip_fixed(&mut self, bytes: u64, words: u64) -> Result<(), ReadError>;
}

struct Binary<'a> {
    data: &'a [u8],
    pos: usize,
    big: bool,
}

impl Binary<'_> {
    #[inline]
    fn bytes<const N: usize>(&mut self) -> Result<[u8; N], ReadError> {
        let b = self
            .data
            .get(self.pos..self.pos + N)
            .ok_or(ReadError::End)?;
        self.pos += N;
        let mut out = [0; N];
        out.copy_from_slice(b);
        Ok(out)
    }

    fn skip_bytes(&mut self, n: u64) -> Result<(), ReadError> {
        let left = (self.data.len() - self.pos) as u64;
        if n > left {
            return Err(ReadError::End);
        }
        self.pos += n as usize;
        Ok(())
    }
}

/// A number of type `$t` in the body's byte order.
macro_rules! binary_number {
    ($body:expr, $t:ty) => {{
        let b = $body.bytes::<{ std::mem::size_of::<$t>() }>()?;
        if $body.big {
            <$t>::from_be_bytes(b)
        } else {
            <$t>::from_le_bytes(b)
        }
    }};
}

impl Body for Binary<'_> {
    #[inline]
    fn float(&mut self, t: Scalar) -> Result<f64, ReadError> {
        Ok(match t {
            Scalar::F32 => f64::from(binary_number!(self, f32)),
            Scalar::F64 => binary_number!(self, f64),
            _ => self.int(t)? as f64,
        })
    }

    #[inline]
    fn int(&mut self, t: Scalar) -> Result<i64, ReadError> {
        Ok(match t {
            Scalar::I8 => i64::from(binary_number!(self, i8)),
            Scalar::U8 => i64::from(binary_number!(self, u8)),
            Scalar::I16 => i64::from(binary_number!(self, i16)),
            Scalar::U16 => i64::from(binary_number!(self, u16)),
            Scalar::I32 => i64::from(binary_number!(self, i32)),
            Scalar::U32 => i64::from(binary_number!(self, u32)),
            Scalar::F32 | Scalar::F64 => {
                let v = self.float(t)?;
                if v.fract() != 0.0 || !v.is_finite() || v.abs() > 1e18 {
                    return Err(ReadError::Bad(format!("{v} is not a whole number")));
                }
                v as i64
            }
        })
    }

    fn skip(&mut self, t: Scalar, n: u64) -> Result<(), ReadError> {
        self.skip_bytes(n.saturating_mul(t.size() as u64))
    }

    fn skip_fixed(&mut self, bytes: u64, _words: u64) -> Result<(), ReadError> {
        self.skip_bytes(bytes)
    }
}

struct Ascii<'a> {
    data: &'a [u8],
    pos: usize,
}

impl<'a> Ascii<'a> {
    /// The next whitespace-separated word.
    fn word(&mut self) -> Result<&'a [u8], ReadError> {
        let data = self.data;
        while self.pos < data.len() && data[self.pos].is_ascii_whitespace() {
            self.pos += 1;
        }
        if self.pos == data.len() {
            return Err(ReadError::End);
        }
        let start = self.pos;
        while self.pos < data.len() && !data[self.pos].is_ascii_whitespace() {
            self.pos += 1;
        }
        Ok(&data[start..self.pos])
    }
}

fn not_a_number(word: &[u8], what: &str) -> ReadError {
    ReadError::Bad(format!(
        "\"{}\" is not {what}",
        String::from_utf8_lossy(word)
    ))
}

impl Body for Ascii<'_> {
    fn float(&mut self, _t: Scalar) -> Result<f64, ReadError> {
        let w = self.word()?;
        std::str::from_utf8(w)
            .ok()
            .and_then(|s| s.parse::<f64>().ok())
            .ok_or_else(|| not_a_number(w, "a number"))
    }

    fn int(&mut self, _t: Scalar) -> Result<i64, ReadError> {
        let w = self.word()?;
        std::str::from_utf8(w)
            .ok()
            .and_then(|s| s.parse::<i64>().ok())
            .ok_or_else(|| not_a_number(w, "a whole number"))
    }

    fn skip(&mut self, _t: Scalar, n: u64) -> Result<(), ReadError> {
        for _ in 0..n {
            self.word()?;
        }
        Ok(())
    }

    fn skip_fixed(&mut self, _bytes: u64, words: u64) -> Result<(), ReadError> {
        self.skip(Scalar::F32, words)
    }
}

/// A list's length, which must not be negative.
fn list_len<B: Body>(body: &mut B, count: Scalar) -> Result<u64, ReadError> {
    let n = body.int(count)?;
    u64::try_from(n).map_err(|_| ReadError::Bad(format!("a list has negative length {n}")))
}

/// Skips one property of one record.
fn skip_property<B: Body>(body: &mut B, kind: Kind) -> Result<(), ReadError> {
    match kind {
        Kind::Scalar(t) => body.skip(t, 1),
        Kind::List { count, item } => {
            let n = list_len(body, count)?;
            body.skip(item, n)
        }
    }
}

fn skip_element<B: Body>(body: &mut B, el: &Element) -> Result<(), String> {
    if el.props.is_empty() || el.count == 0 {
        return Ok(());
    }
    let scalars: Option<Vec<Scalar>> = el
        .props
        .iter()
        .map(|p| match p.kind {
            Kind::Scalar(t) => Some(t),
            Kind::List { .. } => None,
        })
        .collect();
    if let Some(scalars) = scalars {
        // Fixed-size records: skipped at once.
        let bytes: u64 = scalars.iter().map(|t| t.size() as u64).sum();
        let words = scalars.len() as u64;
        return body
            .skip_fixed(
                bytes.saturating_mul(el.count),
                words.saturating_mul(el.count),
            )
            .map_err(|e| e.describe(&el.name, 0, el.count));
    }
    for i in 0..el.count {
        for p in &el.props {
            skip_property(body, p.kind).map_err(|e| e.describe(&el.name, i, el.count))?;
        }
    }
    Ok(())
}

/// Where each vertex property goes: slots 0–2 position, 3–5 normal, 6–7 uv.
struct VertexLayout {
    slots: Vec<Option<usize>>,
    normals: bool,
    uvs: bool,
}

impl VertexLayout {
    fn new(el: &Element) -> Result<VertexLayout, String> {
        let mut slots = vec![None; el.props.len()];
        let (Some(x), Some(y), Some(z)) = (el.scalar("x"), el.scalar("y"), el.scalar("z")) else {
            return Err("the \"vertex\" element has no x, y and z properties".into());
        };
        for (slot, i) in [x, y, z].into_iter().enumerate() {
            slots[i] = Some(slot);
        }
        let normals = match (el.scalar("nx"), el.scalar("ny"), el.scalar("nz")) {
            (Some(a), Some(b), Some(c)) => {
                slots[a] = Some(3);
                slots[b] = Some(4);
                slots[c] = Some(5);
                true
            }
            _ => false,
        };
        let uv_names = [
            ("u", "v"),
            ("s", "t"),
            ("texture_u", "texture_v"),
            ("texture_s", "texture_t"),
        ];
        let uv = uv_names
            .iter()
            .find_map(|(u, v)| Some((el.scalar(u)?, el.scalar(v)?)));
        if let Some((u, v)) = uv {
            slots[u] = Some(6);
            slots[v] = Some(7);
        }
        Ok(VertexLayout {
            slots,
            normals,
            uvs: uv.is_some(),
        })
    }
}

fn read_vertices<B: Body>(
    body: &mut B,
    el: &Element,
    layout: &VertexLayout,
    mesh: &mut TriangleMesh,
) -> Result<(), String> {
    // check_sizes has bounded the count by the data's length.
    let n = el.count as usize;
    mesh.positions.reserve_exact(n);
    if layout.normals {
        mesh.normals.reserve_exact(n);
    }
    if layout.uvs {
        mesh.uvs.reserve_exact(n);
    }
    let mut v = [0.0f64; 8];
    for i in 0..el.count {
        for (p, slot) in el.props.iter().zip(&layout.slots) {
            let r = match (p.kind, slot) {
                (Kind::Scalar(t), Some(s)) => body.float(t).map(|x| v[*s] = x),
                (kind, _) => skip_property(body, kind),
            };
            r.map_err(|e| e.describe("vertex", i, el.count))?;
        }
        let finite = |a: &[f64]| a.iter().all(|x| (*x as f32).is_finite());
        if !finite(&v[0..3]) {
            return Err(format!(
                "vertex {i} has position ({}, {}, {}), which is not finite",
                v[0], v[1], v[2]
            ));
        }
        mesh.positions
            .push(PackedVec3::new(v[0] as f32, v[1] as f32, v[2] as f32));
        if layout.normals {
            if !finite(&v[3..6]) {
                return Err(format!(
                    "vertex {i} has normal ({}, {}, {}), which is not finite",
                    v[3], v[4], v[5]
                ));
            }
            mesh.normals
                .push(PackedVec3::new(v[3] as f32, v[4] as f32, v[5] as f32));
        }
        if layout.uvs {
            if !finite(&v[6..8]) {
                return Err(format!(
                    "vertex {i} has texture coordinates ({}, {}), which are not finite",
                    v[6], v[7]
                ));
            }
            mesh.uvs.push(Vec2::new(v[6] as f32, v[7] as f32));
        }
    }
    Ok(())
}

/// How the index lists of an element are read.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Polygons {
    /// `face`: each list a polygon, triangulated as a fan.
    Faces,
    /// `tristrips`: each list triangle strips, `-1` ending one.
    Strips,
}

/// Reads an element of index lists (the property at `list`), appending triangles to
/// `indices`; returns how many faces had fewer than three vertices.
fn read_polygons<B: Body>(
    body: &mut B,
    el: &Element,
    list: usize,
    polygons: Polygons,
    vertex_count: usize,
    indices: &mut Vec<u32>,
) -> Result<u64, String> {
    let Kind::List { count, item } = el.props[list].kind else {
        return Err(format!(
            "the \"{}\" property of \"{}\" is a single number, not a list",
            el.props[list].name, el.name
        ));
    };
    if !item.is_integer() {
        return Err(format!(
            "the \"{}\" lists of \"{}\" hold floating-point numbers, not vertex indices",
            el.props[list].name, el.name
        ));
    }
    let mut skipped = 0;
    for i in 0..el.count {
        let describe = |e: ReadError| e.describe(&el.name, i, el.count);
        for (j, p) in el.props.iter().enumerate() {
            if j != list {
                skip_property(body, p.kind).map_err(describe)?;
                continue;
            }
            let n = list_len(body, count).map_err(describe)?;
            let vertex = |k: i64| -> Result<u32, String> {
                if (0..vertex_count as i64).contains(&k) {
                    Ok(k as u32)
                } else {
                    Err(format!(
                        "{} {i} refers to vertex {k} but there are {vertex_count} vertices",
                        el.name
                    ))
                }
            };
            match polygons {
                Polygons::Faces if n < 3 => {
                    body.skip(item, n).map_err(describe)?;
                    skipped += 1;
                }
                Polygons::Faces => {
                    let first = vertex(body.int(item).map_err(describe)?)?;
                    let mut prev = vertex(body.int(item).map_err(describe)?)?;
                    for _ in 2..n {
                        let next = vertex(body.int(item).map_err(describe)?)?;
                        indices.extend_from_slice(&[first, prev, next]);
                        prev = next;
                    }
                }
                Polygons::Strips => {
                    let (mut a, mut b) = (None, None);
                    let mut odd = false;
                    for _ in 0..n {
                        let k = body.int(item).map_err(describe)?;
                        if k == -1 {
                            (a, b, odd) = (None, None, false);
                            continue;
                        }
                        let c = vertex(k)?;
                        if let (Some(a), Some(b)) = (a, b) {
                            // Repeated vertices join strips; they make no triangle.
                            if a != b && b != c && a != c {
                                let t = if odd { [b, a, c] } else { [a, b, c] };
                                indices.extend_from_slice(&t);
                            }
                            odd = !odd;
                        }
                        (a, b) = (b, Some(c));
                    }
                }
            }
        }
    }
    Ok(skipped)
}

fn read_body<B: Body>(body: &mut B, header: &Header) -> Result<PlyMesh, String> {
    let mut vertex_elements = header.elements.iter().filter(|e| e.name == "vertex");
    let Some(vertex_el) = vertex_elements.next() else {
        return Err("there is no \"vertex\" element".into());
    };
    if vertex_elements.next().is_some() {
        return Err("there are two \"vertex\" elements".into());
    }
    let vertex_count = usize::try_from(vertex_el.count)
        .ok()
        .filter(|&n| n <= u32::MAX as usize)
        .ok_or_else(|| {
            format!(
                "{} vertices are more than lancer's 32-bit indices can address",
                vertex_el.count
            )
        })?;
    let layout = VertexLayout::new(vertex_el)?;
    let mut out = PlyMesh::default();
    for el in &header.elements {
        let polygons = match el.name.as_str() {
            "vertex" => {
                read_vertices(body, el, &layout, &mut out.mesh)?;
                continue;
            }
            "face" => Polygons::Faces,
            "tristrips" => Polygons::Strips,
            _ => {
                skip_element(body, el)?;
                continue;
            }
        };
        let Some(list) = el
            .property("vertex_indices")
            .or_else(|| el.property("vertex_index"))
        else {
            return Err(format!(
                "the \"{}\" element has no \"vertex_indices\" list",
                el.name
            ));
        };
        out.skipped_faces += read_polygons(
            body,
            el,
            list,
            polygons,
            vertex_count,
            &mut out.mesh.indices,
        )?;
    }
    out.mesh.validate()?;
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse_str(text: &str) -> Result<PlyMesh, PlyError> {
        parse_ply(text.as_bytes(), "t.ply")
    }

    fn mesh(text: &str) -> TriangleMesh {
        parse_str(text).unwrap_or_else(|e| panic!("{e}")).mesh
    }

    fn error(data: &[u8]) -> String {
        match parse_ply(data, "t.ply") {
            Ok(m) => panic!("expected an error, read {m:?}"),
            Err(e) => e.to_string(),
        }
    }

    #[track_caller]
    fn assert_contains(text: &str, part: &str) {
        assert!(text.contains(part), "{text:?} does not contain {part:?}");
    }

    const SQUARE: &str = "ply
format ascii 1.0
comment a unit square as one quad
element vertex 4
property float x
property float y
property float z
element face 1
property list uchar int vertex_indices
end_header
0 0 0
1 0 0
1 1 0
0 1 0
4 0 1 2 3
";

    #[test]
    fn ascii_quad_becomes_two_triangles() {
        let m = mesh(SQUARE);
        assert_eq!(
            m.positions,
            vec![
                PackedVec3::new(0.0, 0.0, 0.0),
                PackedVec3::new(1.0, 0.0, 0.0),
                PackedVec3::new(1.0, 1.0, 0.0),
                PackedVec3::new(0.0, 1.0, 0.0),
            ]
        );
        assert_eq!(m.indices, vec![0, 1, 2, 0, 2, 3]);
        assert!(m.normals.is_empty() && m.uvs.is_empty());
        assert!(!m.flip_normal);
    }

    #[test]
    fn crlf_header_and_polygons_as_fans() {
        let text = "ply\r\nformat ascii 1.0\r\nelement vertex 5\r\nproperty double x\r\n\
                    property double y\r\nproperty double z\r\nelement face 2\r\n\
                    property list uchar uint vertex_index\r\nend_header\r\n\
                    0 0 0\r\n1 0 0\r\n2 1 0\r\n1 2 0\r\n0 1 0\r\n5 0 1 2 3 4\r\n3 4 3 2\r\n";
        let m = mesh(text);
        assert_eq!(m.positions.len(), 5);
        assert_eq!(m.indices, vec![0, 1, 2, 0, 2, 3, 0, 3, 4, 4, 3, 2]);
    }

    #[test]
    fn normals_and_each_uv_spelling() {
        for (u, v) in [
            ("u", "v"),
            ("s", "t"),
            ("texture_u", "texture_v"),
            ("texture_s", "texture_t"),
        ] {
            let text = format!(
                "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n\
                 property float z\nproperty float nx\nproperty float ny\nproperty float nz\n\
                 property float {u}\nproperty float {v}\nelement face 1\n\
                 property list uchar int vertex_indices\nend_header\n\
                 0 0 0 0 0 1 0 0\n1 0 0 0 0 1 1 0\n0 1 0 0 0 1 0.25 0.75\n3 0 1 2\n"
            );
            let m = mesh(&text);
            assert_eq!(m.normals, vec![PackedVec3::Z; 3], "{u} {v}");
            assert_eq!(
                m.uvs,
                vec![
                    Vec2::new(0.0, 0.0),
                    Vec2::new(1.0, 0.0),
                    Vec2::new(0.25, 0.75)
                ],
                "{u} {v}"
            );
        }
    }

    #[test]
    fn unknown_elements_and_properties_are_skipped() {
        // A list and scalars on the vertex, a material element before the faces, a face list
        // ahead of the indices and a scalar after them, and an edge element at the end.
        let text = "ply
format ascii 1.0
obj_info made by hand
element vertex 3
property list uchar float weights
property float x
property uchar red
property float y
property float z
property double confidence
element material 2
property list int int ids
property float shine
element face 1
property list uchar float texcoord
property list uchar int vertex_indices
property int flags
element edge 1
property int vertex1
property int vertex2
end_header
2 0.5 0.5 0 9 0 0 0.1
0 1 7 0 0 0.2
1 7.5 0 7 1 0 0.3
3 1 2 3 0.5
0 2.5
6 0 0 1 0 0 1 3 0 1 2 77
0 1
";
        let m = mesh(text);
        assert_eq!(
            m.positions,
            vec![
                PackedVec3::ZERO,
                PackedVec3::new(1.0, 0.0, 0.0),
                PackedVec3::new(0.0, 1.0, 0.0)
            ]
        );
        assert_eq!(m.indices, vec![0, 1, 2]);
    }

    /// The square of [`SQUARE`] in binary, with normals, a double coordinate and every
    /// integer type somewhere, in the byte order `be`.
    fn binary_square(be: bool) -> Vec<u8> {
        let order = if be { "big" } else { "little" };
        let mut d = format!(
            "ply\nformat binary_{order}_endian 1.0\ncomment every type\n\
             element vertex 4\nproperty float x\nproperty double y\nproperty float32 z\n\
             property char a\nproperty ushort b\nproperty short c\nproperty uint d\n\
             property float nx\nproperty float ny\nproperty float nz\n\
             element face 2\nproperty list ushort int8 junk\n\
             property list uint8 uint16 vertex_indices\nproperty list int uint32 more\n\
             element strip 1\nproperty list int16 int32 xs\nend_header\n"
        )
        .into_bytes();
        macro_rules! put {
            ($v:expr) => {
                d.extend_from_slice(&if be {
                    $v.to_be_bytes()
                } else {
                    $v.to_le_bytes()
                })
            };
        }
        for (x, y) in [(0.0f32, 0.0f64), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)] {
            put!(x);
            put!(y);
            put!(0.0f32);
            put!(-3i8);
            put!(65000u16);
            put!(-2i16);
            put!(4_000_000_000u32);
            put!(0.0f32);
            put!(0.0f32);
            put!(1.0f32);
        }
        // Face 0: a triangle; face 1: the other half of the square.
        for tri in [[0u16, 1, 2], [0, 2, 3]] {
            put!(2u16);
            put!(-1i8);
            put!(5i8);
            put!(3u8);
            for i in tri {
                put!(i);
            }
            put!(1i32);
            put!(7u32);
        }
        put!(2i16);
        put!(1i32);
        put!(2i32);
        d
    }

    #[test]
    fn binary_both_byte_orders() {
        for be in [false, true] {
            let m = parse_ply(&binary_square(be), "t.ply")
                .unwrap_or_else(|e| panic!("{e}"))
                .mesh;
            assert_eq!(m.positions[2], PackedVec3::new(1.0, 1.0, 0.0), "be {be}");
            assert_eq!(m.positions[3], PackedVec3::new(0.0, 1.0, 0.0), "be {be}");
            assert_eq!(m.normals, vec![PackedVec3::Z; 4], "be {be}");
            assert_eq!(m.indices, vec![0, 1, 2, 0, 2, 3], "be {be}");
        }
    }

    #[test]
    fn binary_truncated_anywhere_is_an_error() {
        let full = binary_square(false);
        let body_start = full.windows(11).position(|w| w == b"end_header\n").unwrap() + 11;
        // 4 vertices of 37 bytes, 2 faces of 19, a strip of 10.
        assert_eq!(full.len() - body_start, 4 * 37 + 2 * 19 + 10);
        for cut in body_start..full.len() {
            let e = error(&full[..cut]);
            // Too short for the header's counts, or cut inside a record.
            assert!(
                e.starts_with("t.ply: the header announces ")
                    || (e.starts_with("t.ply: the data ends inside ")
                        && e.ends_with("the file is truncated")),
                "cut at {cut}: {e}"
            );
        }
        // Cut inside the second face's index list.
        let e = error(&full[..body_start + 4 * 37 + 19 + 6]);
        assert_eq!(
            e,
            "t.ply: the data ends inside face 1 of 2: the file is truncated"
        );
    }

    #[test]
    fn ascii_truncated() {
        let text = SQUARE.trim_end().trim_end_matches("3");
        let e = error(text.as_bytes());
        assert_eq!(
            e,
            "t.ply: the data ends inside face 0 of 1: the file is truncated"
        );
    }

    #[test]
    fn out_of_range_and_negative_indices() {
        let e = error(SQUARE.replace("4 0 1 2 3", "4 0 1 9000 3").as_bytes());
        assert_eq!(
            e,
            "t.ply: face 0 refers to vertex 9000 but there are 4 vertices"
        );
        let e = error(SQUARE.replace("4 0 1 2 3", "4 0 -1 2 3").as_bytes());
        assert_contains(&e, "face 0 refers to vertex -1");
    }

    #[test]
    fn non_finite_positions_are_refused() {
        for bad in ["nan", "inf", "-inf", "1e39"] {
            let e = error(
                SQUARE
                    .replace("1 1 0\n", &format!("1 {bad} 0\n"))
                    .as_bytes(),
            );
            assert_contains(&e, "t.ply: vertex 2 has position (1, ");
            assert_contains(&e, "which is not finite");
        }
    }

    #[test]
    fn not_a_number_names_the_word() {
        let e = error(SQUARE.replace("1 1 0\n", "1 one 0\n").as_bytes());
        assert_eq!(e, "t.ply: vertex 2: \"one\" is not a number");
    }

    #[test]
    fn huge_counts_are_refused_before_reading() {
        // 2^40 faces in a file of a few hundred bytes: refused from the header, at once.
        let huge = "element face 1099511627776";
        let ascii = SQUARE.replace("element face 1", huge);
        let full = binary_square(false);
        let end = full.windows(10).position(|w| w == b"end_header").unwrap();
        let mut binary = String::from_utf8(full[..end].to_vec())
            .unwrap()
            .replace("element face 2", huge)
            .into_bytes();
        binary.extend_from_slice(&full[end..]);
        for data in [ascii.into_bytes(), binary] {
            let start = std::time::Instant::now();
            let e = error(&data);
            assert!(start.elapsed().as_secs_f64() < 0.5);
            assert_contains(
                &e,
                "the header announces 1099511627776 \"face\" elements, more than the",
            );
        }
        // So is an unknown element that would be skipped.
        let text = SQUARE.replace(
            "end_header",
            "element blob 4000000000\nproperty double w\nend_header",
        );
        assert_contains(&error(text.as_bytes()), "4000000000 \"blob\" elements");
        // A list length is not trusted either: the reader stops where the data does.
        let mut d = binary_square(false);
        let at = d.len() - 10;
        d[at..at + 2].copy_from_slice(&i16::MAX.to_le_bytes());
        assert_contains(&error(&d), "inside strip 0 of 1");
    }

    #[test]
    fn header_errors() {
        assert_contains(&error(b"PK\x03\x04"), "not a PLY file");
        assert_contains(&error(b"ply\nformat ascii 1.0\n"), "no \"end_header\"");
        let e = error(
            SQUARE
                .replace("format ascii", "format binary_middle_endian")
                .as_bytes(),
        );
        assert_contains(&e, "header line 2: unknown format \"binary_middle_endian\"");
        let e = error(SQUARE.replace("1.0", "2.0").as_bytes());
        assert_contains(&e, "PLY version 2.0");
        let e = error(
            SQUARE
                .replace("property float y", "property float64x y")
                .as_bytes(),
        );
        assert_contains(&e, "header line 6: unknown type \"float64x\"");
        let e = error(SQUARE.replace("list uchar", "list float").as_bytes());
        assert_contains(&e, "floating-point type");
        let e = error(SQUARE.replace("comment", "remark").as_bytes());
        assert_contains(&e, "header line 3: unknown keyword \"remark\"");
        let e = error(SQUARE.replace("format ascii 1.0\n", "").as_bytes());
        assert_contains(&e, "no \"format\" line");
        let e = error(
            SQUARE
                .replace("property float z", "property float w")
                .as_bytes(),
        );
        assert_contains(&e, "no x, y and z");
        let e = error(SQUARE.replace("vertex_indices", "corners").as_bytes());
        assert_contains(&e, "\"face\" element has no \"vertex_indices\" list");
    }

    #[test]
    fn short_faces_are_counted_and_skipped() {
        let text = SQUARE
            .replace("element face 1", "element face 3")
            .replace("4 0 1 2 3\n", "2 0 1\n3 0 1 2\n0\n");
        let ply = parse_str(&text).unwrap();
        assert_eq!(ply.skipped_faces, 2);
        assert_eq!(ply.mesh.indices, vec![0, 1, 2]);
    }

    #[test]
    fn triangle_strips_alternate_and_restart() {
        let text = "ply\nformat ascii 1.0\nelement vertex 6\nproperty float x\n\
                    property float y\nproperty float z\nelement tristrips 1\n\
                    property list int int vertex_indices\nend_header\n\
                    0 0 0\n1 0 0\n0 1 0\n1 1 0\n0 2 0\n1 2 0\n\
                    9 0 1 2 3 -1 2 3 4 5\n";
        let m = mesh(text);
        assert_eq!(m.indices, vec![0, 1, 2, 2, 1, 3, 2, 3, 4, 4, 3, 5]);
    }

    #[test]
    fn gzipped_files_are_read() {
        use flate2::Compression;
        use flate2::write::GzEncoder;
        use std::io::Write;
        let dir = lancer_testing::ScratchDir::new("ply-gzip");
        let path = dir.join("square.ply.gz");
        let mut enc = GzEncoder::new(Vec::new(), Compression::default());
        enc.write_all(SQUARE.as_bytes()).unwrap();
        std::fs::write(&path, enc.finish().unwrap()).unwrap();
        let m = read_ply(&path).unwrap().mesh;
        assert_eq!(m.indices, vec![0, 1, 2, 0, 2, 3]);
        // Not gzip data behind the name: an error naming the file.
        let bad = dir.join("plain.ply.gz");
        std::fs::write(&bad, SQUARE).unwrap();
        let e = read_ply(&bad).unwrap_err();
        assert_eq!(e.file, bad.display().to_string());
        assert_contains(&e.message, "cannot decompress the file");
    }

    #[test]
    fn missing_file_names_it() {
        let e = read_ply(Path::new("/nonexistent/bunny.ply")).unwrap_err();
        assert_eq!(e.file, "/nonexistent/bunny.ply");
        assert_contains(&e.to_string(), "cannot read the file");
    }
}

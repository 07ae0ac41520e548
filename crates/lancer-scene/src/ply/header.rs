//! The PLY header: the format line, the elements with their properties and counts, and
//! the check of those counts against the bytes that follow.

/// A PLY scalar type.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Scalar {
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
    pub(super) fn parse(word: &str) -> Option<Scalar> {
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
    pub(super) fn size(self) -> usize {
        match self {
            Scalar::I8 | Scalar::U8 => 1,
            Scalar::I16 | Scalar::U16 => 2,
            Scalar::I32 | Scalar::U32 | Scalar::F32 => 4,
            Scalar::F64 => 8,
        }
    }

    pub(super) fn is_integer(self) -> bool {
        !matches!(self, Scalar::F32 | Scalar::F64)
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Format {
    Ascii,
    Binary { big_endian: bool },
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Kind {
    Scalar(Scalar),
    List { count: Scalar, item: Scalar },
}

#[derive(Debug)]
pub(super) struct Property {
    pub(super) name: String,
    pub(super) kind: Kind,
}

#[derive(Debug)]
pub(super) struct Element {
    pub(super) name: String,
    pub(super) count: u64,
    pub(super) props: Vec<Property>,
}

impl Element {
    pub(super) fn property(&self, name: &str) -> Option<usize> {
        self.props.iter().position(|p| p.name == name)
    }

    /// The index of the scalar property `name`, if there is one.
    pub(super) fn scalar(&self, name: &str) -> Option<usize> {
        self.property(name)
            .filter(|&i| matches!(self.props[i].kind, Kind::Scalar(_)))
    }

    /// Bytes one record takes at least in `format` (a list may be empty; in ASCII every
    /// number takes a character and a separator).
    pub(super) fn min_record_size(&self, format: Format) -> u64 {
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
pub(super) struct Header {
    pub(super) format: Format,
    pub(super) elements: Vec<Element>,
    /// Where the data starts: just after the `end_header` line.
    pub(super) body_start: usize,
}

pub(super) fn parse_header(data: &[u8]) -> Result<Header, String> {
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
pub(super) fn check_sizes(header: &Header, available: usize) -> Result<(), String> {
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

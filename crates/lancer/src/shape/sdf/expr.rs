//! The signed-distance expression language: lexer and parser, text → syntax tree.
//!
//! Grammar (whitespace allowed between any two tokens):
//!
//! ```text
//! expr   := call
//! call   := name "(" [ arg { "," arg } ] ")"
//! arg    := number | vector | call
//! vector := "[" number "," number "," number "]"
//! number := [ "+" | "-" ] digits [ "." digits ] [ ("e" | "E") [ "+" | "-" ] digits ]
//! name   := letter { letter | digit | "_" }
//! ```
//!
//! Every token and argument keeps its offset (in characters, from 0) in the source string, so
//! that errors can point at a column; the meaning of the calls (which functions exist, which
//! arguments they take) is checked by [`super::node`].

use glam::DVec3;
use std::fmt;

/// A syntax or meaning error in an expression, at a character offset (from 0) of its text.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("column {} of the expression: {message}", .offset + 1)]
pub struct SdfError {
    /// Character offset from the start of the expression, from 0.
    pub offset: usize,
    /// What went wrong, saying what was expected.
    pub message: String,
}

impl SdfError {
    pub(crate) fn new(offset: usize, message: impl Into<String>) -> SdfError {
        SdfError {
            offset,
            message: message.into(),
        }
    }
}

/// One argument of a call.
#[derive(Clone, Debug, PartialEq)]
pub enum Arg {
    /// A number.
    Number(f64),
    /// A vector `[x, y, z]`.
    Vector(DVec3),
    /// A nested call (a distance expression).
    Call(Call),
}

impl Arg {
    /// What kind of argument this is, for error messages.
    pub fn kind(&self) -> &'static str {
        match self {
            Arg::Number(_) => "a number",
            Arg::Vector(_) => "a vector",
            Arg::Call(_) => "a distance expression",
        }
    }
}

/// A function call `name(arg, …)`.
#[derive(Clone, Debug, PartialEq)]
pub struct Call {
    /// Function name.
    pub name: String,
    /// Character offset of the name.
    pub offset: usize,
    /// Arguments with the character offset where each starts.
    pub args: Vec<(Arg, usize)>,
    /// Character offset of the closing parenthesis.
    pub close: usize,
}

#[derive(Clone, Debug, PartialEq)]
enum Tok {
    Name(String),
    Number(f64),
    Open,
    Close,
    OpenBracket,
    CloseBracket,
    Comma,
    End,
}

impl fmt::Display for Tok {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Tok::Name(n) => write!(f, "'{n}'"),
            Tok::Number(x) => write!(f, "the number {x}"),
            Tok::Open => write!(f, "'('"),
            Tok::Close => write!(f, "')'"),
            Tok::OpenBracket => write!(f, "'['"),
            Tok::CloseBracket => write!(f, "']'"),
            Tok::Comma => write!(f, "','"),
            Tok::End => write!(f, "the end of the expression"),
        }
    }
}

/// Splits the text into tokens, each with its character offset.
fn lex(src: &str) -> Result<Vec<(Tok, usize)>, SdfError> {
    let chars: Vec<char> = src.chars().collect();
    let mut out = Vec::new();
    let mut i = 0;
    while i < chars.len() {
        let c = chars[i];
        let start = i;
        let single = match c {
            '(' => Some(Tok::Open),
            ')' => Some(Tok::Close),
            '[' => Some(Tok::OpenBracket),
            ']' => Some(Tok::CloseBracket),
            ',' => Some(Tok::Comma),
            _ => None,
        };
        if let Some(t) = single {
            out.push((t, start));
            i += 1;
        } else if c.is_whitespace() {
            i += 1;
        } else if c.is_ascii_alphabetic() {
            while i < chars.len() && (chars[i].is_ascii_alphanumeric() || chars[i] == '_') {
                i += 1;
            }
            out.push((Tok::Name(chars[start..i].iter().collect()), start));
        } else if c.is_ascii_digit() || matches!(c, '+' | '-' | '.') {
            // Sign, digits and point, then an exponent.
            if matches!(c, '+' | '-') {
                i += 1;
            }
            while i < chars.len() && (chars[i].is_ascii_digit() || chars[i] == '.') {
                i += 1;
            }
            if i < chars.len() && matches!(chars[i], 'e' | 'E') {
                i += 1;
                if i < chars.len() && matches!(chars[i], '+' | '-') {
                    i += 1;
                }
                while i < chars.len() && chars[i].is_ascii_digit() {
                    i += 1;
                }
            }
            let text: String = chars[start..i].iter().collect();
            let x: f64 = text
                .parse()
                .map_err(|_| SdfError::new(start, format!("'{text}' is not a number")))?;
            if !x.is_finite() {
                return Err(SdfError::new(
                    start,
                    format!("'{text}' is not a finite number"),
                ));
            }
            out.push((Tok::Number(x), start));
        } else {
            return Err(SdfError::new(
                start,
                format!(
                    "unexpected character '{}': expected a function name, a number, '[', '(', ')' or ','",
                    c.escape_debug()
                ),
            ));
        }
    }
    out.push((Tok::End, chars.len()));
    Ok(out)
}

struct Parser {
    toks: Vec<(Tok, usize)>,
    pos: usize,
    depth: usize,
}

/// Nesting deeper than this is refused (it would only come from a runaway generator, and the
/// evaluator recurses).
const MAX_DEPTH: usize = 200;

impl Parser {
    fn peek(&self) -> &(Tok, usize) {
        &self.toks[self.pos]
    }

    fn next(&mut self) -> (Tok, usize) {
        let t = self.toks[self.pos].clone();
        if self.pos + 1 < self.toks.len() {
            self.pos += 1;
        }
        t
    }

    fn expect(&mut self, want: Tok, what: &str) -> Result<usize, SdfError> {
        let (t, at) = self.next();
        if t == want {
            Ok(at)
        } else {
            Err(SdfError::new(at, format!("expected {what}, found {t}")))
        }
    }

    fn number(&mut self, context: &str) -> Result<f64, SdfError> {
        match self.next() {
            (Tok::Number(x), _) => Ok(x),
            (t, at) => Err(SdfError::new(
                at,
                format!("expected a number {context}, found {t}"),
            )),
        }
    }

    fn call(&mut self) -> Result<Call, SdfError> {
        let (t, offset) = self.next();
        let Tok::Name(name) = t else {
            return Err(SdfError::new(
                offset,
                format!("expected a function name such as sphere or union, found {t}"),
            ));
        };
        self.depth += 1;
        if self.depth > MAX_DEPTH {
            return Err(SdfError::new(
                offset,
                format!("expressions nested deeper than {MAX_DEPTH} calls are not supported"),
            ));
        }
        self.expect(Tok::Open, &format!("'(' after the function name '{name}'"))?;
        let mut args = Vec::new();
        let close = if self.peek().0 == Tok::Close {
            self.next().1
        } else {
            loop {
                args.push(self.arg()?);
                match self.next() {
                    (Tok::Comma, _) => {}
                    (Tok::Close, at) => break at,
                    (t, at) => {
                        return Err(SdfError::new(
                            at,
                            format!("expected ',' or ')' in the arguments of '{name}', found {t}"),
                        ));
                    }
                }
            }
        };
        self.depth -= 1;
        Ok(Call {
            name,
            offset,
            args,
            close,
        })
    }

    fn arg(&mut self) -> Result<(Arg, usize), SdfError> {
        let (t, at) = self.peek().clone();
        match t {
            Tok::Number(x) => {
                self.next();
                Ok((Arg::Number(x), at))
            }
            Tok::OpenBracket => {
                self.next();
                let x = self.number("(the vector's x)")?;
                self.expect(Tok::Comma, "',' after the vector's x")?;
                let y = self.number("(the vector's y)")?;
                self.expect(Tok::Comma, "',' after the vector's y")?;
                let z = self.number("(the vector's z)")?;
                self.expect(Tok::CloseBracket, "']' closing a 3-vector")?;
                Ok((Arg::Vector(DVec3::new(x, y, z)), at))
            }
            Tok::Name(_) => Ok((Arg::Call(self.call()?), at)),
            t => Err(SdfError::new(
                at,
                format!("expected an argument (a number, a vector [x, y, z] or a call), found {t}"),
            )),
        }
    }
}

/// Parses an expression into its syntax tree (one call).
pub fn parse(src: &str) -> Result<Call, SdfError> {
    let mut p = Parser {
        toks: lex(src)?,
        pos: 0,
        depth: 0,
    };
    let call = p.call()?;
    match p.next() {
        (Tok::End, _) => Ok(call),
        (t, at) => Err(SdfError::new(
            at,
            format!("expected the end of the expression after its outer call, found {t}"),
        )),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_nested_calls_with_offsets() {
        let c =
            parse("smooth_union(sphere(0.6), translate([0, 0.5, -1e-1], torus(0.7, .18)), 0.25)")
                .unwrap();
        assert_eq!(c.name, "smooth_union");
        assert_eq!(c.args.len(), 3);
        assert_eq!(c.args[0].1, 13);
        let Arg::Call(t) = &c.args[1].0 else {
            panic!("{:?}", c.args[1])
        };
        assert_eq!(t.name, "translate");
        assert_eq!(t.offset, 26);
        assert_eq!(t.args[0].0, Arg::Vector(DVec3::new(0.0, 0.5, -0.1)));
        let Arg::Call(torus) = &t.args[1].0 else {
            panic!()
        };
        assert_eq!(torus.args[1].0, Arg::Number(0.18));
        assert_eq!(c.args[2].0, Arg::Number(0.25));
    }

    #[test]
    fn errors_point_at_the_column_and_say_what_was_expected() {
        let cases: [(&str, usize, &str); 9] = [
            ("sphere(1", 8, "expected ',' or ')'"),
            (
                "sphere 1)",
                7,
                "expected '(' after the function name 'sphere'",
            ),
            (
                "union(sphere(1),, box([1,1,1]))",
                16,
                "expected an argument",
            ),
            (
                "translate([1, 2], sphere(1))",
                15,
                "expected ',' after the vector's y",
            ),
            ("translate([1, 2, 3, 4], sphere(1))", 18, "expected ']'"),
            (
                "sphere(1) sphere(2)",
                10,
                "expected the end of the expression",
            ),
            ("sphere(1 $ 2)", 9, "unexpected character '$'"),
            ("sphere(1.2.3)", 7, "'1.2.3' is not a number"),
            ("[1, 2, 3]", 0, "expected a function name"),
        ];
        for (src, col, msg) in cases {
            let e = parse(src).unwrap_err();
            assert_eq!(e.offset, col, "{src}: {e}");
            assert!(e.message.contains(msg), "{src}: {e}");
        }
        // Offsets count characters, not bytes.
        let e = parse("sphere(\u{a0}1 2)").unwrap_err();
        assert_eq!(e.offset, 10, "{e}");
    }

    #[test]
    fn runaway_nesting_is_refused() {
        let src = "scale(1, ".repeat(300) + "sphere(1)" + &")".repeat(300);
        assert!(parse(&src).unwrap_err().message.contains("nested deeper"));
    }
}

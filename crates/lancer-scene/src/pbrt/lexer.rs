//! The pbrt lexer: a scene file as a stream of words, quoted strings, numbers and brackets.
//!
//! pbrt's syntax has no statement separator: a directive is a bare word (`Shape`), followed by
//! its arguments and a parameter list of `"type name" value` pairs; `#` starts a comment that
//! runs to the end of the line.

use crate::error::{Location, SceneError};
use std::sync::Arc;

/// What a token is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TokenKind {
    /// A bare word: a directive name, `true`/`false`, or something malformed.
    Word,
    /// A quoted string (the text is its content, escapes resolved).
    Str,
    /// A finite number (its value is in [`Token::number`]).
    Number,
    /// `[`
    Open,
    /// `]`
    Close,
}

/// One token and where it starts.
#[derive(Clone, Debug, PartialEq)]
pub struct Token {
    /// Its kind.
    pub kind: TokenKind,
    /// Its text: a word, a string's content (escapes resolved), a bracket; empty for numbers.
    pub text: String,
    /// The value of a number.
    pub number: f64,
    /// True when a number is written as an integer (digits and an optional sign).
    pub integral: bool,
    /// Where it starts.
    pub loc: Location,
}

/// Splits one file's text into tokens.
pub struct Lexer {
    src: Arc<str>,
    pos: usize,
    line: u32,
    col: u32,
    file: Arc<str>,
}

fn is_delimiter(c: char) -> bool {
    c.is_whitespace() || matches!(c, '[' | ']' | '"' | '#')
}

impl Lexer {
    /// A lexer over `src`, reporting locations in `file`.
    pub fn new(src: Arc<str>, file: Arc<str>) -> Lexer {
        let pos = if src.starts_with('\u{feff}') { 3 } else { 0 };
        Lexer {
            src,
            pos,
            line: 1,
            col: 1,
            file,
        }
    }

    /// The current location.
    pub fn location(&self) -> Location {
        Location {
            file: self.file.clone(),
            line: self.line,
            col: self.col,
        }
    }

    fn peek_char(&self) -> Option<char> {
        self.src[self.pos..].chars().next()
    }

    fn bump(&mut self) -> Option<char> {
        let c = self.peek_char()?;
        self.pos += c.len_utf8();
        if c == '\n' {
            self.line += 1;
            self.col = 1;
        } else {
            self.col += 1;
        }
        Some(c)
    }

    /// The next token, `None` at the end of the file.
    pub fn next_token(&mut self) -> Result<Option<Token>, SceneError> {
        // Skip blanks and comments.
        loop {
            match self.peek_char() {
                Some(c) if c.is_whitespace() => {
                    self.bump();
                }
                Some('#') => {
                    while let Some(c) = self.peek_char() {
                        if c == '\n' {
                            break;
                        }
                        self.bump();
                    }
                }
                _ => break,
            }
        }
        let loc = self.location();
        let Some(c) = self.peek_char() else {
            return Ok(None);
        };
        let mut token = Token {
            kind: TokenKind::Word,
            text: String::new(),
            number: 0.0,
            integral: false,
            loc,
        };
        match c {
            '[' | ']' => {
                self.bump();
                token.kind = if c == '[' {
                    TokenKind::Open
                } else {
                    TokenKind::Close
                };
                token.text.push(c);
            }
            '"' => {
                self.bump();
                token.kind = TokenKind::Str;
                token.text = self.string_body(&token.loc)?;
            }
            _ => {
                let start = self.pos;
                while let Some(c) = self.peek_char() {
                    if is_delimiter(c) {
                        break;
                    }
                    self.bump();
                }
                let text = &self.src[start..self.pos];
                if c.is_ascii_digit() || matches!(c, '-' | '+' | '.') {
                    token.kind = TokenKind::Number;
                    token.number = parse_number(text, &token.loc)?;
                    let digits = text.strip_prefix(['-', '+']).unwrap_or(text);
                    token.integral =
                        !digits.is_empty() && digits.bytes().all(|b| b.is_ascii_digit());
                } else {
                    token.text = text.to_string();
                }
            }
        }
        Ok(Some(token))
    }

    /// The rest of a quoted string after its opening quote, with `\"`, `\\`, `\n`, `\t`
    /// resolved. A string must close on the line it opens.
    fn string_body(&mut self, open: &Location) -> Result<String, SceneError> {
        let mut s = String::new();
        loop {
            let Some(c) = self.peek_char() else {
                return Err(SceneError::at(
                    open.clone(),
                    "this string is never closed: the file ends first",
                ));
            };
            match c {
                '"' => {
                    self.bump();
                    return Ok(s);
                }
                '\n' => {
                    return Err(SceneError::at(
                        open.clone(),
                        "this string is not closed on its line",
                    ));
                }
                '\\' => {
                    let esc_loc = self.location();
                    self.bump();
                    let e = self.bump();
                    s.push(match e {
                        Some('n') => '\n',
                        Some('t') => '\t',
                        Some('r') => '\r',
                        Some('"') => '"',
                        Some('\\') => '\\',
                        Some('\'') => '\'',
                        Some('b') => '\u{8}',
                        Some('f') => '\u{c}',
                        other => {
                            let what = other.map_or("the end of the file".to_string(), |c| {
                                format!("'\\{}'", c.escape_debug())
                            });
                            return Err(SceneError::at(
                                esc_loc,
                                format!("unknown escape sequence {what} in a string"),
                            ));
                        }
                    });
                }
                c => {
                    s.push(c);
                    self.bump();
                }
            }
        }
    }
}

/// Parses a number: finite, or an error at `loc` (NaN and infinities are refused: a scene
/// that needs them is malformed).
pub fn parse_number(text: &str, loc: &Location) -> Result<f64, SceneError> {
    match text.parse::<f64>() {
        Ok(v) if v.is_finite() && v.abs() <= f32::MAX as f64 => Ok(v),
        Ok(_) => Err(SceneError::at(
            loc.clone(),
            format!("'{text}' is not a finite number"),
        )),
        Err(_) => Err(SceneError::at(
            loc.clone(),
            format!("'{text}' is not a number"),
        )),
    }
}

/// The 1-based line `line` of `src` (without its line break), for error excerpts.
pub fn source_line(src: &str, line: u32) -> Option<String> {
    let src = src.strip_prefix('\u{feff}').unwrap_or(src);
    src.split('\n')
        .nth(line.checked_sub(1)? as usize)
        .map(|l| l.trim_end_matches('\r').to_string())
}

/// Checks that a file's bytes are UTF-8; otherwise an error at the first bad byte.
pub fn decode_utf8(bytes: &[u8], file: &Arc<str>) -> Result<String, SceneError> {
    match std::str::from_utf8(bytes) {
        Ok(s) => Ok(s.to_string()),
        Err(e) => {
            let good = &bytes[..e.valid_up_to()];
            // Safe: the prefix is valid UTF-8 by construction.
            let prefix = std::str::from_utf8(good).unwrap_or_default();
            let line = prefix.matches('\n').count() as u32 + 1;
            let line_start = prefix.rfind('\n').map_or(0, |i| i + 1);
            let col = prefix[line_start..].chars().count() as u32 + 1;
            let bad = bytes[e.valid_up_to()];
            let rest = &bytes[line_start..];
            let end = rest.iter().position(|&b| b == b'\n').unwrap_or(rest.len());
            Err(SceneError {
                location: Some(Location {
                    file: file.clone(),
                    line,
                    col,
                }),
                message: format!(
                    "the file is not valid UTF-8 text (byte 0x{bad:02x}); scene files must be UTF-8"
                ),
                source_line: Some(String::from_utf8_lossy(&rest[..end]).into_owned()),
            })
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn lex(src: &str) -> Result<Vec<(TokenKind, String, u32, u32)>, SceneError> {
        let mut l = Lexer::new(Arc::from(src), Arc::from("t.pbrt"));
        let mut out = Vec::new();
        while let Some(t) = l.next_token()? {
            let text = if t.kind == TokenKind::Number {
                t.number.to_string()
            } else {
                t.text
            };
            out.push((t.kind, text, t.loc.line, t.loc.col));
        }
        Ok(out)
    }

    #[test]
    fn tokens_and_locations() {
        use TokenKind::*;
        let t = lex("Shape \"sphere\" # comment\n  \"float radius\" [-1.5e2]").unwrap();
        assert_eq!(
            t,
            vec![
                (Word, "Shape".into(), 1, 1),
                (Str, "sphere".into(), 1, 7),
                (Str, "float radius".into(), 2, 3),
                (Open, "[".into(), 2, 18),
                (Number, "-150".into(), 2, 19),
                (Close, "]".into(), 2, 25),
            ]
        );
    }

    #[test]
    fn escapes_and_unclosed_strings() {
        assert_eq!(lex(r#""a\"b\\c""#).unwrap()[0].1, "a\"b\\c");
        let e = lex("Shape \"sph").unwrap_err();
        assert_eq!(
            (e.location.as_ref().unwrap().line, e.location.unwrap().col),
            (1, 7)
        );
        assert!(lex("\"a\nb\"").is_err());
        assert!(lex(r#""\q""#).is_err());
        assert!(lex("1e999").is_err());
        assert!(lex("-nan").is_err());
        assert!(lex("1.2.3").is_err());
    }

    #[test]
    fn invalid_utf8_is_located() {
        let e = decode_utf8(b"Shape\n  \"a\xff\"", &Arc::from("x.pbrt")).unwrap_err();
        let loc = e.location.unwrap();
        assert_eq!((loc.line, loc.col), (2, 5));
    }
}

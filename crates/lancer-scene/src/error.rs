//! Diagnostics: errors that stop a scene from loading and warnings that do not, each pinned to
//! a place in a file.

use std::fmt;
use std::sync::Arc;

/// A place in a scene file: the path as the user named it, 1-based line and column (columns
/// count characters, not bytes).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Location {
    /// The file, as named on the command line or in an `Include`.
    pub file: Arc<str>,
    /// Line, from 1.
    pub line: u32,
    /// Column, from 1.
    pub col: u32,
}

impl fmt::Display for Location {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}:{}:{}", self.file, self.line, self.col)
    }
}

/// Why a scene could not be loaded.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct SceneError {
    /// Where (absent when no file is involved, e.g. an unknown format).
    pub location: Option<Location>,
    /// What is wrong, one line.
    pub message: String,
    /// The source line the location points into, for the excerpt.
    pub source_line: Option<String>,
}

impl SceneError {
    /// An error at a place, without an excerpt.
    pub fn at(location: Location, message: impl Into<String>) -> SceneError {
        SceneError {
            location: Some(location),
            message: message.into(),
            source_line: None,
        }
    }

    /// An error not tied to a place in a file.
    pub fn general(message: impl Into<String>) -> SceneError {
        SceneError {
            location: None,
            message: message.into(),
            source_line: None,
        }
    }

    /// The excerpt shown under the message: the offending line and a caret under the column.
    pub fn excerpt_lines(&self) -> Vec<String> {
        match (&self.location, &self.source_line) {
            (Some(loc), Some(text)) => {
                let number = loc.line.to_string();
                let pad = " ".repeat(number.len());
                // Tabs are kept so that the caret lines up with what the terminal shows.
                let lead: String = text
                    .chars()
                    .take(loc.col.saturating_sub(1) as usize)
                    .map(|c| if c == '\t' { '\t' } else { ' ' })
                    .collect();
                vec![
                    format!("{pad} |"),
                    format!("{number} | {text}"),
                    format!("{pad} | {lead}^"),
                ]
            }
            _ => Vec::new(),
        }
    }
}

impl fmt::Display for SceneError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match &self.location {
            Some(loc) => write!(f, "{loc}: {}", self.message),
            None => f.write_str(&self.message),
        }
    }
}

impl std::error::Error for SceneError {}

/// Something lancer read but does not (yet) do, and what it does instead.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Warning {
    /// Where.
    pub location: Location,
    /// What, and what lancer does instead.
    pub message: String,
}

impl fmt::Display for Warning {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}: {}", self.location, self.message)
    }
}

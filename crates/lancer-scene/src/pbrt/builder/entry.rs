//! The reader's entry: every directive of a parsed file into a [`Built`] scene description.

use super::Builder;
use crate::LoadOptions;
use crate::error::{SceneError, Warning};
use crate::pbrt::parser::Parser;
use lancer::scene::desc::SceneDesc;

/// A scene read: its description, its warnings, and its notes (what the reader made, such as
/// the displaced meshes' triangle counts).
pub struct Built {
    /// The scene.
    pub desc: SceneDesc,
    /// What lancer does differently, or what is wrong but readable.
    pub warnings: Vec<Warning>,
    /// Facts worth printing.
    pub notes: Vec<Warning>,
}

/// Reads every directive of `parser` into a scene description, with `options`.
pub fn build(parser: &mut Parser, options: &LoadOptions) -> Result<Built, SceneError> {
    let mut b = Builder::new(options);
    let mut last = None;
    while let Some(d) = parser.next_directive()? {
        last = Some(d.loc.clone());
        b.directive(d)?;
    }
    let end = last.unwrap_or_else(|| parser.start_location());
    b.finish(end)
}

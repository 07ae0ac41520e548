//! The reader's entry: every directive of a parsed file into a [`Built`] scene description.

use super::Builder;
use super::built::Built;
use crate::LoadOptions;
use crate::error::SceneError;
use crate::pbrt::parser::Parser;

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

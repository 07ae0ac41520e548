//! Reading the scene: a file named on the command line, or the built-in default scene.

use crate::cli_error::CliError;
use lancer_scene::LoadedScene;
use std::path::Path;

/// The built-in default scene (`scenes/default.pbrt` in the repository), compiled in.
pub const DEFAULT_SCENE: &str = include_str!("../../../scenes/default.pbrt");

/// Name under which the default scene's diagnostics are reported.
pub const DEFAULT_SCENE_NAME: &str = "<default scene>";

/// Reads `path`, or the built-in default scene when `None`. Prints nothing: the caller decides
/// what to do with the warnings.
pub fn read(path: Option<&Path>) -> Result<LoadedScene, CliError> {
    match path {
        Some(p) => lancer_scene::load(p),
        None => lancer_scene::load_pbrt_str(DEFAULT_SCENE, DEFAULT_SCENE_NAME, Path::new(".")),
    }
    .map_err(|e| CliError::input(e.to_string()).with_detail(e.excerpt_lines()))
}

/// [`read`], then prints the warnings on stderr.
pub fn load(path: Option<&Path>) -> Result<LoadedScene, CliError> {
    let loaded = read(path)?;
    for w in &loaded.warnings {
        eprintln!("warning: {w}");
    }
    Ok(loaded)
}

//! Reading the scene: a file named on the command line, pbrt text on standard input (`-`), or
//! the built-in default scene.

use crate::cli_error::CliError;
use lancer_scene::LoadedScene;
use std::io::Read;
use std::path::{Path, PathBuf};

/// The built-in default scene (`scenes/default.pbrt` in the repository), compiled in.
pub const DEFAULT_SCENE: &str = include_str!("../../../scenes/default.pbrt");

/// Name under which the default scene's diagnostics are reported.
pub const DEFAULT_SCENE_NAME: &str = "<default scene>";

/// Name under which a scene read from standard input is reported (`<stdin>:line:column`).
pub const STDIN_NAME: &str = "<stdin>";

/// True when `path` asks for standard input (`-`).
pub fn is_stdin(path: &Path) -> bool {
    path == Path::new("-")
}

/// Reads `path` (a file, or pbrt text on standard input when it is `-`; relative file names in
/// that text are relative to the current folder), or the built-in default scene when `None`.
/// Prints nothing: the caller decides what to do with the warnings.
pub fn read(path: Option<&Path>) -> Result<LoadedScene, CliError> {
    match path {
        Some(p) if is_stdin(p) => {
            // Gzip-compressed text is accepted, as in files (`zcat`-free pipes).
            let mut bytes = Vec::new();
            let bytes = std::io::stdin()
                .read_to_end(&mut bytes)
                .and_then(|_| lancer_scene::files_read::gunzip_if_compressed(bytes))
                .map_err(|e| CliError::input(format!("{STDIN_NAME}: cannot read: {e}")))?;
            let text = lancer_scene::pbrt::lexer::decode_utf8(&bytes, &STDIN_NAME.into())
                .map_err(|e| CliError::input(e.to_string()).with_detail(e.excerpt_lines()))?;
            let dir = std::env::current_dir().unwrap_or_else(|_| PathBuf::from("."));
            lancer_scene::load_pbrt_str(&text, STDIN_NAME, &dir)
        }
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

/// `--strict`: the first of the reader's warnings as an error (`file:line:column: message`),
/// the others as detail lines; nothing when there is none.
pub fn refuse_warnings(loaded: &LoadedScene) -> Result<(), CliError> {
    let Some(first) = loaded.warnings.first() else {
        return Ok(());
    };
    let others = loaded.warnings[1..]
        .iter()
        .map(|w| format!("warning: {w}"))
        .collect();
    Err(
        CliError::input(format!("{first} (--strict makes every warning an error)"))
            .with_detail(others),
    )
}

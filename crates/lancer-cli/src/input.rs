//! Reading the scene: a file named on the command line, pbrt text on standard input (`-`), or
//! the built-in default scene.

use crate::cli_error::CliError;
use lancer_scene::{LoadOptions, LoadedScene};
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

/// The options that change what the scene reader makes (`lancer render` and `lancer info`).
#[derive(clap::Args, Clone, Copy, Debug)]
pub struct ReadArgs {
    /// Multiplies every displaced plymesh's "edgelength" (pbrt-v4's
    /// --displacementedgescale): larger makes fewer, larger triangles.
    #[arg(long, value_name = "SCALE", default_value_t = 1.0, value_parser = parse_edge_scale)]
    pub displacement_edge_scale: f32,
    /// The most triangles the scene's displaced plymeshes may have in all (a scene that would
    /// make more is refused before it takes the memory; at most 2^30).
    #[arg(long, value_name = "N", default_value_t = lancer_scene::DEFAULT_MAX_DISPLACED_TRIANGLES,
          value_parser = clap::value_parser!(u64).range(1..=lancer::shape::MAX_DISPLACED_TRIANGLES))]
    pub max_displaced_triangles: u64,
}

impl ReadArgs {
    /// The reader's options.
    pub fn options(&self) -> LoadOptions {
        LoadOptions {
            displacement_edge_scale: self.displacement_edge_scale,
            max_displaced_triangles: self.max_displaced_triangles,
        }
    }
}

fn parse_edge_scale(s: &str) -> Result<f32, String> {
    match s.trim().parse::<f32>() {
        Ok(v) if v > 0.0 && v.is_finite() => Ok(v),
        _ => Err(format!("'{s}' is not a positive number")),
    }
}

/// Reads `path` (a file, or pbrt text on standard input when it is `-`; relative file names in
/// that text are relative to the current folder), or the built-in default scene when `None`,
/// with `options`. Prints nothing: the caller decides what to do with the warnings and notes.
pub fn read(path: Option<&Path>, options: &LoadOptions) -> Result<LoadedScene, CliError> {
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
            lancer_scene::load_pbrt_str_with(&text, STDIN_NAME, &dir, options)
        }
        Some(p) => lancer_scene::load_with(p, options),
        None => lancer_scene::load_pbrt_str_with(
            DEFAULT_SCENE,
            DEFAULT_SCENE_NAME,
            Path::new("."),
            options,
        ),
    }
    .map_err(|e| CliError::input(e.to_string()).with_detail(e.excerpt_lines()))
}

/// [`read`], then prints the warnings on stderr.
pub fn load(path: Option<&Path>, options: &LoadOptions) -> Result<LoadedScene, CliError> {
    let loaded = read(path, options)?;
    for w in &loaded.warnings {
        eprintln!("warning: {w}");
    }
    Ok(loaded)
}

/// Prints the reader's notes on stderr (what it made: the displaced meshes' triangles).
pub fn print_notes(loaded: &LoadedScene) {
    for n in &loaded.notes {
        eprintln!("note: {n}");
    }
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

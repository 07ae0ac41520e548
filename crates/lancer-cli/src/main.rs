//! `lancer`: the command line of the lancer ray tracer.
//!
//! `lancer render [SCENE]` renders a scene file (pbrt-v4, and glTF/OBJ/PLY models) or, with no
//! file, the built-in default scene. Exit status: 0 on success, 2 when the input is at fault (a
//! malformed scene, a missing file, bad options), 1 when something else fails (writing the
//! image, an interrupted render).

mod cli_error;
mod input;
mod progress;
mod render;

use clap::{Parser, Subcommand};

/// lancer — a physically based ray tracer.
#[derive(Parser, Debug)]
#[command(name = "lancer", version, about, long_about = None)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand, Debug)]
enum Command {
    /// Render a scene to an image (PNG or EXR, chosen by the extension).
    Render(render::RenderArgs),
}

fn main() {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Render(args) => render::run(args),
    };
    if let Err(e) = result {
        e.report();
        std::process::exit(e.exit_code());
    }
}

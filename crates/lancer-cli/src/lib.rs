//! The command line of the lancer ray tracer as a library: [`run`] is `lancer`'s whole
//! program over a given argument list, so that the binary (`src/main.rs`) and the Python
//! package's `lancer` command (an entry point of the wheel) are the same program; and the
//! pieces another front end reuses: [`split`] (which pixels and samples a part holds, the
//! scene hash) and [`merge`] (checking that parts belong together, adding them up).
//!
//! Exit status: 0 on success, 2 when the input is at fault (a malformed scene, a missing file,
//! bad options), 1 when something else fails (writing the image, an interrupted render; an
//! interrupted render exits with 130 after writing its checkpoint).

mod bench;
mod bench_scene;
mod checkpoint;
pub mod cli_error;
mod completions;
mod denoise;
mod film_memory;
mod img;
mod info;
mod input;
mod live;
pub mod merge;
mod output;
mod preview;
mod progress;
mod render;
mod render_args;
pub mod split;
mod stats;
mod strategy_images;
mod tev;

use clap::{CommandFactory, Parser, Subcommand};
use std::ffi::OsString;

/// What `--version` prints after the name: the version, the commit and the build target.
const VERSION: &str = concat!(
    env!("CARGO_PKG_VERSION"),
    " (commit ",
    env!("LANCER_COMMIT"),
    "; ",
    env!("LANCER_TARGET"),
    ")"
);

/// lancer, a physically based ray tracer: renders pbrt-v4 scenes and glTF, OBJ and PLY models.
#[derive(Parser, Debug)]
#[command(name = "lancer", version = VERSION, propagate_version = true, long_about = None)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand, Debug)]
enum Command {
    /// Render a scene to an image (PNG or EXR, chosen by the extension).
    Render(Box<render_args::RenderArgs>),
    /// Describe a scene without rendering it: camera, counts, lights, bounds, memory, files.
    Info(info::InfoArgs),
    /// Merge the parts of a split render (`render --split i/N`) into the final image.
    Merge(merge::MergeArgs),
    /// Measure the renderer's parts (`bench rays MESH`: BVH build and ray throughput; `bench
    /// scene SCENE`: a render's phases, throughput, peak memory and relMSE).
    #[command(subcommand)]
    Bench(bench::BenchCommand),
    /// Compare, convert and inspect images (`img diff`, `img convert`, `img info`).
    #[command(subcommand)]
    Img(img::ImgCommand),
    /// Print a shell completion script (bash, zsh, fish, elvish, powershell).
    Completions(completions::CompletionsArgs),
}

/// A binary built for x86-64-v3 (see `.cargo/config.toml`) dies of an illegal instruction on
/// an older CPU; say so plainly instead, and how to rebuild.
fn check_cpu() {
    #[cfg(all(target_arch = "x86_64", target_feature = "avx2"))]
    if !(std::arch::is_x86_feature_detected!("avx2") && std::arch::is_x86_feature_detected!("fma"))
    {
        eprintln!(
            "error: this lancer was built for CPUs with AVX2 and FMA, which this one lacks; \
             rebuild it with RUSTFLAGS=\"-C target-cpu=x86-64\" cargo build --release"
        );
        std::process::exit(1);
    }
}

/// Runs `lancer` with `args` (the program name first, as `std::env::args_os` gives them) and
/// returns its exit status; everything is printed on this process's stdout and stderr, as the
/// binary prints it (clap's help, version and usage errors included: status 0 for help and
/// version, 2 for a usage error).
pub fn run(args: Vec<OsString>) -> i32 {
    let status = run_command(args);
    // `std::process::exit` (the binary's, or Python's after its entry point) does not flush.
    let _ = std::io::Write::flush(&mut std::io::stdout());
    status
}

/// [`run`] before the final flush.
fn run_command(args: Vec<OsString>) -> i32 {
    check_cpu();
    let args = render_args::bare_stats_as_text(args);
    // The arguments after `lancer render` (past the program's name and `render`), which a new
    // checkpoint records.
    let command_line = args
        .iter()
        .skip(2)
        .map(|a| a.to_string_lossy().into_owned())
        .collect();
    let cli = match Cli::try_parse_from(args) {
        Ok(cli) => cli,
        Err(e) => {
            let _ = e.print();
            return e.exit_code();
        }
    };
    let result = match cli.command {
        Command::Render(mut args) => {
            args.command_line = command_line;
            render::run(*args)
        }
        Command::Info(args) => info::run(args),
        Command::Merge(args) => merge::run(args),
        Command::Bench(cmd) => bench::run(cmd),
        Command::Img(cmd) => img::run(cmd),
        Command::Completions(args) => completions::run(args, Cli::command()),
    };
    match result {
        Ok(()) => 0,
        Err(e) => {
            e.report();
            e.exit_code()
        }
    }
}

//! `lancer`: the command line of the lancer ray tracer.
//!
//! `lancer render [SCENE]` renders a scene file (pbrt-v4, and glTF/OBJ/PLY models) or, with no
//! file, the built-in default scene. Exit status: 0 on success, 2 when the input is at fault (a
//! malformed scene, a missing file, bad options), 1 when something else fails (writing the
//! image, an interrupted render).

mod bench;
mod bench_scene;
mod checkpoint;
mod cli_error;
mod completions;
mod denoise;
mod img;
mod info;
mod input;
mod live;
mod merge;
mod output;
mod preview;
mod progress;
mod render;
mod render_args;
mod split;
mod stats;
mod tev;

use clap::{CommandFactory, Parser, Subcommand};

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

fn main() {
    check_cpu();
    let cli = Cli::parse_from(render_args::bare_stats_as_text(
        std::env::args_os().collect(),
    ));
    let result = match cli.command {
        Command::Render(args) => render::run(*args),
        Command::Info(args) => info::run(args),
        Command::Merge(args) => merge::run(args),
        Command::Bench(cmd) => bench::run(cmd),
        Command::Img(cmd) => img::run(cmd),
        Command::Completions(args) => completions::run(args, Cli::command()),
    };
    if let Err(e) = result {
        e.report();
        std::process::exit(e.exit_code());
    }
}

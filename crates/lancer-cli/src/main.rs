//! `lancer`: the command line of the lancer ray tracer (the program is the library's
//! [`lancer_cli::run`], which the Python package's `lancer` command runs too).
//!
//! `lancer render [SCENE]` renders a scene file (pbrt-v4, and glTF/OBJ/PLY models) or, with no
//! file, the built-in default scene. Exit status: 0 on success, 2 when the input is at fault (a
//! malformed scene, a missing file, bad options), 1 when something else fails (writing the
//! image, an interrupted render).

fn main() {
    std::process::exit(lancer_cli::run(std::env::args_os().collect()));
}

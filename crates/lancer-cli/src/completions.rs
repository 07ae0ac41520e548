//! `lancer completions SHELL`: prints a completion script for the shell on standard output,
//! generated from the command line's own definition (so it never falls out of date).
//!
//! Install, for example: `lancer completions bash > ~/.local/share/bash-completion/completions/lancer`,
//! `lancer completions zsh > ~/.zfunc/_lancer` (with `~/.zfunc` in `fpath`),
//! `lancer completions fish > ~/.config/fish/completions/lancer.fish`.

use crate::cli_error::CliError;
use clap::Args;
use clap_complete::Shell;

/// Options of `lancer completions`.
#[derive(Args, Debug)]
pub struct CompletionsArgs {
    /// The shell: bash, zsh, fish, elvish or powershell.
    #[arg(value_enum)]
    pub shell: Shell,
}

/// Writes the completion script of `command` (the whole `lancer` command line) for the shell.
pub fn run(args: CompletionsArgs, mut command: clap::Command) -> Result<(), CliError> {
    let name = command.get_name().to_string();
    clap_complete::generate(args.shell, &mut command, name, &mut std::io::stdout());
    Ok(())
}

//! Errors as the command line reports them: one line naming the culprit, optional detail
//! lines, and an exit status telling input errors (2) from other failures (1).

/// A failure of a command.
#[derive(Debug)]
pub struct CliError {
    /// The one-line message (for scene errors: `file:line:column: message`).
    pub message: String,
    /// Further lines (a source excerpt, a hint).
    pub detail: Vec<String>,
    /// True when the user's input is at fault.
    pub input: bool,
}

impl CliError {
    /// An error in the user's input (exit status 2).
    pub fn input(message: impl Into<String>) -> CliError {
        CliError {
            message: message.into(),
            detail: Vec::new(),
            input: true,
        }
    }

    /// Any other failure (exit status 1).
    pub fn runtime(message: impl Into<String>) -> CliError {
        CliError {
            message: message.into(),
            detail: Vec::new(),
            input: false,
        }
    }

    /// Adds detail lines.
    pub fn with_detail(mut self, lines: Vec<String>) -> CliError {
        self.detail = lines;
        self
    }

    /// The process exit status for this error.
    pub fn exit_code(&self) -> i32 {
        if self.input { 2 } else { 1 }
    }

    /// Prints the error on stderr.
    pub fn report(&self) {
        eprintln!("error: {}", self.message);
        for l in &self.detail {
            eprintln!("{l}");
        }
    }
}

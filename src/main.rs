//! `karstgen`: the command users install (`cargo install --path .`). See [`karstgen::cli`].

use std::process::ExitCode;

fn main() -> ExitCode {
    karstgen::cli::main()
}

//! The `probelab` binary: parses the command line and hands it to `commands`, one file per
//! subcommand. The binary owns the terminal; the library it calls never prints.

mod commands;

use clap::Parser;
use commands::output;

fn main() {
    // clap's own output (--help, --version, usage errors) goes through the same rules as the
    // commands': a closed pipe ends quietly (141), any other write error exits 2.
    let cli = match commands::Cli::try_parse() {
        Ok(cli) => cli,
        Err(e) => std::process::exit(match e.print() {
            Ok(()) => e.exit_code(),
            Err(io) => output::failure(&output::StdoutError(io).into()).0,
        }),
    };
    match commands::main_with(cli) {
        Ok(code) => std::process::exit(code),
        Err(e) => {
            // Exit 2 with the message; 141, quietly, when stdout's reader went away.
            let (code, message) = output::failure(&e);
            if let Some(m) = message {
                output::note_fmt(format_args!("{m}"));
            }
            std::process::exit(code);
        }
    }
}

//! The `probelab` binary: parses the command line and hands it to `commands`, one file per
//! subcommand. The binary owns the terminal; the library it calls never prints.

mod commands;

use clap::Parser;
use commands::output;

fn main() {
    quiet_caught_decoder_panics();
    // clap's own output (--help, --version, usage errors) goes through the same rules as the
    // commands': a closed pipe ends quietly (141), any other write error exits 2.
    let cli = match commands::Cli::try_parse() {
        Ok(cli) => cli,
        Err(e) if e.exit_code() == 0 && output::stdout_closed() => {
            // --help or --version into a standard output closed at start.
            output::note_fmt(format_args!("error: {}\n", output::closed_stdout_error()));
            std::process::exit(2);
        }
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

/// Keeps the panics the map loader catches off stderr. A decoder panic on a malformed map file
/// comes back as an error (`LoadError::DecoderPanic`) that the command prints as `error: …`;
/// the default hook would print the panic first. Installed before anything runs, this hook
/// stays quiet while the loader runs a decoder on this thread
/// (`envmap::load::in_guarded_decoder`) and hands every other panic to the default hook.
fn quiet_caught_decoder_panics() {
    let previous = std::panic::take_hook();
    std::panic::set_hook(Box::new(move |info| {
        if !probelab::ops::in_guarded_decoder() {
            previous(info);
        }
    }));
}

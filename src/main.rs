use clap::Parser;

fn main() {
    let cli = probelab::cli::Cli::parse();
    match probelab::cli::main_with(cli) {
        Ok(code) => std::process::exit(code),
        Err(e) => {
            eprintln!("error: {e:#}");
            std::process::exit(2);
        }
    }
}

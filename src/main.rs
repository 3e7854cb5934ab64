//! `voussoir` binary: parse the command line, run, exit with its code.

use clap::Parser;

fn main() {
    let cli = voussoir::cli::Cli::parse();
    std::process::exit(voussoir::cli::run(cli));
}

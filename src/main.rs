//! `voussoir` binary: parse the command line, run, exit with its code.

use clap::Parser;

/// mimalloc rather than glibc's malloc: the solver's large vectors are freed and allocated again
/// stage after stage, and glibc hands their pages back and faults them in anew each time.
#[global_allocator]
static GLOBAL: mimalloc::MiMalloc = mimalloc::MiMalloc;

fn main() {
    let cli = voussoir::cli::Cli::parse();
    std::process::exit(voussoir::cli::run(cli));
}

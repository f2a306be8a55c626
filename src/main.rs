//! The `rubsim` command: scene → model → integrate → analyse → write (see [`cli`]).

mod cli;

use std::io::Write as _;

fn main() {
    // SIGPIPE stays ignored (Rust's default): a closed stdout (`rubsim sweep … | head -1`)
    // must not kill a run before it commits its results; the command line's `println!`
    // ignores the EPIPE instead (see `cli`).
    if let Err(e) = cli::run() {
        // `{e:#}` would repeat a cause its parent already quotes (e.g. the I/O error of
        // "cannot read scene file: …"); append only causes not already shown.
        let mut msg = e.to_string();
        for cause in e.chain().skip(1) {
            let c = cause.to_string();
            if !msg.ends_with(&c) {
                msg = format!("{msg}: {c}");
            }
        }
        // Written, not `eprintln!`: a closed stderr must not turn the error into a panic.
        let _ = writeln!(std::io::stderr(), "error: {msg}");
        std::process::exit(2);
    }
}

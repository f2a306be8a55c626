//! The `rubsim` command: scene → model → integrate → analyse → write (see [`cli`]).

mod cli;

fn main() {
    // Die quietly on a closed pipe (`rubsim … | head`) instead of panicking in println!.
    // SAFETY: restoring the default disposition of SIGPIPE before any thread is started.
    #[cfg(unix)]
    unsafe {
        libc::signal(libc::SIGPIPE, libc::SIG_DFL);
    }
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
        eprintln!("error: {msg}");
        std::process::exit(2);
    }
}

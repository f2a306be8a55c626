//! Running gmsh as a guarded child process: under a time limit, in its own process group, killed
//! with rubsim, its output condensed.
//!
//! # Why a guard
//!
//! gmsh can run for minutes on a bad geometry (a negative pitch, an element size of 0) and prints
//! one line per failing entity (thousands of identical lines). A run of rubsim must not wait for
//! it for ever, must not leave it running when rubsim is stopped, and must not leave its half
//! written mesh in the cache.
//!
//! # How
//!
//! * **Time limit.** [`run`] waits for the child with `wait-timeout` and, past the limit, kills
//!   its whole process group with `SIGKILL` and reports [`Finished::TimedOut`].
//! * **Process group.** The child is started in a new process group (`process_group(0)`), so
//!   that killing the group also kills whatever it started (a wrapper script's children), and a
//!   terminal's Ctrl-C reaches rubsim only, which then decides.
//! * **Killed with rubsim.** Two layers, because neither covers every case alone:
//!   - On Linux the child asks the kernel for `SIGKILL` when the thread that started it dies
//!     (`PR_SET_PDEATHSIG` through `rustix`, between fork and exec). This covers every way
//!     rubsim can die, `SIGKILL` included. The thread that starts gmsh waits for it, so it
//!     outlives it.
//!   - The first guarded run has `signal-hook` catch `SIGTERM`, `SIGINT` and `SIGHUP` (a signal
//!     ignored at that moment, as under `nohup`, stays ignored) and starts a thread that, on the
//!     first of them, kills every registered child group, removes every registered temporary
//!     file, and makes rubsim die of the signal with the usual status (the default action,
//!     restored and raised again). The waiting thread that sees its child killed meanwhile does
//!     not report a gmsh failure: it waits for the process to end, so a stopped rubsim never
//!     exits with an error status of its own instead. This layer is what removes the temporary
//!     files at once; after a `SIGKILL` of rubsim they are removed by the next mesher (see
//!     [`super::gmsh`]). The handlers stay installed for the rest of the process.
//! * **Condensed output.** Lines are read as they come (so a chatty child never blocks on a full
//!   pipe) and counted: each distinct line is kept once, in order of first appearance, with its
//!   count ([`Condensed`], from the private module `condensed`).

pub use super::condensed::Condensed;
use super::condensed::Counter;
use std::io::{BufRead, BufReader, Read};
use std::path::Path;
use std::process::{Command, ExitStatus, Stdio};
use std::time::Duration;
use wait_timeout::ChildExt;

/// How a guarded child ended.
#[derive(Debug)]
pub enum Finished {
    /// It exited (or was killed by someone else) within the limit.
    Exited {
        /// Its exit status.
        status: ExitStatus,
        /// Its output.
        output: Condensed,
    },
    /// It ran past the limit and its process group was killed.
    TimedOut {
        /// What it printed until then.
        output: Condensed,
    },
}

/// Runs `cmd` (stdin closed, stdout and stderr captured) in its own process group under the
/// time limit `limit`, killed with the calling process; `temporary` files (those the child
/// writes) are removed if rubsim is stopped by `SIGTERM`, `SIGINT` or `SIGHUP` meanwhile. On a
/// time-out the group is killed and the files are left to the caller. Errors: the child cannot
/// be started.
pub fn run(mut cmd: Command, limit: Duration, temporary: &[&Path]) -> std::io::Result<Finished> {
    cmd.stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped());
    guard::prepare(&mut cmd);
    let _files = guard::Registered::files(temporary);
    spawn_and_wait(&mut cmd, limit)
}

fn spawn_and_wait(cmd: &mut Command, limit: Duration) -> std::io::Result<Finished> {
    let mut child = cmd.spawn()?;
    let group = guard::Registered::group(child.id());
    let (tx, rx) = std::sync::mpsc::channel();
    let mut readers = 0;
    if let Some(out) = child.stdout.take() {
        reader(0, out, tx.clone());
        readers += 1;
    }
    if let Some(err) = child.stderr.take() {
        reader(1, err, tx.clone());
        readers += 1;
    }
    drop(tx);
    // An error waiting for it is treated as a time-out: the group is killed.
    let status = child.wait_timeout(limit).unwrap_or(None);
    guard::wait_if_stopping();
    if status.is_none() {
        guard::kill_group(child.id());
        let _ = child.kill();
        let _ = child.wait();
    }
    drop(group);
    // The pipes close when the group is gone; a process that left the group and keeps them
    // open is not waited for beyond a second.
    let mut parts: Vec<(usize, Condensed)> = Vec::new();
    while parts.len() < readers {
        match rx.recv_timeout(Duration::from_secs(1)) {
            Ok(p) => parts.push(p),
            Err(_) => break,
        }
    }
    parts.sort_by_key(|(k, _)| *k);
    let mut counter = Counter::default();
    for (_, c) in parts {
        for (l, n) in c.lines {
            counter.add_n(&l, n);
        }
        counter.add_dropped(c.dropped);
    }
    let output = counter.done();
    Ok(match status {
        Some(status) => Finished::Exited { status, output },
        None => Finished::TimedOut { output },
    })
}

/// A thread reading the lines of a pipe, condensed as they come (identical lines counted, so
/// memory stays bounded however much the child prints); sends `(which, lines)` at the end.
fn reader<R: Read + Send + 'static>(
    which: usize,
    r: R,
    tx: std::sync::mpsc::Sender<(usize, Condensed)>,
) {
    std::thread::spawn(move || {
        let mut counter = Counter::default();
        let mut buf = Vec::new();
        let mut r = BufReader::new(r);
        while let Ok(n) = r.read_until(b'\n', &mut buf) {
            if n == 0 {
                break;
            }
            counter.add(&String::from_utf8_lossy(&buf));
            buf.clear();
        }
        let _ = tx.send((which, counter.done()));
    });
}

// ---------------------------------------------------------------------------------------------
// Process group, parent-death signal, and the registry the signal thread reads.

#[cfg(unix)]
mod guard {
    use rustix::process::{Pid, Signal};
    use std::os::unix::process::CommandExt;
    use std::path::{Path, PathBuf};
    use std::process::Command;
    use std::sync::atomic::{AtomicBool, Ordering};
    use std::sync::{Mutex, MutexGuard, Once, PoisonError};

    /// What the signal thread kills and removes.
    #[derive(Clone, PartialEq)]
    enum Entry {
        /// A running child's process group (its pid).
        Group(u32),
        /// A temporary file of a running child.
        File(PathBuf),
    }

    static REGISTRY: Mutex<Vec<Entry>> = Mutex::new(Vec::new());
    /// Set by the signal thread before it kills anything: rubsim is dying of a signal.
    static STOPPING: AtomicBool = AtomicBool::new(false);

    fn registry() -> MutexGuard<'static, Vec<Entry>> {
        REGISTRY.lock().unwrap_or_else(PoisonError::into_inner)
    }

    /// Entries of the registry, taken out of it when this value is dropped.
    pub(super) struct Registered(Vec<Entry>);

    impl Registered {
        /// Registers the temporary files `paths` (and installs the signal thread, once).
        pub(super) fn files(paths: &[&Path]) -> Self {
            install();
            Self::new(paths.iter().map(|p| Entry::File(p.to_path_buf())).collect())
        }

        /// Registers the process group of the child `pid`.
        pub(super) fn group(pid: u32) -> Self {
            Self::new(vec![Entry::Group(pid)])
        }

        fn new(entries: Vec<Entry>) -> Self {
            registry().extend(entries.iter().cloned());
            Self(entries)
        }
    }

    impl Drop for Registered {
        fn drop(&mut self) {
            let mut reg = registry();
            for e in &self.0 {
                if let Some(i) = reg.iter().position(|r| r == e) {
                    reg.swap_remove(i);
                }
            }
        }
    }

    /// Starts the child in a process group of its own and, on Linux, has the kernel kill it
    /// when the thread that starts it dies.
    pub(super) fn prepare(cmd: &mut Command) {
        cmd.process_group(0);
        #[cfg(target_os = "linux")]
        {
            let parent = rustix::process::getpid();
            // SAFETY: between fork and exec only system calls (prctl, getppid), no allocation.
            unsafe {
                cmd.pre_exec(move || {
                    rustix::process::set_parent_process_death_signal(Some(Signal::KILL))?;
                    // The parent may have died before prctl: then nobody would signal the child.
                    if rustix::process::getppid() != Some(parent) {
                        return Err(rustix::io::Errno::SRCH.into());
                    }
                    Ok(())
                });
            }
        }
    }

    /// Kills the process group of the child `pid` (`SIGKILL`).
    pub(super) fn kill_group(pid: u32) {
        if let Some(pid) = i32::try_from(pid).ok().and_then(Pid::from_raw) {
            let _ = rustix::process::kill_process_group(pid, Signal::KILL);
        }
    }

    /// Returns at once unless rubsim is being stopped by a signal; then never (the signal
    /// thread kills the child and ends the process: its death is not a gmsh failure).
    pub(super) fn wait_if_stopping() {
        while STOPPING.load(Ordering::SeqCst) {
            std::thread::park();
        }
    }

    /// Catches `SIGTERM`, `SIGINT` and `SIGHUP` (those not ignored) once, in a thread that
    /// [`stop`]s at the first one. If they cannot be caught, gmsh still dies with rubsim
    /// (`PR_SET_PDEATHSIG`) and its files are removed by the next mesher.
    fn install() {
        use signal_hook::consts::{SIGHUP, SIGINT, SIGTERM};
        static ONCE: Once = Once::new();
        ONCE.call_once(|| {
            let caught: Vec<i32> = [SIGTERM, SIGINT, SIGHUP]
                .into_iter()
                .filter(|&s| !ignored(s))
                .collect();
            let Ok(mut signals) = signal_hook::iterator::Signals::new(caught) else {
                return;
            };
            let _ = std::thread::Builder::new()
                .name("rubsim-signals".into())
                .spawn(move || {
                    if let Some(sig) = signals.forever().next() {
                        stop(sig);
                    }
                });
        });
    }

    /// Kills every registered group, removes every registered file, and dies of `sig`.
    fn stop(sig: i32) {
        STOPPING.store(true, Ordering::SeqCst);
        let reg = registry();
        for e in reg.iter() {
            if let Entry::Group(pid) = e {
                kill_group(*pid);
            }
        }
        for e in reg.iter() {
            if let Entry::File(p) = e {
                let _ = std::fs::remove_file(p);
            }
        }
        let _ = signal_hook::low_level::emulate_default_handler(sig);
        // Only if the default action did not end the process.
        std::process::exit(128 + sig);
    }

    /// True when `sig` is ignored (`SIG_IGN`, inherited from `nohup` or a background job).
    fn ignored(sig: i32) -> bool {
        // SAFETY: sigaction with a null new action only reads the current one into `old`.
        unsafe {
            let mut old: libc::sigaction = std::mem::zeroed();
            libc::sigaction(sig, std::ptr::null(), &mut old) == 0
                && old.sa_sigaction == libc::SIG_IGN
        }
    }
}

/// Elsewhere the child is only killed on a time-out ([`std::process::Child::kill`]).
#[cfg(not(unix))]
mod guard {
    use std::path::Path;
    use std::process::Command;

    pub(super) struct Registered;

    impl Registered {
        pub(super) fn files(_: &[&Path]) -> Self {
            Self
        }
        pub(super) fn group(_: u32) -> Self {
            Self
        }
    }

    pub(super) fn prepare(_: &mut Command) {}
    pub(super) fn kill_group(_: u32) {}
    pub(super) fn wait_if_stopping() {}
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::time::Instant;

    #[cfg(unix)]
    #[test]
    fn a_child_past_its_limit_is_killed_with_its_group() {
        // The shell starts a grandchild (sleep) that must die with it.
        let mut cmd = Command::new("sh");
        cmd.args(["-c", "echo started; echo $$ >&2; sleep 30 & wait"]);
        let t0 = Instant::now();
        let Finished::TimedOut { output } = run(cmd, Duration::from_millis(300), &[]).unwrap()
        else {
            panic!("should time out");
        };
        assert!(t0.elapsed() < Duration::from_secs(5));
        assert_eq!(output.lines[0].0, "started");
        let pgid: i32 = output.lines[1].0.parse().unwrap();
        // Nothing is left running in the group (zombies of the killed grandchild may wait for
        // a reaper that does not come in a container: they run nothing).
        std::thread::sleep(Duration::from_millis(100));
        let running = running_in_group(pgid);
        assert!(running.is_empty(), "group {pgid} survived: {running:?}");
    }

    /// Processes of group `pgid` that are not zombies (Linux `/proc`).
    fn running_in_group(pgid: i32) -> Vec<String> {
        let Ok(rd) = std::fs::read_dir("/proc") else {
            return vec![];
        };
        rd.flatten()
            .filter_map(|e| std::fs::read_to_string(e.path().join("stat")).ok())
            .filter(|stat| {
                let f: Vec<&str> = stat
                    .rsplit_once(')')
                    .map_or(vec![], |(_, r)| r.split_whitespace().collect());
                f.len() > 2 && f[0] != "Z" && f[2] == pgid.to_string()
            })
            .collect()
    }

    #[test]
    fn exit_status_and_output_of_a_child_within_its_limit() {
        let mut cmd = Command::new("sh");
        cmd.args([
            "-c",
            "for i in 1 2 3; do echo same; done; echo err >&2; exit 3",
        ]);
        let Finished::Exited { status, output } = run(cmd, Duration::from_secs(20), &[]).unwrap()
        else {
            panic!("should exit");
        };
        assert_eq!(status.code(), Some(3));
        assert_eq!(output.render(|_| true), "same (×3)\nerr");
    }
}

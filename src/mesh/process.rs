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
//! * **Time limit.** [`run`] polls the child (every 5 ms at first, then every 50 ms) and, past
//!   the limit, kills its whole process group with `SIGKILL` and reports [`Finished::TimedOut`].
//! * **Process group.** The child is started in a new process group (`setpgid(0, 0)`), so that
//!   killing the group also kills whatever it started (a wrapper script's children), and a
//!   terminal's Ctrl-C reaches rubsim only, which then decides.
//! * **Killed with rubsim.** Two layers, because neither covers every case alone:
//!   - On Linux the child asks the kernel for `SIGKILL` when the thread that started it dies
//!     (`prctl(PR_SET_PDEATHSIG)` between fork and exec). This covers every way rubsim can die,
//!     `SIGKILL` included. The thread that starts gmsh waits for it, so it outlives it.
//!   - The first guarded run installs handlers for `SIGTERM`, `SIGINT` and `SIGHUP` that kill
//!     every registered child group and remove every registered temporary file (`kill` and
//!     `unlink` are async-signal-safe), then pass the signal on: to the handler installed before
//!     theirs, if any, or by restoring the default action and raising it again, so rubsim still
//!     dies of the signal with the usual status. A signal that was ignored when the handlers are
//!     installed (`nohup`) stays ignored. This layer is what removes the temporary files at
//!     once; after a `SIGKILL` of rubsim they are removed by the next mesher (see
//!     [`super::gmsh`]).
//! * **Condensed output.** Lines are read as they come (so a chatty child never blocks on a full
//!   pipe) and counted: each distinct line is kept once, in order of first appearance, with its
//!   count ([`Condensed`]).

use std::collections::HashMap;
use std::io::{BufRead, BufReader, Read};
use std::path::Path;
use std::process::{Child, Command, ExitStatus, Stdio};
use std::sync::atomic::{AtomicI32, AtomicPtr, Ordering};
use std::time::{Duration, Instant};

/// Distinct lines kept by [`Condensed`]; later distinct lines are only counted.
const MAX_DISTINCT: usize = 200;
/// Longest line kept (bytes); longer lines are cut.
const MAX_LINE: usize = 500;

/// A child's output (stdout then stderr lines, in order of first appearance), each distinct
/// line once with the number of times it was printed.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Condensed {
    /// `(line, count)`, in order of first appearance (at most 200 distinct lines).
    pub lines: Vec<(String, usize)>,
    /// Lines not kept because 200 distinct lines were already kept.
    pub dropped: usize,
}

impl Condensed {
    /// Counts the lines of `text`.
    pub fn from_text(text: &str) -> Self {
        let mut c = Counter::default();
        for l in text.lines() {
            c.add(l);
        }
        c.done()
    }

    /// The lines `keep` accepts, each as `line` or `line (×n)` when printed n > 1 times, joined
    /// by newlines.
    pub fn render(&self, keep: impl Fn(&str) -> bool) -> String {
        let mut out: Vec<String> = self
            .lines
            .iter()
            .filter(|(l, _)| keep(l))
            .map(|(l, n)| {
                if *n > 1 {
                    format!("{l} (×{n})")
                } else {
                    l.clone()
                }
            })
            .collect();
        if self.dropped > 0 {
            out.push(format!("… and {} more lines", self.dropped));
        }
        out.join("\n")
    }

    /// Total number of lines printed.
    pub fn total(&self) -> usize {
        self.lines.iter().map(|(_, n)| n).sum::<usize>() + self.dropped
    }
}

#[derive(Default)]
struct Counter {
    index: HashMap<String, usize>,
    out: Condensed,
}

impl Counter {
    fn add(&mut self, line: &str) {
        self.add_n(line, 1);
    }

    fn add_n(&mut self, line: &str, n: usize) {
        let mut line = line.trim_end();
        if line.len() > MAX_LINE {
            let mut cut = MAX_LINE;
            while !line.is_char_boundary(cut) {
                cut -= 1;
            }
            line = &line[..cut];
        }
        if let Some(&i) = self.index.get(line) {
            self.out.lines[i].1 += n;
        } else if self.out.lines.len() < MAX_DISTINCT {
            self.index.insert(line.to_string(), self.out.lines.len());
            self.out.lines.push((line.to_string(), n));
        } else {
            self.out.dropped += n;
        }
    }

    fn done(self) -> Condensed {
        self.out
    }
}

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
    install_handlers();
    cmd.stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped());
    guard_command(&mut cmd);
    let files: Vec<usize> = temporary.iter().filter_map(|p| register_file(p)).collect();
    let result = spawn_and_wait(&mut cmd, limit);
    for slot in files {
        unregister_file(slot);
    }
    result
}

fn spawn_and_wait(cmd: &mut Command, limit: Duration) -> std::io::Result<Finished> {
    let mut child = cmd.spawn()?;
    let pid = child.id() as i32;
    let slot = register_child(pid);
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
    let status = wait_until(&mut child, limit);
    if status.is_none() {
        kill_group(pid);
        let _ = child.wait();
    }
    if let Some(s) = slot {
        CHILDREN[s].store(0, Ordering::SeqCst);
    }
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
        counter.out.dropped += c.dropped;
    }
    let output = counter.done();
    Ok(match status {
        Some(status) => Finished::Exited { status, output },
        None => Finished::TimedOut { output },
    })
}

/// The child's exit status, or `None` when `limit` passed first (child still running).
fn wait_until(child: &mut Child, limit: Duration) -> Option<ExitStatus> {
    let start = Instant::now();
    let mut pause = Duration::from_millis(5);
    loop {
        match child.try_wait() {
            Ok(Some(s)) => return Some(s),
            Ok(None) => {}
            // Cannot wait on it: treat as a time-out (the caller kills it).
            Err(_) => return None,
        }
        let elapsed = start.elapsed();
        if elapsed >= limit {
            return None;
        }
        std::thread::sleep(pause.min(limit - elapsed));
        pause = (pause * 2).min(Duration::from_millis(50));
    }
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
// Process group, parent-death signal, and the registry the signal handlers read.

/// Slots for running child process groups (pgid, 0 = free) and temporary files (a leaked C
/// string, null = free), read by the signal handlers.
const SLOTS: usize = 64;
static CHILDREN: [AtomicI32; SLOTS] = [const { AtomicI32::new(0) }; SLOTS];
static FILES: [AtomicPtr<libc::c_char>; SLOTS] =
    [const { AtomicPtr::new(std::ptr::null_mut()) }; SLOTS];

#[cfg(unix)]
fn guard_command(cmd: &mut Command) {
    use std::os::unix::process::CommandExt;
    cmd.process_group(0);
    #[cfg(target_os = "linux")]
    {
        let parent = std::process::id() as libc::pid_t;
        // SAFETY: between fork and exec only async-signal-safe calls (prctl, getppid, _exit).
        unsafe {
            cmd.pre_exec(move || {
                if libc::prctl(libc::PR_SET_PDEATHSIG, libc::SIGKILL) != 0 {
                    return Err(std::io::Error::last_os_error());
                }
                // The parent may have died before prctl: then nobody will signal us.
                if libc::getppid() != parent {
                    libc::_exit(1);
                }
                Ok(())
            });
        }
    }
}

#[cfg(not(unix))]
fn guard_command(_cmd: &mut Command) {}

fn register_child(pid: i32) -> Option<usize> {
    (0..SLOTS).find(|&i| {
        CHILDREN[i]
            .compare_exchange(0, pid, Ordering::SeqCst, Ordering::SeqCst)
            .is_ok()
    })
}

#[cfg(not(unix))]
fn register_file(_path: &Path) -> Option<usize> {
    None
}

#[cfg(unix)]
fn register_file(path: &Path) -> Option<usize> {
    use std::os::unix::ffi::OsStrExt;
    let c = std::ffi::CString::new(path.as_os_str().as_bytes()).ok()?;
    let raw = c.into_raw();
    let slot = (0..SLOTS).find(|&i| {
        FILES[i]
            .compare_exchange(
                std::ptr::null_mut(),
                raw,
                Ordering::SeqCst,
                Ordering::SeqCst,
            )
            .is_ok()
    });
    if slot.is_none() {
        // SAFETY: `raw` came from `into_raw` just above and was not published.
        drop(unsafe { std::ffi::CString::from_raw(raw) });
    }
    slot
}

fn unregister_file(slot: usize) {
    let raw = FILES[slot].swap(std::ptr::null_mut(), Ordering::SeqCst);
    if !raw.is_null() {
        // SAFETY: published by `register_file` from `into_raw`; the swap made it ours (a
        // signal handler that took it first leaves null and leaks it, the process is dying).
        drop(unsafe { std::ffi::CString::from_raw(raw) });
    }
}

fn kill_group(pid: i32) {
    #[cfg(unix)]
    // SAFETY: plain system call; a negative pid names the process group.
    unsafe {
        libc::kill(-pid, libc::SIGKILL);
    }
}

/// Kills every registered group and removes every registered file (async-signal-safe: atomics,
/// `kill`, `unlink`).
fn kill_all_and_clean() {
    for c in &CHILDREN {
        let pid = c.swap(0, Ordering::SeqCst);
        if pid > 0 {
            kill_group(pid);
        }
    }
    for f in &FILES {
        let raw = f.swap(std::ptr::null_mut(), Ordering::SeqCst);
        if !raw.is_null() {
            // SAFETY: a NUL-terminated path published by `register_file` (never freed once
            // taken here).
            unsafe {
                libc::unlink(raw);
            }
        }
    }
}

#[cfg(unix)]
mod handlers {
    use super::kill_all_and_clean;
    use std::sync::atomic::{AtomicUsize, Ordering};

    pub(super) const SIGNALS: [libc::c_int; 3] = [libc::SIGTERM, libc::SIGINT, libc::SIGHUP];
    /// The handler each signal had before ours (`sa_sigaction`) and its flags.
    static PREV: [AtomicUsize; 3] = [const { AtomicUsize::new(0) }; 3];
    static PREV_FLAGS: [AtomicUsize; 3] = [const { AtomicUsize::new(0) }; 3];

    extern "C" fn on_signal(sig: libc::c_int, info: *mut libc::siginfo_t, ctx: *mut libc::c_void) {
        kill_all_and_clean();
        let Some(k) = SIGNALS.iter().position(|&s| s == sig) else {
            return;
        };
        let prev = PREV[k].load(Ordering::SeqCst);
        let flags = PREV_FLAGS[k].load(Ordering::SeqCst) as libc::c_int;
        // SAFETY: `prev` is a handler the process installed before ours; it is called as it
        // was installed (with or without SA_SIGINFO). Otherwise the default action is restored
        // and the signal raised again, so the process dies of it as it would have.
        unsafe {
            if prev != libc::SIG_DFL && prev != libc::SIG_IGN {
                if flags & libc::SA_SIGINFO != 0 {
                    let f: extern "C" fn(libc::c_int, *mut libc::siginfo_t, *mut libc::c_void) =
                        std::mem::transmute(prev);
                    f(sig, info, ctx);
                } else {
                    let f: extern "C" fn(libc::c_int) = std::mem::transmute(prev);
                    f(sig);
                }
            } else {
                libc::signal(sig, libc::SIG_DFL);
                libc::raise(sig);
            }
        }
    }

    pub(super) fn install() {
        for (k, &sig) in SIGNALS.iter().enumerate() {
            // SAFETY: sigaction with a zeroed, then filled, struct; the handler only makes
            // async-signal-safe calls.
            unsafe {
                let mut old: libc::sigaction = std::mem::zeroed();
                if libc::sigaction(sig, std::ptr::null(), &mut old) != 0
                    || old.sa_sigaction == libc::SIG_IGN
                {
                    continue;
                }
                PREV[k].store(old.sa_sigaction, Ordering::SeqCst);
                PREV_FLAGS[k].store(old.sa_flags as usize, Ordering::SeqCst);
                let mut new: libc::sigaction = std::mem::zeroed();
                new.sa_sigaction = on_signal as *const () as usize;
                new.sa_flags = libc::SA_SIGINFO | libc::SA_RESTART;
                libc::sigemptyset(&mut new.sa_mask);
                libc::sigaction(sig, &new, std::ptr::null_mut());
            }
        }
    }
}

/// Installs the signal handlers once (see the module documentation).
fn install_handlers() {
    static ONCE: std::sync::Once = std::sync::Once::new();
    #[cfg(unix)]
    ONCE.call_once(handlers::install);
    #[cfg(not(unix))]
    ONCE.call_once(|| {});
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn repeated_lines_are_counted_once_in_order() {
        let c = Condensed::from_text("a\nb\na\na\nc\n");
        assert_eq!(
            c.lines,
            vec![("a".into(), 3), ("b".into(), 1), ("c".into(), 1)]
        );
        assert_eq!(c.total(), 5);
        assert_eq!(c.render(|l| l != "b"), "a (×3)\nc");
    }

    #[test]
    fn distinct_lines_are_bounded() {
        let text: String = (0..MAX_DISTINCT + 7)
            .map(|i| format!("line {i}\n"))
            .collect();
        let c = Condensed::from_text(&text);
        assert_eq!(c.lines.len(), MAX_DISTINCT);
        assert_eq!(c.dropped, 7);
        assert!(c.render(|_| true).ends_with("… and 7 more lines"));
    }

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

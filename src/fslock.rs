//! Advisory file locks: the one `flock(2)` wrapper of the crate, used by the output directory
//! (`.rubsim-lock`, [`crate::output::OutDir`]) and by gmsh's temporary files in the mesh cache
//! ([`crate::mesh::gmsh`]). A lock held by a live process, in any PID namespace, is what marks
//! its files as in use; a free lock means their owner is gone.

use std::fs::File;

/// Takes an exclusive advisory lock on `f` without waiting (`flock(LOCK_EX | LOCK_NB)`, held
/// until the file is closed; std's `File::try_lock` needs a Rust above the crate's MSRV).
/// `Ok(false)`: another process (or another open file description) holds it.
///
/// # Errors
/// The operating system's error when `flock` fails for another reason than a held lock.
#[cfg(unix)]
pub fn try_lock(f: &File) -> std::io::Result<bool> {
    use std::os::unix::io::AsRawFd;
    // SAFETY: flock(2) on a file descriptor that `f` owns and keeps open.
    if unsafe { libc::flock(f.as_raw_fd(), libc::LOCK_EX | libc::LOCK_NB) } == 0 {
        return Ok(true);
    }
    let e = std::io::Error::last_os_error();
    if e.kind() == std::io::ErrorKind::WouldBlock {
        Ok(false)
    } else {
        Err(e)
    }
}

/// Elsewhere (rubsim is built and tested on Linux) nothing is locked: always taken.
///
/// # Errors
/// None.
#[cfg(not(unix))]
pub fn try_lock(_: &File) -> std::io::Result<bool> {
    Ok(true)
}

//! Work on a stranger's bytes in a forked child process with stated limits, so that a
//! decoder we do not own (`openusd`'s) can fail only as an error.
//!
//! A decoder that trusts a count in its input can ask for terabytes (the allocation
//! failure aborts the process, which no `catch_unwind` can stop), recurse until the
//! stack overflows (the same), panic, or loop. Run here, on Linux, it runs in a child
//! forked from the caller's thread, under an address-space limit of the child's size at
//! the fork plus [`Limits::memory`], a CPU-time limit, a limit on what it may write, and
//! no core dump; its standard output and error go to an anonymous memory file, never the
//! terminal. The parent waits at most [`Limits::wall`], then kills it, and turns every
//! way the child can end into one line: the work's own error, its panic's message, "it
//! asked for N bytes", "its nesting overflowed the stack", "it took over N s".
//!
//! Elsewhere it runs in this process behind a panic boundary only.
//!
//! The child shares the parent's memory copy-on-write (the input is not copied) and
//! calls only what the work calls (glibc's allocator is safe after `fork` in a threaded
//! process); it ends with `_exit`, so no destructor, buffer or exit handler of the
//! parent's runs twice.

use std::time::Duration;

#[cfg(target_os = "linux")]
mod linux;

/// What the child may use.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Limits {
    /// Address space the child may add to what it had at the fork, in bytes (its
    /// reply, written from memory, is bounded by this too).
    pub memory: u64,
    /// CPU time, in whole seconds.
    pub cpu_seconds: u64,
    /// Wall-clock time before the parent kills the child.
    pub wall: Duration,
}

/// A child's successful reply.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Reply {
    /// What the work returned.
    pub bytes: Vec<u8>,
    /// The child's address space at its largest, over what it had at the fork, in
    /// bytes (`VmPeak` less the starting `VmSize`).
    pub peak_memory: u64,
}

/// Runs `work` in a child process under `limits` (on Linux; elsewhere in this process,
/// behind a panic boundary only). `Err(message)` is the work's own error, or says in
/// one line how the child failed (a panic, a limit, a signal).
pub fn run<F>(limits: Limits, work: F) -> Result<Reply, String>
where
    F: FnOnce() -> Result<Vec<u8>, String>,
{
    #[cfg(target_os = "linux")]
    return linux::run(limits, work);
    #[cfg(not(target_os = "linux"))]
    {
        let _ = limits;
        match std::panic::catch_unwind(std::panic::AssertUnwindSafe(work)) {
            Ok(Ok(bytes)) => Ok(Reply {
                bytes,
                peak_memory: 0,
            }),
            Ok(Err(message)) => Err(message),
            Err(_) => Err("the decoder failed on it (a malformed file)".into()),
        }
    }
}

/// In a test binary: when `RUST_BACKTRACE` asks for backtraces, runs test `name`
/// again in a process of its own without them and says so (true: the caller is done).
/// A child that fails a decode prints a symbolised backtrace first when asked, about a
/// hundred times the cost of the decode: a sweep of thousands of hostile files goes
/// from seconds to minutes.
#[doc(hidden)]
pub fn rerun_without_backtraces(name: &str) -> bool {
    if std::env::var_os("RUST_BACKTRACE").is_none_or(|v| v == "0") {
        return false;
    }
    let exe = std::env::current_exe().expect("the test binary's path");
    let out = std::process::Command::new(exe)
        .args(["--exact", name, "--test-threads", "1"])
        .env("RUST_BACKTRACE", "0")
        .output()
        .expect("the test binary runs");
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success() && text.contains("1 passed"),
        "{name} without backtraces: {text}{}",
        String::from_utf8_lossy(&out.stderr)
    );
    true
}

#[cfg(all(test, target_os = "linux"))]
mod tests;

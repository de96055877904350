//! The child process on Linux: `fork`, resource limits, memory files for the reply and
//! the child's own words, and a pipe that wakes the parent when the child ends.

use std::fs::File;
use std::io::{Read as _, Seek as _, SeekFrom, Write as _};
use std::os::fd::{AsRawFd as _, FromRawFd as _};
use std::time::{Duration, Instant};

use super::{Limits, Reply};
use crate::error::size_text;

/// The most of the child's own output read for the diagnosis: its first words (an
/// allocation failure's or a panic's message comes before any backtrace).
const LOG_HEAD: u64 = 16 << 10;

const TAG_OK: u8 = 0;
const TAG_ERROR: u8 = 1;
const TAG_PANIC: u8 = 2;

/// Runs `work` in a child process under `limits`. `Err(message)` is the work's own
/// error, or says how the child failed (a panic, a limit, a signal).
pub(super) fn run<F>(limits: Limits, work: F) -> Result<Reply, String>
where
    F: FnOnce() -> Result<Vec<u8>, String>,
{
    let reply = memory_file(c"fur-isolate-reply")?;
    let log = memory_file(c"fur-isolate-log")?;
    // The child holds the write end of this pipe until it ends: the read end then
    // wakes the parent at once.
    let mut ends = [0; 2];
    // SAFETY: `ends` has room for the two descriptors.
    if unsafe { libc::pipe2(ends.as_mut_ptr(), libc::O_CLOEXEC) } != 0 {
        return Err(format!(
            "could not start the decoding process: {}",
            std::io::Error::last_os_error()
        ));
    }
    // SAFETY: both descriptors were just opened and are owned by nothing else.
    let (ended, alive) = unsafe { (File::from_raw_fd(ends[0]), File::from_raw_fd(ends[1])) };
    // SAFETY: `fork` has no preconditions; in the child only this thread exists, and
    // `child` calls what the work calls and ends with `_exit`, never returning here.
    let pid = unsafe { libc::fork() };
    if pid < 0 {
        return Err(format!(
            "could not start the decoding process: {}",
            std::io::Error::last_os_error()
        ));
    }
    if pid == 0 {
        child(limits, &reply, &log, work);
    }
    drop(alive);
    let status = wait(pid, &ended, limits.wall);
    let head = read_head(&log);
    let status = status?;
    outcome(status, &reply, &head, limits)
}

/// An anonymous file in memory, closed on `exec`.
fn memory_file(name: &std::ffi::CStr) -> Result<File, String> {
    // SAFETY: `name` is a valid C string; the flag is a valid `memfd_create` flag.
    let fd = unsafe { libc::memfd_create(name.as_ptr(), libc::MFD_CLOEXEC) };
    if fd < 0 {
        return Err(format!(
            "could not make the decoding process's memory file: {}",
            std::io::Error::last_os_error()
        ));
    }
    // SAFETY: `fd` was just opened and is owned by nothing else.
    Ok(unsafe { File::from_raw_fd(fd) })
}

/// Sets `resource`'s soft limit to `value` and its hard limit `headroom` above it (the
/// CPU limit signals at the soft limit, and kills without a word at the hard one).
fn set_limit(resource: libc::__rlimit_resource_t, value: u64, headroom: u64) {
    let limit = libc::rlimit {
        rlim_cur: value,
        rlim_max: value.saturating_add(headroom),
    };
    // SAFETY: `limit` is a valid rlimit for the duration of the call. A limit that
    // cannot be set (one already lower) leaves the lower one, which is as safe.
    unsafe { libc::setrlimit(resource, &limit) };
}

/// A `kB` line of `/proc/self/status`, in bytes.
fn status_bytes(key: &str) -> Option<u64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with(key))?;
    let kb: u64 = line[key.len()..]
        .trim()
        .trim_end_matches("kB")
        .trim()
        .parse()
        .ok()?;
    Some(kb * 1024)
}

/// The child: limits, the work, its reply; never returns.
fn child<F>(limits: Limits, reply: &File, log: &File, work: F) -> !
where
    F: FnOnce() -> Result<Vec<u8>, String>,
{
    // SAFETY: both descriptors are open; standard output and error become the log, so
    // nothing the decoder or a panic prints reaches the terminal (or an image on
    // standard output).
    unsafe {
        libc::dup2(log.as_raw_fd(), 1);
        libc::dup2(log.as_raw_fd(), 2);
    }
    let start = status_bytes("VmSize:").unwrap_or(0);
    set_limit(libc::RLIMIT_CORE, 0, 0);
    set_limit(libc::RLIMIT_FSIZE, limits.memory.max(1 << 20), 0);
    set_limit(libc::RLIMIT_CPU, limits.cpu_seconds.max(1), 5);
    set_limit(libc::RLIMIT_AS, start.saturating_add(limits.memory), 0);
    let result = std::panic::catch_unwind(std::panic::AssertUnwindSafe(work));
    let peak = status_bytes("VmPeak:")
        .unwrap_or(start)
        .saturating_sub(start);
    let (tag, body) = match result {
        Ok(Ok(bytes)) => (TAG_OK, bytes),
        Ok(Err(message)) => (TAG_ERROR, message.into_bytes()),
        Err(payload) => (TAG_PANIC, panic_text(payload.as_ref()).into_bytes()),
    };
    let mut out = reply;
    let written = out
        .write_all(&[tag])
        .and_then(|()| out.write_all(&peak.to_le_bytes()))
        .and_then(|()| out.write_all(&body));
    // SAFETY: `_exit` ends the child without running the parent's exit handlers or
    // destructors.
    unsafe { libc::_exit(if written.is_ok() { 0 } else { 3 }) }
}

fn panic_text(payload: &(dyn std::any::Any + Send)) -> String {
    payload
        .downcast_ref::<&str>()
        .map(|s| s.to_string())
        .or_else(|| payload.downcast_ref::<String>().cloned())
        .unwrap_or_else(|| "a panic without a message".into())
}

/// How the child ended.
#[derive(Clone, Copy, Debug)]
enum Ended {
    Exited(i32),
    Signalled(i32),
    TimedOut,
}

/// Waits for `pid`, killing it past `wall`; `ended` is the read end of a pipe whose
/// write end only the child holds (another thread's child may hold it a while too: the
/// wait then falls back to looking every 20 ms).
fn wait(pid: libc::pid_t, ended: &File, wall: Duration) -> Result<Ended, String> {
    let started = Instant::now();
    let mut timed_out = false;
    loop {
        let mut status = 0;
        // SAFETY: `status` is a valid out-pointer; `pid` is our own child.
        let got = unsafe { libc::waitpid(pid, &mut status, libc::WNOHANG) };
        if got == pid {
            return Ok(if timed_out {
                Ended::TimedOut
            } else if libc::WIFEXITED(status) {
                Ended::Exited(libc::WEXITSTATUS(status))
            } else {
                Ended::Signalled(libc::WTERMSIG(status))
            });
        }
        if got < 0 {
            let e = std::io::Error::last_os_error();
            if e.kind() == std::io::ErrorKind::Interrupted {
                continue;
            }
            return Err(format!("lost the decoding process: {e}"));
        }
        if !timed_out && started.elapsed() > wall {
            // SAFETY: `pid` is our own child, not yet reaped.
            unsafe { libc::kill(pid, libc::SIGKILL) };
            timed_out = true;
        }
        let mut poll = libc::pollfd {
            fd: ended.as_raw_fd(),
            events: libc::POLLIN,
            revents: 0,
        };
        // SAFETY: one valid pollfd. Its answer is not needed: the loop looks again.
        let woken = unsafe { libc::poll(&mut poll, 1, 20) };
        if woken > 0 && poll.revents & libc::POLLHUP != 0 {
            // The write end is closed: the child is ending; its exit follows shortly.
            std::thread::sleep(Duration::from_micros(20));
        }
    }
}

/// The first [`LOG_HEAD`] bytes the child printed, as text.
fn read_head(mut log: &File) -> String {
    let mut bytes = Vec::new();
    if log.seek(SeekFrom::Start(0)).is_ok() {
        let _ = log.take(LOG_HEAD).read_to_end(&mut bytes);
    }
    String::from_utf8_lossy(&bytes).into_owned()
}

/// The child's reply, or one line saying how it failed.
fn outcome(ended: Ended, mut reply: &File, log: &str, limits: Limits) -> Result<Reply, String> {
    let memory = size_text(limits.memory);
    match ended {
        Ended::Exited(0) => {}
        Ended::TimedOut => {
            return Err(format!(
                "decoding it took over {} s (the reader's limit for a file of this size)",
                limits.wall.as_secs()
            ))
        }
        Ended::Signalled(libc::SIGXCPU) => {
            return Err(format!(
                "decoding it took over {} s of CPU time (the reader's limit for a file of \
                 this size)",
                limits.cpu_seconds
            ))
        }
        Ended::Signalled(libc::SIGXFSZ) => {
            return Err(format!(
                "what it decodes to passes the reader's {memory} limit"
            ))
        }
        Ended::Exited(code) | Ended::Signalled(code) => return Err(diagnose(log, code, &memory)),
    }
    let len = reply.seek(SeekFrom::End(0)).map_err(|e| e.to_string())?;
    reply.seek(SeekFrom::Start(0)).map_err(|e| e.to_string())?;
    let mut head = [0u8; 9];
    reply
        .read_exact(&mut head)
        .map_err(|_| "the decoding process ended without a reply".to_string())?;
    let mut body = Vec::with_capacity(len.saturating_sub(9).min(limits.memory) as usize);
    reply
        .take(limits.memory)
        .read_to_end(&mut body)
        .map_err(|e| e.to_string())?;
    let peak_memory = u64::from_le_bytes(head[1..9].try_into().unwrap_or([0; 8]));
    let text = || String::from_utf8_lossy(&body).into_owned();
    match head[0] {
        TAG_OK => Ok(Reply {
            bytes: body,
            peak_memory,
        }),
        TAG_ERROR => Err(text()),
        TAG_PANIC => Err(format!(
            "the decoder failed on it (a malformed file): {}",
            one_line(&text())
        )),
        other => Err(format!("the decoding process replied with tag {other}")),
    }
}

/// What the child's words (`log`, its first) and its end (`code`) say happened.
fn diagnose(log: &str, code: i32, memory: &str) -> String {
    if let Some(at) = log.rfind("memory allocation of ") {
        let asked = log[at + "memory allocation of ".len()..]
            .split_whitespace()
            .next()
            .and_then(|n| n.parse::<u64>().ok());
        if let Some(asked) = asked {
            return format!(
                "decoding it asked for {} at once, past the reader's {memory} limit for a \
                 file of this size (a count in the file larger than its bytes can hold)",
                size_text(asked)
            );
        }
    }
    if log.contains("overflowed its stack") {
        return "decoding it overflowed the stack (values nested too deep)".into();
    }
    if code == libc::SIGABRT || code == libc::SIGSEGV || code == libc::SIGBUS {
        return format!(
            "the decoder died on it (signal {code}): most likely it needed more than the \
             reader's {memory} limit"
        );
    }
    let first = log.lines().find(|l| !l.trim().is_empty()).unwrap_or("");
    format!("the decoding process ended with status {code}: {first}")
}

/// `text`'s first line.
fn one_line(text: &str) -> &str {
    text.lines().next().unwrap_or("")
}

use std::time::{Duration, Instant};

use super::*;

fn limits(memory: u64) -> Limits {
    Limits {
        memory,
        cpu_seconds: 20,
        wall: Duration::from_secs(60),
    }
}

#[test]
fn the_works_reply_and_error_come_back_as_they_were() {
    let reply = run(limits(64 << 20), || Ok(b"hello".to_vec())).unwrap();
    assert_eq!(reply.bytes, b"hello");
    let error = run(limits(64 << 20), || Err("no curves".into())).unwrap_err();
    assert_eq!(error, "no curves");
    // A reply larger than a pipe's buffer, and empty ones, arrive whole.
    let big: Vec<u8> = (0..3_000_000u32).map(|i| (i % 251) as u8).collect();
    let expected = big.clone();
    assert_eq!(
        run(limits(64 << 20), move || Ok(big)).unwrap().bytes,
        expected
    );
    assert!(run(limits(64 << 20), || Ok(Vec::new()))
        .unwrap()
        .bytes
        .is_empty());
}

#[test]
fn a_panic_is_one_line_with_its_message() {
    let error = run(limits(64 << 20), || {
        let v: Vec<u8> = std::hint::black_box(Vec::new());
        Ok(vec![v[7]])
    })
    .unwrap_err();
    assert!(error.starts_with("the decoder failed on it"), "{error}");
    assert!(error.contains("index out of bounds"), "{error}");
    assert_eq!(error.lines().count(), 1, "{error}");
}

#[test]
fn an_allocation_past_the_limit_is_an_error_naming_its_size() {
    // 2⁴⁰ bytes: the abort a count from a hostile file causes in-process.
    let error = run(limits(64 << 20), || {
        let n = std::hint::black_box(1usize << 40);
        let v = vec![1u8; n];
        Ok(vec![v[n - 1]])
    })
    .unwrap_err();
    assert!(error.contains("asked for 1024 GiB"), "{error}");
    assert!(error.contains("64 MiB limit"), "{error}");
    // Within the limit the same work succeeds, and its peak is what it took.
    let reply = run(limits(256 << 20), || {
        let v = vec![1u8; std::hint::black_box(96 << 20)];
        Ok(vec![v[v.len() - 1]])
    })
    .unwrap();
    assert_eq!(reply.bytes, [1]);
    assert!(
        (96 << 20..256 << 20).contains(&reply.peak_memory),
        "peak {}",
        reply.peak_memory
    );
}

fn deeper(n: u64) -> u64 {
    let pad = std::hint::black_box([n; 64]);
    if n == 0 {
        return 0;
    }
    deeper(std::hint::black_box(n + 1)) + pad[3]
}

#[test]
fn a_stack_overflow_is_an_error() {
    let error = run(limits(256 << 20), || Ok(deeper(1).to_le_bytes().to_vec())).unwrap_err();
    assert!(error.contains("overflowed the stack"), "{error}");
}

#[test]
fn work_that_never_ends_is_stopped_by_its_limits() {
    let busy = Limits {
        memory: 64 << 20,
        cpu_seconds: 1,
        wall: Duration::from_secs(30),
    };
    let error = run(busy, || loop {
        std::hint::black_box(0u64);
    })
    .unwrap_err();
    assert!(error.contains("over 1 s of CPU time"), "{error}");
    let asleep = Limits {
        wall: Duration::from_millis(300),
        ..busy
    };
    let started = Instant::now();
    let error = run(asleep, || {
        std::thread::sleep(Duration::from_secs(600));
        Ok(Vec::new())
    })
    .unwrap_err();
    assert!(error.contains("took over 0 s"), "{error}");
    assert!(started.elapsed() < Duration::from_secs(30));
}

#[test]
fn what_the_child_prints_is_read_for_the_diagnosis() {
    // The child's standard error is captured (it would corrupt an image on standard
    // output, or clutter the terminal): its last words name the cause.
    let error = run(limits(64 << 20), || {
        let words = b"memory allocation of 4096 bytes failed\n";
        // SAFETY: a valid buffer written to the child's own standard error.
        unsafe { libc::write(2, words.as_ptr().cast(), words.len()) };
        std::process::abort()
    })
    .unwrap_err();
    assert!(error.contains("asked for 4096 bytes"), "{error}");
}

//! The files module's tests: reads bounded and refused, outputs replaced or written
//! through, folders checked and regions rewritten.

use super::*;

fn temp_dir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("fur-files-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// A new output gets the permissions any new file gets in its folder (the umask's),
/// not a temporary file's private 0600; a replaced one keeps its own.
#[test]
fn new_outputs_get_the_usual_permissions_and_replaced_ones_keep_theirs() {
    use std::os::unix::fs::PermissionsExt as _;
    let dir = temp_dir("modes");
    let usual = dir.join("usual.txt");
    std::fs::write(&usual, b"x").unwrap();
    let out = dir.join("out.txt");
    write_output(&out, b"new", "test output").unwrap();
    let mode = |p: &Path| std::fs::metadata(p).unwrap().permissions().mode() & 0o777;
    assert_eq!(mode(&out), mode(&usual));
    std::fs::set_permissions(&out, std::fs::Permissions::from_mode(0o640)).unwrap();
    write_output(&out, b"again", "test output").unwrap();
    assert_eq!(mode(&out), 0o640);
}

#[test]
fn regular_files_are_replaced_and_links_kept() {
    let dir = temp_dir("links");
    let target = dir.join("target.txt");
    std::fs::write(&target, b"old").unwrap();
    let link = dir.join("link.txt");
    std::os::unix::fs::symlink(&target, &link).unwrap();
    write_output(&link, b"new", "test output").unwrap();
    assert!(std::fs::symlink_metadata(&link)
        .unwrap()
        .file_type()
        .is_symlink());
    assert_eq!(std::fs::read(&target).unwrap(), b"new");
    let leftovers: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .filter_map(|e| e.ok())
        .filter(|e| e.file_name().to_string_lossy().contains("partial"))
        .collect();
    assert!(leftovers.is_empty(), "temporary files left: {leftovers:?}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// The check makes no folder that outlives it (a run failing after the check leaves
/// none behind); writing a file makes the folders it needs.
#[test]
fn the_folder_check_leaves_no_folder_and_a_write_makes_it() {
    let dir = temp_dir("made");
    let nested = dir.join("a").join("b");
    check_output_dir(&nested).unwrap();
    assert!(!dir.join("a").exists(), "the check left {}", dir.display());
    let existing = dir.join("kept");
    std::fs::create_dir(&existing).unwrap();
    check_output_dir(&existing).unwrap();
    assert!(
        existing.is_dir(),
        "the check took away a folder it did not make"
    );
    write_output(&nested.join("x.txt"), b"x", "test output").unwrap();
    assert_eq!(std::fs::read(nested.join("x.txt")).unwrap(), b"x");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn reads_refuse_folders_and_oversized_files() {
    let dir = temp_dir("reads");
    let err = read_bounded(&dir, 10, "model").unwrap_err();
    assert!(err.contains("a folder"), "{err}");
    let file = dir.join("big.obj");
    std::fs::write(&file, vec![b'x'; 11]).unwrap();
    let err = read_bounded(&file, 10, "model").unwrap_err();
    assert!(err.contains("over the 10 bytes limit for a model"), "{err}");
    assert_eq!(read_bounded(&file, 11, "model").unwrap().len(), 11);
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn sizes_read_as_people_write_them() {
    assert_eq!(size_text(2 << 30), "2 GiB");
    assert_eq!(size_text(3 << 19), "1.5 MiB");
    assert_eq!(size_text(12), "12 bytes");
}

/// A file that reports a size its reads outgrow (as a file growing while read does) is
/// cut one byte past the limit and refused: `/proc/self/status` reports 0 bytes and
/// holds over a kilobyte. Within the limit it is read whole.
#[test]
fn a_file_that_outgrows_its_reported_size_is_refused_at_the_limit() {
    let status = Path::new("/proc/self/status");
    assert_eq!(std::fs::metadata(status).unwrap().len(), 0);
    let err = read_bounded(status, 100, "model").unwrap_err();
    assert!(
        err.contains("grew past the 100 bytes limit for a model while being read"),
        "{err}"
    );
    let whole = read_bounded(status, 1 << 20, "model").unwrap();
    assert!(whole.len() > 100 && whole.starts_with(b"Name:"));
}

#[test]
fn missing_files_and_other_kinds_are_named() {
    let dir = temp_dir("kinds");
    let missing = dir.join("missing.obj");
    assert_eq!(
        read_bounded(&missing, 10, "model").unwrap_err(),
        "no such file"
    );
    assert_eq!(read_bounded_check(&missing).unwrap_err(), "no such file");
    assert_eq!(
        read_bounded_check(&dir).unwrap_err(),
        "it is a folder, not a regular file"
    );
    let file = dir.join("a.obj");
    std::fs::write(&file, b"v 0 0 0\n").unwrap();
    read_bounded_check(&file).unwrap();
    // Under a regular file is not "no such file": the system's own reason.
    let under = file.join("x.obj");
    assert!(read_bounded_check(&under)
        .unwrap_err()
        .contains("Not a directory"));
    assert!(output_kind(&under).unwrap_err().contains("Not a directory"));
    assert_eq!(read_text_bounded(&file, 8, "model").unwrap(), "v 0 0 0\n");
    std::fs::write(&file, [0xff, 0xfe]).unwrap();
    let err = read_text_bounded(&file, 8, "model").unwrap_err();
    assert!(err.starts_with("it is not UTF-8 text"), "{err}");
    let kind = |p: &Path| kind_name(&std::fs::symlink_metadata(p).unwrap());
    assert_eq!(kind(&dir), "a folder");
    assert_eq!(kind(&file), "a regular file");
    assert_eq!(kind(Path::new("/dev/null")), "a character device");
    let fifo = dir.join("pipe");
    let made = std::process::Command::new("mkfifo").arg(&fifo).status();
    assert!(made.is_ok_and(|s| s.success()), "mkfifo failed");
    assert_eq!(kind(&fifo), "a FIFO (named pipe)");
    let link = dir.join("link");
    std::os::unix::fs::symlink(&file, &link).unwrap();
    assert_eq!(kind(&link), "a symbolic link");
    let err = read_bounded(&fifo, 10, "texture").unwrap_err();
    assert_eq!(
        err,
        "it is a FIFO (named pipe), not a regular file; a texture is read only from a regular file"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// Standard output as `-`, a new or regular file replaced (a link's target), a folder
/// refused, and anything else written through: a device, a FIFO, a link to nothing yet.
#[test]
fn each_output_is_written_the_way_its_kind_needs() {
    let dir = temp_dir("outputs");
    assert_eq!(output_kind(Path::new("-")).unwrap(), OutputKind::Stdout);
    let new = dir.join("new.png");
    assert_eq!(
        output_kind(&new).unwrap(),
        OutputKind::Replace {
            final_path: new.clone()
        }
    );
    std::fs::write(&new, b"x").unwrap();
    let link = dir.join("link.png");
    std::os::unix::fs::symlink(&new, &link).unwrap();
    assert_eq!(
        output_kind(&link).unwrap(),
        OutputKind::Replace {
            final_path: std::fs::canonicalize(&new).unwrap()
        }
    );
    let dangling = dir.join("dangling.png");
    std::os::unix::fs::symlink(dir.join("nowhere.png"), &dangling).unwrap();
    assert_eq!(output_kind(&dangling).unwrap(), OutputKind::Through);
    assert_eq!(
        output_kind(Path::new("/dev/null")).unwrap(),
        OutputKind::Through
    );
    assert_eq!(
        output_kind(&dir).unwrap_err(),
        "it is a folder; give a file name"
    );
    write_output(Path::new("/dev/null"), b"x", "test output").unwrap();
    check_output_file(Path::new("/dev/null")).unwrap();
    check_output_file(&dir.join("sub").join("out.png")).unwrap();
    assert!(!dir.join("sub").exists());
    // A new file in a folder where no file can be made (procfs, even for root).
    assert!(check_output_file(Path::new("/proc/fur-check.png")).is_err());
    let err = check_output_file(&dir).unwrap_err().to_string();
    assert!(err.contains("it is a folder"), "{err}");
    let err = check_output_file(&new.join("under.png"))
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("new.png"),
        "a file under a regular file: {err}"
    );
    let err = check_output_dir(&new).unwrap_err().to_string();
    assert!(err.contains("it is a regular file, not a folder"), "{err}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// A document's region is rewritten between its lines and the rest kept; a document
/// without the lines is refused and left as it was.
#[test]
fn a_region_is_rewritten_between_its_lines_only() {
    let dir = temp_dir("region");
    let doc = dir.join("doc.md");
    std::fs::write(&doc, "intro\n<!-- B -->\nold\n<!-- E -->\noutro\n").unwrap();
    write_region(&doc, "<!-- B -->", "<!-- E -->", "  new table\n").unwrap();
    assert_eq!(
        std::fs::read_to_string(&doc).unwrap(),
        "intro\n<!-- B -->\n\nnew table\n\n<!-- E -->\noutro\n"
    );
    assert_eq!(region("a<b>c<e>d", "<b>", "<e>"), Some(("a<b>", "<e>d")));
    assert_eq!(region("a<e>c<b>d", "<b>", "<e>"), None);
    std::fs::write(&doc, "no markers\n").unwrap();
    let err = write_region(&doc, "<!-- B -->", "<!-- E -->", "x").unwrap_err();
    assert!(
        err.to_string().contains("has no `<!-- B -->` line"),
        "{err}"
    );
    assert_eq!(std::fs::read_to_string(&doc).unwrap(), "no markers\n");
    let _ = std::fs::remove_dir_all(&dir);
}

/// A source that never ends, counting what is read from it.
struct Endless {
    read: u64,
}

impl std::io::Read for Endless {
    fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
        buf.fill(7);
        self.read += buf.len() as u64;
        Ok(buf.len())
    }
}

/// The bound is observed, not inferred: a reader that read a growing source whole and
/// refused it afterwards would never return here, and one that read past the limit
/// would count more than one byte over it.
#[test]
fn a_source_that_never_ends_is_read_one_byte_past_the_limit() {
    for limit in [0, 1, 4095, 4096, 1 << 20] {
        let mut source = Endless { read: 0 };
        let error = read_at_most(&mut source, limit, 0, "groom").unwrap_err();
        assert!(error.contains("grew past"), "{error}");
        assert_eq!(source.read, limit + 1, "limit {limit}");
    }
}

/// Bytes this thread has read through system calls (`rchar` of
/// `/proc/thread-self/io`), less those of reading that file itself.
fn bytes_read(then: impl FnOnce()) -> u64 {
    let rchar = || -> (u64, u64) {
        let text = std::fs::read_to_string("/proc/thread-self/io").unwrap();
        let n = text
            .lines()
            .find_map(|l| l.strip_prefix("rchar: "))
            .unwrap()
            .parse()
            .unwrap();
        (n, text.len() as u64)
    };
    let (before, own) = rchar();
    then();
    let (after, _) = rchar();
    after - before - own
}

/// Every input fur reads — model, scene file, texture, groom — given a source that
/// never ends (a FIFO a writer keeps feeding, `/dev/zero`) reads at most its limit and
/// one byte from it: here none, since such a source is refused from its kind before
/// it is opened. The writer counts what it got rid of: nothing, as nothing opened the
/// FIFO.
#[test]
fn endless_inputs_are_read_no_further_than_their_limit() {
    use std::os::unix::fs::OpenOptionsExt as _;
    use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
    let dir = temp_dir("endless");
    let fifo = dir.join("endless");
    let name = std::ffi::CString::new(fifo.to_str().unwrap()).unwrap();
    // SAFETY: a valid C string and mode.
    assert_eq!(unsafe { libc::mkfifo(name.as_ptr(), 0o600) }, 0);
    let stop = std::sync::Arc::new(AtomicBool::new(false));
    let written = std::sync::Arc::new(AtomicU64::new(0));
    let feeder = {
        let (stop, written, fifo) = (stop.clone(), written.clone(), fifo.clone());
        std::thread::spawn(move || {
            while !stop.load(Ordering::Relaxed) {
                let open = std::fs::OpenOptions::new()
                    .write(true)
                    .custom_flags(libc::O_NONBLOCK)
                    .open(&fifo);
                match open {
                    Ok(mut f) => {
                        let block = [0u8; 4096];
                        while !stop.load(Ordering::Relaxed) {
                            match std::io::Write::write(&mut f, &block) {
                                Ok(n) => written.fetch_add(n as u64, Ordering::Relaxed),
                                Err(_) => break,
                            };
                        }
                    }
                    Err(_) => std::thread::sleep(std::time::Duration::from_millis(1)),
                }
            }
        })
    };
    type Refuses = fn(&Path) -> bool;
    let inputs: [(&str, u64, Refuses); 4] = [
        ("model", MAX_MODEL_BYTES, |p| {
            crate::scene::Mesh::load_obj(&p.with_extension("obj")).is_err()
                && crate::scene::Mesh::load_obj(p).is_err()
        }),
        ("scene file", MAX_SCENE_BYTES, |p| {
            crate::scene_file::SceneFile::load(p).is_err()
        }),
        ("texture", MAX_TEXTURE_BYTES, |p| {
            crate::scene::Texture::load(p).is_err()
        }),
        ("groom", crate::groom_file::MAX_GROOM_BYTES, |p| {
            crate::groom_file::read_groom(&p.with_extension("hair")).is_err()
                && crate::groom_file::read_groom(&p.with_extension("usdc")).is_err()
        }),
    ];
    // Each source under the names each reader takes: the FIFO, and links to it and
    // to `/dev/zero` with a model's and a groom's extensions.
    let zero = dir.join("zero");
    for (base, target) in [(&fifo, fifo.clone()), (&zero, PathBuf::from("/dev/zero"))] {
        for ext in ["", "obj", "hair", "usdc"] {
            let link = base.with_extension(ext);
            if link != fifo {
                std::os::unix::fs::symlink(&target, &link).unwrap();
            }
        }
    }
    for (what, limit, refused) in inputs {
        for source in [&fifo, &zero] {
            let mut was_refused = false;
            let read = bytes_read(|| was_refused = refused(source));
            assert!(was_refused, "{what} from {}", source.display());
            assert!(read <= limit + 1, "{what}: {read} bytes read");
            assert_eq!(
                read,
                0,
                "{what} from {}: {read} bytes read",
                source.display()
            );
        }
    }
    stop.store(true, Ordering::Relaxed);
    feeder.join().unwrap();
    assert_eq!(
        written.load(Ordering::Relaxed),
        0,
        "something opened the FIFO"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

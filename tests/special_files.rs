//! Outputs and inputs that are not plain files: a symbolic link, a FIFO, a character
//! device, standard output (`-`), a file too large to read. `fur` writes through what is
//! not its own and never replaces it, reads only regular files of a stated size, and
//! never hangs (every run is bounded by this harness). Also the last rough edges of the
//! command line: negative numbers as values, a dangling texture, a file without faces.

use std::io::Read as _;
use std::os::unix::fs::FileTypeExt as _;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// The longest any case may run before it counts as a hang.
const LIMIT: Duration = Duration::from_secs(90);

const PNG_MAGIC: &[u8] = b"\x89PNG\r\n\x1a\n";

struct Outcome {
    code: Option<i32>,
    stdout: Vec<u8>,
    stderr: String,
}

fn run(args: &[&str]) -> Outcome {
    let mut child = Command::new(env!("CARGO_BIN_EXE_fur"))
        .args(args)
        .env_remove("DISPLAY")
        .env_remove("WAYLAND_DISPLAY")
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("fur runs");
    // Drain the pipes while waiting, so a large stdout cannot block the child.
    let mut stdout = child.stdout.take().unwrap();
    let mut stderr = child.stderr.take().unwrap();
    let out = std::thread::spawn(move || {
        let mut b = Vec::new();
        let _ = stdout.read_to_end(&mut b);
        b
    });
    let err = std::thread::spawn(move || {
        let mut s = String::new();
        let _ = stderr.read_to_string(&mut s);
        s
    });
    let start = Instant::now();
    let status = loop {
        if let Some(status) = child.try_wait().expect("wait") {
            break status;
        }
        if start.elapsed() > LIMIT {
            let _ = child.kill();
            panic!(
                "`fur {}` hung: still running after {LIMIT:?}",
                args.join(" ")
            );
        }
        std::thread::sleep(Duration::from_millis(20));
    };
    Outcome {
        code: status.code(),
        stdout: out.join().unwrap(),
        stderr: err.join().unwrap(),
    }
}

fn scratch(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join("special_files")
        .join(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

const SMALL: [&str; 8] = [
    "--model",
    "sphere",
    "--width",
    "48",
    "--height",
    "32",
    "--density-scale",
    "0.05",
];

fn render_to(out: &str, extra: &[&str]) -> Outcome {
    let mut args = vec!["render", "--out", out];
    args.extend_from_slice(&SMALL);
    args.extend_from_slice(extra);
    run(&args)
}

fn assert_fails(o: &Outcome, needles: &[&str], case: &str) {
    assert!(
        !o.stderr.contains("panicked"),
        "{case}: panicked:\n{}",
        o.stderr
    );
    assert!(
        matches!(o.code, Some(c) if c != 0 && c != 101),
        "{case}: exit status {:?}, expected a clean failure; stderr:\n{}",
        o.code,
        o.stderr
    );
    for needle in needles {
        assert!(
            o.stderr.contains(needle),
            "{case}: the message does not name `{needle}`:\n{}",
            o.stderr
        );
    }
}

fn assert_succeeds(o: &Outcome, case: &str) {
    assert_eq!(o.code, Some(0), "{case}: failed; stderr:\n{}", o.stderr);
}

fn mkfifo(path: &Path) {
    let status = Command::new("mkfifo")
        .arg(path)
        .status()
        .expect("mkfifo runs");
    assert!(status.success(), "mkfifo {}", path.display());
}

fn is_root() -> bool {
    Command::new("id")
        .arg("-u")
        .output()
        .is_ok_and(|o| String::from_utf8_lossy(&o.stdout).trim() == "0")
}

#[test]
fn a_symlinked_output_keeps_the_link_and_fills_its_target() {
    let dir = scratch("symlink");
    let target = dir.join("real.png");
    std::fs::write(&target, b"old").unwrap();
    let link = dir.join("link.png");
    std::os::unix::fs::symlink(&target, &link).unwrap();
    let o = render_to(link.to_str().unwrap(), &[]);
    assert_succeeds(&o, "--out LINK");
    assert!(
        std::fs::symlink_metadata(&link)
            .unwrap()
            .file_type()
            .is_symlink(),
        "the link was replaced by a file"
    );
    assert!(std::fs::read(&target).unwrap().starts_with(PNG_MAGIC));
    // Frames of a sequence that are links keep them too.
    let frames = dir.join("frames");
    std::fs::create_dir_all(&frames).unwrap();
    let frame_target = dir.join("first_frame.png");
    std::os::unix::fs::symlink(&frame_target, frames.join("frame_0000.png")).unwrap();
    let o = run(&[
        "render",
        "--frames",
        "2",
        "--out-dir",
        frames.to_str().unwrap(),
        "--model",
        "sphere",
        "--width",
        "32",
        "--height",
        "24",
        "--density-scale",
        "0.05",
    ]);
    assert_succeeds(&o, "--out-dir with a linked frame");
    assert!(std::fs::symlink_metadata(frames.join("frame_0000.png"))
        .unwrap()
        .file_type()
        .is_symlink());
    assert!(std::fs::read(&frame_target).unwrap().starts_with(PNG_MAGIC));
    assert!(std::fs::read(frames.join("frame_0001.png"))
        .unwrap()
        .starts_with(PNG_MAGIC));
    // No temporary file is left behind anywhere.
    for d in [&dir, &frames] {
        for entry in std::fs::read_dir(d).unwrap() {
            let name = entry.unwrap().file_name().to_string_lossy().into_owned();
            // The temporary files `tempfile` makes beside an output: `.tmpXXXXXX`.
            assert!(!name.starts_with(".tmp"), "left behind: {name}");
        }
    }
}

#[test]
fn a_fifo_output_is_written_through_and_stays_a_fifo() {
    let dir = scratch("fifo_out");
    let fifo = dir.join("image.fifo");
    mkfifo(&fifo);
    let reader = {
        let fifo = fifo.clone();
        std::thread::spawn(move || {
            let mut bytes = Vec::new();
            std::fs::File::open(&fifo)
                .unwrap()
                .read_to_end(&mut bytes)
                .unwrap();
            bytes
        })
    };
    let o = render_to(fifo.to_str().unwrap(), &[]);
    assert_succeeds(&o, "--out FIFO");
    let bytes = reader.join().unwrap();
    assert!(
        bytes.starts_with(PNG_MAGIC),
        "the reader got {} bytes",
        bytes.len()
    );
    assert!(std::fs::symlink_metadata(&fifo)
        .unwrap()
        .file_type()
        .is_fifo());
}

#[test]
fn standard_output_takes_the_image_and_the_summary_goes_to_stderr() {
    let o = render_to("-", &[]);
    assert_succeeds(&o, "--out -");
    assert!(o.stdout.starts_with(PNG_MAGIC), "stdout is not a PNG");
    let decoded = image::load_from_memory(&o.stdout).expect("a whole PNG on stdout");
    assert_eq!((decoded.width(), decoded.height()), (48, 32));
    assert!(o.stderr.contains("wrote -"), "{}", o.stderr);
}

#[test]
fn device_nodes_are_written_through_and_never_replaced() {
    if !is_root() {
        eprintln!("skipped: making device nodes needs root");
        return;
    }
    let dir = scratch("devices");
    let full = dir.join("full");
    let null = dir.join("null");
    for (path, minor) in [(&full, "7"), (&null, "3")] {
        let status = Command::new("mknod")
            .args([path.to_str().unwrap(), "c", "1", minor])
            .status()
            .unwrap();
        assert!(status.success(), "mknod {}", path.display());
    }
    let o = render_to(full.to_str().unwrap(), &[]);
    assert_fails(&o, &["No space left on device", "full"], "--out FULL");
    let o = render_to(null.to_str().unwrap(), &[]);
    assert_succeeds(&o, "--out NULL");
    for path in [&full, &null] {
        let kind = std::fs::symlink_metadata(path).unwrap().file_type();
        assert!(kind.is_char_device(), "{} was replaced", path.display());
    }
    // An export and a scene file to the full device fail the same way.
    let o = run(&["export-model", full.to_str().unwrap(), "--model", "sphere"]);
    assert_fails(&o, &["No space left on device"], "export-model FULL");
    assert!(std::fs::symlink_metadata(&full)
        .unwrap()
        .file_type()
        .is_char_device());
}

#[test]
fn inputs_that_are_not_regular_files_are_refused_without_blocking() {
    let dir = scratch("fifo_in");
    let fifo = dir.join("model.obj");
    mkfifo(&fifo);
    let fifo = fifo.to_str().unwrap();
    let cases: [(Vec<&str>, &str); 4] = [
        (vec!["--model", fifo], "FIFO"),
        (vec!["--model", "/dev/zero"], "character device"),
        (vec!["--model", "sphere", "--texture", fifo], "FIFO"),
        (vec![fifo], "FIFO"),
    ];
    let out = dir.join("out.png");
    for (extra, needle) in cases {
        let mut args = vec!["render", "--out", out.to_str().unwrap(), "--width", "32"];
        args.extend_from_slice(&extra);
        let o = run(&args);
        assert_fails(&o, &[needle, "regular file"], &extra.join(" "));
    }
}

#[test]
fn inputs_over_the_size_limit_are_refused_before_reading() {
    let dir = scratch("huge");
    // Sparse files: large on paper, nothing on disk.
    let model = dir.join("huge.obj");
    std::fs::File::create(&model)
        .unwrap()
        .set_len(3 << 30)
        .unwrap();
    let scene = dir.join("huge.toml");
    std::fs::File::create(&scene)
        .unwrap()
        .set_len(2 << 20)
        .unwrap();
    let out = dir.join("out.png");
    let out = out.to_str().unwrap();
    let start = Instant::now();
    let o = run(&["render", "--out", out, "--model", model.to_str().unwrap()]);
    assert_fails(&o, &["3 GiB", "2 GiB limit", "huge.obj"], "a 3 GiB model");
    let o = run(&["render", "--out", out, scene.to_str().unwrap()]);
    assert_fails(
        &o,
        &["2 MiB", "1 MiB limit", "huge.toml"],
        "a 2 MiB scene file",
    );
    assert!(
        start.elapsed() < Duration::from_secs(30),
        "refusing took {:?}: the files were read",
        start.elapsed()
    );
}

#[test]
fn negative_numbers_are_values_and_their_range_is_named() {
    let dir = scratch("negative");
    let out = dir.join("out.png");
    let out = out.to_str().unwrap();
    let o = run(&["render", "--out", out, "--hair-length", "-0.2"]);
    assert_fails(&o, &["hair length", "-0.2"], "--hair-length -0.2");
    assert!(!o.stderr.contains("unexpected argument"), "{}", o.stderr);
    let o = run(&["view", "--frames", "2", "--script", "-1:wind=on"]);
    assert_fails(&o, &["-1:wind=on"], "--script -1:wind=on");
    assert!(!o.stderr.contains("unexpected argument"), "{}", o.stderr);
    // A negative yaw is a fine value, not a flag.
    let o = render_to(out, &["--yaw", "-30"]);
    assert_succeeds(&o, "--yaw -30");
}

#[test]
fn a_dangling_material_texture_warns_and_renders_untextured() {
    let dir = scratch("dangling");
    let obj = dir.join("tri.obj");
    std::fs::write(
        dir.join("tri.mtl"),
        "newmtl fur\nKd 1 1 1\nmap_Kd gone.png\n",
    )
    .unwrap();
    std::fs::write(
        &obj,
        "mtllib tri.mtl\nusemtl fur\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\n\
         vt 0 0\nvt 1 0\nvt 0 1\n\
         f 1/1 3/3 2/2\nf 1/1 2/2 4/3\nf 1/1 4/3 3/3\nf 2/2 3/3 4/3\n",
    )
    .unwrap();
    let out = dir.join("out.png");
    let o = run(&[
        "render",
        "--model",
        obj.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--width",
        "32",
        "--height",
        "24",
    ]);
    assert_succeeds(&o, "a dangling map_Kd");
    assert!(
        o.stderr.contains("warning")
            && o.stderr.contains("gone.png")
            && o.stderr.contains("tri.obj"),
        "the warning names neither file:\n{}",
        o.stderr
    );
    assert!(std::fs::read(&out).unwrap().starts_with(PNG_MAGIC));
}

#[test]
fn lines_and_points_are_not_faces() {
    let dir = scratch("no_faces");
    let obj = dir.join("lines.obj");
    std::fs::write(&obj, "v 0 0 0\nv 1 0 0\nv 0 1 0\nl 1 2 3\np 1 2 3\n").unwrap();
    let out = dir.join("out.png");
    let o = run(&[
        "render",
        "--model",
        obj.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_fails(&o, &["no faces", "lines.obj"], "an OBJ of lines and points");
    // Beside faces, a three-vertex line adds no triangle.
    let mesh = fur_core::scene::Mesh::parse_obj(
        b"v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 3\nl 1 2 4\np 4\n",
    )
    .unwrap();
    assert_eq!(mesh.triangle_count(), 1);
}

/// Flags `fur render` takes, and values a careless user gives them.
const FLAGS: [&str; 14] = [
    "--hair-length",
    "--segments",
    "--density-scale",
    "--yaw",
    "--pitch",
    "--distance",
    "--samples",
    "--vertex-lod",
    "--comb",
    "--curl",
    "--frames",
    "--model",
    "--texture",
    "--primitive",
];
const VALUES: [&str; 14] = [
    "-1", "-0.2", "0", "1e40", "nan", "-inf", "-", "abc", "", "--", "3", "0.5", "sphere", "-x",
];

proptest::proptest! {
    #![proptest_config(proptest::prelude::ProptestConfig {
        cases: 24,
        failure_persistence: None,
        ..Default::default()
    })]

    /// Generated argument lists never panic or hang: each ends in a clean exit (0 for
    /// a valid scene, 1 for a refused one, 2 for a usage error).
    #[test]
    fn generated_argument_lists_fail_cleanly(
        picks in proptest::collection::vec((0..FLAGS.len(), 0..VALUES.len()), 1..4)
    ) {
        let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("special_files");
        std::fs::create_dir_all(&dir).unwrap();
        let out = dir.join("fuzz.png");
        let mut args = vec![
            "render", "--out", out.to_str().unwrap(), "--width", "24", "--height", "16",
            "--density-scale", "0.02", "--frames", "1",
        ];
        for (f, v) in &picks {
            args.push(FLAGS[*f]);
            args.push(VALUES[*v]);
        }
        let o = run(&args);
        proptest::prop_assert!(!o.stderr.contains("panicked"), "{:?}: {}", args, o.stderr);
        proptest::prop_assert!(
            matches!(o.code, Some(0..=2)),
            "{:?}: exit {:?}: {}", args, o.code, o.stderr
        );
    }
}

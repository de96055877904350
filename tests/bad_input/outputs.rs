//! Output paths: refused before any work, and no folder left by a failed run.

use super::*;

/// A run that fails after its output folder was checked leaves no folder behind.
#[test]
fn a_failed_run_leaves_no_output_folder() {
    let folder = scratch().join("never_made").join("frames");
    let _ = std::fs::remove_dir_all(scratch().join("never_made"));
    let out = folder.to_str().unwrap();
    let o = run(&[
        "render",
        "--frames",
        "3",
        "--amplitude",
        "nan",
        "--out-dir",
        out,
    ]);
    fails(&o, "amplitude", "render --amplitude nan --out-dir");
    assert!(
        !scratch().join("never_made").exists(),
        "the failed run left {}",
        folder.display()
    );
}

#[test]
fn bad_output_paths_fail_before_any_work() {
    let dir = scratch();
    let a_file = file("not_a_folder.txt", b"x");
    let under_file = format!("{a_file}/frame.png");
    let cases: Vec<(Vec<String>, &str)> = vec![
        (
            vec![
                "render".into(),
                "--out".into(),
                dir.to_str().unwrap().into(),
            ],
            "folder",
        ),
        (
            vec!["render".into(), "--out".into(), under_file.clone()],
            "folder",
        ),
        (
            vec![
                "render".into(),
                "--frames".into(),
                "3".into(),
                "--out-dir".into(),
                a_file.clone(),
            ],
            "a regular file, not a folder",
        ),
        (
            vec!["export-model".into(), dir.to_str().unwrap().into()],
            "folder",
        ),
        (vec!["export-model".into(), under_file], "folder"),
        (
            vec!["bench".into(), "--out-dir".into(), a_file],
            "a regular file, not a folder",
        ),
    ];
    for (args, needle) in cases {
        let start = Instant::now();
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        fails(&run(&args), needle, &args.join(" "));
        assert!(
            start.elapsed() < Duration::from_secs(10),
            "`{}` worked before checking its output",
            args.join(" ")
        );
    }
    // Into a folder that does not exist yet: made, then written.
    let fresh = dir.join("new_folder/deeper/blob.obj");
    let _ = std::fs::remove_dir_all(dir.join("new_folder"));
    succeeds(
        &run(&["export-model", fresh.to_str().unwrap()]),
        None,
        "export into a new folder",
    );
    assert!(fresh.exists());
}

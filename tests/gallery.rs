//! `tools/gallery.sh`, the command that regenerates docs/pipeline.md's pictures, writes
//! every picture the page shows, and writes the same bytes when run twice on one
//! machine (every view is seeded; none depends on time or threads).

use std::path::Path;
use std::process::Command;

fn gallery(dir: &Path) {
    let _ = std::fs::remove_dir_all(dir);
    let out = Command::new("bash")
        .arg(Path::new(env!("CARGO_MANIFEST_DIR")).join("tools/gallery.sh"))
        .arg(env!("CARGO_BIN_EXE_fur"))
        .arg(dir)
        .output()
        .expect("bash runs the gallery");
    assert!(
        out.status.success(),
        "tools/gallery.sh failed:\n{}{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
}

#[test]
fn the_gallery_writes_every_picture_of_the_page_byte_for_byte_twice() {
    let root = Path::new(env!("CARGO_TARGET_TMPDIR")).join("gallery");
    let (a, b) = (root.join("a"), root.join("b"));
    gallery(&a);
    gallery(&b);
    let page =
        std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("docs/pipeline.md"))
            .unwrap();
    let shown: Vec<&str> = page
        .split("](pipeline/")
        .skip(1)
        .filter_map(|rest| rest.split(')').next())
        .collect();
    assert!(shown.len() >= 14, "the page shows {} pictures", shown.len());
    let mut written: Vec<String> = std::fs::read_dir(&a)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    written.sort();
    for name in &shown {
        assert!(
            written.iter().any(|w| w == name),
            "the gallery does not write {name}"
        );
    }
    for name in &written {
        assert!(
            shown.contains(&name.as_str()),
            "{name} is written but not shown"
        );
        let (x, y) = (
            std::fs::read(a.join(name)).unwrap(),
            std::fs::read(b.join(name)).unwrap(),
        );
        assert!(x == y, "{name} differs between two runs");
    }
}

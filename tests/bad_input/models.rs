//! Malformed and awkward models and textures.

use super::*;

#[test]
fn malformed_models_fail_cleanly() {
    let garbage: Vec<u8> = (0..4096u32)
        .map(|i| (i.wrapping_mul(2654435761) >> 13) as u8)
        .collect();
    let cases: Vec<(&str, String, &str)> = vec![
        (
            "missing file",
            scratch().join("nope.obj").to_str().unwrap().into(),
            "no such file",
        ),
        ("a folder", scratch().to_str().unwrap().into(), "folder"),
        ("empty file", file("empty.obj", b""), "no faces"),
        (
            "vertices only",
            file("points.obj", b"v 0 0 0\nv 1 0 0\nv 0 1 0\n"),
            "no faces",
        ),
        (
            "lines and points only",
            file("lines.obj", b"v 0 0 0\nv 1 0 0\nv 0 1 0\nl 1 2\np 3\n"),
            "no faces",
        ),
        ("binary garbage", file("garbage.obj", &garbage), "no faces"),
        (
            "index out of bounds",
            file("oob.obj", b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n"),
            "vertex index out of bounds",
        ),
        (
            "negative index out of bounds",
            file("neg.obj", b"v 0 0 0\nv 1 0 0\nf -1 -2 -7\n"),
            "vertex index out of bounds",
        ),
        (
            "NaN coordinate",
            file("nan.obj", b"v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n"),
            "not finite",
        ),
        (
            "infinite coordinate",
            file("inf.obj", b"v 0 0 0\nv inf 0 0\nv 0 1 0\nf 1 2 3\n"),
            "not finite",
        ),
        (
            "degenerate faces",
            file("flat.obj", b"v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\nf 1 1 2\n"),
            "degenerate",
        ),
        (
            "missing normal index",
            file(
                "badvn.obj",
                b"v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nf 1//1 2//2 3//3\n",
            ),
            "normal index out of bounds",
        ),
        (
            "non-numeric vertex",
            file("text.obj", b"v zero one two\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"),
            "position parse error",
        ),
    ];
    for (case, path, needle) in cases {
        let outcome = render_model(&path, &[]);
        fails(&outcome, needle, case);
        // And it names the model it could not read.
        let name = Path::new(&path).file_name().unwrap().to_string_lossy();
        assert!(
            outcome.stderr.contains("cannot read model") && outcome.stderr.contains(&*name),
            "{case}: the message does not name the model `{name}`:\n{}",
            outcome.stderr
        );
    }
}

#[test]
fn awkward_but_valid_models_render() {
    let plain = octahedron(1.0, true);
    let mut bom = b"\xEF\xBB\xBF".to_vec();
    bom.extend_from_slice(plain.as_bytes());
    let mut latin1 = b"# caf\xE9 \xFF model\n".to_vec();
    latin1.extend_from_slice(plain.as_bytes());
    let crlf = plain.replace('\n', "\r\n");
    let cases: Vec<(&str, String, Option<&str>)> = vec![
        ("byte-order mark", file("bom.obj", &bom), None),
        ("non-UTF-8 comment", file("latin1.obj", &latin1), None),
        ("CRLF line ends", file("crlf.obj", crlf.as_bytes()), None),
        (
            "a millionth of a unit",
            file("tiny.obj", octahedron(1e-6, true).as_bytes()),
            Some("scaled"),
        ),
        (
            "1e30 units",
            file("huge.obj", octahedron(1e30, true).as_bytes()),
            Some("scaled"),
        ),
        (
            "inside out",
            file(
                "inverted.obj",
                format!("{}vn 0 0 1\n", octahedron(1.0, false)).as_bytes(),
            ),
            None,
        ),
    ];
    for (case, path, warning) in cases {
        succeeds(&render_model(&path, &[]), warning, case);
    }
    // Normals in the file pointing inwards grow fur inwards: flipped, with a warning.
    let mut inward = String::new();
    for line in octahedron(1.0, true).lines() {
        inward += line;
        inward += "\n";
    }
    for i in 0..6 {
        let n = [
            [-1, 0, 0],
            [1, 0, 0],
            [0, -1, 0],
            [0, 1, 0],
            [0, 0, -1],
            [0, 0, 1],
        ][i];
        inward += &format!("vn {} {} {}\n", n[0], n[1], n[2]);
    }
    let inward = inward
        .lines()
        .map(|l| {
            if let Some(rest) = l.strip_prefix("f ") {
                let ids: Vec<&str> = rest.split_whitespace().collect();
                format!(
                    "f {}//{} {}//{} {}//{}\n",
                    ids[0], ids[0], ids[1], ids[1], ids[2], ids[2]
                )
            } else {
                format!("{l}\n")
            }
        })
        .collect::<String>();
    succeeds(
        &render_model(&file("inward.obj", inward.as_bytes()), &[]),
        Some("inside out"),
        "normals pointing inwards",
    );
    // Asking for the skin's blend on a body with no skin: it renders, and says the
    // flag changes nothing.
    succeeds(
        &render_model("sphere", &["--skin-blend", "on"]),
        Some("changes nothing"),
        "the skin's blend on a rigid body",
    );
    // The skin's blend by default, where its grid would not fit (33 MiB over the
    // critter's field at 128 cells padded by its hair at full length everywhere, the
    // limit 32): it renders without it, and says so.
    succeeds(
        &render_model(
            "critter",
            &["--sdf-resolution", "128", "--thickness-limit", "0"],
        ),
        Some("collision goes without it"),
        "the default skin's blend over too fine a field",
    );
}

#[test]
fn bad_textures_fail_cleanly_and_a_missing_material_warns() {
    let dir = scratch();
    let missing = dir.join("no_such_texture.png");
    let text = file("notes.png", b"this is not an image\n");
    let cases: Vec<(Vec<String>, &str)> = vec![
        (
            vec!["--texture".into(), missing.display().to_string()],
            "no_such_texture.png",
        ),
        (vec!["--texture".into(), text.clone()], "notes.png"),
        (
            vec!["--texture".into(), dir.display().to_string()],
            "folder",
        ),
    ];
    for (extra, needle) in &cases {
        let extra: Vec<&str> = extra.iter().map(String::as_str).collect();
        fails(&render_model("sphere", &extra), needle, &extra.join(" "));
    }
    // A model without texture coordinates cannot take one.
    let plain = file("plain_octahedron.obj", octahedron(1.0, true).as_bytes());
    fails(
        &render_model(&plain, &["--texture", "tabby"]),
        "texture coordinates",
        "a texture on a model without UVs",
    );
    // A material library that is not there: a warning, and the model renders.
    let mut obj = String::from("mtllib gone.mtl\nusemtl fur\n");
    obj += &octahedron(1.0, true);
    let model = file("octahedron_without_mtl.obj", obj.as_bytes());
    succeeds(
        &render_model(&model, &[]),
        Some("gone.mtl"),
        "a missing .mtl",
    );
}

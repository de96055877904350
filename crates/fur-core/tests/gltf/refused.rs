//! Bad files refused with messages naming the file and the problem, before allocating
//! and without blocking.

use std::path::Path;
use std::time::{Duration, Instant};

use fur_core::scene::load_gltf;

use super::*;

/// The error `load_gltf` gives for `path`, checked to name the file.
fn refused(path: &Path) -> String {
    let start = Instant::now();
    let error = load_gltf(path)
        .expect_err("the file should be refused")
        .to_string();
    assert!(
        start.elapsed() < Duration::from_secs(2),
        "took {:?}: {error}",
        start.elapsed()
    );
    assert!(
        error.contains(&path.display().to_string()),
        "the file is not named: {error}"
    );
    error
}

fn assert_names(error: &str, needle: &str) {
    assert!(error.contains(needle), "`{needle}` not in: {error}");
}

#[test]
fn broken_containers_and_buffers_are_refused() {
    let dir = Scratch::new("containers");
    let good = one_bone(&[0; 12], &[1.0, 0.0, 0.0, 0.0].repeat(3), &[0.0, 1.0]);
    let total = good.len();
    let path = dir.write("cut.glb", &good[..120]);
    assert_names(
        &refused(&path),
        &format!("truncated .glb: the header says {total} bytes, the file has 120"),
    );
    let path = dir.write("tiny.glb", b"glTF\x02\0\0\0\x05\0\0\0");
    assert_names(&refused(&path), "too few");
    let path = dir.write("short.glb", b"glTF\x02\0");
    assert_names(&refused(&path), "12-byte header");
    let path = dir.write("garbage.glb", [7u8; 64]);
    assert_names(&refused(&path), "not a glTF file");
    let path = dir.write(
        "old.gltf",
        r#"{"asset":{"version":"1.0"},"meshes":{"a":{}}}"#,
    );
    assert_names(&refused(&path), "glTF 1.0");

    let mut doc = Doc::default();
    let p = doc.floats(&TRIANGLE, "VEC3");
    let rest = format!(
        r#","nodes":[{{"mesh":0}}],"meshes":[{{"primitives":[{{"attributes":{{"POSITION":{p}}}}}]}}]"#
    );
    let with_uri = |uri: &str| doc.json(&format!(r#"{{"byteLength":36,"uri":"{uri}"}}"#), &rest);
    let path = dir.write("scene.gltf", with_uri("scene.bin"));
    assert_names(
        &refused(&path),
        "buffer 0 (scene.bin) cannot be read: no such file",
    );
    let path = dir.write("web.gltf", with_uri("https://example.com/scene.bin"));
    assert_names(&refused(&path), "http(s) URLs are not fetched");
    let path = dir.write("absolute.gltf", with_uri("/etc/passwd"));
    assert_names(&refused(&path), "absolute path");
    std::fs::create_dir_all(dir.0.join("folder.bin")).unwrap();
    let path = dir.write("folder.gltf", with_uri("folder.bin"));
    assert_names(&refused(&path), "a folder");
    dir.write("small.bin", [0u8; 20]);
    let path = dir.write("small.gltf", with_uri("small.bin"));
    assert_names(
        &refused(&path),
        "buffer 0 (small.bin) has 20 bytes, but its byteLength says 36",
    );
    let path = dir.write("draco.gltf", with_uri("x.bin").replace(
        r#""asset":{"version":"2.0"}"#,
        r#""asset":{"version":"2.0"},"extensionsUsed":["KHR_draco_mesh_compression"],"extensionsRequired":["KHR_draco_mesh_compression"]"#,
    ));
    assert_names(
        &refused(&path),
        "requires the glTF extension(s) KHR_draco_mesh_compression",
    );
}

#[test]
fn out_of_bounds_and_absurd_accessors_are_refused_before_allocating() {
    let dir = Scratch::new("bounds");
    let mut doc = Doc::default();
    let p = doc.floats(&TRIANGLE, "VEC3");
    let rest = format!(
        r#","nodes":[{{"mesh":0}}],"meshes":[{{"primitives":[{{"attributes":{{"POSITION":{p}}}}}]}}]"#
    );
    let original = doc.accessors[p].clone();
    doc.accessors[p] = original.replace(r#""count":3"#, r#""count":4"#);
    let path = dir.write("overrun.glb", doc.glb(&rest));
    assert_names(
        &refused(&path),
        "accessor 0 (POSITION of mesh 0 primitive 0) reaches byte 48 of a 36-byte buffer view 0",
    );
    doc.accessors[p] = original.replace(r#""count":3"#, r#""count":2147483648"#);
    let path = dir.write("huge.glb", doc.glb(&rest));
    let start = Instant::now();
    let error = refused(&path);
    assert!(
        start.elapsed() < Duration::from_millis(500),
        "{:?}",
        start.elapsed()
    );
    assert_names(
        &error,
        "accessor 0 (POSITION of mesh 0 primitive 0) reaches byte 25769803776",
    );
    doc.accessors[p] = original.replace(r#""count":3"#, r#""count":3,"byteOffset":4294967296"#);
    let path = dir.write("far.glb", doc.glb(&rest));
    assert_names(&refused(&path), "reaches byte 4294967332");
    doc.accessors[p] = original.replace(r#""count":3"#, r#""count":3,"sparse":{"count":1,"indices":{"bufferView":0,"componentType":5121},"values":{"bufferView":0}}"#);
    let path = dir.write("sparse.glb", doc.glb(&rest));
    assert_names(&refused(&path), "sparse accessors are not supported");
    doc.accessors[p] = original.clone();
    // The buffer view claims more than the buffer holds.
    doc.views[0] = doc.views[0].replace(r#""byteLength":36"#, r#""byteLength":4000000000"#);
    doc.accessors[p] = original.replace(r#""count":3"#, r#""count":300000000"#);
    let path = dir.write("view.glb", doc.glb(&rest));
    assert_names(
        &refused(&path),
        "buffer view 0 reaches byte 4000000000 of the 36-byte buffer 0",
    );
    doc.views[0] = doc.views[0].replace(r#""byteLength":4000000000"#, r#""byteLength":36"#);
    doc.accessors[p] = original;
    // Indices naming missing things, which panic the gltf crate's own validation.
    let path = dir.write(
        "index.glb",
        doc.glb(&rest.replace(&format!(r#""POSITION":{p}"#), r#""POSITION":7"#)),
    );
    assert_names(
        &refused(&path),
        "accessor 7 (POSITION of mesh 0 primitive 0) does not exist",
    );
    let path = dir.write(
        "node.glb",
        doc.glb(&format!(r#"{rest},"scenes":[{{"nodes":[3]}}]"#)),
    );
    assert_names(
        &refused(&path),
        "scene 0 lists node 3, which does not exist",
    );
    let path = dir.write(
        "cycle.glb",
        doc.glb(
            &rest
                .replace(r#""mesh":0}"#, r#""mesh":0,"children":[0]}"#)
                .replace("\"nodes\":[", "\"scenes\":[{\"nodes\":[0]}],\"nodes\":["),
        ),
    );
    assert_names(&refused(&path), "node 0 is reached twice");
}

#[test]
fn bad_skins_and_keys_are_refused_naming_them() {
    let dir = Scratch::new("skins");
    let one = [1.0, 0.0, 0.0, 0.0];
    let cases: [(&str, Vec<u8>, &str); 6] = [
        ("joint.glb", one_bone(&[0, 0, 0, 0, 3, 0, 0, 0, 0, 0, 0, 0], &one.repeat(3), &[0.0, 1.0]), "JOINTS_0 of mesh 0 primitive 0: vertex 1 names joint 3, but skin 0 has 1 joints"),
        ("nan.glb", one_bone(&[0; 12], &[1.0, 0.0, 0.0, 0.0, f32::NAN, 1.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0], &[0.0, 1.0]), "WEIGHTS_0 of mesh 0 primitive 0: vertex 1 has the weight NaN"),
        ("zero.glb", one_bone(&[0; 12], &[1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0], &[0.0, 1.0]), "vertex 1's weights [0.0, 0.0, 0.0, 0.0] sum to 0"),
        ("negative.glb", one_bone(&[0; 12], &[1.0, 0.0, 0.0, 0.0, 1.5, -0.5, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0], &[0.0, 1.0]), "vertex 1 has the weight -0.5"),
        ("keys.glb", one_bone(&[0; 12], &one.repeat(3), &[0.0, 1.0, 1.0]), "animation 0 (`wave`) channel 0: key times must increase, but key 2 at 1 s is not after key 1 at 1 s"),
        ("nan-key.glb", one_bone(&[0; 12], &one.repeat(3), &[0.0, f32::NAN]), "key 1's time NaN is not finite"),
    ];
    for (name, bytes, needle) in cases {
        let path = dir.write(name, bytes);
        assert_names(&refused(&path), needle);
    }
    // No triangles: only points.
    let mut doc = Doc::default();
    let p = doc.floats(&TRIANGLE, "VEC3");
    let path = dir.write("points.glb", doc.glb(&format!(r#","nodes":[{{"mesh":0}}],"meshes":[{{"primitives":[{{"attributes":{{"POSITION":{p}}},"mode":0}}]}}]"#)));
    assert_names(&refused(&path), "no triangles");
    let path = dir.write("empty.glb", doc.glb(""));
    assert_names(&refused(&path), "no triangles");
}

#[test]
fn folders_and_fifos_are_refused_without_blocking() {
    let dir = Scratch::new("special");
    let folder = dir.0.join("model.glb");
    std::fs::create_dir_all(&folder).unwrap();
    assert_names(&refused(&folder), "a folder");
    let fifo = dir.0.join("pipe.glb");
    let status = std::process::Command::new("mkfifo")
        .arg(&fifo)
        .status()
        .expect("mkfifo runs");
    assert!(status.success());
    let (send, receive) = std::sync::mpsc::channel();
    let path = fifo.clone();
    std::thread::spawn(move || {
        let _ = send.send(load_gltf(&path).map(|_| ()).map_err(|e| e.to_string()));
    });
    match receive.recv_timeout(Duration::from_secs(10)) {
        Ok(result) => assert_names(
            &result.expect_err("a FIFO is refused"),
            "a FIFO (named pipe), not a regular file",
        ),
        Err(_) => {
            // Unblock the reader before failing.
            let _ = std::fs::OpenOptions::new().write(true).open(&fifo);
            panic!("load_gltf blocked on a FIFO");
        }
    }
    assert_names(&refused(&dir.0.join("absent.glb")), "no such file");
}

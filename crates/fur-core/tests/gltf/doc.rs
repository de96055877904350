//! glTF files made for the tests: a scratch folder, a document builder that packs
//! accessors into one buffer, `.glb` containers, and a one-bone body (shared with the
//! application's glTF tests, `tests/gltf/`).
#![allow(dead_code)]

use std::path::PathBuf;

use glam::Quat;

/// A scratch folder for one test, removed when dropped.
pub struct Scratch(pub PathBuf);

impl Scratch {
    pub fn new(name: &str) -> Self {
        let dir = std::env::temp_dir().join(format!("fur-gltf-{name}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        Self(dir)
    }

    pub fn write(&self, name: &str, bytes: impl AsRef<[u8]>) -> PathBuf {
        let path = self.0.join(name);
        std::fs::write(&path, bytes).unwrap();
        path
    }
}

impl Drop for Scratch {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

/// A glTF document under construction: its binary buffer, buffer views and accessors;
/// the rest of the JSON is given as text.
#[derive(Default)]
pub struct Doc {
    pub bin: Vec<u8>,
    pub views: Vec<String>,
    pub accessors: Vec<String>,
}

pub const FLOAT: u32 = 5126;
pub const UBYTE: u32 = 5121;
pub const USHORT: u32 = 5123;

impl Doc {
    pub fn accessor(
        &mut self,
        bytes: &[u8],
        count: usize,
        component: u32,
        ty: &str,
        normalized: bool,
    ) -> usize {
        while self.bin.len() % 4 != 0 {
            self.bin.push(0);
        }
        self.views.push(format!(
            r#"{{"buffer":0,"byteOffset":{},"byteLength":{}}}"#,
            self.bin.len(),
            bytes.len()
        ));
        self.bin.extend_from_slice(bytes);
        self.accessors.push(format!(
            r#"{{"bufferView":{},"componentType":{component},"count":{count},"type":"{ty}","normalized":{normalized}}}"#,
            self.views.len() - 1
        ));
        self.accessors.len() - 1
    }

    pub fn floats(&mut self, data: &[f32], ty: &str) -> usize {
        let bytes: Vec<u8> = data.iter().flat_map(|x| x.to_le_bytes()).collect();
        self.accessor(&bytes, data.len() / dims(ty), FLOAT, ty, false)
    }

    pub fn u8s(&mut self, data: &[u8], ty: &str, normalized: bool) -> usize {
        self.accessor(data, data.len() / dims(ty), UBYTE, ty, normalized)
    }

    pub fn u16s(&mut self, data: &[u16], ty: &str) -> usize {
        let bytes: Vec<u8> = data.iter().flat_map(|x| x.to_le_bytes()).collect();
        self.accessor(&bytes, data.len() / dims(ty), USHORT, ty, false)
    }

    /// The JSON text with `buffer` as buffer 0's object and `rest` (`,"nodes":...`).
    pub fn json(&self, buffer: &str, rest: &str) -> String {
        format!(
            r#"{{"asset":{{"version":"2.0"}},"buffers":[{buffer}],"bufferViews":[{}],"accessors":[{}]{rest}}}"#,
            self.views.join(","),
            self.accessors.join(",")
        )
    }

    pub fn glb(&self, rest: &str) -> Vec<u8> {
        glb(
            &self.json(&format!(r#"{{"byteLength":{}}}"#, self.bin.len()), rest),
            &self.bin,
        )
    }
}

pub fn dims(ty: &str) -> usize {
    match ty {
        "SCALAR" => 1,
        "VEC2" => 2,
        "VEC3" => 3,
        "VEC4" => 4,
        _ => 16,
    }
}

pub fn glb(json: &str, bin: &[u8]) -> Vec<u8> {
    let pad = |n: usize| (4 - n % 4) % 4;
    let json_len = json.len() + pad(json.len());
    let bin_len = bin.len() + pad(bin.len());
    let total = 12 + 8 + json_len + 8 + bin_len;
    let mut out = Vec::with_capacity(total);
    out.extend_from_slice(b"glTF");
    out.extend_from_slice(&2u32.to_le_bytes());
    out.extend_from_slice(&(total as u32).to_le_bytes());
    out.extend_from_slice(&(json_len as u32).to_le_bytes());
    out.extend_from_slice(b"JSON");
    out.extend_from_slice(json.as_bytes());
    out.extend(std::iter::repeat_n(b' ', pad(json.len())));
    out.extend_from_slice(&(bin_len as u32).to_le_bytes());
    out.extend_from_slice(b"BIN\0");
    out.extend_from_slice(bin);
    out.extend(std::iter::repeat_n(0, pad(bin.len())));
    out
}

pub const TRIANGLE: [f32; 9] = [0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0];

/// A triangle skinned to one bone (translated by +x), the mesh node's own transform
/// (ignored) far away, with a clip turning the bone; `weights` and `joints` per vertex.
pub fn one_bone(joints: &[u8], weights: &[f32], times: &[f32]) -> Vec<u8> {
    let mut doc = Doc::default();
    let p = doc.floats(&TRIANGLE, "VEC3");
    let j = doc.u8s(joints, "VEC4", false);
    let w = doc.floats(weights, "VEC4");
    let t = doc.floats(times, "SCALAR");
    let values: Vec<f32> = (0..times.len())
        .flat_map(|k| Quat::from_rotation_z(0.5 * k as f32).to_array())
        .collect();
    let r = doc.floats(&values, "VEC4");
    doc.glb(&format!(
        r#","nodes":[{{"name":"bone","translation":[1,0,0]}},{{"name":"skinned","mesh":0,"skin":0,"translation":[100,100,100]}}],
        "skins":[{{"joints":[0]}}],
        "meshes":[{{"primitives":[{{"attributes":{{"POSITION":{p},"JOINTS_0":{j},"WEIGHTS_0":{w}}}}}]}}],
        "animations":[{{"name":"wave","channels":[{{"sampler":0,"target":{{"node":0,"path":"rotation"}}}}],"samplers":[{{"input":{t},"output":{r}}}]}}],
        "scenes":[{{"nodes":[0,1]}}],"scene":0"#
    ))
}

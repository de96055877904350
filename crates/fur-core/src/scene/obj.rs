//! OBJ files: reading a model (positions, normals, texture coordinates and the diffuse
//! texture its material names) and writing one.

use std::cell::RefCell;
use std::collections::HashMap;
use std::path::{Path, PathBuf};

use glam::{Vec2, Vec3};

use super::{Mesh, TextureSpec};
use crate::error::{Error, Result};

/// Where an OBJ file lies, for its material libraries and texture.
struct Origin<'a> {
    /// The OBJ file, named in warnings.
    obj: &'a Path,
    /// Its folder: material libraries and textures are relative to it.
    folder: &'a Path,
}

impl Mesh {
    /// Loads an OBJ file (all its objects, triangulated). Normals come from the file
    /// when every face has them, otherwise from area-weighted face normals; texture
    /// coordinates (`vt`) when every face has them, otherwise none. A UTF-8 byte-order
    /// mark and bytes that are not UTF-8 (in comments and names, as some exporters
    /// write them) are accepted. The material libraries (`mtllib`) are read from the
    /// OBJ's folder, and [`Mesh::texture`] is the `map_Kd` of the first material the
    /// faces use; a material library that is missing or unreadable is a warning (the
    /// model loads without a texture), not an error.
    pub fn load_obj(path: &Path) -> Result<Self> {
        let error = |message: String| Error::Model {
            path: path.to_path_buf(),
            message,
        };
        let bytes = crate::files::read_bounded(path, crate::files::MAX_MODEL_BYTES, "model")
            .map_err(error)?;
        let origin = Origin {
            obj: path,
            folder: path.parent().unwrap_or(Path::new("")),
        };
        Self::parse(&bytes, Some(&origin)).map_err(error)
    }

    /// Parses OBJ text (see [`Mesh::load_obj`]); the error says what is wrong. With no
    /// folder to read them from, material libraries are ignored: the texture is `None`.
    pub fn parse_obj(bytes: &[u8]) -> std::result::Result<Self, String> {
        Self::parse(bytes, None)
    }

    fn parse(bytes: &[u8], origin: Option<&Origin>) -> std::result::Result<Self, String> {
        let text = faces_only(&utf8_text(bytes));
        if !text
            .lines()
            .any(|l| l.split_whitespace().next() == Some("f"))
        {
            return Err(
                "the file has no faces (`f` elements): fur grows from triangles, and \
                 lines (`l`) and points (`p`) are not faces"
                    .into(),
            );
        }
        let options = tobj::LoadOptions {
            triangulate: true,
            single_index: false,
            ignore_points: true,
            ignore_lines: true,
        };
        let warnings = RefCell::new(Vec::new());
        let load_mtl = |name: &Path| -> tobj::MTLLoadResult {
            let Some(origin) = origin else {
                return Ok(Default::default());
            };
            let file = origin.folder.join(name);
            let result = crate::files::read_bounded(
                &file,
                crate::files::MAX_MATERIAL_BYTES,
                "material library",
            )
            .and_then(|bytes| {
                tobj::load_mtl_buf(&mut std::io::Cursor::new(utf8_text(&bytes).as_bytes()))
                    .map_err(|e| format!("not a valid material library ({e})"))
            });
            result.map_err(|message| {
                warnings.borrow_mut().push(format!(
                    "material library {} of model {} cannot be read ({message}); the model \
                     loads without its texture",
                    file.display(),
                    origin.obj.display()
                ));
                tobj::LoadError::OpenFileFailed
            })
        };
        let (models, materials) = tobj::load_obj_buf(
            &mut std::io::Cursor::new(text.as_bytes()),
            &options,
            load_mtl,
        )
        .map_err(|e| format!("not a valid OBJ file ({e})"))?;
        for warning in warnings.into_inner() {
            log::warn!("{warning}");
        }
        let materials = materials.unwrap_or_default();
        let texture = origin.and_then(|origin| {
            let id = models
                .iter()
                .filter(|m| !m.mesh.indices.is_empty())
                .find_map(|m| m.mesh.material_id)?;
            let spec = materials.get(id)?.diffuse_texture.as_deref()?;
            texture_file(spec).map(|name| TextureSpec::File(origin.folder.join(name)))
        });
        let mut positions = Vec::new();
        let mut file_normals: Vec<Vec3> = Vec::new();
        let mut normal_indices: Vec<u32> = Vec::new();
        let mut indices = Vec::new();
        let mut uvs = Vec::new();
        let mut all_faces_have_normals = true;
        let mut all_faces_have_uvs = every_face_has_texture_coordinates(&text);
        for model in &models {
            let m = &model.mesh;
            if m.positions.len() % 3 != 0 {
                return Err(format!(
                    "object `{}` has a truncated position list",
                    model.name
                ));
            }
            let base = positions.len() as u32;
            let normal_base = file_normals.len() as u32;
            positions.extend(
                m.positions
                    .chunks_exact(3)
                    .map(|p| Vec3::new(p[0], p[1], p[2])),
            );
            file_normals.extend(
                m.normals
                    .chunks_exact(3)
                    .map(|n| Vec3::new(n[0], n[1], n[2])),
            );
            for &i in &m.indices {
                if (base + i) as usize >= positions.len() {
                    return Err(format!(
                        "object `{}` references vertex {} of {}",
                        model.name,
                        i + 1,
                        m.positions.len() / 3
                    ));
                }
                indices.push(base + i);
            }
            if m.normal_indices.len() == m.indices.len() && !m.normals.is_empty() {
                for &i in &m.normal_indices {
                    if i as usize >= m.normals.len() / 3 {
                        return Err(format!(
                            "object `{}` references normal {} of {}",
                            model.name,
                            i + 1,
                            m.normals.len() / 3
                        ));
                    }
                    normal_indices.push(normal_base + i);
                }
            } else if !m.indices.is_empty() {
                all_faces_have_normals = false;
            }
            if all_faces_have_uvs && m.texcoord_indices.len() == m.indices.len() {
                for &i in &m.texcoord_indices {
                    let i = i as usize;
                    let Some(uv) = m.texcoords.get(2 * i..2 * i + 2) else {
                        return Err(format!(
                            "object `{}` references texture coordinate {} of {}",
                            model.name,
                            i + 1,
                            m.texcoords.len() / 2
                        ));
                    };
                    // OBJ's v points up the image; ours points down its rows.
                    uvs.push(Vec2::new(uv[0], 1.0 - uv[1]));
                }
            } else if !m.indices.is_empty() {
                all_faces_have_uvs = false;
            }
        }
        if indices.is_empty() {
            return Err("the file has no faces: fur grows from triangles".into());
        }
        if let Some(p) = positions.iter().find(|p| !p.is_finite()) {
            return Err(format!("a vertex position is not finite: {p}"));
        }
        let normals = if all_faces_have_normals {
            let mut normals = vec![Vec3::ZERO; positions.len()];
            for (&vi, &ni) in indices.iter().zip(&normal_indices) {
                normals[vi as usize] += file_normals[ni as usize];
            }
            normals
        } else {
            Vec::new()
        };
        if !all_faces_have_uvs {
            uvs.clear();
        }
        let mut mesh = Self {
            positions,
            normals,
            indices,
            uvs,
            texture,
        };
        mesh.drop_degenerate_triangles();
        if mesh.indices.is_empty() {
            return Err("every face is degenerate (zero area)".into());
        }
        if let Some(uv) = mesh.uvs.iter().find(|uv| !uv.is_finite()) {
            return Err(format!(
                "a texture coordinate (`vt`) is not finite: ({}, {})",
                uv.x,
                1.0 - uv.y
            ));
        }
        mesh.compact();
        // A normal that cannot be normalised (zero, infinite or NaN: from broken `vn`
        // lines or ones that cancel out) discards the file's normals.
        if mesh.normals.is_empty() || mesh.normals.iter().any(|n| n.try_normalize().is_none()) {
            mesh.normals = mesh.face_weighted_normals();
        } else {
            mesh.normals.iter_mut().for_each(|n| *n = n.normalize());
        }
        Ok(mesh)
    }

    /// Writes the mesh as OBJ with positions, normals, texture coordinates (when it has
    /// them) and faces. The texture is not written (no material library).
    pub fn write_obj(&self, path: &Path) -> Result<()> {
        use std::fmt::Write as _;
        let mut text = String::from("# fur: generated model\n");
        for p in &self.positions {
            let _ = writeln!(text, "v {:.6} {:.6} {:.6}", p.x, p.y, p.z);
        }
        for n in &self.normals {
            let _ = writeln!(text, "vn {:.6} {:.6} {:.6}", n.x, n.y, n.z);
        }
        // One `vt` per distinct corner UV, in order of first use (1-based).
        let mut uv_numbers: HashMap<[u32; 2], usize> = HashMap::new();
        let mut corner_uv = Vec::with_capacity(self.uvs.len());
        for uv in &self.uvs {
            let next = uv_numbers.len() + 1;
            let number = *uv_numbers
                .entry([uv.x.to_bits(), uv.y.to_bits()])
                .or_insert_with(|| {
                    let _ = writeln!(text, "vt {:.6} {:.6}", uv.x, 1.0 - uv.y);
                    next
                });
            corner_uv.push(number);
        }
        let textured = self.uvs.len() == self.indices.len();
        for (k, t) in self.indices.chunks_exact(3).enumerate() {
            text.push('f');
            for (c, &i) in t.iter().enumerate() {
                let v = i + 1;
                if textured {
                    let _ = write!(text, " {v}/{}/{v}", corner_uv[3 * k + c]);
                } else {
                    let _ = write!(text, " {v}//{v}");
                }
            }
            text.push('\n');
        }
        crate::files::write_output(path, text.as_bytes(), "write the model to")
    }

    /// Removes triangles with repeated indices or zero area (and their corner UVs).
    fn drop_degenerate_triangles(&mut self) {
        let positions = &self.positions;
        let has_uvs = self.uvs.len() == self.indices.len();
        let mut indices = Vec::with_capacity(self.indices.len());
        let mut uvs = Vec::with_capacity(self.uvs.len());
        for (k, t) in self.indices.chunks_exact(3).enumerate() {
            let [a, b, c] = [t[0], t[1], t[2]].map(|i| positions[i as usize]);
            let degenerate = t[0] == t[1]
                || t[1] == t[2]
                || t[0] == t[2]
                || (b - a).cross(c - a).length_squared() <= 0.0;
            if !degenerate {
                indices.extend_from_slice(t);
                if has_uvs {
                    uvs.extend_from_slice(&self.uvs[3 * k..3 * k + 3]);
                }
            }
        }
        self.indices = indices;
        self.uvs = uvs;
    }

    /// Drops vertices no triangle uses: they would grow hairs nobody draws. Corner UVs
    /// follow the corners, which keep their order.
    fn compact(&mut self) {
        let mut remap = vec![u32::MAX; self.positions.len()];
        let mut positions = Vec::new();
        let mut normals = Vec::new();
        for i in self.indices.iter_mut() {
            let old = *i as usize;
            if remap[old] == u32::MAX {
                remap[old] = positions.len() as u32;
                positions.push(self.positions[old]);
                if let Some(n) = self.normals.get(old) {
                    normals.push(*n);
                }
            }
            *i = remap[old];
        }
        self.positions = positions;
        self.normals = normals;
    }
}

/// The text of an OBJ or MTL file: without a UTF-8 byte-order mark, bytes that are
/// not UTF-8 replaced.
fn utf8_text(bytes: &[u8]) -> String {
    let bytes = bytes.strip_prefix(b"\xEF\xBB\xBF").unwrap_or(bytes);
    String::from_utf8_lossy(bytes).into_owned()
}

/// The OBJ text without its line (`l`) and point (`p`) elements: tobj reads a
/// three-vertex `l` as a triangle, but only `f` elements are faces. Blanked lines keep
/// the line count.
fn faces_only(text: &str) -> String {
    text.lines()
        .map(|line| match line.split_whitespace().next() {
            Some("l" | "p") => "",
            _ => line,
        })
        .collect::<Vec<_>>()
        .join("\n")
}

/// Whether every face (`f` line with three or more corners) gives every corner a
/// texture coordinate (`v/vt` or `v/vt/vn`). tobj fills missing ones in from their
/// neighbours, so this is read from the text itself.
fn every_face_has_texture_coordinates(text: &str) -> bool {
    text.lines().all(|line| {
        let mut words = line.split_whitespace();
        if words.next() != Some("f") {
            return true;
        }
        let corners: Vec<&str> = words.collect();
        corners.len() < 3
            || corners
                .iter()
                .all(|c| c.split('/').nth(1).is_some_and(|t| !t.is_empty()))
    })
}

/// The file name in a `map_Kd` statement, after its options (`-s 1 1 1`, `-bm 0.5`,
/// ...); backslashes (from Windows exporters) become slashes.
fn texture_file(spec: &str) -> Option<PathBuf> {
    let mut words = spec.split_whitespace().peekable();
    while let Some(option) = words.peek().copied().filter(|w| w.starts_with('-')) {
        words.next();
        let arguments = match option {
            "-blendu" | "-blendv" | "-bm" | "-boost" | "-cc" | "-clamp" | "-imfchan"
            | "-texres" | "-type" => 1,
            "-mm" => 2,
            // -o, -s, -t: one to three numbers.
            _ => 3,
        };
        for _ in 0..arguments {
            if arguments == 3 && words.peek().is_some_and(|w| w.parse::<f32>().is_err()) {
                break;
            }
            words.next();
        }
    }
    let name = words.collect::<Vec<_>>().join(" ").replace('\\', "/");
    (!name.is_empty()).then(|| PathBuf::from(name))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn written_uvs_read_back_per_corner() {
        let mesh = Mesh::uv_sphere(1.0, 6, 8);
        let path = std::env::temp_dir().join(format!("fur-obj-uv-{}.obj", std::process::id()));
        mesh.write_obj(&path).unwrap();
        let read = Mesh::load_obj(&path);
        let _ = std::fs::remove_file(&path);
        let read = read.unwrap();
        assert_eq!(read.uvs.len(), mesh.uvs.len());
        assert_eq!(read.texture, None);
        for (a, b) in read.uvs.iter().zip(&mesh.uvs) {
            assert!((*a - *b).abs().max_element() < 2e-6, "{a} vs {b}");
        }
        for (k, (&a, &b)) in read.indices.iter().zip(&mesh.indices).enumerate() {
            let (pa, pb) = (read.positions[a as usize], mesh.positions[b as usize]);
            assert!((pa - pb).length() < 1e-5, "corner {k}: {pa} vs {pb}");
        }
    }

    #[test]
    fn uvs_follow_triangles_past_degenerate_ones() {
        let text = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 2 0 0\nvt 0 0\nvt 1 0\nvt 0 1\nvt 0.5 0.5\n\
                    f 1/1 2/1 4/1\nf 1/4 2/2 3/3\n";
        let mesh = Mesh::parse_obj(text.as_bytes()).unwrap();
        assert_eq!(mesh.triangle_count(), 1);
        let expected = [
            Vec2::new(0.5, 0.5),
            Vec2::new(1.0, 1.0),
            Vec2::new(0.0, 0.0),
        ];
        assert_eq!(mesh.uvs, expected);
    }

    #[test]
    fn non_finite_uvs_are_refused_and_partial_ones_dropped() {
        let bad = "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt nan 0\nf 1/1 2/1 3/1\n";
        let message = Mesh::parse_obj(bad.as_bytes()).unwrap_err();
        assert!(message.contains("texture coordinate"), "{message}");
        let partial = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nvt 0 0\nf 1/1 2/1 3/1\nf 2 4 3\n";
        let mesh = Mesh::parse_obj(partial.as_bytes()).unwrap();
        assert!(mesh.uvs.is_empty());
    }

    #[test]
    fn texture_names_lose_their_options() {
        assert_eq!(texture_file("fur.png"), Some("fur.png".into()));
        assert_eq!(
            texture_file("-s 1 1 1 -bm 0.5 tex\\my fur.png"),
            Some("tex/my fur.png".into())
        );
        assert_eq!(texture_file("-o 0.5 a.png"), Some("a.png".into()));
        assert_eq!(texture_file("-clamp on"), None);
    }
}

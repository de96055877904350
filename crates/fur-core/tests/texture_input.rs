//! Texture input from files (no GPU): image files load or fail with an error naming
//! the file, and OBJ models bring their texture coordinates and their material's
//! diffuse texture.

use std::path::{Path, PathBuf};

use fur_core::error::Error;
use fur_core::scene::{Mesh, Texture, TextureSpec};

/// A fresh, empty folder under the system's temporary folder, removed when dropped.
struct TempDir(PathBuf);

impl TempDir {
    fn new(name: &str) -> Self {
        let dir =
            std::env::temp_dir().join(format!("fur-texture-input-{}-{name}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        Self(dir)
    }

    fn path(&self, name: &str) -> PathBuf {
        self.0.join(name)
    }
}

impl Drop for TempDir {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

/// Loading `path` fails with a texture error whose message names the file.
fn refused(path: &Path) -> String {
    let error = Texture::load(path).expect_err("the texture should be refused");
    assert!(matches!(error, Error::Texture { .. }), "{error:?}");
    let message = error.to_string();
    assert!(
        message.contains(&path.display().to_string()),
        "the message does not name {}: {message}",
        path.display()
    );
    message
}

/// A 6 × 4 image: red, green, blue and white quadrants (columns split 3 | 3).
fn quadrants() -> image::RgbaImage {
    image::RgbaImage::from_fn(6, 4, |x, y| match (x < 3, y < 2) {
        (true, true) => image::Rgba([255, 0, 0, 255]),
        (false, true) => image::Rgba([0, 255, 0, 255]),
        (true, false) => image::Rgba([0, 0, 255, 255]),
        (false, false) => image::Rgba([255, 255, 255, 255]),
    })
}

#[test]
fn png_jpeg_and_tga_files_load_with_their_mips() {
    let dir = TempDir::new("formats");
    let image = quadrants();
    let png = dir.path("quadrants.png");
    let tga = dir.path("quadrants.tga");
    let jpeg = dir.path("quadrants.jpg");
    image.save(&png).unwrap();
    image.save(&tga).unwrap();
    image::DynamicImage::ImageRgba8(image.clone())
        .to_rgb8()
        .save(&jpeg)
        .unwrap();
    for path in [&png, &tga] {
        let t = Texture::load(path).unwrap();
        assert_eq!((t.width, t.height), (6, 4));
        assert_eq!(t.levels[0], image.as_raw().as_slice(), "{}", path.display());
        let sizes: Vec<_> = (0..t.levels.len()).map(|l| t.level_size(l)).collect();
        assert_eq!(sizes, [(6, 4), (3, 2), (1, 1)]);
    }
    let t = Texture::load(&jpeg).unwrap();
    assert_eq!((t.width, t.height, t.levels.len()), (6, 4, 3));
    // Lossy, but the quadrants stay apart.
    let red = t.sample(glam::Vec2::new(0.1, 0.1));
    assert!(red.x > 0.5 && red.y < 0.3 && red.z < 0.3, "{red}");
    let white = t.sample(glam::Vec2::new(0.9, 0.9));
    assert!(white.min_element() > 0.6, "{white}");
}

#[test]
fn bad_texture_files_are_refused_naming_the_file() {
    let dir = TempDir::new("bad");
    refused(&dir.path("missing.png"));
    assert!(refused(&dir.0).contains("folder"));

    let text = dir.path("notes.png");
    std::fs::write(&text, "this is not an image\n").unwrap();
    assert!(refused(&text).contains("PNG, JPEG or TGA"));

    let unknown = dir.path("notes.dat");
    std::fs::write(&unknown, "still not an image\n").unwrap();
    assert!(refused(&unknown).contains("PNG, JPEG or TGA"));

    let empty = dir.path("empty.png");
    std::fs::write(&empty, png_header(0, 0)).unwrap();
    refused(&empty);
    let truncated = dir.path("truncated.png");
    std::fs::write(&truncated, &png_header(4, 4)[..20]).unwrap();
    refused(&truncated);

    let wide = dir.path("wide.png");
    image::GrayImage::new(9000, 1).save(&wide).unwrap();
    let message = refused(&wide);
    assert!(
        message.contains("9000") && message.contains("8192"),
        "{message}"
    );
}

/// The PNG signature and an IHDR chunk for an RGBA8 image of `width × height` (no
/// pixel data).
fn png_header(width: u32, height: u32) -> Vec<u8> {
    let mut chunk = b"IHDR".to_vec();
    chunk.extend(width.to_be_bytes());
    chunk.extend(height.to_be_bytes());
    chunk.extend([8, 6, 0, 0, 0]);
    let mut bytes = b"\x89PNG\r\n\x1a\n".to_vec();
    bytes.extend(13u32.to_be_bytes());
    bytes.extend(&chunk);
    bytes.extend(crc32(&chunk).to_be_bytes());
    bytes
}

fn crc32(bytes: &[u8]) -> u32 {
    let mut crc = !0u32;
    for &b in bytes {
        crc ^= u32::from(b);
        for _ in 0..8 {
            crc = if crc & 1 != 0 {
                (crc >> 1) ^ 0xEDB8_8320
            } else {
                crc >> 1
            };
        }
    }
    !crc
}

/// A unit square in two triangles with texture coordinates on every face, using
/// material `fur` from `stripes.mtl`.
const TEXTURED_OBJ: &str = "mtllib stripes.mtl
v 0 0 0
v 1 0 0
v 1 1 0
v 0 1 0
vt 0 0
vt 1 0
vt 1 1
vt 0 1
vn 0 0 1
usemtl fur
f 1/1/1 2/2/1 3/3/1
f 1/1/1 3/3/1 4/4/1
";

#[test]
fn an_obj_brings_its_uvs_and_its_materials_texture() {
    let dir = TempDir::new("obj");
    let obj = dir.path("square.obj");
    std::fs::write(&obj, TEXTURED_OBJ).unwrap();
    std::fs::write(
        dir.path("stripes.mtl"),
        "newmtl fur\nKd 1 1 1\nmap_Kd stripes.png\n",
    )
    .unwrap();
    quadrants().save(dir.path("stripes.png")).unwrap();

    let mesh = Mesh::load_obj(&obj).unwrap();
    let texture = dir.path("stripes.png");
    assert_eq!(mesh.texture, Some(TextureSpec::File(texture.clone())));
    assert_eq!(mesh.uvs.len(), mesh.indices.len());
    // Per corner, following the positions; OBJ's v (up) becomes v down the image.
    for (&i, uv) in mesh.indices.iter().zip(&mesh.uvs) {
        let p = mesh.positions[i as usize];
        assert_eq!((uv.x, uv.y), (p.x, 1.0 - p.y), "corner at {p}");
    }
    let loaded = mesh.texture.as_ref().unwrap().load().unwrap();
    assert_eq!((loaded.width, loaded.height), (6, 4));

    // Without the material library the model still loads, untextured.
    std::fs::remove_file(dir.path("stripes.mtl")).unwrap();
    let mesh = Mesh::load_obj(&obj).unwrap();
    assert_eq!(mesh.texture, None);
    assert_eq!(mesh.uvs.len(), mesh.indices.len());

    // A texture file that does not exist is the texture loader's error, not the model's.
    std::fs::write(dir.path("stripes.mtl"), "newmtl fur\nmap_Kd gone.png\n").unwrap();
    let mesh = Mesh::load_obj(&obj).unwrap();
    let gone = dir.path("gone.png");
    assert_eq!(mesh.texture, Some(TextureSpec::File(gone.clone())));
    let message = mesh.texture.unwrap().load().unwrap_err().to_string();
    assert!(message.contains(&gone.display().to_string()), "{message}");

    // Parsing bytes (no folder) ignores materials.
    let mesh = Mesh::parse_obj(TEXTURED_OBJ.as_bytes()).unwrap();
    assert_eq!(mesh.texture, None);
    assert_eq!(mesh.uvs.len(), 6);
}

#[test]
fn texture_coordinates_on_only_some_faces_are_dropped() {
    let dir = TempDir::new("partial");
    let obj = dir.path("partial.obj");
    std::fs::write(
        &obj,
        "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 1 1\n\
         f 1/1 2/2 3/3\nf 1 3 4\n",
    )
    .unwrap();
    let mesh = Mesh::load_obj(&obj).unwrap();
    assert_eq!(mesh.triangle_count(), 2);
    assert!(mesh.uvs.is_empty());
    assert_eq!(mesh.texture, None);
}

//! The singular points of the fur's flow, marked in the `masters` view's image: where
//! the master hairs part from or meet at a point (whorls, red rings) and where they
//! part along two lines (saddles, cyan crosses), found from the hairs as grown, with a
//! key in the image's lower-left corner.

use ab_glyph::ScaleFont;
use glam::{Mat4, Vec3};

use crate::legend::{key_font, text_width, Canvas};
use fur_core::render::RgbaImage;
use fur_core::scene::{singular_points, Mesh, Singularity, Strands};

/// A whorl's mark (linear red).
pub const WHORL: Vec3 = Vec3::new(1.0, 0.08, 0.05);
/// A saddle's mark (linear cyan).
pub const SADDLE: Vec3 = Vec3::new(0.05, 0.8, 1.0);

/// The singular points of the way the master hairs lie on `mesh`: each hair's reach
/// from root to tip along the surface at its root (none where it stands along the
/// normal). Hairs past the mesh's vertices (a drawn groom's guides) are not counted.
pub fn of_masters(mesh: &Mesh, strands: &Strands) -> Vec<Singularity> {
    let directions: Vec<Vec3> = (0..mesh.vertex_count())
        .map(|v| {
            if v >= strands.count() {
                return Vec3::ZERO;
            }
            let s = strands.strand(v);
            let reach = s[s.len() - 1] - s[0];
            let n = mesh.normals[v].normalize_or_zero();
            let along = reach - reach.dot(n) * n;
            if along.length() <= 1e-3 * reach.length() {
                Vec3::ZERO
            } else {
                along.normalize()
            }
        })
        .collect();
    singular_points(mesh, &directions)
}

/// A singular point placed on the body: its index, position and the surface's normal
/// there (model space).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Mark {
    pub index: i32,
    pub position: Vec3,
    pub normal: Vec3,
}

/// Where each of `points` lies on the body posed as `positions` and `normals`.
pub fn placed(points: &[Singularity], positions: &[Vec3], normals: &[Vec3]) -> Vec<Mark> {
    points
        .iter()
        .map(|p| {
            let mean = |of: &[Vec3], or: Vec3| {
                p.corners
                    .iter()
                    .map(|&v| of.get(v as usize).copied().unwrap_or(or))
                    .sum::<Vec3>()
                    / 3.0
            };
            Mark {
                index: p.index,
                position: mean(positions, p.position),
                normal: mean(normals, Vec3::ZERO).normalize_or_zero(),
            }
        })
        .collect()
}

/// Draws `marks` into `image`, placed by `model` (model to world) and
/// `view_projection` (Vulkan clip space) of a camera at `eye` (world): a ring for a
/// whorl, a cross for a saddle, an image height / 60 across and outlined in black so
/// they read on any fur, faint where the surface faces away from the eye (the mark is
/// behind the body); and their key in the lower-left corner. Returns how many marks
/// fell in the image.
pub fn draw(
    image: &mut RgbaImage,
    marks: &[Mark],
    model: Mat4,
    view_projection: Mat4,
    eye: Vec3,
) -> usize {
    let size = (image.height as f32 / 60.0).max(3.0);
    let (w, h) = (image.width as f32, image.height as f32);
    let mut canvas = Canvas { image };
    let mut drawn = 0;
    for m in marks {
        let world = model.transform_point3(m.position);
        let clip = view_projection * world.extend(1.0);
        if clip.w <= 0.0 {
            continue;
        }
        let ndc = clip.truncate() / clip.w;
        let centre = glam::Vec2::new((ndc.x * 0.5 + 0.5) * w, (ndc.y * 0.5 + 0.5) * h);
        if (0.0..w).contains(&centre.x) && (0.0..h).contains(&centre.y) {
            let facing = model.transform_vector3(m.normal).dot(eye - world) >= 0.0;
            let opacity = if facing { 1.0 } else { 0.35 };
            mark(&mut canvas, centre, size, m.index > 0, opacity);
            drawn += 1;
        }
    }
    key(&mut canvas, size);
    drawn
}

/// One mark centred at `centre`: a ring (`whorl`) or a cross of half-size `size`.
fn mark(canvas: &mut Canvas<'_>, centre: glam::Vec2, size: f32, whorl: bool, opacity: f32) {
    let reach = size.ceil() as i32 + 3;
    let (cx, cy) = (centre.x.round() as i32, centre.y.round() as i32);
    for dy in -reach..=reach {
        for dx in -reach..=reach {
            let (x, y) = (dx as f32, dy as f32);
            // Distance from the mark's stroke, in pixels.
            let off = if whorl {
                ((x * x + y * y).sqrt() - size).abs()
            } else if x.abs().max(y.abs()) <= size + 1.0 {
                (x.abs() - y.abs()).abs() / std::f32::consts::SQRT_2
            } else {
                f32::MAX
            };
            let colour = if whorl { WHORL } else { SADDLE };
            if off < 1.0 {
                canvas.blend(cx + dx, cy + dy, colour, opacity);
            } else if off < 2.2 {
                canvas.blend(cx + dx, cy + dy, Vec3::ZERO, 0.8 * opacity);
            }
        }
    }
}

/// The marks' key in the lower-left corner: a ring, "whorl", a cross, "saddle".
fn key(canvas: &mut Canvas<'_>, size: f32) {
    let (font, _, margin) = key_font(canvas.image.height);
    let line = font.height().ceil() as i32;
    let labels = ["whorl", "saddle"];
    let mark_w = (2.0 * size).ceil() as i32 + 4;
    let width: i32 = labels
        .iter()
        .map(|l| mark_w + 4 + text_width(&font, l) + margin)
        .sum::<i32>()
        + margin;
    let height = line.max(mark_w) + 2 * margin;
    let (image_w, image_h) = (canvas.image.width as i32, canvas.image.height as i32);
    if width + 2 * margin > image_w || height + 2 * margin > image_h {
        return;
    }
    let (x0, y0) = (margin, image_h - margin - height);
    canvas.fill(x0, y0, width, height, |_, _| Vec3::ZERO, 0.7);
    let mut x = x0 + margin;
    let middle = y0 + height / 2;
    for (label, whorl) in labels.into_iter().zip([true, false]) {
        mark(
            canvas,
            glam::Vec2::new((x + mark_w / 2) as f32, middle as f32),
            size,
            whorl,
            1.0,
        );
        x += mark_w + 4;
        canvas.text(&font, label, x, middle - line / 2);
        x += text_width(&font, label) + margin;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::legend::tests::blank;

    /// A whorl is drawn red and a saddle cyan where the camera sees them, and a point
    /// behind the camera not at all. Seen failing with the image's y flipped.
    #[test]
    fn marks_fall_where_the_camera_sees_the_points() {
        let mut image = blank(200, 200);
        // Clip space is the model's own: x, y in [−1, 1], y down the image.
        let at = |index, position| Mark {
            index,
            position,
            normal: Vec3::NEG_Z,
        };
        let eye = Vec3::new(0.0, 0.0, -5.0);
        let points = [
            at(1, Vec3::new(-0.5, -0.5, 0.5)),
            at(-1, Vec3::new(0.5, 0.5, 0.5)),
        ];
        let behind = at(1, Vec3::new(0.0, 0.0, 0.5));
        let n = draw(&mut image, &points, Mat4::IDENTITY, Mat4::IDENTITY, eye);
        assert_eq!(n, 2);
        let pixel = |x: u32, y: u32| {
            let i = ((y * 200 + x) * 4) as usize;
            [image.data[i], image.data[i + 1], image.data[i + 2]]
        };
        let size = (200.0f32 / 60.0).max(3.0);
        // The whorl's ring, on its right: (50 + size, 50).
        let ring = pixel(50 + size.round() as u32, 50);
        assert!(ring[0] > 200 && ring[1] < 100, "{ring:?}");
        // The saddle's cross at its centre (150, 150).
        let cross = pixel(150, 150);
        assert!(cross[2] > 200 && cross[0] < 100, "{cross:?}");
        // A projection that puts every point behind the eye (w < 0) draws no mark.
        let mut other = blank(200, 200);
        let behind_eye = Mat4::from_cols(
            glam::Vec4::X,
            glam::Vec4::Y,
            glam::Vec4::Z,
            glam::Vec4::new(0.0, 0.0, 0.0, -1.0),
        );
        assert_eq!(
            draw(&mut other, &[behind], Mat4::IDENTITY, behind_eye, eye),
            0
        );
        // A mark on a surface facing away is drawn faint.
        let mut faint = blank(200, 200);
        let away = Mark {
            normal: Vec3::Z,
            ..points[0]
        };
        draw(&mut faint, &[away], Mat4::IDENTITY, Mat4::IDENTITY, eye);
        let i = ((50 * 200 + 50 + size.round() as u32) * 4) as usize;
        assert!(
            faint.data[i] < ring[0] && faint.data[i] > 10,
            "{}",
            faint.data[i]
        );
    }

    /// On a grown blob the marks are the flow's: every master hair's reach lies along the
    /// surface, so its whorls are the flow field's (two at the ear tips, one where the
    /// flow ends) and its saddle between the ears.
    #[test]
    fn the_masters_marks_are_the_flows_singular_points() {
        let mesh = Mesh::blob();
        let (groom, _) = fur_core::scene_file::SceneOptions::default()
            .resolve(&mesh)
            .unwrap();
        let strands = Strands::grow(&mesh, &groom).unwrap();
        let points = of_masters(&mesh, &strands);
        let sum: i32 = points.iter().map(|p| p.index).sum();
        assert_eq!(sum, 2, "{points:?}");
        let whorls = points.iter().filter(|p| p.index == 1).count();
        assert_eq!(whorls, 3, "{points:?}");
    }
}

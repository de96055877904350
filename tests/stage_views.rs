//! The stage views that colour by a number the pipeline computes: `density` (the
//! tessellation control stage's levels) and `simulation` (the kernel's probe of each
//! vertex's displacement and collision pushes), and the masters view's hair count, on
//! lavapipe with validation on.

mod common;

use std::collections::HashMap;

use ash::vk;
use fur_core::colour::linear_to_srgb8;
use fur_core::render::stage::{displacement_colour, inner_level, level_colour};
use fur_core::render::{FrameSettings, FurStyle, RgbaImage, Stage};
use fur_core::scene::{Camera, GroomParams, Mesh, Strands};
use fur_core::sim::{Sdf, SimParams};
use fur_gpu::render::{FrameReport, Renderer};
use fur_gpu::sim::GpuSim;
use fur_gpu::strand_textures::StrandTextures;
use glam::{Mat4, Vec2, Vec3, Vec4, Vec4Swizzles};

/// Draws `strands` on `mesh` once at `size`, one frame in flight.
fn draw(
    device: &std::sync::Arc<fur_gpu::gpu::Device>,
    mesh: &Mesh,
    strands: &Strands,
    settings: &FrameSettings,
    size: impl Into<fur_core::colour::Size>,
) -> (RgbaImage, FrameReport, f32) {
    let fur_core::colour::Size { width, height } = size.into();
    let textures = StrandTextures::new(device, strands, settings.head).unwrap();
    let extent = vk::Extent2D { width, height };
    let mut renderer = Renderer::new(device, mesh, &textures, extent, 1, 1).unwrap();
    let max_level = renderer.max_level();
    let (image, report) = renderer.render(&textures, settings).unwrap();
    (image, report, max_level)
}

fn srgb(c: Vec3) -> [u8; 3] {
    [c.x, c.y, c.z].map(linear_to_srgb8)
}

fn near(a: [u8; 3], b: [u8; 3], tolerance: u8) -> bool {
    (0..3).all(|c| a[c].abs_diff(b[c]) <= tolerance)
}

/// Separate right triangles in the y = 0 plane, legs `sizes`, side by side along x,
/// their normals up (+y); the last one turned over (normal down), so hair grown from it
/// grows away from a camera above.
fn triangles(sizes: &[f32]) -> Mesh {
    let mut mesh = Mesh {
        positions: Vec::new(),
        normals: Vec::new(),
        indices: Vec::new(),
        uvs: Vec::new(),
        texture: None,
    };
    let gap = 0.15;
    let width: f32 = sizes.iter().sum::<f32>() + gap * (sizes.len() - 1) as f32;
    let mut x = -0.5 * width;
    for (k, &s) in sizes.iter().enumerate() {
        let base = mesh.positions.len() as u32;
        let (a, b, c) = (
            Vec3::new(x, 0.0, 0.5 * s),
            Vec3::new(x + s, 0.0, 0.5 * s),
            Vec3::new(x, 0.0, -0.5 * s),
        );
        let up = k + 1 < sizes.len();
        mesh.positions.extend([a, b, c]);
        mesh.normals
            .extend([if up { Vec3::Y } else { Vec3::NEG_Y }; 3]);
        // Counter-clockwise seen from the side the normal points to.
        if up {
            mesh.indices.extend([base, base + 1, base + 2]);
        } else {
            mesh.indices.extend([base, base + 2, base + 1]);
        }
        x += s + gap;
    }
    mesh
}

/// The pixels whose centres lie inside triangle `t` of `mesh` (as `view_proj` puts it
/// on a `size` image) at least `inset` pixels from its edges.
fn pixels_inside(
    mesh: &Mesh,
    t: usize,
    view_proj: Mat4,
    size: (u32, u32),
    inset: f32,
) -> Vec<(u32, u32)> {
    let corner = |k: usize| {
        let p = mesh.positions[mesh.indices[3 * t + k] as usize];
        let clip = view_proj * p.extend(1.0);
        let ndc = clip.xyz() / clip.w;
        Vec2::new(
            (ndc.x * 0.5 + 0.5) * size.0 as f32,
            (ndc.y * 0.5 + 0.5) * size.1 as f32,
        )
    };
    let [a, b, c] = [corner(0), corner(1), corner(2)];
    let edge_distance = |p: Vec2, u: Vec2, v: Vec2| {
        let d = v - u;
        d.perp_dot(p - u) / d.length()
    };
    let orientation = (b - a).perp_dot(c - a).signum();
    let mut inside = Vec::new();
    for y in 0..size.1 {
        for x in 0..size.0 {
            let p = Vec2::new(x as f32 + 0.5, y as f32 + 0.5);
            let d = [(a, b), (b, c), (c, a)]
                .map(|(u, v)| orientation * edge_distance(p, u, v))
                .into_iter()
                .fold(f32::MAX, f32::min);
            if d >= inset {
                inside.push((x, y));
            }
        }
    }
    inside
}

/// The density view paints each triangle in the colour of the inner level the
/// tessellation control stage gives it, which for triangles of known areas is known
/// (`inner_level`, the CPU twin of `fur.tesc`): the most common colour inside each
/// triangle is its level's and not its neighbours' (level ± 1). A triangle whose hair
/// grows away from the camera is culled: it shows the mesh pass's grey stripes, and
/// the control stage counts it. No hair is drawn.
#[test]
fn the_density_view_colours_each_triangle_by_its_level_and_hatches_the_culled() {
    let device = common::device();
    let mesh = triangles(&[0.2, 0.4, 0.8, 1.6, 0.6]);
    let groom = GroomParams {
        segments: 4,
        segment_length: 0.02,
        comb_strength: 0.0,
        ..Default::default()
    };
    let size = (512, 192);
    let style = FurStyle {
        density: 400.0,
        lod_distance: 100.0,
        ..FurStyle::default()
    };
    let settings = FrameSettings {
        camera: Camera {
            target: Vec3::ZERO,
            pitch_deg: 89.0,
            distance: 2.4,
            ..Default::default()
        },
        style: style.clone(),
        show: Stage::Density,
        count_hairs: true,
        ..Default::default()
    };
    let strands = Strands::grow(&mesh, &groom).unwrap();
    let (image, report, max_level) = draw(&device, &mesh, &strands, &settings, size);
    common::assert_clean(&device);
    let counts = report.counts.expect("lavapipe counts");
    assert_eq!(counts.hairs, 0, "the density view draws no hair");
    assert_eq!(
        counts.triangles_culled, 1,
        "the turned-over triangle is culled"
    );

    let view_proj = settings
        .camera
        .view_projection(size.0 as f32 / size.1 as f32);
    let mut failures = Vec::new();
    for t in 0..4 {
        let [a, b, c] = [0, 1, 2].map(|k| mesh.positions[mesh.indices[3 * t + k] as usize]);
        let area = 0.5 * (b - a).cross(c - a).length();
        let level = inner_level(area, style.density, 1.0, max_level);
        let inside = pixels_inside(&mesh, t, view_proj, size, 2.5);
        assert!(inside.len() > 30, "triangle {t}: {} pixels", inside.len());
        let mut histogram: HashMap<[u8; 3], usize> = HashMap::new();
        for &(x, y) in &inside {
            let p = image.pixel(x, y);
            *histogram.entry([p[0], p[1], p[2]]).or_default() += 1;
        }
        let (mode, count) = histogram.into_iter().max_by_key(|(_, n)| *n).unwrap();
        let want = srgb(level_colour(level, max_level));
        let share = count as f32 / inside.len() as f32;
        let neighbours = [level - 1.0, level + 1.0].map(|l| srgb(level_colour(l, max_level)));
        println!(
            "triangle {t}: level {level}, mode {mode:?} on {share:.2} of its pixels, want {want:?}"
        );
        if !near(mode, want, 2) || neighbours.iter().any(|n| near(mode, *n, 2)) || share < 0.3 {
            failures.push(format!(
                "triangle {t} (level {level}): mode {mode:?}, want {want:?}"
            ));
        }
    }
    // The culled triangle: grey (r = g = b), in two stripes of clearly different grey.
    let culled = pixels_inside(&mesh, 4, view_proj, size, 2.5);
    let greys: Vec<u8> = culled
        .iter()
        .map(|&(x, y)| image.pixel(x, y))
        .filter(|p| p[0] == p[1] && p[1] == p[2])
        .map(|p| p[0])
        .collect();
    let (lo, hi) = (greys.iter().min(), greys.iter().max());
    println!(
        "culled: {} of {} pixels grey, {lo:?}..{hi:?}",
        greys.len(),
        culled.len()
    );
    if greys.len() < culled.len() * 95 / 100 || hi.zip(lo).is_none_or(|(h, l)| h - l < 30) {
        failures.push(format!("culled triangle not striped grey: {lo:?}..{hi:?}"));
    }
    if !failures.is_empty() {
        common::keep(&image, "density_view");
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// The masters view draws exactly the master hairs: the input assembler's primitives
/// over the target's passes are the body's triangles plus one line segment per master
/// hair segment, so the statistics count the hairs drawn.
#[test]
fn the_masters_view_draws_exactly_the_master_hairs() {
    let device = common::device();
    let mesh = Mesh::blob();
    let groom = GroomParams {
        segments: 5,
        ..Default::default()
    };
    let (centre, radius) = mesh.bounds();
    let strands = Strands::grow(&mesh, &groom).unwrap();
    for show in [Stage::Masters, Stage::Simulation] {
        let settings = FrameSettings {
            camera: Camera {
                target: centre,
                distance: 3.0 * radius,
                ..Default::default()
            },
            show,
            ..Default::default()
        };
        let (_, report, _) = draw(&device, &mesh, &strands, &settings, (96, 64));
        let statistics = common::statistics(report.statistics);
        let triangles = mesh.indices.len() as u64 / 3;
        let segments = statistics.input_primitives - triangles;
        let per_strand = u64::from(groom.segments);
        assert_eq!(segments % per_strand, 0, "{show:?}: {segments} segments");
        assert_eq!(
            segments / per_strand,
            strands.count() as u64,
            "{show:?}: master hairs drawn"
        );
        assert_eq!(statistics.tess_eval_invocations, 0);
    }
    common::assert_clean(&device);
}

/// One pressing case (hair combed down on a sphere under strong gravity and a shake,
/// `fur_core::sim::sdf::pressing_case`) simulated on the GPU for `frames` frames, with or
/// without collision and the probe: the vertices (w = the probe's value, or 1).
struct Pressed {
    strands: Strands,
    vertices: Vec<Vec4>,
    head: Mat4,
    sdf: Sdf,
    hair: f32,
    margin: f32,
}

fn pressed(collision: bool, probe: bool, frames: usize) -> Pressed {
    let device = common::device();
    let mesh = Mesh::icosphere(2);
    let (_, radius) = mesh.bounds();
    let (groom, params, motion) = fur_core::sim::sdf::pressing_case(radius, collision);
    let strands = Strands::grow(&mesh, &groom).unwrap();
    let hair = strands.hair_length();
    let (sdf, _) = Sdf::build(
        &mesh,
        params.sdf_cells(2.0 * radius + 2.0 * hair, hair, false),
        hair,
    )
    .unwrap();
    let mut textures = StrandTextures::new(&device, &strands, motion.head(0.0).as_mat4()).unwrap();
    let body = collision.then_some(&sdf);
    let mut gpu = GpuSim::with_body(&device, &textures, params.clone(), 1, body).unwrap();
    gpu.set_probe(probe.then_some(None), &mut textures).unwrap();
    gpu.run_frames(&mut textures, frames, |t| motion.head(t))
        .unwrap();
    let vertices = textures.read_vertices(textures.current).unwrap();
    let head = motion.head(gpu.time).as_mat4();
    drop(gpu);
    drop(textures);
    common::assert_clean(&device);
    Pressed {
        strands,
        vertices,
        head,
        sdf,
        hair,
        margin: params.collision_margin,
    }
}

/// The kernel's probe: each vertex's w is 1 + its distance from its rest shape
/// carried by the body, as a fraction of its strand's rest length (worked out here from
/// the positions read back and the rest shape), negated where collision pushed it; the
/// probe changes no position (bit for bit); without collision nothing is pushed; every
/// pushed vertex ends near the collision margin; and the hair did move.
#[test]
fn the_simulation_probe_measures_displacement_and_pushes_without_changing_the_simulation() {
    let frames = 12;
    let probed = pressed(true, true, frames);
    let plain = pressed(true, false, frames);
    let v = probed.strands.vertices_per_strand as usize;
    let mut worst = 0.0f32;
    let (mut pushed, mut moved) = (0, 0);
    for (i, (p, q)) in probed.vertices.iter().zip(&plain.vertices).enumerate() {
        assert_eq!(
            p.xyz(),
            q.xyz(),
            "vertex {i}: the probe changed the simulation"
        );
        assert_eq!(q.w, 1.0, "vertex {i}: w without the probe");
        let rest = probed.strands.strand(i / v);
        let length: f32 = rest.windows(2).map(|w| w[0].distance(w[1])).sum();
        let carried = probed.head.transform_point3(rest[i % v]);
        let want = 1.0 + p.xyz().distance(carried) / length;
        worst = worst.max((p.w.abs() - want).abs() / (want - 1.0).max(1e-3));
        if p.w < 0.0 {
            pushed += 1;
            // Collision leaves a pushed vertex at the margin (in the body's frame).
            let model = probed.head.inverse().transform_point3(p.xyz());
            let (field, _) = probed
                .sdf
                .sample(fur_core::geometry::V3::<f32>::from_vec3(model))
                .expect("a pushed vertex lies in the field");
            let margin = probed.margin * length;
            assert!(
                field < 2.0 * margin,
                "vertex {i} pushed but {field} from the body (margin {margin})"
            );
        }
        moved += usize::from(p.w.abs() - 1.0 > 0.05);
    }
    println!(
        "{pushed} of {} vertices pushed, {moved} moved over 5% of their hair; worst relative error {worst:e}",
        probed.vertices.len()
    );
    assert!(worst < 1e-3, "probe off the displacement by {worst}");
    assert!(pushed > 0, "collision pushed nothing in the pressing case");
    assert!(moved > 0, "nothing moved");
    let free = pressed(false, true, frames);
    assert!(
        free.vertices.iter().all(|p| p.w >= 1.0),
        "vertices marked pushed with collision off"
    );
    let _ = free.hair;
}

/// The simulation view colours the master hairs by the probe: at rest every master
/// hair is the scale's rest colour, blue; after a shake, hair shows the scale's colours
/// away from blue, and what is drawn is the scale's colours (or white, pushed).
#[test]
fn the_simulation_view_is_blue_at_rest_and_coloured_in_motion() {
    let device = common::device();
    let mesh = Mesh::blob();
    let (centre, radius) = mesh.bounds();
    let strands = Strands::grow(&mesh, &GroomParams::default()).unwrap();
    let motion = fur_core::sim::Motion {
        kind: fur_core::sim::MotionKind::Shake,
        amplitude: 0.3,
        rate: 2.0,
    };
    let mut settings = FrameSettings {
        camera: Camera {
            target: centre,
            distance: 2.8 * radius,
            ..Default::default()
        },
        show: Stage::Simulation,
        draw_mesh: false,
        head: motion.head(0.0).as_mat4(),
        ..Default::default()
    };
    let size = (128, 96);
    let mut textures = StrandTextures::new(&device, &strands, settings.head).unwrap();
    let extent = vk::Extent2D {
        width: size.0,
        height: size.1,
    };
    let mut renderer = Renderer::new(&device, &mesh, &textures, extent, 1, 1).unwrap();
    let mut gpu = GpuSim::new(&device, &textures, SimParams::default()).unwrap();
    gpu.set_probe(Some(None), &mut textures).unwrap();
    let background = srgb(fur_gpu::render::BACKGROUND);
    let drawn = |image: &RgbaImage| -> Vec<[u8; 3]> {
        (0..image.height)
            .flat_map(|y| (0..image.width).map(move |x| (x, y)))
            .map(|(x, y)| {
                let p = image.pixel(x, y);
                [p[0], p[1], p[2]]
            })
            .filter(|p| !near(*p, background, 1))
            .collect()
    };
    // Lines cover their pixels partly (lavapipe draws them smooth): a pixel is a blend
    // of the background and its line's colour.
    let linear = |p: [u8; 3]| Vec3::from(p.map(fur_core::colour::srgb8_to_linear));
    let bg = linear(background);
    let blend_of = |p: [u8; 3], colour: Vec3| {
        let (p, d) = (linear(p) - bg, colour - bg);
        let a = (p.dot(d) / d.length_squared()).clamp(0.0, 1.0);
        (p - a * d).length() < 0.02
    };
    let rest = displacement_colour(0.0);
    let (still, _) = renderer.render(&textures, &settings).unwrap();
    let at_rest = drawn(&still);
    let off: Vec<&[u8; 3]> = at_rest.iter().filter(|p| !blend_of(**p, rest)).collect();
    assert!(at_rest.len() > 500, "{} hair pixels", at_rest.len());
    assert!(
        off.is_empty(),
        "{} of {} hair pixels at rest are not the rest colour: {:?}",
        off.len(),
        at_rest.len(),
        &off[..off.len().min(8)]
    );

    gpu.run_frames(&mut textures, 20, |t| motion.head(t))
        .unwrap();
    settings.head = motion.head(gpu.time).as_mat4();
    let (shaken, _) = renderer.render(&textures, &settings).unwrap();
    let pixels = drawn(&shaken);
    let scale: Vec<Vec3> = (0..=256)
        .map(|k| displacement_colour(k as f32 / 256.0 * 0.25))
        .chain([Vec3::ONE])
        .collect();
    let on_scale = pixels
        .iter()
        .filter(|p| scale.iter().any(|s| blend_of(**p, *s)))
        .count();
    // Pixels a line covers fully, and those of them away from the rest colour.
    let solid: Vec<&[u8; 3]> = pixels
        .iter()
        .filter(|p| scale.iter().any(|s| near(**p, srgb(*s), 2)))
        .collect();
    let moving = solid.iter().filter(|p| !near(***p, srgb(rest), 8)).count();
    println!(
        "{} hair pixels, {on_scale} on the scale, {} solid, {moving} of them away from rest",
        pixels.len(),
        solid.len()
    );
    drop(gpu);
    drop(renderer);
    drop(textures);
    common::assert_clean(&device);
    assert!(on_scale * 100 >= pixels.len() * 98, "colours off the scale");
    assert!(solid.len() > 200, "few solid line pixels");
    assert!(
        moving * 10 >= solid.len(),
        "the shaken hair barely shows motion"
    );
}
